//! A dent far smaller than its target (a nanometre on a 1 m plate: a hit barely over the
//! threshold speed) refines toward edges no shorter than 1/16384 of the target's diagonal: its
//! map is finer than f32 resolves at that size, and bisecting toward it would only pile
//! triangles around one point (before this floor, such a dent took seconds to minutes).

use dentbend::dent::DentSettings;
use dentbend::glam::{Affine3A, Vec3};
use dentbend::{Impact, mesh};

#[test]
fn a_nanometre_dent_refines_no_edge_below_the_floor() {
    let plate = mesh::subdivided_box(Vec3::new(1.0, 0.2, 1.0), [6, 1, 6]).unwrap();
    let (lo, hi) = plate.bounds();
    let floor = lo.distance(hi) / 16384.0;
    let mut ball = mesh::icosphere(0.2, 1).unwrap();
    ball.transform(Affine3A::from_translation(Vec3::new(0.1, 0.3, 0.0))).unwrap();
    for d in [1e-9f32, 1e-15, 1e-30] {
        let mut target = plate.clone();
        let mut params = DentSettings::new(1.0, 0.02, 0.08).params;
        params.resolution = dentbend::Resolution::Auto { min: 16, max: 32 };
        params.dent_distance = d;
        let impact = Impact::head_on(Vec3::new(0.1, 0.1, 0.0), -Vec3::Y);
        dentbend::dent(&mut target, &ball, &impact, &params).unwrap();
        // Longest-edge bisection halves edges longer than the asked length, so no new edge is
        // shorter than half the floor.
        let shortest = target.faces()[plate.face_count()..]
            .iter()
            .flat_map(|f| (0..3).map(move |k| (f[k], f[(k + 1) % 3])))
            .map(|(a, b)| target.positions()[a as usize].distance(target.positions()[b as usize]))
            .fold(f32::INFINITY, f32::min);
        assert!(shortest >= 0.5 * floor, "d = {d:e}: a new edge of {shortest:e} m, floor {floor:e} m");
    }
}
