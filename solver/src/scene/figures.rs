//! Built-in scenes for the paper's Figures 1, 2, 5, 8 and 11 (Figure 10 is in `rain.rs`).
//!
//! Dent distances follow d = gain·(v_n − threshold), capped: the balls arrive at 6–8 m/s and
//! leave dents of 0.1–0.3 m.

use glam::{Quat, Vec3};

use super::kit::{BLUE, GREEN, ORANGE, SAND, STEEL, ball, dentable, finish, frames, launch, scaled, world};
use super::{Scene, SceneSize};
use crate::sim::{BodyDesc, BodyKind, ColliderKind, SimError, SurfaceMaterial};
use dentbend::dent::{Attenuation, Resolution};

/// Figure 1: two equal dentable balls (radius 1 m) fly at each other head-on at 4 m/s each, no
/// gravity; dented from the undented shapes at once (Jacobi), the dents are mirror images.
/// Full: 20,480 triangles per ball; demo: 5,120.
pub(super) fn pair(size: SceneSize) -> Result<Scene, SimError> {
    let subdivisions = match size {
        SceneSize::Full => 5,
        SceneSize::Demo => 4,
    };
    let mesh = ball(1.0, subdivisions)?;
    let mut world = world(Vec3::ZERO)?;
    // Closing at 8 m/s: d = 0.03·(8 − 1) = 0.21 m.
    let dent = dentable(1.0, 0.03, 0.3, None);
    for (name, side, color) in [("left", -1.0, ORANGE), ("right", 1.0, BLUE)] {
        let mut desc = BodyDesc::new(name, mesh.clone())
            .at(Vec3::new(2.2 * side, 0.0, 0.0))
            .velocity(Vec3::new(-4.0 * side, 0.0, 0.0))
            .collider(ColliderKind::Ball)
            .dentable(dent.clone());
        desc.surface.restitution = 0.2;
        desc.color = color;
        world.add(desc)?;
    }
    let frames = frames(size, 90, 60);
    let description = "Figure 1: two dentable balls collide head-on and dent each other symmetrically.";
    Ok(finish("pair", world, Vec3::new(0.0, -0.3, -1.0), |_| true, frames, description))
}

/// Figure 2: balls (radius 0.6 m) land at about 7.5 m/s on two static 4 × 0.5 × 4 m blocks, the
/// left with the paper's logistic attenuation, the right with none (its back face bulges as
/// much as the dent is deep). Full: `block-fine` blocks (57,344 triangles); demo: `block`.
pub(super) fn ball_block(size: SceneSize) -> Result<Scene, SimError> {
    let block = scaled(fine_block(size), Vec3::new(1.0, 0.5, 1.0))?;
    let projectile = ball(0.6, ball_subdivisions(size))?;
    let mut world = world(super::kit::GRAVITY)?;
    let variants =
        [("block-attenuated", "ball-1", Attenuation::Logistic), ("block-unattenuated", "ball-2", Attenuation::None)];
    for (k, (block_name, ball_name, attenuation)) in variants.into_iter().enumerate() {
        let x = if k == 0 { -2.5 } else { 2.5 };
        // 7.46 m/s at the top face: d = 0.035·(7.46 − 1) = 0.23 m.
        let mut dent = dentable(1.0, 0.035, 0.3, None);
        dent.params.attenuation = attenuation;
        dent.move_projectile = true;
        world.add(target(block_name, block.clone(), Vec3::new(x, 0.0, 0.0), STEEL).dentable(dent))?;
        let desc = BodyDesc::new(ball_name, projectile.clone())
            .at(Vec3::new(x, 0.25 + 0.6 + 1.0, 0.0))
            .velocity(Vec3::new(0.0, -6.0, 0.0))
            .collider(ColliderKind::Ball);
        world.add(BodyDesc { color: ORANGE, surface: dented_surface(), ..desc })?;
    }
    let frames = frames(size, 120, 60);
    let description = "Figure 2: balls dent two blocks; with attenuation (left) the back face barely moves, \
                       without (right) it bulges out as far as the dent goes in.";
    Ok(finish("ball-block", world, Vec3::new(0.0, 0.06, -1.0), |_| true, frames, description))
}

/// Figure 5: bunnies (about 1.5 m long, not dentable) fall on four static 2.4 × 0.6 × 2.4 m
/// blocks whose dent distance (0.04 → 0.16 m) and Gaussian width σ (0.015 → 0.09 m) grow left
/// to right: deeper and smoother dents, "different materials". Full: `block-fine` blocks;
/// demo: `block`.
pub(super) fn bunny_block(size: SceneSize) -> Result<Scene, SimError> {
    let block = scaled(fine_block(size), Vec3::splat(0.6))?;
    let bunny = scaled("bunny", Vec3::splat(0.15))?;
    let mut world = world(super::kit::GRAVITY)?;
    let (caps, sigmas) = ([0.04, 0.08, 0.12, 0.16], [0.015, 0.04, 0.065, 0.09]);
    for (k, (cap, sigma)) in caps.into_iter().zip(sigmas).enumerate() {
        let x = -4.5 + 3.0 * k as f32;
        // About 6 m/s at impact: the gain is high enough that every block reaches its cap.
        let mut dent = dentable(1.0, 0.2, cap, Some(sigma));
        dent.move_projectile = true;
        world.add(target(&format!("block-{}", k + 1), block.clone(), Vec3::new(x, 0.0, 0.0), SAND).dentable(dent))?;
        let mut desc = BodyDesc::new(format!("bunny-{}", k + 1), bunny.clone())
            .at(Vec3::new(x, 0.3 + 1.0, 0.0))
            .velocity(Vec3::new(0.0, -4.0, 0.0));
        desc.orientation = Quat::from_rotation_y(0.5);
        desc.color = [0.75, 0.72, 0.68];
        desc.surface = dented_surface();
        world.add(desc)?;
    }
    let frames = frames(size, 120, 60);
    let description = "Figure 5: bunnies dent four blocks whose dent distance and Gaussian width grow from left \
                       to right: deeper, smoother dents read as softer materials.";
    Ok(finish("bunny-block", world, Vec3::new(0.0, -0.8, -1.0), |_| true, frames, description))
}

/// Figure 8: balls (radius 0.6 m) hit three static 4 × 1 × 4 m blocks at 7 m/s, 0°, 30° and 60°
/// from the normal (sliding towards +z): the dents shear along the velocity and get shallower
/// (cos θ). Full: `block-fine` blocks; demo: `block`.
pub(super) fn glancing(size: SceneSize) -> Result<Scene, SimError> {
    let block = dentbend::mesh::builtin(fine_block(size))?;
    let projectile = ball(0.6, ball_subdivisions(size))?;
    let gravity = super::kit::GRAVITY;
    let mut world = world(gravity)?;
    for (k, degrees) in [0.0f32, 30.0, 60.0].into_iter().enumerate() {
        let x = -5.0 + 5.0 * k as f32;
        // Normal speeds 7, 6.1 and 3.5 m/s: d = 0.24, 0.20 and 0.10 m.
        let mut dent = dentable(1.0, 0.04, 0.3, None);
        dent.move_projectile = true;
        let suffix = format!("{}deg", degrees as u32);
        world.add(target(&format!("block-{suffix}"), block.clone(), Vec3::new(x, 0.0, 0.0), STEEL).dentable(dent))?;
        let theta = degrees.to_radians();
        let hit_velocity = 7.0 * Vec3::new(0.0, -theta.cos(), theta.sin());
        let (start, velocity) = launch(Vec3::new(x, 0.5 + 0.6, -0.5), hit_velocity, gravity, 0.25);
        let desc = BodyDesc::new(format!("ball-{suffix}"), projectile.clone())
            .at(start)
            .velocity(velocity)
            .collider(ColliderKind::Ball);
        world.add(BodyDesc { color: GREEN, surface: dented_surface(), ..desc })?;
    }
    let frames = frames(size, 120, 60);
    let description = "Figure 8: balls hit blocks at 0°, 30° and 60° from the normal; glancing dents are sheared \
                       along the velocity and shallower.";
    Ok(finish("glancing", world, Vec3::new(0.35, -0.7, -1.0), |_| true, frames, description))
}

/// Figure 11: the same impact (ball of radius 0.6 m at about 7.5 m/s on a static 4 × 1 × 4 m
/// block) with the dent grid fixed at 20, 50, 100 and 200 cells per side. Full: `block-fine`
/// blocks; demo: `block`.
pub(super) fn resolution(size: SceneSize) -> Result<Scene, SimError> {
    let block = dentbend::mesh::builtin(fine_block(size))?;
    let projectile = ball(0.6, ball_subdivisions(size))?;
    let mut world = world(super::kit::GRAVITY)?;
    for (k, cells) in [20u32, 50, 100, 200].into_iter().enumerate() {
        let x = -7.5 + 5.0 * k as f32;
        let mut dent = dentable(1.0, 0.035, 0.3, None);
        dent.params.resolution = Resolution::Fixed(cells);
        dent.move_projectile = true;
        world.add(target(&format!("block-res{cells}"), block.clone(), Vec3::new(x, 0.0, 0.0), STEEL).dentable(dent))?;
        let desc = BodyDesc::new(format!("ball-res{cells}"), projectile.clone())
            .at(Vec3::new(x, 0.5 + 0.6 + 1.0, 0.0))
            .velocity(Vec3::new(0.0, -6.0, 0.0))
            .collider(ColliderKind::Ball);
        world.add(BodyDesc { color: ORANGE, surface: dented_surface(), ..desc })?;
    }
    let frames = frames(size, 120, 60);
    let description = "Figure 11: one ball impact, dent grids of 20, 50, 100 and 200 cells per side (left to right).";
    Ok(finish("resolution", world, Vec3::new(0.0, -0.8, -1.0), |_| true, frames, description))
}

/// A static target with a triangle-mesh collider at `position` (m), restitution
/// [`DENTED_RESTITUTION`].
pub(super) fn target(name: &str, mesh: dentbend::mesh::TriMesh, position: Vec3, color: [f32; 3]) -> BodyDesc {
    let desc = BodyDesc::new(name, mesh).kind(BodyKind::Static).at(position).collider(ColliderKind::TriMesh);
    BodyDesc { color, surface: dented_surface(), ..desc }
}

/// Restitution of the figures' targets and projectiles: denting takes most of the energy, and the
/// rebound (about 0.7 m/s) stays below the dent thresholds, so each impact makes one dent.
const DENTED_RESTITUTION: f32 = 0.1;

fn dented_surface() -> SurfaceMaterial {
    SurfaceMaterial { restitution: DENTED_RESTITUTION, ..SurfaceMaterial::default() }
}

/// The dent target block: `block-fine` (57,344 triangles) at full size, `block` (24,576) in the demo.
fn fine_block(size: SceneSize) -> &'static str {
    match size {
        SceneSize::Full => "block-fine",
        SceneSize::Demo => "block",
    }
}

/// Icosphere subdivisions of the projectile balls: 5,120 triangles at full size, 1,280 in the demo.
fn ball_subdivisions(size: SceneSize) -> u32 {
    match size {
        SceneSize::Full => 4,
        SceneSize::Demo => 3,
    }
}
