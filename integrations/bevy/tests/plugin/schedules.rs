//! bevy_rapier3d in another schedule than `PostUpdate`: with `in_fixed_schedule()` Rapier steps
//! in `FixedUpdate`, and the plug-in finds that schedule itself, records the states and reads the
//! impacts around each fixed step, and dents as it does in `PostUpdate`. A ball dropped on a
//! fixed block dents it once in every set-up: Rapier in `PostUpdate`, in `FixedUpdate` found or
//! named, and named wrongly (Rapier's own schedule wins, with a warning).

use crate::common;

use bevy::prelude::*;
use bevy_dentbend::{DentStats, Dentable, DentbendPlugin, bevy_mesh, dentbend};
use bevy_rapier3d::prelude::*;
use libtest_mimic::Trial;

/// Where Rapier steps, and whether the plug-in is told.
#[derive(Clone, Copy)]
enum Setup {
    PostUpdate,
    FixedFound,
    FixedNamed,
    Misnamed,
}

/// Dents of a 6 m/s ball dropped on a fixed 2 × 0.5 × 2 m block (threshold 2 m/s), after 90
/// frames of 1/60 s, every dent on the CPU.
fn dents(setup: Setup) -> u64 {
    let rapier = RapierPhysicsPlugin::<NoUserData>::default();
    let (rapier, dentbend) = match setup {
        Setup::PostUpdate => (rapier, DentbendPlugin::cpu_only()),
        Setup::FixedFound => (rapier.in_fixed_schedule(), DentbendPlugin::cpu_only()),
        Setup::FixedNamed => (rapier.in_fixed_schedule(), DentbendPlugin::cpu_only().in_fixed_schedule()),
        Setup::Misnamed => (rapier.in_fixed_schedule(), DentbendPlugin::cpu_only().in_schedule(PostUpdate)),
    };
    let mut app = common::physics_app(rapier, dentbend);
    app.insert_resource(Time::<Fixed>::from_hz(60.0));
    let block = dentbend::mesh::subdivided_box(Vec3::new(2.0, 0.5, 2.0), [16, 4, 16]).expect("a box");
    let collider = Collider::trimesh(block.positions().to_vec(), block.faces().to_vec()).expect("a tri-mesh");
    let mesh = app.world_mut().resource_mut::<Assets<Mesh>>().add(bevy_mesh(&block));
    app.world_mut().spawn((
        Mesh3d(mesh),
        Transform::default(),
        RigidBody::Fixed,
        collider,
        Dentable::new(2.0, 0.01, 0.05),
    ));
    common::launch_ball(&mut app, Vec3::new(0.0, 0.6, 0.0), 0.1, 2000.0, Vec3::new(0.0, -6.0, 0.0));
    for _ in 0..90 {
        app.update();
    }
    app.world().resource::<DentStats>().dents
}

pub fn tests() -> Vec<Trial> {
    let trial = |name: &'static str, setup: Setup| {
        Trial::test(format!("schedules::{name}"), move || match dents(setup) {
            1 => Ok(()),
            n => Err(format!("{n} dents, expected the ball's one").into()),
        })
    };
    vec![
        trial("rapier_in_post_update_dents", Setup::PostUpdate),
        trial("rapier_in_the_fixed_schedule_dents_found_by_the_plug_in", Setup::FixedFound),
        trial("rapier_in_the_fixed_schedule_dents_when_named", Setup::FixedNamed),
        trial("a_misnamed_schedule_gives_way_to_rapier_s_own", Setup::Misnamed),
    ]
}
