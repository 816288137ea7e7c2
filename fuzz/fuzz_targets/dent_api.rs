//! The dent API on small meshes with arbitrary impacts and parameters (NaN, ±∞ and huge values
//! included): a call that fails leaves its target meshes bit-for-bit unchanged, and one that
//! succeeds leaves every vertex and normal finite.
#![no_main]

use dentbend::dent::{BodyState, DentSettings, Surface, decide_dent_distance};
use dentbend::glam::{Affine3A, Mat3, Vec3};
use dentbend::mesh::TriMesh;
use dentbend::{DentMap, Impact, dent, dent_pair};
use dentbend_fuzz::dent_input::{Call, DentInput, ParamsInput};
use dentbend_fuzz::{assert_finite_mesh, fingerprint};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|input: DentInput| {
    let mut target = input.target.mesh();
    let mut projectile = input.projectile.mesh();
    if projectile.transform(Affine3A::from_translation(input.projectile_offset.vec3())).is_err() {
        return;
    }
    let impact = Impact {
        point: input.point.vec3(),
        normal: input.normal.vec3(),
        relative_velocity: input.relative_velocity.vec3(),
    };
    let params = input.params.params();
    let before = fingerprint(&target);
    let projectile_before = fingerprint(&projectile);
    match &input.call {
        Call::Dent => match dent(&mut target, &projectile, &impact, &params) {
            Ok(report) => {
                assert_finite_mesh(&target);
                assert!(report.max_displacement.is_finite(), "non-finite max_displacement {report:?}");
            }
            Err(_) => assert_eq!(fingerprint(&target), before, "a failed dent changed its target"),
        },
        Call::DentPair { other } => {
            let other_params = other.as_ref().map_or_else(|| params.clone(), ParamsInput::params);
            match dent_pair(&mut target, &mut projectile, &impact, &params, &other_params) {
                Ok(_) => {
                    assert_finite_mesh(&target);
                    assert_finite_mesh(&projectile);
                }
                Err(_) => {
                    assert_eq!(fingerprint(&target), before, "a failed dent_pair changed its first mesh");
                    assert_eq!(
                        fingerprint(&projectile),
                        projectile_before,
                        "a failed dent_pair changed its second mesh"
                    );
                }
            }
        }
        Call::Gaussian { width } => {
            if let Ok(map) = DentMap::gaussian(width.value(), &impact, &params) {
                apply_map(&map, &mut target, &params.attenuation, &before);
            }
        }
        Call::Heights { res, extent, heights } => {
            if heights.is_empty() {
                return;
            }
            let res = u32::from(*res);
            let heights: Vec<f32> = (0..res * res).map(|i| heights[i as usize % heights.len()].value()).collect();
            if let Ok(map) = DentMap::from_heights(&heights, res, extent.value(), &impact, &params) {
                apply_map(&map, &mut target, &params.attenuation, &before);
            }
        }
        Call::Decide { threshold, gain, cap, hardness, mass, spin } => {
            let mut settings = DentSettings::new(threshold.value(), gain.value(), cap.value());
            settings.params = params.clone();
            settings.hardness = hardness.as_ref().map(|h| h.value());
            let projectile_state = BodyState::moving(
                Vec3::ZERO,
                input.relative_velocity.vec3(),
                spin.vec3(),
                mass.value(),
                Mat3::IDENTITY,
            );
            let surface = Surface { mesh: &projectile, to_world: Affine3A::IDENTITY };
            let decided = decide_dent_distance(&settings, &impact, &BodyState::FIXED, &projectile_state, &surface);
            if let Ok(Some(d)) = decided {
                assert!(d.is_finite() && d > 0.0, "decided a dent distance of {d}");
                assert!(d <= settings.material.cap * (1.0 + 1e-6), "dent distance {d} over the cap");
            }
        }
    }
});

/// Applies `map` and checks the outcome: finite on success, unchanged on failure.
fn apply_map(map: &DentMap, target: &mut TriMesh, attenuation: &dentbend::Attenuation, before: &[u32]) {
    match map.apply(target, attenuation) {
        Ok(_) => assert_finite_mesh(target),
        Err(_) => assert_eq!(fingerprint(target), before, "a failed DentMap::apply changed its target"),
    }
}
