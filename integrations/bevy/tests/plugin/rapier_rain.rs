//! bevy_rapier3d end to end: balls fall on dentable bodies, Rapier's impacts dent them on the GPU
//! path (the game dent too), the bodies' `Collider`s (and Rapier's own colliders) take the dented
//! vertices from the collider read-back, and a ball at rest dents nothing more.

use crate::common;
use libtest_mimic::Trial;

use bevy::prelude::*;
use bevy_dentbend::demo::{RainPlugin, RainSettings, Target, headless_app};
use bevy_dentbend::{DentPath, DentStats, DentWorld};
use bevy_rapier3d::plugin::context::RapierContextColliders;
use bevy_rapier3d::prelude::*;

/// Runs the rain for `frames` frames; the app.
fn rain(settings: RainSettings, frames: u32) -> App {
    let mut app = headless_app(true);
    app.insert_resource(settings).add_plugins(RainPlugin);
    app.finish();
    app.cleanup();
    for _ in 0..frames {
        app.update();
    }
    app
}

/// The scene's body of `kind`.
fn body(app: &mut App, kind: Target) -> Entity {
    let mut q = app.world_mut().query::<(Entity, &Target)>();
    q.iter(app.world()).find(|(_, t)| **t == kind).map(|(e, _)| e).expect("a body of the scene")
}

/// The vertices of `entity`'s tri-mesh collider, from the Bevy component and from Rapier.
fn collider_vertices(app: &mut App, entity: Entity) -> (Vec<Vec3>, Vec<Vec3>) {
    let component = app.world().get::<Collider>(entity).expect("a collider");
    let ours = component.raw.as_trimesh().expect("a tri-mesh").vertices().to_vec();
    let mut q = app.world_mut().query::<&RapierContextColliders>();
    let colliders = q.single(app.world()).expect("one Rapier context");
    let handle = colliders.entity2collider().get(&entity).copied().expect("a Rapier collider");
    let theirs = colliders.colliders.get(handle).unwrap().shape().as_trimesh().unwrap().vertices().to_vec();
    (ours, theirs)
}

/// Raining balls dent the block on the GPU path; after the read-backs, the block's collider (the
/// component and Rapier's copy) has exactly the main world's dented vertices.
fn impacts_dent_and_colliders_follow() {
    let mut app = rain(RainSettings { balls_per_frame: 0.25, ..default() }, 150);
    let stats = app.world().resource::<DentStats>().clone();
    assert!(stats.gpu_dents >= 3, "only {} GPU dents from 37 balls", stats.gpu_dents);
    // Every body dents on the GPU path: the block and the bunny with the paper's dent, the crate
    // with the game dent (refinement, rim, guard) run around the kernels.
    eprintln!("{stats:?}");
    assert_eq!((stats.gpu_dents, stats.cpu_dents), (stats.dents, 0), "{stats:?}");
    let block = body(&mut app, Target::Block);
    assert_eq!(app.world().resource::<DentWorld>().path(block), Some(DentPath::Gpu));
    let game_crate = body(&mut app, Target::Crate);
    assert_eq!(app.world().resource::<DentWorld>().path(game_crate), Some(DentPath::Gpu));
    // Stop the rain and let the read-backs and refits land: the read-backs are polled each frame
    // and Rapier takes a changed `Collider` at its next step, so how many frames that takes
    // depends on the machine's load (10 were not always enough on a busy 2-core machine). Wait
    // until both colliders hold the main world's mesh, at most 300 frames (5 s of game time).
    app.world_mut().resource_mut::<RainSettings>().balls_per_frame = 0.0;
    for _ in 0..300 {
        app.update();
        let mesh = app.world().resource::<DentWorld>().mesh(block).expect("the block").clone();
        let (ours, theirs) = collider_vertices(&mut app, block);
        if ours == mesh.positions() && theirs == mesh.positions() {
            break;
        }
    }
    let mesh = app.world().resource::<DentWorld>().mesh(block).expect("the block").clone();
    let spawned = bevy_dentbend::dentbend::mesh::subdivided_box(Vec3::new(4.0, 1.0, 4.0), [64, 8, 64]).unwrap();
    assert!(app.world().resource::<DentStats>().collider_readback_bytes > 0, "no read-back arrived");
    assert_ne!(mesh.positions(), spawned.positions(), "the main world's block never took its dents");
    let (ours, theirs) = collider_vertices(&mut app, block);
    assert_eq!(ours, mesh.positions(), "the Collider component is not the dented mesh");
    assert_eq!(theirs, mesh.positions(), "Rapier's collider is not the dented mesh");
}

/// One ball dropped on the block: it dents where it lands and bounces; over the next two seconds,
/// resting (or rolling slowly in its dent), it makes no further dent and is not launched: it
/// stays on the block below 0.5 m/s, a quarter of the 2 m/s dent threshold.
fn a_ball_at_rest_dents_no_more() {
    let mut app = rain(RainSettings { balls_per_frame: 0.0, ..default() }, 5);
    let sphere = app.world_mut().resource_mut::<Assets<Mesh>>().add(Sphere::new(0.12).mesh().ico(2).unwrap());
    let ball = app
        .world_mut()
        .spawn((
            bevy_dentbend::DentProjectile,
            Mesh3d(sphere),
            Transform::from_xyz(-1.0, 1.0, 0.5),
            RigidBody::Dynamic,
            Collider::ball(0.12),
            ColliderMassProperties::Density(7800.0),
            Restitution::coefficient(0.2),
            Velocity::linear(Vec3::new(0.0, -6.0, 0.0)),
        ))
        .id();
    for _ in 0..120 {
        app.update();
    }
    let settled = app.world().resource::<DentStats>().dents;
    assert!(settled >= 1, "the ball never dented the block");
    for _ in 0..120 {
        app.update();
    }
    assert_eq!(app.world().resource::<DentStats>().dents, settled, "a ball at rest kept denting");
    let v = app.world().get::<Velocity>(ball).expect("the ball").linear.length();
    let y = app.world().get::<Transform>(ball).expect("the ball").translation.y;
    assert!(v < 0.5 && (0.0..0.3).contains(&y), "the ball was launched ({v} m/s at y = {y} m)");
}

pub fn tests() -> Vec<Trial> {
    common::gpu_trials(
        module_path!(),
        vec![
            ("impacts_dent_and_colliders_follow", impacts_dent_and_colliders_follow),
            ("a_ball_at_rest_dents_no_more", a_ball_at_rest_dents_no_more),
        ],
    )
}
