//! Scaled entities (glTF imports often are): a block spawned with a uniform or a non-uniform
//! scale, its collider built from the unscaled mesh as bevy_rapier3d expects, dents where the
//! ball hits it, sized in metres: the plug-in's mesh is the asset's times the scale, the dent's
//! depth is the one decided (world metres), and the collider bevy_rapier3d scales follows it.

use crate::common;
use libtest_mimic::Trial;

use bevy::prelude::*;
use bevy_dentbend::dentbend::mesh;
use bevy_dentbend::{DentApplied, DentPath, DentStats, DentWorld, Dentable, DentbendPlugin, bevy_mesh};
use bevy_rapier3d::prelude::*;

#[derive(Resource, Default)]
struct Applied(Vec<DentApplied>);

fn collect(mut applied: MessageReader<DentApplied>, mut out: ResMut<Applied>) {
    out.0.extend(applied.read().copied());
}

/// A 2 × 0.5 × 2 m block (unscaled) spawned with `scale`, its top at y = 0.25·scale.y; a 6 m/s
/// ball dropped on it (threshold 2 m/s, 1 cm per m/s: a 4 cm dent).
fn dents_scaled(scale: Vec3) {
    let mut app = common::physics_app(RapierPhysicsPlugin::<NoUserData>::default(), DentbendPlugin::default());
    app.init_resource::<Applied>().add_systems(Last, collect);
    let tri = mesh::subdivided_box(Vec3::new(2.0, 0.5, 2.0), [24, 6, 24]).expect("a box");
    let collider = Collider::trimesh(tri.positions().to_vec(), tri.faces().to_vec()).expect("a tri-mesh");
    let asset = app.world_mut().resource_mut::<Assets<Mesh>>().add(bevy_mesh(&tri));
    let block = app
        .world_mut()
        .spawn((
            Mesh3d(asset),
            Transform::from_scale(scale),
            RigidBody::Fixed,
            collider,
            Dentable::new(2.0, 0.01, 0.05),
        ))
        .id();
    let at = Vec3::new(0.1, 0.25 * scale.y + 0.4, 0.2);
    common::launch_ball(&mut app, at, 0.1, 2000.0, Vec3::new(0.0, -6.0, 0.0));
    for _ in 0..60 {
        app.update();
    }
    assert_eq!(app.world().resource::<DentStats>().dents, 1, "the ball's one dent");
    let world = app.world().resource::<DentWorld>();
    assert_eq!(world.path(block), Some(DentPath::Cpu), "a scaled body dents on the CPU path");
    let kept = world.mesh(block).expect("registered").clone();
    // The asset holds the mesh without the scale (to 1e-6 relative: one f32 multiply and divide).
    let handle = &app.world().get::<Mesh3d>(block).expect("a mesh").0;
    let asset = app.world().resource::<Assets<Mesh>>().get(handle).expect("the asset");
    let positions = asset.attribute(Mesh::ATTRIBUTE_POSITION).and_then(|a| a.as_float3()).expect("positions");
    for (p, k) in positions.iter().zip(kept.positions()) {
        let p = Vec3::from_array(*p) * scale;
        assert!((p - *k).length() <= 1e-6 * k.length().max(1.0), "asset {p} against kept {k}");
    }
    // The dent, in world metres: how far the kept (scaled, refined) mesh's top face sinks below
    // the top plane is the depth made, within 10 % of the distance decided (a scale left in the
    // mesh would make it 2× or ½× off).
    let applied = app.world().resource::<Applied>().0.clone();
    let [dent] = applied.as_slice() else { panic!("{applied:?}") };
    let top = 0.25 * scale.y;
    let on_top = |p: &&Vec3| p.y > top - 0.2 && p.x.abs() < 0.9 * scale.x && p.z.abs() < 0.9 * scale.z;
    let deepest = kept.positions().iter().filter(on_top).map(|p| top - p.y).fold(0.0f32, f32::max);
    let made = dent.depth_made.expect("a CPU-path dent reports its depth");
    assert!((deepest - made).abs() < 1e-4, "deepest {deepest} m against reported {made} m");
    assert!((made - dent.dent_distance).abs() < 0.1 * dent.dent_distance, "made {made} of {}", dent.dent_distance);
    // Decided from the ball's speed at the contact: 6 m/s at spawn, up to √(36 + 2·9.81·0.3) ≈
    // 6.47 m/s after its 0.3 m fall, so (v − 2)·0.01 is 4.0 to 4.5 cm.
    assert!((0.0395..0.0455).contains(&dent.dent_distance), "decided {}", dent.dent_distance);
    // bevy_rapier3d's scaled collider has the kept mesh's vertices (to 1e-5 m).
    let collider = app.world().get::<Collider>(block).expect("a collider");
    let raw = collider.raw.as_trimesh().expect("a tri-mesh").vertices().to_vec();
    assert_eq!(raw.len(), kept.vertex_count());
    for (r, k) in raw.iter().zip(kept.positions()) {
        assert!(r.distance(*k) < 1e-5, "collider {r} against kept {k}");
    }
}

pub fn tests() -> Vec<Trial> {
    common::headless_trials(
        module_path!(),
        vec![
            ("a_uniformly_scaled_body_dents_in_metres", || dents_scaled(Vec3::splat(2.0))),
            ("a_non_uniformly_scaled_body_dents_in_metres", || dents_scaled(Vec3::new(2.0, 0.5, 1.5))),
        ],
    )
}
