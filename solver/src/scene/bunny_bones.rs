//! Built-in scene `bunny-bones` (paper Figure 12): the Stanford bunny as a bending body with the
//! four-bone skeleton of [`bunny_skeleton`](dentbend::bend::bunny_skeleton) — body, a head bone
//! that pokes out of the neck, and one bone per ear — hit on an ear and on the head.

use glam::Vec3;

use super::kit::frames;
use super::kit::{GROUND, ORANGE, finish, launch, world};
use super::{Scene, SceneSize};
use crate::coupling::{BendableDesc, Bending, SkeletonSpec};
use crate::sim::{BodyDesc, BodyKind, ColliderKind, JointKind, SimError, SurfaceMaterial};
use dentbend::bend::JointRule;
use dentbend::bend::{BUNNY_BODY, WeightParams};
use dentbend::mesh::{builtin as builtin_mesh, subdivided_box};

/// Scale of the built-in bunny (about 10 across) in the `bunny-bones` scene: 1.45 m tall.
pub const BUNNY_SCALE: f32 = 0.15;

/// The plastic joints of the `bunny-bones` scene: rigid up to an angular impulse of 0.5 N·m·s
/// in a step (30 N·m as a torque at 60 steps/s), which the balls' hits exceed; a bend goes on
/// briefly after a hit, its rate losing (1 rad/s² + 4/s × rate) as it slows.
pub(crate) const BUNNY_JOINT: JointKind =
    JointKind::Bend(JointRule::Plastic { strength: 0.5, damping_constant: 1.0, damping_proportional: 4.0 });

/// Falloff exponent of the bunny's skinning weights (w ∝ d⁻⁸): sharper than the default 4, so
/// that each ear moves with its own bone only. The ear bones start inside the head, about 0.2 m
/// apart through it; with 4 an ear vertex keeps about 1 % on the other ear, with 8 below 0.1 %
/// past the first third of its ear.
pub const BUNNY_FALLOFF: f32 = 8.0;

/// Where the heavy ball lands on top of the bunny's head, in front of the ears, world, m.
pub(crate) const BUNNY_HEAD_HIT: Vec3 = Vec3::new(-0.62, 1.16, 0.25);
/// Where the light ball hits the front of the bunny's right ear, world, m.
pub(crate) const BUNNY_EAR_HIT: Vec3 = Vec3::new(-0.584, 1.3, -0.325);

/// Figure 12: the bunny (1.45 m tall, 400 kg/m³, 262 kg) is a bending body of four bones joined
/// by plastic joints ([`BUNNY_JOINT`]); its body bone is glued to a stand by a rigid joint and
/// there is no gravity, so that nothing but the bending moves it. A 0.7 kg ball thrown from the
/// front hits its right ear at 5 m/s after 0.25 s and bends it back by about 33°; the left ear,
/// geodesically far from it, does not follow. A 16 kg ball lands on top of its head at 5 m/s
/// after 0.35 s and bends the head forward at the neck by about 22°. Full: level set 64 cells
/// across; demo: 40.
pub(super) fn bunny_bones(size: SceneSize) -> Result<Scene, SimError> {
    let resolution = match size {
        SceneSize::Full => 64,
        SceneSize::Demo => 40,
    };
    let mut world = world(Vec3::ZERO)?;
    let stand = subdivided_box(Vec3::new(1.4, 0.1, 1.0), [4, 1, 3])?;
    let desc = BodyDesc::new("stand", stand).kind(BodyKind::Static).at(Vec3::new(0.0, -0.05, 0.05));
    let stand = world.add(BodyDesc { color: GROUND, ..desc.collider(ColliderKind::Cuboid) })?;
    let mut mesh = builtin_mesh("bunny")?;
    mesh.transform(glam::Affine3A::from_scale(Vec3::splat(BUNNY_SCALE)))?;
    let density = 400.0;
    // Name, radius (m), mass (kg), hit point, velocity at the hit (m/s), restitution, time to it (s).
    let throws = [
        ("ball-ear", 0.09, 0.7, BUNNY_EAR_HIT, Vec3::new(5.0, 0.0, 0.0), 0.5, 0.25),
        ("ball-head", 0.12, 16.0, BUNNY_HEAD_HIT, Vec3::new(0.0, -5.0, 0.0), 0.5, 0.35),
    ];
    for (name, radius, mass, hit, velocity, restitution, lead) in throws {
        let projectile = super::kit::ball(radius, 3)?;
        // The ball's centre passes one radius short of the hit point.
        let centre = hit - velocity.normalize() * radius;
        let (start, start_velocity) = launch(centre, velocity, Vec3::ZERO, lead);
        let desc = BodyDesc::new(name, projectile).at(start).velocity(start_velocity).collider(ColliderKind::Ball);
        let surface = SurfaceMaterial { restitution, friction: 0.4 };
        world.add(BodyDesc { density: mass / desc.mesh.volume(), color: ORANGE, surface, ..desc })?;
    }

    let mut desc = BendableDesc::new("bunny", mesh);
    desc.density = density;
    desc.color = [0.78, 0.74, 0.68];
    let bones = dentbend::bend::bunny_bones(BUNNY_SCALE)
        .map_err(|e| SimError::BadShape { body: "bunny".into(), reason: format!("bending: {e}") })?;
    let anchor = bones[BUNNY_BODY].head;
    desc.skeleton = SkeletonSpec::Bones(bones);
    desc.weights = WeightParams { resolution, falloff: BUNNY_FALLOFF, ..WeightParams::default() };
    desc.joint = BUNNY_JOINT;
    desc.surface = SurfaceMaterial { restitution: 0.1, friction: 0.8 };
    let mut bending = Bending::new();
    let bunny = bending.add(&mut world, desc)?;
    // The body bone is glued to the stand at its head (the bunny sits at the origin): the body
    // stays put while the head and ears bend.
    let body = bending.bodies()[bunny].body_indices()[BUNNY_BODY];
    world.add_joint(stand, body, anchor, JointKind::Rigid)?;
    let description = "Figure 12: the Stanford bunny bends as four bones (body, a head bone poking out of the \
                       neck, two ears) joined by plastic joints: a light ball bends one ear back while the other \
                       ear stays put, a heavy one bends the head forward at the neck.";
    let framed = |n: &str| !n.starts_with("ball") && n != "stand";
    let mut scene =
        finish("bunny-bones", world, Vec3::new(0.75, -0.35, -1.0), framed, frames(size, 150, 90), description);
    scene.bending = bending;
    Ok(scene)
}
