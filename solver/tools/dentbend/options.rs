//! Arguments shared by the subcommands: the scene size, the projectile, the dent-map knobs, and
//! helpers to turn them into library values.

use clap::{Args, ValueEnum};
use dentbend::dent::Refine;
use dentbend::glam::{Affine3A, Mat3, Vec3};
use dentbend::{DentParams, Resolution, TriMesh, mesh};

use crate::error::{CliError, flag_error};
use crate::vector::parse_vec3;

/// `--size` of a built-in scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SizeChoice {
    /// The paper's sizes.
    Full,
    /// Small and quick.
    Demo,
}

/// The projectile mesh and its placement.
#[derive(Debug, Args)]
pub struct ProjectileOptions {
    /// Projectile mesh: an .obj or .ply path, or a built-in name (bunny, bunny-dense, sphere,
    /// uvsphere, box, block, block-fine, plank, cylinder, crate)
    #[arg(long, value_name = "MESH")]
    pub projectile: String,

    /// Scales the projectile uniformly about the origin of its file's coordinates, before
    /// --rotate (> 0)
    #[arg(long, value_name = "S", allow_negative_numbers = true)]
    pub scale: Option<f32>,

    /// Rotates the projectile by X, then Y, then Z degrees about the fixed x, y and z axes
    /// through the origin of its file's coordinates: p' = Rz·Ry·Rx·p, right-handed (a positive
    /// angle turns counter-clockwise seen from the axis' positive end)
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    pub rotate: Option<Vec3>,

    /// Moves the projectile by this offset after --rotate, mesh units
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    pub translate: Option<Vec3>,
}

impl ProjectileOptions {
    /// Loads the projectile and applies `--scale`, then `--rotate`, then `--translate`.
    pub fn load(&self) -> Result<TriMesh, CliError> {
        let scale = self.scale.unwrap_or(1.0);
        if !(scale.is_finite() && scale > 0.0) {
            return Err(CliError::Usage(format!("--scale {scale} is out of range: it must be finite and > 0")));
        }
        let mut projectile = load_mesh("projectile", &self.projectile)?;
        if self.scale.is_some() || self.rotate.is_some() || self.translate.is_some() {
            let placed = placement(scale, self.rotate_deg(), self.translation());
            projectile.transform(placed).map_err(CliError::Place)?;
        }
        Ok(projectile)
    }

    /// The rotation in degrees, zero when none was given.
    pub fn rotate_deg(&self) -> Vec3 {
        self.rotate.unwrap_or(Vec3::ZERO)
    }

    /// The translation, zero when none was given.
    pub fn translation(&self) -> Vec3 {
        self.translate.unwrap_or(Vec3::ZERO)
    }
}

/// Scales by `scale`, then rotates by `degrees` ([`rotation`]), then moves by `translate`.
pub fn placement(scale: f32, degrees: Vec3, translate: Vec3) -> Affine3A {
    Affine3A::from_mat3_translation(rotation(degrees) * Mat3::from_diagonal(Vec3::splat(scale)), translate)
}

/// `Rz·Ry·Rx` for Euler angles in degrees: rotate about x first, then y, then z.
pub fn rotation(degrees: Vec3) -> Mat3 {
    let r = degrees * (std::f32::consts::PI / 180.0);
    Mat3::from_rotation_z(r.z) * Mat3::from_rotation_y(r.y) * Mat3::from_rotation_x(r.x)
}

/// Loads a mesh file or built-in mesh for the given role (`"projectile"`, `"target"`).
pub fn load_mesh(role: &'static str, spec: &str) -> Result<TriMesh, CliError> {
    mesh::load(spec).map_err(|source| CliError::Load { role, spec: spec.to_owned(), source })
}

/// The dent-map knobs ([`DentParams`]); lengths are in the meshes' units.
#[derive(Debug, Args)]
pub struct MapOptions {
    /// Dent distance d: depth of the dent and peak of its profile, mesh units (> 0)
    #[arg(long, value_name = "D", allow_negative_numbers = true)]
    pub dent_distance: f32,

    /// Z-buffer grid side, cells (1..=2048) [default: automatic, 25..=400 from the meshes' mean
    /// edge lengths]
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub res: Option<u32>,

    /// Width σ of the broadening Gaussians, mesh units (> 0) [default: d/2]
    #[arg(long, value_name = "S", allow_negative_numbers = true)]
    pub sigma: Option<f32>,

    /// k₁: plain heat-smoothing steps after broadening
    #[arg(long, value_name = "K", default_value_t = DentParams::new(1.0).heat_iters)]
    pub heat_iters: u32,

    /// k₂: clamped, increase-only heat-smoothing steps after rescaling to d
    #[arg(long, value_name = "K", default_value_t = DentParams::new(1.0).clamp_iters)]
    pub clamp_iters: u32,

    /// α of each heat step E ← E + α·ΔE, in (0, 0.25]
    #[arg(long, value_name = "A", default_value_t = DentParams::new(1.0).heat_rate)]
    pub heat_rate: f32,

    /// Widening t of glancing dents' leading side, 1/mesh unit (≥ 0; 0 is the plain shear)
    #[arg(long, value_name = "T", default_value_t = DentParams::new(1.0).widen, allow_negative_numbers = true)]
    pub widen: f32,

    /// Lower clamp of cos θ for glancing impacts, in [0.01, 1] (0.1 allows θ up to 84.3°)
    #[arg(long, value_name = "C", default_value_t = DentParams::new(1.0).min_cos)]
    pub min_cos: f32,
}

impl MapOptions {
    /// The validated parameters (falloff left at the default).
    pub fn params(&self) -> Result<DentParams, CliError> {
        let defaults = DentParams::new(self.dent_distance);
        let params = DentParams {
            sigma: self.sigma,
            resolution: self.res.map_or(defaults.resolution, Resolution::Fixed),
            heat_iters: self.heat_iters,
            clamp_iters: self.clamp_iters,
            heat_rate: self.heat_rate,
            widen: self.widen,
            min_cos: self.min_cos,
            ..defaults
        };
        params.validate().map_err(flag_error)?;
        Ok(params)
    }
}

/// `--refine`: `auto`, `off`, or a maximum edge length (mesh units; its range is checked with
/// the other parameters).
pub fn parse_refine(text: &str) -> Result<Refine, String> {
    match text {
        "auto" => Ok(Refine::default()),
        "off" => Ok(Refine::Off),
        _ => text
            .parse::<f32>()
            .map(Refine::MaxEdge)
            .map_err(|_| format!("expected auto, off or a maximum edge length, got {text:?}")),
    }
}

/// Checks that a direction given as `flag` is not the zero vector.
pub fn nonzero(v: Vec3, flag: &str) -> Result<Vec3, CliError> {
    if v.length_squared() < f32::MIN_POSITIVE {
        return Err(CliError::Usage(format!("{flag} must be a non-zero vector, got {}", fmt_vec(v))));
    }
    Ok(v)
}

/// `x` with three significant digits (`0.0313`, `212`, `0.200`; `8.75e27` outside 1e-3..1e5).
pub fn sig3(x: f32) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    if !(1e-3..1e5).contains(&x.abs()) {
        return format!("{x:.2e}");
    }
    let decimals = (2 - x.abs().log10().floor() as i32).max(0) as usize;
    format!("{x:.decimals$}")
}

/// `x,y,z` with [`sig3`] components.
pub fn fmt_vec(v: Vec3) -> String {
    format!("{},{},{}", sig3(v.x), sig3(v.y), sig3(v.z))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_is_x_then_y_then_z_about_fixed_axes() {
        let close = |a: Vec3, b: Vec3| a.distance(b) < 1e-6;
        assert!(close(rotation(Vec3::new(90.0, 0.0, 0.0)) * Vec3::Y, Vec3::Z));
        assert!(close(rotation(Vec3::new(0.0, 90.0, 0.0)) * Vec3::Z, Vec3::X));
        assert!(close(rotation(Vec3::new(0.0, 0.0, 90.0)) * Vec3::X, Vec3::Y));
        // x first: y → z (about x), then z stays (about z).
        assert!(close(rotation(Vec3::new(90.0, 0.0, 90.0)) * Vec3::Y, Vec3::Z));
        assert!(close(rotation(Vec3::new(90.0, 0.0, 90.0)) * Vec3::X, Vec3::Y));
    }

    #[test]
    fn three_significant_digits() {
        assert_eq!(sig3(0.031_37), "0.0314");
        assert_eq!(sig3(212.4), "212");
        assert_eq!(sig3(0.2), "0.200");
        assert_eq!(sig3(0.0), "0");
        assert_eq!(sig3(8.75e27), "8.75e27");
        assert_eq!(sig3(-1.26e-30), "-1.26e-30");
    }
}
