//! GPU twin of [`cpu::skin`](crate::cpu::skin): linear blend skinning of a parent mesh, one
//! invocation per vertex.
//!
//! A mesh's rest positions, rest normals and influences go to the GPU once
//! ([`Skin::upload`], validated there); each frame only the bone matrices travel
//! ([`Skin::encode`], at most [`MAX_BONES`] × 48 bytes). The skinned positions and normals stay
//! in the [`SkinMesh`]'s output buffers, which a renderer can bind as vertex buffers and the
//! `displace` and `normals` kernels as position buffers (`vec4` per vertex, w = 0) without a
//! read-back; [`Skin::run`] reads them back.
//!
//! ```no_run
//! use dentbend::cpu::{SkinInfluence, skin_bones};
//! use dentbend::glam::{Affine3A, Vec3};
//! use dentbend::gpu::{GpuContext, skin::Skin};
//!
//! let context = GpuContext::new()?;
//! let mesh = dentbend::mesh::builtin("plank")?;
//! let skin = Skin::new(&context)?;
//! // Every vertex on bone 0 of a one-bone skeleton.
//! let influences = vec![SkinInfluence::rigid(0); mesh.vertex_count()];
//! let resident = skin.upload(&context, mesh.positions(), mesh.normals(), &influences, 1)?;
//! let rest = [Affine3A::IDENTITY];
//! for frame in 0..3 {
//!     let pose = [Affine3A::from_translation(Vec3::Y * frame as f32)];
//!     let skinned = skin.run(&context, &resident, &skin_bones(&rest, &pose)?)?;
//!     assert_eq!(skinned.positions.len(), mesh.vertex_count());
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use bytemuck::{Pod, Zeroable};
use glam::{Vec3, Vec4};

use super::{Binding, GpuContext, GpuError, Kernel, buffers};
pub use crate::cpu::Skinned;
use crate::cpu::{SkinBone, SkinError, SkinInfluence, SkinParams, check_length};

/// Invocations per workgroup along x. Keep in sync with `WORKGROUP` in `shaders/skin.wgsl`.
pub(crate) const WORKGROUP: u32 = 64;

/// Most bones one mesh may have on the GPU: the bone matrices travel in one uniform buffer of
/// `MAX_BONES` × 48 bytes (12 KiB, inside the 16 KiB downlevel uniform binding limit). Keep in
/// sync with `SKIN_MAX_BONES` in `shaders/skin.wgsl`.
pub const MAX_BONES: usize = 256;

/// One rest vertex as the shader reads it: both vectors padded to `vec4`. 32 bytes; keep in sync
/// with `SkinRest` in `shaders/skin.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
struct SkinRest {
    /// xyz: rest position, world units; w: 0.
    position: [f32; 4],
    /// xyz: rest normal (unit); w: 0.
    normal: [f32; 4],
}

/// The `skin` kernel, compiled once.
#[derive(Debug)]
pub struct Skin {
    kernel: Kernel,
}

/// A mesh resident on the GPU for skinning: its rest vertices and influences (uploaded once), a
/// uniform for the bone matrices (rewritten each frame) and the output buffers.
#[derive(Debug)]
pub struct SkinMesh {
    params: SkinParams,
    bones: wgpu::Buffer,
    positions: wgpu::Buffer,
    normals: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
}

impl SkinMesh {
    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.params.vertex_count as usize
    }

    /// Number of bones the influences were validated against; [`Skin::encode`] takes exactly
    /// this many matrices.
    pub fn bone_count(&self) -> usize {
        self.params.bone_count as usize
    }

    /// The skinned positions after the last submitted [`Skin::encode`]: `vec4` per vertex, xyz in
    /// world units, w = 0 (a vertex buffer with stride 16 and a `Float32x3` attribute at offset
    /// 0, or a storage buffer). Usages: `STORAGE | VERTEX | COPY_SRC | COPY_DST`.
    pub fn positions(&self) -> &wgpu::Buffer {
        &self.positions
    }

    /// The skinned unit normals after the last submitted [`Skin::encode`], laid out as
    /// [`positions`](Self::positions).
    pub fn normals(&self) -> &wgpu::Buffer {
        &self.normals
    }
}

impl Skin {
    /// Compiles the kernel.
    ///
    /// # Errors
    /// [`GpuError::Validation`] if the shader does not compile on this device.
    pub fn new(context: &GpuContext) -> Result<Self, GpuError> {
        let bindings =
            [Binding::Uniform, Binding::Uniform, Binding::Read, Binding::Read, Binding::ReadWrite, Binding::ReadWrite];
        let kernel = Kernel::new(context, "skin", super::shaders::body("skin"), "main", &bindings)?;
        Ok(Self { kernel })
    }

    /// Validates a mesh's rest data and uploads it: rest positions (world units) and normals,
    /// one [`SkinInfluence`] per vertex naming bones below `bone_count`. The outputs start out
    /// zero until the first [`encode`](Self::encode) is submitted.
    ///
    /// # Errors
    /// [`SkinError::Length`] if the slices differ in length; [`SkinError::NonFiniteRest`] or a
    /// bad influence (see [`SkinInfluence`]); [`GpuError::OverLimit`]
    /// for more than [`MAX_BONES`] bones, more than 4,194,240 (65,535 workgroups of 64) vertices or a buffer over the
    /// binding limit; any device error.
    pub fn upload(
        &self,
        context: &GpuContext,
        rest_positions: &[Vec3],
        rest_normals: &[Vec3],
        influences: &[SkinInfluence],
        bone_count: u32,
    ) -> Result<SkinMesh, SkinError> {
        let n = rest_positions.len();
        check_length("rest normals", rest_normals.len(), n)?;
        check_length("influences", influences.len(), n)?;
        if bone_count as usize > MAX_BONES {
            return Err(over_limit("skin bones", bone_count as u64, MAX_BONES as u64));
        }
        let groups = (n as u64).div_ceil(WORKGROUP as u64);
        let limit = context.limits.max_compute_workgroups_per_dimension as u64;
        if groups > limit {
            return Err(over_limit("skin workgroups (vertices / WORKGROUP)", groups, limit));
        }
        SkinInfluence::validate_all(rest_positions, rest_normals, influences, bone_count)?;
        let rest: Vec<SkinRest> = rest_positions
            .iter()
            .zip(rest_normals)
            .map(|(p, n)| SkinRest { position: p.extend(0.0).to_array(), normal: n.extend(0.0).to_array() })
            .collect();
        let output_bytes = (n * size_of::<Vec4>()) as u64;
        buffers::check_binding_size(context, "skin rest vertices", size_of_val(rest.as_slice()) as u64)?;
        buffers::check_binding_size(context, "skin influences", size_of_val(influences) as u64)?;
        buffers::check_binding_size(context, "skin outputs", output_bytes)?;

        let params = SkinParams::new(n as u32, bone_count);
        let mesh = context.scoped("skin upload", || {
            let params_buffer = buffers::uniform(context, "skin params", &params);
            let bones = context.buffer_with_contents(
                "skin bones",
                &[0; MAX_BONES * size_of::<SkinBone>()],
                wgpu::BufferUsages::UNIFORM,
            );
            let rest = buffers::storage(context, "skin rest vertices", &rest);
            let influences = buffers::storage(context, "skin influences", influences);
            let positions = output(context, "skin positions", output_bytes);
            let normals = output(context, "skin normals", output_bytes);
            // The bind group keeps the params, rest and influence buffers alive (wgpu frees a
            // buffer once its last handle or bind group is gone).
            let bind_group =
                self.kernel.bind(context, &[&params_buffer, &bones, &rest, &influences, &positions, &normals]);
            SkinMesh { params, bones, positions, normals, bind_group }
        })?;
        Ok(mesh)
    }

    /// Writes this frame's bone matrices (exactly [`SkinMesh::bone_count`] of them, see
    /// [`skin_bones`](crate::cpu::skin_bones)) to the mesh's uniform through the queue and
    /// records the dispatch that skins it into [`SkinMesh::positions`] and
    /// [`SkinMesh::normals`].
    ///
    /// The matrices reach the GPU at the next `queue.submit`, before that submission's command
    /// buffers run: record at most one `encode` per mesh per submission (a second one would
    /// overwrite the first one's bones).
    ///
    /// # Errors
    /// [`SkinError::Length`] for the wrong number of bones; [`SkinError::NonFiniteBone`].
    pub fn encode(
        &self,
        context: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        mesh: &SkinMesh,
        bones: &[SkinBone],
    ) -> Result<(), SkinError> {
        SkinBone::validate_all(bones, mesh.params.bone_count)?;
        if !bones.is_empty() {
            context.queue.write_buffer(&mesh.bones, 0, bytemuck::cast_slice(bones));
        }
        let groups = mesh.params.vertex_count.div_ceil(WORKGROUP);
        if groups > 0 {
            self.kernel.dispatch(encoder, &mesh.bind_group, [groups, 1, 1]);
        }
        Ok(())
    }

    /// [`encode`](Self::encode) for many meshes at once: checks every mesh's bones first (nothing
    /// is written or recorded when one is wrong), then writes each mesh's bone matrices and
    /// records all the dispatches in one compute pass. As with `encode`, name each mesh at most
    /// once per submission.
    ///
    /// # Errors
    /// As [`encode`](Self::encode), for the first mesh whose bones are wrong.
    pub fn encode_all(
        &self,
        context: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        jobs: &[(&SkinMesh, &[SkinBone])],
    ) -> Result<(), SkinError> {
        for (mesh, bones) in jobs {
            SkinBone::validate_all(bones, mesh.params.bone_count)?;
        }
        let mut dispatches = Vec::with_capacity(jobs.len());
        for (mesh, bones) in jobs {
            if !bones.is_empty() {
                context.queue.write_buffer(&mesh.bones, 0, bytemuck::cast_slice(bones));
            }
            let groups = mesh.params.vertex_count.div_ceil(WORKGROUP);
            if groups > 0 {
                dispatches.push((&mesh.bind_group, [groups, 1, 1]));
            }
        }
        if !dispatches.is_empty() {
            self.kernel.dispatch_all(encoder, &dispatches);
        }
        Ok(())
    }

    /// Skins `mesh` with `bones` on the GPU and reads the result back: the same as
    /// [`cpu::skin`](crate::cpu::skin) on the uploaded rest data.
    ///
    /// # Errors
    /// As [`encode`](Self::encode); any device error (validation, lost device, a read-back that
    /// times out).
    pub fn run(&self, context: &GpuContext, mesh: &SkinMesh, bones: &[SkinBone]) -> Result<Skinned, SkinError> {
        let mut encoder = context.device.create_command_encoder(&Default::default());
        context.scoped("skin", || self.encode(context, &mut encoder, mesh, bones))??;
        context.queue.submit([encoder.finish()]);
        let skinned = SkinMesh::read_back_all(context, &[mesh])?;
        Ok(skinned.into_iter().next().expect("one mesh read back"))
    }
}

impl SkinMesh {
    /// The skinned vertices of every mesh in `meshes`, after the commands already submitted
    /// (their [`Skin::encode`]s): all read back with one submission and one wait.
    ///
    /// # Errors
    /// Any device error (lost device, a read-back that times out, a mesh larger than the
    /// device's largest buffer).
    pub fn read_back_all(context: &GpuContext, meshes: &[&SkinMesh]) -> Result<Vec<Skinned>, SkinError> {
        let sources: Vec<(&wgpu::Buffer, usize)> = meshes
            .iter()
            .flat_map(|mesh| [(&mesh.positions, mesh.vertex_count()), (&mesh.normals, mesh.vertex_count())])
            .collect();
        let data = buffers::read_back_all_after::<Vec4>(context, None, &sources)?;
        let xyz = |values: &[Vec4]| values.iter().map(|v| v.truncate()).collect();
        Ok(data.chunks_exact(2).map(|pair| Skinned { positions: xyz(&pair[0]), normals: xyz(&pair[1]) }).collect())
    }
}

/// A zeroed output buffer of `bytes` (at least 16) that kernels write and renderers bind as a
/// vertex buffer.
fn output(context: &GpuContext, label: &str, bytes: u64) -> wgpu::Buffer {
    context.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.max(16),
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::VERTEX
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

impl From<GpuError> for SkinError {
    fn from(error: GpuError) -> Self {
        SkinError::Gpu(std::sync::Arc::new(error))
    }
}

fn over_limit(what: &str, needed: u64, limit: u64) -> SkinError {
    GpuError::OverLimit { what: what.into(), needed, limit }.into()
}
