//! Denting coupled with bending (paper §4, last paragraph): a hit on a sub-body dents the skinned
//! mesh, the displacement is mapped back to the rest mesh, and the sub-bodies are refitted.
//!
//! Tolerances: coordinates here are at most about 2 m, where an f32 ulp is 2.4e-7 m; the
//! paths compared differ only by frames composed in another order (a few roundings of each
//! coordinate, and maps Lipschitz in their inputs with constants of order one), so their
//! results agree to about 1e-6 m. The checks use 1e-5 m: 1/4000 of the 4 cm dents, while every
//! mistake they guard against (a frame or map-back missing, a dent applied twice or to the wrong
//! mesh) moves vertices by a sizeable part of the dent.

use dentbend::bend::JointRule;
use dentbend::bend::WeightParams;
use dentbend::glam::{Quat, Vec3};
use dentbend::mesh::{self, TriMesh};
use dentbend_solver::coupling::Simulation;
use dentbend_solver::coupling::{ArticulatedBody, BendDenter, BendableDesc, Bending, SkeletonSpec, dent_step};
use dentbend_solver::scene::{PLANK_DENT, PLANK_HIT, SceneSize, builtin_scene};
use dentbend_solver::sim::{
    BodyDesc, ColliderKind, CollisionEvent, DecidedDent, DentSettings, Denter, JointKind, SimError, World,
    WorldSettings,
};

/// Ball radius, m.
const RADIUS: f32 = 0.15;
/// Closing speed of the hits, m/s.
const SPEED: f32 = 5.0;
/// Path tolerance, m (see the module comment).
const TOLERANCE: f32 = 1e-5;
/// Hits per comparison: the second lands on the first's dent.
const STEPS: u64 = 2;

/// Threshold 1 m/s, 1 cm per m/s above it, cap 6 cm: 4 cm at 5 m/s.
fn settings(progressive: bool) -> DentSettings {
    DentSettings { progressive, ..DentSettings::new(1.0, 0.01, 0.06) }
}

/// A 2 × 0.4 × 0.4 m bar with 5 cm cells, so that a dent covers many vertices.
fn bar_mesh() -> TriMesh {
    mesh::plank(2.0, 0.4, 0.4, 40).unwrap()
}

/// The bar as a two-bone bending body (bone joint near x = 0), coarse level set for speed.
fn bendable(dent: Option<DentSettings>) -> BendableDesc {
    let mut desc = BendableDesc::new("bar", bar_mesh());
    desc.skeleton = SkeletonSpec::Auto { bones: 2 };
    desc.weights = WeightParams { resolution: 32, ..WeightParams::default() };
    desc.dent = dent;
    desc
}

fn world() -> World {
    World::new(WorldSettings { gravity: Vec3::ZERO, sleep_time: 0.0, ..Default::default() }).unwrap()
}

fn ball(at: Vec3, dent: Option<DentSettings>) -> BodyDesc {
    let desc = BodyDesc::new("ball", mesh::icosphere(RADIUS, 3).unwrap()).at(at).collider(ColliderKind::Ball);
    BodyDesc { dent, ..desc }
}

/// Body `a` hit at `point` by body `b` coming along `-up` (unit) at [`SPEED`].
fn hit(a: usize, b: usize, point: Vec3, up: Vec3) -> CollisionEvent {
    CollisionEvent { a, b, point, normal: up, relative_velocity: -SPEED * up, normal_speed: SPEED, impulse: Vec3::ZERO }
}

fn largest(deltas: impl Iterator<Item = Vec3>) -> f32 {
    deltas.map(Vec3::length).fold(0.0, f32::max)
}

fn displacement(before: &TriMesh, after: &TriMesh) -> Vec<Vec3> {
    after.positions().iter().zip(before.positions()).map(|(a, b)| *a - *b).collect()
}

/// Two steps' hits on the top face at x = `x` (in the blend near the bones' joint, or not) on a
/// plain dentable bar and on a bending one at rest: the rest-mesh displacements, the ball's dents
/// and the records agree. `placed`: both bars moved off the origin and turned (all bones alike,
/// still the rest pose), so the two paths work in differently placed frames.
fn plain_and_bending_agree(progressive: bool, ball_dents: bool, x: f32, placed: bool) {
    let (origin, turn) = match placed {
        true => (Vec3::new(0.3, 1.0, -0.2), Quat::from_rotation_y(0.35) * Quat::from_rotation_x(0.17)),
        false => (Vec3::ZERO, Quat::IDENTITY),
    };
    let (point, up) = (origin + turn * Vec3::new(x, 0.2, 0.0), turn * Vec3::Y);
    let ball_settings = ball_dents.then(|| settings(false));
    // Plain: the bar as one dynamic body with a hull collider, as the sub-bodies are.
    let mut plain = world();
    let bar = BodyDesc::new("bar", bar_mesh()).collider(ColliderKind::ConvexHull).dentable(settings(progressive));
    let target = plain.add(BodyDesc { orientation: turn, ..bar.at(origin) }).unwrap();
    let plain_ball = plain.add(ball(point + up * RADIUS, ball_settings.clone())).unwrap();
    let plain_before = (plain.bodies()[target].mesh().clone(), plain.bodies()[plain_ball].mesh().clone());
    let mut denter = Denter::new(&plain, None).unwrap();
    let mut plain_records = Vec::new();
    for step in 1..=STEPS {
        plain_records.extend(denter.process(&mut plain, &[hit(target, plain_ball, point, up)], step).unwrap());
    }

    // Bending, at rest: every bone transform the same.
    let mut posed = world();
    let mut bending = Bending::new();
    let desc = bendable(Some(settings(progressive)));
    bending.add(&mut posed, BendableDesc { position: origin, orientation: turn, ..desc }).unwrap();
    let projectile = posed.add(ball(point + up * RADIUS, ball_settings)).unwrap();
    let body = &bending.bodies()[0];
    let bone = body.skeleton().nearest_bone(Vec3::new(x, 0.0, 0.0)).unwrap().0;
    let sub_body = body.body_indices()[bone];
    let rest_before = body.rest_mesh().clone();
    let ball_before = posed.bodies()[projectile].mesh().clone();
    let (mut bend_denter, mut denter) = (BendDenter::new(), Denter::new(&posed, None).unwrap());
    let mut records = Vec::new();
    for step in 1..=STEPS {
        let events = [hit(sub_body, projectile, point, up)];
        // Nothing moves: no model transforms before (every body taken as still).
        let dents = dent_step(&mut bend_denter, &mut denter, &mut bending, &mut posed, &events, step, &[]);
        records.extend(dents.unwrap());
    }

    let what = format!("progressive {progressive}, ball dents {ball_dents}, x = {x}, placed {placed}");
    let expected = displacement(&plain_before.0, plain.bodies()[target].mesh());
    let got = displacement(&rest_before, bending.bodies()[0].rest_mesh());
    let worst = largest(expected.iter().zip(&got).map(|(a, b)| *a - *b));
    let depth = largest(expected.iter().copied());
    println!("{what}: dent {depth:.4} m, worst difference {worst:.2e} m");
    // Two 4 cm dents: stacked (about 6 cm) or, progressive, one of the accumulated 6 cm cap.
    assert!(depth > 0.05, "{what}: dent only {depth} m");
    assert!(worst <= TOLERANCE, "{what}: bending dent differs by {worst} m");
    if ball_dents {
        let plain_ball = displacement(&plain_before.1, plain.bodies()[plain_ball].mesh());
        let bend_ball = displacement(&ball_before, posed.bodies()[projectile].mesh());
        let worst = largest(plain_ball.iter().zip(&bend_ball).map(|(a, b)| *a - *b));
        let depth = largest(plain_ball.iter().copied());
        println!("{what}: ball dent {depth:.4} m, worst difference {worst:.2e} m");
        assert!(depth > 0.05, "{what}: ball dent only {depth} m");
        assert!(worst <= TOLERANCE, "{what}: ball dents differ by {worst} m");
    }
    // Same dents (the Simulation lists plain bodies' first, then bending bodies').
    let names = |r: &[dentbend_solver::sim::DentRecord]| {
        let mut list: Vec<_> = r.iter().map(|r| (r.target.clone(), r.projectile.clone(), r.dent_distance)).collect();
        list.sort_by(|a, b| a.partial_cmp(b).unwrap());
        list
    };
    assert_eq!(names(&records), names(&plain_records), "{what}");
    assert!(records.iter().any(|r| r.target == "bar" && r.projectile == "ball"), "{what}: {records:?}");
}

#[test]
fn a_bending_body_at_rest_dents_like_a_plain_body() {
    // Far from the joint (one bone's vertices) and at it (blended vertices), at the origin and
    // placed elsewhere.
    for placed in [false, true] {
        plain_and_bending_agree(false, false, 0.55, placed);
        plain_and_bending_agree(false, false, 0.05, placed);
    }
    // Progressive: the second hit deepens the first from the pre-dent mesh, in both.
    plain_and_bending_agree(true, false, 0.55, true);
    // Both dentable: both dents from the undented surfaces (Jacobi), as for a plain pair (the
    // ball dented by the bar's dented surface would differ by up to the dent in the hollow).
    // At the origin only: the bar's flat top face makes every vertex of it the "most advanced
    // point" the ball's dent map is centred on, a tie that rounding decides, so moving both
    // pairs by the same rigid motion can shift the ball's dent in the plain pair as well.
    plain_and_bending_agree(false, true, 0.05, false);
}

/// The bar with bone 1 turned by `angle` about z around the bones' joint (a bend held by a weak
/// plastic joint, which takes the bend as its new target), and two balls far away.
fn bent_bar(angle: f32) -> (World, ArticulatedBody, [usize; 2], Quat, Vec3) {
    let mut world = world();
    let mut desc = bendable(Some(settings(false)));
    desc.joint =
        JointKind::Bend(JointRule::Plastic { strength: 1e-3, damping_constant: 0.0, damping_proportional: 0.0 });
    let body = ArticulatedBody::new(&mut world, desc).unwrap();
    let joint = body.skeleton().joints()[0].point;
    let turn = Quat::from_rotation_z(angle);
    let index = body.body_indices()[1];
    let b = &mut world.bodies_mut()[index];
    b.position = joint + turn * (b.position - joint);
    b.orientation = turn * b.orientation;
    let far = |k: f32| ball(Vec3::new(0.0, 5.0 + k, 0.0), None);
    let balls = [world.add(far(0.0)).unwrap(), world.add(BodyDesc { name: "ball2".into(), ..far(1.0) }).unwrap()];
    (world, body, balls, turn, joint)
}

/// A head-on 4 cm dent by `ball` (put in place) at the rest point `rest` of bone 1's top face, in
/// the bent pose.
fn dent_at(world: &mut World, body: &ArticulatedBody, ball: usize, rest: Vec3, turn: Quat, joint: Vec3) -> DecidedDent {
    let point = joint + turn * (rest - joint);
    let up = turn * Vec3::Y;
    world.bodies_mut()[ball].position = point + up * RADIUS;
    let impact = dentbend::Impact { point, normal: -up, relative_velocity: -SPEED * up };
    DecidedDent { target: body.body_indices()[1], projectile: ball, impact, dent_distance: 0.04 }
}

#[test]
fn a_dent_on_a_bent_body_moves_with_its_bone() {
    let (mut world, mut body, balls, turn, joint) = bent_bar(30f32.to_radians());
    // One dent well inside bone 1, one at the joint where the two bones' weights blend.
    let far = dent_at(&mut world, &body, balls[0], Vec3::new(0.6, 0.2, 0.0), turn, joint);
    let near = dent_at(&mut world, &body, balls[1], Vec3::new(joint.x + 0.05, 0.2, 0.0), turn, joint);
    let dents = [(far, world.bodies()[balls[0]].surface()), (near, world.bodies()[balls[1]].surface())];
    let pose = body.dent_in_pose(&world, &body.rest_mesh().clone(), &dents).unwrap();

    let world_delta = displacement(&pose.skinned, &pose.dented);
    let rest_delta = displacement(body.rest_mesh(), &pose.rest_mesh);
    let deepest = (0..world_delta.len()).max_by(|&a, &b| world_delta[a].length().total_cmp(&world_delta[b].length()));
    let deepest = deepest.unwrap();
    let depth = world_delta[deepest].length();
    assert!(depth > 0.03, "dent only {depth} m");
    // The world dent points into the turned top face; mapped back, into the rest top face.
    let down = world_delta[deepest].normalize().dot(turn * -Vec3::Y);
    let rest_down = rest_delta[deepest].normalize().dot(-Vec3::Y);
    assert!(down > 0.99 && rest_down > 0.99, "world {down}, rest {rest_down}");
    // Without the map-back the rest displacement would be off by 2·sin 15° of the dent: the
    // re-skinning check below can tell.
    assert!(world_delta[deepest].distance(rest_delta[deepest]) > 0.4 * depth);
    // Blended vertices (both bones ≥ 0.2) moved: the near dent reached the joint's blend.
    let weights = body.weights();
    let blended = pose.moved.iter().filter(|&&v| {
        let (_, w) = weights.influences(v);
        w.iter().filter(|&&w| w >= 0.2).count() >= 2
    });
    assert!(blended.count() > 3, "no blended vertex dented");

    let before: Vec<TriMesh> = body.body_indices().iter().map(|&i| world.bodies()[i].world_mesh()).collect();
    let masses: Vec<f32> = body.body_indices().iter().map(|&i| world.bodies()[i].mass).collect();
    body.apply_pose_dent(&mut world, pose.clone()).unwrap();
    // Re-skinning the dented rest mesh gives the dented world mesh back.
    let skinned = body.skinned_mesh(&world).unwrap();
    let worst = largest(displacement(&pose.dented, &skinned).into_iter());
    println!("dent {depth:.4} m, re-skinning off by {worst:.2e} m");
    assert!(worst <= TOLERANCE, "re-skinned mesh off by {worst} m");

    // Only the sub-bodies owning a moved vertex changed; masses are kept (a dent moves material).
    assert_eq!(pose.bones, vec![0, 1], "both dents' bones");
    check_sub_bodies(&world, &body, &pose.moved, &before, &masses);
}

/// The sub-body world meshes changed exactly for the bones owning a vertex of `moved`.
fn check_sub_bodies(world: &World, body: &ArticulatedBody, moved: &[usize], before: &[TriMesh], masses: &[f32]) {
    let owners = body.sub_bodies().triangle_bones();
    for (bone, &index) in body.body_indices().iter().enumerate() {
        let owns = body
            .rest_mesh()
            .faces()
            .iter()
            .zip(owners)
            .any(|(f, &o)| o as usize == bone && f.iter().any(|v| moved.contains(&(*v as usize))));
        let after = world.bodies()[index].world_mesh();
        let changed = after.positions() != before[bone].positions();
        assert_eq!(changed, owns, "bone {bone}: changed {changed}, owns a moved vertex {owns}");
        assert_eq!(world.bodies()[index].mass, masses[bone], "bone {bone}: mass changed");
        // The sub-body's mesh is the dented rest mesh's part, where the bone puts it.
        let (sub, _) = body.sub_bodies().sub_mesh(body.rest_mesh(), bone).unwrap();
        let model = world.bodies()[index].model_transform();
        let worst =
            largest(after.positions().iter().zip(sub.positions()).map(|(a, p)| *a - model.transform_point3(*p)));
        assert!(worst <= TOLERANCE, "bone {bone}: sub-body mesh off by {worst} m");
    }
}

#[test]
fn only_the_dented_bones_sub_bodies_change_and_the_world_steps_on() {
    let (mut world, mut body, [ball, _], turn, joint) = bent_bar(30f32.to_radians());
    let dent = dent_at(&mut world, &body, ball, Vec3::new(0.6, 0.2, 0.0), turn, joint);
    let pose = body.dent_in_pose(&world, &body.rest_mesh().clone(), &[(dent, world.bodies()[ball].surface())]);
    let pose = pose.unwrap();
    assert_eq!(pose.bones, vec![1], "a dent 0.6 m into bone 1 reaches bone 0");
    let before: Vec<TriMesh> = body.body_indices().iter().map(|&i| world.bodies()[i].world_mesh()).collect();
    let masses: Vec<f32> = body.body_indices().iter().map(|&i| world.bodies()[i].mass).collect();
    let poses: Vec<_> = world.bodies().iter().map(|b| (b.position, b.orientation)).collect();
    body.apply_pose_dent(&mut world, pose.clone()).unwrap();
    check_sub_bodies(&world, &body, &pose.moved, &before, &masses);
    // Poses are kept exactly.
    assert!(world.bodies().iter().zip(&poses).all(|(b, p)| (b.position, b.orientation) == *p));

    // The world steps on: the joint holds the bent bar together, nothing blows up.
    world.bodies_mut()[ball].position = Vec3::new(0.0, 5.0, 0.0);
    for _ in 0..30 {
        world.step();
    }
    let joint = &world.joints()[0];
    let (a, b) = joint.anchors(world.bodies()).unwrap();
    let speed = world.bodies().iter().map(|b| b.linear_velocity.length()).fold(0.0, f32::max);
    println!("after 30 steps: anchors {:.2e} m apart, fastest body {speed:.2e} m/s", a.distance(b));
    assert!(a.distance(b) < 1e-3, "joint anchors {a} and {b} apart");
    assert!(world.bodies().iter().all(|b| b.position.is_finite()) && speed < 1e-3, "fastest body {speed} m/s");
}

#[test]
fn bad_dent_settings_on_a_bendable_body_are_refused() {
    let cases = [
        ("negative threshold", DentSettings::new(-1.0, 0.01, 0.06)),
        ("zero cap", DentSettings::new(1.0, 0.01, 0.0)),
        ("NaN gain", DentSettings::new(1.0, f32::NAN, 0.06)),
        ("negative hardness", DentSettings { hardness: Some(-5.0), ..settings(false) }),
    ];
    for (what, dent) in cases {
        let mut world = world();
        let error = Bending::new().add(&mut world, bendable(Some(dent))).expect_err(what);
        println!("{what}: {error}");
        assert!(matches!(&error, SimError::Dent { body, .. } if body == "bar"), "{what}: {error:?}");
        assert!(world.bodies().is_empty(), "{what}: the world changed");
    }
    // A body without dent settings cannot be dented by hand either.
    let mut world = world();
    let body = ArticulatedBody::new(&mut world, bendable(None)).unwrap();
    let ball = world.add(ball(Vec3::Y, None)).unwrap();
    let impact = dentbend::Impact::head_on(Vec3::new(0.5, 0.2, 0.0), -Vec3::Y);
    let dent = DecidedDent { target: body.body_indices()[1], projectile: ball, impact, dent_distance: 0.04 };
    let error = body.dent_in_pose(&world, body.rest_mesh(), &[(dent, world.bodies()[ball].surface())]);
    assert!(matches!(error, Err(SimError::Invalid { .. })), "{error:?}");
}

#[test]
fn the_plank_scene_dents_where_the_ball_lands_and_bends_there() {
    // Figure 14's plank is dentable: the ball's hit (about 6 m/s) leaves one dent of
    // gain·(v − threshold) ≈ 2 cm at the hit, the joint made there bends it.
    let scene = builtin_scene("plank", SceneSize::Demo).unwrap();
    let rest_before = scene.bending.bodies()[0].rest_mesh().clone();
    let mut sim = Simulation::new(scene.world, None).unwrap().with_bending(scene.bending);
    for _ in 0..20 {
        sim.step().unwrap();
    }
    let dents: Vec<_> = sim.dents().iter().filter(|d| d.target == "plank").collect();
    assert_eq!(dents.len(), 1, "{:?}", sim.dents());
    let dent = dents[0];
    let (threshold, gain, cap) = PLANK_DENT;
    let speed = dent.relative_velocity.dot(dent.normal.normalize());
    let expected = (gain * (speed - threshold)).min(cap);
    assert_eq!(dent.projectile, "ball");
    assert!((dent.dent_distance - expected).abs() < 1e-6 && dent.dent_distance > 0.01, "{dent:?}");
    assert!(dent.point.distance(PLANK_HIT) < 0.1, "dent at {}", dent.point);

    // The rest mesh is dented at the hit (in the rest frame the plank's top face is y = 0.05):
    // its deepest displacement is within a dent radius of the hit and about the dent distance
    // deep (the falloff and the map's sampling between vertices: within 30 %).
    let plank = sim.bending().find("plank").unwrap();
    let delta = displacement(&rest_before, plank.rest_mesh());
    let deepest = (0..delta.len()).max_by(|&a, &b| delta[a].length().total_cmp(&delta[b].length())).unwrap();
    let at = rest_before.positions()[deepest];
    println!("deepest {:.4} m at {at}, dent distance {:.4} m", delta[deepest].length(), dent.dent_distance);
    assert!((at - Vec3::new(PLANK_HIT.x, 0.05, 0.0)).length() < 0.15, "deepest rest move at {at}");
    assert!((delta[deepest].length() - dent.dent_distance).abs() < 0.3 * dent.dent_distance);
    assert!(delta[deepest].normalize().dot(-Vec3::Y) > 0.9, "rest dent along {}", delta[deepest]);
    // Vertices far from the hit (beyond 0.5 m) did not move.
    assert!(
        delta.iter().zip(rest_before.positions()).all(|(d, p)| (p.x - PLANK_HIT.x).abs() < 0.5 || *d == Vec3::ZERO)
    );
    // And it bends there: a joint was made at the hit.
    assert_eq!(sim.bending().joints().len(), 1);
}

/// The rest-mesh (bending) or body-mesh (plain) displacement of a 4 cm dent at x = 0.55 on the
/// bar's top face, the contact found with the bar where it starts; `moved`: the bar then moved
/// 10 cm down (as a hit pushes a plank down during the step) before the dent is made;
/// `carried`: the dent is told the bodies' model transforms before that move.
fn dent_after_a_move(bending: bool, moved: bool, carried: bool) -> Vec<Vec3> {
    let point = Vec3::new(0.55, 0.2, 0.0);
    let mut world = world();
    let mut bodies = Bending::new();
    let (targets, hit_body) = if bending {
        bodies.add(&mut world, bendable(Some(settings(false)))).unwrap();
        let body = &bodies.bodies()[0];
        (body.body_indices().to_vec(), body.body_indices()[body.skeleton().nearest_bone(point).unwrap().0])
    } else {
        let bar = BodyDesc::new("bar", bar_mesh()).collider(ColliderKind::ConvexHull).dentable(settings(false));
        let index = world.add(bar).unwrap();
        (vec![index], index)
    };
    let projectile = world.add(ball(point + Vec3::Y * RADIUS, None)).unwrap();
    let before: Vec<_> = world.bodies().iter().map(|b| b.model_transform()).collect();
    if moved {
        targets.iter().for_each(|&i| world.bodies_mut()[i].position -= Vec3::Y * 0.1);
    }
    let mesh = |world: &World, bodies: &Bending| match bending {
        true => bodies.bodies()[0].rest_mesh().clone(),
        false => world.bodies()[hit_body].mesh().clone(),
    };
    let start = mesh(&world, &bodies);
    let events = [hit(hit_body, projectile, point, Vec3::Y)];
    let before = if carried { before } else { Vec::new() };
    let mut denter = Denter::new(&world, None).unwrap();
    dent_step(&mut BendDenter::new(), &mut denter, &mut bodies, &mut world, &events, 1, &before).unwrap();
    displacement(&start, &mesh(&world, &bodies))
}

#[test]
fn a_contact_is_carried_with_a_target_that_moved_on() {
    for bending in [false, true] {
        // Carried with the bar's motion, the dent is the one the bar gets where it was hit.
        let still = dent_after_a_move(bending, false, true);
        let carried = dent_after_a_move(bending, true, true);
        let worst = largest(still.iter().zip(&carried).map(|(a, b)| *a - *b));
        let depth = largest(still.iter().copied());
        assert!(depth > 0.035, "bending {bending}: dent only {depth} m");
        assert!(worst <= TOLERANCE, "bending {bending}: carried dent differs by {worst} m");
        // Left where the contact was, it lies 10 cm above the surface and the falloff
        // (2/(1 + e^(z/d)) = 0.15 at z = 2.5 d) leaves little of it.
        let left = largest(dent_after_a_move(bending, true, false).into_iter());
        println!("bending {bending}: dent {depth:.4} m, carried off by {worst:.2e} m, left behind {left:.4} m");
        assert!(left < 0.3 * depth, "bending {bending}: dent left behind is {left} m deep");
    }
}

#[test]
fn a_ball_touching_two_bones_dents_once() {
    // A ball landing on the bones' joint touches both sub-bodies: the two contacts are one
    // impact on the mesh (impulse-weighted point, here the middle), so one 4 cm dent, not two
    // stacked ones (about 6 cm, see the comparison test).
    let mut world = world();
    let mut bending = Bending::new();
    bending.add(&mut world, bendable(Some(settings(false)))).unwrap();
    let body = &bending.bodies()[0];
    let joint = body.skeleton().joints()[0].point;
    let point = Vec3::new(joint.x, 0.2, 0.0);
    let projectile = world.add(ball(point + Vec3::Y * RADIUS, None)).unwrap();
    let rest = body.rest_mesh().clone();
    let offset = Vec3::X * 0.01;
    let events: Vec<CollisionEvent> = body
        .body_indices()
        .iter()
        .zip([-offset, offset])
        .map(|(&sub, shift)| CollisionEvent { impulse: Vec3::Y, ..hit(sub, projectile, point + shift, Vec3::Y) })
        .collect();
    let mut denter = Denter::new(&world, None).unwrap();
    let records = dent_step(&mut BendDenter::new(), &mut denter, &mut bending, &mut world, &events, 1, &[]).unwrap();
    assert_eq!(records.len(), 1, "{records:?}");
    assert!(records[0].point.distance(point) < 1e-6, "merged contact at {}", records[0].point);
    let depth = largest(displacement(&rest, bending.bodies()[0].rest_mesh()).into_iter());
    assert!((depth - 0.04).abs() < 0.1 * 0.04, "dent {depth} m for d = 0.04 m");
}
