//! The dent map: a 3-vector displacement per cell of a grid on the collision plane, and how it is
//! applied to a target mesh.

use glam::Vec3;

use super::error::invalid;
use super::thickness::{FittedFalloff, MapView, fit_falloff};
use super::{Attenuation, DentError, Grid};
use crate::cpu::{self, DisplaceParams};
use crate::mesh::{TriMesh, in_coordinate_range};

/// A dent map `D̂(x, y)` on the collision plane (paper §3.1): `grid.axis_z` is the denting
/// normal and each cell holds `[Δx, Δy, Δz, height]`, the world-space displacement of a target
/// point at that cell and the unsheared height it came from, world units.
#[derive(Debug, Clone, PartialEq)]
pub struct DentMap {
    /// Grid on the collision plane, centred on the impact point.
    pub grid: Grid,
    /// `res × res` cells, row-major `[row][col]`.
    pub cells: Vec<[f32; 4]>,
    /// Dent distance d the map was built for, world units.
    pub dent_distance: f32,
}

/// What applying a dent map did.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DisplaceReport {
    /// Vertices that moved.
    pub moved_vertices: usize,
    /// Largest vertex displacement, world units.
    pub max_displacement: f32,
    /// Human-readable warnings (a falloff that would fold the wall under the dent, paper
    /// Figure 2d, measured on the body; a dent the intersection guard limited).
    pub warnings: Vec<String>,
    /// Enclosed volume after minus before, cubic world units, signed; measured by the dent
    /// pipeline's volume stage (zero from [`DentMap::apply`], which does not measure it).
    pub volume_change: f64,
    /// Volume the displacement alone changed (|volume change| before any rim), cubic world
    /// units; zero from [`DentMap::apply`].
    pub cavity_volume: f64,
    /// Fraction of the displacement kept when the intersection guard scaled the dent back so
    /// that no faces cross (`None`: not limited).
    pub limited_to: Option<f32>,
    /// Thinnest wall measured along the dent axis under the dent, world units (`None`: not
    /// measured, because the falloff cannot fold any wall under this map, or no ray met the body).
    pub wall_thickness: Option<f32>,
}

/// New positions computed for a mesh, not yet written into it.
pub(crate) struct PendingDisplacement {
    pub(crate) positions: Vec<Vec3>,
    pub(crate) moved: Vec<bool>,
    pub(crate) report: DisplaceReport,
}

impl PendingDisplacement {
    /// The displacement of `before` to `positions` (`moved` flags the vertices whose position
    /// changed) made with the falloff `fitted` (`None`: the caller's, not measured), with its
    /// report: vertices moved, the largest displacement, the wall measured and the thin-wall
    /// warning.
    ///
    /// # Errors
    /// [`DentError::NonFiniteResult`] if a position left the coordinate range.
    pub(crate) fn checked(
        before: &[Vec3],
        positions: Vec<Vec3>,
        moved: Vec<bool>,
        fitted: Option<FittedFalloff>,
    ) -> Result<Self, DentError> {
        if let Some(index) = positions.iter().position(|&p| !in_coordinate_range(p)) {
            return Err(DentError::NonFiniteResult { index });
        }
        // Both ends lie within ±MAX_COORDINATE, so the distance (at most 2·√3·10⁶) is finite in f32.
        let max_displacement = positions.iter().zip(before).map(|(new, old)| new.distance(*old)).fold(0.0, f32::max);
        let (warning, wall_thickness) = fitted.map_or((None, None), |f| (f.warning, f.thickness));
        let moved_vertices = moved.iter().filter(|&&m| m).count();
        let warnings = warning.into_iter().collect();
        let report =
            DisplaceReport { moved_vertices, max_displacement, warnings, wall_thickness, ..Default::default() };
        Ok(Self { positions, moved, report })
    }

    /// Writes the positions into `target` (the mesh they were computed from) and refreshes the
    /// normals around the moved vertices.
    pub(crate) fn commit(self, target: &mut TriMesh) -> DisplaceReport {
        target.positions_mut().copy_from_slice(&self.positions);
        target.recompute_normals_near(&self.moved);
        self.report
    }
}

impl DentMap {
    /// Displacement stored at cell (`row`, `col`), world units.
    ///
    /// # Panics
    /// If `row` or `col` is not below `grid.res`.
    pub fn displacement(&self, row: u32, col: u32) -> Vec3 {
        let res = self.grid.res as usize;
        assert!(row < self.grid.res && col < self.grid.res, "cell ({row}, {col}) outside the {res}² map");
        let [x, y, z, _] = self.cells[row as usize * res + col as usize];
        Vec3::new(x, y, z)
    }

    /// The unsheared heights (the smoothed profile mapped onto the plane), row-major.
    pub fn heights(&self) -> Vec<f32> {
        self.cells.iter().map(|c| c[3]).collect()
    }

    /// Largest displacement length in the map, world units.
    pub fn max_displacement(&self) -> f32 {
        self.cells.iter().map(|&[x, y, z, _]| Vec3::new(x, y, z).length()).fold(0.0, f32::max)
    }

    /// Applies the map to `target` with the falloff `attenuation` (paper §3.1): every vertex at
    /// depth z below the plane moves by `a(z)·D̂(x, y)`; normals near the dent are refreshed.
    /// Where the target's wall under the dent is thin enough for the falloff to fold it, the
    /// falloff is stretched in depth to keep half the wall, with a warning (see `thickness`).
    ///
    /// # Errors
    /// [`DentError::InvalidParameter`] for a bad falloff or map or a displacement too long to
    /// measure in f32, [`DentError::NonFiniteResult`] if a vertex would leave finite space;
    /// `target` is unchanged then.
    pub fn apply(&self, target: &mut TriMesh, attenuation: &Attenuation) -> Result<DisplaceReport, DentError> {
        self.validate()?;
        self.validate_cells()?;
        Ok(self.displaced(target, attenuation)?.commit(target))
    }

    /// Computes the displaced positions of `target` without writing them.
    pub(crate) fn displaced(
        &self,
        target: &TriMesh,
        attenuation: &Attenuation,
    ) -> Result<PendingDisplacement, DentError> {
        self.displaced_positions(target.positions(), target.faces(), attenuation)
    }

    /// Computes the displaced copy of `before` (the vertex positions of a target with `faces`)
    /// without writing it, with the falloff fitted to the target's thickness.
    pub(crate) fn displaced_positions(
        &self,
        before: &[Vec3],
        faces: &[[u32; 3]],
        attenuation: &Attenuation,
    ) -> Result<PendingDisplacement, DentError> {
        self.validate()?;
        let d = self.dent_distance;
        super::params::validate_attenuation(attenuation, d)?;
        let view = MapView { grid: self.grid, cells: &self.cells, dent_distance: self.dent_distance };
        let fitted = fit_falloff(&view, before, faces, attenuation);
        let (params, table) = self.displace_params(&fitted.attenuation, before.len());
        let mut positions = before.to_vec();
        let mut moved = vec![false; positions.len()];
        cpu::displace(&params, &self.cells, &table, &mut positions, &mut moved);
        PendingDisplacement::checked(before, positions, moved, Some(fitted))
    }

    kernels_fn! {
        /// The `displace` kernel's inputs that apply this map with `attenuation` to `vertex_count`
        /// vertices: its parameter block and falloff table.
        fn displace_params(&self, attenuation: &Attenuation, vertex_count: usize) -> (DisplaceParams, Vec<f32>) {
            let (falloff, falloff_scale, table) = cpu::falloff_table(attenuation, self.dent_distance);
            let params = DisplaceParams {
                grid: self.grid.uniform(),
                dent_distance: self.dent_distance,
                falloff,
                falloff_scale,
                vertex_count: vertex_count as u32,
                vertex_offset: 0,
                cell_offset: 0,
                table_offset: 0,
                table_len: table.len() as u32,
            };
            (params, table)
        }
    }

    fn validate(&self) -> Result<(), DentError> {
        let g = &self.grid;
        if !(self.dent_distance.is_finite() && self.dent_distance > 0.0) {
            return Err(invalid("dent_distance", self.dent_distance, "must be finite and > 0"));
        }
        if g.res == 0 || g.res > super::MAX_RESOLUTION || self.cells.len() != g.cell_count() {
            return Err(invalid("dent map res", g.res, "must be in 1..=2048 with res² cells"));
        }
        if !(g.cell_size.is_finite() && g.cell_size > 0.0) {
            return Err(invalid("dent map cell_size", g.cell_size, "must be finite and > 0"));
        }
        let axes_ok = [g.axis_x, g.axis_y, g.axis_z].iter().all(|a| (a.length() - 1.0).abs() < 1e-3);
        if !g.origin.is_finite() || !axes_ok {
            return Err(invalid("dent map grid", format!("{g:?}"), "needs a finite origin and unit axes"));
        }
        Ok(())
    }

    /// Fails when a cell holds a non-finite value: `O(res²)`, which a steep glance's mostly empty
    /// map makes the largest cost of applying it, so only maps from outside the pipeline pay it.
    fn validate_cells(&self) -> Result<(), DentError> {
        if self.cells.iter().flatten().any(|v| !v.is_finite()) {
            return Err(invalid("dent map cells", "non-finite", "every displacement must be finite"));
        }
        Ok(())
    }
}
