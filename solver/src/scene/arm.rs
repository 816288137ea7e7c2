//! Built-in scene `arm` (paper Figure 15): a long body of many bones — a thick torso that narrows
//! into an arm — simulated with condensation. The torso's joints are strong and stay quiet, so
//! they are condensed into one rigid cluster; the four joints of the arm are weak plastic joints
//! that a ball's hit bends, while only the four arm bones are simulated individually.

use glam::Vec3;

use super::arm_shape::{Centreline, tube};
use super::kit::frames;
use super::kit::{GROUND, ORANGE, ball, finish, launch, world};
use super::{Scene, SceneSize};
use crate::coupling::{BendableDesc, Bending, CondenseSettings, JointOverride, SkeletonSpec};
use crate::sim::{BodyDesc, BodyKind, ColliderKind, JointKind, SimError, SurfaceMaterial};
use dentbend::bend::JointRule;
use dentbend::bend::WeightParams;
use dentbend::mesh::subdivided_box;

/// Bones of the arm, at the end of the body's chain, and the joints they hang from.
pub const ARM_BONES: usize = 4;
/// Length of the arm along its centreline, m (four bones of 0.4 m).
pub(crate) const ARM_LENGTH: f32 = 1.6;

/// The torso's joints: plastic, but so strong (an angular impulse of 200 N·m·s in one step,
/// 12,000 N·m as a torque) that the ball's hit, which bends the arm's, leaves them whole.
pub(crate) const ARM_TORSO_JOINT: JointKind =
    JointKind::Bend(JointRule::Plastic { strength: 200.0, damping_constant: 1.0, damping_proportional: 3.0 });

/// The arm's four plastic joints, shoulder first: weaker towards the hand (angular impulses of
/// 10.5 to 1.7 N·m·s in a step), so that all four give under the ball's hit. A bend goes on
/// after the hit at a damped rate, losing (1 rad/s² + p × rate) with p = 8/s at the shoulder
/// and 25/s further out, so that each joint settles at a comparable angle (26–29°). Found by a
/// search for values around which ±7 % on any strength or ±10 % on the ball's speed, mass or
/// hit point still bends every joint by 17–33°.
pub(crate) const ARM_JOINTS: [JointKind; ARM_BONES] = [
    JointKind::Bend(JointRule::Plastic { strength: 10.5, damping_constant: 1.0, damping_proportional: 8.0 }),
    JointKind::Bend(JointRule::Plastic { strength: 6.6, damping_constant: 1.0, damping_proportional: 25.0 }),
    JointKind::Bend(JointRule::Plastic { strength: 5.3, damping_constant: 1.0, damping_proportional: 25.0 }),
    JointKind::Bend(JointRule::Plastic { strength: 1.7, damping_constant: 1.0, damping_proportional: 25.0 }),
];

/// The body's centreline before its corners are rounded (xy plane, m): a tail at the left, the
/// torso lying along x, a shoulder, and the arm rising along +y.
const CORNERS: [Vec3; 6] = [
    Vec3::new(-2.2, 0.25, 0.0),
    Vec3::new(-1.6, 0.0, 0.0),
    Vec3::new(-0.6, 0.0, 0.0),
    Vec3::new(0.2, 0.15, 0.0),
    Vec3::new(0.5, 0.6, 0.0),
    Vec3::new(0.5, 2.2, 0.0),
];
/// Radii of the torso and of the arm, m.
const TORSO_RADIUS: f32 = 0.24;
const ARM_RADIUS: f32 = 0.1;
/// Where the ball hits the arm: this far from the end of the centreline, m (near the hand).
const HIT_FROM_END: f32 = 0.13;
/// The ball: radius (m), mass (kg), speed when it hits (m/s, along +x), and when (s).
const BALL: (f32, f32, f32, f32) = (0.13, 3.0, 9.0, 0.3);

/// Figure 15: the body (centreline 4.5 m long: a 2.9 m torso 0.48 m thick that narrows into a
/// 1.6 m arm 0.2 m thick; 500 kg/m³, about 250 kg) is a chain of torso bones and [`ARM_BONES`]
/// arm bones; the torso's joints are [`ARM_TORSO_JOINT`], the arm's [`ARM_JOINTS`] (per-joint
/// kinds through [`BendableDesc::joint_overrides`]). A torso bone is glued to a stand and there
/// is no gravity, so that nothing but the hit moves the body. A 3 kg ball hits the hand at 9 m/s
/// after 0.3 s; the arm whips and its four joints settle bent by 26–29°, alternately one way
/// and the other. Condensation is on: before the hit the whole body is one rigid cluster; the
/// hit dissolves it, and while the four arm joints bend the torso and the shoulder bone are one
/// cluster and the four arm bones are simulated individually; once they stop (about 0.5 s after
/// the hit), the body is one cluster again, keeping its bends. Full: 20 torso bones, 48 vertices
/// around, level set 112 cells long; demo: 12, 24 and 64.
pub(super) fn arm(size: SceneSize) -> Result<Scene, SimError> {
    let (torso_bones, around, resolution) = match size {
        SceneSize::Full => (20, 48, 112),
        SceneSize::Demo => (12, 24, 64),
    };
    let line = Centreline::smoothed(&CORNERS, 4);
    let length = line.length();
    let arm_start = length - ARM_LENGTH;
    let radius = |s: f32| {
        let tail = smoothstep(0.0, 0.7, s);
        let shoulder = smoothstep(arm_start - 0.35, arm_start + 0.1, s);
        let torso = 0.4 * TORSO_RADIUS + 0.6 * TORSO_RADIUS * tail;
        torso + (ARM_RADIUS - torso) * shoulder
    };
    let rings = (length / (std::f32::consts::TAU * ARM_RADIUS / around as f32)).ceil() as usize;
    let mesh = tube(&line, radius, rings, around)?;
    let knots: Vec<f32> = (0..=torso_bones)
        .map(|k| arm_start * k as f32 / torso_bones as f32)
        .chain((1..=ARM_BONES).map(|k| arm_start + ARM_LENGTH * k as f32 / ARM_BONES as f32))
        .collect();
    let bones = line.bones(&knots);

    let mut world = world(Vec3::ZERO)?;
    let glued = torso_bones / 2;
    let anchor = bones[glued].head;
    let stand_top = anchor.y - radius(knots[glued]) - 0.01;
    let stand = subdivided_box(Vec3::new(0.8, 0.6, 0.6), [2, 2, 2])?;
    let desc = BodyDesc::new("stand", stand).kind(BodyKind::Static).at(Vec3::new(anchor.x, stand_top - 0.3, 0.0));
    let stand = world.add(BodyDesc { color: GROUND, ..desc.collider(ColliderKind::Cuboid) })?;

    let (ball_radius, ball_mass, speed, lead) = BALL;
    let hit = line.at(length - HIT_FROM_END) - Vec3::X * ARM_RADIUS;
    let velocity = Vec3::X * speed;
    let (start, start_velocity) = launch(hit - Vec3::X * ball_radius, velocity, Vec3::ZERO, lead);
    let projectile = ball(ball_radius, 3)?;
    let density = ball_mass / projectile.volume();
    let desc = BodyDesc::new("ball", projectile).at(start).velocity(start_velocity).collider(ColliderKind::Ball);
    let surface = SurfaceMaterial { restitution: 0.3, friction: 0.4 };
    world.add(BodyDesc { density, color: ORANGE, surface, ..desc })?;

    let mut desc = BendableDesc::new("armadillo", mesh);
    desc.density = 500.0;
    desc.color = [0.32, 0.45, 0.75];
    desc.skeleton = SkeletonSpec::Bones(bones);
    desc.weights = WeightParams { resolution, ..WeightParams::default() };
    desc.joint = ARM_TORSO_JOINT;
    desc.joint_overrides =
        (0..ARM_BONES).map(|k| JointOverride { child: torso_bones + k, joint: ARM_JOINTS[k] }).collect();
    desc.surface = SurfaceMaterial { restitution: 0.3, friction: 0.6 };
    let mut bending = Bending::new();
    let body = bending.add(&mut world, desc)?;
    world.add_joint(stand, bending.bodies()[body].body_indices()[glued], anchor, JointKind::Rigid)?;
    bending.condense(CondenseSettings::default())?;

    let description = "Figure 15: a long body of many bones (a torso narrowing into an arm) is condensed into one \
                       rigid cluster; a ball hits the arm, whose four plastic joints bend while the rest of the \
                       body stays one cluster, and once quiet the body is one cluster again, keeping its bends.";
    let view = Vec3::new(0.15, -0.2, -1.0);
    let mut scene = finish("arm", world, view, |_| true, frames(size, 180, 120), description);
    scene.bending = bending;
    Ok(scene)
}

/// 0 below `a`, 1 above `b`, a smooth cubic ramp between.
fn smoothstep(a: f32, b: f32, x: f32) -> f32 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}
