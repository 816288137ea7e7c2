//! Dent maps that do not come from a projectile: painted height maps (PNG) and analytic
//! Gaussians (paper §3.1), so an artist can supply the shape of a dent.

use super::error::invalid;
use super::{DentError, DentFrame, DentMap, DentParams, Grid, Impact, MAX_RESOLUTION, Resolution, plan};

/// Side of an analytic Gaussian map when the resolution is automatic, cells: odd, so a cell
/// centre sits on the impact point and the map's peak is exactly d.
const GAUSSIAN_AUTO_RES: u32 = 65;

impl DentMap {
    /// Places a height field at an impact. `heights` (`res × res`, row-major, world units, ≥ 0)
    /// is the dent as seen along the relative velocity, on a square of side `extent` (world
    /// units) centred on the impact point; glancing impacts stretch and shear it exactly like
    /// a projectile's profile (paper §3.3). Column `i` runs along the in-plane velocity
    /// direction t̂, row `j` along n̂ × t̂.
    ///
    /// # Errors
    /// Invalid parameters, impact, size or heights (negative or non-finite).
    pub fn from_heights(
        heights: &[f32],
        res: u32,
        extent: f32,
        impact: &Impact,
        params: &DentParams,
    ) -> Result<Self, DentError> {
        params.validate()?;
        impact.validate()?;
        if !(1..=MAX_RESOLUTION).contains(&res) || heights.len() != (res as usize).pow(2) {
            return Err(invalid(
                "heights",
                format!("{} values for res {res}", heights.len()),
                "need res² values, res in 1..=2048",
            ));
        }
        if !(extent.is_finite() && extent > 0.0) {
            return Err(invalid("extent", extent, "must be finite and > 0"));
        }
        if let Some(bad) = heights.iter().find(|h| !(h.is_finite() && **h >= 0.0)) {
            return Err(invalid("heights", bad, "every height must be finite and >= 0"));
        }
        let frame = DentFrame::new(impact, params.min_cos);
        let (axis_x, axis_y, axis_z) = frame.zbuffer_axes();
        let grid = Grid { origin: impact.point, axis_x, axis_y, axis_z, cell_size: extent / res as f32, res };
        let map_grid = plan::map_grid(&grid, impact.point, &frame);
        let mut cells = vec![[0.0; 4]; map_grid.cell_count()];
        crate::cpu::glance(&plan::glance_params(&grid, &map_grid, &frame, params.widen), heights, &mut cells);
        Ok(Self { grid: map_grid, cells, dent_distance: params.dent_distance })
    }

    #[cfg(feature = "io")]
    /// Reads a square 8- or 16-bit grayscale PNG (see `io::read_height_png`; `io` feature) as a dent
    /// of side `extent` (world units): its brightest pixel becomes the dent distance, black is
    /// no dent. Pixel (row r, column c) is cell (r, c) of [`from_heights`](Self::from_heights).
    ///
    /// # Errors
    /// [`DentError::Image`] for unreadable, non-square or all-black pictures and for pictures
    /// wider than [`MAX_RESOLUTION`] pixels (refused from the header, before decoding);
    /// otherwise as [`from_heights`](Self::from_heights).
    pub fn from_png(
        path: impl AsRef<std::path::Path>,
        extent: f32,
        impact: &Impact,
        params: &DentParams,
    ) -> Result<Self, DentError> {
        let path = path.as_ref();
        let image = crate::io::read_height_png_within(path, MAX_RESOLUTION).map_err(|e| read_error(path, e))?;
        Self::from_height_image(&image, path, extent, impact, params)
    }

    #[cfg(feature = "io")]
    /// [`from_png`](Self::from_png) for the bytes of a PNG held in memory (`io` feature); errors
    /// name the path `<memory>`.
    ///
    /// # Errors
    /// As [`from_png`](Self::from_png).
    pub fn from_png_bytes(bytes: &[u8], extent: f32, impact: &Impact, params: &DentParams) -> Result<Self, DentError> {
        let path = std::path::Path::new("<memory>");
        let image = crate::io::decode_height_png_within(bytes, MAX_RESOLUTION).map_err(|e| read_error(path, e))?;
        Self::from_height_image(&image, path, extent, impact, params)
    }

    #[cfg(feature = "io")]
    /// A decoded height picture, named `path` in errors, as in [`from_png`](Self::from_png).
    fn from_height_image(
        image: &crate::io::HeightImage,
        path: &std::path::Path,
        extent: f32,
        impact: &Impact,
        params: &DentParams,
    ) -> Result<Self, DentError> {
        if image.width != image.height {
            let message = format!("is {}×{} pixels; dent maps must be square", image.width, image.height);
            return Err(image_error(path, message));
        }
        let peak = image.values.iter().copied().fold(0.0, f32::max);
        if peak <= 0.0 {
            return Err(image_error(path, "is black everywhere: no dent to apply".into()));
        }
        let scale = params.dent_distance / peak;
        let heights: Vec<f32> = image.values.iter().map(|v| v * scale).collect();
        Self::from_heights(&heights, image.width, extent, impact, params)
    }

    /// An analytic Gaussian dent `d·exp(−r²/(2w²))` of width `width` (world units) at the
    /// impact, on a grid of side `7·width` (65 cells unless the resolution is fixed).
    ///
    /// # Errors
    /// Invalid parameters, impact or width.
    pub fn gaussian(width: f32, impact: &Impact, params: &DentParams) -> Result<Self, DentError> {
        if !(width.is_finite() && width > 0.0) {
            return Err(invalid("width", width, "must be finite and > 0"));
        }
        params.validate()?; // before sizing the grid from `params.resolution`
        let res = match params.resolution {
            Resolution::Fixed(n) => n,
            Resolution::Auto { min, max } => GAUSSIAN_AUTO_RES.clamp(min, max),
        };
        let extent = 2.0 * plan::TAIL_SIGMAS * width;
        let heights = gaussian_heights(res, extent, width, params.dent_distance);
        Self::from_heights(&heights, res, extent, impact, params)
    }
}

/// `d·exp(−r²/(2σ²))` at the cell centres of a `res × res` grid of side `extent` centred on
/// r = 0 (world units).
pub(crate) fn gaussian_heights(res: u32, extent: f32, sigma: f32, dent_distance: f32) -> Vec<f32> {
    let h = extent / res as f32;
    let shift = 0.5 * res as f32 - 0.5;
    let c = 0.5 / (sigma * sigma);
    (0..res)
        .flat_map(|row| (0..res).map(move |col| (row, col)))
        .map(|(row, col)| {
            let (x, y) = ((col as f32 - shift) * h, (row as f32 - shift) * h);
            dent_distance * (-c * (x * x + y * y)).exp()
        })
        .collect()
}

#[cfg(feature = "io")]
/// A [`DentError::Image`] about the picture at `path`.
fn image_error(path: &std::path::Path, message: String) -> DentError {
    DentError::Image { path: path.to_path_buf(), message }
}

#[cfg(feature = "io")]
/// A picture that could not be read as a [`DentError::Image`]; one over the largest dent map
/// ([`MAX_RESOLUTION`] pixels a side, refused from its header) says so.
fn read_error(path: &std::path::Path, error: crate::io::IoError) -> DentError {
    match error {
        crate::io::IoError::Image { source: image::ImageError::Limits(_), .. } => {
            image_error(path, format!("is larger than {MAX_RESOLUTION}×{MAX_RESOLUTION} pixels, the largest dent map"))
        }
        other => image_error(path, other.to_string()),
    }
}
