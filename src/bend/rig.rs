//! A bendable body's rig, engine-neutral (paper §4): the rest mesh, its skeleton, the
//! volumetric-geodesic skinning weights and the sub-bodies each bone simulates as. Every engine
//! that bends (dentbend's own world, Rapier, Bevy) builds its bodies and joints from one of
//! these, splits a bone where a fast hit lands ([`Rig::split`], staged, then
//! [`Rig::apply_split`]) and maps a dent made in the current pose back to the rest mesh
//! ([`Rig::rest_after_pose_dent`]).

use std::sync::Arc;

use glam::{Affine3A, Mat3, Vec3};

use super::{BendError, Skeleton, SkinWeights, SubBodies, WeightCache, WeightParams};
use crate::cpu::{SkinBone, SkinInfluence, SkinParams, skin};
use crate::mesh::TriMesh;

/// Determinant below which a vertex's blended linear part counts as singular (bones turned by
/// nearly 180° against each other: two bones at ½ each turned by θ give cos²(θ/2), 10⁻³ at
/// θ ≈ 176°); the vertex's dominant bone's rotation is inverted instead.
pub(crate) const SINGULAR_BLEND: f32 = 1e-3;

/// The rig of one bendable body.
#[derive(Debug, Clone)]
pub struct Rig {
    rest: TriMesh,
    skeleton: Skeleton,
    /// Shared by copies of one body (the level set and voxel graph are the big part).
    cache: Arc<WeightCache>,
    weights: SkinWeights,
    /// The weights as the skinning kernels take them: up to four per vertex.
    influences: Vec<SkinInfluence>,
    sub_bodies: Arc<SubBodies>,
    density: f32,
}

/// A split of one bone computed and checked, not yet applied ([`Rig::apply_split`]).
#[derive(Debug, Clone)]
pub struct RigSplit {
    skeleton: Skeleton,
    weights: SkinWeights,
    sub_bodies: Arc<SubBodies>,
    /// The bone split; it keeps its index as the first half.
    pub bone: usize,
    /// The new bone (the second half).
    pub new_bone: usize,
    /// Where the halves join (the new bone's head), rest frame, m.
    pub joint_point: Vec3,
    /// Bones whose sub-body changed (ascending; the split bone always), the new bone left out.
    pub changed: Vec<usize>,
}

impl Rig {
    /// The rig of the closed `rest` mesh (rest frame, m) over `skeleton` (same frame): weights
    /// with `params`, sub-bodies at `density` kg/m³.
    ///
    /// # Errors
    /// [`BendError`] for invalid parameters, an open or empty mesh, a skeleton whose weights or
    /// sub-bodies cannot be computed.
    pub fn new(rest: TriMesh, skeleton: Skeleton, params: WeightParams, density: f32) -> Result<Self, BendError> {
        let cache = Arc::new(WeightCache::new(&rest, params)?);
        Self::with_cache(rest, skeleton, cache, density)
    }

    /// As [`new`](Self::new) on a weight cache already built for `rest` (copies of one body
    /// share it).
    ///
    /// # Errors
    /// As [`new`](Self::new); [`BendError::Mismatch`] when `cache` belongs to another mesh.
    pub fn with_cache(
        rest: TriMesh,
        skeleton: Skeleton,
        cache: Arc<WeightCache>,
        density: f32,
    ) -> Result<Self, BendError> {
        let weights = SkinWeights::compute(&rest, &skeleton, &cache)?;
        let sub_bodies = Arc::new(SubBodies::compute(&rest, &weights, cache.level_set(), density)?);
        let influences = influences(&weights);
        Ok(Self { rest, skeleton, cache, weights, influences, sub_bodies, density })
    }

    /// The rest mesh (rest frame, m).
    pub fn rest(&self) -> &TriMesh {
        &self.rest
    }

    /// The skeleton (rest frame).
    pub fn skeleton(&self) -> &Skeleton {
        &self.skeleton
    }

    /// The skinning weights, per rest vertex.
    pub fn weights(&self) -> &SkinWeights {
        &self.weights
    }

    /// The weight cache (level set and voxel graph).
    pub fn cache(&self) -> &Arc<WeightCache> {
        &self.cache
    }

    /// The sub-bodies, one per bone, with their mass properties.
    pub fn sub_bodies(&self) -> &SubBodies {
        &self.sub_bodies
    }

    /// Density of the sub-bodies, kg/m³.
    pub fn density(&self) -> f32 {
        self.density
    }

    /// Up to four influences per vertex, as the skinning kernels take them.
    pub fn influences(&self) -> &[SkinInfluence] {
        &self.influences
    }

    /// The rest mesh skinned by `bones` (each bone's rest → output transform) on the CPU, its
    /// normals those of the skinned positions.
    ///
    /// # Errors
    /// [`BendError::Skin`] for another bone count or non-finite bones.
    pub fn skinned(&self, bones: &[Affine3A]) -> Result<TriMesh, BendError> {
        let bones: Vec<SkinBone> = bones.iter().copied().map(SkinBone::from_affine).collect();
        let n = self.rest.vertex_count();
        let (mut positions, mut normals) = (vec![Vec3::ZERO; n], vec![Vec3::ZERO; n]);
        let params = SkinParams::new(n as u32, bones.len() as u32);
        let rest = (self.rest.positions(), self.rest.normals());
        skin(&params, &bones, rest.0, rest.1, &self.influences, &mut positions, &mut normals)?;
        Ok(TriMesh::new(positions, self.rest.faces().to_vec())?)
    }

    /// `bone`'s part of the rest mesh (an open surface, rest frame; what its collider is built
    /// from).
    ///
    /// # Errors
    /// [`BendError::BoneOutOfRange`]; [`BendError::Mesh`] when the bone owns no triangle.
    pub fn part(&self, bone: usize) -> Result<TriMesh, BendError> {
        self.sub_bodies.sub_mesh(&self.rest, bone).map(|(mesh, _)| mesh)
    }

    /// Where a hit at `rest_point` (rest frame) on `bone` splits it: the point's projection on
    /// the bone; `None` when that is within `min_spacing` m of one of `joints` (rest frame).
    pub fn split_point(
        &self,
        bone: usize,
        rest_point: Vec3,
        min_spacing: f32,
        joints: impl IntoIterator<Item = Vec3>,
    ) -> Option<Vec3> {
        let b = self.skeleton.bones().get(bone)?;
        let on_bone = b.point_at(b.project(rest_point).clamp(0.0, 1.0));
        let crowded = joints.into_iter().any(|j| j.distance(on_bone) < min_spacing);
        (!crowded && rest_point.is_finite()).then_some(on_bone)
    }

    /// Splits `bone` at `rest_point`'s projection on it: the skeleton gains a bone, the split
    /// bone's weights are computed again (the others' stay), and the sub-bodies are recut.
    /// Nothing changes until [`apply_split`](Self::apply_split). `Ok(None)` when either half
    /// would be shorter than `min_bone_length` m or within
    /// 5 % of an end, or would own no triangle or
    /// no inside cell at this resolution.
    ///
    /// # Errors
    /// A weight computation that fails (a bug); nothing changed.
    pub fn split(&self, bone: usize, rest_point: Vec3, min_bone_length: f32) -> Result<Option<RigSplit>, BendError> {
        let Some(b) = self.skeleton.bones().get(bone) else {
            return Err(BendError::BoneOutOfRange { bone, count: self.skeleton.len() });
        };
        let (length, t) = (b.length(), b.project(rest_point));
        if !rest_point.is_finite() || t * length < min_bone_length || (1.0 - t) * length < min_bone_length {
            return Ok(None);
        }
        let mut skeleton = self.skeleton.clone();
        let (first, second) = match skeleton.split_bone(bone, rest_point) {
            Ok(halves) => halves,
            Err(BendError::SplitNearEnd { .. }) => return Ok(None),
            Err(e) => return Err(e),
        };
        let weights = self.weights.after_split(&self.rest, &skeleton, bone, (first, second), &self.cache)?;
        let sub_bodies = SubBodies::compute(&self.rest, &weights, self.cache.level_set(), self.density)?;
        if sub_bodies.bodies().iter().any(|s| s.mass.is_none() || s.triangles.is_empty()) {
            log::debug!("split of bone {bone} skipped: a half owns no cell or triangle");
            return Ok(None);
        }
        let changed = (0..self.skeleton.len())
            .filter(|&k| {
                let (old, new) = (&self.sub_bodies.bodies()[k], &sub_bodies.bodies()[k]);
                k == bone || old.triangles != new.triangles || old.cell_count != new.cell_count
            })
            .collect();
        let joint_point = skeleton.bones()[second].head;
        Ok(Some(RigSplit {
            skeleton,
            weights,
            sub_bodies: Arc::new(sub_bodies),
            bone: first,
            new_bone: second,
            joint_point,
            changed,
        }))
    }

    /// Applies a split this rig computed.
    ///
    /// # Errors
    /// [`BendError::Mismatch`] for a split of another rig (another vertex count); the rig is
    /// unchanged then.
    pub fn apply_split(&mut self, split: RigSplit) -> Result<(), BendError> {
        if split.weights.vertex_count() != self.rest.vertex_count() || split.skeleton.len() != self.skeleton.len() + 1 {
            let (expected, actual) = (self.skeleton.len() + 1, split.skeleton.len());
            return Err(BendError::Mismatch { what: "bones of a split of this rig", expected, actual });
        }
        self.influences = influences(&split.weights);
        (self.skeleton, self.weights, self.sub_bodies) = (split.skeleton, split.weights, split.sub_bodies);
        Ok(())
    }

    /// The rest mesh after a dent made in a pose: `base` is the rest mesh the dent started from
    /// (the rig's, or a progressive dent's pre-dent copy: the same faces), `skinned` it skinned
    /// by the bones' `transforms` (rest → the frame the dent was made in), `dented` the same
    /// dented, `moved` the vertices the dent moved. Each moved vertex's displacement Δ maps back as
    /// (Σₖ wₖ Rₖ)⁻¹ Δ, Rₖ the bones' linear parts and wₖ the skinning weights (the weight
    /// missing from 1 on the identity, as the skinning kernel blends it), so skinning the result
    /// gives the dented mesh back; a vertex whose blend is singular (determinant below 10⁻³) takes
    /// its dominant bone's inverse rotation.
    ///
    /// # Errors
    /// [`BendError::Mismatch`] for meshes or transforms of another rig, [`BendError::Mesh`]
    /// for a non-finite result.
    pub fn rest_after_pose_dent(
        &self,
        base: &TriMesh,
        skinned: &TriMesh,
        dented: &TriMesh,
        moved: &[u32],
        transforms: &[Affine3A],
    ) -> Result<TriMesh, BendError> {
        let count = self.rest.vertex_count();
        let counts = [
            ("base vertices", base.vertex_count()),
            ("skinned vertices", skinned.vertex_count()),
            ("dented vertices", dented.vertex_count()),
        ];
        for (what, actual) in counts {
            if actual != count {
                return Err(BendError::Mismatch { what, expected: count, actual });
            }
        }
        if transforms.len() != self.skeleton.len() {
            let (expected, actual) = (self.skeleton.len(), transforms.len());
            return Err(BendError::Mismatch { what: "bone transforms", expected, actual });
        }
        let linear: Vec<Mat3> = transforms.iter().map(|t| Mat3::from(t.matrix3)).collect();
        let mut positions = base.positions().to_vec();
        for &v in moved {
            let Some(rest) = positions.get_mut(v as usize) else { continue };
            let delta = dented.positions()[v as usize] - skinned.positions()[v as usize];
            *rest += self.unblend(v as usize, &linear, delta);
        }
        let mut rest = base.clone();
        rest.set_positions(positions)?;
        Ok(rest)
    }

    /// The bones whose sub-body owns a face touching a vertex of `moved` (ascending).
    pub fn bones_owning(&self, moved: &[u32]) -> Vec<usize> {
        let mut flags = vec![false; self.rest.vertex_count()];
        for &v in moved {
            if let Some(f) = flags.get_mut(v as usize) {
                *f = true;
            }
        }
        let mut owns = vec![false; self.skeleton.len()];
        for (face, &bone) in self.rest.faces().iter().zip(self.sub_bodies.triangle_bones()) {
            if face.iter().any(|&v| flags[v as usize])
                && let Some(o) = owns.get_mut(bone as usize)
            {
                *o = true;
            }
        }
        (0..owns.len()).filter(|&k| owns[k]).collect()
    }

    /// Replaces the rest mesh by `rest` (a dent mapped back: the same faces and vertex count).
    /// Weights, level set and sub-bodies are kept: a dent is plastic flow, not loss of material.
    ///
    /// # Errors
    /// [`BendError::Mismatch`] for another vertex count or other faces; the rig is unchanged.
    pub fn set_rest(&mut self, rest: TriMesh) -> Result<(), BendError> {
        if rest.vertex_count() != self.rest.vertex_count() || rest.faces() != self.rest.faces() {
            let (expected, actual) = (self.rest.vertex_count(), rest.vertex_count());
            return Err(BendError::Mismatch { what: "rest mesh (same faces and vertices)", expected, actual });
        }
        self.rest = rest;
        Ok(())
    }

    /// Displacement `delta` of skinned vertex `v` mapped back through the inverse of its blended
    /// linear part (`linear`: each bone's), blended as the skinning kernel blends it.
    fn unblend(&self, v: usize, linear: &[Mat3], delta: Vec3) -> Vec3 {
        let SkinInfluence { bones, weights } = &self.influences[v];
        let mut blend = Mat3::ZERO;
        let mut total = 0.0;
        let mut dominant = (f32::NEG_INFINITY, Mat3::IDENTITY);
        for (&bone, &w) in bones.iter().zip(weights) {
            let Some(&m) = linear.get(bone as usize) else { continue };
            blend += m * w;
            total += w;
            if w > dominant.0 {
                dominant = (w, m);
            }
        }
        blend += Mat3::IDENTITY * (1.0 - total);
        if blend.determinant().abs() > SINGULAR_BLEND {
            blend.inverse() * delta
        } else {
            dominant.1.transpose() * delta
        }
    }
}

/// `weights` as the skinning kernels take them.
fn influences(weights: &SkinWeights) -> Vec<SkinInfluence> {
    weights.influences4().into_iter().map(|(bones, weights)| SkinInfluence { bones, weights }).collect()
}
