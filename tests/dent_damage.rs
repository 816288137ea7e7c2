//! The world-free damage API (`damage::Damage`), fed a hand-written contact list as "your own
//! solver" would: dent decisions keyed by the caller's ids, moved vertices for collider refits,
//! projectile placement, progressive dents, Jacobi pairs, the energy model from both bodies'
//! states, and errors that change nothing.

use dentbend::damage::{CpuBackend, Damage, DamageError, Hit, TargetSet};
use dentbend::dent::{BodyState, DentSettings, Impact, Surface, moved_vertices};
use dentbend::glam::{Affine3A, Mat3, Vec3};
use dentbend::mesh::{self, TriMesh};

const BLOCK: u32 = 7;
const BALL: u32 = 42;

/// The 4 × 1 × 4 block (top at y = 0.5) as a dentable target: 1 m/s threshold, 0.04 m per m/s,
/// at most 0.3 m.
fn block_set(settings: DentSettings) -> TargetSet<u32> {
    let mut set = TargetSet::new();
    set.insert(BLOCK, mesh::builtin("block").unwrap(), Affine3A::IDENTITY, settings).unwrap();
    set.insert_rigid(BALL);
    set
}

fn ball_mesh() -> TriMesh {
    mesh::icosphere(0.5, 3).unwrap()
}

/// A 1 kg ball centred 0.5 m above the block's top, falling at `speed` m/s onto it.
fn ball_state(speed: f32) -> BodyState {
    BodyState::moving(Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, -speed, 0.0), Vec3::ZERO, 1.0, Mat3::IDENTITY * 10.0)
}

fn hit<'a>(ball: &'a TriMesh, speed: f32) -> Hit<'a, u32> {
    let state = ball_state(speed);
    let point = Vec3::new(0.0, 0.5, 0.0);
    Hit {
        target: BLOCK,
        projectile: BALL,
        impact: Impact::from_contact(point, -Vec3::Y, &BodyState::FIXED, &state).unwrap(),
        target_state: BodyState::FIXED,
        projectile_state: state,
        projectile_surface: Surface { mesh: ball, to_world: Affine3A::from_translation(state.center_of_mass) },
    }
}

fn deepest(before: &TriMesh, after: &TriMesh) -> f32 {
    before.positions().iter().zip(after.positions()).map(|(a, b)| a.distance(*b)).fold(0.0, f32::max)
}

#[test]
fn a_contact_list_dents_by_the_material_and_reports_what_moved() {
    let mut settings = DentSettings::new(1.0, 0.04, 0.3);
    settings.move_projectile = true;
    let mut set = block_set(settings);
    let before = set.mesh(BLOCK).unwrap().clone();
    let ball = ball_mesh();
    let mut damage = Damage::new();
    // Too slow: 0.8 m/s is under the 1 m/s threshold.
    let slow = damage.plan(&set, &[hit(&ball, 0.8)], 1, &mut CpuBackend).unwrap();
    assert!(slow.dents.is_empty() && slow.targets.is_empty());

    let plan = damage.plan(&set, &[hit(&ball, 6.0)], 2, &mut CpuBackend).unwrap();
    assert_eq!(plan.dents.len(), 1);
    let dent = plan.dents[0];
    // d = 0.04 · (6 − 1) = 0.2 m; f32 arithmetic on exact inputs, so 1e-6 m.
    assert!((dent.dent_distance - 0.2).abs() < 1e-6, "{}", dent.dent_distance);
    assert_eq!((dent.target, dent.projectile), (BLOCK, BALL));
    // The ball is moved down into the dent by the dent distance.
    assert!(dent.projectile_offset.abs_diff_eq(Vec3::new(0.0, -0.2, 0.0), 1e-6), "{}", dent.projectile_offset);
    // Nothing changed before the plan is applied.
    assert_eq!(set.mesh(BLOCK).unwrap().positions(), before.positions());

    let moved = set.apply(plan.targets);
    let after = set.mesh(BLOCK).unwrap();
    // The dent reaches d at its centre (the head-on peak is exact up to the map's bilinear
    // sampling: 1% of d).
    assert!((deepest(&before, after) - 0.2).abs() < 0.002, "{}", deepest(&before, after));
    // Exactly the vertices that moved are reported, and only near the impact.
    assert_eq!(moved, vec![(BLOCK, moved_vertices(before.positions(), after.positions()))]);
    assert!(!moved[0].1.is_empty() && moved[0].1.len() < before.vertex_count());
}

#[test]
fn the_relative_velocity_includes_spin_on_both_bodies() {
    // A projectile spinning about z at 4 rad/s, centre 1 m above the contact: ω × r at the
    // contact (r = −y) is 4·(ẑ × −ŷ) = +4 x̂ m/s, on top of its 2 m/s fall.
    let spinning = BodyState::moving(Vec3::Y, Vec3::new(0.0, -2.0, 0.0), Vec3::new(0.0, 0.0, 4.0), 1.0, Mat3::IDENTITY);
    let target = BodyState { linear_velocity: Vec3::new(1.0, 0.0, 0.0), ..BodyState::FIXED };
    let impact = Impact::from_contact(Vec3::ZERO, -Vec3::Y, &target, &spinning).unwrap();
    assert!(impact.relative_velocity.abs_diff_eq(Vec3::new(3.0, -2.0, 0.0), 1e-6), "{}", impact.relative_velocity);
}

#[test]
fn the_energy_model_takes_both_bodies_masses() {
    // With a hardness the depth comes from the energy lost, ½ m_eff v² (1 − e²): a heavier ball
    // at the same speed loses more energy and dents deeper.
    let mut settings = DentSettings::new(0.0, 1.0, 0.3);
    settings.hardness = Some(2.0e5);
    let set = block_set(settings);
    let ball = ball_mesh();
    let depth = |mass: f32| {
        let mut h = hit(&ball, 5.0);
        h.projectile_state.inverse_mass = 1.0 / mass;
        let plan = Damage::new().plan(&set, &[h], 1, &mut CpuBackend).unwrap();
        plan.dents[0].dent_distance
    };
    let (light, heavy) = (depth(1.0), depth(4.0));
    assert!(heavy > light && light > 0.0 && heavy < 0.3, "{light} {heavy}");
}

#[test]
fn progressive_hits_deepen_one_dent_from_the_pre_dent_surface() {
    let mut settings = DentSettings::new(1.0, 0.02, 0.3);
    settings.progressive = true;
    let mut set = block_set(settings);
    let before = set.mesh(BLOCK).unwrap().clone();
    let ball = ball_mesh();
    let mut damage = Damage::new();
    let mut distances = Vec::new();
    for step in 1..=3 {
        let plan = damage.plan(&set, &[hit(&ball, 6.0)], step, &mut CpuBackend).unwrap();
        distances.push(plan.dents[0].dent_distance);
        set.apply(plan.targets);
    }
    // 0.1 m per hit, accumulated: 0.1, 0.2, 0.3 (f32 sums, 1e-6 m).
    for (got, want) in distances.iter().zip([0.1, 0.2, 0.3]) {
        assert!((got - want).abs() < 1e-6, "{distances:?}");
    }
    // One dent 0.3 m deep, not three stacked (which would reach 0.6 m): within the map's 1%.
    let depth = deepest(&before, set.mesh(BLOCK).unwrap());
    assert!((depth - 0.3).abs() < 0.003, "{depth}");
    // A gap of a step ends the contact: the next hit starts a new dent at 0.1 m.
    let plan = damage.plan(&set, &[hit(&ball, 6.0)], 5, &mut CpuBackend).unwrap();
    assert!((plan.dents[0].dent_distance - 0.1).abs() < 1e-6);
}

#[test]
fn two_dentable_balls_dent_each_other_alike() {
    // Jacobi: both maps come from the undented surfaces, so a symmetric head-on hit gives two
    // equal dents whatever the order of the hits.
    let settings = DentSettings::new(0.5, 0.05, 0.3);
    let mut set = TargetSet::new();
    let (a, b) = (1u32, 2u32);
    let sphere = ball_mesh();
    let (pa, pb) = (Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0));
    set.insert(a, sphere.clone(), Affine3A::from_translation(pa), settings.clone()).unwrap();
    set.insert(b, sphere.clone(), Affine3A::from_translation(pb), settings).unwrap();
    let sa = BodyState::moving(pa, Vec3::new(0.0, 2.0, 0.0), Vec3::ZERO, 1.0, Mat3::IDENTITY);
    let sb = BodyState::moving(pb, Vec3::new(0.0, -2.0, 0.0), Vec3::ZERO, 1.0, Mat3::IDENTITY);
    let point = Vec3::new(0.0, 0.5, 0.0);
    let hits = [
        Hit {
            target: a,
            projectile: b,
            impact: Impact::from_contact(point, -Vec3::Y, &sa, &sb).unwrap(),
            target_state: sa,
            projectile_state: sb,
            projectile_surface: Surface { mesh: &sphere, to_world: Affine3A::from_translation(pb) },
        },
        Hit {
            target: b,
            projectile: a,
            impact: Impact::from_contact(point, Vec3::Y, &sb, &sa).unwrap(),
            target_state: sb,
            projectile_state: sa,
            projectile_surface: Surface { mesh: &sphere, to_world: Affine3A::from_translation(pa) },
        },
    ];
    let plan = Damage::new().plan(&set, &hits, 1, &mut CpuBackend).unwrap();
    assert_eq!(plan.dents.len(), 2);
    let depth = |key: u32| deepest(&sphere, &plan.targets.iter().find(|t| t.key == key).unwrap().mesh);
    // Mirror images: equal depths within f32 rounding of the mirrored frames (1e-5 m).
    assert!((depth(a) - depth(b)).abs() < 1e-5, "{} {}", depth(a), depth(b));
    assert!(depth(a) > 0.1, "{}", depth(a));
}

#[test]
fn bad_contacts_are_named_and_change_nothing() {
    let set = block_set(DentSettings::new(1.0, 0.04, 0.3));
    let ball = ball_mesh();
    let mut damage = Damage::new();
    let cases: Vec<(&str, Hit<'_, u32>)> = vec![
        ("nan point", Hit { impact: Impact { point: Vec3::NAN, ..hit(&ball, 6.0).impact }, ..hit(&ball, 6.0) }),
        ("infinite velocity", {
            let mut h = hit(&ball, 6.0);
            h.impact.relative_velocity.y = f32::NEG_INFINITY;
            h
        }),
        ("zero normal", Hit { impact: Impact { normal: Vec3::ZERO, ..hit(&ball, 6.0).impact }, ..hit(&ball, 6.0) }),
        ("unknown target", Hit { target: 99, ..hit(&ball, 6.0) }),
        ("unknown projectile", Hit { projectile: 98, ..hit(&ball, 6.0) }),
    ];
    for (what, bad) in cases {
        // A good hit first: the whole plan fails, so it is not half-applied either.
        let error = damage.plan(&set, &[hit(&ball, 6.0), bad], 1, &mut CpuBackend).unwrap_err();
        match (what, &error) {
            ("unknown target", DamageError::UnknownBody { hit: 1, body }) => assert_eq!(body, "99"),
            ("unknown projectile", DamageError::UnknownBody { hit: 1, body }) => assert_eq!(body, "98"),
            (_, DamageError::Dent { hit: 1, .. }) if !what.starts_with("unknown") => {}
            _ => panic!("{what}: unexpected {error}"),
        }
    }
    // A non-finite body state is refused when it matters (the energy model).
    let mut settings = DentSettings::new(0.0, 1.0, 0.3);
    settings.hardness = Some(1.0e5);
    let hard = block_set(settings);
    let mut h = hit(&ball, 6.0);
    h.projectile_state.inverse_mass = f32::NAN;
    let error = Damage::new().plan(&hard, &[h], 1, &mut CpuBackend).unwrap_err();
    assert!(error.to_string().contains("inverse_mass"), "{error}");
    // No progressive state was left behind by the failures: a first progressive-free plan works.
    assert!(damage.plan(&set, &[hit(&ball, 6.0)], 2, &mut CpuBackend).is_ok());
}
