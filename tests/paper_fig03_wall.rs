//! Paper Figure 3 (issue 18 item 4): the built-in scene `wall`. Balls dent a prescored static
//! wall one after another; when its dents add up past its limit it breaks along the pattern
//! placed at the last hit: pieces fly on in the ball's direction, the rest stays one closed body.

use std::collections::HashMap;

use dentbend::coupling::Simulation;
use dentbend::fracture::FractureCause;
use dentbend::scene::{SceneSize, WALL_DENT_LIMIT, builtin_scene};
use dentbend::sim::BodyKind;

/// Frames of the demo-sized scene; the third ball arrives at about frame 80.
const FRAMES: u32 = 120;

#[test]
fn the_wall_is_dented_then_breaks_and_its_pieces_fly_on() {
    let scene = builtin_scene("wall", SceneSize::Demo).unwrap();
    let wall = scene.world.find("wall").unwrap();
    let volume_before = scene.world.bodies()[wall].mesh().volume();
    let mut sim = Simulation::new(scene.world, None).unwrap();
    let mut broke_at = None;
    for frame in 1..=FRAMES {
        let (timing, _) = sim.step().unwrap();
        if timing.fractures > 0 && broke_at.is_none() {
            broke_at = Some(frame);
        }
    }
    let broke_at = broke_at.expect("the wall breaks within 120 frames");
    // It broke once, by its dents, after more than two of them (each 4.2 cm; the limit 10 cm).
    let fractures = sim.fractures();
    assert_eq!(fractures.len(), 1, "{fractures:?}");
    let fracture = &fractures[0];
    assert_eq!((fracture.body.as_str(), fracture.cause), ("wall", FractureCause::Dent));
    assert!(fracture.accumulated_dent > WALL_DENT_LIMIT);
    let dents_before = sim.dents().iter().filter(|d| d.target == "wall" && d.step <= broke_at as u64).count();
    assert!(dents_before >= 3, "{dents_before} dents before the break");
    assert!((10..=50).contains(&fracture.pieces.len()), "{} pieces", fracture.pieces.len());

    // The rest is the same body, still static, one closed mesh with a hole through it.
    let world = sim.world();
    let rest = &world.bodies()[wall];
    assert_eq!((rest.name.as_str(), rest.kind), ("wall", BodyKind::Static));
    let volume_after = rest.mesh().volume();
    let hole = volume_before - volume_after;
    // The 16-gon of inradius 0.45 m through the 0.2 m wall: 0.129 m³ (2 % for the dents).
    assert!((hole - 0.129).abs() < 0.03 * 0.129, "hole of {hole} m³");
    let mut edges: HashMap<(u32, u32), i32> = HashMap::new();
    for f in rest.mesh().faces() {
        for k in 0..3 {
            *edges.entry((f[k], f[(k + 1) % 3])).or_default() += 1;
        }
    }
    assert!(edges.iter().all(|(&(a, b), &n)| n == 1 && edges.get(&(b, a)) == Some(&1)), "the rest is not closed");

    // The pieces are dynamic and, 40 frames on, have moved on through the wall (−z, the balls'
    // direction): their mean velocity points that way and most are behind the wall's front face.
    let pieces: Vec<_> = fracture.pieces.iter().map(|name| &world.bodies()[world.find(name).unwrap()]).collect();
    assert!(pieces.iter().all(|p| p.kind == BodyKind::Dynamic && p.mass > 0.0));
    let momentum: f32 = pieces.iter().map(|p| p.mass * p.linear_velocity.z).sum();
    assert!(momentum < 0.0, "the pieces' momentum along z is {momentum} kg·m/s");
    let pushed = pieces.iter().filter(|p| p.position.z < -0.1).count();
    assert!(2 * pushed >= pieces.len(), "{pushed} of {} pieces went through", pieces.len());
}
