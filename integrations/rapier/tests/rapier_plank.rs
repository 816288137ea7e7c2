//! What `rapier_plank` shows (Figure 14 in Rapier): a joint appears where the ball hits, the
//! plank bends plastically and stays bent after the ball is gone, and its ends stay straight.

use dentbend_rapier::demo::plank::{HIT_X, PLANK_SIZE, Plank};
use dentbend_rapier::{AdapterError, BodyStates, Contact, JointState};
use glam::{Quat, Vec3};

/// Steps until the bend has settled (the post-bend rate decays as e^(−10 t): 1 s is plenty).
const SETTLE: usize = 60;

/// Angle between the two pieces' orientations, degrees: the plank's actual bend.
fn pieces_angle(p: &Plank) -> f32 {
    let pieces = p.plank().pieces();
    let r = |i: usize| -> Quat { *p.world.bodies.get(pieces[i].body).unwrap().rotation() };
    (r(0).inverse() * r(1)).normalize().angle_between(Quat::IDENTITY).to_degrees()
}

#[test]
fn a_joint_appears_where_the_ball_hits() {
    let mut p = Plank::new(64).unwrap();
    let totals = p.run(SETTLE).unwrap();
    assert_eq!(totals.joints_created, 1);
    let joints = p.plank().joints();
    assert_eq!(joints.len(), 1);
    assert_eq!(p.plank().skeleton().len(), 2);
    assert_eq!(p.plank().pieces().len(), 2);
    // The ball falls straight down on x = HIT_X: the joint lies on the bone (the plank's axis)
    // there, within 1 cm (the contact point is the impulse-weighted mean of Rapier's solver
    // contacts between a ball and a box face: at the ball's lowest point).
    let at = joints[0].rest_point;
    assert!((at - Vec3::new(HIT_X, 0.0, 0.0)).length() < 0.01, "joint at {at}");
    // The ball lands within the first 0.1 s.
    assert!(totals.split_step.is_some_and(|s| s <= 6), "split at {:?}", totals.split_step);
    assert!(joints[0].dynamic && matches!(joints[0].rule, JointState::Plastic(_)));
}

#[test]
fn the_plank_bends_plastically_and_stays_bent_after_the_ball_is_gone() {
    let mut p = Plank::new(64).unwrap();
    let totals = p.run(SETTLE).unwrap();
    assert!(totals.plastic_bends >= 1);
    let bent = p.plank().joints()[0].bend_angle().to_degrees();
    let actual = pieces_angle(&p);
    // The joint bent by more than 5°, and the pieces follow its rest orientation (within the
    // drift the rule corrects: 1°).
    assert!(bent > 5.0, "bend {bent}°");
    assert!((actual - bent).abs() < 1.0, "pieces at {actual}°, joint rest at {bent}°");

    // Take the ball away: a plastic joint does not spring back.
    assert!(p.world.remove_body(p.ball));
    p.run(SETTLE).unwrap();
    let after = pieces_angle(&p);
    assert!(after > 5.0 && (after - actual).abs() < 1.0, "bend {actual}° with the ball, {after}° without");
    assert!((p.plank().joints()[0].bend_angle().to_degrees() - bent).abs() < 0.5);
}

#[test]
fn the_plank_ends_stay_straight() {
    let mut p = Plank::new(64).unwrap();
    p.run(SETTLE).unwrap();
    let plank = p.plank();
    let skinned = plank.skinned_mesh(&p.world).unwrap();
    let transforms = plank.bone_transforms(&p.world).unwrap();
    let rest = plank.rest_mesh().positions();
    // The outer 0.5 m of each side: its skinned vertices are a rigid motion (its bone's
    // transform) of its rest vertices, within 1 % of the thickness.
    let tolerance = 0.01 * PLANK_SIZE.y;
    let mut checked = 0;
    for (v, r) in rest.iter().enumerate() {
        if r.x.abs() < 0.5 * PLANK_SIZE.x - 0.5 {
            continue;
        }
        let (bone, _, _) = plank.skeleton().nearest_bone(*r).unwrap();
        let rigid = transforms[bone].transform_point3(*r);
        let off = rigid.distance(skinned.positions()[v]);
        assert!(off < tolerance, "vertex {v} at rest {r}: {off} m off its bone's rigid motion");
        checked += 1;
    }
    assert!(checked > 20, "{checked} end vertices");
    // And the ends are bent relative to each other: the bend is at the joint, not spread.
    assert!(pieces_angle(&p) > 5.0);
}

#[test]
fn a_bad_contact_changes_no_joint_or_body() {
    let mut p = Plank::new(64).unwrap();
    p.run(SETTLE).unwrap();
    let states = BodyStates::record(&p.world.bodies, &p.world.colliders);
    let piece = p.plank().pieces()[0];
    let joints_before: Vec<_> = p.plank().joints().to_vec();
    let poses: Vec<_> = p.plank().pieces().iter().map(|pc| *p.world.bodies.get(pc.body).unwrap().position()).collect();
    let vels: Vec<_> = p.plank().pieces().iter().map(|pc| p.world.bodies.get(pc.body).unwrap().angvel()).collect();
    let bad = Contact {
        collider1: piece.collider,
        collider2: piece.collider,
        point: Vec3::new(f32::NAN, 0.0, 0.0),
        normal: Vec3::Y,
        impulse: 1.0,
        started: true,
    };
    let err = p.adapter.after_step(&mut p.world, &states, vec![bad], 0.0).unwrap_err();
    assert!(matches!(err, AdapterError::NonFiniteContact { .. }), "{err}");
    assert_eq!(p.plank().joints(), &joints_before[..]);
    for (i, pc) in p.plank().pieces().iter().enumerate() {
        let rb = p.world.bodies.get(pc.body).unwrap();
        assert_eq!(*rb.position(), poses[i]);
        assert_eq!(rb.angvel(), vels[i]);
    }
}

#[test]
fn the_ball_dents_the_plank_where_it_lands() {
    let mut p = Plank::new(64).unwrap();
    let totals = p.run(SETTLE).unwrap();
    let (threshold, gain, cap) = dentbend_rapier::demo::plank::PLANK_DENT;
    assert!(totals.dents >= 1);
    assert!(totals.max_dent_depth <= cap + 1e-6);
    let plank = p.plank();
    let before = dentbend::mesh::plank(PLANK_SIZE.x, PLANK_SIZE.z, PLANK_SIZE.y, 64).unwrap();
    let after = plank.rest_mesh();
    assert_eq!(after.vertex_count(), before.vertex_count());
    // The dent's reach in the rest frame: the ball's radius plus 5σ (σ = cap / 2 by default).
    let reach = dentbend_rapier::demo::plank::BALL_RADIUS + 5.0 * 0.5 * cap;
    let hit = Vec3::new(HIT_X, 0.5 * PLANK_SIZE.y, 0.0);
    let mut deepest: f32 = 0.0;
    for (v, (a, b)) in before.positions().iter().zip(after.positions()).enumerate() {
        let m = a.distance(*b);
        assert!(m.is_finite());
        if m <= 1e-6 {
            continue;
        }
        let lateral = Vec3::new(a.x - hit.x, 0.0, a.z - hit.z).length();
        assert!(lateral <= reach, "rest vertex {v} at {a} moved {m} m, {lateral} m off the hit");
        if m > 0.01 * cap {
            assert!(a.distance(hit) <= reach, "rest vertex {v} at {a} moved {m} m");
        }
        assert!(m <= 1.01 * cap * totals.dents as f32, "rest vertex {v} moved {m} m");
        deepest = deepest.max(m);
    }
    // The ball lands at about 6 m/s: about (6 − 2) · 5 mm = 2 cm; at least half of it shows in
    // the rest mesh (the mapping back is a rotation: lengths are kept).
    let expected = (dentbend_rapier::demo::plank::BALL_SPEED - threshold) * gain;
    assert!(deepest >= 0.5 * expected, "deepest {deepest} m, expected about {expected} m");
    // The pieces' hulls are the dented sub-bodies'.
    for piece in plank.pieces() {
        let hull = p.world.colliders.get(piece.collider).unwrap().shape().as_convex_polyhedron().unwrap();
        assert!(hull.points().iter().all(|q| after.positions().contains(q)));
    }
    assert!(plank.skinned_mesh(&p.world).unwrap().positions().iter().all(|q| q.is_finite()));
}

#[test]
fn pieces_stay_in_bone_order_after_the_split() {
    let mut p = Plank::new(64).unwrap();
    p.run(SETTLE).unwrap();
    for (b, piece) in p.plank().pieces().iter().enumerate() {
        assert_eq!(piece.bone, b);
    }
}
