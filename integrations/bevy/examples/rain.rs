//! Balls rain on a dentable block and the bunny in a window; every impact dents (on Bevy's GPU
//! when it can run the kernels):
//! `cargo +nightly run --release -p bevy_dentbend --ignore-rust-version --features window
//! --example rain`.

use bevy::prelude::*;
use bevy_dentbend::DentbendPlugin;
use bevy_dentbend::demo::RainPlugin;
use bevy_rapier3d::prelude::{NoUserData, RapierPhysicsPlugin};

fn main() {
    let window = Window { title: "dentbend: rain".into(), resolution: (1280, 720).into(), ..default() };
    App::new()
        .add_plugins(DefaultPlugins.set(WindowPlugin { primary_window: Some(window), ..default() }))
        .add_plugins(RapierPhysicsPlugin::<NoUserData>::default())
        .add_plugins(DentbendPlugin::default())
        .add_plugins(RainPlugin)
        .run();
}
