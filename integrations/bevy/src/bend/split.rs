//! Dynamic articulation in Bevy (paper §4.2): a hit on a bendable body's bone whose normal
//! approach speed reaches `settings.split_speed` splits the bone where it lands
//! ([`Rig::split`](dentbend::bend::Rig::split)): the hit bone's entity keeps the first half,
//! a new bone entity (same pose and velocity) takes the second, the joints of the bone's far
//! half move to it, a joint of the body's rule joins the halves, and every bone whose sub-body
//! the split recut gets its new hull.

use bevy::prelude::*;
use dentbend::bend::JointState;
use dentbend::glam::Quat;

use super::rig::register_skin;
use super::{BendPiece, Bends, Joint, Rig};
use crate::engine::Engine;
use crate::link::MainLink;
use crate::mesh_data::slab_layout;
use crate::{DentBody, DentContact, DentPath, DentStats};

/// A split to make: the body, the hit bone and where the hit landed (rest frame), with both
/// sides of the contact as they were before the step.
struct Split {
    owner: Entity,
    bone: usize,
    rest_point: Vec3,
    hit: DentBody,
    hitter: DentBody,
}

/// Splits the bones that this step's fast hits landed on (one split per bone a step).
pub(crate) fn split_bones<E: Engine>(
    mut commands: Commands,
    mut contacts: MessageReader<DentContact>,
    mut bends: ResMut<Bends>,
    pieces: Query<&BendPiece>,
    bodies: Query<&E::Body>,
    mut stats: ResMut<DentStats>,
    (link, meshes): (Res<MainLink>, Res<Assets<Mesh>>),
) {
    let mut splits: Vec<Split> = Vec::new();
    for c in contacts.read().filter(|c| c.started) {
        for (bone, other, normal) in [(c.a, c.b, -c.normal), (c.b, c.a, c.normal)] {
            let Ok(piece) = pieces.get(bone.entity) else { continue };
            let Some(rig) = bends.rigs.get(&piece.owner) else { continue };
            let Some(speed) = rig.settings.split_speed else { continue };
            let approach = (other.state.velocity_at(c.point) - bone.state.velocity_at(c.point)).dot(normal.normalize());
            // NaN (a degenerate normal) is no split.
            let fast = approach.is_finite() && approach >= speed;
            if !fast || splits.iter().any(|s| s.owner == piece.owner && s.bone == piece.bone) {
                continue;
            }
            let rest_point = bone.pose.inverse().transform_point3(c.point);
            let joints = rig.joints.iter().map(|j| j.point);
            if rig.core.split_point(piece.bone, rest_point, rig.settings.min_joint_spacing, joints).is_some() {
                splits.push(Split { owner: piece.owner, bone: piece.bone, rest_point, hit: bone, hitter: other });
            }
        }
    }
    for s in splits {
        let Some(rig) = bends.rigs.get_mut(&s.owner) else { continue };
        match split::<E>(&mut commands, rig, &s, &pieces) {
            Ok(true) => {
                stats.splits += 1;
                // The hit is solved again next step, against the articulated body: what hit it
                // goes back to where and how it was before the step (a dynamic body whose entity
                // is the one hit: a fixed or kinematic one is where its owner puts it).
                if bodies.get(s.hitter.entity).is_ok_and(E::is_dynamic) {
                    E::place(&mut commands, s.hitter.entity, pre_step_transform(&s.hitter), pre_step_motion(&s.hitter));
                }
                rig.last.clear();
                if rig.path == DentPath::Gpu
                    && let Some(layout) = meshes.get(&rig.mesh).and_then(|m| slab_layout(m).ok())
                {
                    register_skin(&link, s.owner, rig.mesh.id(), &rig.core, layout);
                }
            }
            Ok(false) => {}
            Err(e) => warn!("bevy_dentbend: bendable {} is not split: {e}", s.owner),
        }
    }
}

/// Makes split `s` of `rig`; whether it was made (a point too near the bone's ends is not).
fn split<E: Engine>(
    commands: &mut Commands,
    rig: &mut Rig,
    s: &Split,
    pieces: &Query<&BendPiece>,
) -> Result<bool, String> {
    let Some(made) = rig.core.split(s.bone, s.rest_point, 0.0).map_err(|e| e.to_string())? else { return Ok(false) };
    let (first, second, at) = (made.bone, made.new_bone, made.joint_point);
    let changed = made.changed.clone();
    let mut core = rig.core.clone();
    core.apply_split(made).map_err(|e| e.to_string())?;
    let part = |bone: usize| -> Result<Vec<Vec3>, String> {
        Ok(core.part(bone).map_err(|e| e.to_string())?.positions().to_vec())
    };
    let hull = |bone: usize| E::hull(&part(bone)?).ok_or(format!("bone {bone}'s new part has no convex hull"));
    let recut: Vec<(usize, E::Collider)> = changed.iter().map(|&b| Ok((b, hull(b)?))).collect::<Result<_, String>>()?;
    let old = rig.pieces[first];
    pieces.get(old).map_err(|_| format!("bone {first}'s entity is gone"))?;
    // Both halves start from the hit bone's pose and velocity before the step.
    let (transform, motion) = (pre_step_transform(&s.hit), pre_step_motion(&s.hit));
    let material = (rig.settings.density, rig.settings.friction);
    let second_body = E::bone_body(&part(second)?, material, transform, motion)
        .ok_or(format!("bone {second}'s new part has no convex hull"))?;
    // Checked: commit.
    rig.core = core;
    E::place(commands, old, transform, motion);
    for (bone, collider) in recut {
        commands.entity(rig.pieces[bone]).insert(collider);
    }
    let new = commands.spawn((BendPiece { owner: s.owner, bone: second }, second_body)).id();
    rig.pieces.push(new);
    // Joints from the split bone to its children now start at the second half.
    for joint in rig.joints.iter_mut().filter(|j| j.parent == first) {
        if rig.core.skeleton().bones()[joint.child].parent == Some(second) {
            joint.parent = second;
            if let Some(link) = joint.link {
                commands.entity(link).try_despawn();
            }
            joint.link = E::join(commands, new, rig.pieces[joint.child], joint.point);
        }
    }
    let rule = JointState::new(rig.settings.joint, Quat::IDENTITY).map_err(|e| e.to_string())?;
    let link = E::join(commands, old, new, at);
    rig.joints.push(Joint { parent: first, child: second, point: at, rule, link });
    Ok(true)
}

/// `body`'s transform before the step (its pose: rigid).
fn pre_step_transform(body: &DentBody) -> Transform {
    Transform::from_matrix(Mat4::from(body.pose))
}

/// `body`'s motion before the step: its centre of mass's velocity and its spin.
fn pre_step_motion(body: &DentBody) -> (Vec3, Vec3) {
    (body.state.linear_velocity, body.state.angular_velocity)
}
