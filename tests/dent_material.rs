//! Dent distance from impact speed (paper Algorithm 1, line 2): threshold, gain and cap on the
//! normal speed, and bad materials rejected.

use dentbend::dent::DentMaterial;
use dentbend::glam::Vec3;
use dentbend::{DentError, Impact};

const STEEL: DentMaterial = DentMaterial { threshold: 2.0, gain: 0.01, cap: 0.3 };

fn hit(velocity: Vec3) -> Impact {
    Impact { point: Vec3::ZERO, normal: Vec3::new(0.0, -2.0, 0.0), relative_velocity: velocity }
}

#[test]
fn below_the_threshold_nothing_dents() {
    assert_eq!(STEEL.dent_distance(&hit(Vec3::new(0.0, -2.0, 0.0))).unwrap(), None);
    assert_eq!(STEEL.dent_distance(&hit(Vec3::new(50.0, -1.0, 0.0))).unwrap(), None, "tangential speed does not dent");
}

#[test]
fn above_it_the_dent_grows_linearly_up_to_the_cap() {
    // f32 products of small numbers: a few ulps.
    let d = |vn: f32| STEEL.dent_distance(&hit(Vec3::new(3.0, -vn, 0.0))).unwrap().unwrap();
    assert!((d(12.0) - 0.1).abs() < 1e-6);
    assert!((d(22.0) - 0.2).abs() < 1e-6);
    assert_eq!(d(1000.0), 0.3);
}

#[test]
fn bad_materials_and_impacts_are_errors() {
    let v = Vec3::new(0.0, -10.0, 0.0);
    for bad in [
        DentMaterial { threshold: f32::NAN, ..STEEL },
        DentMaterial { threshold: -1.0, ..STEEL },
        DentMaterial { gain: f32::INFINITY, ..STEEL },
        DentMaterial { cap: 0.0, ..STEEL },
    ] {
        assert!(matches!(bad.dent_distance(&hit(v)), Err(DentError::InvalidParameter { .. })));
    }
    let zero_normal = Impact { normal: Vec3::ZERO, ..hit(v) };
    assert!(matches!(STEEL.dent_distance(&zero_normal), Err(DentError::InvalidImpact(_))));
}
