//! Z-buffer profile of the projectile (paper §3.2, ARCHITECTURE.md §4). CPU twin of `shaders/zbuffer.wgsl`.
//!
//! Three passes, each one invocation per triangle (`for face in faces` here) in grid-index space,
//! where cell (row j, col i) is centred at the integer point (i, j); samples are max-merged
//! (`atomicMax` on the float bits on the GPU; heights are ≥ 0, whose bit patterns order like the
//! floats):
//!
//! 1. **Centres.** Every cell centre inside the closed triangle (barycentric test with a small
//!    tolerance, so centres on shared edges are never dropped) gets the interpolated height: an
//!    exact Z-buffer over all triangles, front- and back-facing alike, so non-convex shapes come
//!    out right. Where a centre ray meets the projectile, this is the profile.
//! 2. **Edges.** So that nothing narrower than a cell is lost (needles, fins, edge-on triangles
//!    whose projection is a segment), each edge is walked along its dominant axis with one sample
//!    per column (or row) line it crosses, in the cell nearest that point, plus the cell of its
//!    start vertex, into a second buffer. These samples only fill cells whose centre ray missed
//!    (combine pass): silhouettes widen by at most one cell and covered cells keep their exact
//!    centre value.
//! 3. **Tip.** The highest vertex (height d when `origin` sits at the tip's depth) always marks
//!    its cell, so the profile's peak is the tip's height wherever it falls between centres.
//!
//! Heights are `z = d + s`, s = depth along `axis_z` from `origin` (world units); triangles with
//! no point above `z = 0` are culled.

use glam::Vec3;

use super::ZbufferParams;

/// Barycentric tolerance of the centre test: centres up to this fraction of the triangle's
/// altitude outside an edge still count as inside, so centres on shared edges are never missed.
const INSIDE_EPS: f32 = 1e-5;

/// Triangles whose projected doubled area (cells²) is below this fraction of their longest
/// projected edge squared are treated as segments: the centre test is skipped (its barycentrics
/// would be noise) and the edge samples alone mark them.
const DEGENERATE_EPS: f32 = 1e-6;

/// Writes the projectile profile `P = max(0, d + max s)` of every cell, where
/// `s(p) = (p − grid.origin)·grid.axis_z ≤ 0` over the surface along the cell-centre ray.
/// `profile` is `res × res`, row-major.
pub fn zbuffer(params: &ZbufferParams, positions: &[Vec3], faces: &[[u32; 3]], profile: &mut [f32]) {
    profile.fill(0.0);
    let g = &params.grid;
    let d = params.dent_distance;
    let valid = g.res > 0 && g.cell_size > 0.0 && d > 0.0;
    if !valid {
        return;
    }
    let frame = Frame {
        origin: Vec3::from(g.origin),
        axis_x: Vec3::from(g.axis_x) / g.cell_size,
        axis_y: Vec3::from(g.axis_y) / g.cell_size,
        axis_z: Vec3::from(g.axis_z),
        shift: 0.5 * g.res as f32 - 0.5,
        d,
    };
    let (res, last) = (g.res as usize, g.res - 1);
    let count = (params.face_count as usize).min(faces.len());
    // Vertices in grid-index space, once (the shader transforms each triangle's corners itself).
    let grid_points: Vec<Vec3> = positions.iter().map(|&p| frame.to_grid(p)).collect();
    let triangles = || {
        faces[..count].iter().filter_map(|face| {
            let corners = face.map(|v| grid_points.get(v as usize).copied());
            let [Some(p0), Some(p1), Some(p2)] = corners else { return None };
            let v = [p0, p1, p2];
            // Cull: entirely at or below the cut plane z = 0 (NaN-safe), or not representable.
            let reaches = v[0].z.max(v[1].z).max(v[2].z) > 0.0;
            (reaches && v.iter().all(|p| p.is_finite())).then_some(v)
        })
    };

    let mut centres = Target { profile, res, last, d };
    triangles().for_each(|v| rasterize_centres(&mut centres, v));

    let mut edge_cells = vec![0.0; res * res];
    let mut edges = Target { profile: &mut edge_cells, res, last, d };
    for v in triangles() {
        for k in 0..3 {
            rasterize_edge(&mut edges, v[k], v[(k + 1) % 3]);
        }
    }
    for (cell, &edge) in centres.profile.iter_mut().zip(&edge_cells) {
        if *cell == 0.0 {
            *cell = edge;
        }
    }

    // The tip: the highest vertex height, compared exactly as computed (no tolerance needed).
    let tip = triangles().flat_map(|v| v.map(|c| c.z.min(d))).fold(0.0, f32::max);
    for v in triangles() {
        for corner in v.iter().filter(|c| c.z.min(d) >= tip) {
            if let (Some(row), Some(col)) = (centres.nearest(corner.y), centres.nearest(corner.x)) {
                centres.write(row, col, corner.z);
            }
        }
    }
}

/// World → grid-index space.
struct Frame {
    /// Grid centre at tip depth, world units.
    origin: Vec3,
    /// `axis_x / h`, 1/world unit.
    axis_x: Vec3,
    /// `axis_y / h`, 1/world unit.
    axis_y: Vec3,
    /// Unit depth direction.
    axis_z: Vec3,
    /// `res/2 − ½`: grid index of the grid centre line.
    shift: f32,
    /// Dent distance, world units.
    d: f32,
}

impl Frame {
    /// `(column, row, height)`: cell centres at integer column and row; height `d + s`, world
    /// units.
    fn to_grid(&self, p: Vec3) -> Vec3 {
        let r = p - self.origin;
        Vec3::new(r.dot(self.axis_x) + self.shift, r.dot(self.axis_y) + self.shift, r.dot(self.axis_z) + self.d)
    }
}

/// The profile being written.
struct Target<'a> {
    /// Heights, world units, row-major.
    profile: &'a mut [f32],
    /// Cells per side.
    res: usize,
    /// `res − 1`: the last valid column and row index.
    last: u32,
    /// Dent distance, world units: the cap on heights.
    d: f32,
}

impl Target<'_> {
    /// Max-merges height `z` (world units) into cell (`row`, `col`), both in `0..=last`;
    /// heights not above 0 (or NaN) are ignored and heights are capped at d.
    fn write(&mut self, row: u32, col: u32, z: f32) {
        let index = row as usize * self.res + col as usize;
        if z > 0.0
            && let Some(cell) = self.profile.get_mut(index)
        {
            *cell = cell.max(z.min(self.d));
        }
    }

    /// Index of the cell whose span `[i − ½, i + ½)` holds grid coordinate `x`, if on the grid.
    fn nearest(&self, x: f32) -> Option<u32> {
        // x + ½ > 0, so truncation is floor; `min` guards the rounding of x + ½ up to res.
        (x >= -0.5 && x < self.last as f32 + 0.5).then(|| ((x + 0.5) as u32).min(self.last))
    }

    /// The grid indices i with `lo ≤ i ≤ hi`, as an inclusive range, if any.
    fn span(&self, lo: f32, hi: f32) -> Option<(u32, u32)> {
        // `max` and `min` also turn NaN into the grid's bounds.
        let (lo, hi) = (lo.max(0.0), hi.min(self.last as f32));
        if lo > hi {
            return None;
        }
        // ceil and floor of non-negative values, by truncation.
        let first = lo as u32 + u32::from(((lo as u32) as f32) < lo);
        let end = hi as u32;
        (first <= end).then_some((first, end))
    }
}

/// Centre samples of one triangle (grid-index space): every centre inside the closed triangle
/// gets the height interpolated there.
fn rasterize_centres(target: &mut Target, v: [Vec3; 3]) {
    // Barycentric coordinate of vertex k: w_k = e_k(p) / area2, with the edge function
    // e_k(p) = (b − a) × (p − a) of the opposite edge a = v[k+1] → b = v[k+2]. It is linear in
    // p: stepped from the first cell of the clipped bounding box.
    let area2 = (v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[1].y - v[0].y) * (v[2].x - v[0].x);
    let longest2 = (0..3).map(|k| (v[(k + 1) % 3] - v[k]).truncate().length_squared()).fold(0.0, f32::max);
    let solid = area2.abs() > DEGENERATE_EPS * longest2;
    if !solid {
        return;
    }
    let (lo, hi) = (v[0].min(v[1]).min(v[2]), v[0].max(v[1]).max(v[2]));
    let (Some((col_first, col_end)), Some((row_first, row_end))) = (target.span(lo.x, hi.x), target.span(lo.y, hi.y))
    else {
        return;
    };
    let inv_area2 = 1.0 / area2;
    let (x0, y0) = (col_first as f32, row_first as f32);
    let mut w0 = [0.0; 3];
    let (mut dw_dx, mut dw_dy) = ([0.0; 3], [0.0; 3]);
    for k in 0..3 {
        let (a, b) = (v[(k + 1) % 3], v[(k + 2) % 3]);
        w0[k] = ((b.x - a.x) * (y0 - a.y) - (b.y - a.y) * (x0 - a.x)) * inv_area2;
        dw_dx[k] = -(b.y - a.y) * inv_area2;
        dw_dy[k] = (b.x - a.x) * inv_area2;
    }
    for row in row_first..=row_end {
        let dy = (row - row_first) as f32;
        let w_row = [0, 1, 2].map(|k| w0[k] + dy * dw_dy[k]);
        let mut entered = false;
        for col in col_first..=col_end {
            let dx = (col - col_first) as f32;
            let w = [0, 1, 2].map(|k| w_row[k] + dx * dw_dx[k]);
            if w[0] >= -INSIDE_EPS && w[1] >= -INSIDE_EPS && w[2] >= -INSIDE_EPS {
                let z = (w[0] * v[0].z + w[1] * v[1].z + w[2] * v[2].z).clamp(lo.z, hi.z);
                target.write(row, col, z);
                entered = true;
            } else if entered {
                break; // the covered columns of a row are contiguous
            }
        }
    }
}

/// Edge samples of segment `a → b` (grid-index space): the cell of `a`, then one sample per
/// column line (or row line, whichever axis the segment spans more of) it crosses, in the cell
/// nearest that crossing, with the segment's height there.
fn rasterize_edge(target: &mut Target, a: Vec3, b: Vec3) {
    if let (Some(row), Some(col)) = (target.nearest(a.y), target.nearest(a.x)) {
        target.write(row, col, a.z);
    }
    // Walk along the dominant axis u; w is the other grid coordinate.
    let along_x = (b.x - a.x).abs() >= (b.y - a.y).abs();
    let (ua, wa, ub, wb) = if along_x { (a.x, a.y, b.x, b.y) } else { (a.y, a.x, b.y, b.x) };
    let du = ub - ua;
    if du == 0.0 {
        return; // a point, or parallel to axis_z: the vertex samples cover it
    }
    let Some((first, end)) = target.span(ua.min(ub), ua.max(ub)) else { return };
    let inv_du = 1.0 / du;
    for u in first..=end {
        let t = ((u as f32 - ua) * inv_du).clamp(0.0, 1.0);
        if let Some(w) = target.nearest(wa + t * (wb - wa)) {
            let (row, col) = if along_x { (w, u) } else { (u, w) };
            target.write(row, col, a.z + t * (b.z - a.z));
        }
    }
}
