//! Bringing an [`Asset`]'s attributes through a dent: new vertices interpolate every attribute
//! from their parents, new faces keep their parent face's group, and authored normals (and the
//! tangents on them) are recomputed around what moved, each vertex from the faces of its own
//! side, so hard edges stay hard.

use std::collections::HashMap;

use glam::{Vec3, Vec4};

use super::asset::{Skin, VertexAttributes, check_attributes};
use super::trimesh::face_area_normal;
use super::{Asset, MeshError, RefineError, Refinement, TriMesh};

/// Coincident vertices whose normals before the dent lie within this cosine (about 1°) of each
/// other are one smooth vertex split only for another attribute (a UV seam): their normals are
/// recomputed together. Farther apart, they are two sides of a hard edge.
const SAME_SIDE_COS: f32 = 0.999_85;

impl Asset {
    /// Follows a dent of this asset's mesh: `dented` is the dented mesh (this one's vertices and
    /// faces first, then what `refinement` appended), `moved` the vertices the dent moved (as
    /// `damage::DentedTarget::moved` lists them; new vertices count as moved either way).
    ///
    /// - A new vertex's attributes blend its two parents' at its `fraction` t: UVs and colours
    ///   linearly (its parents lie on its own side of any seam, so this is right per side);
    ///   normals linearly, then renormalised; tangents' xyz linearly, then made perpendicular to
    ///   the normal, with w (handedness) the nearer parent's (a's for t < ½); skin weights: both
    ///   parents' influences, weighted by 1 − t and t, merged per joint, the four largest kept
    ///   (ties to the lower joint index) and renormalised to sum 1.
    /// - A new face takes its parent face's group.
    /// - Authored normals of vertices that share a face with a moved vertex are recomputed as
    ///   the area-weighted sum of their own faces' normals; coincident vertices whose normals
    ///   agreed within about 1° before (a UV seam, not a hard edge) share their sum. Every other
    ///   normal stays bit-identical. Tangents of recomputed normals are re-orthogonalised.
    ///
    /// # Errors
    /// [`MeshError::DentMismatch`] when `dented`, `refinement` and `moved` do not describe a
    /// dent of this asset's mesh (counts, a parent index, a moved index out of range); the
    /// asset is unchanged then.
    pub fn follow_dent(&mut self, dented: TriMesh, refinement: &Refinement, moved: &[u32]) -> Result<(), MeshError> {
        check_dent(&self.mesh, &dented, refinement, moved)?;
        let count = dented.vertex_count();
        let mut flags = vec![false; count];
        moved.iter().for_each(|&v| flags[v as usize] = true);
        flags[self.mesh.vertex_count()..].iter_mut().for_each(|f| *f = true);
        let attributes = interpolate(&self.attributes, refinement);
        let mut attributes = attributes.map_err(|e| MeshError::DentMismatch {
            what: "attribute entries for the refinement's base vertices",
            expected: refinement.base_vertex_count,
            actual: match e {
                super::RefineError::AttributeCount { actual, .. } => actual,
                _ => 0,
            },
        })?;
        if let Some(normals) = attributes.normals.as_mut() {
            let affected = affected(&dented, &flags);
            recompute_normals(&dented, &affected, normals);
            if let Some(tangents) = attributes.tangents.as_mut() {
                let base = self.mesh.vertex_count();
                for v in (0..count).filter(|&v| affected[v] || v >= base) {
                    tangents[v] = orthogonal_tangent(tangents[v], normals[v]);
                }
            }
        }
        check_attributes(&attributes, count)?;
        let mut face_groups = self.face_groups.clone();
        face_groups.extend(refinement.face_parents.iter().map(|&f| self.face_groups[f as usize]));
        self.replace_checked(dented, attributes, face_groups);
        Ok(())
    }
}

/// Every attribute extended to the new vertices (see [`Asset::follow_dent`] for the rules).
fn interpolate(old: &VertexAttributes, r: &Refinement) -> Result<VertexAttributes, RefineError> {
    if r.vertices.is_empty() {
        // Also an empty `Refinement::default()`, whose base counts are zero.
        return Ok(old.clone());
    }
    let lerp2 = |s: &Vec<glam::Vec2>| r.interpolate(s, |a, b, t| a.lerp(*b, t));
    let lerp4 = |s: &Vec<Vec4>| r.interpolate(s, |a, b, t| a.lerp(*b, t));
    let normal = |a: &Vec3, b: &Vec3, t| a.lerp(*b, t).normalize_or_zero();
    let tangent = |a: &Vec4, b: &Vec4, t| a.truncate().lerp(b.truncate(), t).extend(nearer(a, b, t).w);
    Ok(VertexAttributes {
        uvs: old.uvs.iter().map(lerp2).collect::<Result<_, _>>()?,
        normals: old.normals.as_ref().map(|n| r.interpolate(n, normal)).transpose()?,
        tangents: old.tangents.as_ref().map(|s| r.interpolate(s, tangent)).transpose()?,
        colors: old.colors.iter().map(lerp4).collect::<Result<_, _>>()?,
        skin: old.skin.as_ref().map(|s| follow_skin(s, r)).transpose()?,
    })
}

/// Checks that `dented`, `refinement` and `moved` describe one dent of `mesh`.
fn check_dent(mesh: &TriMesh, dented: &TriMesh, refinement: &Refinement, moved: &[u32]) -> Result<(), MeshError> {
    let mismatch = |what, expected, actual| match expected == actual {
        true => Ok(()),
        false => Err(MeshError::DentMismatch { what, expected, actual }),
    };
    let (vertices, faces) = (mesh.vertex_count(), mesh.face_count());
    if !refinement.is_empty() {
        mismatch("the refinement's base vertex count", vertices, refinement.base_vertex_count)?;
        mismatch("the refinement's base face count", faces, refinement.base_face_count)?;
    }
    mismatch("the dented mesh's vertex count", vertices + refinement.added_vertices(), dented.vertex_count())?;
    mismatch("the dented mesh's face count", faces + refinement.added_faces(), dented.face_count())?;
    for (k, s) in refinement.vertices.iter().enumerate() {
        let limit = vertices + k;
        if let Some(&p) = s.parents.iter().find(|&&p| p as usize >= limit) {
            return Err(MeshError::DentMismatch { what: "a new vertex's parent", expected: limit, actual: p as usize });
        }
    }
    if let Some(&f) = refinement.face_parents.iter().find(|&&f| f as usize >= faces) {
        return Err(MeshError::DentMismatch { what: "a new face's parent", expected: faces, actual: f as usize });
    }
    match moved.iter().find(|&&v| v as usize >= dented.vertex_count()) {
        None => Ok(()),
        Some(&v) => {
            Err(MeshError::DentMismatch { what: "a moved vertex", expected: dented.vertex_count(), actual: v as usize })
        }
    }
}

/// `a` for t < ½, else `b`.
fn nearer<'a, T>(a: &'a T, b: &'a T, t: f32) -> &'a T {
    if t < 0.5 { a } else { b }
}

/// Skin influences of the new vertices (see [`Asset::follow_dent`] for the rule).
fn follow_skin(skin: &Skin, refinement: &Refinement) -> Result<Skin, RefineError> {
    let pairs: Vec<([u16; 4], Vec4)> = skin.joints.iter().copied().zip(skin.weights.iter().copied()).collect();
    let merged = refinement.interpolate(&pairs, merge_influences)?;
    Ok(Skin { joints: merged.iter().map(|p| p.0).collect(), weights: merged.iter().map(|p| p.1).collect() })
}

/// Both parents' influences weighted by 1 − t and t, merged per joint, the four largest kept.
fn merge_influences(a: &([u16; 4], Vec4), b: &([u16; 4], Vec4), t: f32) -> ([u16; 4], Vec4) {
    let mut all: Vec<(u16, f32)> = Vec::with_capacity(8);
    let sides = [(a, 1.0 - t), (b, t)];
    for ((joints, weights), share) in sides {
        for (&joint, weight) in joints.iter().zip(weights.to_array()) {
            match all.iter_mut().find(|(j, _)| *j == joint) {
                Some((_, w)) => *w += weight * share,
                None => all.push((joint, weight * share)),
            }
        }
    }
    all.sort_by(|x, y| y.1.total_cmp(&x.1).then(x.0.cmp(&y.0)));
    all.resize(4, (0, 0.0));
    let sum: f32 = all[..4].iter().map(|p| p.1).sum();
    let scale = if sum > 0.0 { 1.0 / sum } else { 1.0 };
    let joints = [all[0].0, all[1].0, all[2].0, all[3].0];
    (joints, Vec4::new(all[0].1, all[1].1, all[2].1, all[3].1) * scale)
}

/// Vertices that share a face with a flagged one.
fn affected(mesh: &TriMesh, flags: &[bool]) -> Vec<bool> {
    let mut out = vec![false; mesh.vertex_count()];
    for f in mesh.faces().iter().filter(|f| f.iter().any(|&v| flags[v as usize])) {
        f.iter().for_each(|&v| out[v as usize] = true);
    }
    out
}

/// Recomputes `normals` of the `affected` vertices from their own faces (area-weighted), summed
/// over coincident vertices whose normals agreed before (see [`SAME_SIDE_COS`]).
fn recompute_normals(mesh: &TriMesh, affected: &[bool], normals: &mut [Vec3]) {
    let mut sums = vec![Vec3::ZERO; mesh.vertex_count()];
    for f in mesh.faces().iter().filter(|f| f.iter().any(|&v| affected[v as usize])) {
        let n = face_area_normal(mesh.positions(), f);
        f.iter().for_each(|&v| sums[v as usize] += n);
    }
    let mut at: HashMap<[u32; 3], Vec<Vec<u32>>> = HashMap::new();
    for v in (0..mesh.vertex_count()).filter(|&v| affected[v]) {
        let key = mesh.positions()[v].to_array().map(f32::to_bits);
        let sides = at.entry(key).or_default();
        match sides.iter_mut().find(|side| normals[side[0] as usize].dot(normals[v]) >= SAME_SIDE_COS) {
            Some(side) => side.push(v as u32),
            None => sides.push(vec![v as u32]),
        }
    }
    for side in at.values().flatten() {
        let sum: Vec3 = side.iter().map(|&v| sums[v as usize]).sum();
        for &v in side {
            let n = &mut normals[v as usize];
            *n = sum.try_normalize().unwrap_or(*n);
        }
    }
}

/// `tangent`'s xyz made unit and perpendicular to `normal` (any perpendicular if it was along
/// it), w (the handedness) kept: a tangent re-orthogonalised after its normal changed.
pub fn orthogonal_tangent(tangent: Vec4, normal: Vec3) -> Vec4 {
    let t = tangent.truncate();
    let along = t - normal * normal.dot(t);
    let xyz =
        along.try_normalize().unwrap_or_else(|| normal.try_normalize().unwrap_or(Vec3::Z).any_orthonormal_vector());
    xyz.extend(tangent.w)
}
