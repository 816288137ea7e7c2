//! Sub-bodies: triangles by dominant weight, level-set cells coloured from them, and mass
//! properties that add up to the whole body's (and match the mesh's within the voxel error).

use dentbend::TriMesh;
use dentbend::bend::{
    BendError, LevelSet, NO_BONE, SubBodies, WeightParams, auto_skeleton, bunny_skeleton, compute_weights,
};
use dentbend::glam::{Mat3, Vec3};
use dentbend::mesh;
use dentbend_solver::sim::{MassProperties, mass_properties};

fn params(resolution: u32) -> WeightParams {
    WeightParams { resolution, ..WeightParams::default() }
}

/// Largest absolute entry of a matrix.
fn max_abs(m: Mat3) -> f32 {
    m.to_cols_array().iter().fold(0.0f32, |a, &x| a.max(x.abs()))
}

/// Inertia of `parts` about the common centre `centre`, by the parallel-axis theorem.
fn combined_inertia(parts: &[MassProperties], centre: Vec3) -> Mat3 {
    parts.iter().fold(Mat3::ZERO, |sum, p| {
        let r = p.center - centre;
        let shift = Mat3::from_diagonal(Vec3::splat(r.length_squared())) - Mat3::from_cols(r * r.x, r * r.y, r * r.z);
        sum + p.inertia + shift * p.mass
    })
}

#[test]
fn bar_sub_bodies_split_the_mass_at_the_joint() {
    // 8 × 1 × 1 bar; at resolution 32 the cells are 0.25 m and the bar's faces fall on cell
    // faces, so the voxel body is the bar exactly and its mass properties match the mesh's to f32
    // rounding (1e-4 relative).
    let bar = mesh::plank(8.0, 1.0, 1.0, 16).unwrap();
    let skeleton = auto_skeleton(&bar, 2).unwrap();
    let (weights, cache) = compute_weights(&bar, &skeleton, params(32)).unwrap();
    let density = 700.0;
    let subs = SubBodies::compute(&bar, &weights, cache.level_set(), density).unwrap();
    let exact = mass_properties(&bar, density).unwrap();
    let total = subs.total();
    assert!((total.mass - exact.mass).abs() <= 1e-4 * exact.mass, "{} vs {}", total.mass, exact.mass);
    assert!(
        max_abs(total.inertia - exact.inertia) <= 1e-4 * max_abs(exact.inertia),
        "{} vs {}",
        total.inertia,
        exact.inertia
    );
    let parts: Vec<MassProperties> = subs.bodies().iter().map(|b| b.mass.unwrap()).collect();
    let sum: f32 = parts.iter().map(|p| p.mass).sum();
    assert!((sum - total.mass).abs() <= 1e-5 * total.mass, "{sum} vs {}", total.mass);
    // By symmetry each half's centre is at x = ±2 on the axis, on its bone (x from ∓3.6 to 0).
    for (b, part) in parts.iter().enumerate() {
        let expected = Vec3::new(if b == 0 { -2.0 } else { 2.0 }, 0.0, 0.0);
        assert!((part.center - expected).length() < 1e-3, "bone {b}: centre {}", part.center);
        assert!(skeleton.bones()[b].distance(part.center) < 1e-3);
        assert!((part.mass - exact.mass / 2.0).abs() <= 1e-4 * exact.mass);
    }
    // The parts' inertias recombine into the whole body's (parallel-axis theorem).
    let recombined = combined_inertia(&parts, total.center);
    assert!(max_abs(recombined - total.inertia) <= 1e-4 * max_abs(total.inertia), "{recombined} vs {}", total.inertia);
}

#[test]
fn triangles_and_cells_are_all_assigned() {
    let bar = mesh::plank(6.0, 1.0, 1.0, 12).unwrap();
    let skeleton = auto_skeleton(&bar, 3).unwrap();
    let (weights, cache) = compute_weights(&bar, &skeleton, params(24)).unwrap();
    let subs = SubBodies::compute(&bar, &weights, cache.level_set(), 1.0).unwrap();
    assert!(subs.triangle_bones().iter().all(|&b| b < 3));
    assert!(subs.cell_bones().iter().all(|&b| b != NO_BONE && b < 3));
    let mut faces = 0;
    for b in 0..3 {
        let (part, parents) = subs.sub_mesh(&bar, b).unwrap();
        faces += part.face_count();
        assert_eq!(part.vertex_count(), parents.len());
        // Each part is an open surface: some edge has a face on one side only.
        assert!(part.face_count() > 0);
        // Its triangles are where its bone is: the middle third for bone 1.
        let centre = part.positions().iter().copied().sum::<Vec3>() / part.vertex_count() as f32;
        assert!(skeleton.bones()[b].distance(centre) < 0.6, "bone {b}: surface centre {centre}");
    }
    assert_eq!(faces, bar.face_count());
    let cells: usize = subs.bodies().iter().map(|b| b.cell_count).sum();
    assert_eq!(cells, cache.level_set().cell_count());
    assert!(matches!(subs.sub_mesh(&bar, 3), Err(BendError::BoneOutOfRange { bone: 3, count: 3 })));
    assert!(matches!(
        SubBodies::compute(&bar, &weights, cache.level_set(), -1.0),
        Err(BendError::InvalidParameter { name: "density", .. })
    ));
}

#[test]
fn bunny_sub_bodies_add_up_and_sit_on_their_bones() {
    let bunny = mesh::load("bunny").unwrap();
    let skeleton = bunny_skeleton(1.0).unwrap();
    let (weights, cache) = compute_weights(&bunny, &skeleton, params(32)).unwrap();
    let set = cache.level_set();
    let subs = SubBodies::compute(&bunny, &weights, set, 1000.0).unwrap();
    let total = subs.total();
    let parts: Vec<MassProperties> = subs.bodies().iter().map(|b| b.mass.expect("every bone owns cells")).collect();
    let sum: f32 = parts.iter().map(|p| p.mass).sum();
    assert!((sum - total.mass).abs() <= 1e-5 * total.mass, "{sum} vs {}", total.mass);
    // Voxel vs mesh mass: only cells the surface crosses can be misclassified, so the volume
    // error is below area × cell size / 2 (a cell misread as inside or outside carries ≤ h³ and
    // those cells cover ~area·h); at resolution 32 that is 6 % of the volume.
    let exact = mass_properties(&bunny, 1000.0).unwrap();
    let bound = 0.5 * bunny.area() * set.cell_size() * 1000.0;
    assert!((total.mass - exact.mass).abs() <= bound, "voxels {} vs mesh {} (bound {bound})", total.mass, exact.mass);
    assert!((total.center - exact.center).length() < set.cell_size());
    // Each sub-body's centre lies near its bone: within half a bone length for the body and head
    // (big blobs around short bones), within a quarter for the ears.
    for (b, part) in parts.iter().enumerate() {
        let bone = &skeleton.bones()[b];
        let limit = if b < 2 { 0.5 } else { 0.25 } * bone.length();
        let d = bone.distance(part.center);
        assert!(d < limit, "bone {b}: centre {} is {d} m from its bone (limit {limit})", part.center);
    }
    let recombined = combined_inertia(&parts, total.center);
    assert!(max_abs(recombined - total.inertia) <= 1e-4 * max_abs(total.inertia), "{recombined} vs {}", total.inertia);
}

#[test]
fn level_set_rows_through_vertices_and_edges_classify_exactly() {
    // A 2 m cube with vertices every 0.125 m, at resolution 8 (0.25 m cells): every row of cell
    // centres (odd multiples of 0.125 m) runs exactly through mesh vertices and along edges in the
    // (y, z) projection, the case the tie rule exists for. Exactly the 8³ centres inside count.
    let cube = mesh::subdivided_box(Vec3::splat(2.0), [16, 16, 16]).unwrap();
    let set = LevelSet::build(&cube, 8).unwrap();
    assert_eq!(set.cell_size(), 0.25);
    assert_eq!(set.inside_count(), 512);
    for c in 0..set.cell_count() {
        let p = set.center(c);
        assert_eq!(set.is_inside(c), p.abs().max_element() < 1.0, "cell {c} at {p}");
    }
    // Wound inside out, the same solid.
    let flipped =
        TriMesh::new(cube.positions().to_vec(), cube.faces().iter().map(|&[a, b, c]| [a, c, b]).collect()).unwrap();
    assert_eq!(LevelSet::build(&flipped, 8).unwrap().inside_count(), 512);
    assert!(!set.is_inside(usize::MAX) && set.nearest_triangle(usize::MAX).is_none());
}

#[test]
fn level_set_distance_is_exact_in_the_band() {
    // Unit icosphere (chord error < 1e-3 m): |φ| is the distance to the sphere in the band.
    let ball = mesh::icosphere(1.0, 4).unwrap();
    let set = LevelSet::build(&ball, 24).unwrap();
    let mut band = 0;
    for c in 0..set.cell_count() {
        let (p, phi) = (set.center(c), set.phi()[c]);
        let exact = p.length() - 1.0;
        assert_eq!(phi < 0.0, exact < 0.0, "cell {c} at {p}: φ {phi}");
        if exact.abs() < 0.8 * set.band() {
            assert!((phi - exact).abs() < 2e-3, "cell {c}: φ {phi} vs {exact}");
            assert!(set.nearest_triangle(c).is_some());
            band += 1;
        } else {
            assert!(phi.abs() <= set.band() + 1e-6);
        }
    }
    assert!(band > 500, "{band} band cells");
    // Voxel volume within the surface-crossing bound of 4π/3.
    let volume = set.inside_count() as f32 * set.cell_volume();
    let bound = 0.5 * ball.area() * set.cell_size();
    assert!((volume - ball.volume()).abs() < bound, "{volume} vs {}", ball.volume());
}
