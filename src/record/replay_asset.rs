//! Carrying a game asset's attributes along a replay: each [`ReplayStep`] applied to the
//! [`Asset`] of the mesh it started from, so a body restored from a damage file keeps its UVs,
//! authored normals and the rest, as the body that was damaged did.

use std::collections::HashMap;

use super::ReplayStep;
use crate::dent::changed_vertices;
use crate::fracture::carry_asset;
use crate::mesh::{Asset, MeshError, Refinement, SplitVertex};

impl ReplayStep<'_> {
    /// Brings `asset` (an asset of this step's `before` mesh) through the step: an edit's new
    /// vertices interpolate their edge's attributes ([`splits`](Self::splits),
    /// [`Asset::follow_dent`]) and its new faces take the group of a face of `before` at one of
    /// their corners; a fracture's rest takes its attributes from where its vertices lie
    /// ([`carry_asset`]).
    ///
    /// # Errors
    /// [`MeshError::DentMismatch`] when `asset` is not of `before`'s mesh (its vertex or face
    /// count), or the edit is no refinement of it (faces removed, a face slot holding corners
    /// of another face, a new vertex on no edge: `before` and `after` are not one damage
    /// history apart); `asset` is unchanged then.
    pub fn carry(&self, asset: &mut Asset) -> Result<(), MeshError> {
        let (before, expected) = match self {
            Self::Edited { before, .. } | Self::Broke { before, .. } => (*before, asset.mesh()),
        };
        let mismatch = |what, expected, actual| MeshError::DentMismatch { what, expected, actual };
        if expected.vertex_count() != before.vertex_count() || expected.face_count() != before.face_count() {
            return Err(mismatch(
                "the asset's vertex count, as the step's mesh before",
                before.vertex_count(),
                expected.vertex_count(),
            ));
        }
        match self {
            Self::Edited { before, after } => {
                if after.face_count() < before.face_count() {
                    return Err(mismatch(
                        "faces after an edit, at least as many as before",
                        before.face_count(),
                        after.face_count(),
                    ));
                }
                let vertices = self.splits();
                if !is_refinement(before.faces(), after.faces(), before.vertex_count() as u32, &vertices) {
                    return Err(mismatch("an edit that refines the mesh before (its faces and splits)", 0, 1));
                }
                let base = before.vertex_count() as u32;
                let face_parents = corner_faces(before.faces(), base, &vertices, &after.faces()[before.face_count()..]);
                let refinement = Refinement {
                    base_vertex_count: before.vertex_count(),
                    base_face_count: before.face_count(),
                    vertices,
                    face_parents,
                    ..Refinement::default()
                };
                asset.follow_dent((*after).clone(), &refinement, &changed_vertices(before, after))
            }
            Self::Broke { rest, origins, .. } => {
                *asset = carry_asset(asset, (*rest).clone(), origins)?;
                Ok(())
            }
        }
    }
}

/// For each of `new_faces`, a face of `faces` (over `base` vertices) at one of its corners: its
/// first corner taken back through `splits` (vertex `base + k` came from `splits[k]`) to an
/// old vertex, and the first old face there (face 0 when none is).
fn corner_faces(faces: &[[u32; 3]], base: u32, splits: &[SplitVertex], new_faces: &[[u32; 3]]) -> Vec<u32> {
    let mut first_face: HashMap<u32, u32> = HashMap::new();
    for (f, face) in faces.iter().enumerate() {
        for &v in face {
            first_face.entry(v).or_insert(f as u32);
        }
    }
    let root = |mut v: u32| {
        while v >= base {
            match splits.get((v - base) as usize) {
                Some(s) => v = s.parents[0],
                None => break,
            }
        }
        v
    };
    new_faces.iter().map(|f| first_face.get(&root(f[0])).copied().unwrap_or(0)).collect()
}

/// Whether `after` is `before` (over `base` vertices) moved and refined: no face removed, each
/// old face's slot holding only its own corners and new vertices, each new vertex on an edge
/// (`splits` with two different parents).
fn is_refinement(before: &[[u32; 3]], after: &[[u32; 3]], base: u32, splits: &[SplitVertex]) -> bool {
    after.len() >= before.len()
        && splits.iter().all(|s| s.parents[0] != s.parents[1])
        && before.iter().zip(after).all(|(old, new)| new.iter().all(|v| *v >= base || old.contains(v)))
}
