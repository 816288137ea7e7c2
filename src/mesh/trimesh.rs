//! The indexed triangle mesh type shared by every stage of the crate.

use glam::{DVec3, Vec3};

use super::MeshError;

/// An indexed triangle mesh with per-vertex normals.
///
/// Positions are in world units (metres by convention); faces index into the position array and
/// are wound counter-clockwise when seen from outside. Invariants, checked by every constructor:
/// at least one vertex and one face, every coordinate finite, every index in range. Degenerate
/// (zero-area) triangles are allowed; they contribute nothing to normals, area or volume.
#[derive(Debug, Clone, PartialEq)]
pub struct TriMesh {
    positions: Vec<Vec3>,
    faces: Vec<[u32; 3]>,
    normals: Vec<Vec3>,
}

impl TriMesh {
    /// Builds a mesh from positions and faces, validating both and computing vertex normals.
    ///
    /// # Errors
    /// [`MeshError::Empty`], [`MeshError::NonFinite`], [`MeshError::OutOfRange`] (a coordinate
    /// beyond ±[`MAX_COORDINATE`]) or [`MeshError::IndexOutOfRange`].
    ///
    /// # Example
    /// ```
    /// use dentbend::{glam::Vec3, TriMesh};
    /// let tri = TriMesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 2]]).unwrap();
    /// assert_eq!(tri.normals()[0], Vec3::Z);
    /// ```
    pub fn new(positions: Vec<Vec3>, faces: Vec<[u32; 3]>) -> Result<Self, MeshError> {
        validate(&positions, &faces)?;
        let mut mesh = Self { normals: vec![Vec3::ZERO; positions.len()], positions, faces };
        mesh.recompute_normals();
        Ok(mesh)
    }

    /// Builds a mesh with the caller's own vertex normals (an asset's authored ones: hard edges,
    /// smoothing groups), validated like [`new`](Self::new). They are kept bit for bit until the
    /// mesh moves: a dent recomputes only the normals around the vertices it moved
    /// ([`recompute_normals_near`](Self::recompute_normals_near)) and gives new vertices their
    /// parents' normals interpolated.
    ///
    /// # Errors
    /// As [`new`](Self::new); [`MeshError::LengthMismatch`] when `normals` has not one entry per
    /// position, [`MeshError::InvalidParameter`] for a non-finite normal.
    pub fn with_normals(positions: Vec<Vec3>, faces: Vec<[u32; 3]>, normals: Vec<Vec3>) -> Result<Self, MeshError> {
        validate(&positions, &faces)?;
        if normals.len() != positions.len() {
            return Err(MeshError::LengthMismatch { expected: positions.len(), actual: normals.len() });
        }
        if let Some(index) = normals.iter().position(|n| !n.is_finite()) {
            return Err(MeshError::InvalidParameter(format!("normal {index} = {} is not finite", normals[index])));
        }
        Ok(Self { positions, faces, normals })
    }

    /// A mesh from parts the caller guarantees valid, with `normals` (one per vertex) kept
    /// except around the vertices flagged in `moved`, which are recomputed.
    pub(crate) fn from_valid_with_normals(
        positions: Vec<Vec3>,
        faces: Vec<[u32; 3]>,
        normals: Vec<Vec3>,
        moved: &[bool],
    ) -> Self {
        debug_assert!(validate(&positions, &faces).is_ok() && normals.len() == positions.len());
        let mut mesh = Self { positions, faces, normals };
        mesh.recompute_normals_near(moved);
        mesh
    }

    /// Builds a mesh from parts the caller guarantees valid (the crate's own generators and
    /// subdivision), computing vertex normals; the invariants are checked in debug builds only.
    pub(crate) fn from_valid(positions: Vec<Vec3>, faces: Vec<[u32; 3]>) -> Self {
        debug_assert!(validate(&positions, &faces).is_ok());
        let mut mesh = Self { normals: vec![Vec3::ZERO; positions.len()], positions, faces };
        mesh.recompute_normals();
        mesh
    }

    /// Vertex positions, world units.
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// Triangles as vertex-index triples, counter-clockwise seen from outside.
    pub fn faces(&self) -> &[[u32; 3]] {
        &self.faces
    }

    /// Unit vertex normals: area-weighted average of the adjacent face normals (zero for a vertex
    /// touched only by degenerate faces).
    pub fn normals(&self) -> &[Vec3] {
        &self.normals
    }

    /// The mesh's arrays, moved out: positions, faces and normals (as the accessors above).
    pub fn into_parts(self) -> (Vec<Vec3>, Vec<[u32; 3]>, Vec<Vec3>) {
        (self.positions, self.faces, self.normals)
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    pub fn face_count(&self) -> usize {
        self.faces.len()
    }

    /// Replaces every vertex position (same count) and refreshes the normals.
    ///
    /// # Errors
    /// [`MeshError::LengthMismatch`], [`MeshError::NonFinite`] or [`MeshError::OutOfRange`]; the
    /// mesh is unchanged then.
    pub fn set_positions(&mut self, positions: Vec<Vec3>) -> Result<(), MeshError> {
        if positions.len() != self.positions.len() {
            return Err(MeshError::LengthMismatch { expected: self.positions.len(), actual: positions.len() });
        }
        check_finite(&positions)?;
        self.positions = positions;
        self.recompute_normals();
        Ok(())
    }

    /// Mutable positions for the crate's kernels, which keep them finite and refresh normals.
    pub(crate) fn positions_mut(&mut self) -> &mut [Vec3] {
        &mut self.positions
    }

    /// Applies an affine map to every vertex (normals are recomputed).
    ///
    /// # Errors
    /// [`MeshError::NonFinite`] or [`MeshError::OutOfRange`] if the map moves a vertex out of
    /// finite space or beyond ±[`MAX_COORDINATE`]; the mesh is unchanged then.
    pub fn transform(&mut self, matrix: glam::Affine3A) -> Result<(), MeshError> {
        let moved: Vec<Vec3> = self.positions.iter().map(|&p| matrix.transform_point3(p)).collect();
        self.set_positions(moved)
    }

    /// Recomputes every vertex normal from the current positions.
    pub fn recompute_normals(&mut self) {
        self.normals.iter_mut().for_each(|n| *n = Vec3::ZERO);
        for face in &self.faces {
            let area_normal = face_area_normal(&self.positions, face);
            for &v in face {
                self.normals[v as usize] += area_normal;
            }
        }
        self.normals.iter_mut().for_each(|n| *n = n.normalize_or_zero());
    }

    /// Recomputes the normals of the vertices that share a face with a vertex flagged in `moved`
    /// (one flag per vertex; missing flags count as false); cheaper than
    /// [`recompute_normals`](Self::recompute_normals) when a dent touches a small part of a
    /// large mesh.
    pub fn recompute_normals_near(&mut self, moved: &[bool]) {
        let mut flags = vec![false; self.positions.len()];
        flags.iter_mut().zip(moved).for_each(|(f, &m)| *f = m);
        let moved = &flags[..];
        let touches = |f: &[u32; 3], flags: &[bool]| f.iter().any(|&v| flags[v as usize]);
        let mut affected = vec![false; self.positions.len()];
        for face in self.faces.iter().filter(|f| touches(f, moved)) {
            face.iter().for_each(|&v| affected[v as usize] = true);
        }
        for (n, _) in self.normals.iter_mut().zip(&affected).filter(|(_, a)| **a) {
            *n = Vec3::ZERO;
        }
        for face in self.faces.iter().filter(|f| touches(f, &affected)) {
            let area_normal = face_area_normal(&self.positions, face);
            for &v in face.iter().filter(|&&v| affected[v as usize]) {
                self.normals[v as usize] += area_normal;
            }
        }
        for (n, _) in self.normals.iter_mut().zip(&affected).filter(|(_, a)| **a) {
            *n = n.normalize_or_zero();
        }
    }

    /// Axis-aligned bounds `(min, max)`, world units.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.positions
            .iter()
            .fold((Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)), |(lo, hi), &p| (lo.min(p), hi.max(p)))
    }

    /// The vertex of the surface farthest along `direction` (the support point; the first one
    /// on ties): a projectile's most advanced point along its velocity. Vertices no face uses
    /// are not part of the surface and are ignored.
    pub fn support_point(&self, direction: Vec3) -> Vec3 {
        // One dot product per corner, the first of equal maxima kept (a plain loop: the
        // flattened iterator chain compiled to several times the work).
        let mut best = self.positions[self.faces[0][0] as usize];
        let mut best_dot = best.dot(direction);
        for face in &self.faces {
            for &v in face {
                let p = self.positions[v as usize];
                let d = p.dot(direction);
                if d > best_dot {
                    (best, best_dot) = (p, d);
                }
            }
        }
        best
    }

    /// Signed enclosed volume (divergence theorem), cubic world units; positive for a closed mesh
    /// wound counter-clockwise seen from outside, meaningless for an open one.
    pub fn volume(&self) -> f32 {
        let origin = self.bounds().0;
        let sum: f64 = self
            .faces
            .iter()
            .map(|f| {
                let [a, b, c] = f.map(|v| (self.positions[v as usize] - origin).as_dvec3());
                a.dot(b.cross(c))
            })
            .sum();
        (sum / 6.0) as f32
    }

    /// Total surface area, square world units.
    pub fn area(&self) -> f32 {
        let total: f64 = self.faces.iter().map(|f| self.face_area(f)).sum();
        total as f32
    }

    /// Whether the surface area exceeds `limit` (square world units): [`area`](Self::area)
    /// `> limit`, summed face by face (in f64, as `area`) and stopped as soon as the sum is past
    /// the limit, so a test against a small threshold usually reads one face.
    pub fn area_exceeds(&self, limit: f64) -> bool {
        let mut total = 0.0f64;
        for f in &self.faces {
            total += self.face_area(f);
            if total > limit {
                return true;
            }
        }
        false
    }

    /// Area of triangle `f`, square world units, in f64.
    fn face_area(&self, f: &[u32; 3]) -> f64 {
        let [a, b, c] = f.map(|v| self.positions[v as usize].as_dvec3());
        0.5 * (b - a).cross(c - a).length()
    }

    /// Mean length of the triangle edges, world units (shared edges count once per face).
    pub fn mean_edge_length(&self) -> f32 {
        self.edge_lengths().mean
    }

    /// The mean (as [`mean_edge_length`](Self::mean_edge_length)) and the longest of the
    /// faces' edge lengths, in one pass, mesh units.
    pub fn edge_lengths(&self) -> EdgeLengths {
        // Three f64 sums and three maxima, one per edge of a face, kept apart so that no face
        // waits on the previous one's additions (a single chain of maxima was most of the time).
        let (mut sum, mut most) = (DVec3::ZERO, Vec3::ZERO);
        for f in &self.faces {
            let [a, b, c] = f.map(|v| self.positions[v as usize]);
            let lengths = Vec3::new(a.distance(b), b.distance(c), c.distance(a));
            sum += lengths.as_dvec3();
            most = most.max(lengths);
        }
        let total = sum.x + sum.y + sum.z;
        EdgeLengths { mean: (total / (3 * self.faces.len()) as f64) as f32, longest: most.max_element() }
    }
}

/// Edge length statistics of a mesh ([`TriMesh::edge_lengths`]), mesh units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeLengths {
    /// Mean over the faces' edges (an edge shared by two faces counts twice).
    pub mean: f32,
    /// Longest edge.
    pub longest: f32,
}

/// Cross product of two edges of `face`: its normal scaled by twice its area.
pub(crate) fn face_area_normal(positions: &[Vec3], face: &[u32; 3]) -> Vec3 {
    let [a, b, c] = face.map(|v| positions[v as usize]);
    (b - a).cross(c - a)
}

/// Largest coordinate magnitude a mesh may have, mesh units: 10⁶ (1000 km in metres). Twice
/// a triangle's area needs squared lengths (10¹² here) and a volume needs cubes (10¹⁸), far
/// inside f32's 3.4·10³⁸, while a game world's coordinates rarely pass 10⁵.
pub const MAX_COORDINATE: f32 = 1.0e6;

/// Whether `p` is finite and within ±[`MAX_COORDINATE`] on every axis.
pub(crate) fn in_coordinate_range(p: Vec3) -> bool {
    p.is_finite() && p.abs().max_element() <= MAX_COORDINATE
}

/// Every position finite and within ±[`MAX_COORDINATE`].
fn check_finite(positions: &[Vec3]) -> Result<(), MeshError> {
    let bad = positions.iter().position(|&p| !in_coordinate_range(p));
    match bad {
        Some(index) if !positions[index].is_finite() => {
            Err(MeshError::NonFinite { index, position: positions[index].to_array() })
        }
        Some(index) => {
            Err(MeshError::OutOfRange { index, position: positions[index].to_array(), limit: MAX_COORDINATE })
        }
        None => Ok(()),
    }
}

/// Checks the [`TriMesh`] invariants without building one.
pub fn validate(positions: &[Vec3], faces: &[[u32; 3]]) -> Result<(), MeshError> {
    if positions.is_empty() || faces.is_empty() {
        return Err(MeshError::Empty { vertices: positions.len(), faces: faces.len() });
    }
    check_finite(positions)?;
    for (face, f) in faces.iter().enumerate() {
        if let Some(&index) = f.iter().find(|&&v| v as usize >= positions.len()) {
            return Err(MeshError::IndexOutOfRange { face, index, vertex_count: positions.len() });
        }
    }
    Ok(())
}
