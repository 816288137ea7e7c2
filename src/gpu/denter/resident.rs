//! The targets a [`GpuDenter`](super::GpuDenter) keeps on the device, and the host's copy of
//! each.
//!
//! Every target lives in one slice of four shared buffers: positions and normals (`vec4<f32>`
//! per vertex), triangles (3 u32, indices relative to the target's first vertex) and the
//! vertex→face adjacency block the `normals` kernel reads. The host keeps a mirror of each target
//! (its [`TriMesh`]: positions bit for bit the device's, triangles, and normals as the CPU
//! pipeline keeps them), so the stages that run on the host (refinement, the fitted falloff, the
//! guard, the volume rim) read the surface without reading it back; after a batch only the
//! vertices the kernels moved come back ([`super::stages`]).
//!
//! A target that refinement grew is written back into its slice when it fits there; otherwise
//! every target is laid out afresh, the grown ones with half as much room again, so a target
//! dented over and over is laid out again only a few times.

use std::ops::Range;

use crate::gpu::displace::WORKGROUP;
use crate::gpu::normals::adjacency;
use crate::gpu::{GpuContext, GpuError, buffers};
use crate::mesh::TriMesh;

/// Vertices and triangles of room a grown target gets beyond half its size again.
const GROWTH_ALLOWANCE: u32 = 64;

/// One resident target: its mirror and where it sits in the shared buffers.
#[derive(Debug, Clone)]
pub(super) struct Resident {
    /// The host's copy of the target.
    pub(super) mesh: TriMesh,
    /// The mirror's mean edge length, world units (sets automatic grids).
    pub(super) mean_edge: f32,
    /// First vertex in the position and normal buffers.
    pub(super) first_vertex: u32,
    /// Vertices its slice holds.
    pub(super) vertex_room: u32,
    /// First triangle in the face buffer.
    pub(super) face_offset: u32,
    /// Triangles its slice holds.
    pub(super) face_room: u32,
    /// First u32 of its adjacency block.
    pub(super) adjacency_offset: u32,
    /// u32s its adjacency slice holds.
    pub(super) adjacency_room: u32,
    /// Kernels recorded into a caller's encoder moved it since the mirror was last updated: the
    /// mirror is read back before the host next needs it.
    pub(super) behind: bool,
    /// Refinement grew it: laid out with room to grow again.
    pub(super) grows: bool,
}

impl Resident {
    /// A target not yet laid out.
    pub(super) fn new(mesh: TriMesh) -> Self {
        Self {
            mean_edge: mesh.mean_edge_length(),
            mesh,
            first_vertex: 0,
            vertex_room: 0,
            face_offset: 0,
            face_room: 0,
            adjacency_offset: 0,
            adjacency_room: 0,
            behind: false,
            grows: false,
        }
    }

    /// `mesh` in this target's slices (which it must [`fit`](Self::fits)), current on the device
    /// once uploaded.
    pub(super) fn placed_as(&self, mesh: TriMesh) -> Self {
        Self { mean_edge: mesh.mean_edge_length(), mesh, behind: false, ..*self }
    }

    /// Its vertices in the position and normal buffers.
    pub(super) fn vertices(&self) -> Range<u32> {
        self.first_vertex..self.first_vertex + self.mesh.vertex_count() as u32
    }

    /// Whether `mesh` fits in this target's slices.
    pub(super) fn fits(&self, mesh: &TriMesh) -> bool {
        let (vertices, faces) = (mesh.vertex_count() as u64, mesh.face_count() as u64);
        vertices <= u64::from(self.vertex_room)
            && faces <= u64::from(self.face_room)
            && vertices + 1 + 3 * faces <= u64::from(self.adjacency_room)
    }

    /// The room a layout gives it: its size, or half as much again (and a little) if it grows.
    fn room(&self) -> (u64, u64) {
        let (vertices, faces) = (self.mesh.vertex_count() as u64, self.mesh.face_count() as u64);
        if self.grows {
            let more = |n: u64| n + n / 2 + u64::from(GROWTH_ALLOWANCE);
            (more(vertices), more(faces))
        } else {
            (vertices, faces)
        }
    }
}

/// The shared buffers every resident target lives in.
#[derive(Debug)]
pub(super) struct ResidentBuffers {
    /// `vec4<f32>` per vertex: xyz world units, w = moved in the current batch.
    pub(super) positions: wgpu::Buffer,
    /// Unit normals, `vec4<f32>` per vertex (w unused).
    pub(super) normals: wgpu::Buffer,
    /// Triangles, 3 u32 each, relative to their target's first vertex.
    pub(super) faces: wgpu::Buffer,
    /// Each target's vertex→face block ([`adjacency`]), face indices relative to its first face.
    pub(super) adjacency: wgpu::Buffer,
}

impl ResidentBuffers {
    /// Lays `targets` out one after another (each with the room [`Resident::room`] gives it),
    /// sets their offsets, and uploads their mirrors; `usage` adds to the vertex and normal
    /// buffers' `STORAGE | COPY_SRC | COPY_DST`.
    ///
    /// # Errors
    /// [`GpuError::OverLimit`] when the targets do not fit one storage binding, or have more
    /// vertices than the moved-flag clear can dispatch over; device errors (a lost device,
    /// caught in an error scope); nothing is changed then.
    pub(super) fn lay_out(
        context: &GpuContext,
        targets: &mut [Resident],
        usage: wgpu::BufferUsages,
    ) -> Result<Self, GpuError> {
        let mut offsets = Vec::with_capacity(targets.len());
        let (mut vertices, mut faces, mut words) = (0u64, 0u64, 0u64);
        for target in targets.iter() {
            let (vertex_room, face_room) = target.room();
            offsets.push((vertices, vertex_room, faces, face_room, words, vertex_room + 1 + 3 * face_room));
            vertices += vertex_room;
            faces += face_room;
            words += vertex_room + 1 + 3 * face_room;
        }
        check_sizes(context, vertices, faces, words)?;
        context.check_alive()?;
        let buffers = context.scoped("resident buffers", || Self::create(context, targets, &offsets, usage))?;
        for (target, &(v, vr, f, fr, a, ar)) in targets.iter_mut().zip(&offsets) {
            (target.first_vertex, target.vertex_room) = (v as u32, vr as u32);
            (target.face_offset, target.face_room) = (f as u32, fr as u32);
            (target.adjacency_offset, target.adjacency_room) = (a as u32, ar as u32);
        }
        Ok(buffers)
    }

    /// The buffers of a layout (`offsets`: per target, its first vertex, vertex room, first
    /// face, face room, first adjacency word and adjacency room), holding `targets`' mirrors.
    fn create(
        context: &GpuContext,
        targets: &[Resident],
        offsets: &[(u64, u64, u64, u64, u64, u64)],
        usage: wgpu::BufferUsages,
    ) -> Self {
        let (vertices, faces, words) =
            offsets.last().map_or((0, 0, 0), |&(v, vr, f, fr, a, ar)| (v + vr, f + fr, a + ar));
        let mut position_words = vec![[0f32; 4]; vertices as usize];
        let mut normal_words = vec![[0f32; 4]; vertices as usize];
        let mut face_words = vec![[0u32; 3]; faces as usize];
        let mut adjacency_words = vec![0u32; words as usize];
        for (target, &(first, _, f, _, a, _)) in targets.iter().zip(offsets) {
            let first = first as usize;
            let slice = first..first + target.mesh.vertex_count();
            position_words[slice.clone()].copy_from_slice(&vec4s(target.mesh.positions()));
            normal_words[slice].copy_from_slice(&vec4s(target.mesh.normals()));
            let f = f as usize;
            face_words[f..f + target.mesh.face_count()].copy_from_slice(target.mesh.faces());
            let block = adjacency(target.mesh.vertex_count(), target.mesh.faces());
            let a = a as usize;
            adjacency_words[a..a + block.len()].copy_from_slice(&block);
        }
        let vertex_usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | usage;
        let bytes = |data: &[[f32; 4]]| bytemuck::cast_slice::<[f32; 4], u8>(data).to_vec();
        Self {
            positions: context.buffer_with_contents("resident positions", &bytes(&position_words), vertex_usage),
            normals: context.buffer_with_contents("resident normals", &bytes(&normal_words), vertex_usage),
            faces: buffers::storage(context, "resident faces", &face_words),
            adjacency: buffers::storage(context, "resident adjacency", &adjacency_words),
        }
    }

    /// Writes `target`'s mirror into its slices (moved flags cleared), through the queue: it
    /// lands before the next submission. The caller has checked that it [`fits`](Resident::fits).
    ///
    /// # Errors
    /// Device errors (a lost device), caught in an error scope.
    pub(super) fn upload(&self, context: &GpuContext, target: &Resident) -> Result<(), GpuError> {
        context.scoped("resident target upload", || self.write_target(context, target))
    }

    /// [`upload`](Self::upload)'s writes.
    fn write_target(&self, context: &GpuContext, target: &Resident) {
        let queue = &context.queue;
        let first = u64::from(target.first_vertex) * 16;
        queue.write_buffer(&self.positions, first, bytemuck::cast_slice(&vec4s(target.mesh.positions())));
        queue.write_buffer(&self.normals, first, bytemuck::cast_slice(&vec4s(target.mesh.normals())));
        if target.mesh.face_count() > 0 {
            let faces = bytemuck::cast_slice(target.mesh.faces());
            queue.write_buffer(&self.faces, u64::from(target.face_offset) * 12, faces);
        }
        let block = adjacency(target.mesh.vertex_count(), target.mesh.faces());
        queue.write_buffer(&self.adjacency, u64::from(target.adjacency_offset) * 4, bytemuck::cast_slice(&block));
    }

    /// Writes `positions` of `target`'s vertices `first..` (with moved flags `moved`, one per
    /// position) through the queue. Call inside an error scope ([`GpuContext::scoped`]).
    pub(super) fn write_positions(
        &self,
        context: &GpuContext,
        target: &Resident,
        first: usize,
        positions: &[glam::Vec3],
        moved: &[bool],
    ) {
        let data: Vec<[f32; 4]> =
            positions.iter().zip(moved).map(|(p, &m)| [p.x, p.y, p.z, f32::from(u8::from(m))]).collect();
        let offset = (u64::from(target.first_vertex) + first as u64) * 16;
        context.queue.write_buffer(&self.positions, offset, bytemuck::cast_slice(&data));
    }
}

/// `vec4`s with w = 0.
fn vec4s(values: &[glam::Vec3]) -> Vec<[f32; 4]> {
    values.iter().map(|v| v.extend(0.0).to_array()).collect()
}

/// Checks a layout of `vertices`, `faces` and `words` adjacency u32s against the device.
fn check_sizes(context: &GpuContext, vertices: u64, faces: u64, words: u64) -> Result<(), GpuError> {
    buffers::check_binding_size(context, "resident vertices", vertices * 16)?;
    buffers::check_binding_size(context, "resident faces", faces * 12)?;
    buffers::check_binding_size(context, "resident adjacency", words * 4)?;
    // The moved-flag clear runs one invocation per resident vertex in a 1-D dispatch.
    let max_vertices = u64::from(context.limits.max_compute_workgroups_per_dimension) * u64::from(WORKGROUP);
    if vertices > max_vertices {
        let what = "resident vertices of all targets".into();
        return Err(GpuError::OverLimit { what, needed: vertices, limit: max_vertices });
    }
    Ok(())
}
