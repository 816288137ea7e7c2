//! Built-in bending scenes (paper §4): Figure 14's plank that a ball breaks a plastic joint into
//! (dynamic articulation), and an elastic bar that a ball sets ringing.

use glam::Vec3;

use super::kit::frames;
use super::kit::{BLUE, GROUND, ORANGE, SAND, STEEL, ball, finish, world};
use super::{Scene, SceneSize};
use crate::coupling::{BendableDesc, Bending, DynamicArticulation, SkeletonSpec};
use crate::sim::{BodyDesc, BodyKind, ColliderKind, DentSettings, JointKind, SimError, SurfaceMaterial};
use dentbend::bend::JointRule;
use dentbend::bend::WeightParams;
use dentbend::mesh::{plank as plank_mesh, subdivided_box};

/// Plank length (x), thickness (y) and width (z) of the built-in `plank` scene, m.
pub const PLANK_SIZE: Vec3 = Vec3::new(4.0, 0.1, 0.3);
/// Where the ball of the `plank` scene hits the plank's top face, world, m (just off the middle, so the
/// joint visibly lands where the ball hits).
pub const PLANK_HIT: Vec3 = Vec3::new(0.3, 0.05, 0.0);

/// The `plank` scene's dent settings: threshold 2 m/s, 5 mm per m/s above it, at most 3 cm (the
/// ball's hit at about 6 m/s leaves about 2 cm in the 10 cm plank).
pub const PLANK_DENT: (f32, f32, f32) = (2.0, 0.005, 0.03);

/// Figure 14: a steel-grey ball (radius 0.2 m, 60 kg) falls at about 6 m/s on a wooden plank
/// 4 × 0.1 × 0.3 m (700 kg/m³, one bone, dynamic articulation above 2 m/s) lying across two
/// supports 3.4 m apart. The hit splits the bone where the ball lands and joins the halves with
/// a plastic joint (strength 40 N·m·s, enough to carry the plank and the ball at rest, far from
/// enough to stop the ball), which bends into a V; the ends stay straight. The plank is
/// dentable ([`PLANK_DENT`]): the ball also leaves a dent where it lands, which bends with it.
/// Full: 128 segments, level set 192 cells long; demo: 64 and 128.
pub(super) fn plank(size: SceneSize) -> Result<Scene, SimError> {
    let (segments, resolution) = match size {
        SceneSize::Full => (128, 192),
        SceneSize::Demo => (64, 128),
    };
    let mut world = world(super::kit::GRAVITY)?;
    let support = subdivided_box(Vec3::new(0.4, 0.6, 0.6), [2, 2, 2])?;
    for (name, x) in [("support-left", -1.9), ("support-right", 1.9)] {
        let desc = BodyDesc::new(name, support.clone()).kind(BodyKind::Static).at(Vec3::new(x, -0.3, 0.0));
        world.add(BodyDesc { color: STEEL, ..desc.collider(ColliderKind::Cuboid) })?;
    }
    let ground = subdivided_box(Vec3::new(8.0, 0.2, 3.0), [8, 1, 3])?;
    let desc = BodyDesc::new("ground", ground).kind(BodyKind::Static).at(Vec3::new(0.0, -0.7, 0.0));
    world.add(BodyDesc { color: GROUND, ..desc.collider(ColliderKind::TriMesh) })?;
    let radius = 0.2;
    let projectile = ball(radius, 3)?;
    let density = 60.0 / projectile.volume();
    // The plank's top face lies at y = PLANK_SIZE.y + 2 mm. At 0.1 s (6 steps) the ball's lowest
    // point is aimed 1 cm above it (the stepping lands it about 8 mm lower): the step that
    // closes the gap then starts with the surfaces millimetres apart, so the collision's point
    // (midway between them when the contact is found) is on the plank, not up to half a step's
    // travel (5 cm) above it, where the dent's depth falloff would leave little of the dent.
    let top = PLANK_SIZE.y + 0.002;
    let aim = Vec3::new(PLANK_HIT.x, top + 0.01 + radius, PLANK_HIT.z);
    let (start, velocity) = super::kit::launch(aim, Vec3::new(0.0, -6.0, 0.0), super::kit::GRAVITY, 0.1);
    let desc = BodyDesc::new("ball", projectile).at(start).velocity(velocity).collider(ColliderKind::Ball);
    world.add(BodyDesc {
        density,
        color: ORANGE,
        surface: SurfaceMaterial { restitution: 0.0, friction: 0.5 },
        ..desc
    })?;

    let mut desc = BendableDesc::new("plank", plank_mesh(PLANK_SIZE.x, PLANK_SIZE.z, PLANK_SIZE.y, segments)?);
    // 2 mm above the supports: it settles on them before the ball lands.
    desc.position = Vec3::new(0.0, PLANK_SIZE.y / 2.0 + 0.002, 0.0);
    desc.density = 700.0;
    desc.color = SAND;
    desc.skeleton = SkeletonSpec::Auto { bones: 1 };
    desc.weights = WeightParams { resolution, ..WeightParams::default() };
    let joint =
        JointKind::Bend(JointRule::Plastic { strength: 40.0, damping_constant: 0.5, damping_proportional: 10.0 });
    desc.dynamic = Some(DynamicArticulation::new(2.0, joint, 0.3));
    let (threshold, gain, cap) = PLANK_DENT;
    desc.dent = Some(DentSettings::new(threshold, gain, cap));
    let mut bending = Bending::new();
    bending.add(&mut world, desc)?;
    let description = "Figure 14: a ball hits a plank lying on two supports; a plastic joint appears where it \
                       hits and the plank dents and bends there while its ends stay straight.";
    let mut scene =
        finish("plank", world, Vec3::new(0.0, -0.35, -1.0), |n| n != "ground", frames(size, 90, 45), description);
    scene.bending = bending;
    Ok(scene)
}

/// Elastic joint stiffness (N·m/rad) and damping (N·m·s/rad) of the `spring` scene's bar: with the two
/// halves' reduced inertia of about 1.2 kg·m² it rings at about 1.5 Hz and loses 70 % of its
/// amplitude per second.
pub(crate) const SPRING_JOINT: JointKind = JointKind::Bend(JointRule::Elastic { stiffness: 100.0, damping: 3.0 });

/// An elastic bar: a 2 × 0.2 × 0.2 m bar (700 kg/m³, two bones joined by an elastic joint) floats
/// without gravity; a 10 kg ball hits one end sideways at 4 m/s, the bar bends at its middle and
/// springs back to straight while it drifts away. Full: 64 segments, level set 96; demo: 32, 64.
pub(super) fn spring(size: SceneSize) -> Result<Scene, SimError> {
    let (segments, resolution) = match size {
        SceneSize::Full => (64, 96),
        SceneSize::Demo => (32, 64),
    };
    let mut world = world(Vec3::ZERO)?;
    let projectile = ball(0.15, 3)?;
    let density = 10.0 / projectile.volume();
    let desc = BodyDesc::new("ball", projectile)
        .at(Vec3::new(0.85, 0.0, 1.0))
        .velocity(Vec3::new(0.0, 0.0, -4.0))
        .collider(ColliderKind::Ball);
    world.add(BodyDesc {
        density,
        color: ORANGE,
        surface: SurfaceMaterial { restitution: 0.3, friction: 0.2 },
        ..desc
    })?;
    let mut desc = BendableDesc::new("bar", plank_mesh(2.0, 0.2, 0.2, segments)?);
    desc.density = 700.0;
    desc.color = BLUE;
    desc.skeleton = SkeletonSpec::Auto { bones: 2 };
    desc.weights = WeightParams { resolution, ..WeightParams::default() };
    desc.joint = SPRING_JOINT;
    let mut bending = Bending::new();
    bending.add(&mut world, desc)?;
    let description = "An elastic bar floating without gravity is hit at one end: it bends at its elastic joint \
                       and springs back straight.";
    let mut scene = finish("spring", world, Vec3::new(0.0, -1.0, -0.6), |_| true, frames(size, 180, 120), description);
    scene.bending = bending;
    Ok(scene)
}
