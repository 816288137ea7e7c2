//! A mesh's directed edges as one flat table per vertex, for walking or checking its faces.

/// Each vertex's outgoing edges over some faces (edge a → b for every face corner a followed by
/// b), in one flat table: vertex `a`'s are `list[start[a]..start[a + 1]]`, in face order.
pub(crate) struct Outgoing {
    start: Vec<u32>,
    list: Vec<u32>,
}

impl Outgoing {
    /// The outgoing edges of `count` vertices over `faces`.
    pub(crate) fn of(faces: &[[u32; 3]], count: usize) -> Self {
        let mut start = vec![0u32; count + 1];
        for face in faces {
            for &a in face {
                start[a as usize + 1] += 1;
            }
        }
        for k in 0..count {
            start[k + 1] += start[k];
        }
        let mut fill = start.clone();
        let mut list = vec![0u32; start[count] as usize];
        for face in faces {
            for k in 0..3 {
                let (a, b) = (face[k] as usize, face[(k + 1) % 3]);
                list[fill[a] as usize] = b;
                fill[a] += 1;
            }
        }
        Self { start, list }
    }

    /// The vertices `a` has an edge to.
    pub(crate) fn from(&self, a: u32) -> &[u32] {
        &self.list[self.start[a as usize] as usize..self.start[a as usize + 1] as usize]
    }
}
