//! Stage 1 of applying a dent: where the target's triangles under the dent map's footprint are
//! too coarse for the map, split them ([`mesh::refine`](crate::mesh::refine)) before the map
//! moves any vertex, so that a 12-triangle crate takes a dent shaped like the projectile instead
//! of moving (or tilting) whole faces.
//!
//! The footprint is the map's grid on the collision plane (the projectile's footprint plus the
//! Gaussian tails, so the map is about zero at its border), one cell wider, from one grid width
//! in front of the plane to the depth where the falloff drops below 1 %. Refinement only
//! appends vertices and faces, so every other stage can keep using vertex indices.

use std::borrow::Cow;
use std::collections::HashMap;

use glam::Vec3;

use super::error::invalid;
use super::map::PendingDisplacement;
use super::refine_setting::{AUTO_DOUBLINGS, Refine};
use super::{DentError, DentParams, Grid};
use crate::mesh::weld::{near_miss, position_key};
use crate::mesh::{OrientedBox, RefineError, Refinement, TriMesh, refine_parts};

/// The falloff a(z) below which the footprint ends in depth.
const FALLOFF_FLOOR: f32 = 0.01;

/// The edge length [`Refine::Auto`] refines to under a dent map on `grid` with Gaussian width
/// `sigma`, world units: `max(2σ, 2 cells, width / 12)`. The smoothed profile bends over about
/// σ, so vertices σ/√2 apart (the legs of bisected triangles with 2σ sides) follow it within a
/// few percent of d; shorter edges add triangles the map cannot shape. Twelve edges across the
/// map's width shape a shallow dent (whose σ = d/2 is tiny) as well as the eye can tell, without
/// millimetre triangles.
pub(crate) fn auto_max_edge(grid: &Grid, sigma: f32) -> f32 {
    (2.0 * sigma.max(grid.cell_size)).max(grid.extent() / AUTO_EDGES_ACROSS_REFINED)
}

/// Edges across a dent map's width that [`Refine::Auto`] refines to at least.
const AUTO_EDGES_ACROSS_REFINED: f32 = 12.0;

/// The edge length above which [`Refine::Auto`] calls a target too coarse for a dent map on
/// `grid` with Gaussian width `sigma`, world units: the longer of [`AUTO_COARSENESS`] times
/// [`auto_max_edge`] and half the map's width (the projectile's footprint with the Gaussian
/// tails). A target with no longer edge under the footprint spans the dent with two edges or
/// more and takes it as it is: refining it would grow a body that is dented again and again
/// (the built-in `block`, 8.8 cm diagonals, and `block-fine` take the soak's 1.7 cm dents, whose
/// maps are 21 cm wide, unrefined). A coarser target, where the dent would land inside a face or
/// two (a low-poly crate), is refined to [`auto_max_edge`] everywhere under the footprint.
pub(crate) fn auto_coarse_edge(grid: &Grid, sigma: f32) -> f32 {
    (AUTO_COARSENESS * auto_max_edge(grid, sigma)).max(grid.extent() / AUTO_EDGES_ACROSS)
}

/// The shortest edge [`Refine::Auto`] refines to, as a fraction of the target's diagonal
/// (2⁻¹⁴: 61 µm on a 1 m body, 128 ulps of f32 at its size). Below it a dent's map (a dent of
/// a micrometre) is finer than the target can take: refining toward it only piles triangles
/// around one point.
pub(crate) const MIN_EDGE_OF_SIZE: f32 = 1.0 / 16384.0;

/// How many times longer than [`auto_max_edge`] an edge under a dent must be for
/// [`Refine::Auto`] to refine the target (see [`auto_coarse_edge`]).
pub(crate) const AUTO_COARSENESS: f32 = 4.0;

/// Edges across a dent map's width that [`Refine::Auto`] takes as fine enough.
const AUTO_EDGES_ACROSS: f32 = 2.0;

/// The box of space whose vertices a dent map on `grid` moves with the falloff of `params`:
/// the grid one cell wider, from one grid width in front of the collision plane to the depth
/// where a(z) falls below 1 % (where a(z) stays above it within 8d, `target_size` deep).
pub(crate) fn footprint_box(grid: &Grid, params: &DentParams, target_size: f32) -> OrientedBox {
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

    /// The faces and vertex normals of the surface to displace: the refined ones, or `target`'s.
    pub(crate) fn surface<'a>(&'a self, target: &'a TriMesh) -> (&'a [[u32; 3]], Cow<'a, [Vec3]>) {
        match &self.parts {
            None => (target.faces(), Cow::Borrowed(target.normals())),
            Some((p, f)) => {
                (f, Cow::Owned(refined_mesh(target, p.clone(), f.clone(), &self.refinement, &[]).normals().to_vec()))
            }
        }
    }

    /// Dent `k`'s vertices and triangles added, and its warning.
    pub(crate) fn added_by(&self, k: usize) -> (usize, usize, Option<&str>) {
        self.per_dent.get(k).map_or((0, 0, None), |r| (r.added_vertices, r.added_faces, r.warning.as_deref()))
    }

    /// Takes the refined parts (positions, faces), leaving the target as it was.
    #[cfg(feature = "gpu")]
    pub(crate) fn take_parts(&mut self) -> Option<(Vec<Vec3>, Vec<[u32; 3]>)> {
        self.parts.take()
    }

    /// Writes `pending` (displaced from [`positions`](Self::positions)) into `target` with the
    /// refined faces; normals are recomputed only around what moved (new vertices interpolate
    /// their parents').
    pub(crate) fn commit(&mut self, target: &mut TriMesh, pending: PendingDisplacement) -> super::DisplaceReport {
        match self.parts.take() {
            None => pending.commit(target),
            Some((_, faces)) => {
                *target = refined_mesh(target, pending.positions, faces, &self.refinement, &pending.moved);
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
            Some((_, faces)) => *target = refined_mesh(target, positions, faces, &self.refinement, moved),
        }
    }
}

/// `target` after `refinement` (giving `positions` and `faces`) and a displacement that moved the
/// vertices flagged in `moved`: base vertices keep their normals (an asset's authored ones stay
/// bit for bit where nothing moved), new vertices get their parents' interpolated and
/// renormalised, and the normals around moved vertices are recomputed.
pub(crate) fn refined_mesh(
    target: &TriMesh,
    positions: Vec<Vec3>,
    faces: Vec<[u32; 3]>,
    refinement: &Refinement,
    moved: &[bool],
) -> TriMesh {
    let nlerp = |a: &Vec3, b: &Vec3, t: f32| a.lerp(*b, t).normalize_or_zero();
    match refinement.interpolate(target.normals(), nlerp) {
        Ok(normals) if normals.len() == positions.len() => {
            TriMesh::from_valid_with_normals(positions, faces, normals, moved)
        }
        _ => TriMesh::from_valid(positions, faces),
    }
}

/// The refine stage of `dents` (in order) on `target`, all from its surface as it is; `Err`
/// names the dent (its index in `dents`) that failed, and nothing is changed then.
/// `longest_edge`, the target's longest edge when the caller knows it, lets a target with no
/// edge too coarse for a dent skip the search for one.
pub(crate) fn refine_for_dents(
    target: &TriMesh,
    dents: &[Footprint<'_>],
    longest_edge: Option<f32>,
) -> Result<RefinedTarget, (usize, DentError)> {
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
        let size = *size.get_or_insert_with(|| {
            let (lo, hi) = target.bounds();
            lo.distance(hi)
        });
        let region = footprint_box(&dent.grid, dent.params, size);
        check_seams(target, &region, dent.grid.cell_size).map_err(|e| (k, e))?;
        let (wanted, trigger, cap, auto) = match dent.params.refine {
            Refine::Off => {
                out.per_dent.push(DentRefinement::default());
                continue;
            }
            // A dent's map can be far smaller than the target (a dent of a micrometre): its
            // edges are never asked to be shorter than f32 resolves well at the target's size.
            Refine::Auto { max_new_triangles } => (
                auto_max_edge(&dent.grid, dent.sigma).max(size * MIN_EDGE_OF_SIZE),
                auto_coarse_edge(&dent.grid, dent.sigma).max(size * MIN_EDGE_OF_SIZE),
                max_new_triangles as usize,
                true,
            ),
            Refine::MaxEdge(edge) => (edge, edge, Refine::MAX_EDGE_NEW_TRIANGLES, false),
        };
        if out.parts.is_none() && longest_edge.is_some_and(|longest| longest <= trigger) {
            out.per_dent.push(DentRefinement::default());
            continue;
        }
        let mut done = DentRefinement::default();
        let (positions, faces) = match &out.parts {
            Some((p, f)) => (&p[..], &f[..]),
            None => (target.positions(), target.faces()),
        };
        if !crate::mesh::any_too_long(positions, faces, &region, trigger) {
            out.per_dent.push(done);
            continue;
        }
        let mut edge = wanted;
        for attempt in 0..=AUTO_DOUBLINGS {
            let (positions, faces) =
                out.parts.get_or_insert_with(|| (target.positions().to_vec(), target.faces().to_vec()));
            match refine_parts(positions, faces, &region, edge, cap) {
                Ok(refinement) => {
                    done.added_vertices = refinement.added_vertices();
                    done.added_faces = refinement.added_faces();
                    done.warning = held_back_warning(refinement.held_back.len());
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
                Err(RefineError::WouldCross) => {
                    done.warning = held_back_warning(usize::MAX);
                    break;
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

/// Vertices closer than this fraction of a dent map's cell, at different positions, are a seam
/// whose sides nearly coincide: the map cannot tell them apart, yet they would not move as one.
const NEAR_SEAM_CELLS: f32 = 1e-3;

/// Refuses a dent whose footprint `region` on `target` (its map's cells `cell_size` wide) holds
/// two vertices that nearly but not exactly share a position and share no face, not even
/// through vertices at their positions ([`DentError::NearlyCoincidentVertices`]). Two ends of a
/// tiny edge (a cut's sliver, on either side of a seam) stay joined however the map moves them;
/// two sides of a seam would crack.
fn check_seams(target: &TriMesh, region: &OrientedBox, cell_size: f32) -> Result<(), DentError> {
    let positions = target.positions();
    let under: Vec<u32> = (0..positions.len() as u32).filter(|&v| region.contains(positions[v as usize])).collect();
    // Built only when a near pair is found (rare): the faces of every vertex under the dent,
    // and the vertices under it at each position.
    let tables = std::cell::OnceCell::new();
    let joined = |v: u32, w: u32| {
        let Near { faces_of, at } = tables.get_or_init(|| {
            let mut at: HashMap<[u32; 3], Vec<u32>> = HashMap::new();
            for &u in &under {
                at.entry(position_key(positions[u as usize])).or_default().push(u);
            }
            Near { faces_of: faces_touching(target, &under), at }
        });
        let copies = |u: u32| at.get(&position_key(positions[u as usize])).map_or(&[][..], Vec::as_slice);
        let w_copies = copies(w);
        copies(v).iter().any(|c| {
            faces_of
                .get(c)
                .is_some_and(|faces| faces.iter().any(|&f| target.faces()[f].iter().any(|x| w_copies.contains(x))))
        })
    };
    match near_miss(positions, &under, NEAR_SEAM_CELLS * cell_size, &joined) {
        Some((a, b, distance)) => Err(DentError::NearlyCoincidentVertices { a, b, distance }),
        None => Ok(()),
    }
}

/// What [`check_seams`] looks up about the vertices under a dent: the faces of each, and the
/// vertices at each position.
struct Near {
    faces_of: HashMap<u32, Vec<usize>>,
    at: HashMap<[u32; 3], Vec<u32>>,
}

/// For each of the vertices `under`, the faces of `mesh` that use it.
fn faces_touching(mesh: &TriMesh, under: &[u32]) -> HashMap<u32, Vec<usize>> {
    let mut faces_of: HashMap<u32, Vec<usize>> = under.iter().map(|&v| (v, Vec::new())).collect();
    for (f, face) in mesh.faces().iter().enumerate() {
        for v in face {
            if let Some(list) = faces_of.get_mut(v) {
                list.push(f);
            }
        }
    }
    faces_of
}

/// The warning for a refinement that left `faces` too-coarse faces unsplit (`usize::MAX`: all of
/// them) because splitting them would have made faces cross; `None` for 0.
fn held_back_warning(faces: usize) -> Option<String> {
    let what = match faces {
        0 => return None,
        usize::MAX => "refinement skipped".to_owned(),
        n => format!("{n} faces left unrefined"),
    };
    let message = format!(
        "{what}: splitting them would make faces cross (the surface there is folded flat onto itself); the dent \
         moves their vertices as they are"
    );
    log::warn!("{message}");
    Some(message)
}
