//! `[body.fracture]`: a breakable body's pattern and toughness, read and checked with the error
//! placed on the field at fault.

use std::ops::Range;

use toml::Spanned;

use super::file::FractureFile;
use dentbend::fracture::{FractureError, FractureSettings, PatternParams};

/// Cells of a pattern when `[body.fracture]` gives none.
pub const DEFAULT_FRACTURE_CELLS: u32 = 32;

/// A refused `[body.fracture]` value: the field (`fracture.<key>`, or `fracture` for the table),
/// where it is written, and why.
pub(super) struct FieldError {
    pub field: String,
    pub span: Range<usize>,
    pub message: String,
}

/// `[body.fracture]` → its settings (`density`: the body's, the default for its pieces),
/// checked by [`FractureSettings::new`] with the error placed on the field it names.
pub(super) fn fracture_settings(
    fracture: &Spanned<FractureFile>,
    density: f32,
) -> Result<FractureSettings, FieldError> {
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
                "max_pieces" => ("max_pieces", file.max_pieces.as_ref().map(Spanned::span)),
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
        FieldError { field, span: at.unwrap_or_else(|| fracture.span()), message }
    };
    let mut settings =
        FractureSettings::new(params, value(&file.toughness), value(&file.dent_limit)).map_err(&error)?;
    settings.density = value(&file.density).unwrap_or(density);
    if let Some(limit) = &file.max_pieces {
        settings.max_pieces = *limit.get_ref();
    }
    settings.validate().map_err(error)?;
    Ok(settings)
}
