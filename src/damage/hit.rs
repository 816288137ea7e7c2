//! What the damage API asks of the caller's world: each contact as a [`Hit`] keyed by the
//! caller's ids, and its dentable bodies through [`DentTargets`].

use glam::Affine3A;

use crate::dent::{BodyState, DentSettings, Impact, Surface};
use crate::fracture::FractureSettings;
use crate::mesh::TriMesh;

/// One contact a solver reported, as denting sees it from the target's side.
#[derive(Debug, Clone, Copy)]
pub struct Hit<'a, K> {
    /// The body that may dent (the caller's id).
    pub target: K,
    /// The body that hit it.
    pub projectile: K,
    /// The contact, world coordinates consistent with the target's `to_world`: normal into the
    /// target, the projectile's velocity relative to the target before the step
    /// ([`Impact::from_contact`] builds it from both bodies' states).
    pub impact: Impact,
    /// The target's state before the step (for the energy model).
    pub target_state: BodyState,
    /// The projectile's state before the step.
    pub projectile_state: BodyState,
    /// The projectile's surface where it hit (mesh and mesh → world transform).
    pub projectile_surface: Surface<'a>,
}

/// A dentable body as the caller's world holds it.
#[derive(Debug, Clone, Copy)]
pub struct TargetView<'a> {
    /// Its surface, in its own (mesh) coordinates, m.
    pub mesh: &'a TriMesh,
    /// Mesh coordinates → world, consistent with its hits' impacts.
    pub to_world: Affine3A,
    /// How it dents.
    pub settings: &'a DentSettings,
    /// Radius of a ball about the mesh's origin that holds the mesh, m
    /// (`radius_about_origin`, or the collider's bounding sphere).
    pub radius: f32,
    /// How it breaks (`None`: it never does). A breakable body's mesh must be closed and its
    /// `to_world` rigid.
    pub fracture: Option<&'a FractureSettings>,
}

/// The caller's bodies, as the damage API asks about them.
pub trait DentTargets<K> {
    /// Whether `key` names a body the caller has (dentable or not).
    fn contains(&self, key: K) -> bool;
    /// `key` as a dentable target; `None` for a body that does not dent.
    fn target(&self, key: K) -> Option<TargetView<'_>>;
}
