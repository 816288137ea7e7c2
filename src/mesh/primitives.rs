//! Procedural primitives: closed, welded, wound counter-clockwise seen from outside, centred at
//! the origin, sizes in world units.

use std::collections::HashMap;
use std::f32::consts::{PI, TAU};

use glam::Vec3;

use super::subdivide::{split_faces, unit_midpoints};
use super::{MeshError, TriMesh};

/// Most triangles any generator will build (about 200 MB of mesh): larger requests are refused.
pub const MAX_PRIMITIVE_TRIANGLES: u64 = 1 << 24;

fn invalid(message: String) -> MeshError {
    MeshError::InvalidParameter(message)
}

fn positive(name: &str, value: f32) -> Result<(), MeshError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(invalid(format!("{name} must be finite and positive, got {value}")))
    }
}

fn at_least(name: &str, value: u32, min: u32) -> Result<(), MeshError> {
    if value >= min { Ok(()) } else { Err(invalid(format!("{name} must be at least {min}, got {value}"))) }
}

fn budget(what: &str, triangles: u128) -> Result<(), MeshError> {
    if triangles <= u128::from(MAX_PRIMITIVE_TRIANGLES) {
        Ok(())
    } else {
        Err(invalid(format!(
            "{what} would have {triangles} triangles, more than the limit of {MAX_PRIMITIVE_TRIANGLES}"
        )))
    }
}

/// The regular icosahedron on the unit sphere, from the vertices (0, ±1, ±φ) and their cyclic
/// permutations (so the vertex set is closed under every coordinate sign flip), 20 outward faces.
fn icosahedron() -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let phi = (1.0 + 5f32.sqrt()) / 2.0;
    let mut corners = Vec::with_capacity(12);
    for s1 in [-1.0, 1.0] {
        for s2 in [-1.0, 1.0] {
            corners.push(Vec3::new(0.0, s1, s2 * phi));
            corners.push(Vec3::new(s1, s2 * phi, 0.0));
            corners.push(Vec3::new(s2 * phi, 0.0, s1));
        }
    }
    // Edges have squared length 4; the next-nearest pairs are at 4φ + 4 ≈ 10.5.
    let adjacent = |i: usize, j: usize| corners[i].distance_squared(corners[j]) < 4.5;
    let mut faces = Vec::with_capacity(20);
    for i in 0..12 {
        for j in i + 1..12 {
            for k in j + 1..12 {
                if adjacent(i, j) && adjacent(j, k) && adjacent(i, k) {
                    let (a, b, c) = (corners[i], corners[j], corners[k]);
                    let outward = (b - a).cross(c - a).dot(a + b + c) > 0.0;
                    let [i, j, k] = [i, j, k].map(|v| v as u32);
                    faces.push(if outward { [i, j, k] } else { [i, k, j] });
                }
            }
        }
    }
    (corners.into_iter().map(Vec3::normalize).collect(), faces)
}

/// A geodesic sphere of `radius` (world units): the standard icosahedron, split 1→4
/// `subdivisions` times with the new vertices projected onto the sphere.
///
/// It has 20·4^s triangles and 10·4^s + 2 vertices (s = 4: 5120 and 2562), and its vertex set is
/// mirror-symmetric under x → −x, y → −y and z → −z.
///
/// # Errors
/// [`MeshError::InvalidParameter`] unless `radius` is finite and positive and `subdivisions ≤ 8`.
///
/// # Example
/// ```
/// let ball = dentbend::mesh::icosphere(0.5, 3).unwrap();
/// assert_eq!(ball.face_count(), 1280);
/// ```
pub fn icosphere(radius: f32, subdivisions: u32) -> Result<TriMesh, MeshError> {
    positive("icosphere radius", radius)?;
    if subdivisions > 8 {
        return Err(invalid(format!("icosphere subdivisions must be at most 8, got {subdivisions}")));
    }
    let (mut positions, mut faces) = icosahedron();
    for _ in 0..subdivisions {
        let split = split_faces(positions.len(), &faces);
        let fresh = unit_midpoints(&positions, &split);
        positions.extend(fresh);
        faces = split.faces;
    }
    positions.iter_mut().for_each(|p| *p *= radius);
    TriMesh::new(positions, faces)
}

/// A latitude-longitude sphere of `radius` (world units) about the y axis: `segments` meridians
/// (≥ 3), `rings` latitude bands (≥ 2), a single vertex at each pole.
///
/// It has 2·segments·(rings − 1) triangles and segments·(rings − 1) + 2 vertices.
///
/// # Errors
/// [`MeshError::InvalidParameter`] for a non-positive or non-finite radius, too few segments or
/// rings, or more than [`MAX_PRIMITIVE_TRIANGLES`] triangles.
pub fn uv_sphere(radius: f32, segments: u32, rings: u32) -> Result<TriMesh, MeshError> {
    positive("uv_sphere radius", radius)?;
    at_least("uv_sphere segments", segments, 3)?;
    at_least("uv_sphere rings", rings, 2)?;
    budget("uv_sphere", 2 * u128::from(segments) * u128::from(rings - 1))?;
    let (n, r) = (segments as usize, rings as usize);
    let mut positions = Vec::with_capacity(n * (r - 1) + 2);
    positions.push(Vec3::new(0.0, radius, 0.0));
    for k in 1..r {
        let theta = PI * k as f32 / r as f32;
        let (y, rho) = (radius * theta.cos(), radius * theta.sin());
        for s in 0..n {
            let phi = TAU * s as f32 / n as f32;
            positions.push(Vec3::new(rho * phi.cos(), y, -rho * phi.sin()));
        }
    }
    positions.push(Vec3::new(0.0, -radius, 0.0));
    let south = (positions.len() - 1) as u32;
    let at = |k: usize, s: usize| (1 + (k - 1) * n + s % n) as u32;
    let mut faces = Vec::with_capacity(2 * n * (r - 1));
    for s in 0..n {
        faces.push([0, at(1, s), at(1, s + 1)]);
        for k in 1..r - 1 {
            let (a, b, c, d) = (at(k, s), at(k + 1, s), at(k + 1, s + 1), at(k, s + 1));
            faces.extend([[a, b, c], [a, c, d]]);
        }
        faces.push([at(r - 1, s), south, at(r - 1, s + 1)]);
    }
    TriMesh::new(positions, faces)
}

/// A box of extents `size` (world units) centred at the origin, each face a grid of quads split
/// in two: `cells[axis]` cells along each axis, vertices on shared edges and corners welded.
///
/// It has 4·(cx·cy + cy·cz + cz·cx) triangles.
///
/// # Errors
/// [`MeshError::InvalidParameter`] for a non-positive or non-finite size, a zero cell count, or
/// more than [`MAX_PRIMITIVE_TRIANGLES`] triangles.
///
/// # Example
/// ```
/// use dentbend::glam::Vec3;
/// let cube = dentbend::mesh::subdivided_box(Vec3::ONE, [2, 2, 2]).unwrap();
/// assert_eq!((cube.face_count(), cube.vertex_count()), (48, 26));
/// ```
pub fn subdivided_box(size: Vec3, cells: [u32; 3]) -> Result<TriMesh, MeshError> {
    for (axis, name) in ["x", "y", "z"].iter().enumerate() {
        positive(&format!("box size along {name}"), size[axis])?;
        at_least(&format!("box cells along {name}"), cells[axis], 1)?;
    }
    let [cx, cy, cz] = cells.map(u128::from);
    budget("subdivided_box", 4 * (cx * cy + cy * cz + cz * cx))?;

    // Lattice coordinate i of n along an axis of length l: exact at both ends and mirror-exact.
    let coord = |i: u32, n: u32, l: f32| (2 * i64::from(i) - i64::from(n)) as f32 / (2 * n) as f32 * l;
    let mut ids: HashMap<[u32; 3], u32> = HashMap::new();
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    let mut vertex = |lattice: [u32; 3]| -> u32 {
        *ids.entry(lattice).or_insert_with(|| {
            positions.push(Vec3::from_array(std::array::from_fn(|a| coord(lattice[a], cells[a], size[a]))));
            (positions.len() - 1) as u32
        })
    };
    for axis in 0..3 {
        // (u, v, normal axis) is a right-handed frame, so (u, v) quads are CCW seen from +axis.
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        for side in [0, cells[axis]] {
            for i in 0..cells[u] {
                for j in 0..cells[v] {
                    let mut corner = |di: u32, dj: u32| {
                        let mut lattice = [0; 3];
                        lattice[axis] = side;
                        lattice[u] = i + di;
                        lattice[v] = j + dj;
                        vertex(lattice)
                    };
                    let (a, b, c, d) = (corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1));
                    if side == 0 {
                        faces.extend([[a, c, b], [a, d, c]]);
                    } else {
                        faces.extend([[a, b, c], [a, c, d]]);
                    }
                }
            }
        }
    }
    TriMesh::new(positions, faces)
}

/// A plank: a box `length` along x, `thickness` along y and `width` along z (world units),
/// centred at the origin, with `segments` cells along its length and about square cells on the
/// sides (at least one across each).
///
/// # Errors
/// As [`subdivided_box`], plus a zero `segments`.
pub fn plank(length: f32, width: f32, thickness: f32, segments: u32) -> Result<TriMesh, MeshError> {
    positive("plank length", length)?;
    positive("plank width", width)?;
    positive("plank thickness", thickness)?;
    at_least("plank segments", segments, 1)?;
    let cell = length / segments as f32;
    // Float-to-int `as` saturates, so absurd ratios end in the triangle budget check.
    let across = |extent: f32| ((extent / cell).round() as u32).max(1);
    subdivided_box(Vec3::new(length, thickness, width), [segments, across(thickness), across(width)])
}

/// A capped cylinder of `radius` and `height` (world units) about the y axis, centred at the
/// origin: `segments` around (≥ 3), `stacks` bands along the axis (≥ 1), and each cap made of
/// round(segments / 2π) (at least 1) concentric rings around a centre vertex.
///
/// # Errors
/// [`MeshError::InvalidParameter`] for a non-positive or non-finite size, too few segments or
/// stacks, or more than [`MAX_PRIMITIVE_TRIANGLES`] triangles.
pub fn cylinder(radius: f32, height: f32, segments: u32, stacks: u32) -> Result<TriMesh, MeshError> {
    positive("cylinder radius", radius)?;
    positive("cylinder height", height)?;
    at_least("cylinder segments", segments, 3)?;
    at_least("cylinder stacks", stacks, 1)?;
    let caps = ((segments as f32 / TAU).round() as u32).max(1);
    budget("cylinder", 2 * u128::from(segments) * (u128::from(stacks) + 2 * u128::from(caps)))?;
    let (n, m, c) = (segments as usize, stacks as usize, caps as usize);
    let around = |s: usize| {
        let phi = TAU * (s % n) as f32 / n as f32;
        (phi.cos(), -phi.sin())
    };
    let mut positions = Vec::new();
    // Side rings, bottom (k = 0) to top (k = m).
    for k in 0..=m {
        let y = height * (k as f32 / m as f32 - 0.5);
        positions.extend((0..n).map(|s| Vec3::new(radius * around(s).0, y, radius * around(s).1)));
    }
    let side = |k: usize, s: usize| (k * n + s % n) as u32;
    let mut faces = Vec::new();
    for k in 0..m {
        for s in 0..n {
            let (a, b, cc, d) = (side(k, s), side(k, s + 1), side(k + 1, s + 1), side(k + 1, s));
            faces.extend([[a, b, cc], [a, cc, d]]);
        }
    }
    for (top, y, outer_ring) in [(false, -0.5 * height, 0), (true, 0.5 * height, m)] {
        let centre = positions.len() as u32;
        positions.push(Vec3::new(0.0, y, 0.0));
        let first_inner = positions.len();
        for j in 1..c {
            let rho = radius * j as f32 / c as f32;
            positions.extend((0..n).map(|s| Vec3::new(rho * around(s).0, y, rho * around(s).1)));
        }
        // Ring j (0 = centre, c = the side's end ring), vertex s.
        let ring = |j: usize, s: usize| match j {
            0 => centre,
            j if j == c => side(outer_ring, s),
            j => (first_inner + (j - 1) * n + s % n) as u32,
        };
        let mut push = |tri: [u32; 3]| faces.push(if top { tri } else { [tri[0], tri[2], tri[1]] });
        for s in 0..n {
            push([centre, ring(1, s), ring(1, s + 1)]);
            for j in 1..c {
                let (a, b, cc, d) = (ring(j, s), ring(j + 1, s), ring(j + 1, s + 1), ring(j, s + 1));
                push([a, b, cc]);
                push([a, cc, d]);
            }
        }
    }
    TriMesh::new(positions, faces)
}
