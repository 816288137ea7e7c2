//! The GPU half of [`Skinner`](super::Skinner): the rest meshes and influences of the bending
//! bodies resident on the GPU, skinned by the `skin` kernel with one submission per call.
//!
//! Consecutive bodies share one [`SkinMesh`] (a *group*: their rest vertices one after the other,
//! each body's bones after the previous body's, at most [`MAX_BONES`] bones and
//! 65,536 vertices by default), so that a scene of many small bodies (Figure 13's 2,400 struts)
//! costs a few bone writes and dispatches per call rather than thousands. A group is uploaded
//! again only when one of its bodies' [`rest_revision`](ArticulatedBody::rest_revision) (a
//! dent, a split) or bone count changes; each [`skin`](GpuSkinner::skin) writes only the bone
//! matrices.

use std::ops::Range;

use super::skinning::{bone_matrices, skin_on_cpu};
use super::{ArticulatedBody, Bending};
use crate::sim::{SimError, World};
use dentbend::cpu::{SkinBone, SkinError, SkinInfluence};
use dentbend::gpu::skin::{MAX_BONES, Skin, SkinMesh, Skinned};
use dentbend::gpu::{GpuContext, GpuError};

/// What a body's upload depends on: its rest revision, vertex count and bone count.
type Key = (u64, usize, usize);

/// The bending bodies of a [`Bending`] resident on the GPU for the `skin` kernel.
#[derive(Debug)]
pub struct GpuSkinner {
    context: &'static GpuContext,
    skin: Skin,
    /// Covering the first bodies in order (all of them after a [`sync`](Self::sync)).
    groups: Vec<Group>,
    group_vertices: usize,
    uploads: usize,
}

/// Consecutive bodies skinned together.
#[derive(Debug)]
struct Group {
    /// The first body's index in [`Bending::bodies`].
    start: usize,
    /// Each member's key when the group was uploaded.
    keys: Vec<Key>,
    /// Each member's first vertex in the group's buffers, then the group's vertex count.
    offsets: Vec<usize>,
    residence: Residence,
}

/// Where a group is skinned.
#[derive(Debug)]
enum Residence {
    /// Resident on the GPU.
    Gpu(SkinMesh),
    /// Over the device's limits (a body of more than [`MAX_BONES`] bones, or buffers larger than
    /// a binding): each member skinned by the CPU twin into its outputs here.
    Cpu(Vec<Skinned>),
}

impl GpuSkinner {
    /// Compiles the `skin` kernel on `context`; groups hold at most `group_vertices` vertices
    /// (at least one body each; 65,536 vertices by default in [`Skinner`](super::Skinner)).
    /// Nothing is uploaded before the first [`sync`](Self::sync).
    ///
    /// # Errors
    /// [`SimError::GpuSkinning`] if the kernel does not compile on this device.
    pub fn new(context: &'static GpuContext, group_vertices: usize) -> Result<Self, SimError> {
        let skin = Skin::new(context).map_err(gpu_error)?;
        Ok(Self { context, skin, groups: Vec::new(), group_vertices, uploads: 0 })
    }

    /// Groups uploaded so far (each group at the first sync, then one per group changed).
    pub fn uploads(&self) -> usize {
        self.uploads
    }

    /// The number of groups now.
    pub fn groups(&self) -> usize {
        self.groups.len()
    }

    /// Where bending body `body` is resident: its group's mesh (whose output buffers hold the
    /// last [`skin`](Self::skin), for a renderer to bind) and the body's vertex range in it;
    /// `None` for a body skinned on the CPU or not synced yet.
    pub fn resident(&self, body: usize) -> Option<(&SkinMesh, Range<usize>)> {
        let group = self.groups.iter().find(|g| (g.start..g.start + g.keys.len()).contains(&body))?;
        let member = body - group.start;
        match &group.residence {
            Residence::Gpu(mesh) => Some((mesh, group.offsets[member]..group.offsets[member + 1])),
            Residence::Cpu(_) => None,
        }
    }

    /// Brings the GPU's copies in line with `bending`'s bodies: keeps every group whose bodies
    /// are unchanged, uploads again each group with a body whose rest revision, vertex or bone
    /// count changed (split in two where it outgrew the limits), and groups and uploads new
    /// bodies. Returns how many groups it uploaded. A body over the device's limits is skinned on
    /// the CPU from then on (logged at each upload).
    ///
    /// # Errors
    /// [`SimError::GpuSkinning`] for a device error; [`SimError::BadShape`] for rest data the
    /// kernel refuses (weights not summing to one, a bone index past the body's bones…). The
    /// groups uploaded before the error stay.
    pub fn sync(&mut self, bending: &Bending) -> Result<usize, SimError> {
        let bodies = bending.bodies();
        let keys: Vec<Key> = bodies.iter().map(key).collect();
        let before = self.uploads;
        let mut next = 0;
        for group in std::mem::take(&mut self.groups) {
            let end = group.start + group.keys.len();
            if group.start != next || end > keys.len() {
                break;
            }
            if keys[group.start..end] == group.keys[..] {
                self.groups.push(group);
            } else {
                self.upload_range(bodies, &keys, group.start..end)?;
            }
            next = end;
        }
        self.upload_range(bodies, &keys, next..keys.len())?;
        Ok(self.uploads - before)
    }

    /// Groups the bodies of `range` and uploads each group.
    fn upload_range(&mut self, bodies: &[ArticulatedBody], keys: &[Key], range: Range<usize>) -> Result<(), SimError> {
        for members in pack(keys, range, self.group_vertices) {
            let group = self.upload(bodies, keys, members)?;
            self.groups.push(group);
            self.uploads += 1;
        }
        Ok(())
    }

    /// Uploads the rest data of the bodies `members` as one group, or falls back to the CPU when
    /// it is over the device's limits.
    fn upload(&self, bodies: &[ArticulatedBody], keys: &[Key], members: Range<usize>) -> Result<Group, SimError> {
        let group = &bodies[members.clone()];
        let mut offsets = vec![0];
        let (mut positions, mut normals, mut influences) = (Vec::new(), Vec::new(), Vec::new());
        let mut base = 0u32;
        for body in group {
            let rest = body.rest_mesh();
            let bones = body.skeleton().len() as u32;
            // Checked body by body, against the body's own bones: once offset, a bad index would
            // name the next body's bone instead of being skipped.
            let fail = |e| body.skin_error(e);
            SkinInfluence::validate_all(rest.positions(), rest.normals(), body.influences(), bones).map_err(fail)?;
            positions.extend_from_slice(rest.positions());
            normals.extend_from_slice(rest.normals());
            influences.extend(
                body.influences()
                    .iter()
                    .map(|i| SkinInfluence { bones: i.bones.map(|b| b + base), weights: i.weights }),
            );
            base += bones;
            offsets.push(positions.len());
        }
        let residence = match self.skin.upload(self.context, &positions, &normals, &influences, base) {
            Ok(mesh) => Residence::Gpu(mesh),
            Err(SkinError::Gpu(error)) if matches!(error.downcast_ref(), Some(GpuError::OverLimit { .. })) => {
                let names: Vec<&str> = group.iter().map(ArticulatedBody::name).collect();
                log::warn!("bending bodies {names:?} are skinned on the CPU: {error}");
                Residence::Cpu(vec![Skinned::default(); group.len()])
            }
            Err(SkinError::Gpu(error)) => return Err(gpu_error(format!("bending bodies from {members:?}: {error}"))),
            Err(error) => return Err(group[0].skin_error(error)),
        };
        Ok(Group { start: members.start, keys: keys[members].to_vec(), offsets, residence })
    }

    /// Skins every body of `bending` to its sub-bodies' poses in `world`: [`sync`](Self::sync),
    /// then each group's bone matrices (its bodies' sub-bodies' model transforms) written to its
    /// uniform and one dispatch per group, all in one compute pass and one submission, and a wait
    /// for it (so that a device error surfaces here, and a caller's timing covers the kernel's
    /// work). The results stay on the GPU until [`read_back`](Self::read_back).
    ///
    /// # Errors
    /// As [`sync`](Self::sync); [`SimError::Invalid`] if a sub-body is missing from `world`;
    /// [`SimError::BadShape`] for a bone transform that is not finite.
    pub fn skin(&mut self, bending: &Bending, world: &World) -> Result<(), SimError> {
        self.sync(bending)?;
        let bodies = bending.bodies();
        let mut group_bones: Vec<Vec<SkinBone>> = Vec::with_capacity(self.groups.len());
        for group in &mut self.groups {
            let members = &bodies[group.start..group.start + group.keys.len()];
            match &mut group.residence {
                Residence::Gpu(mesh) => {
                    let mut bones = Vec::with_capacity(mesh.bone_count());
                    for body in members {
                        let matrices = bone_matrices(body, world)?;
                        SkinBone::validate_all(&matrices, matrices.len() as u32).map_err(|e| body.skin_error(e))?;
                        bones.extend(matrices);
                    }
                    group_bones.push(bones);
                }
                Residence::Cpu(outputs) => {
                    for (body, out) in members.iter().zip(outputs) {
                        skin_on_cpu(body, &bone_matrices(body, world)?, out)?;
                    }
                }
            }
        }
        let meshes = self.groups.iter().filter_map(|g| match &g.residence {
            Residence::Gpu(mesh) => Some(mesh),
            Residence::Cpu(_) => None,
        });
        let jobs: Vec<(&SkinMesh, &[SkinBone])> = meshes.zip(&group_bones).map(|(m, b)| (m, b.as_slice())).collect();
        if jobs.is_empty() {
            return Ok(());
        }
        let context = self.context;
        let mut encoder = context.device.create_command_encoder(&Default::default());
        context
            .scoped("skinning", || self.skin.encode_all(context, &mut encoder, &jobs))
            .map_err(gpu_error)?
            .map_err(gpu_error)?;
        context.queue.submit([encoder.finish()]);
        context.wait().map_err(gpu_error)
    }

    /// Reads the last [`skin`](Self::skin)'s results back, one per body in [`Bending::bodies`]
    /// order (all groups with one copy and one wait); zero before the first skin.
    ///
    /// # Errors
    /// [`SimError::GpuSkinning`] if the read-back fails.
    pub fn read_back(&self) -> Result<Vec<Skinned>, SimError> {
        let meshes: Vec<&SkinMesh> = self
            .groups
            .iter()
            .filter_map(|group| match &group.residence {
                Residence::Gpu(mesh) => Some(mesh),
                Residence::Cpu(_) => None,
            })
            .collect();
        let mut data = SkinMesh::read_back_all(self.context, &meshes).map_err(gpu_error)?.into_iter();
        let mut skinned = Vec::new();
        for group in &self.groups {
            match &group.residence {
                Residence::Gpu(_) => {
                    let whole = data.next().ok_or_else(|| gpu_error("the read-back returned too few meshes"))?;
                    skinned.extend(group.offsets.windows(2).map(|range| Skinned {
                        positions: whole.positions[range[0]..range[1]].to_vec(),
                        normals: whole.normals[range[0]..range[1]].to_vec(),
                    }));
                }
                Residence::Cpu(outputs) => skinned.extend(outputs.iter().cloned()),
            }
        }
        Ok(skinned)
    }
}

/// Splits the bodies `range` (keys: `keys`) into runs of consecutive bodies of at most
/// [`MAX_BONES`] bones and `group_vertices` vertices together, or of one body over either.
fn pack(keys: &[Key], range: Range<usize>, group_vertices: usize) -> Vec<Range<usize>> {
    let mut runs = Vec::new();
    let (mut start, mut vertices, mut bones) = (range.start, 0, 0);
    for k in range.clone() {
        let (_, v, b) = keys[k];
        if k > start && (bones + b > MAX_BONES || vertices + v > group_vertices) {
            runs.push(start..k);
            (start, vertices, bones) = (k, 0, 0);
        }
        vertices += v;
        bones += b;
    }
    if start < range.end {
        runs.push(start..range.end);
    }
    runs
}

/// What `body`'s upload depends on.
fn key(body: &ArticulatedBody) -> Key {
    (body.rest_revision(), body.rest_mesh().vertex_count(), body.skeleton().len())
}

/// A [`SimError::GpuSkinning`] with `error`'s message.
fn gpu_error(error: impl std::fmt::Display) -> SimError {
    SimError::GpuSkinning(error.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Keys of bodies with these (vertices, bones).
    fn keys(sizes: &[(usize, usize)]) -> Vec<Key> {
        sizes.iter().map(|&(v, b)| (0, v, b)).collect()
    }

    #[test]
    fn packing_keeps_groups_within_the_bone_and_vertex_limits() {
        // 200 + 56 bones fill a group; one more bone starts the next.
        let k = keys(&[(10, 200), (10, 56), (10, 1), (10, 2)]);
        assert_eq!(pack(&k, 0..4, 1000), [0..2, 2..4]);
        assert_eq!(pack(&k, 0..4, 30), [0..2, 2..4]);
        // 30 vertices at most: three bodies of 10, then the fourth alone.
        assert_eq!(pack(&keys(&[(10, 1); 4]), 0..4, 30), [0..3, 3..4]);
        // A body over either limit is a group of its own.
        let k = keys(&[(5, 1), (50, 1), (5, 300), (5, 1)]);
        assert_eq!(pack(&k, 0..4, 20), [0..1, 1..2, 2..3, 3..4]);
        // Only the range given; nothing for an empty one.
        assert_eq!(pack(&k, 3..4, 20), vec![Range { start: 3, end: 4 }]);
        assert!(pack(&k, 2..2, 20).is_empty());
    }
}
