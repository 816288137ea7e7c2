//! A push that goes on after the impact: only progressive targets dent again, deepening one
//! dent from the pre-dent surface (paper Figure 3); ordinary targets dent once per impact.

mod common;

use dentbend::damage::CpuBackend;
use dentbend::dent::DentSettings;
use dentbend_rapier::{BodyStates, Dentables};
use glam::Vec3;

/// Dent distances made by the two steps of a push at 6 m/s on a block denting with
/// `settings`: the impact's step (`started`), then a step of the same push.
fn push_twice(settings: DentSettings) -> (Vec<f32>, Vec<f32>) {
    let (mut world, (block, block_mesh), (ball, ball_mesh)) = common::block_and_ball(Vec3::ZERO, 0.35);
    let mut dentables = Dentables::new();
    dentables.insert(&world.colliders, &world.bodies, block, block_mesh, settings).unwrap();
    dentables.insert_projectile(&world.colliders, ball, ball_mesh).unwrap();
    let states = BodyStates::record(&world.bodies, &world.colliders);
    let contact = |started| common::top_contact(block, ball, started);
    let mut step = |started| {
        let r = dentables
            .process(&[contact(started)], &states, &mut world.bodies, &mut world.colliders, &mut CpuBackend)
            .unwrap();
        r.dents.iter().map(|d| d.dent_distance).collect::<Vec<f32>>()
    };
    (step(true), step(false))
}

#[test]
fn only_progressive_targets_dent_again_while_the_push_goes_on() {
    // 2 m/s threshold, 5 mm per m/s: 2 cm per step at 6 m/s, at most 5 cm.
    let plain = DentSettings::new(2.0, 0.005, 0.05);
    let (first, second) = push_twice(plain.clone());
    assert_eq!((first.len(), second.len()), (1, 0), "{first:?} {second:?}");
    assert!((first[0] - 0.02).abs() < 1e-6);

    let progressive = DentSettings { progressive: true, ..plain };
    let (first, second) = push_twice(progressive);
    assert_eq!((first.len(), second.len()), (1, 1), "{first:?} {second:?}");
    // The second step deepens the same dent: the accumulated distance, 2 + 2 cm.
    assert!((first[0] - 0.02).abs() < 1e-6 && (second[0] - 0.04).abs() < 1e-6, "{first:?} {second:?}");
}
