//! Every dent entry point fed bad input returns a typed error, never panics, and leaves the
//! caller's meshes unchanged.

mod common;

use common::sphere_at;
use dentbend::glam::Vec3;
use dentbend::{Attenuation, DentError, DentParams, Impact, Resolution, TriMesh, dent, dent_map, dent_pair, mesh};

fn setup() -> (TriMesh, TriMesh, Impact) {
    let block = mesh::subdivided_box(Vec3::new(4.0, 1.0, 4.0), [16, 4, 16]).unwrap();
    let ball = sphere_at(Vec3::new(0.0, 1.5, 0.0), 1.0);
    let impact = Impact { point: Vec3::new(0.0, 0.5, 0.0), normal: -Vec3::Y, relative_velocity: -Vec3::Y };
    (block, ball, impact)
}

/// Runs `dent` and `dent_pair` with the given inputs and checks both fail the same way with
/// every mesh untouched.
fn assert_rejected(impact: Impact, params: DentParams, check: impl Fn(&DentError) -> bool) {
    let (block, ball, _) = setup();
    let (mut target, mut other) = (block.clone(), ball.clone());
    let err = dent(&mut target, &ball, &impact, &params).unwrap_err();
    assert!(check(&err), "dent gave the wrong error: {err:?}");
    assert_eq!(target, block, "dent changed the target on error");
    let err = dent_pair(&mut target, &mut other, &impact, &params, &params).unwrap_err();
    assert!(check(&err), "dent_pair gave the wrong error: {err:?}");
    assert_eq!(target, block, "dent_pair changed A on error");
    assert_eq!(other, ball, "dent_pair changed B on error");
    assert!(!err.to_string().is_empty());
}

fn bad_param(name: &'static str) -> impl Fn(&DentError) -> bool {
    move |e| matches!(e, DentError::InvalidParameter { name: n, .. } if *n == name)
}

fn bad_impact(e: &DentError) -> bool {
    matches!(e, DentError::InvalidImpact(_))
}

#[test]
fn non_finite_or_non_positive_dent_distance() {
    let (_, _, impact) = setup();
    for d in [f32::NAN, f32::INFINITY, -1.0, 0.0] {
        assert_rejected(impact, DentParams::new(d), bad_param("dent_distance"));
    }
}

#[test]
fn bad_parameters_are_named() {
    let (_, _, impact) = setup();
    let base = DentParams::new(0.2);
    let cases: Vec<(DentParams, &str)> = vec![
        (DentParams { sigma: Some(f32::NAN), ..base.clone() }, "sigma"),
        (DentParams { sigma: Some(-0.1), ..base.clone() }, "sigma"),
        (DentParams { resolution: Resolution::Fixed(0), ..base.clone() }, "resolution"),
        (DentParams { resolution: Resolution::Fixed(100_000), ..base.clone() }, "resolution"),
        (DentParams { resolution: Resolution::Auto { min: 50, max: 10 }, ..base.clone() }, "resolution"),
        (DentParams { heat_rate: 0.3, ..base.clone() }, "heat_rate"),
        (DentParams { heat_rate: f32::NAN, ..base.clone() }, "heat_rate"),
        (DentParams { heat_iters: 10_000_000, ..base.clone() }, "heat_iters"),
        (DentParams { widen: f32::INFINITY, ..base.clone() }, "widen"),
        (DentParams { widen: -1.0, ..base.clone() }, "widen"),
        (DentParams { min_cos: 0.0, ..base.clone() }, "min_cos"),
        (DentParams { min_cos: f32::NAN, ..base.clone() }, "min_cos"),
        (DentParams { attenuation: Attenuation::Linear { scale: 0.0 }, ..base.clone() }, "attenuation.scale"),
        (
            DentParams { attenuation: Attenuation::Custom(std::sync::Arc::new(|_, _| 0.5)), ..base.clone() },
            "attenuation",
        ),
        (
            DentParams {
                attenuation: Attenuation::Custom(std::sync::Arc::new(|z, _| if z > 0.1 { f32::NAN } else { 1.0 })),
                ..base.clone()
            },
            "attenuation",
        ),
    ];
    for (params, name) in cases {
        assert_rejected(impact, params, bad_param(name));
    }
}

#[test]
fn bad_impacts() {
    let (_, _, ok) = setup();
    let params = DentParams::new(0.2);
    assert_rejected(Impact { normal: Vec3::ZERO, ..ok }, params.clone(), bad_impact);
    assert_rejected(Impact { normal: Vec3::new(f32::NAN, -1.0, 0.0), ..ok }, params.clone(), bad_impact);
    assert_rejected(Impact { point: Vec3::new(0.0, f32::INFINITY, 0.0), ..ok }, params.clone(), bad_impact);
    assert_rejected(Impact { relative_velocity: Vec3::splat(f32::NAN), ..ok }, params.clone(), bad_impact);
    assert_rejected(Impact { relative_velocity: Vec3::Y, ..ok }, params, |e| matches!(e, DentError::Separating { .. }));
}

#[test]
fn zero_velocity_means_head_on() {
    let (mut block, ball, impact) = setup();
    let report =
        dent(&mut block, &ball, &Impact { relative_velocity: Vec3::ZERO, ..impact }, &DentParams::new(0.2)).unwrap();
    assert!(report.theta_deg.abs() < 1e-3 && report.moved_vertices > 0);
}

#[test]
fn projectile_behind_the_plane() {
    let (block, _, impact) = setup();
    let buried = sphere_at(Vec3::new(0.0, -3.0, 0.0), 0.5);
    let mut target = block.clone();
    let err = dent(&mut target, &buried, &impact, &DentParams::new(0.2)).unwrap_err();
    assert!(matches!(err, DentError::ProjectileBehindPlane { distance } if distance > 0.0), "{err:?}");
    assert_eq!(target, block);
}

#[test]
fn degenerate_projectiles() {
    let (block, _, impact) = setup();
    let point = TriMesh::new(vec![Vec3::new(0.0, 0.6, 0.0); 3], vec![[0, 1, 2]]).unwrap();
    let segment = TriMesh::new(
        vec![Vec3::new(0.0, 0.6, 0.0), Vec3::new(1.0, 0.6, 0.0), Vec3::new(2.0, 0.6, 0.0)],
        vec![[0, 1, 2]],
    )
    .unwrap();
    for projectile in [point, segment] {
        let mut target = block.clone();
        let err = dent(&mut target, &projectile, &impact, &DentParams::new(0.2)).unwrap_err();
        assert!(matches!(err, DentError::DegenerateProjectile), "{err:?}");
        assert_eq!(target, block);
        assert!(dent_map(&projectile, &impact, &DentParams::new(0.2), None).is_err());
    }
}

#[test]
fn degenerate_targets_are_refused_by_every_cpu_entry_point() {
    let (block, ball, impact) = setup();
    let collapsed = TriMesh::new(vec![Vec3::ZERO; block.vertex_count()], block.faces().to_vec()).unwrap();
    let line = (0..block.vertex_count()).map(|i| Vec3::X * i as f32).collect();
    let on_a_line = TriMesh::new(line, block.faces().to_vec()).unwrap();
    let params = DentParams::new(0.2);
    for degenerate in [collapsed, on_a_line] {
        let mut target = degenerate.clone();
        let err = dent(&mut target, &ball, &impact, &params).unwrap_err();
        assert!(matches!(err, DentError::DegenerateTarget), "{err:?}");
        assert_eq!(target, degenerate);
        let mut other = block.clone();
        let err = dentbend::dent::dent_pair(&mut target, &mut other, &impact, &params, &params).unwrap_err();
        assert!(matches!(err, DentError::DegenerateTarget), "{err:?}");
        assert_eq!((&target, &other), (&degenerate, &block));
        // In a batch, the job on the degenerate target is named and no target changes.
        let mut targets = [block.clone(), degenerate.clone()];
        let jobs = [
            dentbend::dent::DentJob { target: 0, projectile: &ball, impact, params: params.clone() },
            dentbend::dent::DentJob { target: 1, projectile: &ball, impact, params: params.clone() },
        ];
        let err = dentbend::dent::dent_batch_tracked(&mut targets, &jobs).unwrap_err();
        assert_eq!(err.job, 1);
        assert!(matches!(err.error, DentError::DegenerateTarget), "{err:?}");
        assert_eq!(targets, [block.clone(), degenerate.clone()]);
    }
}

#[test]
fn empty_and_malformed_meshes_cannot_be_built() {
    assert!(matches!(TriMesh::new(vec![], vec![]), Err(dentbend::MeshError::Empty { .. })));
    assert!(matches!(TriMesh::new(vec![Vec3::ZERO; 3], vec![]), Err(dentbend::MeshError::Empty { .. })));
    assert!(matches!(
        TriMesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::NAN], vec![[0, 1, 2]]),
        Err(dentbend::MeshError::NonFinite { index: 2, .. })
    ));
    assert!(matches!(
        TriMesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 3]]),
        Err(dentbend::MeshError::IndexOutOfRange { face: 0, index: 3, .. })
    ));
}

#[test]
fn target_edge_must_be_finite() {
    let (_, ball, impact) = setup();
    for edge in [f32::NAN, f32::INFINITY, -1.0] {
        assert!(matches!(
            dent_map(&ball, &impact, &DentParams::new(0.2), Some(edge)),
            Err(DentError::InvalidParameter { name: "target_edge", .. })
        ));
    }
}

#[test]
fn corrupt_dent_maps_are_not_applied() {
    let (block, ball, impact) = setup();
    let good = dent_map(&ball, &impact, &DentParams::new(0.2), None).unwrap();
    let mut corrupt = [good.clone(), good.clone(), good.clone(), good.clone()];
    corrupt[0].cells[10] = [f32::NAN, 0.0, 0.0, 0.0];
    corrupt[1].cells.pop();
    corrupt[2].grid.cell_size = 0.0;
    corrupt[3].dent_distance = f32::INFINITY;
    for map in corrupt {
        let mut target = block.clone();
        assert!(map.apply(&mut target, &Attenuation::Logistic).is_err());
        assert_eq!(target, block);
    }
    let mut target = block.clone();
    assert!(good.apply(&mut target, &Attenuation::Linear { scale: f32::NAN }).is_err());
    assert_eq!(target, block);
}

/// σ or d beyond f32 range is refused by name instead of producing an infinite grid.
#[test]
fn sizes_beyond_f32_are_errors() {
    let (_, _, impact) = setup();
    assert_rejected(impact, DentParams { sigma: Some(1e38), ..DentParams::new(0.2) }, bad_param("sigma"));
    assert_rejected(impact, DentParams::new(2e38), bad_param("dent_distance"));
    assert_rejected(impact, DentParams { min_cos: 1e-30, ..DentParams::new(0.2) }, bad_param("min_cos"));
}

/// σ far below a cell keeps the profile itself (every Gaussian is narrower than a cell).
#[test]
fn a_tiny_sigma_still_dents() {
    let (mut block, ball, impact) = setup();
    let params = DentParams { sigma: Some(1e-25), ..DentParams::new(0.2) };
    let report = dent(&mut block, &ball, &impact, &params).unwrap();
    assert!(report.moved_vertices > 0 && (report.max_displacement - 0.2).abs() < 0.01, "{report:?}");
}

/// A normal whose squared length overflows f32 still has a direction; a velocity at the top of
/// the supported range keeps its angle, and one beyond it is refused by name.
#[test]
fn huge_vectors_keep_their_direction() {
    let (block, ball, impact) = setup();
    let mut target = block.clone();
    let huge_normal = Impact { normal: Vec3::new(0.0, -1e20, 0.0), ..impact };
    assert!(dent(&mut target, &ball, &huge_normal, &DentParams::new(0.2)).unwrap().moved_vertices > 0);
    let fast = Impact { relative_velocity: Vec3::new(3.0, -1.0, 0.0) * (dentbend::dent::MAX_SPEED / 3.2), ..impact };
    let map = dentbend::dent::dent_map_stages(&ball, &fast, &DentParams::new(0.2), None).unwrap();
    let expected = 3f32.atan().to_degrees(); // 71.6°
    assert!((map.frame.theta_deg() - expected).abs() < 1e-3, "θ {}", map.frame.theta_deg());
    let too_fast = Impact { relative_velocity: Vec3::new(3e38, -1e38, 0.0), ..impact };
    let error = dentbend::dent::dent_map_stages(&ball, &too_fast, &DentParams::new(0.2), None).unwrap_err();
    assert!(error.to_string().contains("faster than"), "{error}");
}

/// A stray vertex that no face uses is not part of the projectile's surface.
#[test]
fn unreferenced_vertices_do_not_move_the_tip() {
    let (block, ball, impact) = setup();
    let mut positions = ball.positions().to_vec();
    positions.push(Vec3::new(0.0, -5.0, 0.0)); // far ahead of the ball, inside the block
    let stray = TriMesh::new(positions, ball.faces().to_vec()).unwrap();
    let (mut a, mut b) = (block.clone(), block.clone());
    let clean = dent(&mut a, &ball, &impact, &DentParams::new(0.2)).unwrap();
    let with_stray = dent(&mut b, &stray, &impact, &DentParams::new(0.2)).unwrap();
    assert_eq!(clean, with_stray);
    assert_eq!(a, b);
}
