//! The two scans behind [`LevelSet::build`](super::LevelSet::build): the winding number of every
//! cell centre along x-parallel rows, and the narrow-band distance to the nearest triangle.

use glam::{UVec3, Vec2, Vec3};
use rayon::prelude::*;

use super::BendError;
use super::geometry::triangle_dist2;
use crate::mesh::TriMesh;

/// Triangles per parallel work item.
const CHUNK: usize = 512;

/// Winding number of the mesh at every cell centre (index `i + nx·(j + ny·k)`): rays run along +x
/// through each row of centres, and every triangle the ray crosses adds −sign(nₓ) to the cells
/// past the crossing.
///
/// A row that passes exactly through an edge or a vertex in the (y, z) projection is decided as
/// if nudged by an infinitesimal fixed offset: each projected edge is oriented canonically (y
/// increasing, then z) and its edge function is computed from that orientation only, so the two
/// triangles sharing an edge see the same number and exactly one of them claims the row (or both
/// or neither, at a silhouette, which cancels). Triangles with zero projected area are skipped.
///
/// Along every row of a closed mesh the winding returns to zero past the last crossing; a row
/// where it does not passes through a hole.
///
/// # Errors
/// [`BendError::OpenMesh`] with the number of such rows.
pub(crate) fn row_winding(mesh: &TriMesh, origin: Vec3, cell: f32, dims: [usize; 3]) -> Result<Vec<i32>, BendError> {
    let [nx, ny, nz] = dims;
    let positions = mesh.positions();
    let chunks: Vec<Vec<(u32, u32, i32)>> = mesh
        .faces()
        .par_chunks(CHUNK)
        .map(|faces| {
            let mut out = Vec::new();
            for f in faces {
                let corners = f.map(|v| positions[v as usize] - origin);
                crossings(corners, cell, [nx, ny, nz], &mut out);
            }
            out
        })
        .collect();
    let row_len = nx + 1;
    let mut delta = vec![0i32; row_len * ny * nz];
    for &(row, i0, d) in chunks.iter().flatten() {
        delta[row as usize * row_len + i0 as usize] += d;
    }
    let mut winding = vec![0i32; nx * ny * nz];
    let open_rows = winding
        .par_chunks_mut(nx)
        .zip(delta.par_chunks(row_len))
        .map(|(row, d)| {
            let mut w = 0;
            for (cell, &step) in row.iter_mut().zip(d.iter()) {
                w += step;
                *cell = w;
            }
            w + d[nx] != 0
        })
        .filter(|&open| open)
        .count();
    if open_rows > 0 {
        return Err(BendError::OpenMesh { open_rows });
    }
    Ok(winding)
}

/// Pushes `(row, first cell past the crossing, winding step)` for every row centre the triangle
/// (corners relative to the grid origin) covers in the (y, z) projection.
fn crossings(corners: [Vec3; 3], cell: f32, [nx, ny, nz]: [usize; 3], out: &mut Vec<(u32, u32, i32)>) {
    let p = corners.map(|c| Vec2::new(c.y, c.z));
    let area = cross2(p[1] - p[0], p[2] - p[0]);
    if area == 0.0 || !area.is_finite() {
        return;
    }
    let s = area.signum();
    // Per winding edge (u → v, opposite corner w): canonical start/end and its orientation sign.
    let edges = [(0, 1, 2), (1, 2, 0), (2, 0, 1)].map(|(u, v, w)| {
        let d = p[v] - p[u];
        let forward = d.x > 0.0 || (d.x == 0.0 && d.y > 0.0);
        let (start, end) = if forward { (p[u], p[v]) } else { (p[v], p[u]) };
        (start, end - start, if forward { s } else { -s }, w)
    });
    let lo = p[0].min(p[1]).min(p[2]) / cell - 0.5;
    let hi = p[0].max(p[1]).max(p[2]) / cell - 0.5;
    let (j0, j1) = (lo.x.ceil().max(0.0) as usize, (hi.x.floor().min(ny as f32 - 1.0)).max(-1.0));
    let (k0, k1) = (lo.y.ceil().max(0.0) as usize, (hi.y.floor().min(nz as f32 - 1.0)).max(-1.0));
    if j1 < 0.0 || k1 < 0.0 {
        return;
    }
    for k in k0..=k1 as usize {
        for j in j0..=j1 as usize {
            let q = (Vec2::new(j as f32, k as f32) + 0.5) * cell;
            let mut bary = [0.0f32; 3];
            let mut inside = true;
            for &(start, dir, sign, opposite) in &edges {
                let e = cross2(dir, q - start);
                // A zero edge function counts as positive in the canonical orientation.
                let claims = if e == 0.0 { sign > 0.0 } else { sign * e > 0.0 };
                if !claims {
                    inside = false;
                    break;
                }
                bary[opposite] = (sign * e).max(0.0);
            }
            let total = bary[0] + bary[1] + bary[2];
            if !inside || total <= 0.0 {
                continue;
            }
            let x = (bary[0] * corners[0].x + bary[1] * corners[1].x + bary[2] * corners[2].x) / total;
            let i0 = ((x / cell - 0.5).floor() + 1.0).clamp(0.0, nx as f32) as u32;
            out.push(((j + ny * k) as u32, i0, -(s as i32)));
        }
    }
}

fn cross2(a: Vec2, b: Vec2) -> f32 {
    a.x * b.y - a.y * b.x
}

/// Cells along z per parallel slab of [`narrow_band`].
const SLAB: usize = 2;

/// A triangle as [`narrow_band`] visits it: corners relative to the grid origin, its plane, its
/// bounding sphere grown by the band, and the cells of its grown bounding box.
#[derive(Debug, Clone, Copy)]
struct Patch {
    corners: [Vec3; 3],
    normal: Vec3,
    offset: f32,
    centre: Vec3,
    reach2: f32,
    lo: UVec3,
    hi: UVec3,
}

/// ⌈x⌉ for x ≥ 0 without a libm call (0 for negative x).
fn ceil_pos(x: f32) -> u32 {
    let t = x.max(0.0) as u32;
    t + u32::from((t as f32) < x)
}

/// Distance from every cell centre within `band` (m) of a triangle to its nearest triangle, and
/// that triangle's index (the lower one on ties); `band` and `u32::MAX` elsewhere.
///
/// The grid is cut into slabs of [`SLAB`] cell layers along z, one parallel task each; a slab
/// visits the triangles whose bounding box grown by `band` reaches it, and each of those the
/// cells of that box in the slab within `band` of its bounding sphere, skipping cells whose
/// distance to the triangle's plane already exceeds the best distance found.
pub(crate) fn narrow_band(
    mesh: &TriMesh,
    origin: Vec3,
    cell: f32,
    dims: [usize; 3],
    band: f32,
) -> (Vec<f32>, Vec<u32>) {
    let [nx, ny, nz] = dims;
    let positions = mesh.positions();
    let limit = UVec3::new(nx as u32, ny as u32, nz as u32) - 1;
    // Corners are at least BORDER_CELLS − band cells from the grid's sides, so every box bound
    // below is non-negative before clamping.
    let patches: Vec<Option<Patch>> = mesh
        .faces()
        .par_iter()
        .map(|f| {
            let corners = f.map(|v| positions[v as usize] - origin);
            let [a, b, c] = corners;
            let lo_f = (a.min(b).min(c) - band) / cell - 0.5;
            let hi_f = (a.max(b).max(c) + band) / cell - 0.5;
            let lo = UVec3::new(ceil_pos(lo_f.x), ceil_pos(lo_f.y), ceil_pos(lo_f.z));
            let hi = hi_f.max(Vec3::ZERO).as_uvec3().min(limit);
            if hi_f.min_element() < 0.0 || hi.cmplt(lo).any() {
                return None;
            }
            let normal = (b - a).cross(c - a).normalize_or_zero();
            let centre = (a + b + c) / 3.0;
            let reach = a.distance(centre).max(b.distance(centre)).max(c.distance(centre)) + band;
            Some(Patch { corners, normal, offset: normal.dot(a), centre, reach2: reach * reach, lo, hi })
        })
        .collect();
    let slabs = nz.div_ceil(SLAB);
    let mut members: Vec<Vec<u32>> = vec![Vec::new(); slabs];
    for (t, patch) in patches.iter().enumerate() {
        if let Some(p) = patch {
            for list in &mut members[p.lo.z as usize / SLAB..=p.hi.z as usize / SLAB] {
                list.push(t as u32);
            }
        }
    }
    let layer = nx * ny;
    // Squared distances; cells no triangle comes within `band` of keep band² (and no triangle).
    let mut distance = vec![band * band; layer * nz];
    let mut nearest = vec![u32::MAX; layer * nz];
    distance.par_chunks_mut(layer * SLAB).zip(nearest.par_chunks_mut(layer * SLAB)).zip(&members).enumerate().for_each(
        |(slab, ((dist, near), triangles))| {
            let k_start = slab * SLAB;
            let k_end = k_start + dist.len() / layer;
            for &t in triangles {
                let Some(p) = &patches[t as usize] else { continue };
                let [a, b, c] = p.corners;
                for k in (p.lo.z as usize).max(k_start)..=(p.hi.z as usize).min(k_end - 1) {
                    let z = (k as f32 + 0.5) * cell;
                    for j in p.lo.y as usize..=p.hi.y as usize {
                        let y = (j as f32 + 0.5) * cell;
                        // The row's cells inside the triangle's reach sphere.
                        let rest = p.reach2 - (y - p.centre.y).powi(2) - (z - p.centre.z).powi(2);
                        if rest < 0.0 {
                            continue;
                        }
                        let half = rest.sqrt();
                        let i0 = ceil_pos((p.centre.x - half) / cell - 0.5).max(p.lo.x);
                        let i1_f = (p.centre.x + half) / cell - 0.5;
                        if i1_f < i0 as f32 {
                            continue;
                        }
                        let i1 = (i1_f as u32).min(p.hi.x);
                        let row = (k - k_start) * layer + j * nx;
                        let base = p.normal.y * y + p.normal.z * z - p.offset;
                        for i in i0 as usize..=i1 as usize {
                            let x = (i as f32 + 0.5) * cell;
                            let plane = p.normal.x * x + base;
                            let slot = row + i;
                            // The plane distance bounds the triangle distance from below.
                            if plane * plane >= dist[slot] {
                                continue;
                            }
                            let d2 = triangle_dist2(Vec3::new(x, y, z), a, b, c);
                            if d2 < dist[slot] {
                                dist[slot] = d2;
                                near[slot] = t;
                            }
                        }
                    }
                }
            }
        },
    );
    distance.par_iter_mut().for_each(|d| *d = d.sqrt());
    (distance, nearest)
}
