//! [`DentParams`] as bytes: every field, so that a replayed dent is computed exactly as the
//! recorded one. The field list is destructured without `..`: a new field of `DentParams`
//! fails to compile here until it is recorded too.

use super::RecordError;
use super::bytes::{ByteReader, ByteWriter};
use crate::dent::{Attenuation, DentParams, Refine, Resolution, VolumeMode};

/// Appends `params`.
///
/// # Errors
/// [`RecordError::NotRecordable`] for a custom falloff (a function, not data).
pub fn write_params(out: &mut ByteWriter, params: &DentParams) -> Result<(), RecordError> {
    let DentParams {
        dent_distance,
        sigma,
        resolution,
        heat_iters,
        clamp_iters,
        heat_rate,
        attenuation,
        widen,
        min_cos,
        refine,
        volume,
        guard_crossings,
    } = params;
    out.f32(*dent_distance);
    match sigma {
        None => out.u8(0),
        Some(s) => {
            out.u8(1);
            out.f32(*s);
        }
    }
    match resolution {
        Resolution::Auto { min, max } => {
            out.u8(0);
            out.u32(*min);
            out.u32(*max);
        }
        Resolution::Fixed(n) => {
            out.u8(1);
            out.u32(*n);
        }
    }
    out.u32(*heat_iters);
    out.u32(*clamp_iters);
    out.f32(*heat_rate);
    match attenuation {
        Attenuation::Logistic => out.u8(0),
        Attenuation::Linear { scale } => {
            out.u8(1);
            out.f32(*scale);
        }
        Attenuation::None => out.u8(2),
        Attenuation::Custom(_) => {
            return Err(RecordError::NotRecordable("a custom falloff function as a dent parameter".into()));
        }
    }
    out.f32(*widen);
    out.f32(*min_cos);
    match refine {
        Refine::Auto { max_new_triangles } => {
            out.u8(0);
            out.u32(*max_new_triangles);
        }
        Refine::Off => out.u8(1),
        Refine::MaxEdge(edge) => {
            out.u8(2);
            out.f32(*edge);
        }
    }
    out.u8(match volume {
        VolumeMode::Free => 0,
        VolumeMode::Preserve => 1,
    });
    out.u8(u8::from(*guard_crossings));
    Ok(())
}

/// Reads [`write_params`]' bytes and validates them.
pub fn read_params(r: &mut ByteReader<'_>) -> Result<DentParams, RecordError> {
    let dent_distance = r.f32("dent distance")?;
    let sigma = match r.u8("sigma flag")? {
        0 => None,
        1 => Some(r.f32("sigma")?),
        t => return Err(RecordError::Malformed(format!("sigma flag {t}"))),
    };
    let resolution = match r.u8("resolution kind")? {
        0 => Resolution::Auto { min: r.u32("resolution min")?, max: r.u32("resolution max")? },
        1 => Resolution::Fixed(r.u32("resolution")?),
        t => return Err(RecordError::Malformed(format!("resolution kind {t}"))),
    };
    let heat_iters = r.u32("heat iterations")?;
    let clamp_iters = r.u32("clamp iterations")?;
    let heat_rate = r.f32("heat rate")?;
    let attenuation = match r.u8("falloff kind")? {
        0 => Attenuation::Logistic,
        1 => Attenuation::Linear { scale: r.f32("falloff scale")? },
        2 => Attenuation::None,
        t => return Err(RecordError::Malformed(format!("falloff kind {t}"))),
    };
    let widen = r.f32("widen")?;
    let min_cos = r.f32("min cos")?;
    let refine = match r.u8("refine kind")? {
        0 => Refine::Auto { max_new_triangles: r.u32("refine cap")? },
        1 => Refine::Off,
        2 => Refine::MaxEdge(r.f32("refine edge")?),
        t => return Err(RecordError::Malformed(format!("refine kind {t}"))),
    };
    let volume = match r.u8("volume mode")? {
        0 => VolumeMode::Free,
        1 => VolumeMode::Preserve,
        t => return Err(RecordError::Malformed(format!("volume mode {t}"))),
    };
    let guard_crossings = match r.u8("guard flag")? {
        0 => false,
        1 => true,
        t => return Err(RecordError::Malformed(format!("guard flag {t}"))),
    };
    let params = DentParams {
        dent_distance,
        sigma,
        resolution,
        heat_iters,
        clamp_iters,
        heat_rate,
        attenuation,
        widen,
        min_cos,
        refine,
        volume,
        guard_crossings,
    };
    params.validate()?;
    Ok(params)
}
