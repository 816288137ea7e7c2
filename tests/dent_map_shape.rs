//! Shape of the dent map built from the bunny (paper Figures 5 and 7): the peak is d, the
//! envelope never lowers the profile, larger σ gives a wider dent, and the map fades to zero
//! before the border.

use dentbend::dent::dent_map_stages;
use dentbend::glam::Vec3;
use dentbend::{DentParams, Impact, Resolution, mesh};

const D: f32 = 1.5;

/// The bunny dropped along -y onto whatever lies below it: the tip is its lowest vertex.
fn bunny_impact() -> (dentbend::TriMesh, Impact) {
    let bunny = mesh::builtin("bunny").unwrap();
    let tip = bunny.positions().iter().copied().min_by(|a, b| a.y.total_cmp(&b.y)).unwrap();
    (bunny, Impact { point: tip, normal: -Vec3::Y, relative_velocity: -Vec3::Y })
}

fn stages(params: &DentParams) -> dentbend::dent::DentStages {
    let (bunny, impact) = bunny_impact();
    dent_map_stages(&bunny, &impact, params, None).unwrap()
}

#[test]
fn every_stage_peaks_at_the_dent_distance() {
    let s = stages(&DentParams::new(D));
    let max = |v: &[f32]| v.iter().copied().fold(0.0, f32::max);
    // The tip cell holds d + 0 exactly up to f32 depth rounding.
    assert!((max(&s.zbuffer) - D).abs() <= 1e-5 * D);
    assert!((max(&s.envelope) - D).abs() <= 1e-5 * D, "the envelope's peak is the profile's peak");
    assert!((max(&s.smoothed) - D).abs() <= 1e-5 * D, "rescale then clamped steps keep the peak at d");
    assert!(s.zbuffer.iter().all(|&p| (0.0..=D * (1.0 + 1e-6)).contains(&p)));
    for (e, p) in s.envelope.iter().zip(&s.zbuffer) {
        // Each cell is its own Gaussian source; 1e-5·d covers the log/exp round trip in f32.
        assert!(*e >= p - 1e-5 * D, "broadening lowered a cell: {e} < {p}");
    }
}

#[test]
fn the_map_fades_out_before_the_border() {
    let s = stages(&DentParams::new(D));
    let res = s.zbuffer_grid.res as usize;
    let border = (0..res).flat_map(|i| [i, (res - 1) * res + i, i * res, i * res + res - 1]);
    let edge_max = border.map(|k| s.smoothed[k]).fold(0.0, f32::max);
    // 3.5σ of Gaussian tail leaves e^{-6.1} ≈ 0.2 % of a cell's height; heat diffusion adds a
    // little: 1 % of d.
    assert!(edge_max <= 0.01 * D, "border reaches {edge_max}");
}

#[test]
fn larger_sigma_gives_a_wider_dent() {
    let area = |sigma: f32| {
        let s = stages(&DentParams { sigma: Some(sigma), ..DentParams::new(D) });
        let h = s.zbuffer_grid.cell_size;
        s.smoothed.iter().filter(|&&v| v > 0.05 * D).count() as f32 * h * h
    };
    let (narrow, medium, wide) = (area(0.2), area(0.6), area(1.2));
    assert!(narrow < medium && medium < wide, "dent areas {narrow} {medium} {wide}");
}

#[test]
fn deeper_dents_cover_more_of_the_projectile() {
    let footprint = |d: f32| {
        let s = stages(&DentParams { sigma: Some(0.3), ..DentParams::new(d) });
        let h = s.zbuffer_grid.cell_size;
        s.zbuffer.iter().filter(|&&v| v > 0.0).count() as f32 * h * h
    };
    assert!(footprint(0.5) < footprint(1.5) && footprint(1.5) < footprint(4.0));
}

#[test]
fn resolution_is_automatic_within_bounds_or_fixed() {
    let auto = stages(&DentParams::new(D));
    assert!((25..=400).contains(&auto.zbuffer_grid.res));
    let fixed = stages(&DentParams { resolution: Resolution::Fixed(64), ..DentParams::new(D) });
    assert_eq!(fixed.zbuffer_grid.res, 64);
    assert_eq!(fixed.zbuffer.len(), 64 * 64);
    let tight = stages(&DentParams { resolution: Resolution::Auto { min: 30, max: 40 }, ..DentParams::new(D) });
    assert!((30..=40).contains(&tight.zbuffer_grid.res));
}
