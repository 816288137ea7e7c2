//! Indexed f64 meshes for cutting: welding a [`TriMesh`]'s coincident vertices, checking that it
//! is closed, splitting it into connected parts, and turning the result back into a `TriMesh`.

use glam::DVec3;

use super::FractureError;
use super::origin::Location;
use super::outgoing::Outgoing;
use crate::mesh::TriMesh;

/// Vertices (f64, the mesh's coordinates, m) and triangles, counter-clockwise from outside,
/// with where they came from in the welded mesh.
#[derive(Debug, Clone, Default)]
pub(crate) struct Soup {
    pub positions: Vec<DVec3>,
    pub faces: Vec<[u32; 3]>,
    /// Per face: the input face it is.
    pub input_face: Vec<u32>,
    /// Per input vertex: the vertex it became.
    pub welded: Vec<u32>,
    /// Whether any two input vertices became one.
    pub seams: bool,
}

impl Soup {
    /// Each vertex's location: itself.
    pub(crate) fn locations(&self) -> Vec<Location> {
        (0..self.positions.len() as u32).map(Location::Vertex).collect()
    }
}

/// `mesh` with coincident vertices (bit-equal positions, −0 = +0) merged and the faces that
/// collapse dropped; vertices keep the order of their first copy. Without hashing: the copies
/// of one position are neighbours once the vertices are sorted by position bits.
pub(crate) fn weld(mesh: &TriMesh) -> Soup {
    let key = |p: glam::Vec3| {
        let [x, y, z] = (p + glam::Vec3::ZERO).to_array().map(f32::to_bits);
        (u128::from(x) << 64) | (u128::from(y) << 32) | u128::from(z)
    };
    let mut order: Vec<(u128, u32)> = mesh.positions().iter().enumerate().map(|(i, &p)| (key(p), i as u32)).collect();
    order.sort_unstable();
    // Each vertex's first copy (the lowest index of its run).
    let mut first = vec![0u32; order.len()];
    for run in order.chunk_by(|a, b| a.0 == b.0) {
        for &(_, i) in run {
            first[i as usize] = run[0].1;
        }
    }
    let mut positions = Vec::with_capacity(mesh.vertex_count());
    let mut remap = vec![0u32; order.len()];
    for (i, &p) in mesh.positions().iter().enumerate() {
        remap[i] = if first[i] as usize == i {
            positions.push(p.as_dvec3());
            positions.len() as u32 - 1
        } else {
            remap[first[i] as usize]
        };
    }
    let mut faces = Vec::with_capacity(mesh.face_count());
    let mut input_face = Vec::with_capacity(mesh.face_count());
    for (k, face) in mesh.faces().iter().enumerate() {
        let [a, b, c] = face.map(|v| remap[v as usize]);
        if a != b && b != c && c != a {
            faces.push([a, b, c]);
            input_face.push(k as u32);
        }
    }
    let seams = positions.len() < mesh.vertex_count();
    Soup { positions, faces, input_face, welded: remap, seams }
}

/// Checks that `mesh` bounds a solid a pattern can break: once coincident vertices are welded,
/// every edge is shared by two faces of opposite orientation.
///
/// # Errors
/// [`FractureError::OpenMesh`] naming an edge that is not.
pub(crate) fn check_mesh_closed(mesh: &TriMesh) -> Result<(), FractureError> {
    let soup = weld(mesh);
    check_closed(&soup.faces, soup.positions.len())
}

/// Checks that every directed edge of `faces` (over `vertex_count` vertices) is used once and
/// its reverse once: a closed, consistently oriented surface. Linear time: each vertex's
/// outgoing edges in one flat table, checked vertex by vertex.
///
/// # Errors
/// [`FractureError::OpenMesh`] naming the first offending edge in face order.
pub(crate) fn check_closed(faces: &[[u32; 3]], vertex_count: usize) -> Result<(), FractureError> {
    let outgoing = Outgoing::of(faces, vertex_count);
    let from = |a: u32| outgoing.from(a);
    // Edge (a, b) used `forward` times, and its reverse.
    let counts = |a: u32, b: u32| {
        let forward = from(a).iter().filter(|&&x| x == b).count();
        (forward, from(b).iter().filter(|&&x| x == a).count())
    };
    let closed = (0..vertex_count as u32).all(|a| from(a).iter().all(|&b| counts(a, b) == (1, 1)));
    if !closed {
        for face in faces {
            for k in 0..3 {
                let (a, b) = (face[k], face[(k + 1) % 3]);
                let (forward, backward) = counts(a, b);
                if (forward, backward) != (1, 1) {
                    return Err(FractureError::OpenMesh { a, b, count: forward });
                }
            }
        }
    }
    Ok(())
}

/// The indices of `faces` (over `vertex_count` vertices) in groups joined by shared vertices,
/// each group in face order, groups in order of their first face.
pub(crate) fn components(faces: &[[u32; 3]], vertex_count: usize) -> Vec<Vec<usize>> {
    let mut parent: Vec<u32> = (0..vertex_count as u32).collect();
    fn root(parent: &mut [u32], mut v: u32) -> u32 {
        while parent[v as usize] != v {
            parent[v as usize] = parent[parent[v as usize] as usize];
            v = parent[v as usize];
        }
        v
    }
    for f in faces {
        let r0 = root(&mut parent, f[0]);
        for &v in &f[1..] {
            let r = root(&mut parent, v);
            parent[r as usize] = r0;
        }
    }
    // Group of each root, by root id (`u32::MAX`: none yet).
    let mut group_of = vec![u32::MAX; vertex_count];
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for (k, f) in faces.iter().enumerate() {
        let r = root(&mut parent, f[0]) as usize;
        if group_of[r] == u32::MAX {
            group_of[r] = groups.len() as u32;
            groups.push(Vec::new());
        }
        groups[group_of[r] as usize].push(k);
    }
    groups
}
