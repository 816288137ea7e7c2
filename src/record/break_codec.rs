//! The compact binary form of a fracture as the fracture module rebuilds it
//! ([`crate::fracture::FractureRecord`]): the pattern's cell count (varint), seed (u64) and
//! radius (f32), the placement's point and normal (3 × f32 each) and the density (f32): 41 to
//! 45 bytes. Damage files and replication messages both carry it. Whether the output is welded
//! is not part of it: a damage file tells in the record's tag, and replication only carries
//! fractures made live, which keep a mesh's seams.

use super::RecordError;
use super::bytes::{ByteReader, ByteWriter};
use crate::fracture::{FractureRecord, PatternParams, Placement};

/// Appends `record` to `out`.
pub fn write_break(out: &mut ByteWriter, record: &FractureRecord) {
    let FractureRecord { pattern, placement, density, weld_output: _ } = record;
    out.varint(u64::from(pattern.cells));
    out.u64(pattern.seed);
    out.f32(pattern.radius);
    out.vec3(placement.point);
    out.vec3(placement.normal);
    out.f32(*density);
}

/// Reads a record written by [`write_break`]; its values are checked when it is replayed. The
/// output keeps the mesh's seams (a file of version 1 says otherwise for its records).
pub fn read_break(r: &mut ByteReader<'_>) -> Result<FractureRecord, RecordError> {
    let pattern = PatternParams { cells: r.varint32("cells")?, seed: r.u64("seed")?, radius: r.f32("radius")? };
    let placement = Placement { point: r.vec3("fracture point")?, normal: r.vec3("fracture normal")? };
    Ok(FractureRecord { pattern, placement, density: r.f32("density")?, weld_output: false })
}
