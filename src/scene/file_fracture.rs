//! `[body.fracture]`: a breakable body's pattern and toughness, read and checked with the error
//! placed on the field at fault.

use serde::Deserialize;
use toml::Spanned;

use super::SceneError;
use super::source::Source;
use crate::fracture::{FractureError, FractureSettings, PatternParams};

/// Cells of a pattern when `[body.fracture]` gives none.
pub const DEFAULT_FRACTURE_CELLS: u32 = 32;

/// `[body.fracture]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct FractureFile {
    /// Voronoi cells of the pattern.
    pub cells: Option<Spanned<u32>>,
    /// Seed of the pattern's generator.
    pub seed: Option<Spanned<u64>>,
    /// m.
    pub radius: Spanned<f32>,
    /// J.
    pub toughness: Option<Spanned<f32>>,
    /// m.
    pub dent_limit: Option<Spanned<f32>>,
    /// kg/m³ (pieces of a static or kinematic body).
    pub density: Option<Spanned<f32>>,
}

/// `[body.fracture]` of body `body` → its settings (`density`: the body's, the default for its
/// pieces), checked by [`FractureSettings::new`] with the error placed on the field it names.
pub(super) fn fracture_settings(
    src: &Source<'_>,
    body: &str,
    fracture: &Spanned<FractureFile>,
    density: f32,
) -> Result<FractureSettings, SceneError> {
    let file = fracture.get_ref();
    let value = |v: &Option<Spanned<f32>>| v.as_ref().map(|v| *v.get_ref());
    let params = PatternParams {
        cells: file.cells.as_ref().map_or(DEFAULT_FRACTURE_CELLS, |c| *c.get_ref()),
        seed: file.seed.as_ref().map_or(0, |s| *s.get_ref()),
        radius: *file.radius.get_ref(),
    };
    let error = |error: FractureError| {
        let (field, at) = match &error {
            FractureError::InvalidParameter { name, .. } => match *name {
                "cells" => ("cells", file.cells.as_ref().map(Spanned::span)),
                "radius" => ("radius", Some(file.radius.span())),
                "toughness" => ("toughness", file.toughness.as_ref().map(Spanned::span)),
                "dent_limit" => ("dent_limit", file.dent_limit.as_ref().map(Spanned::span)),
                "density" => ("density", file.density.as_ref().map(Spanned::span)),
                other => (other, None),
            },
            _ => ("", None),
        };
        let message = match (&error, &at) {
            (FractureError::InvalidParameter { value, reason, .. }, Some(_)) => format!("{value} {reason}"),
            (FractureError::InvalidParameter { reason, .. }, None) => (*reason).to_owned(),
            (other, _) => other.to_string(),
        };
        // A value the file does not give is the table's fault.
        let field = if at.is_some() { format!("fracture.{field}") } else { "fracture".to_owned() };
        src.error_at(at.unwrap_or_else(|| fracture.span()), Some(body), &field, message)
    };
    let mut settings =
        FractureSettings::new(params, value(&file.toughness), value(&file.dent_limit)).map_err(&error)?;
    settings.density = value(&file.density).unwrap_or(density);
    settings.validate().map_err(error)?;
    Ok(settings)
}
