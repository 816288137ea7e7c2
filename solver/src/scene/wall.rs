//! Figure 3: a prescored wall dented over time by balls until it breaks.
//!
//! Three balls (radius 0.15 m, 20 kg) hit a static 3 × 2 × 0.2 m wall near the same spot at
//! 8 m/s, half a second apart, without gravity. Each makes a dent of d = 0.006·(8 − 1) = 4.2 cm (progressive:
//! while a ball presses on, its dent deepens from the surface before it); the wall breaks when
//! its dents add up to more than [`WALL_DENT_LIMIT`], at the third ball: a pattern of 40
//! Voronoi cells (finer near the hit) within 0.45 m of it breaks loose as dynamic pieces, which
//! keep the dent, and the ball carries on through the hole, pushing them along.

use glam::Vec3;

use super::kit::{ORANGE, STEEL, ball, dentable, finish, frames, launch, world};
use super::{Scene, SceneSize};
use crate::sim::{BodyDesc, BodyKind, ColliderKind, SimError, SurfaceMaterial};
use dentbend::fracture::{FractureSettings, PatternParams};
use dentbend::mesh;

/// The wall's size (x, y, z), m; its front face looks along +z.
pub const WALL_SIZE: Vec3 = Vec3::new(3.0, 2.0, 0.2);
/// Accumulated dent distance that breaks the wall, m: more than two dents, less than three.
pub const WALL_DENT_LIMIT: f32 = 0.1;

/// Height of the wall's centre, m.
const WALL_CENTRE_Y: f32 = 1.2;
/// Where the balls hit the front face, relative to its centre (x, y), m: more than a ball's
/// diameter apart, so that a ball rebounding slowly misses the next ones coming in.
const HITS: [(f32, f32); 3] = [(-0.18, 0.0), (0.18, 0.02), (0.0, 0.3)];

pub(super) fn wall(size: SceneSize) -> Result<Scene, SimError> {
    let cells = match size {
        SceneSize::Full => [60, 40, 2],
        SceneSize::Demo => [30, 20, 2],
    };
    // No gravity, so the balls fly straight and the pieces show where the last ball sent them.
    let mut world = world(Vec3::ZERO)?;

    let mut dent = dentable(1.0, 0.006, 0.06, None);
    dent.progressive = true;
    let pattern = PatternParams { cells: 40, seed: 3, radius: 0.45 };
    let mut fracture = FractureSettings::new(pattern, Some(5000.0), Some(WALL_DENT_LIMIT))
        .map_err(|error| SimError::Fracture { body: "wall".into(), error })?;
    fracture.density = 2400.0;
    let wall = mesh::subdivided_box(WALL_SIZE, cells)?;
    let desc = BodyDesc::new("wall", wall)
        .kind(BodyKind::Static)
        .at(Vec3::new(0.0, WALL_CENTRE_Y, 0.0))
        .collider(ColliderKind::TriMesh)
        .dentable(dent)
        .breakable(fracture);
    let surface = SurfaceMaterial { restitution: 0.1, ..SurfaceMaterial::default() };
    world.add(BodyDesc { color: STEEL, surface, ..desc })?;

    let radius = 0.15;
    let projectile = ball(radius, 3)?;
    let volume = projectile.volume();
    for (k, (x, y)) in HITS.into_iter().enumerate() {
        let contact = Vec3::new(x, WALL_CENTRE_Y + y, 0.5 * WALL_SIZE.z + radius);
        let (start, velocity) = launch(contact, Vec3::new(0.0, 0.0, -8.0), Vec3::ZERO, 0.3 + 0.5 * k as f32);
        let desc = BodyDesc::new(format!("ball-{}", k + 1), projectile.clone())
            .at(start)
            .velocity(velocity)
            .collider(ColliderKind::Ball);
        world.add(BodyDesc { density: 20.0 / volume, color: ORANGE, surface, ..desc })?;
    }
    let frames = frames(size, 150, 120);
    let description = "Figure 3: balls dent a prescored wall, one after another, until its dents pass its limit \
                       and it breaks along a Voronoi pattern placed at the last hit.";
    Ok(finish("wall", world, Vec3::new(-0.6, -0.35, -1.0), |name| name == "wall", frames, description))
}
