//! CPU batches: many dents over several targets give exactly what one-at-a-time denting in
//! submission order gives, and one bad dent fails the batch by index with every target unchanged.

mod common;

use common::sphere_at;
use dentbend::dent::{DentJob, Refine, dent_batch};
use dentbend::glam::Vec3;
use dentbend::{DentParams, Impact, TriMesh, mesh};

fn targets() -> Vec<TriMesh> {
    vec![mesh::builtin("block").unwrap(), mesh::builtin("box").unwrap(), mesh::builtin("block").unwrap()]
}

/// Balls dropped on the top faces (block top y = 0.5, box top y = 1), two on target 0 overlapping.
fn jobs<'a>(balls: &'a [TriMesh]) -> Vec<DentJob<'a>> {
    let hit = |target, x: f32, top: f32, ball: usize, d: f32| DentJob {
        target,
        projectile: &balls[ball],
        impact: Impact {
            point: Vec3::new(x, top, 0.0),
            normal: -Vec3::Y,
            relative_velocity: Vec3::new(0.3, -1.0, 0.0),
        },
        // The raw map application (`DentMap::apply`) is the sequential reference here, so the
        // box (12.5 cm cells, coarser than a 0.1 m dent's map) is not refined first;
        // tests/dent_refine.rs covers batches that refine.
        params: DentParams { refine: Refine::Off, ..DentParams::new(d) },
    };
    vec![hit(0, 0.0, 0.5, 0, 0.2), hit(1, 0.2, 1.0, 1, 0.1), hit(0, 0.4, 0.5, 1, 0.15), hit(2, -1.0, 0.5, 0, 0.25)]
}

fn balls() -> Vec<TriMesh> {
    vec![sphere_at(Vec3::new(0.0, 3.0, 0.0), 0.8), sphere_at(Vec3::new(2.0, 3.0, 1.0), 0.4)]
}

#[test]
fn a_batch_equals_denting_one_at_a_time_in_order() {
    let balls = balls();
    let jobs = jobs(&balls);
    let mut batched = targets();
    let reports = dent_batch(&mut batched, &jobs).unwrap();
    let mut sequential = targets();
    // Maps come from the undented targets' edge lengths in both cases (the batch plans first).
    let edges: Vec<f32> = sequential.iter().map(|t| t.mean_edge_length()).collect();
    for (job, report) in jobs.iter().zip(&reports) {
        let map = dentbend::dent_map(job.projectile, &job.impact, &job.params, Some(edges[job.target])).unwrap();
        let displaced = map.apply(&mut sequential[job.target], &job.params.attenuation).unwrap();
        assert_eq!(displaced.moved_vertices, report.moved_vertices);
    }
    // Same kernels on the same inputs in the same order: bit-identical positions; normals are
    // refreshed over the union of moved vertices in both cases.
    for (b, s) in batched.iter().zip(&sequential) {
        assert_eq!(b.positions(), s.positions());
    }
    assert!(reports.iter().all(|r| r.moved_vertices > 0 && r.theta_deg > 10.0));
    // The second dent on target 0 moved vertices the first had moved: order mattered.
    let mut reversed = targets();
    let mut jobs_rev = jobs.clone();
    jobs_rev.swap(0, 2);
    dent_batch(&mut reversed, &jobs_rev).unwrap();
    assert_ne!(reversed[0].positions(), batched[0].positions());
}

#[test]
fn one_bad_dent_fails_the_batch_by_index_and_changes_nothing() {
    let balls = balls();
    let before = targets();
    for (bad, mutate) in [
        (2usize, Box::new(|j: &mut DentJob| j.impact.normal = Vec3::ZERO) as Box<dyn Fn(&mut DentJob)>),
        (1, Box::new(|j: &mut DentJob| j.params.dent_distance = f32::NAN)),
        (3, Box::new(|j: &mut DentJob| j.target = 7)),
    ] {
        let mut jobs = jobs(&balls);
        mutate(&mut jobs[bad]);
        let mut targets = targets();
        let err = dent_batch(&mut targets, &jobs).unwrap_err();
        assert_eq!(err.job, bad, "{err}");
        assert_eq!(targets, before, "a failed batch must leave every target unchanged");
    }
}
