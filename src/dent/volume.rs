//! Stage 3 of a dent: measure the volume the displacement changed and, when asked, put it back
//! with a raised rim around the crater (ARCHITECTURE.md §2).
//!
//! Only the triangles with a moved corner change the enclosed volume, so the change is summed
//! over those alone (signed tetrahedra against the impact point, f64). To restore it, a ring of
//! vertices around the crater moves out along its vertex normals by `s·w_i`: `w_i` is largest
//! just outside the crater and fades to zero at twice its extent (an ellipse that follows a
//! glancing crater's length), and `s` solves
//! `ΔV(s) = 0` exactly (`ΔV` is a cubic in `s`: each triangle's tetrahedron is).

use glam::{DVec3, Vec3, Vec3A};

use super::map::PendingDisplacement;
use super::{DentMap, VolumeMode};
use crate::mesh::face_grid::Aabb;
use crate::mesh::face_sort::{FaceSort, MARK_A, MARK_B, out_code};
use crate::mesh::in_coordinate_range;
use crate::mesh::weld::position_key;

/// Width of the rim past the crater's edge, in crater half-extents (on each of the map's axes).
const RIM_WIDTH: f64 = 1.0;
/// Vertices displaced by at least this fraction of the largest displacement form the crater
/// whose radius sets the rim's.
const CRATER_FRACTION: f32 = 0.1;
/// Largest rim push tried, in crater radii: a cavity no rim that high can refill is left alone
/// (with a warning) rather than grown into a spike.
const MAX_PUSH_RADII: f64 = 4.0;

/// Measures the volume change `pending` makes to a mesh of `faces` whose positions were
/// `before`, and under [`VolumeMode::Preserve`] pushes a rim around `map`'s crater out along
/// `normals` (the mesh's vertex normals before the dent) until it is undone. Writes the result
/// into `pending.report`; returns how to put `pending` back as it was and, when `sort_for_guard`,
/// the faces sorted on the way for the intersection guard (marked: those with a corner the dent
/// or the rim may move; region: around the moved vertices and the rim, see
/// `guard_pairs::pairs_to_test`).
///
/// # Errors
/// [`DentError::NonFiniteResult`](super::DentError::NonFiniteResult) when the rim would leave
/// the coordinate range; `pending` is unchanged then.
pub(crate) fn restore_volume(
    faces: &[[u32; 3]],
    normals: &[Vec3],
    before: &[Vec3],
    pending: &mut PendingDisplacement,
    map: &DentMap,
    mode: VolumeMode,
    sort_for_guard: bool,
) -> Result<(RimUndo, Option<FaceSort>), super::DentError> {
    let mut undo = RimUndo { vertices: Vec::new(), report: pending.report.clone() };
    let origin = map.grid.origin.as_dvec3();
    let tetra = |p: &[Vec3], f: &[u32; 3]| {
        let [a, b, c] = f.map(|v| p[v as usize].as_dvec3() - origin);
        a.dot(b.cross(c)) / 6.0
    };
    let moved: Vec<u32> = (0..before.len() as u32).filter(|&v| pending.moved[v as usize]).collect();
    let rim = match mode {
        VolumeMode::Preserve => rim_weights(normals, before, pending, &moved, map),
        VolumeMode::Free => None,
    };
    // One pass over the faces: those with a moved corner (mark A) changed the volume, those with
    // a rim corner (mark B) will; sorted for the guard on the way when asked. Each vertex's
    // place in `rim`, or NONE.
    const NONE: u32 = u32::MAX;
    let mut codes: Vec<u8> = pending.moved.iter().map(|&m| if m { MARK_A } else { 0 }).collect();
    let mut slot = vec![NONE; if rim.is_some() { before.len() } else { 0 }];
    if let Some((rim, _)) = &rim {
        for (k, &(v, _)) in rim.iter().enumerate() {
            slot[v as usize] = k as u32;
            codes[v as usize] |= MARK_B;
        }
    }
    let region =
        sort_for_guard.then(|| guard_region(before, &pending.positions, &moved, rim.as_ref().map(|r| &r.0[..])));
    if let Some(region) = &region {
        codes.iter_mut().zip(before).for_each(|(c, &p)| *c |= out_code(p, region));
    }
    let sort = FaceSort::new(faces, &codes, region);
    let (mut dug, mut rim_faces) = (0.0, Vec::new());
    for f in sort.marked.iter().map(|&f| &faces[f as usize]) {
        let code = f.iter().fold(0, |c, &v| c | codes[v as usize]);
        if code & MARK_A != 0 {
            dug += tetra(&pending.positions, f) - tetra(before, f);
        }
        if code & MARK_B != 0 {
            rim_faces.push(f);
        }
    }
    let sorted = region.is_some().then_some(sort);
    pending.report.cavity_volume = dug.abs();
    pending.report.volume_change = dug;
    if mode == VolumeMode::Free || dug == 0.0 {
        return Ok((undo, sorted));
    }
    let Some((rim, crater)) = rim else {
        warn(pending, "no surface around the dent to raise a rim on: its volume is not restored");
        return Ok((undo, sorted));
    };
    let push = |v: u32| match slot[v as usize] {
        NONE => DVec3::ZERO,
        k => rim[k as usize].1,
    };
    // The rim faces' volume now, and the cubic's other coefficients.
    let [before_rim, k1, k2, k3] = rim_faces.iter().fold([0.0; 4], |mut k, f| {
        let [a, b, c] = f.map(|v| pending.positions[v as usize].as_dvec3() - origin);
        let [ua, ub, uc] = f.map(push);
        k[0] += a.dot(b.cross(c)) / 6.0;
        k[1] += (ua.dot(b.cross(c)) + a.dot(ub.cross(c)) + a.dot(b.cross(uc))) / 6.0;
        k[2] += (ua.dot(ub.cross(c)) + ua.dot(b.cross(uc)) + a.dot(ub.cross(uc))) / 6.0;
        k[3] += ua.dot(ub.cross(uc)) / 6.0;
        k
    });
    let cubic = [dug, k1, k2, k3];
    let heaviest = rim.iter().map(|(_, u)| u.length()).fold(0.0, f64::max);
    let Some(s) = root_toward(cubic, MAX_PUSH_RADII * crater / heaviest) else {
        warn(pending, "no rim up to 4 crater radii high refills this dent: its volume is not restored");
        return Ok((undo, sorted));
    };

    let old: Vec<Vec3> = rim.iter().map(|&(v, _)| pending.positions[v as usize]).collect();
    for &(v, u) in &rim {
        let p = (pending.positions[v as usize].as_dvec3() + s * u).as_vec3();
        if !in_coordinate_range(p) {
            rim.iter().zip(&old).for_each(|(&(w, _), &q)| pending.positions[w as usize] = q);
            return Err(super::DentError::NonFiniteResult { index: v as usize });
        }
        pending.positions[v as usize] = p;
    }
    let after_rim: f64 = rim_faces.iter().map(|f| tetra(&pending.positions, f)).sum();
    pending.report.volume_change = dug + (after_rim - before_rim);
    for (&(v, _), &q) in rim.iter().zip(&old) {
        let i = v as usize;
        if pending.positions[i] != q {
            undo.vertices.push((v, q, pending.moved[i]));
            pending.report.moved_vertices += usize::from(!pending.moved[i]);
            pending.moved[i] = true;
            let length = pending.positions[i].distance(before[i]);
            pending.report.max_displacement = pending.report.max_displacement.max(length);
        }
    }
    Ok((undo, sorted))
}

/// Where the guard should sort the faces around: the box of the moved vertices (before and
/// after) and of the rim's vertices (before), widened by a twentieth of its size on every side
/// so that it also holds the rim once raised (a rim higher than that only costs the guard a
/// pass of its own).
fn guard_region(before: &[Vec3], after: &[Vec3], moved: &[u32], rim: Option<&[(u32, DVec3)]>) -> Aabb {
    let dent = moved.iter().map(|&v| v as usize).flat_map(|v| [before[v], after[v]]);
    let raised = rim.unwrap_or_default().iter().map(|&(v, _)| before[v as usize]);
    let region = Aabb::of(dent.chain(raised));
    let widen = Vec3::splat(0.05 * (region.max - region.min).max_element().max(0.0));
    Aabb { min: region.min - widen, max: region.max + widen }
}

/// What [`restore_volume`] changed in a dent: the vertices its rim moved (with their positions
/// and moved flags before) and the report before it, so the dent can be put back as it was.
pub(crate) struct RimUndo {
    vertices: Vec<(u32, Vec3, bool)>,
    report: super::DisplaceReport,
}

impl RimUndo {
    /// Puts `pending` back as it was before [`restore_volume`].
    pub(crate) fn undo(self, pending: &mut PendingDisplacement) {
        for (v, position, moved) in self.vertices {
            pending.positions[v as usize] = position;
            pending.moved[v as usize] = moved;
        }
        pending.report = self.report;
    }
}

/// The rim: each vertex that may move and its push per unit `s` (weight × unit normal; `s` is
/// in world units), with the crater's longest half-extent `R` (its radius when round; the rim's
/// height limit counts in it); `None` when no vertex qualifies.
///
/// The crater (the vertices displaced by at least [`CRATER_FRACTION`] of the deepest) spans
/// `±a` and `±b` along the map's two axes on the collision plane (each at least a cell); the
/// ellipse with those half-axes, grown until it holds every crater vertex, is its outline:
/// long along the slide of a glancing hit, close to round under a head-on one (a circle when the
/// crater reaches equally far along both axes). A vertex at
/// `(x, y)` on those axes and depth `z` along the denting normal gets
/// `w = (1 − (ρ/ρ_out)²)² · (1 − (z/R)²)² · (1 − δ/δ_max)` with `ρ = √((x/a)² + (y/b)²)`,
/// `ρ_out = 1 + RIM_WIDTH`, `R = max(a, b)` and `δ` the vertex's dent displacement: the rim
/// follows the crater's outline at a width proportional to its extent on each axis, and the
/// last factor keeps the crater itself down, so the weight peaks on its lip.
fn rim_weights(
    normals: &[Vec3],
    before: &[Vec3],
    pending: &PendingDisplacement,
    moved: &[u32],
    map: &DentMap,
) -> Option<(Vec<(u32, DVec3)>, f64)> {
    let centre = map.grid.origin;
    let axes = [map.grid.axis_x, map.grid.axis_y, map.grid.axis_z].map(Vec3::as_dvec3);
    let offsets = |p: Vec3| {
        let r = (p - centre).as_dvec3();
        axes.map(|a| r.dot(a))
    };
    let shift = |v: u32| pending.positions[v as usize].distance(before[v as usize]);
    let deepest = moved.iter().map(|&v| shift(v)).fold(0.0, f32::max);
    let cell = f64::from(map.grid.cell_size);
    let crater_offsets: Vec<[f64; 3]> = moved
        .iter()
        .filter(|&&v| shift(v) >= CRATER_FRACTION * deepest)
        .map(|&v| offsets(before[v as usize]))
        .collect();
    let (half_x, half_y) =
        crater_offsets.iter().fold((cell, cell), |(a, b), [x, y, _]| (a.max(x.abs()), b.max(y.abs())));
    // Grown to hold every crater vertex (a round crater gets the circle through its farthest).
    let grow =
        crater_offsets.iter().map(|[x, y, _]| ((x / half_x).powi(2) + (y / half_y).powi(2)).sqrt()).fold(1.0, f64::max);
    let (half_x, half_y) = (half_x * grow, half_y * grow);
    let crater = half_x.max(half_y);
    let outer = 1.0 + RIM_WIDTH;
    // A cheap f32 test first: the rim lies within the ball of radius √((outer·R)² + R²).
    let reach = (crater * (outer * outer + 1.0).sqrt() * 1.001) as f32;
    let bump = |x: f64| (1.0 - x * x).max(0.0).powi(2);
    let centre_lanes = Vec3A::from(centre);
    let mut lifted: Vec<(u32, f64, Option<DVec3>)> = (0..before.len() as u32)
        .zip(before)
        .filter(|(_, p)| Vec3A::from(**p).distance_squared(centre_lanes) < reach * reach)
        .filter_map(|(v, _)| {
            let [x, y, z] = offsets(before[v as usize]);
            let rho = ((x / half_x).powi(2) + (y / half_y).powi(2)).sqrt();
            if rho >= outer || z.abs() >= crater {
                return None;
            }
            let lip = 1.0 - f64::from(shift(v) / deepest.max(f32::MIN_POSITIVE)).min(1.0);
            let w = bump(rho / outer) * bump(z / crater) * lip;
            let n = normals.get(v as usize).and_then(|n| n.as_dvec3().try_normalize());
            (w > 0.0).then_some((v, w, n))
        })
        .collect();
    share_normals_at_seams(&mut lifted, before);
    let rim: Vec<(u32, DVec3)> = lifted.into_iter().filter_map(|(v, w, n)| Some((v, w * n?))).collect();
    (!rim.is_empty()).then_some((rim, crater))
}

/// Gives the rim's vertices that share a position (the sides of a hard edge or a UV seam, each
/// with the normal of its own faces) one normal, the normalised mean of theirs, so they rise
/// together and the seam stays closed; their weights already agree (they depend on the position
/// and the dent's displacement there only). A group whose mean vanishes does not rise.
fn share_normals_at_seams(lifted: &mut [(u32, f64, Option<DVec3>)], before: &[Vec3]) {
    let key = |v: u32| position_key(before[v as usize]);
    lifted.sort_unstable_by_key(|&(v, _, _)| (key(v), v));
    for group in lifted.chunk_by_mut(|a, b| key(a.0) == key(b.0)).filter(|g| g.len() > 1) {
        let mean = group.iter().filter_map(|(_, _, n)| *n).sum::<DVec3>().try_normalize();
        group.iter_mut().for_each(|(_, _, n)| *n = mean);
    }
    lifted.sort_unstable_by_key(|&(v, _, _)| v);
}

/// The root of `k₀ + k₁s + k₂s² + k₃s³` nearest zero on the side where the cubic starts toward
/// zero (the sign of `−k₀/k₁`), with `|s| ≤ limit`; `None` if it has none there.
fn root_toward(k: [f64; 4], limit: f64) -> Option<f64> {
    let f = |s: f64| k[0] + s * (k[1] + s * (k[2] + s * k[3]));
    if k[1] == 0.0 || !limit.is_finite() {
        return None;
    }
    let direction = -(k[0] / k[1]).signum();
    // Walk out from 0 until the sign flips; steps of a sixteenth of the linear guess, doubling,
    // catch the nearest root of a cubic whose curvature bends it back before that guess.
    let (mut lo, mut hi) = (0.0, (k[0] / k[1]).abs().min(limit) / 16.0);
    while f(direction * hi).signum() == f(0.0).signum() {
        if hi >= limit {
            return None;
        }
        (lo, hi) = (hi, (2.0 * hi).min(limit));
    }
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if f(direction * mid).signum() == f(0.0).signum() {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(direction * hi)
}

fn warn(pending: &mut PendingDisplacement, message: &str) {
    log::warn!("{message}");
    pending.report.warnings.push(message.to_owned());
}

/// Enclosed volume of a mesh of `faces` at `after` minus at `before`, cubic world units, summed
/// over the faces with a `moved` corner (the others change nothing), in f64.
pub(crate) fn volume_change(faces: &[[u32; 3]], before: &[Vec3], after: &[Vec3], moved: &[bool]) -> f64 {
    let origin = faces.first().map_or(DVec3::ZERO, |f| before[f[0] as usize].as_dvec3());
    let tetra = |p: &[Vec3], f: &[u32; 3]| {
        let [a, b, c] = f.map(|v| p[v as usize].as_dvec3() - origin);
        a.dot(b.cross(c)) / 6.0
    };
    faces.iter().filter(|f| f.iter().any(|&v| moved[v as usize])).map(|f| tetra(after, f) - tetra(before, f)).sum()
}

#[cfg(test)]
mod tests {
    use super::root_toward;

    /// The nearest root on the side the line points to: x³ − 6x² + 11x − 6 = (x−1)(x−2)(x−3)
    /// seen from 0 has its nearest root at 1; a cubic with no root within the limit has none.
    #[test]
    fn finds_the_nearest_root() {
        let s = root_toward([-6.0, 11.0, -6.0, 1.0], 10.0).unwrap();
        assert!((s - 1.0).abs() < 1e-12, "{s}");
        let s = root_toward([6.0, 11.0, 6.0, 1.0], 10.0).unwrap(); // (x+1)(x+2)(x+3)
        assert!((s + 1.0).abs() < 1e-12, "{s}");
        assert_eq!(root_toward([1.0, -1.0, 0.0, 0.0], 0.5), None);
        assert_eq!(root_toward([1.0, 0.0, 1.0, 0.0], 5.0), None);
    }
}
