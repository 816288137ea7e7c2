//! Hits as the damage API takes them, for tests that throw balls at fixed bodies.

use dentbend::damage::Hit;
use dentbend::dent::{BodyState, Impact, Surface};
use dentbend::glam::{Affine3A, Vec3};
use dentbend::mesh::TriMesh;

/// `projectile`, a ball of surface `ball` (its own coordinates, centred on its centre of mass)
/// moving as `state`, hits the fixed body `target` at `point` with `normal` into the target.
pub fn on_fixed<'a, K>(
    target: K,
    projectile: K,
    ball: &'a TriMesh,
    point: Vec3,
    normal: Vec3,
    state: BodyState,
) -> Hit<'a, K> {
    Hit {
        target,
        projectile,
        impact: Impact::from_contact(point, normal, &BodyState::FIXED, &state).expect("a finite contact"),
        target_state: BodyState::FIXED,
        projectile_state: state,
        projectile_surface: Surface { mesh: ball, to_world: Affine3A::from_translation(state.center_of_mass) },
    }
}
