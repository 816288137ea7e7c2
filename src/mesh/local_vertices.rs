//! Local numbers for the few vertices of a large mesh that a computation touches: dense indices
//! into its own small arrays, in the order the vertices were met, and the way back.

/// No local number.
const NONE: u32 = u32::MAX;

/// Some vertices of a mesh, numbered locally in the order added.
pub(crate) struct LocalVertices {
    /// Local number of each mesh vertex, or [`NONE`].
    number: Vec<u32>,
    /// Mesh vertex of each local number.
    pub(crate) vertices: Vec<u32>,
}

impl LocalVertices {
    /// None yet, for a mesh of `vertex_count` vertices.
    pub(crate) fn new(vertex_count: usize) -> Self {
        Self { number: vec![NONE; vertex_count], vertices: Vec::new() }
    }

    /// Numbers `v` if it has no number yet.
    pub(crate) fn add(&mut self, v: u32) {
        if self.number[v as usize] == NONE {
            self.number[v as usize] = self.vertices.len() as u32;
            self.vertices.push(v);
        }
    }

    /// Numbers the corners of the faces `chosen` of `faces` that have none yet.
    pub(crate) fn add_corners(&mut self, faces: &[[u32; 3]], chosen: &[u32]) {
        chosen.iter().flat_map(|&f| faces[f as usize]).for_each(|v| self.add(v));
    }

    /// The local number of `v`, if it has one.
    pub(crate) fn get(&self, v: u32) -> Option<usize> {
        self.number.get(v as usize).filter(|&&k| k != NONE).map(|&k| k as usize)
    }

    /// The local number of `v`, which must have one.
    pub(crate) fn of(&self, v: u32) -> usize {
        debug_assert!(self.get(v).is_some(), "vertex {v} has no local number");
        self.number[v as usize] as usize
    }

    /// How many vertices are numbered.
    pub(crate) fn len(&self) -> usize {
        self.vertices.len()
    }

    /// Forgets every number, at the cost of the vertices numbered (not of the mesh).
    pub(crate) fn clear(&mut self) {
        self.vertices.iter().for_each(|&v| self.number[v as usize] = NONE);
        self.vertices.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vertices_are_numbered_once_in_the_order_met() {
        let mut local = LocalVertices::new(10);
        local.add_corners(&[[4, 2, 7], [2, 7, 9]], &[0, 1]);
        local.add(4);
        local.add(0);
        assert_eq!(local.vertices, [4, 2, 7, 9, 0]);
        assert_eq!((local.of(9), local.get(0), local.get(3), local.get(99)), (3, Some(4), None, None));
        assert_eq!(local.len(), 5);
        // Cleared, every number is forgotten and numbering starts again.
        local.clear();
        assert_eq!((local.len(), local.get(4), local.get(9)), (0, None, None));
        local.add(9);
        assert_eq!((local.of(9), local.vertices.as_slice()), (0, &[9][..]));
    }
}
