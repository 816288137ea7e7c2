//! GPU twin of [`TriMesh::recompute_normals`](crate::TriMesh::recompute_normals) (and, per
//! target, of [`recompute_normals_near`](crate::TriMesh::recompute_normals_near)): area-weighted
//! unit vertex normals of many meshes in one dispatch.
//!
//! WGSL has no float atomics, so each vertex gathers its faces through a CSR adjacency built
//! once per mesh by [`adjacency`] (faces listed in ascending order, so every sum runs in the
//! CPU's face order).

use bytemuck::{Pod, Zeroable};
use glam::{Vec3, Vec4};

use super::{Binding, GpuContext, GpuError, Kernel, buffers};

/// Invocations per workgroup along x. Keep in sync with `WORKGROUP` in `shaders/normals.wgsl`.
pub(crate) const WORKGROUP: u32 = 64;

/// Targets per dispatch: the parameter blocks travel in one 16 KiB uniform buffer (the downlevel
/// uniform binding limit), since the four storage bindings are taken. Keep in sync with
/// `NORMALS_MAX_TARGETS` in `shaders/normals.wgsl`.
pub const MAX_TARGETS_PER_DISPATCH: usize = 512;

/// Where one target's data sits in the batched buffers of a normals dispatch. 32 bytes; keep in
/// sync with `NormalsParams` in `shaders/normals.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Pod, Zeroable)]
pub struct NormalsParams {
    /// Number of vertices.
    pub vertex_count: u32,
    /// First vertex of the target in the position and normal buffers (vertices).
    pub vertex_offset: u32,
    /// First triangle of the target in the face buffer (triangles, 3 u32 each); its vertex
    /// indices are relative to `vertex_offset`.
    pub face_offset: u32,
    /// First u32 of the target's [`adjacency`] block in the adjacency buffer; its face indices
    /// are relative to `face_offset`.
    pub adjacency_offset: u32,
    /// 1: recompute only the vertices that share a face with a vertex whose moved flag
    /// (position `w`) is set, like `recompute_normals_near`; 0: every vertex.
    pub moved_only: u32,
    /// Padding, zero.
    pub _pad: [u32; 3],
}

/// The vertex → faces adjacency of a mesh in the CSR layout `normals.wgsl` reads:
/// `vertex_count + 1` offsets, then for each vertex the indices of the faces touching it in
/// ascending order (a face appears once per corner on the vertex). Offsets count from the start
/// of the returned block, so `block[v]..block[v + 1]` are vertex v's entries.
///
/// # Panics
/// If a face names a vertex `>= vertex_count`.
pub fn adjacency(vertex_count: usize, faces: &[[u32; 3]]) -> Vec<u32> {
    let mut counts = vec![0u32; vertex_count + 1];
    for &v in faces.iter().flatten() {
        counts[v as usize + 1] += 1;
    }
    let header = vertex_count as u32 + 1;
    let mut block = Vec::with_capacity(header as usize + 3 * faces.len());
    let mut total = header;
    for count in &counts[1..] {
        block.push(total);
        total += count;
    }
    block.push(total);
    block.resize(total as usize, 0);
    let mut next: Vec<u32> = block[..vertex_count].to_vec();
    for (f, face) in faces.iter().enumerate() {
        for &v in face {
            block[next[v as usize] as usize] = f as u32;
            next[v as usize] += 1;
        }
    }
    block
}

/// One mesh of a [`Normals::run_batch`] batch.
#[derive(Debug, Clone, Copy)]
pub struct NormalsTarget<'a> {
    /// Vertex positions, world units.
    pub positions: &'a [Vec3],
    /// Triangles as vertex-index triples.
    pub faces: &'a [[u32; 3]],
    /// `None` recomputes every normal; `Some((moved, normals))` only those of vertices sharing a
    /// face with a moved vertex (one flag per vertex), the others keep `normals` (one per vertex).
    pub near: Option<(&'a [bool], &'a [Vec3])>,
}

/// The `normals` kernel, compiled once.
#[derive(Debug)]
pub struct Normals {
    kernel: Kernel,
}

impl Normals {
    /// Compiles the kernel.
    ///
    /// # Errors
    /// [`GpuError::Validation`] if the shader does not compile on this device.
    pub fn new(context: &GpuContext) -> Result<Self, GpuError> {
        let bindings = [Binding::Uniform, Binding::Read, Binding::Read, Binding::Read, Binding::ReadWrite];
        let kernel = Kernel::new(context, "normals", super::shaders::body("normals"), "main", &bindings)?;
        Ok(Self { kernel })
    }

    /// Records the dispatches that write the unit normals of the targets `params` describes into
    /// `normals` (`vec4` per vertex, w = 0), reading `positions` (`vec4`: xyz world position, w
    /// moved flag), `faces` (3 u32 per triangle) and `adjacency` (the [`adjacency`] blocks). One
    /// dispatch per [`MAX_TARGETS_PER_DISPATCH`] targets; their uniform buffers are created here.
    ///
    /// # Errors
    /// [`GpuError::OverLimit`] if a target has more than 4,194,240 (65,535 workgroups of 64) vertices.
    #[allow(clippy::too_many_arguments, reason = "the four bound buffers plus the batch description")]
    pub fn encode(
        &self,
        context: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        params: &[NormalsParams],
        positions: &wgpu::Buffer,
        faces: &wgpu::Buffer,
        adjacency: &wgpu::Buffer,
        normals: &wgpu::Buffer,
    ) -> Result<(), GpuError> {
        let limit = context.limits.max_compute_workgroups_per_dimension;
        for chunk in params.chunks(MAX_TARGETS_PER_DISPATCH) {
            let groups = chunk.iter().map(|p| p.vertex_count).max().unwrap_or(0).div_ceil(WORKGROUP);
            if groups > limit {
                let what = "normals workgroups (vertices per target / WORKGROUP)";
                return Err(GpuError::OverLimit { what: what.into(), needed: groups as u64, limit: limit as u64 });
            }
            if groups == 0 {
                continue;
            }
            // The shader declares a fixed-size array: the uniform must hold all of it.
            let mut block = [NormalsParams::default(); MAX_TARGETS_PER_DISPATCH];
            block[..chunk.len()].copy_from_slice(chunk);
            let uniform = buffers::uniform(context, "normals params", &block);
            let bind = self.kernel.bind(context, &[&uniform, positions, faces, adjacency, normals]);
            self.kernel.dispatch(encoder, &bind, [groups, chunk.len() as u32, 1]);
        }
        Ok(())
    }

    /// Computes the unit vertex normals of every target on the GPU (building their adjacency on
    /// the way) and returns them per target, as
    /// [`TriMesh::recompute_normals`](crate::TriMesh::recompute_normals) (or
    /// `recompute_normals_near` for a target with `near`) would leave them.
    ///
    /// # Errors
    /// [`GpuError::Validation`] for a face index out of range or `near` slices shorter than the
    /// positions; [`GpuError::OverLimit`] for a buffer over the binding limit; as
    /// [`encode`](Self::encode); any device error.
    pub fn run_batch(&self, context: &GpuContext, targets: &[NormalsTarget<'_>]) -> Result<Vec<Vec<Vec3>>, GpuError> {
        let mut params = Vec::with_capacity(targets.len());
        let mut positions: Vec<Vec4> = Vec::new();
        let mut normals: Vec<Vec4> = Vec::new();
        let mut faces: Vec<[u32; 3]> = Vec::new();
        let mut adjacency_buffer: Vec<u32> = Vec::new();
        for (t, target) in targets.iter().enumerate() {
            let n = target.positions.len();
            if target.faces.iter().flatten().any(|&v| v as usize >= n) {
                return Err(batch_error(format!("target {t}: a face names a vertex past its {n} vertices")));
            }
            if target.near.is_some_and(|(moved, normals)| moved.len() < n || normals.len() < n) {
                return Err(batch_error(format!("target {t}: `near` needs a flag and a normal per vertex")));
            }
            params.push(NormalsParams {
                vertex_count: n as u32,
                vertex_offset: positions.len() as u32,
                face_offset: faces.len() as u32,
                adjacency_offset: adjacency_buffer.len() as u32,
                moved_only: target.near.is_some() as u32,
                _pad: [0; 3],
            });
            match target.near {
                Some((moved, old)) => {
                    let flag = |k: usize| if moved[k] { 1.0 } else { 0.0 };
                    positions.extend(target.positions.iter().enumerate().map(|(k, p)| p.extend(flag(k))));
                    normals.extend(old[..n].iter().map(|v| v.extend(0.0)));
                }
                None => {
                    positions.extend(target.positions.iter().map(|p| p.extend(0.0)));
                    normals.extend(std::iter::repeat_n(Vec4::ZERO, n));
                }
            }
            faces.extend_from_slice(target.faces);
            adjacency_buffer.extend(adjacency(n, target.faces));
        }
        buffers::check_binding_size(context, "normals positions", size_of_val(positions.as_slice()) as u64)?;
        buffers::check_binding_size(context, "normals faces", size_of_val(faces.as_slice()) as u64)?;
        buffers::check_binding_size(context, "normals adjacency", size_of_val(adjacency_buffer.as_slice()) as u64)?;

        let positions_buffer = buffers::storage(context, "normals positions", &positions);
        let faces_buffer = buffers::storage(context, "normals faces", &faces);
        let adjacency_gpu = buffers::storage(context, "normals adjacency", &adjacency_buffer);
        let normals_buffer = buffers::storage(context, "normals out", &normals);
        let mut encoder = context.device.create_command_encoder(&Default::default());
        context.scoped("normals", || {
            self.encode(
                context,
                &mut encoder,
                &params,
                &positions_buffer,
                &faces_buffer,
                &adjacency_gpu,
                &normals_buffer,
            )
        })??;
        context.queue.submit([encoder.finish()]);
        let out: Vec<Vec4> = buffers::read_back(context, &normals_buffer, normals.len())?;
        Ok(params
            .iter()
            .map(|p| {
                let start = p.vertex_offset as usize;
                out[start..start + p.vertex_count as usize].iter().map(|v| v.truncate()).collect()
            })
            .collect())
    }
}

fn batch_error(message: String) -> GpuError {
    GpuError::Validation { label: "normals batch".into(), message }
}
