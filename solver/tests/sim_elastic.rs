//! Elastic joints (paper §4.3): the analytically integrated torsional spring oscillates with the
//! period of its effective inertia, decays with damping and keeps its amplitude without; the
//! prismatic spring likewise along its axis.

use dentbend::bend::JointRule;
use dentbend::glam::{Quat, Vec3};
use dentbend::mesh;
use dentbend_solver::sim::{BodyDesc, BodyKind, ColliderKind, JointKind, World, WorldSettings};

fn weightless() -> WorldSettings {
    WorldSettings { gravity: Vec3::ZERO, angular_damping: 0.0, sleep_time: 0.0, ..Default::default() }
}

fn block(name: &str, size: Vec3, at: Vec3) -> BodyDesc {
    BodyDesc::new(name, mesh::subdivided_box(size, [1, 1, 1]).unwrap()).at(at).collider(ColliderKind::Cuboid)
}

/// Turns body `k` by `angle` about z around world point `pivot`.
fn turn_about(world: &mut World, k: usize, pivot: Vec3, angle: f32) {
    let body = &mut world.bodies_mut()[k];
    let turn = Quat::from_rotation_z(angle);
    body.position = pivot + turn * (body.position - pivot);
    body.orientation = (turn * body.orientation).normalize();
}

/// Samples `signal` every step for `steps` steps and returns (times of its zero crossings,
/// interpolated linearly between steps, s; the largest |value| between successive crossings).
fn crossings_and_peaks(world: &mut World, steps: usize, signal: impl Fn(&World) -> f32) -> (Vec<f64>, Vec<f32>) {
    let dt = f64::from(world.settings().dt);
    let (mut crossings, mut peaks) = (Vec::new(), Vec::new());
    let mut last = signal(world);
    let mut peak = 0.0f32;
    for step in 1..=steps {
        world.step();
        let now = signal(world);
        peak = peak.max(now.abs());
        if (last < 0.0) != (now < 0.0) {
            let fraction = f64::from(last / (last - now));
            crossings.push((step as f64 - 1.0 + fraction) * dt);
            peaks.push(peak);
            peak = 0.0;
        }
        last = now;
    }
    (crossings, peaks)
}

/// Period from the first and last zero crossings (two per period).
fn period(crossings: &[f64]) -> f64 {
    2.0 * (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64
}

/// A 0.4 × 0.1 × 0.1 m box (4 kg) on a static base through an elastic joint at its end, turned
/// 5° about z and let go, no gravity. A point joint makes the box turn about the anchor, so the
/// effective inertia about z is the box's own plus m·d² (d = 0.2 m, parallel axes) — the paper's
/// (I₁ + I₂)⁻¹·I₁·I₂ with the base's I₁ infinite. Returns (world, box, I about the anchor).
fn box_on_a_spring(stiffness: f32, damping: f32) -> (World, usize, f32) {
    let mut world = World::new(weightless()).unwrap();
    let base = world.add(block("base", Vec3::splat(0.1), Vec3::ZERO).kind(BodyKind::Static)).unwrap();
    let arm = world.add(block("arm", Vec3::new(0.4, 0.1, 0.1), Vec3::new(0.25, 0.0, 0.0))).unwrap();
    let anchor = Vec3::new(0.05, 0.0, 0.0);
    world.add_joint(base, arm, anchor, JointKind::Bend(JointRule::Elastic { stiffness, damping })).unwrap();
    turn_about(&mut world, arm, anchor, 5f32.to_radians());
    let body = &world.bodies()[arm];
    let inertia = body.inertia.z_axis.z + body.mass * 0.2 * 0.2;
    (world, arm, inertia)
}

/// The joint's displacement about z (the spring's θ − θ₀), rad.
fn twist(world: &World) -> f32 {
    world.joints()[0].deviation(world.bodies()).unwrap().z
}

/// Undamped: over 3 s (about 5.6 periods, 32 steps each) the period from the zero crossings is
/// 2π√(I/κ) within 2 % (the brief's bound; the analytic integration makes the sampled angles
/// exact, so only the linear interpolation of the crossings and f32 round-off remain, well under
/// 0.5 %), and no peak exceeds the first by more than 0.5 % (the sampled peaks miss the true
/// one by up to 1 − cos(π/32) ≈ 0.5 %), so the amplitude does not grow, nor fall by more than
/// 2 %. The anchor holds within 0.1 mm.
#[test]
fn undamped_spring_keeps_its_period_and_amplitude() {
    let stiffness = 30.0;
    let (mut world, _, inertia) = box_on_a_spring(stiffness, 0.0);
    let expected = std::f64::consts::TAU * f64::from(inertia / stiffness).sqrt();
    let (crossings, peaks) = crossings_and_peaks(&mut world, 180, twist);
    assert!(crossings.len() >= 10, "only {} zero crossings", crossings.len());
    let measured = period(&crossings);
    assert!((measured / expected - 1.0).abs() < 0.02, "period {measured} s, expected {expected} s");
    let first = peaks[1];
    assert!((first - 5f32.to_radians()).abs() < 0.01 * 5f32.to_radians(), "first full swing peaked at {first} rad");
    for (k, &p) in peaks.iter().enumerate().skip(1) {
        assert!(p <= first * 1.005, "swing {k} peaked at {p} rad, first at {first} rad");
    }
    // The joint's stabilization loses a little (0.7 % over 3 s measured): at most 2 %.
    assert!(peaks.last().unwrap() > &(first * 0.98), "undamped swing lost amplitude: {peaks:?}");
    let gap = world.joints()[0].separation(world.bodies()).unwrap().length();
    assert!(gap < 1e-4, "anchor opened by {gap} m");
}

/// Damped (ζ = C / (2√(κI)) = 0.05): every swing is smaller than the one before, each by the
/// factor exp(−γ·T_d/2) (γ = C/2I, T_d the damped period) within 3 % (the sampled peaks are off
/// by up to 0.5 % each), and the damped period is 2π/√(κ/I − γ²) within 2 %.
#[test]
fn damped_spring_decays_at_the_analytic_rate() {
    let stiffness = 30.0f32;
    let inertia = box_on_a_spring(stiffness, 0.0).2;
    let damping = 2.0 * 0.05 * (stiffness * inertia).sqrt();
    let (mut world, _, _) = box_on_a_spring(stiffness, damping);
    let gamma = f64::from(damping / (2.0 * inertia));
    let damped_period = std::f64::consts::TAU / (f64::from(stiffness / inertia) - gamma * gamma).sqrt();
    let (crossings, peaks) = crossings_and_peaks(&mut world, 180, twist);
    let measured = period(&crossings);
    assert!((measured / damped_period - 1.0).abs() < 0.02, "period {measured} s, expected {damped_period} s");
    let ratio = (-gamma * damped_period / 2.0).exp() as f32;
    for k in 2..peaks.len() {
        let seen = peaks[k] / peaks[k - 1];
        assert!(seen < 1.0, "swing {k} grew: {peaks:?}");
        assert!((seen / ratio - 1.0).abs() < 0.03, "swing {k} shrank by {seen}, expected {ratio}");
    }
}

/// Two free 0.5 m boxes (5 kg each) joined end to end by an elastic joint, bent 6° apart
/// (each turned 3° about the joint): with no net momentum the centres of mass stay put and each
/// box turns about its own centre (the joint moving sideways), so the effective inertia is the
/// paper's (I₁ + I₂)⁻¹·I₁·I₂ = I/2 of the boxes' central inertias. Period within 2 %; the system's
/// centre of mass stays within 0.1 mm.
#[test]
fn two_free_bodies_swing_with_the_reduced_inertia() {
    let mut world = World::new(weightless()).unwrap();
    let size = Vec3::new(0.5, 0.1, 0.1);
    let left = world.add(block("left", size, Vec3::new(-0.25, 0.0, 0.0))).unwrap();
    let right = world.add(block("right", size, Vec3::new(0.25, 0.0, 0.0))).unwrap();
    let stiffness = 20.0;
    world.add_joint(left, right, Vec3::ZERO, JointKind::Bend(JointRule::Elastic { stiffness, damping: 0.0 })).unwrap();
    turn_about(&mut world, left, Vec3::ZERO, -3f32.to_radians());
    turn_about(&mut world, right, Vec3::ZERO, 3f32.to_radians());
    let body = &world.bodies()[right];
    let expected = std::f64::consts::TAU * f64::from(body.inertia.z_axis.z / 2.0 / stiffness).sqrt();
    let centre = |w: &World| (w.bodies()[left].position + w.bodies()[right].position) / 2.0;
    let start = centre(&world);
    let (crossings, _) = crossings_and_peaks(&mut world, 180, twist);
    assert!(crossings.len() >= 8, "only {} zero crossings", crossings.len());
    let measured = period(&crossings);
    assert!((measured / expected - 1.0).abs() < 0.02, "period {measured} s, expected {expected} s");
    let drift = centre(&world) - start;
    assert!(drift.length() < 1e-4, "the centre of mass drifted by {drift}");
}

/// Prismatic: a 4 kg box on a static base by an elastic prismatic joint along x, pulled 1 cm
/// out and let go, oscillates along x with period 2π√(m/k) within 2 %, while the anchors stay
/// together across the axis (0.01 mm) and the box does not turn (0.001 rad).
#[test]
fn prismatic_spring_oscillates_along_its_axis() {
    let mut world = World::new(weightless()).unwrap();
    let base = world.add(block("base", Vec3::splat(0.1), Vec3::ZERO).kind(BodyKind::Static)).unwrap();
    let slider = world.add(block("slider", Vec3::new(0.4, 0.1, 0.1), Vec3::new(0.25, 0.0, 0.0))).unwrap();
    let stiffness = 400.0;
    let kind = JointKind::ElasticPrismatic { axis: Vec3::X, stiffness, damping: 0.0 };
    world.add_joint(base, slider, Vec3::new(0.05, 0.0, 0.0), kind).unwrap();
    world.bodies_mut()[slider].position.x += 0.01;
    let mass = world.bodies()[slider].mass;
    let expected = std::f64::consts::TAU * f64::from(mass / stiffness).sqrt();
    let offset = |w: &World| w.joints()[0].separation(w.bodies()).unwrap().x;
    let (crossings, peaks) = crossings_and_peaks(&mut world, 180, offset);
    assert!(crossings.len() >= 10, "only {} zero crossings", crossings.len());
    let measured = period(&crossings);
    assert!((measured / expected - 1.0).abs() < 0.02, "period {measured} s, expected {expected} s");
    assert!(peaks.iter().skip(1).all(|&p| (p - 0.01).abs() < 1e-4), "amplitude changed: {peaks:?}");
    let across = world.joints()[0].separation(world.bodies()).unwrap() * Vec3::new(0.0, 1.0, 1.0);
    assert!(across.length() < 1e-5, "anchors parted across the axis by {across}");
    let turned = world.joints()[0].deviation(world.bodies()).unwrap().length();
    assert!(turned < 1e-3, "the slider turned {turned} rad");
}
