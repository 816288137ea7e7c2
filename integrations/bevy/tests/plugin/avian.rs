//! Avian 0.8 as the contact source (`avian` feature): a ball dropped on a fixed block dents it
//! and the block's Avian collider follows the dent vertex for vertex; a ball breaks a prescored
//! wall, its pieces become dynamic Avian bodies with the pieces' own masses and the ball goes
//! through the hole; Avian stepping in `PostUpdate` instead of its default `FixedPostUpdate` is
//! followed; a collider on a parent body dents its child mesh; a paused Avian sends no contact;
//! a body's locked rotation axes take no angular impulse in the state the plug-in records; a
//! bendable plank of Avian bodies splits where a fast ball lands, bends there and keeps its dent.

use crate::common;
use libtest_mimic::Trial;

use avian3d::prelude::*;
use bevy::prelude::*;
use bevy_dentbend::dentbend::bend::auto_skeleton;
use bevy_dentbend::dentbend::dent::DentSettings;
use bevy_dentbend::dentbend::fracture::{FractureSettings, PatternParams};
use bevy_dentbend::dentbend::{TriMesh, mesh};
use bevy_dentbend::{
    BendPiece, BendSettings, Bendable, Bends, DentContact, DentPiece, DentProjectile, DentStats, DentWorld, Dentable,
    DentbendPlugin, bevy_mesh,
};

/// An app stepping Avian (in `schedule`) and the plug-in (CPU path) 1/60 s a frame.
fn app(schedule: impl bevy::ecs::schedule::ScheduleLabel) -> App {
    let mut app = common::physics_app(PhysicsPlugins::new(schedule), DentbendPlugin::cpu_only());
    app.insert_resource(Time::<Fixed>::from_hz(60.0));
    app
}

/// The fixed block: 2 × 0.5 × 2 m, 16 × 4 × 16 cells, top face at y = 0.25.
fn block() -> TriMesh {
    mesh::subdivided_box(Vec3::new(2.0, 0.5, 2.0), [16, 4, 16]).expect("a box")
}

/// Spawns the fixed block, a static Avian tri-mesh denting 1 cm per m/s over 2 m/s (at most
/// 5 cm); its entity.
fn spawn_block(app: &mut App) -> Entity {
    let tri = block();
    let mesh = app.world_mut().resource_mut::<Assets<Mesh>>().add(bevy_mesh(&tri));
    let collider = Collider::trimesh(tri.positions().to_vec(), tri.faces().to_vec());
    app.world_mut()
        .spawn((Mesh3d(mesh), Transform::default(), RigidBody::Static, collider, Dentable::new(2.0, 0.01, 0.05)))
        .id()
}

/// Spawns a dynamic Avian ball of `radius` m and `mass` kg at `at` moving at `velocity` m/s, a
/// projectile; its entity.
fn launch_ball(app: &mut App, at: Vec3, radius: f32, mass: f32, velocity: Vec3) -> Entity {
    let mesh = app.world_mut().resource_mut::<Assets<Mesh>>().add(Sphere::new(radius).mesh().ico(3).expect("a sphere"));
    let density = mass / (4.0 / 3.0 * std::f32::consts::PI * radius.powi(3));
    app.world_mut()
        .spawn((
            Mesh3d(mesh),
            Transform::from_translation(at),
            RigidBody::Dynamic,
            Collider::sphere(radius),
            ColliderDensity(density),
            LinearVelocity(velocity),
            DentProjectile,
        ))
        .id()
}

/// The tri-mesh vertices of `entity`'s Avian collider (its entity's coordinates).
fn collider_vertices(app: &App, entity: Entity) -> Vec<Vec3> {
    let collider = app.world().get::<Collider>(entity).expect("a collider");
    collider.shape().as_trimesh().expect("a tri-mesh").vertices().to_vec()
}

/// One ball at 6 m/s on the block in `schedule`: one dent, and the collider is the dented mesh
/// (to 1e-5 m: the refit copies the mesh's f32 positions; the bound only allows for a rebuild's
/// reordering-free copy).
fn a_dropped_ball_dents(schedule: impl bevy::ecs::schedule::ScheduleLabel) {
    let mut app = app(schedule);
    let block = spawn_block(&mut app);
    launch_ball(&mut app, Vec3::new(0.1, 0.8, 0.2), 0.1, 8.0, Vec3::new(0.0, -6.0, 0.0));
    for _ in 0..60 {
        app.update();
    }
    assert_eq!(app.world().resource::<DentStats>().dents, 1, "the ball's one dent");
    let dented = app.world().resource::<DentWorld>().mesh(block).expect("the block").clone();
    let deepest = dented.positions().iter().map(|p| p.y).fold(f32::INFINITY, f32::min);
    let top = dented.positions().iter().filter(|p| p.y > 0.0).map(|p| p.y).fold(f32::INFINITY, f32::min);
    // Impact ≈ 6.5 m/s: (6.5 − 2) × 1 cm ≈ 4.5 cm deep, under the 5 cm cap; the lowest top-face
    // vertex must be at least 2 cm down (a dent), the bottom face untouched.
    assert!(top < 0.25 - 0.02, "the top face is dented (lowest top vertex at y = {top})");
    assert!((deepest + 0.25).abs() < 1e-6, "the bottom face stays at y = -0.25 ({deepest})");
    let vertices = collider_vertices(&app, block);
    assert_eq!(vertices.len(), dented.vertex_count());
    for (v, p) in vertices.iter().zip(dented.positions()) {
        assert!((*v - *p).length() < 1e-5, "collider vertex {v} against the mesh's {p}");
    }
}

/// A 50 kg ball at 12 m/s (3.6 kJ) against a wall of toughness 1 kJ, without gravity.
fn a_ball_breaks_a_wall_into_avian_bodies() {
    let mut app = app(FixedPostUpdate);
    app.insert_resource(Gravity(Vec3::ZERO));
    let tri = mesh::subdivided_box(Vec3::new(3.0, 2.0, 0.2), [60, 40, 2]).expect("a box");
    let pattern = PatternParams { cells: 40, seed: 3, radius: 0.5 };
    let mut fracture = FractureSettings::new(pattern, Some(1000.0), None).expect("settings");
    fracture.density = 300.0;
    let mesh = app.world_mut().resource_mut::<Assets<Mesh>>().add(bevy_mesh(&tri));
    let collider = Collider::trimesh(tri.positions().to_vec(), tri.faces().to_vec());
    let dentable = Dentable::new(2.0, 0.002, 0.03).breaking(fracture);
    let wall = app
        .world_mut()
        .spawn((Mesh3d(mesh), Transform::from_xyz(0.0, 1.0, 0.0), RigidBody::Static, collider, dentable))
        .id();
    let ball = launch_ball(&mut app, Vec3::new(0.2, 1.1, 1.0), 0.2, 50.0, Vec3::new(0.0, 0.0, -12.0));
    for _ in 0..60 {
        app.update();
    }
    let stats = app.world().resource::<DentStats>().clone();
    assert_eq!(stats.fractures, 1, "{stats:?}");
    assert!(stats.pieces >= 20, "{stats:?}");
    let mut q = app.world_mut().query::<(&DentPiece, &RigidBody, &Collider, &ComputedMass)>();
    let pieces: Vec<_> = q.iter(app.world()).collect();
    assert_eq!(pieces.len() as u64, stats.pieces, "every piece became a body");
    for (piece, body, collider, mass) in &pieces {
        assert_eq!(piece.from, wall);
        assert_eq!(**body, RigidBody::Dynamic);
        assert!(collider.shape().as_convex_polyhedron().is_some());
        // Avian's mass is the piece's (f32 through Avian's inverse), not the hull's density.
        let expected = piece.mass.mass;
        assert!((mass.value() - expected).abs() < 1e-3 * expected, "mass {} against {expected}", mass.value());
    }
    let rest = app.world().resource::<DentWorld>().mesh(wall).expect("the wall stays").clone();
    assert_eq!(collider_vertices(&app, wall).len(), rest.vertex_count(), "the collider is the rest");
    let z = app.world().get::<Position>(ball).expect("the ball").0.z;
    assert!(z < -0.3, "the ball at z = {z} did not go through the hole");
}

/// The `Dentable` and body on a parent, the mesh on its child offset from it: contacts on the
/// parent's collider dent the child's mesh, and the collider follows in the parent's coordinates.
fn a_parent_collider_dents_its_child_mesh() {
    let mut app = app(FixedPostUpdate);
    let tri = block();
    let offset = Vec3::new(0.3, 0.25, -0.2);
    let mesh = app.world_mut().resource_mut::<Assets<Mesh>>().add(bevy_mesh(&tri));
    let placed: Vec<Vec3> = tri.positions().iter().map(|&p| p + offset).collect();
    let collider = Collider::trimesh(placed, tri.faces().to_vec());
    let parent = app.world_mut().spawn((Transform::default(), RigidBody::Static, collider)).id();
    let child = app
        .world_mut()
        .spawn((Mesh3d(mesh), Transform::from_translation(offset), ChildOf(parent), Dentable::new(2.0, 0.01, 0.05)))
        .id();
    launch_ball(&mut app, offset + Vec3::new(0.1, 0.8, 0.2), 0.1, 8.0, Vec3::new(0.0, -6.0, 0.0));
    for _ in 0..60 {
        app.update();
    }
    assert_eq!(app.world().resource::<DentStats>().dents, 1, "the ball's one dent");
    let dented = app.world().resource::<DentWorld>().mesh(child).expect("the child mesh").clone();
    assert_ne!(dented.positions(), tri.positions(), "the mesh moved");
    for (v, p) in collider_vertices(&app, parent).iter().zip(dented.positions()) {
        assert!((*v - (*p + offset)).length() < 1e-5, "collider vertex {v} against the mesh's {p} + {offset}");
    }
}

/// A dynamic, turned block (0.5 rad about y) falls at 6 m/s onto a fixed ball: the dent is on
/// its bottom face where the ball met it, in the block's own coordinates (its pose and state
/// before the step in Avian's frames). The dent's centre, the mean of the moved bottom
/// vertices weighted by how far they moved, must lie within 6 cm (one cell of the 32 × 32
/// bottom face) of the ball's top mapped into the block.
fn a_moving_turned_body_dents_where_it_was_hit() {
    let mut app = app(FixedPostUpdate);
    let tri = mesh::subdivided_box(Vec3::new(2.0, 0.5, 2.0), [32, 4, 32]).expect("a box");
    let mesh = app.world_mut().resource_mut::<Assets<Mesh>>().add(bevy_mesh(&tri));
    let collider = Collider::trimesh(tri.positions().to_vec(), tri.faces().to_vec());
    let turn = Quat::from_rotation_y(0.5);
    let centre = Vec3::new(0.2, 0.1 + 0.25 + 0.2, -0.1);
    let block = app
        .world_mut()
        .spawn((
            Mesh3d(mesh),
            Transform::from_translation(centre).with_rotation(turn),
            RigidBody::Dynamic,
            collider,
            ColliderDensity(500.0),
            LinearVelocity(Vec3::new(0.0, -6.0, 0.0)),
            Dentable::new(2.0, 0.01, 0.05),
        ))
        .id();
    let ball = app.world_mut().resource_mut::<Assets<Mesh>>().add(Sphere::new(0.1).mesh().ico(3).expect("a sphere"));
    app.world_mut().spawn((
        Mesh3d(ball),
        Transform::default(),
        RigidBody::Static,
        Collider::sphere(0.1),
        DentProjectile,
    ));
    for _ in 0..20 {
        app.update();
    }
    assert_eq!(app.world().resource::<DentStats>().dents, 1, "one dent");
    let dented = app.world().resource::<DentWorld>().mesh(block).expect("the block").clone();
    let (mut sum, mut weight) = (Vec3::ZERO, 0.0);
    for (p, q) in tri.positions().iter().zip(dented.positions()) {
        let moved = p.distance(*q);
        if moved > 1e-5 {
            assert!(p.y < -0.2, "only the bottom face moves (vertex at {p} moved)");
            sum += *p * moved;
            weight += moved;
        }
    }
    let dent_centre = sum / weight;
    let expected = turn.inverse() * (Vec3::new(0.0, 0.1, 0.0) - centre);
    let off = Vec2::new(dent_centre.x - expected.x, dent_centre.z - expected.z).length();
    assert!(off < 0.06, "the dent is centred at {dent_centre}, {off} m from the hit at {expected}");
}

/// The contacts the plug-in received, counted.
#[derive(Resource, Default)]
struct Received(usize);

fn count_contacts(mut contacts: MessageReader<DentContact>, mut received: ResMut<Received>) {
    received.0 += contacts.read().count();
}

/// A ball resting on the block pushes on it every step (a contact each step, 1 m/s: no dent);
/// with Avian's clock paused no step runs, and no contact may be sent (the contact graph still
/// holds the last step's pairs).
fn a_paused_avian_sends_no_contacts() {
    let mut app = app(FixedPostUpdate);
    app.init_resource::<Received>().add_systems(PostUpdate, count_contacts);
    spawn_block(&mut app);
    launch_ball(&mut app, Vec3::new(0.1, 0.36, 0.2), 0.1, 8.0, Vec3::new(0.0, -1.0, 0.0));
    for _ in 0..30 {
        app.update();
    }
    assert!(app.world().resource::<Received>().0 >= 10, "the resting ball pushes every step");
    app.world_mut().resource_mut::<Time<Physics>>().pause();
    // The pause takes hold from the next frame's time update.
    app.update();
    app.world_mut().resource_mut::<Received>().0 = 0;
    for _ in 0..10 {
        app.update();
    }
    assert_eq!(app.world().resource::<Received>().0, 0, "no step ran, so no contact");
    assert_eq!(app.world().resource::<DentStats>().dents, 0, "1 m/s is under the threshold");
}

/// The inverse inertia of each contact's body `of`, as the plug-in recorded it.
#[derive(Resource)]
struct Recorded {
    of: Entity,
    inverse_inertia: Vec<Mat3>,
}

fn record_inertia(mut contacts: MessageReader<DentContact>, mut recorded: ResMut<Recorded>) {
    for c in contacts.read() {
        for body in [&c.a, &c.b] {
            if body.entity == recorded.of {
                recorded.inverse_inertia.push(body.state.inverse_inertia);
            }
        }
    }
}

/// A ball that cannot turn about x (`LockedAxes`) falls on the block: the state the plug-in
/// records has the inverse inertia Avian's solver uses, its x row and column zero and the
/// others the ball's (1/I = 5 / (2 m r²) = 31.25 kg⁻¹m⁻² for 8 kg and 0.1 m, to 1 %: Avian's
/// collider is a true sphere).
fn a_body_with_locked_rotation_takes_no_angular_impulse_about_it() {
    let mut app = app(FixedPostUpdate);
    spawn_block(&mut app);
    let ball = launch_ball(&mut app, Vec3::new(0.1, 0.5, 0.2), 0.1, 8.0, Vec3::new(0.0, -6.0, 0.0));
    app.world_mut().entity_mut(ball).insert(LockedAxes::new().lock_rotation_x());
    app.insert_resource(Recorded { of: ball, inverse_inertia: Vec::new() }).add_systems(PostUpdate, record_inertia);
    for _ in 0..20 {
        app.update();
    }
    let recorded = &app.world().resource::<Recorded>().inverse_inertia;
    assert!(!recorded.is_empty(), "the ball touched the block");
    let expected = 5.0 / (2.0 * 8.0 * 0.1 * 0.1);
    for m in recorded {
        assert_eq!((m.x_axis, m.y_axis.x, m.z_axis.x), (Vec3::ZERO, 0.0, 0.0), "locked about x: {m}");
        for v in [m.y_axis.y, m.z_axis.z] {
            assert!((v - expected).abs() < 0.01 * expected, "free axes keep 1/I = {expected}: {m}");
        }
    }
}

/// dentbend-rapier's Figure 14 scene on Avian: a one-bone plank 4 × 0.1 × 0.3 m (700 kg/m³,
/// split by hits of 2 m/s or more, dentable: 2 m/s threshold, 5 mm per m/s, at most 2 cm) across
/// supports 3.8 m apart, and a 60 kg ball (radius 0.2 m) falling at 6 m/s onto it 0.3 m off the
/// middle. The hit splits the bone where it lands (two Avian bone bodies, one Avian joint), the
/// plastic joint yields and the plank stays bent there by more than 3°, and the dents are in its
/// rest mesh (same vertices and faces, at least 2 mm deep and at most the 2 cm cap a dent). The joint is 10 N·m·s, not
/// Rapier's 40: Avian's soft contacts spread the hit over a few steps, and the most the rule
/// has to hold in one step here is about 18 N·m·s, so a 40 N·m·s joint would hold.
fn a_bendable_plank_splits_bends_and_dents_on_avian() {
    let mut app = app(FixedPostUpdate);
    let plank = mesh::plank(4.0, 0.3, 0.1, 64).expect("a plank");
    let skeleton = auto_skeleton(&plank, 1).expect("a one-bone skeleton");
    let mut settings = BendSettings::plastic(700.0, 10.0);
    settings.split_speed = Some(2.0);
    let bendable = Bendable::new(skeleton, settings).dentable(DentSettings::new(2.0, 0.005, 0.02));
    let world = app.world_mut();
    for x in [-1.9, 1.9] {
        world.spawn((Transform::from_xyz(x, -0.3, 0.0), RigidBody::Static, Collider::cuboid(0.4, 0.6, 0.6)));
    }
    world.spawn((Transform::from_xyz(0.0, -0.7, 0.0), RigidBody::Static, Collider::cuboid(8.0, 0.2, 3.0)));
    let asset = world.resource_mut::<Assets<Mesh>>().add(bevy_mesh(&plank));
    let body = world.spawn((Mesh3d(asset), Transform::from_xyz(0.0, 0.052, 0.0), bendable)).id();
    launch_ball(&mut app, Vec3::new(0.3, 0.7, 0.0), 0.2, 60.0, Vec3::new(0.0, -6.0, 0.0));
    for _ in 0..3 {
        app.update();
    }
    let original = app.world().resource::<Bends>().rest(body).expect("the plank registered").0.clone();
    assert_eq!(app.world().resource::<Bends>().pieces(body).map(<[Entity]>::len), Some(1));
    for _ in 0..120 {
        app.update();
    }
    let stats = app.world().resource::<DentStats>().clone();
    assert_eq!(stats.splits, 1, "{stats:?}");
    assert!(stats.bendable_dents >= 1, "{stats:?}");
    let bends = app.world().resource::<Bends>();
    let pieces = bends.pieces(body).expect("a bendable").to_vec();
    assert_eq!(pieces.len(), 2, "two bones after the split");
    let bent = bends.bend_angles(body).expect("a bendable");
    assert_eq!(bent.len(), 1, "one joint");
    assert!(bent[0].abs() > 3f32.to_radians(), "the new joint bent {} rad", bent[0]);
    let rest = bends.rest(body).expect("a bendable").0.clone();
    assert_eq!((rest.vertex_count(), rest.faces()), (original.vertex_count(), original.faces()));
    let deepest = rest.positions().iter().zip(original.positions()).map(|(a, b)| a.distance(*b)).fold(0.0, f32::max);
    // Each dent moves a vertex by at most the cap (2 cm; 0.5 % for the blended bone rotations
    // it is mapped back through), and the ball may land more than once.
    let most = 0.0201 * stats.bendable_dents as f32;
    assert!((0.002..=most).contains(&deepest), "the rest mesh's dent is {deepest} m after {stats:?}");
    // The bones are Avian bodies joined by one Avian spherical joint.
    for piece in pieces {
        assert_eq!(app.world().get::<RigidBody>(piece), Some(&RigidBody::Dynamic));
        assert!(app.world().get::<BendPiece>(piece).is_some());
    }
    let mut joints = app.world_mut().query::<&SphericalJoint>();
    assert_eq!(joints.iter(app.world()).count(), 1);
}

pub fn tests() -> Vec<Trial> {
    common::headless_trials(
        module_path!(),
        vec![
            ("a_dropped_ball_dents_in_fixed_post_update", || a_dropped_ball_dents(FixedPostUpdate)),
            ("a_dropped_ball_dents_in_post_update", || a_dropped_ball_dents(PostUpdate)),
            ("a_ball_breaks_a_wall_into_avian_bodies", a_ball_breaks_a_wall_into_avian_bodies),
            ("a_parent_collider_dents_its_child_mesh", a_parent_collider_dents_its_child_mesh),
            ("a_moving_turned_body_dents_where_it_was_hit", a_moving_turned_body_dents_where_it_was_hit),
            ("a_paused_avian_sends_no_contacts", a_paused_avian_sends_no_contacts),
            (
                "a_body_with_locked_rotation_takes_no_angular_impulse_about_it",
                a_body_with_locked_rotation_takes_no_angular_impulse_about_it,
            ),
            ("a_bendable_plank_splits_bends_and_dents_on_avian", a_bendable_plank_splits_bends_and_dents_on_avian),
        ],
    )
}
