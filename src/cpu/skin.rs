//! Linear blend skinning of a parent mesh (paper §4: the `skin` step that updates the mesh of an
//! articulated body every frame). CPU twin of `shaders/skin.wgsl`.
//!
//! Every vertex blends the skinning matrices of its four bones, `M = Σ wᵢ·Sᵢ + (1 − Σ wᵢ)·I`
//! (weight missing from one, within the validation tolerance, stays on the rest pose, and
//! identity bones give the rest mesh back bit for bit), then moves its rest position by `M` and
//! its rest normal by the cofactor matrix of `M`'s linear part `A`,
//! `cof(A) = det(A)·A⁻ᵀ`: the inverse-transpose up to a factor that the final normalization
//! removes (or that flips the normal with a mirroring `A`, exactly as the skinned triangles'
//! winding flips), and defined even where `A` is singular.

use glam::{UVec4, Vec3, Vec3A, Vec4};
use rayon::prelude::*;

use super::skin_error::{SkinError, WEIGHT_SUM_TOLERANCE};
use super::skin_layout::{SkinBone, SkinInfluence, SkinParams};

/// Vertices per parallel task: enough work to outweigh rayon's scheduling.
const CHUNK: usize = 4096;

/// A skinned mesh: what [`skin`] computes and the GPU's `skin` kernel reads back.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Skinned {
    /// Skinned positions, world units, one per vertex.
    pub positions: Vec<Vec3>,
    /// Skinned unit normals (zero where the transformed normal vanishes), one per vertex.
    pub normals: Vec<Vec3>,
}

/// Whether an influence has finite, non-negative weights summing to one within
/// [`WEIGHT_SUM_TOLERANCE`] and bone indices below `bone_count`; the fast test, without the
/// reason.
#[inline]
fn influence_ok(influence: &SkinInfluence, bone_count: u32) -> bool {
    // Finite and non-negative: NaN fails both comparisons, ±∞ one of them.
    let weights = Vec4::from_array(influence.weights);
    let finite = (weights.cmpge(Vec4::ZERO) & weights.cmple(Vec4::splat(f32::MAX))).all();
    let bones = UVec4::from_array(influence.bones).cmplt(UVec4::splat(bone_count)).all();
    finite & bones & ((weight_sum(&influence.weights) - 1.0).abs() <= WEIGHT_SUM_TOLERANCE)
}

/// The sum of four weights, in one fixed order.
#[inline]
fn weight_sum(weights: &[f32; 4]) -> f32 {
    weights[0] + weights[1] + weights[2] + weights[3]
}

/// Why `influence` fails [`influence_ok`] (which it must).
#[cold]
fn influence_error(vertex: usize, influence: &SkinInfluence, bone_count: u32) -> SkinError {
    for (slot, &weight) in influence.weights.iter().enumerate() {
        if !weight.is_finite() {
            return SkinError::NonFiniteWeight { vertex, slot };
        }
        if weight < 0.0 {
            return SkinError::NegativeWeight { vertex, slot, weight };
        }
    }
    if let Some(&bone) = influence.bones.iter().find(|&&b| b >= bone_count) {
        return SkinError::BoneIndex { vertex, bone, bone_count };
    }
    SkinError::WeightSum { vertex, sum: weight_sum(&influence.weights) }
}

/// The index of the first item for which `bad(index, item)` holds, searched in parallel chunks.
fn first_bad<T: Sync>(items: &[T], bad: impl Fn(usize, &T) -> bool + Sync) -> Option<usize> {
    let chunks = items.par_chunks(CHUNK).enumerate();
    chunks
        .filter_map(|(c, chunk)| (c * CHUNK..).zip(chunk).position(|(v, item)| bad(v, item)).map(|k| c * CHUNK + k))
        .min()
}

impl SkinInfluence {
    /// Checks a skinned mesh's rest vertices and influences before they are uploaded or skinned
    /// (what [`skin`] and the GPU upload check): finite rest positions and normals, finite
    /// non-negative weights summing to one, bones below `bone_count`; reports the first bad
    /// vertex. For a caller that merges several meshes and wants the error against each one.
    ///
    /// # Errors
    /// As the checks named: [`SkinError::Length`], [`SkinError::NonFiniteRest`],
    /// [`SkinError::NonFiniteWeight`], [`SkinError::NegativeWeight`], [`SkinError::WeightSum`] or
    /// [`SkinError::BoneIndex`].
    pub fn validate_all(
        rest_positions: &[Vec3],
        rest_normals: &[Vec3],
        influences: &[Self],
        bone_count: u32,
    ) -> Result<(), SkinError> {
        check_length("rest normals", rest_normals.len(), rest_positions.len())?;
        check_length("influences", influences.len(), rest_positions.len())?;
        let rest_ok = |v: usize| rest_positions[v].is_finite() & rest_normals[v].is_finite();
        let bad = first_bad(influences, |v, i| !(rest_ok(v) & influence_ok(i, bone_count)));
        match bad {
            Some(vertex) if !rest_ok(vertex) => Err(SkinError::NonFiniteRest { vertex }),
            Some(vertex) => Err(influence_error(vertex, &influences[vertex], bone_count)),
            None => Ok(()),
        }
    }
}

impl SkinBone {
    /// Checks `bone_count` skinning matrices for NaN and ∞ (what [`skin`] checks).
    ///
    /// # Errors
    /// [`SkinError::Length`] or [`SkinError::NonFiniteBone`].
    pub fn validate_all(bones: &[Self], bone_count: u32) -> Result<(), SkinError> {
        check_length("bone matrices", bones.len(), bone_count as usize)?;
        match bones.iter().position(|b| !b.is_finite()) {
            Some(bone) => Err(SkinError::NonFiniteBone { bone }),
            None => Ok(()),
        }
    }
}

/// [`SkinError::Length`] unless `len == expected`.
pub(crate) fn check_length(what: &'static str, len: usize, expected: usize) -> Result<(), SkinError> {
    if len != expected {
        return Err(SkinError::Length { what, len, expected });
    }
    Ok(())
}

/// Skins a mesh: writes every vertex's skinned position (world units) and unit normal (zero
/// where the transformed normal vanishes) from its rest position and normal, its four
/// [`SkinInfluence`]s and the bones' skinning matrices (see the module docs for the blend).
///
/// The inputs follow the shader's bindings in order: `params`, `bones` (bone count entries,
/// see [`skin_bones`](super::skin_bones)), the rest vertices (`rest_positions` and
/// `rest_normals`, which the shader reads interleaved from one buffer), `influences`, then the
/// outputs `positions` and `normals`. Every slice but `bones` holds `params.vertex_count`
/// entries. All inputs are checked before anything is written, so on error the outputs are
/// untouched; runs on all cores.
///
/// # Errors
/// [`SkinError::Length`] for a slice of the wrong length; [`SkinError::NonFiniteBone`],
/// [`SkinError::NonFiniteRest`]; [`SkinError::NonFiniteWeight`], [`SkinError::NegativeWeight`],
/// [`SkinError::WeightSum`] or [`SkinError::BoneIndex`] for a bad influence.
///
/// # Example
/// ```
/// use dentbend::cpu::{SkinBone, SkinInfluence, SkinParams, skin};
/// use dentbend::glam::{Affine3A, Vec3};
///
/// let bones = [SkinBone::IDENTITY, SkinBone::from_affine(Affine3A::from_translation(Vec3::Y))];
/// let rest = [Vec3::ZERO, Vec3::X];
/// let normals_in = [Vec3::Z; 2];
/// // The second vertex follows both bones half and half.
/// let influences = [
///     SkinInfluence::rigid(0),
///     SkinInfluence { bones: [0, 1, 0, 0], weights: [0.5, 0.5, 0.0, 0.0] },
/// ];
/// let (mut positions, mut normals) = ([Vec3::ZERO; 2], [Vec3::ZERO; 2]);
/// skin(&SkinParams::new(2, 2), &bones, &rest, &normals_in, &influences, &mut positions, &mut normals)?;
/// assert_eq!(positions, [Vec3::ZERO, Vec3::new(1.0, 0.5, 0.0)]);
/// assert_eq!(normals, [Vec3::Z; 2]);
/// # Ok::<(), dentbend::cpu::SkinError>(())
/// ```
pub fn skin(
    params: &SkinParams,
    bones: &[SkinBone],
    rest_positions: &[Vec3],
    rest_normals: &[Vec3],
    influences: &[SkinInfluence],
    positions: &mut [Vec3],
    normals: &mut [Vec3],
) -> Result<(), SkinError> {
    let n = params.vertex_count as usize;
    check_length("rest positions", rest_positions.len(), n)?;
    check_length("rest normals", rest_normals.len(), n)?;
    check_length("influences", influences.len(), n)?;
    check_length("skinned positions", positions.len(), n)?;
    check_length("skinned normals", normals.len(), n)?;
    SkinBone::validate_all(bones, params.bone_count)?;
    SkinInfluence::validate_all(rest_positions, rest_normals, influences, params.bone_count)?;

    positions.par_chunks_mut(CHUNK).zip(normals.par_chunks_mut(CHUNK)).enumerate().for_each(
        |(chunk, (positions, normals))| {
            let range = chunk * CHUNK..chunk * CHUNK + positions.len();
            let rest = rest_positions[range.clone()].iter().zip(&rest_normals[range.clone()]);
            for (((position, normal), (p, n)), influence) in
                positions.iter_mut().zip(normals.iter_mut()).zip(rest).zip(&influences[range])
            {
                (*position, *normal) = skin_vertex(bones, *p, *n, influence);
            }
        },
    );
    Ok(())
}

/// One invocation of the shader's `main`: the skinned position and unit normal of a vertex.
#[inline]
fn skin_vertex(bones: &[SkinBone], p: Vec3, n: Vec3, influence: &SkinInfluence) -> (Vec3, Vec3) {
    // Blend the rows of the bones' matrices, skipping bones past the bone count.
    let mut rows = [Vec4::ZERO; 3];
    let mut total = 0.0;
    for (&bone, &weight) in influence.bones.iter().zip(&influence.weights) {
        let Some(bone) = bones.get(bone as usize) else {
            continue;
        };
        for (row, bone_row) in rows.iter_mut().zip(&bone.rows) {
            *row += weight * Vec4::from_array(*bone_row);
        }
        total += weight;
    }
    // The weight missing from one stays on the rest pose: M += (1 − Σ w)·I. Identity bones sum
    // the diagonal exactly as `total`, so it comes out exactly 1.
    let missing = 1.0 - total;
    rows[0].x += missing;
    rows[1].y += missing;
    rows[2].z += missing;

    let p1 = p.extend(1.0);
    let position = Vec3::new(rows[0].dot(p1), rows[1].dot(p1), rows[2].dot(p1));
    // Rows of cof(A) = det(A)·A⁻ᵀ: the cross products of A's rows.
    let [a0, a1, a2] = rows.map(Vec3A::from_vec4);
    let n = Vec3A::from(n);
    let normal = Vec3A::new(a1.cross(a2).dot(n), a2.cross(a0).dot(n), a0.cross(a1).dot(n));
    (position, normal.normalize_or_zero().into())
}
