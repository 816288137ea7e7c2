//! Save and restore through the Rapier adapter: a run's recorded damage, written as a damage
//! file and read back, gives a fresh scene the same meshes bit for bit (content hashes) with no
//! simulation, and colliders that match them (tri-mesh vertices equal to the mesh's, hulls
//! spanning the mesh's bounds). Damage restored onto another mesh is refused with a typed error
//! and changes nothing.

use dentbend::mesh::TriMesh;
use dentbend::record::{DamageFile, RecordError};
use dentbend_rapier::demo::rain::{Rain, RainSettings};
use dentbend_rapier::rapier3d::prelude::ColliderHandle;
use dentbend_rapier::{AdapterError, PhysicsWorld};

fn settings() -> RainSettings {
    RainSettings { steps: 150, balls: 12, waves: 2, wave_interval: 40, seed: 9, rigid_balls: false }
}

fn trimesh_matches(world: &PhysicsWorld, handle: ColliderHandle, mesh: &TriMesh) {
    let shape = world.colliders.get(handle).unwrap().shape().as_trimesh().unwrap();
    assert_eq!(shape.vertices(), mesh.positions(), "the collider follows the restored mesh");
    assert_eq!(shape.indices(), mesh.faces());
}

#[test]
fn a_saved_run_restores_bit_for_bit_with_colliders_that_follow() {
    let mut run = Rain::new(settings()).unwrap();
    run.record_damage().unwrap();
    let totals = run.run().unwrap();
    assert!(totals.dents.len() >= 10, "{} dents", totals.dents.len());
    let file = DamageFile::from_json(&run.adapter.dentables.damage_file().to_json().unwrap()).unwrap();

    let mut restored = Rain::new(settings()).unwrap();
    restored.restore(&file).unwrap();
    let (a, b) = (run.mesh_hashes(), restored.mesh_hashes());
    assert_eq!(a.len(), 2 + settings().balls);
    assert_eq!(a, b);
    for handle in [restored.bunny, restored.block] {
        let mesh = restored.adapter.dentables.mesh(handle).unwrap();
        assert_ne!(mesh.positions(), restored.initial[&handle].positions(), "it was dented");
        trimesh_matches(&restored.world, handle, mesh);
    }
    // A restored ball's hull spans its dented mesh.
    for &(_, c) in &restored.balls {
        let mesh = restored.adapter.dentables.mesh(c).unwrap();
        let aabb = restored.world.colliders.get(c).unwrap().shape().compute_local_aabb();
        let lo = mesh.positions().iter().fold(glam::Vec3::MAX, |m, p| m.min(*p));
        assert!((aabb.mins - lo).abs().max_element() < 1e-5);
    }
    // Recording goes on from the restored damage: a restored save saves the same.
    restored.record_damage().unwrap();
    let again = restored.adapter.dentables.damage_file();
    assert_eq!(again.dents(), 0, "record_damage starts a new record from the meshes now");
}

#[test]
fn damage_restored_onto_another_mesh_is_refused_and_changes_nothing() {
    let mut run = Rain::new(settings()).unwrap();
    run.record_damage().unwrap();
    run.run().unwrap();
    let file = run.adapter.dentables.damage_file();
    let block = file.body("block").unwrap().clone();

    // The bunny's collider given the block's damage.
    let mut fresh = Rain::new(settings()).unwrap();
    let before = fresh.adapter.dentables.mesh(fresh.bunny).unwrap().clone();
    let err = fresh.adapter.dentables.restore(&mut fresh.world.colliders, fresh.bunny, &block).unwrap_err();
    assert!(matches!(err, AdapterError::Record(RecordError::BaseMismatch { .. })), "{err}");
    assert_eq!(fresh.adapter.dentables.mesh(fresh.bunny).unwrap().positions(), before.positions());
    trimesh_matches(&fresh.world, fresh.bunny, &before);
    // Restoring twice: the second time the mesh is no longer the base.
    fresh.adapter.dentables.restore(&mut fresh.world.colliders, fresh.block, &block).unwrap();
    let err = fresh.adapter.dentables.restore(&mut fresh.world.colliders, fresh.block, &block).unwrap_err();
    assert!(matches!(err, AdapterError::Record(RecordError::BaseMismatch { .. })), "{err}");
}
