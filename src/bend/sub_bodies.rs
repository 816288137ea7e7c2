//! Sub-bodies (paper §4, opening): each bone gets the triangles its weight dominates and the
//! level-set cells nearest to those triangles, and from its inside cells a mass, centre of mass
//! and inertia tensor.

use glam::{DMat3, DVec3};
use rayon::prelude::*;

use super::{BendError, LevelSet, SkinWeights};
use crate::mesh::MassProperties;
use crate::mesh::TriMesh;

/// Label of a cell or triangle that no bone owns.
pub const NO_BONE: u32 = u32::MAX;

/// The owner of every triangle: the bone with the largest summed weight over the triangle's
/// three vertices (the largest weight at its centroid under linear interpolation; lowest bone
/// index on ties). The sum, rather than the single largest vertex weight, keeps a triangle
/// straddling a blend region with the bone that covers most of it.
///
/// # Errors
/// [`BendError::Mismatch`] if `weights` belong to a mesh with another vertex count.
pub(crate) fn triangle_owners(mesh: &TriMesh, weights: &SkinWeights) -> Result<Vec<u32>, BendError> {
    if weights.vertex_count() != mesh.vertex_count() {
        let (expected, actual) = (mesh.vertex_count(), weights.vertex_count());
        return Err(BendError::Mismatch { what: "weight vertices", expected, actual });
    }
    Ok(mesh
        .faces()
        .par_iter()
        .map_init(Vec::new, |sums: &mut Vec<(u32, f32)>, face| {
            sums.clear();
            for &v in face {
                let (bones, ws) = weights.influences(v as usize);
                for (&b, &w) in bones.iter().zip(ws) {
                    match sums.iter_mut().find(|s| s.0 == b) {
                        Some(s) => s.1 += w,
                        None => sums.push((b, w)),
                    }
                }
            }
            sums.iter()
                .fold((NO_BONE, f32::NEG_INFINITY), |best, &(b, w)| {
                    if w > best.1 || (w == best.1 && b < best.0) { (b, w) } else { best }
                })
                .0
        })
        .collect())
}

/// One bone's share of a body.
#[derive(Debug, Clone)]
pub struct SubBody {
    /// The bone.
    pub bone: usize,
    /// Its triangles (indices into the parent mesh's faces); an open surface.
    pub triangles: Vec<u32>,
    /// Number of level-set cells assigned to it, inside and outside.
    pub cell_count: usize,
    /// Mass properties of its inside cells at the given density (mass kg, centre m, inertia
    /// kg·m² about the centre, volume m³); `None` when it owns no inside cell.
    pub mass: Option<MassProperties>,
}

/// A body divided among the bones of its skeleton.
#[derive(Debug, Clone)]
pub struct SubBodies {
    triangle_bones: Vec<u32>,
    cell_bones: Vec<u32>,
    bodies: Vec<SubBody>,
    total: MassProperties,
}

impl SubBodies {
    /// Divides `mesh` (whose level set is `level_set`, as from
    /// [`WeightCache::level_set`](super::WeightCache::level_set)) among the bones of `weights`.
    ///
    /// Triangles go to their owners (`triangle_owners`). Cells: first those the surface passes
    /// through (centre within half a cell diagonal of it) go to the owner of their nearest
    /// triangle, then, one ring of 26 neighbours at a time, the rest of the grid, inside and
    /// outside, takes the label of a neighbour in the previous ring (where several compete, the
    /// one reached by a face step before an edge step before a corner step, then the lowest bone
    /// index). Mass properties come from the inside cells at `density` (kg/m³): each cell a
    /// uniform cube of mass ρh³, so the inertia about the sub-body's centre adds each cube's own
    /// ρh⁵/6 per axis. The sub-body masses sum to the whole body's voxel mass.
    ///
    /// # Errors
    /// [`BendError::InvalidParameter`] for a density that is not finite and positive;
    /// [`BendError::Mismatch`] if `weights` belong to another mesh.
    pub fn compute(
        mesh: &TriMesh,
        weights: &SkinWeights,
        level_set: &LevelSet,
        density: f32,
    ) -> Result<Self, BendError> {
        if !(density.is_finite() && density > 0.0) {
            let value = density.to_string();
            return Err(BendError::InvalidParameter { name: "density", value, reason: "must be finite and > 0" });
        }
        let triangle_bones = triangle_owners(mesh, weights)?;
        let cell_bones = color_cells(level_set, &triangle_bones);
        let bone_count = weights.bone_count();
        let mut triangles = vec![Vec::new(); bone_count];
        for (t, &b) in triangle_bones.iter().enumerate() {
            if let Some(list) = triangles.get_mut(b as usize) {
                list.push(t as u32);
            }
        }
        // Per bone (and, last, the whole body): cell count and moments of the inside cells.
        let (cell_counts, moments) = cell_bones
            .par_chunks(4096)
            .enumerate()
            .map(|(chunk, labels)| {
                let mut counts = vec![0usize; bone_count];
                let mut moments = vec![Moments::default(); bone_count + 1];
                for (offset, &b) in labels.iter().enumerate() {
                    let Some(count) = counts.get_mut(b as usize) else { continue };
                    *count += 1;
                    let c = chunk * 4096 + offset;
                    if level_set.is_inside(c) {
                        let centre = level_set.center(c).as_dvec3();
                        moments[b as usize].add(centre);
                        moments[bone_count].add(centre);
                    }
                }
                (counts, moments)
            })
            .collect::<Vec<_>>()
            .into_iter()
            // Summed in chunk order, so the result does not depend on the thread schedule.
            .fold((vec![0; bone_count], vec![Moments::default(); bone_count + 1]), |(mut ca, mut ma), (cb, mb)| {
                ca.iter_mut().zip(cb).for_each(|(a, b)| *a += b);
                ma.iter_mut().zip(mb).for_each(|(a, b)| a.merge(&b));
                (ca, ma)
            });
        let mut moments = moments;
        let total = moments.pop().unwrap_or_default();
        let (h, rho) = (f64::from(level_set.cell_size()), f64::from(density));
        let bodies = triangles
            .into_iter()
            .zip(moments)
            .zip(cell_counts)
            .enumerate()
            .map(|(bone, ((triangles, m), cell_count))| SubBody { bone, triangles, cell_count, mass: m.finish(h, rho) })
            .collect();
        let total = total.finish(h, rho).ok_or(BendError::EmptyInterior { resolution: level_set.resolution() })?;
        Ok(Self { triangle_bones, cell_bones, bodies, total })
    }

    /// Owner bone of every triangle of the parent mesh.
    pub fn triangle_bones(&self) -> &[u32] {
        &self.triangle_bones
    }

    /// Owner bone of every level-set cell (indexed as [`LevelSet`] describes).
    pub fn cell_bones(&self) -> &[u32] {
        &self.cell_bones
    }

    /// One sub-body per bone, in bone order.
    pub fn bodies(&self) -> &[SubBody] {
        &self.bodies
    }

    /// Mass properties of all inside cells together (the whole body as voxels).
    pub fn total(&self) -> MassProperties {
        self.total
    }

    /// The open surface of `bone`'s sub-body as its own mesh, with the parent-mesh index of each
    /// of its vertices.
    ///
    /// # Errors
    /// [`BendError::BoneOutOfRange`]; [`BendError::Mismatch`] if `mesh` is not the parent mesh
    /// (another triangle count); [`BendError::Mesh`] (empty) when the bone owns no triangle.
    pub fn sub_mesh(&self, mesh: &TriMesh, bone: usize) -> Result<(TriMesh, Vec<u32>), BendError> {
        if mesh.face_count() != self.triangle_bones.len() {
            let (expected, actual) = (self.triangle_bones.len(), mesh.face_count());
            return Err(BendError::Mismatch { what: "triangles of the parent mesh", expected, actual });
        }
        let body = self.bodies.get(bone).ok_or(BendError::BoneOutOfRange { bone, count: self.bodies.len() })?;
        let mut remap = vec![u32::MAX; mesh.vertex_count()];
        let mut parents = Vec::new();
        let faces: Vec<[u32; 3]> = body
            .triangles
            .iter()
            .map(|&t| {
                mesh.faces()[t as usize].map(|v| {
                    if remap[v as usize] == u32::MAX {
                        remap[v as usize] = parents.len() as u32;
                        parents.push(v);
                    }
                    remap[v as usize]
                })
            })
            .collect();
        let positions = parents.iter().map(|&v| mesh.positions()[v as usize]).collect();
        Ok((TriMesh::new(positions, faces)?, parents))
    }
}

/// Bit position of the ring count in a colouring key.
const RING_SHIFT: u32 = 40;
/// Bit position of the step class (0 face, 1 edge, 2 corner neighbour) in a colouring key.
const CLASS_SHIFT: u32 = 32;
/// Ring count of a cell not reached yet (large, and room left to add to it).
const FAR: u64 = 1 << 22;

/// Labels every cell: surface cells from their nearest triangle's owner, then every other cell
/// from the surface cell fewest 26-neighbour rings away (chessboard distance, exact by two raster
/// sweeps of a 3×3×3 mask), inside and outside alike. Among candidates the same number of rings
/// away, the one reached by the shortest last step (face, then edge, then corner neighbour) wins,
/// then the lower bone index; so the split between two bones' cells follows their surfaces.
fn color_cells(set: &LevelSet, triangle_bones: &[u32]) -> Vec<u32> {
    let [nx, ny, nz] = set.dims();
    // Key: rings << RING_SHIFT | step class << CLASS_SHIFT | bone; smaller wins.
    let mut keys: Vec<u64> = (0..set.cell_count())
        .into_par_iter()
        .map(|c| {
            let bone =
                if set.is_surface(c) { set.nearest_triangle(c).and_then(|t| triangle_bones.get(t)) } else { None };
            bone.map_or((FAR << RING_SHIFT) | u64::from(NO_BONE), |&b| u64::from(b))
        })
        .collect();
    let dims = [nx as isize, ny as isize, nz as isize];
    // The 13 neighbours earlier in raster order: offset and the key increment of the step.
    let steps: Vec<([isize; 3], u64)> = (-1isize..=1)
        .flat_map(|dk| (-1isize..=1).flat_map(move |dj| (-1isize..=1).map(move |di| [di, dj, dk])))
        .filter(|&[di, dj, dk]| (dk, dj, di) < (0, 0, 0))
        .map(|d| {
            let class = (d[0].abs() + d[1].abs() + d[2].abs() - 1) as u64;
            (d, (1 << RING_SHIFT) | (class << CLASS_SHIFT))
        })
        .collect();
    let step_key = |from: u64, increment: u64| (from & !(0xFF << CLASS_SHIFT)) + increment;
    let mut sweep = |sign: isize| {
        let offsets: Vec<(isize, u64)> =
            steps.iter().map(|(d, inc)| (sign * (d[0] + dims[0] * (d[1] + dims[1] * d[2])), *inc)).collect();
        for step in 0..keys.len() {
            let c = if sign < 0 { keys.len() - 1 - step } else { step };
            let here = [(c % nx) as isize, ((c / nx) % ny) as isize, (c / (nx * ny)) as isize];
            let mut best = keys[c];
            if (0..3).all(|a| here[a] > 0 && here[a] + 1 < dims[a]) {
                for &(offset, increment) in &offsets {
                    best = best.min(step_key(keys[(c as isize + offset) as usize], increment));
                }
            } else {
                for ((d, _), &(offset, increment)) in steps.iter().zip(&offsets) {
                    if (0..3).all(|a| (0..dims[a]).contains(&(here[a] + sign * d[a]))) {
                        best = best.min(step_key(keys[(c as isize + offset) as usize], increment));
                    }
                }
            }
            keys[c] = best;
        }
    };
    sweep(1);
    sweep(-1);
    keys.into_iter().map(|k| k as u32).collect()
}

/// Running sums of unit-mass cell centres.
#[derive(Debug, Clone, Copy)]
struct Moments {
    count: f64,
    first: DVec3,
    second: DMat3,
}

impl Default for Moments {
    // Not derived: glam's `DMat3::default()` is the identity.
    fn default() -> Self {
        Self { count: 0.0, first: DVec3::ZERO, second: DMat3::ZERO }
    }
}

impl Moments {
    fn merge(&mut self, other: &Self) {
        self.count += other.count;
        self.first += other.first;
        self.second += other.second;
    }

    fn add(&mut self, p: DVec3) {
        self.count += 1.0;
        self.first += p;
        self.second += DMat3::from_cols(p * p.x, p * p.y, p * p.z);
    }

    /// Mass properties of `count` cubes of side `h` at density `rho`.
    fn finish(&self, h: f64, rho: f64) -> Option<MassProperties> {
        if self.count == 0.0 {
            return None;
        }
        let cell_mass = rho * h * h * h;
        let centre = self.first / self.count;
        let covariance = (self.second / self.count
            - DMat3::from_cols(centre * centre.x, centre * centre.y, centre * centre.z))
            * (self.count * cell_mass);
        let trace = covariance.x_axis.x + covariance.y_axis.y + covariance.z_axis.z;
        let own = self.count * cell_mass * h * h / 6.0;
        let inertia = DMat3::from_diagonal(DVec3::splat(trace + own)) - covariance;
        Some(MassProperties {
            mass: (self.count * cell_mass) as f32,
            center: centre.as_vec3(),
            inertia: inertia.as_mat3(),
            volume: (self.count * h * h * h) as f32,
        })
    }
}
