//! `#[repr(C)]` blocks of the `skin` kernel and the host helper that turns bone poses into
//! skinning matrices.
//!
//! Keep in sync with `shaders/skin.wgsl` (`SkinParams`, `SkinBone`, `SkinInfluence`): the structs
//! below are laid out exactly as the WGSL ones, with no implicit padding on either side.

use bytemuck::{Pod, Zeroable};
use glam::{Affine3A, Mat3A, Vec3A, Vec4};

use super::skin_error::SkinError;

/// Bones that influence one vertex.
pub(crate) const BONES_PER_VERTEX: usize = 4;

/// Inputs of [`skin`](super::skin) besides the buffers. 16 bytes; keep in sync with `SkinParams`
/// in `shaders/skin.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Pod, Zeroable)]
pub struct SkinParams {
    /// Number of vertices of the skinned mesh.
    pub vertex_count: u32,
    /// Number of bone matrices; influences naming a bone `>= bone_count` are skipped.
    pub bone_count: u32,
    /// Padding, zero.
    pub _pad: [u32; 2],
}

impl SkinParams {
    /// Parameters for `vertex_count` vertices and `bone_count` bones (padding zeroed).
    pub fn new(vertex_count: u32, bone_count: u32) -> Self {
        Self { vertex_count, bone_count, _pad: [0; 2] }
    }
}

/// One bone's skinning transform `S = current pose × (rest pose)⁻¹`, which carries a rest-pose
/// point (world units) to where the bone has moved it. A 3×4 affine matrix stored as its three
/// rows: `rows[r] = [S_r0, S_r1, S_r2, t_r]`, so `p'_r = rows[r] · (p, 1)` with the translation
/// `t` in world units in the last column. 48 bytes; keep in sync with `SkinBone` in
/// `shaders/skin.wgsl` (`array<vec4<f32>, 3>`, row-major).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct SkinBone {
    /// The rows of the 3×4 matrix: linear part (dimensionless) in the first three columns,
    /// translation (world units) in the fourth.
    pub rows: [[f32; 4]; 3],
}

impl SkinBone {
    /// The bone that does not move anything.
    pub const IDENTITY: Self = Self { rows: [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]] };

    /// The rows of `transform`.
    pub fn from_affine(transform: Affine3A) -> Self {
        let m = transform.matrix3;
        let t = transform.translation;
        Self { rows: [0, 1, 2].map(|r| m.row(r).extend(t[r]).to_array()) }
    }

    /// The transform these rows hold.
    pub fn to_affine(&self) -> Affine3A {
        let [x, y, z] = self.rows.map(Vec4::from_array);
        // Columns of the linear part: the rows' first three entries read downwards.
        let matrix3 = Mat3A::from_cols(Vec3A::new(x.x, y.x, z.x), Vec3A::new(x.y, y.y, z.y), Vec3A::new(x.z, y.z, z.z));
        Affine3A { matrix3, translation: Vec3A::new(x.w, y.w, z.w) }
    }

    /// Whether every entry is finite.
    pub fn is_finite(&self) -> bool {
        self.rows.iter().flatten().all(|v| v.is_finite())
    }
}

/// The bones of one vertex and their weights. 32 bytes; keep in sync with `SkinInfluence` in
/// `shaders/skin.wgsl` (`vec4<u32>`, `vec4<f32>`).
///
/// Valid influences have finite, non-negative weights summing to one within [`WEIGHT_SUM_TOLERANCE`](super::WEIGHT_SUM_TOLERANCE)
/// and name bones below the bone count; pad unused slots with bone 0 and weight 0.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default, Pod, Zeroable)]
pub struct SkinInfluence {
    /// Bone indices into the bone matrices.
    pub bones: [u32; BONES_PER_VERTEX],
    /// Weight of each bone (dimensionless, in [0, 1]).
    pub weights: [f32; BONES_PER_VERTEX],
}

impl SkinInfluence {
    /// A vertex carried by `bone` alone.
    pub fn rigid(bone: u32) -> Self {
        Self { bones: [bone, 0, 0, 0], weights: [1.0, 0.0, 0.0, 0.0] }
    }
}

/// The skinning matrix `current[i] × rest[i]⁻¹` of every bone: `rest[i]` is bone i's
/// bone-to-world pose in the rest (bind) pose, `current[i]` its pose now (world units).
///
/// # Errors
/// [`SkinError::Length`] if the two slices differ in length; [`SkinError::NonFiniteBone`] if a
/// pose holds NaN or ∞ or the product does; [`SkinError::SingularRestPose`] if a rest pose cannot
/// be inverted.
///
/// # Example
/// ```
/// use dentbend::cpu::{SkinBone, skin_bones};
/// use dentbend::glam::{Affine3A, Vec3};
///
/// let rest = [Affine3A::from_translation(Vec3::X)];
/// let current = [Affine3A::from_translation(Vec3::new(1.0, 2.0, 0.0))];
/// let bones = skin_bones(&rest, &current)?;
/// assert_eq!(bones[0], SkinBone::from_affine(Affine3A::from_translation(2.0 * Vec3::Y)));
/// # Ok::<(), dentbend::cpu::SkinError>(())
/// ```
pub fn skin_bones(rest: &[Affine3A], current: &[Affine3A]) -> Result<Vec<SkinBone>, SkinError> {
    if rest.len() != current.len() {
        return Err(SkinError::Length { what: "current bone poses", len: current.len(), expected: rest.len() });
    }
    rest.iter()
        .zip(current)
        .enumerate()
        .map(|(bone, (rest, current))| {
            if !rest.is_finite() || !current.is_finite() {
                return Err(SkinError::NonFiniteBone { bone });
            }
            let det = rest.matrix3.determinant();
            if det == 0.0 || !det.is_finite() {
                return Err(SkinError::SingularRestPose { bone });
            }
            let inverse = rest.inverse();
            if !inverse.is_finite() {
                return Err(SkinError::SingularRestPose { bone });
            }
            let skinning = SkinBone::from_affine(*current * inverse);
            if !skinning.is_finite() {
                return Err(SkinError::NonFiniteBone { bone });
            }
            Ok(skinning)
        })
        .collect()
}
