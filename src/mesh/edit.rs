//! Mesh edits: what changed between two versions of a mesh whose later version only moved
//! vertices, appended vertices and faces, and rewrote faces in place (a dent moves vertices; a
//! local refinement appends vertices and faces and keeps each split face's slot for one of its
//! children). Applying an edit to the earlier version gives the later one bit for bit.

use glam::Vec3;

use super::{MeshError, TriMesh};

/// The difference between a mesh `before` and a mesh `after` with at least as many vertices
/// and faces, where vertex and face indices below `before`'s counts keep their meaning.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MeshEdit {
    /// Vertex count of the mesh the edit applies to.
    pub base_vertices: u32,
    /// Face count of the mesh the edit applies to.
    pub base_faces: u32,
    /// Existing vertices that moved: (index, steps), ascending indices. Each coordinate's new
    /// f32 bits are its old bits plus the step (wrapping u32 arithmetic): exact, and for a
    /// coordinate of one sign the step is the move in units in the last place, small for the
    /// small moves of a dent (see [`step`](Self::step) and [`stepped`](Self::stepped)).
    pub moved: Vec<(u32, [i32; 3])>,
    /// New vertices, numbered from `base_vertices` on.
    pub appended_vertices: Vec<Vec3>,
    /// Existing faces that were rewritten: (index, new vertex indices), ascending indices.
    pub changed_faces: Vec<(u32, [u32; 3])>,
    /// New faces, numbered from `base_faces` on.
    pub appended_faces: Vec<[u32; 3]>,
}

/// Bitwise equality of two positions (distinguishes −0 from +0, as a replay must).
fn same_bits(a: Vec3, b: Vec3) -> bool {
    a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits)
}

impl MeshEdit {
    /// The step from `old` to `new`: per coordinate, the difference of their f32 bits.
    pub fn step(old: Vec3, new: Vec3) -> [i32; 3] {
        let (o, n) = (old.to_array(), new.to_array());
        [0, 1, 2].map(|k| n[k].to_bits().wrapping_sub(o[k].to_bits()) as i32)
    }

    /// `old` moved by `step` (exactly the position [`step`](Self::step) was taken to).
    pub fn stepped(old: Vec3, step: [i32; 3]) -> Vec3 {
        let o = old.to_array();
        Vec3::from_array([0, 1, 2].map(|k| f32::from_bits(o[k].to_bits().wrapping_add(step[k] as u32))))
    }

    /// The edit that turns `before` into `after`.
    ///
    /// # Errors
    /// [`MeshError::InvalidParameter`] when `after` has fewer vertices or faces than `before`
    /// (an edit only appends).
    pub fn between(before: &TriMesh, after: &TriMesh) -> Result<Self, MeshError> {
        let (nv, nf) = (before.vertex_count(), before.face_count());
        if after.vertex_count() < nv || after.face_count() < nf {
            return Err(MeshError::InvalidParameter(format!(
                "a mesh edit only appends: {nv} vertices and {nf} faces became {} and {}",
                after.vertex_count(),
                after.face_count()
            )));
        }
        let (old, new) = (before.positions(), after.positions());
        let moved =
            (0..nv).filter(|&v| !same_bits(old[v], new[v])).map(|v| (v as u32, Self::step(old[v], new[v]))).collect();
        let (old_faces, new_faces) = (before.faces(), after.faces());
        let changed_faces =
            (0..nf).filter(|&f| old_faces[f] != new_faces[f]).map(|f| (f as u32, new_faces[f])).collect();
        Ok(Self {
            base_vertices: nv as u32,
            base_faces: nf as u32,
            moved,
            appended_vertices: new[nv..].to_vec(),
            changed_faces,
            appended_faces: new_faces[nf..].to_vec(),
        })
    }

    /// Whether the edit changes nothing.
    pub fn is_empty(&self) -> bool {
        self.moved.is_empty()
            && self.appended_vertices.is_empty()
            && self.changed_faces.is_empty()
            && self.appended_faces.is_empty()
    }

    /// `mesh` with the edit applied, as a new mesh (normals recomputed from the new positions);
    /// `mesh` itself is not changed.
    ///
    /// # Errors
    /// [`MeshError::LengthMismatch`] when `mesh` does not have the counts the edit was made for;
    /// [`MeshError::InvalidParameter`] for indices out of order or out of range;
    /// as [`TriMesh::new`] for a result that is not a valid mesh.
    pub fn apply(&self, mesh: &TriMesh) -> Result<TriMesh, MeshError> {
        if mesh.vertex_count() != self.base_vertices as usize {
            return Err(MeshError::LengthMismatch {
                expected: self.base_vertices as usize,
                actual: mesh.vertex_count(),
            });
        }
        if mesh.face_count() != self.base_faces as usize {
            return Err(MeshError::LengthMismatch { expected: self.base_faces as usize, actual: mesh.face_count() });
        }
        ascending_below(self.moved.iter().map(|m| m.0), self.base_vertices, "moved vertex")?;
        ascending_below(self.changed_faces.iter().map(|c| c.0), self.base_faces, "changed face")?;
        let mut positions = Vec::with_capacity(mesh.vertex_count() + self.appended_vertices.len());
        positions.extend_from_slice(mesh.positions());
        for &(v, step) in &self.moved {
            positions[v as usize] = Self::stepped(positions[v as usize], step);
        }
        positions.extend_from_slice(&self.appended_vertices);
        let mut faces = Vec::with_capacity(mesh.face_count() + self.appended_faces.len());
        faces.extend_from_slice(mesh.faces());
        for &(f, face) in &self.changed_faces {
            faces[f as usize] = face;
        }
        faces.extend_from_slice(&self.appended_faces);
        TriMesh::new(positions, faces)
    }
}

/// Checks that `indices` ascend strictly and stay below `limit`.
fn ascending_below(indices: impl Iterator<Item = u32>, limit: u32, what: &str) -> Result<(), MeshError> {
    let mut previous: Option<u32> = None;
    for i in indices {
        if i >= limit || previous.is_some_and(|p| i <= p) {
            return Err(MeshError::InvalidParameter(format!(
                "{what} index {i} is out of order or beyond the mesh's {limit}"
            )));
        }
        previous = Some(i);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moved_appended_and_rewritten_round_trip() {
        let before = crate::mesh::builtin("block").unwrap();
        let mut positions = before.positions().to_vec();
        positions[2] += Vec3::new(0.0, -0.1, 0.0);
        positions.push(Vec3::new(0.1, 0.5, 0.1));
        let mut faces = before.faces().to_vec();
        let n = positions.len() as u32 - 1;
        let [a, b, c] = faces[0];
        faces[0] = [a, b, n];
        faces.push([b, c, n]);
        faces.push([c, a, n]);
        let after = TriMesh::new(positions, faces).unwrap();
        let edit = MeshEdit::between(&before, &after).unwrap();
        assert_eq!((edit.moved.len(), edit.appended_vertices.len()), (1, 1));
        assert_eq!((edit.changed_faces.len(), edit.appended_faces.len()), (1, 2));
        let replayed = edit.apply(&before).unwrap();
        assert_eq!(replayed, after);
        assert!(edit.apply(&after).is_err(), "an edit applies only to the mesh it was made for");
    }
}
