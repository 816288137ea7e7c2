//! Vertices that share a position. Game meshes split a vertex wherever an attribute is
//! discontinuous (a hard edge's two normals, a UV seam, a material boundary), so one point of the
//! surface is several vertices there, each with the faces of its own side. Every stage that
//! reasons about the surface (refinement, the volume rim) treats such vertices as one point and
//! moves them identically, so a closed asset stays closed.
//!
//! Positions are compared bit for bit (with −0 equal to +0): a seam whose vertices merely lie
//! close is found by [`near_miss`] and refused by the dent stages, since no stage could keep
//! its sides together.

use std::collections::HashMap;

use glam::{DVec3, Vec3};

use super::{MeshError, TriMesh};

/// A position's key: its bits, with −0 taken as +0.
pub(crate) fn position_key(p: Vec3) -> [u32; 3] {
    // Adding +0 turns −0 into +0 and leaves every other value as it is.
    (p + Vec3::ZERO).to_array().map(f32::to_bits)
}

/// The smallest-index vertex of every group of vertices that share a position.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Weld {
    /// `canonical[v]`: the first vertex at `v`'s position (`v` itself when it is alone).
    canonical: Vec<u32>,
}

impl Weld {
    /// The groups of `positions`; `None` when no two vertices share a position (most meshes
    /// built for simulation: then every vertex is its own point).
    pub(crate) fn of(positions: &[Vec3]) -> Option<Self> {
        let mut first: HashMap<[u32; 3], u32> = HashMap::with_capacity(positions.len());
        let mut canonical: Vec<u32> = Vec::with_capacity(positions.len());
        let mut shared = false;
        for (v, &p) in positions.iter().enumerate() {
            let c = *first.entry(position_key(p)).or_insert(v as u32);
            shared |= c != v as u32;
            canonical.push(c);
        }
        shared.then_some(Self { canonical })
    }

    /// The group of vertex `v` (its first vertex); a vertex past the ones known is its own.
    pub(crate) fn canonical(&self, v: u32) -> u32 {
        self.canonical.get(v as usize).copied().unwrap_or(v)
    }

    /// Records vertex `v` (the next index) as a member of the group of `group`.
    pub(crate) fn push(&mut self, group: u32) {
        self.canonical.push(group);
    }

    /// Forgets the vertices from `len` on.
    pub(crate) fn truncate(&mut self, len: usize) {
        self.canonical.truncate(len);
    }
}

/// Two of the vertices `candidates` of `positions` that lie within `tolerance` (world units, > 0)
/// of each other without sharing a position, and that `joined` does not call joined (an edge
/// between them keeps them together), and their distance; `None` when there are none.
///
/// The candidates are sorted by their projection on a fixed direction no mesh is aligned with,
/// and each is compared with those whose projection lies within `tolerance` of its own (a pair
/// that close projects that close): a handful of comparisons per vertex, unless many vertices
/// project alike, when a hash grid of cell `tolerance` takes over.
pub(crate) fn near_miss(
    positions: &[Vec3],
    candidates: &[u32],
    tolerance: f32,
    joined: &dyn Fn(u32, u32) -> bool,
) -> Option<(u32, u32, f32)> {
    if !(tolerance.is_finite() && tolerance > 0.0) || candidates.len() < 2 {
        return None;
    }
    // Unit, with irrational-looking components: grid-aligned meshes project apart on it.
    let direction = DVec3::new(0.573_462_7, 0.612_340_9, 0.544_174_6).normalize();
    let mut projected: Vec<(f64, u32)> =
        candidates.iter().map(|&v| (positions[v as usize].as_dvec3().dot(direction), v)).collect();
    projected.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
    // f64 projections of f32 points are exact to far below the tolerance; the margin covers them.
    let window = f64::from(tolerance) * (1.0 + 1e-9);
    let budget = SWEEP_COMPARISONS_PER_VERTEX * projected.len();
    let mut compared = 0;
    for (i, &(along, v)) in projected.iter().enumerate() {
        for &(_, w) in projected[i + 1..].iter().take_while(|(o, _)| o - along <= window) {
            compared += 1;
            if compared > budget {
                return near_miss_in_grid(positions, candidates, tolerance, joined);
            }
            if let Some(found) = close_apart(positions, v, w, tolerance, joined) {
                return Some(found);
            }
        }
    }
    None
}

/// Comparisons per vertex the projection sweep of [`near_miss`] makes before it hands over to
/// the hash grid.
const SWEEP_COMPARISONS_PER_VERTEX: usize = 16;

/// `(v, w, distance)` when vertices `v` and `w` lie within `tolerance` without sharing a position
/// or being `joined`.
fn close_apart(
    positions: &[Vec3],
    v: u32,
    w: u32,
    tolerance: f32,
    joined: &dyn Fn(u32, u32) -> bool,
) -> Option<(u32, u32, f32)> {
    let (p, q) = (positions[v as usize], positions[w as usize]);
    let distance = p.distance(q);
    (distance <= tolerance && position_key(p) != position_key(q) && !joined(v, w)).then_some((
        v.min(w),
        v.max(w),
        distance,
    ))
}

/// [`near_miss`] by a hash grid of cell `tolerance`: each vertex compared with those of its 27
/// cells.
fn near_miss_in_grid(
    positions: &[Vec3],
    candidates: &[u32],
    tolerance: f32,
    joined: &dyn Fn(u32, u32) -> bool,
) -> Option<(u32, u32, f32)> {
    // f64 cells: within the coordinate range even a tiny tolerance numbers them exactly.
    let cell = |p: Vec3| (p.as_dvec3() / f64::from(tolerance)).floor().as_i64vec3().to_array();
    let mut cells: HashMap<[i64; 3], Vec<u32>> = HashMap::with_capacity(candidates.len());
    for &v in candidates {
        cells.entry(cell(positions[v as usize])).or_default().push(v);
    }
    for &v in candidates {
        let [x, y, z] = cell(positions[v as usize]);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let Some(near) = cells.get(&[x + dx, y + dy, z + dz]) else { continue };
                    if let Some(found) =
                        near.iter().filter(|&&w| w > v).find_map(|&w| close_apart(positions, v, w, tolerance, joined))
                    {
                        return Some(found);
                    }
                }
            }
        }
    }
    None
}

impl TriMesh {
    /// Closes seams whose sides nearly coincide: every vertex within `tolerance` (world units,
    /// finite and ≥ 0) of an earlier vertex that stays where it is takes that vertex's position
    /// exactly. Exporters and generators often leave a UV seam's or a pole's vertices a few
    /// ulps apart (a sphere's seam column computed at 2π instead of 0); the dent stages refuse
    /// those ([`DentError::NearlyCoincidentVertices`](crate::DentError::NearlyCoincidentVertices))
    /// until they are snapped together. Returns how many vertices moved. Normals are kept as
    /// they are: a move within the tolerance changes no shading, and an asset's authored normals
    /// (a seam's sides may differ on purpose) stay bit for bit.
    ///
    /// # Errors
    /// [`MeshError::InvalidParameter`] for a negative or non-finite `tolerance`; the mesh is
    /// unchanged then.
    pub fn snap_seams(&mut self, tolerance: f32) -> Result<usize, MeshError> {
        if !(tolerance.is_finite() && tolerance >= 0.0) {
            return Err(MeshError::InvalidParameter(format!(
                "snap_seams tolerance {tolerance} must be finite and >= 0"
            )));
        }
        if tolerance == 0.0 {
            return Ok(0);
        }
        let cell = |p: Vec3| (p.as_dvec3() / f64::from(tolerance)).floor().as_i64vec3().to_array();
        let mut anchors: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
        let mut moved = 0;
        let mut positions = self.positions().to_vec();
        for v in 0..positions.len() {
            let p = positions[v];
            let [x, y, z] = cell(p);
            let neighbours =
                (-1..=1).flat_map(|dx| (-1..=1).flat_map(move |dy| (-1..=1).map(move |dz| [x + dx, y + dy, z + dz])));
            let anchor = neighbours
                .filter_map(|c| anchors.get(&c))
                .flatten()
                .copied()
                .filter(|&a| positions[a as usize].distance(p) <= tolerance)
                .min();
            match anchor {
                Some(a) if position_key(positions[a as usize]) != position_key(p) => {
                    positions[v] = positions[a as usize];
                    moved += 1;
                }
                Some(_) => {}
                None => anchors.entry([x, y, z]).or_default().push(v as u32),
            }
        }
        if moved > 0 {
            self.positions_mut().copy_from_slice(&positions);
        }
        Ok(moved)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn groups_vertices_that_share_a_position() {
        let positions = [Vec3::ZERO, Vec3::X, Vec3::new(-0.0, 0.0, 0.0), Vec3::X, Vec3::Y];
        let weld = Weld::of(&positions).expect("two pairs share a position");
        let groups: Vec<u32> = (0..5).map(|v| weld.canonical(v)).collect();
        assert_eq!(groups, [0, 1, 0, 1, 4]);
        assert_eq!(weld.canonical(9), 9);
    }

    #[test]
    fn a_mesh_without_shared_positions_has_no_weld() {
        assert_eq!(Weld::of(&[Vec3::ZERO, Vec3::X, Vec3::Y]), None);
    }

    #[test]
    fn finds_vertices_that_nearly_coincide() {
        let nudged = Vec3::new(1.0 + 4.0 * f32::EPSILON, 0.0, 0.0);
        let positions = [Vec3::ZERO, Vec3::X, Vec3::X, nudged, Vec3::Y];
        assert_eq!(
            near_miss(&positions, &[0, 1, 2, 4], 1e-5, &|_, _| false),
            None,
            "bit-identical vertices are a seam"
        );
        let (a, b, distance) = near_miss(&positions, &[0, 1, 2, 3, 4], 1e-5, &|_, _| false).expect("a near miss");
        assert!(a != b && [a, b].contains(&3) && distance > 0.0 && distance <= 1e-5);
        assert_eq!(
            near_miss(&positions, &[0, 1, 2, 3, 4], 1e-9, &|_, _| false),
            None,
            "farther apart than the tolerance"
        );
        let joined = |v: u32, w: u32| [v, w].contains(&3);
        assert_eq!(near_miss(&positions, &[0, 1, 2, 3, 4], 1e-5, &joined), None, "joined by an edge, not a seam");
    }

    #[test]
    fn the_grid_finds_what_the_sweep_finds_where_many_vertices_project_alike() {
        // Points on a plane perpendicular to the sweep's direction all project alike: the sweep
        // runs out of comparisons and the hash grid answers.
        let direction = DVec3::new(0.573_462_7, 0.612_340_9, 0.544_174_6).normalize().as_vec3();
        let (a, b) = (direction.any_orthonormal_pair().0, direction.any_orthonormal_pair().1);
        let mut positions: Vec<Vec3> =
            (0..40).flat_map(|i| (0..40).map(move |j| a * i as f32 + b * j as f32)).collect();
        let all: Vec<u32> = (0..positions.len() as u32).collect();
        assert_eq!(near_miss(&positions, &all, 1e-4, &|_, _| false), None);
        positions.push(positions[700] + Vec3::splat(1e-5));
        let all: Vec<u32> = (0..positions.len() as u32).collect();
        let (v, w, distance) = near_miss(&positions, &all, 1e-4, &|_, _| false).expect("the nudged twin");
        assert_eq!((v, w), (700, 1600));
        assert!(distance > 0.0 && distance <= 1e-4);
    }
}
