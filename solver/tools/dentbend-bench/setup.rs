//! The inputs every benchmark shares: the paper's Table 1 scene (the bunny projectile, Figure
//! 5a far right) on a grid of a given side, and a dense target for `displace`.

use dentbend::cpu::DisplaceParams;
use dentbend::dent::dent_map_stages;
use dentbend::dent::{DentPlan, DentStages, plan_dent};
use dentbend::glam::{Affine3A, Vec3};
use dentbend::{DentMap, DentParams, Impact, Resolution, TriMesh, dent_map, mesh};

/// Dent distance of the Table 1 scene, world units: about a third of the bunny's 10-unit size,
/// so the profile holds the head and both ears.
pub const DENT_DISTANCE: f32 = 3.0;
/// Gaussian width of the Table 1 scene, world units.
pub const SIGMA: f32 = 0.5;

/// One grid side's worth of kernel inputs.
pub struct Scene {
    pub projectile: TriMesh,
    pub params: DentParams,
    /// Frame, grids and each kernel's parameter block.
    pub plan: DentPlan,
    /// Every stage's output, the inputs of the next kernel.
    pub stages: DentStages,
}

impl Scene {
    /// The bunny falling ears first (along +y) onto a target above it, on a `res × res` grid.
    pub fn table1(res: u32) -> Result<Self, String> {
        let projectile = mesh::builtin("bunny").map_err(|e| e.to_string())?;
        let tip = projectile.support_point(Vec3::Y);
        let impact = Impact { point: tip, normal: Vec3::Y, relative_velocity: Vec3::Y };
        let params =
            DentParams { sigma: Some(SIGMA), resolution: Resolution::Fixed(res), ..DentParams::new(DENT_DISTANCE) };
        let plan = plan_dent(&projectile, &impact, &params, None).map_err(|e| e.to_string())?;
        let stages = dent_map_stages(&projectile, &impact, &params, None).map_err(|e| e.to_string())?;
        Ok(Self { projectile, params, plan, stages })
    }
}

/// Cells per axis of the `displace` target: 101,570 vertices.
pub const DISPLACE_CELLS: [u32; 3] = [184, 46, 184];

/// A 4 × 1 × 4 block dented on its top face by a unit ball: the `displace` inputs.
pub struct DisplaceScene {
    pub target: TriMesh,
    pub map: DentMap,
    pub params: DentParams,
    /// Falloff samples for [`dentbend::cpu::displace`] (empty for the built-in falloffs).
    pub table: Vec<f32>,
    pub kernel_params: DisplaceParams,
}

impl DisplaceScene {
    /// The block gridded to `cells` per axis and the ball's dent map for it.
    pub fn new(cells: [u32; 3]) -> Result<Self, String> {
        let target = mesh::subdivided_box(Vec3::new(4.0, 1.0, 4.0), cells).map_err(|e| e.to_string())?;
        let mut ball = mesh::builtin("sphere").map_err(|e| e.to_string())?;
        ball.transform(Affine3A::from_translation(Vec3::new(0.0, 1.5, 0.0))).map_err(|e| e.to_string())?;
        let impact = Impact { point: Vec3::new(0.0, 0.5, 0.0), normal: -Vec3::Y, relative_velocity: -Vec3::Y };
        let params = DentParams::new(0.2);
        let map = dent_map(&ball, &impact, &params, Some(target.mean_edge_length())).map_err(|e| e.to_string())?;
        let (kernel_params, table) = map.displace_params(&params.attenuation, target.vertex_count());
        Ok(Self { target, map, params, table, kernel_params })
    }
}
