//! Computing skinning weights in the rest pose from volumetric geodesic distances, and updating
//! them after a bone split for the split bone only (paper §4, Algorithm 2 steps 1 and 9).

use glam::Vec3;
use rayon::prelude::*;

use super::geodesic::{UNIT, UNREACHED, VoxelGraph};
use super::weights::{MAX_INFLUENCES, WeightsBuilder};
use super::{BendError, Bone, LevelSet, Skeleton, SkinWeights, WeightParams};
use crate::mesh::TriMesh;

/// Distances below this many cells count as this many (keeps d⁻ᵖ finite at a bone).
const NEAR_CELLS: f32 = 0.5;

/// What weight computations reuse for one mesh: its level set, the voxel graph of its solid
/// cells and each vertex's interpolation stencil. Build it once per rest mesh; a bone split then
/// costs two geodesic marches.
#[derive(Debug, Clone)]
pub struct WeightCache {
    level_set: LevelSet,
    graph: VoxelGraph,
    stencils: Vec<Stencil>,
    params: WeightParams,
}

/// The eight cell centres around a vertex and their trilinear weights (zero on cells outside the
/// solid).
#[derive(Debug, Clone, Copy)]
struct Stencil {
    cells: [u32; 8],
    weights: [f32; 8],
}

impl WeightCache {
    /// Builds the level set of the closed `mesh` at `params.resolution` and everything derived.
    ///
    /// # Errors
    /// [`BendError::InvalidParameter`] for bad `params`; as [`LevelSet::build`] otherwise.
    pub fn new(mesh: &TriMesh, params: WeightParams) -> Result<Self, BendError> {
        params.validate()?;
        let level_set = LevelSet::build(mesh, params.resolution)?;
        let graph = VoxelGraph::new(&level_set);
        let stencils = mesh.positions().par_iter().map(|&p| stencil(&level_set, &graph, p)).collect();
        Ok(Self { level_set, graph, stencils, params })
    }

    /// The level set the weights march through (also the one sub-bodies are cut from).
    pub fn level_set(&self) -> &LevelSet {
        &self.level_set
    }

    /// The parameters the cache was built with.
    pub fn params(&self) -> WeightParams {
        self.params
    }

    /// Number of mesh vertices the cache was built for.
    pub fn vertex_count(&self) -> usize {
        self.stencils.len()
    }

    /// Geodesic distance (m) from `bone` to every vertex through the solid; `f32::INFINITY` for a
    /// vertex in a part of the body the bone cannot reach.
    fn vertex_distances(&self, bone: &Bone) -> Vec<f32> {
        let seeds = self.graph.seeds(&self.level_set, bone.head, bone.tail);
        let field = self.graph.march(&seeds);
        let scale = self.level_set.cell_size() / UNIT;
        self.stencils
            .iter()
            .map(|s| {
                let (mut sum, mut total) = (0.0f32, 0.0f32);
                for (&c, &w) in s.cells.iter().zip(&s.weights) {
                    let d = field[c as usize];
                    if w > 0.0 && d != UNREACHED {
                        sum += w * d as f32;
                        total += w;
                    }
                }
                if total > 0.0 { sum / total * scale } else { f32::INFINITY }
            })
            .collect()
    }

    fn check_mesh(&self, mesh: &TriMesh) -> Result<(), BendError> {
        if mesh.vertex_count() != self.stencils.len() {
            return Err(BendError::Mismatch {
                what: "mesh vertices (weight cache built for another mesh)",
                expected: self.stencils.len(),
                actual: mesh.vertex_count(),
            });
        }
        Ok(())
    }
}

/// Builds the weight cache of `mesh` and the weights of `skeleton` in one call.
///
/// # Errors
/// As [`WeightCache::new`] and [`SkinWeights::compute`].
///
/// # Example
/// ```
/// use dentbend::bend::{WeightParams, auto_skeleton, compute_weights};
/// let plank = dentbend::mesh::builtin("plank").unwrap();
/// let skeleton = auto_skeleton(&plank, 2).unwrap();
/// let params = WeightParams { resolution: 32, ..WeightParams::default() };
/// let (weights, _cache) = compute_weights(&plank, &skeleton, params).unwrap();
/// assert_eq!(weights.vertex_count(), plank.vertex_count());
/// ```
pub fn compute_weights(
    mesh: &TriMesh,
    skeleton: &Skeleton,
    params: WeightParams,
) -> Result<(SkinWeights, WeightCache), BendError> {
    let cache = WeightCache::new(mesh, params)?;
    let weights = SkinWeights::compute(mesh, skeleton, &cache)?;
    Ok((weights, cache))
}

impl SkinWeights {
    /// Skinning weights of `mesh` (the rest pose `cache` was built from) over `skeleton`.
    ///
    /// For each bone, the geodesic distance through the body's solid cells (inside or touching
    /// the surface) is marched from the cells the bone passes through (a bone poking out of the
    /// body starts from the part inside; one wholly outside from the nearest solid cells), then
    /// read at each vertex by trilinear interpolation over the solid cells around it. A vertex
    /// keeps its `params.influences` = k nearest bones with weights w_b ∝ d_b⁻ᵖ − d_{k+1}⁻ᵖ
    /// (the (k+1)-th bone's term makes a weight fade to zero before the bone drops out of the k
    /// nearest), normalised to sum to 1. Distances are clamped below at half a cell. Paths stay in
    /// the body, so a bone does not reach across a gap (the bunny's ears do not follow its head
    /// through the air); a vertex no bone reaches falls back to straight-line distances.
    ///
    /// # Errors
    /// [`BendError::Mismatch`] if `mesh` has another vertex count than the cache's mesh.
    pub fn compute(mesh: &TriMesh, skeleton: &Skeleton, cache: &WeightCache) -> Result<Self, BendError> {
        cache.check_mesh(mesh)?;
        let fields: Vec<Vec<f32>> = skeleton.bones().par_iter().map(|b| cache.vertex_distances(b)).collect();
        let near = NEAR_CELLS * cache.level_set.cell_size();
        let (k, p) = (cache.params.influences, cache.params.falloff);
        let per_vertex: Vec<Influences> = mesh
            .positions()
            .par_iter()
            .enumerate()
            .map_init(Vec::new, |d: &mut Vec<(f32, u32)>, (v, &position)| {
                d.clear();
                d.extend(fields.iter().enumerate().map(|(b, f)| (f[v].max(near), b as u32)));
                if d.iter().all(|x| !x.0.is_finite()) {
                    d.clear();
                    d.extend(euclidean(skeleton, position, near));
                }
                inverse_distance(d, k, p)
            })
            .collect();
        let mut builder = WeightsBuilder::with_capacity(per_vertex.len(), k);
        for influences in &per_vertex {
            builder.push_vertex(influences.items[..influences.count].iter().copied());
        }
        Ok(builder.finish(skeleton.len()))
    }

    /// The weights after [`Skeleton::split_bone`] split `old_bone` into `new_bones` (as it
    /// returned them; `skeleton` is the skeleton after the split).
    ///
    /// Only the split bone's weight changes: on every vertex it influenced, its weight w is
    /// divided between the two halves in proportion to dₐ⁻ᵖ : d_b⁻ᵖ, the geodesic distances to
    /// each half (two marches). Every other bone's weight on every vertex is copied bit for bit,
    /// and each vertex's weights still sum to what they summed to.
    ///
    /// # Errors
    /// [`BendError::Mismatch`] if the mesh, the cache or `skeleton` (which must have exactly one
    /// more bone than these weights) do not match; [`BendError::BoneOutOfRange`] for a bad
    /// index; [`BendError::InvalidParameter`] if `new_bones` are not two distinct bones, each
    /// `old_bone` or a bone these weights do not know.
    pub fn after_split(
        &self,
        mesh: &TriMesh,
        skeleton: &Skeleton,
        old_bone: usize,
        new_bones: (usize, usize),
        cache: &WeightCache,
    ) -> Result<Self, BendError> {
        cache.check_mesh(mesh)?;
        if self.vertex_count() != mesh.vertex_count() {
            let (expected, actual) = (self.vertex_count(), mesh.vertex_count());
            return Err(BendError::Mismatch { what: "mesh vertices (weights of another mesh)", expected, actual });
        }
        if skeleton.len() != self.bone_count() + 1 {
            let (expected, actual) = (self.bone_count() + 1, skeleton.len());
            return Err(BendError::Mismatch { what: "bones after one split", expected, actual });
        }
        let count = self.bone_count();
        if old_bone >= count {
            return Err(BendError::BoneOutOfRange { bone: old_bone, count });
        }
        let (a, b) = new_bones;
        for bone in [a, b] {
            if bone >= skeleton.len() {
                return Err(BendError::BoneOutOfRange { bone, count: skeleton.len() });
            }
        }
        if a == b || [a, b].iter().any(|&n| n != old_bone && n < count) {
            let value = format!("{new_bones:?}");
            let reason = "must be two distinct bones, each the split bone or a new one";
            return Err(BendError::InvalidParameter { name: "new_bones", value, reason });
        }
        let (bones, old) = (skeleton.bones(), old_bone as u32);
        let (da, db) = rayon::join(|| cache.vertex_distances(&bones[a]), || cache.vertex_distances(&bones[b]));
        let near = NEAR_CELLS * cache.level_set.cell_size();
        let p = cache.params.falloff;
        let positions = mesh.positions();
        // Per vertex: the old bone's weight split into the two halves' (NaN where it had none).
        let shares: Vec<(f32, f32)> = (0..self.vertex_count())
            .into_par_iter()
            .map(|v| {
                let Some(w) = self.find(v, old) else { return (f32::NAN, f32::NAN) };
                let (mut ra, mut rb) = (da[v], db[v]);
                if !(ra.is_finite() || rb.is_finite()) {
                    (ra, rb) = (bones[a].distance(positions[v]), bones[b].distance(positions[v]));
                }
                let (ra, rb) = (ra.max(near), rb.max(near));
                let (ka, kb) = (kernel(ra, ra.min(rb), p), kernel(rb, ra.min(rb), p));
                let share = if ka + kb > 0.0 { ka / (ka + kb) } else { 0.5 };
                let wa = w * share;
                (wa, w - wa)
            })
            .collect();
        let mut builder = WeightsBuilder::with_capacity(self.vertex_count(), self.max_influence_count() + 1);
        for (v, &(wa, wb)) in shares.iter().enumerate() {
            let (bones, weights) = self.influences(v);
            let kept = bones.iter().copied().zip(weights.iter().copied()).filter(|&(bone, _)| bone != old);
            let added = [(a as u32, wa), (b as u32, wb)].into_iter().filter(|x| x.1 > 0.0);
            builder.push_vertex(kept.chain(added));
        }
        Ok(builder.finish(skeleton.len()))
    }
}

/// Up to [`MAX_INFLUENCES`] `(bone, weight)` pairs of one vertex.
#[derive(Debug, Clone, Copy)]
struct Influences {
    count: usize,
    items: [(u32, f32); MAX_INFLUENCES],
}

/// (scale/d)ᵖ: the kernel d⁻ᵖ relative to a reference distance `scale` ≤ d, so it stays in
/// [0, 1] whatever the units; 0 for an infinite distance (integer p by repeated multiplication).
fn kernel(d: f32, scale: f32, p: f32) -> f32 {
    let ratio = scale / d;
    if !ratio.is_finite() {
        0.0
    } else if p == p.trunc() {
        ratio.powi(p as i32)
    } else {
        ratio.powf(p)
    }
}

/// Weights from `(distance, bone)` pairs (reordered here): the k nearest with
/// d⁻ᵖ − d_{k+1}⁻ᵖ, normalised (plain d⁻ᵖ if that leaves nothing, as when the k nearest tie with
/// the next).
fn inverse_distance(d: &mut [(f32, u32)], k: usize, p: f32) -> Influences {
    let k = k.min(d.len()).min(MAX_INFLUENCES);
    let by_distance = |x: &(f32, u32), y: &(f32, u32)| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1));
    if d.len() > k + 1 {
        d.select_nth_unstable_by(k, by_distance);
    }
    d[..k].sort_unstable_by(by_distance);
    let scale = d[0].0;
    let cutoff = d.get(k).map_or(0.0, |x| kernel(x.0, scale, p));
    let mut out = Influences { count: 0, items: [(0, 0.0); MAX_INFLUENCES] };
    for subtract in [cutoff, 0.0] {
        out.count = 0;
        for &(dist, bone) in &d[..k] {
            let w = kernel(dist, scale, p) - subtract;
            if w > 0.0 {
                out.items[out.count] = (bone, w);
                out.count += 1;
            }
        }
        if out.count > 0 {
            break;
        }
    }
    let total: f32 = out.items[..out.count].iter().map(|x| x.1).sum();
    if !(total > 0.0 && total.is_finite()) {
        // Unreachable in practice (distances are finite and clamped); fall back to the nearest.
        out.items[0] = (d[0].1, 1.0);
        out.count = 1;
        return out;
    }
    out.items[..out.count].iter_mut().for_each(|x| x.1 /= total);
    out
}

/// Straight-line distances from `p` to every bone, clamped below at `near`.
fn euclidean(skeleton: &Skeleton, p: Vec3, near: f32) -> impl Iterator<Item = (f32, u32)> + '_ {
    skeleton.bones().iter().enumerate().map(move |(b, bone)| (bone.distance(p).max(near), b as u32))
}

/// The interpolation stencil of a vertex at `p`: the eight cell centres of the dual cell holding
/// it, trilinear weights, zeroed on cells outside the solid.
fn stencil(set: &LevelSet, graph: &VoxelGraph, p: Vec3) -> Stencil {
    let [nx, ny, nz] = set.dims();
    let q = (p - set.origin()) / set.cell_size() - 0.5;
    let limit = Vec3::new(nx as f32, ny as f32, nz as f32) - 2.0;
    let base = q.floor().clamp(Vec3::ZERO, limit);
    let f = (q - base).clamp(Vec3::ZERO, Vec3::ONE);
    let b = base.as_uvec3();
    let mut out = Stencil { cells: [0; 8], weights: [0.0; 8] };
    for corner in 0..8u32 {
        let (di, dj, dk) = (corner & 1, (corner >> 1) & 1, corner >> 2);
        let index = (b.x + di) as usize + nx * ((b.y + dj) as usize + ny * (b.z + dk) as usize);
        let w = [f.x, f.y, f.z]
            .iter()
            .zip([di, dj, dk])
            .map(|(&t, bit)| if bit == 1 { t } else { 1.0 - t })
            .product::<f32>();
        out.cells[corner as usize] = index as u32;
        // A tiny floor keeps a corner that sits exactly on the vertex's far side usable.
        out.weights[corner as usize] = if graph.is_solid(index) { w + 1e-6 } else { 0.0 };
    }
    out
}
