//! Figure 14 (paper §4.2, dynamic articulation): a ball hits a one-bone plank lying on two
//! supports; a plastic joint appears where it hits, the plank bends there, and its ends stay
//! straight and as thick as they were.
//!
//! The demo-size scene (64 segments, level set 128 cells along the 4 m plank: cells of
//! 4.0 / 128 ≈ 0.031 m plus border) keeps the whole run under a few seconds in debug builds.

use dentbend::glam::Vec3;
use dentbend_solver::coupling::Simulation;
use dentbend_solver::scene::{PLANK_HIT, PLANK_SIZE, SceneSize, builtin_scene};

/// Frames of the run: the ball lands at frame 6 and the bend has settled by about frame 30.
const FRAMES: usize = 45;

fn run_plank() -> Simulation {
    let scene = builtin_scene("plank", SceneSize::Demo).unwrap();
    let mut sim = Simulation::new(scene.world, None).unwrap().with_bending(scene.bending);
    for frame in 0..FRAMES {
        sim.step().unwrap_or_else(|e| panic!("frame {}: {e}", frame + 1));
    }
    sim
}

#[test]
fn a_joint_appears_at_the_hit_and_the_plank_bends_with_straight_ends() {
    let sim = run_plank();
    let bending = sim.bending();
    let world = sim.world();
    let plank = bending.find("plank").unwrap();

    // One joint, at the hit's projection on the bone (the plank's axis, y = z = 0 in its rest
    // frame; the ball falls straight down onto x = PLANK_HIT.x): within one level-set cell.
    let joints = bending.joints();
    assert_eq!(joints.len(), 1, "joints made: {joints:?}");
    let made = &joints[0];
    let cell = plank.cell_size();
    let expected = Vec3::new(PLANK_HIT.x, 0.0, 0.0);
    assert!(
        made.rest_position.distance(expected) <= cell,
        "joint at {:?}, hit projects to {expected:?}, cell {cell}",
        made.rest_position
    );
    assert!(made.frame >= 2 && made.frame <= 10, "joint made at frame {}", made.frame);
    assert_eq!(plank.skeleton().len(), 2);

    // The plank bends there: the plastic joint's net bend exceeds 5°.
    let joint = &world.joints()[made.joint];
    let angle = joint.bend_angle().to_degrees();
    println!("bend {angle:.2}°, {} bend events, joint at {:?}", bending.bends().len(), made.position);
    assert!(angle > 5.0, "net bend {angle}°");
    assert!(bending.bends().iter().any(|b| b.joint == made.joint), "no bend event of the new joint");

    // The ends (the outer 0.5 m of each side) stay straight and unthickened: each end's skinned
    // vertices are a rigid motion of its rest vertices. The candidate rigid motion is the end
    // bone's transform (no better fit is needed: it already bounds the best rigid fit's
    // residual); residual < 1 % of the thickness. The thickness, measured along the moved y
    // axis, is unchanged within 1 %.
    let skinned = plank.skinned_mesh(world).unwrap();
    let transforms = plank.bone_transforms(world).unwrap();
    let rest = plank.rest_mesh().positions();
    let thickness = PLANK_SIZE.y;
    for side in [-1.0f32, 1.0] {
        let end: Vec<usize> = (0..rest.len()).filter(|&v| rest[v].x * side > PLANK_SIZE.x / 2.0 - 0.5).collect();
        assert!(end.len() > 20, "end vertices {}", end.len());
        let bone = plank.skeleton().nearest_bone(rest[end[0]]).unwrap().0;
        let motion = transforms[bone];
        let residual = end
            .iter()
            .map(|&v| skinned.positions()[v].distance(motion.transform_point3(rest[v])))
            .fold(0.0f32, f32::max);
        assert!(residual < 0.01 * thickness, "side {side}: residual {residual} m");
        let up = motion.transform_vector3(Vec3::Y).normalize();
        let (lo, hi) = end
            .iter()
            .map(|&v| skinned.positions()[v].dot(up))
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), s| (lo.min(s), hi.max(s)));
        assert!(((hi - lo) - thickness).abs() < 0.01 * thickness, "side {side}: thickness {}", hi - lo);
        println!("side {side}: bone {bone}, residual {residual:.2e} m, thickness {:.5} m", hi - lo);
    }
}
