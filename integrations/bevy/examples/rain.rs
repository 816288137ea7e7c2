//! Balls rain on a dentable block and the bunny in a window; every impact dents (on Bevy's GPU
//! when it can run the kernels):
//! `cargo +nightly run --release -p bevy_dentbend --ignore-rust-version --features window
//! --example rain`.

use bevy::prelude::*;
use bevy_dentbend::DentbendPlugin;
use bevy_dentbend::demo::{Physics, RainPlugin};

fn main() {
    let window = Window { title: "dentbend: rain".into(), resolution: (1280, 720).into(), ..default() };
    let mut app = App::new();
    app.add_plugins(DefaultPlugins.set(WindowPlugin { primary_window: Some(window), ..default() }));
    // bevy_rapier3d, one 1/60 s step a frame.
    Physics::Rapier.add_to(&mut app);
    app.add_plugins(DentbendPlugin::default()).add_plugins(RainPlugin).run();
}
