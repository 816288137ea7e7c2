//! What the C API's tests share: meshes through `db_mesh_new`, the thread's message, and a
//! 2 kg ball of radius 0.3 m falling on a floor's top (y = 0.25 m).

#![allow(dead_code)]

use std::ffi::CStr;

use dentbend_c::*;

/// The identity mesh → world transform, 3×4 column by column.
pub const IDENTITY: [f32; 12] = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0];

/// The message of the last failing call on this thread.
pub fn last_error() -> String {
    // SAFETY: the library's message, NUL-terminated.
    unsafe { CStr::from_ptr(db_last_error()) }.to_string_lossy().into_owned()
}

/// A mesh of the library's `TriMesh`, through `db_mesh_new`.
pub fn made(m: &dentbend::TriMesh) -> *mut DbMesh {
    let positions: Vec<f32> = m.positions().iter().flat_map(|p| p.to_array()).collect();
    let indices: Vec<u32> = m.faces().iter().flatten().copied().collect();
    // SAFETY: both arrays are as long as the counts say.
    let handle = unsafe { db_mesh_new(positions.as_ptr(), m.vertex_count(), indices.as_ptr(), m.face_count()) };
    assert!(!handle.is_null(), "{}", last_error());
    handle
}

/// The hit of the ball (surface `ball`, mesh centred on its origin) falling at `speed` m/s on
/// `target`'s top at `(x, 0.25, z)`, fired by `projectile`.
pub fn falling_ball(target: u64, projectile: u64, ball: *const DbMesh, x: f32, z: f32, speed: f32) -> DbHit {
    // A solid 2 kg ball of radius 0.3 m: I = 0.4·m·r².
    let i = 1.0 / (0.4 * 2.0 * 0.3 * 0.3);
    let fixed = DbBodyState {
        center_of_mass: [0.0; 3],
        linear_velocity: [0.0; 3],
        angular_velocity: [0.0; 3],
        mass: 0.0,
        inverse_inertia: [0.0; 9],
    };
    let falling = DbBodyState {
        center_of_mass: [x, 0.55, z],
        linear_velocity: [0.0, -speed, 0.0],
        mass: 2.0,
        inverse_inertia: [i, 0.0, 0.0, 0.0, i, 0.0, 0.0, 0.0, i],
        ..fixed
    };
    let mut to_world = IDENTITY;
    to_world[9..].copy_from_slice(&[x, 0.55, z]);
    DbHit {
        target,
        projectile,
        point: [x, 0.25, z],
        normal: [0.0, -1.0, 0.0],
        target_state: fixed,
        projectile_state: falling,
        projectile_surface: ball,
        projectile_to_world: to_world,
    }
}
