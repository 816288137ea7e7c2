//! The GPU backend: the same contact dents alike on the GPU and the CPU, and the rain scene
//! runs with its dents on the GPU. Skipped (with the reason printed) when no adapter exists,
//! unless `DENTBEND_REQUIRE_GPU=1` (set in CI, which installs lavapipe).

mod common;

use dentbend::damage::{CpuBackend, DentBackend};
use dentbend::gpu::{GpuContext, shared_context};
use dentbend::mesh::TriMesh;
use dentbend_rapier::demo::rain::{Rain, RainSettings, ball_dent, target_dent};
use dentbend_rapier::rapier3d::prelude::ColliderHandle;
use dentbend_rapier::{BodyStates, Dentables, GpuBackend};
use glam::Vec3;

fn context() -> Option<&'static GpuContext> {
    match shared_context() {
        Ok(context) => Some(context),
        Err(error) if std::env::var("DENTBEND_REQUIRE_GPU").as_deref() == Ok("1") => {
            panic!("DENTBEND_REQUIRE_GPU=1 but no GPU is usable: {error}")
        }
        Err(error) => {
            eprintln!("skipping GPU test: {error}");
            None
        }
    }
}

/// A block and a ball hitting it head-on at 6 m/s, dented on `backend`: both dented meshes.
fn dent_once(backend: &mut dyn DentBackend<ColliderHandle>) -> (TriMesh, TriMesh) {
    let (mut world, (block, block_mesh), (ball, ball_mesh)) = common::block_and_ball(Vec3::new(0.0, -9.81, 0.0), 0.36);
    let mut dentables = Dentables::new();
    dentables.insert(&world.colliders, &world.bodies, block, block_mesh, target_dent()).unwrap();
    dentables.insert(&world.colliders, &world.bodies, ball, ball_mesh, ball_dent()).unwrap();
    let states = BodyStates::record(&world.bodies, &world.colliders);
    let contact = common::top_contact(block, ball, true);
    let report = dentables.process(&[contact], &states, &mut world.bodies, &mut world.colliders, backend).unwrap();
    assert_eq!(report.dents.len(), 2);
    (dentables.mesh(block).unwrap().clone(), dentables.mesh(ball).unwrap().clone())
}

#[test]
fn the_gpu_and_the_cpu_dent_alike() {
    let Some(context) = context() else { return };
    let cpu = dent_once(&mut CpuBackend);
    let gpu = dent_once(&mut GpuBackend::new(context));
    // The kernels match their CPU twins to about 1e-6 of the dent distance each (see the core
    // parity tests); six kernels in a row and the GPU's fused multiply-adds: 1e-4 of the cap.
    for (c, g, cap) in [(&cpu.0, &gpu.0, target_dent().material.cap), (&cpu.1, &gpu.1, ball_dent().material.cap)] {
        let worst = c.positions().iter().zip(g.positions()).map(|(a, b)| a.distance(*b)).fold(0.0, f32::max);
        println!("largest CPU/GPU difference {worst:e} m (cap {cap} m)");
        assert!(worst <= 1e-4 * cap, "{worst} m");
        assert_eq!(c.vertex_count(), g.vertex_count());
    }
}

#[test]
fn the_rain_scene_dents_on_the_gpu() {
    let Some(context) = context() else { return };
    let settings = RainSettings { steps: 120, balls: 8, waves: 1, ..RainSettings::default() };
    let mut rain = Rain::with_backend(settings, Box::new(GpuBackend::new(context))).unwrap();
    let totals = rain.run().unwrap();
    assert!(totals.dents.iter().any(|(_, d)| d.target == rain.block || d.target == rain.bunny), "no dents");
    for target in [rain.bunny, rain.block] {
        let mesh = rain.adapter.dentables.mesh(target).unwrap();
        assert!(mesh.positions().iter().all(|p| p.is_finite()));
        let shape = rain.world.colliders.get(target).unwrap().shape().as_trimesh().unwrap();
        assert_eq!(shape.vertices(), mesh.positions());
    }
}
