//! Stage 1 of applying a dent: where the target's triangles under the dent map's footprint are
//! too coarse for the map, split them ([`mesh::refine`](crate::mesh::refine)) before the map
//! moves any vertex, so that a 12-triangle crate takes a dent shaped like the projectile instead
//! of moving (or tilting) whole faces.
//!
//! The footprint is the map's grid on the collision plane (the projectile's footprint plus the
//! Gaussian tails, so the map is about zero at its border), one cell wider, from one grid width
//! in front of the plane to the depth where the falloff drops below 1 %. Refinement only
//! appends vertices and faces, so every other stage can keep using vertex indices.

use glam::Vec3;

use super::error::invalid;
use super::map::PendingDisplacement;
use super::{BatchError, DentError, DentJob, DentParams, DentReport, Grid, plan_dent};
use crate::mesh::{MAX_COORDINATE, OrientedBox, RefineError, Refinement, TriMesh, refine_parts};

/// Whether, and how finely, the target is refined under a dent before it is displaced.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Refine {
    /// Refine where the target's edges under the footprint are longer than the map resolves:
    /// `max(2σ, 2 map cells)` ([`auto_max_edge`]). A dent that would need more than `max_new_triangles` new triangles
    /// is refined with edges twice, four or eight times as long (the first that fits), or not at
    /// all, with a warning in its report. The default, with
    /// [`DEFAULT_MAX_NEW_TRIANGLES`].
    Auto {
        /// Most triangles one dent may add.
        max_new_triangles: u32,
    },
    /// Never refine: the dent moves the target's vertices as they are.
    Off,
    /// Refine until no edge under the footprint is longer than this, world units (finite,
    /// > 0). A dent that would need more than [`MAX_EDGE_NEW_TRIANGLES`] new triangles fails
    /// with [`DentError::InvalidParameter`] and changes nothing.
    MaxEdge(f32),
}

/// Triangles one dent may add under [`Refine::Auto`] by default: enough for a 1 m² footprint
/// with 2.5 cm edges (a 12-triangle 2 m crate hit by a 1 m ball with d = 0.1 m adds about 700).
pub const DEFAULT_MAX_NEW_TRIANGLES: u32 = 20_000;

/// Triangles one dent may add under [`Refine::MaxEdge`].
pub const MAX_EDGE_NEW_TRIANGLES: usize = 1_000_000;

/// Times [`Refine::Auto`] doubles its edge length before it gives up on a dent.
const AUTO_DOUBLINGS: u32 = 3;

/// The falloff a(z) below which the footprint ends in depth.
const FALLOFF_FLOOR: f32 = 0.01;

impl Default for Refine {
    /// `Auto { max_new_triangles: DEFAULT_MAX_NEW_TRIANGLES }`.
    fn default() -> Self {
        Self::Auto { max_new_triangles: DEFAULT_MAX_NEW_TRIANGLES }
    }
}

impl Refine {
    /// Checks the setting.
    ///
    /// # Errors
    /// [`DentError::InvalidParameter`] for a `MaxEdge` that is NaN, infinite, ≤ 0 or above
    /// [`MAX_COORDINATE`].
    pub fn validate(&self) -> Result<(), DentError> {
        match *self {
            Self::MaxEdge(edge) if !(edge.is_finite() && edge > 0.0 && edge <= MAX_COORDINATE) => {
                Err(invalid("refine", edge, "must be a finite edge length > 0 and at most 1e6"))
            }
            _ => Ok(()),
        }
    }
}

/// The edge length [`Refine::Auto`] refines to under a dent map on `grid` with Gaussian width
/// `sigma`, world units: `max(2σ, 2 cells)`. The smoothed profile bends over about σ, so
/// vertices σ/√2 apart (the legs of bisected triangles with 2σ sides) follow it within a few
/// percent of d; shorter edges add triangles the map cannot shape. Targets already that fine
/// (the built-in `block` and `block-fine` under dents with σ ≥ 0.05 m) are left alone.
pub fn auto_max_edge(grid: &Grid, sigma: f32) -> f32 {
    2.0 * sigma.max(grid.cell_size)
}

/// The box of space whose vertices a dent map on `grid` moves with the falloff of `params`:
/// the grid one cell wider, from one grid width in front of the collision plane to the depth
/// where a(z) falls below 1 % (where a(z) stays above it within 8d, `target_size` deep).
pub fn footprint_box(grid: &Grid, params: &DentParams, target_size: f32) -> OrientedBox {
    let d = params.dent_distance;
    const SAMPLES: u32 = 64;
    let step = 8.0 * d / SAMPLES as f32;
    let last_strong = (0..=SAMPLES).rev().find(|&k| params.attenuation.eval(k as f32 * step, d).abs() >= FALLOFF_FLOOR);
    let depth = match last_strong {
        Some(k) if k == SAMPLES => target_size.max(8.0 * d),
        Some(k) => (k + 1) as f32 * step,
        None => step,
    };
    let front = grid.extent();
    let half_width = 0.5 * grid.extent() + grid.cell_size;
    OrientedBox {
        centre: grid.origin + grid.axis_z * (0.5 * (depth - front)),
        axes: [grid.axis_x, grid.axis_y, grid.axis_z],
        half_extents: Vec3::new(half_width, half_width, 0.5 * (depth + front)),
    }
}

/// One dent's map, as the refine stage sees it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Footprint<'p> {
    /// The dent-map grid on the collision plane.
    pub grid: Grid,
    /// Gaussian width, world units.
    pub sigma: f32,
    /// The dent's parameters (falloff, refine setting).
    pub params: &'p DentParams,
}

/// What the refine stage did to one dent.
#[derive(Debug, Clone, Default)]
pub(crate) struct DentRefinement {
    added_vertices: usize,
    added_faces: usize,
    warning: Option<String>,
}

/// A target after the refine stage of all the dents about to be applied to it.
#[derive(Debug, Clone, Default)]
pub(crate) struct RefinedTarget {
    /// New positions and faces; `None` when nothing was refined.
    parts: Option<(Vec<Vec3>, Vec<[u32; 3]>)>,
    /// What was added, from the target as it was.
    pub refinement: Refinement,
    per_dent: Vec<DentRefinement>,
}

impl RefinedTarget {
    /// The positions to displace: the refined ones, or `target`'s own.
    pub(crate) fn positions<'a>(&'a self, target: &'a TriMesh) -> &'a [Vec3] {
        self.parts.as_ref().map_or(target.positions(), |(p, _)| p)
    }

    /// Adds dent `k`'s refinement counts and warning to its report.
    pub(crate) fn annotate(&self, k: usize, report: &mut DentReport) {
        if let Some(r) = self.per_dent.get(k) {
            report.refined_vertices = r.added_vertices;
            report.refined_triangles = r.added_faces;
            report.warnings.extend(r.warning.iter().cloned());
        }
    }

    /// Writes `pending` (displaced from [`positions`](Self::positions)) into `target` with the
    /// refined faces.
    pub(crate) fn commit(&mut self, target: &mut TriMesh, pending: PendingDisplacement) -> super::DisplaceReport {
        match self.parts.take() {
            None => pending.commit(target),
            Some((_, faces)) => {
                *target = TriMesh::from_valid(pending.positions, faces);
                pending.report
            }
        }
    }

    /// Replaces `positions` (displaced from [`positions`](Self::positions)) into `target` with
    /// the refined faces, or writes them as they are.
    pub(crate) fn commit_positions(&mut self, target: &mut TriMesh, positions: Vec<Vec3>, moved: &[bool]) {
        match self.parts.take() {
            None => {
                target.positions_mut().copy_from_slice(&positions);
                target.recompute_normals_near(moved);
            }
            Some((_, faces)) => *target = TriMesh::from_valid(positions, faces),
        }
    }
}

/// The refine stage of `dents` (in order) on `target`, all from its surface as it is; `Err`
/// names the dent (its index in `dents`) that failed, and nothing is changed then.
pub(crate) fn refine_for_dents(target: &TriMesh, dents: &[Footprint<'_>]) -> Result<RefinedTarget, (usize, DentError)> {
    let mut out = RefinedTarget {
        refinement: Refinement {
            base_vertex_count: target.vertex_count(),
            base_face_count: target.face_count(),
            ..Refinement::default()
        },
        ..RefinedTarget::default()
    };
    let mut size = None;
    for (k, dent) in dents.iter().enumerate() {
        dent.params.refine.validate().map_err(|e| (k, e))?;
        let (wanted, cap, auto) = match dent.params.refine {
            Refine::Off => {
                out.per_dent.push(DentRefinement::default());
                continue;
            }
            Refine::Auto { max_new_triangles } => {
                (auto_max_edge(&dent.grid, dent.sigma), max_new_triangles as usize, true)
            }
            Refine::MaxEdge(edge) => (edge, MAX_EDGE_NEW_TRIANGLES, false),
        };
        let size = *size.get_or_insert_with(|| {
            let (lo, hi) = target.bounds();
            lo.distance(hi)
        });
        let region = footprint_box(&dent.grid, dent.params, size);
        let mut done = DentRefinement::default();
        let mut edge = wanted;
        for attempt in 0..=AUTO_DOUBLINGS {
            let (positions, faces) = match &out.parts {
                Some((p, f)) => (&p[..], &f[..]),
                None => (target.positions(), target.faces()),
            };
            if !crate::mesh::any_too_long(positions, faces, &region, edge) {
                break;
            }
            let (positions, faces) =
                out.parts.get_or_insert_with(|| (target.positions().to_vec(), target.faces().to_vec()));
            match refine_parts(positions, faces, &region, edge, cap) {
                Ok(refinement) => {
                    done.added_vertices = refinement.added_vertices();
                    done.added_faces = refinement.added_faces();
                    out.refinement.extend(refinement).map_err(|_| (k, invalid("refine", "chain", "internal")))?;
                    break;
                }
                Err(RefineError::TooManyTriangles { .. }) if auto && attempt < AUTO_DOUBLINGS => edge *= 2.0,
                Err(RefineError::TooManyTriangles { .. }) if auto => {
                    let message = format!(
                        "refinement skipped: this dent needs more than {cap} new triangles even with {edge:.3e}-long \
                         edges (8× the {wanted:.3e} its map resolves); it moves the target's vertices as they are"
                    );
                    log::warn!("{message}");
                    done.warning = Some(message);
                }
                Err(RefineError::TooManyTriangles { .. }) => {
                    let reason = "needs more than 1,000,000 new triangles under this dent: use a longer edge";
                    return Err((k, invalid("refine", edge, reason)));
                }
                Err(e) => return Err((k, invalid("refine", e, "was refused"))),
            }
        }
        if let Some((_, faces)) = &out.parts
            && faces.len() == target.face_count()
        {
            out.parts = None; // nothing was split after all
        }
        out.per_dent.push(done);
    }
    Ok(out)
}

/// What [`refine_targets`] did: per target, its refined mesh (`None` when left as it was) and
/// what was appended; per job, a report with only its refinement counts and warnings filled in.
#[derive(Debug, Clone, Default)]
pub struct RefinedTargets {
    /// Per target (batch order): the refined mesh, `None` when nothing was refined.
    pub meshes: Vec<Option<TriMesh>>,
    /// Per target: what refinement appended (empty when nothing).
    pub refinements: Vec<Refinement>,
    /// Per job: `refined_vertices`, `refined_triangles` and warnings.
    pub reports: Vec<DentReport>,
}

/// The refine stage on its own, for backends that displace elsewhere (the GPU): plans every job
/// (as [`plan_dent`] does, with the target's mean edge) and refines its target where it will
/// land, each target's jobs in order, all from the targets as they are.
///
/// # Errors
/// [`BatchError`] naming the first job (in job order) whose plan or refinement failed.
pub fn refine_targets(targets: &[TriMesh], jobs: &[DentJob<'_>]) -> Result<RefinedTargets, BatchError> {
    if let Some((job, bad)) = jobs.iter().enumerate().find(|(_, j)| j.target >= targets.len()) {
        return Err(BatchError { job, error: invalid("target", bad.target, "must index the batch's target list") });
    }
    let mut plans = Vec::with_capacity(jobs.len());
    for (job, j) in jobs.iter().enumerate() {
        if matches!(j.params.refine, Refine::Off) {
            plans.push(None);
            continue;
        }
        let edge = targets[j.target].mean_edge_length();
        let plan =
            plan_dent(j.projectile, &j.impact, &j.params, Some(edge)).map_err(|error| BatchError { job, error })?;
        plans.push(Some((plan.map_grid, plan.sigma)));
    }
    let mut out = RefinedTargets { reports: vec![DentReport::default(); jobs.len()], ..RefinedTargets::default() };
    for (t, target) in targets.iter().enumerate() {
        let mine: Vec<usize> = (0..jobs.len()).filter(|&j| jobs[j].target == t && plans[j].is_some()).collect();
        let dents: Vec<Footprint<'_>> = mine
            .iter()
            .filter_map(|&j| plans[j].map(|(grid, sigma)| Footprint { grid, sigma, params: &jobs[j].params }))
            .collect();
        let mut done = refine_for_dents(target, &dents).map_err(|(k, error)| BatchError { job: mine[k], error })?;
        for (k, &j) in mine.iter().enumerate() {
            done.annotate(k, &mut out.reports[j]);
        }
        out.meshes.push(done.parts.take().map(|(positions, faces)| TriMesh::from_valid(positions, faces)));
        out.refinements.push(done.refinement);
    }
    Ok(out)
}
