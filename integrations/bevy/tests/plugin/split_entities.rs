//! Dentable meshes whose collider sits on another entity, as glTF scenes and game hierarchies
//! build them: a `Dentable` on a body whose mesh is its child, and a `Dentable` on a child mesh
//! (offset from its parent) whose body and collider are the parent's. A ball dents the mesh in
//! both, and the collider on the other entity follows the dent in its own coordinates. A
//! `Dentable` over several meshes is refused, naming them.

use crate::common;
use libtest_mimic::Trial;

use bevy::prelude::*;
use bevy_dentbend::dentbend::{TriMesh, mesh};
use bevy_dentbend::{DentRefused, DentStats, DentWorld, Dentable, DentbendPlugin, bevy_mesh};
use bevy_rapier3d::prelude::*;

/// Where the `Dentable` goes.
#[derive(Clone, Copy)]
enum Layout {
    /// On the parent body (collider), the mesh on its child.
    OnBody,
    /// On the child mesh, offset by `CHILD_OFFSET`; the body and collider on the parent.
    OnMesh,
}

/// The child mesh's offset from its parent in [`Layout::OnMesh`], m.
const CHILD_OFFSET: Vec3 = Vec3::new(0.3, 0.25, -0.2);

fn app() -> App {
    common::physics_app(RapierPhysicsPlugin::<NoUserData>::default(), DentbendPlugin::cpu_only())
}

fn block() -> TriMesh {
    mesh::subdivided_box(Vec3::new(2.0, 0.5, 2.0), [16, 4, 16]).expect("a box")
}

/// One dent through a collider on another entity; the collider's vertices (its entity's
/// coordinates) are the dented mesh placed there.
fn dents_through_the_other_entity(layout: Layout) {
    let mut app = app();
    let tri = block();
    let mesh = app.world_mut().resource_mut::<Assets<Mesh>>().add(bevy_mesh(&tri));
    let (offset, parent_has_dentable) = match layout {
        Layout::OnBody => (Vec3::ZERO, true),
        Layout::OnMesh => (CHILD_OFFSET, false),
    };
    let collider_vertices: Vec<Vec3> = tri.positions().iter().map(|&p| p + offset).collect();
    let collider = Collider::trimesh(collider_vertices, tri.faces().to_vec()).expect("a tri-mesh");
    let dentable = Dentable::new(2.0, 0.01, 0.05);
    let parent = app.world_mut().spawn((Transform::default(), RigidBody::Fixed, collider)).id();
    let child = app.world_mut().spawn((Mesh3d(mesh), Transform::from_translation(offset), ChildOf(parent))).id();
    if parent_has_dentable {
        app.world_mut().entity_mut(parent).insert(dentable);
    } else {
        app.world_mut().entity_mut(child).insert(dentable);
    }
    common::launch_ball(&mut app, offset + Vec3::new(0.1, 0.8, 0.2), 0.1, 2000.0, Vec3::new(0.0, -6.0, 0.0));
    for _ in 0..60 {
        app.update();
    }
    assert_eq!(app.world().resource::<DentStats>().dents, 1, "the ball's one dent");
    let world = app.world().resource::<DentWorld>();
    assert_eq!(world.mesh_entity(parent), child, "contacts on the parent's collider are the child mesh's");
    let dented = world.mesh(child).expect("the child mesh dents");
    assert_ne!(dented.positions(), tri.positions(), "the mesh moved");
    let collider = app.world().get::<Collider>(parent).expect("the parent's collider");
    let vertices = collider.as_trimesh().expect("a tri-mesh").raw.vertices().to_vec();
    assert_eq!(vertices.len(), dented.vertex_count());
    for (v, p) in vertices.iter().zip(dented.positions()) {
        assert!((*v - (*p + offset)).length() < 1e-5, "collider vertex {v} against the mesh's {p} + {offset}");
    }
}

fn several_meshes_are_refused() {
    let mut app = app();
    let tri = block();
    let mesh = app.world_mut().resource_mut::<Assets<Mesh>>().add(bevy_mesh(&tri));
    let parent = app.world_mut().spawn((Transform::default(), Dentable::new(2.0, 0.01, 0.05))).id();
    for x in [-2.0, 2.0] {
        app.world_mut().spawn((Mesh3d(mesh.clone()), Transform::from_xyz(x, 0.0, 0.0), ChildOf(parent)));
    }
    for _ in 0..3 {
        app.update();
    }
    let why = app.world().get::<DentRefused>(parent).map(|r| r.0.clone()).expect("refused");
    assert!(why.contains("2 descendants") && why.contains("put a Dentable on each mesh entity"), "{why}");
}

pub fn tests() -> Vec<Trial> {
    common::headless_trials(
        module_path!(),
        vec![
            ("a_dentable_body_dents_its_child_mesh", || dents_through_the_other_entity(Layout::OnBody)),
            ("a_dentable_child_mesh_dents_through_its_parent_s_collider", || {
                dents_through_the_other_entity(Layout::OnMesh)
            }),
            ("a_dentable_over_several_meshes_is_refused", several_meshes_are_refused),
        ],
    )
}
