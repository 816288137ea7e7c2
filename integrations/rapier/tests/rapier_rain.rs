//! What `rapier_rain` shows: balls raining on the bunny and a block dent both where they land
//! and nowhere else, no deeper than the material allows, colliders following the dented meshes
//! (refitted in place, rebuilt where refinement added vertices), one dent per impact, nothing NaN.

use dentbend::mesh::TriMesh;
use dentbend_rapier::demo::rain::{BALL_RADIUS, Rain, RainSettings, ball_dent, target_dent};
use dentbend_rapier::rapier3d::prelude::ColliderHandle;
use dentbend_rapier::{dentbend, to_affine};

/// How far from an impact point a dent can move a vertex, m: the profile is the part of the
/// ball (radius 0.12 m) within d of its tip, so no wider than the ball; the Gaussian
/// broadening (σ) is below 1e-3 of its peak beyond 3.7σ and the heat steps spread it a few
/// cells more: ball radius + 5σ.
fn reach(sigma: f32) -> f32 {
    BALL_RADIUS + 5.0 * sigma
}

fn displacement(a: &TriMesh, b: &TriMesh) -> Vec<f32> {
    a.positions().iter().zip(b.positions()).map(|(p, q)| p.distance(*q)).collect()
}

#[test]
fn balls_dent_the_bunny_and_the_block_where_they_land_and_nowhere_else() {
    let mut rain = Rain::new(RainSettings::default()).unwrap();
    let totals = rain.run().unwrap();
    let sigma = target_dent().params.sigma.unwrap();
    let cap = target_dent().material.cap;
    for target in [rain.bunny, rain.block] {
        let dents: Vec<_> = totals.dents.iter().filter(|(_, d)| d.target == target).map(|(_, d)| *d).collect();
        assert!(dents.len() >= 5, "{target:?}: only {} dents", dents.len());
        let pose = to_affine(rain.world.colliders.get(target).unwrap().position());
        let before = &rain.initial[&target];
        let after = rain.adapter.dentables.mesh(target).unwrap();
        // Refinement (on by default) may append vertices and faces under a dent on the coarse
        // bunny; the original vertices keep their indices, so they are compared one to one.
        assert!(after.vertex_count() >= before.vertex_count() && after.face_count() >= before.face_count());
        let moved = displacement(before, after);
        let mut moved_count = 0;
        for (v, &m) in moved.iter().enumerate() {
            assert!(m.is_finite(), "vertex {v} not finite");
            if m <= 1e-6 {
                continue;
            }
            moved_count += 1;
            let world = pose.transform_point3(before.positions()[v]);
            // Any motion lies within reach of an impact's axis (the dent map is laid across the
            // viewing direction; vertices behind the surface move by the depth falloff, below
            // 1 % of the dent past a few dent distances deep) ...
            let lateral = |d: &dentbend::damage::AppliedDent<ColliderHandle>| {
                let r = world - d.impact.point;
                (r - r.dot(d.impact.view_direction()) * d.impact.view_direction()).length()
            };
            let near = dents.iter().filter(|d| lateral(d) <= reach(sigma)).count();
            assert!(near > 0, "{target:?}: vertex {v} at {world} moved {m} m off every impact's axis");
            // ... and motion above 1 % of the cap lies within reach of an impact point.
            if m > 0.01 * cap {
                let close = dents.iter().any(|d| d.impact.point.distance(world) <= reach(sigma));
                assert!(close, "{target:?}: vertex {v} at {world} moved {m} m, no impact within {} m", reach(sigma));
            }
            // Each dent moves a vertex by at most its distance (≤ cap) times the falloff (≤ 1):
            // 1 % for the bilinear map sampling.
            assert!(m <= 1.01 * cap * near as f32 + 1e-6, "{target:?}: vertex {v} moved {m} m, {near} dents near");
        }
        assert!(moved_count > 0 && moved_count < before.vertex_count() / 2, "{target:?}: {moved_count} moved");
        for d in &dents {
            assert!(d.dent_distance > 0.0 && d.dent_distance <= cap + 1e-6, "{d:?}");
        }
        // The collider was refitted (or, after a refinement, rebuilt) to the dented mesh.
        let shape = rain.world.colliders.get(target).unwrap().shape().as_trimesh().unwrap();
        assert_eq!(shape.vertices(), after.positions());
    }
    // The balls dent too, each no deeper than its cap, and their hulls follow their meshes.
    let ball_cap = ball_dent().material.cap;
    let on_balls: Vec<_> =
        totals.dents.iter().filter(|(_, d)| d.target != rain.bunny && d.target != rain.block).collect();
    assert!(!on_balls.is_empty());
    assert!(on_balls.iter().all(|(_, d)| d.dent_distance <= ball_cap + 1e-6));
    for &(body, collider) in &rain.balls {
        let mesh = rain.adapter.dentables.mesh(collider).unwrap();
        assert!(mesh.positions().iter().all(|p| p.is_finite()));
        let hull = rain.world.colliders.get(collider).unwrap().shape().as_convex_polyhedron().unwrap();
        assert!(hull.points().iter().all(|p| mesh.positions().contains(p)), "hull of {collider:?} is not the mesh's");
        let rb = rain.world.bodies.get(body).unwrap();
        assert!(rb.translation().is_finite() && rb.linvel().is_finite());
    }
}

#[test]
fn one_dent_per_impact_while_a_ball_rests_on_the_block() {
    // One ball over the block: it lands at about 5.6 m/s (a dent), bounces at most at
    // 0.3 × that (1.7 m/s, under the 2 m/s threshold), then rests: one dent on the block.
    let settings = RainSettings { steps: 150, balls: 2, waves: 1, wave_interval: 1000, seed: 3, rigid_balls: false };
    let mut rain = Rain::new(settings).unwrap();
    let totals = rain.run().unwrap();
    let block: Vec<ColliderHandle> =
        totals.dents.iter().filter(|(_, d)| d.target == rain.block).map(|(_, d)| d.projectile).collect();
    assert_eq!(block.len(), 1, "{:?}", totals.dents);
    let (_, landed) = rain.balls[1];
    assert_eq!(block[0], landed);
    // The ball is at rest on the block by the end.
    let rb = rain.world.bodies.get(rain.balls[1].0).unwrap();
    assert!(rb.linvel().length() < 0.1, "{}", rb.linvel());
}
