//! The part of a projectile that can shape a dent: only triangles near the impact point count,
//! so a large projectile (a bunny landing on a small ball) takes its depth origin from the part
//! that hit, not from its farthest point, and the Z-buffer sees fewer triangles.

use glam::{Affine3A, Vec3};

use super::DentSettings;
use crate::mesh::TriMesh;

/// A surface as it dents others: a mesh in its own coordinates and its mesh → world transform
/// (rigid) at the moment of the contact.
#[derive(Debug, Clone, Copy)]
pub struct Surface<'a> {
    /// The surface, in its own coordinates, m.
    pub mesh: &'a TriMesh,
    /// Mesh coordinates → world.
    pub to_world: Affine3A,
}

impl Surface<'_> {
    /// The surface in world coordinates.
    pub fn world_mesh(&self) -> TriMesh {
        let mut mesh = self.mesh.clone();
        // A rigid motion of a valid mesh stays finite; the transform cannot fail.
        let _ = mesh.transform(self.to_world);
        mesh
    }
}

impl DentSettings {
    /// How far from the impact point a projectile can matter for a dent `dent_distance` m deep
    /// in a target of these settings held in a ball of `target_radius` m about its origin: the
    /// target's size (its dent cannot be wider), plus the deepest dent and the Gaussian tails
    /// (4σ), m. A local contact cropped to it loses nothing the dent reads.
    pub fn projectile_reach(&self, target_radius: f32, dent_distance: f32) -> f32 {
        let cap = self.material.cap.max(dent_distance);
        let sigma = self.params.sigma.unwrap_or(0.5 * cap);
        2.0 * target_radius + cap + 4.0 * sigma
    }
}

/// The triangles of `mesh` with a corner within `radius` of `centre` (same coordinates), their
/// vertices renumbered in first-use order; the whole mesh (cloned) when all of it is that
/// close; `None` when no triangle is.
pub(crate) fn crop_to_ball(mesh: &TriMesh, centre: Vec3, radius: f32) -> Option<TriMesh> {
    let near: Vec<bool> = mesh.positions().iter().map(|p| p.distance_squared(centre) <= radius * radius).collect();
    if near.iter().all(|&n| n) {
        return Some(mesh.clone());
    }
    let mut index = vec![u32::MAX; mesh.vertex_count()];
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    for face in mesh.faces() {
        if !face.iter().any(|&v| near[v as usize]) {
            continue;
        }
        faces.push(face.map(|v| {
            if index[v as usize] == u32::MAX {
                index[v as usize] = positions.len() as u32;
                positions.push(mesh.positions()[v as usize]);
            }
            index[v as usize]
        }));
    }
    TriMesh::new(positions, faces).ok()
}

/// Radius of the smallest ball about the mesh's origin that holds every vertex, m.
pub fn radius_about_origin(mesh: &TriMesh) -> f32 {
    mesh.positions().iter().map(|p| p.length_squared()).fold(0.0, f32::max).sqrt()
}
