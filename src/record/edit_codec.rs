//! The compact binary form of a [`MeshEdit`]: counts and indices as LEB128 varints, ascending
//! indices delta-coded (a dent's moved vertices are mostly neighbours: one byte each), moved
//! coordinates as their steps in f32 bits, zigzag varints (a coordinate a dent's tail moves by
//! a few ulps takes one byte, an unmoved one a zero byte), new vertices as the exact
//! little-endian bits of their coordinates.

use super::RecordError;
use super::bytes::{ByteReader, ByteWriter};
use crate::mesh::MeshEdit;

/// Most vertices or faces an edit may name: 2²⁸ (a mesh far beyond what dentbend handles).
pub(crate) const MAX_EDIT_ITEMS: u64 = 1 << 28;

/// Appends `edit` to `out`.
pub fn write_edit(out: &mut ByteWriter, edit: &MeshEdit) {
    out.varint(u64::from(edit.base_vertices));
    out.varint(u64::from(edit.base_faces));
    write_ascending(out, edit.moved.iter().map(|m| m.0), edit.moved.len());
    edit.moved.iter().flat_map(|m| m.1).for_each(|step| out.varint(u64::from(zigzag(step))));
    out.varint(edit.appended_vertices.len() as u64);
    edit.appended_vertices.iter().for_each(|&p| out.vec3(p));
    write_ascending(out, edit.changed_faces.iter().map(|c| c.0), edit.changed_faces.len());
    edit.changed_faces.iter().for_each(|c| c.1.iter().for_each(|&v| out.varint(u64::from(v))));
    out.varint(edit.appended_faces.len() as u64);
    edit.appended_faces.iter().flatten().for_each(|&v| out.varint(u64::from(v)));
}

/// Reads an edit written by [`write_edit`].
pub fn read_edit(r: &mut ByteReader<'_>) -> Result<MeshEdit, RecordError> {
    let base_vertices = r.varint32("edit base vertex count")?;
    let base_faces = r.varint32("edit base face count")?;
    // A moved vertex takes at least 1 index byte and 3 step bytes.
    let moved_at = read_ascending(r, "moved vertices", 4)?;
    let mut moved = Vec::with_capacity(moved_at.len());
    for v in moved_at {
        moved.push((v, [read_step(r)?, read_step(r)?, read_step(r)?]));
    }
    let n = r.count("appended vertices", 12, MAX_EDIT_ITEMS)?;
    let mut appended_vertices = Vec::with_capacity(n);
    for _ in 0..n {
        appended_vertices.push(r.vec3("appended vertex")?);
    }
    let changed_at = read_ascending(r, "changed faces", 4)?;
    let mut changed_faces = Vec::with_capacity(changed_at.len());
    for f in changed_at {
        changed_faces.push((f, read_face(r)?));
    }
    let n = r.count("appended faces", 3, MAX_EDIT_ITEMS)?;
    let mut appended_faces = Vec::with_capacity(n);
    for _ in 0..n {
        appended_faces.push(read_face(r)?);
    }
    Ok(MeshEdit { base_vertices, base_faces, moved, appended_vertices, changed_faces, appended_faces })
}

/// `v` with its sign in the lowest bit: small magnitudes of either sign stay small.
fn zigzag(v: i32) -> u32 {
    ((v << 1) ^ (v >> 31)) as u32
}

fn read_step(r: &mut ByteReader<'_>) -> Result<i32, RecordError> {
    let z = r.varint32("moved vertex step")?;
    Ok(((z >> 1) as i32) ^ -((z & 1) as i32))
}

fn read_face(r: &mut ByteReader<'_>) -> Result<[u32; 3], RecordError> {
    Ok([r.varint32("face index")?, r.varint32("face index")?, r.varint32("face index")?])
}

/// A strictly ascending index list: its length, the first index, then each gap minus one.
fn write_ascending(out: &mut ByteWriter, indices: impl Iterator<Item = u32>, len: usize) {
    out.varint(len as u64);
    let mut next = 0u32;
    for i in indices {
        out.varint(u64::from(i - next));
        next = i + 1;
    }
}

/// Reads [`write_ascending`]'s list; each entry is followed by at least `item_bytes` bytes in
/// all (its index byte included), which bounds the count by the bytes left.
fn read_ascending(r: &mut ByteReader<'_>, what: &'static str, item_bytes: usize) -> Result<Vec<u32>, RecordError> {
    let n = r.count(what, item_bytes, MAX_EDIT_ITEMS)?;
    let mut out = Vec::with_capacity(n);
    let mut next = 0u64;
    for _ in 0..n {
        let i = next + r.varint(what)?;
        let i = u32::try_from(i).map_err(|_| RecordError::Malformed(format!("{what}: index {i} beyond 32 bits")))?;
        out.push(i);
        next = u64::from(i) + 1;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn edits_round_trip_bit_for_bit() {
        let edit = MeshEdit {
            base_vertices: 10,
            base_faces: 4,
            moved: vec![(0, [0, -1, i32::MIN]), (1, [i32::MAX, 7, -300]), (9, [1, 0, 0])],
            appended_vertices: vec![Vec3::new(0.25, 0.5, 0.75)],
            changed_faces: vec![(3, [0, 1, 10])],
            appended_faces: vec![[1, 2, 10], [2, 0, 10]],
        };
        let mut w = ByteWriter::default();
        write_edit(&mut w, &edit);
        let back = read_edit(&mut ByteReader::new(&w.bytes)).unwrap();
        let minus_zero = MeshEdit::stepped(Vec3::ZERO, MeshEdit::step(Vec3::ZERO, Vec3::new(-0.0, 1.0, -1.0)));
        assert_eq!(minus_zero.x.to_bits(), (-0.0f32).to_bits());
        assert_eq!((minus_zero.y, minus_zero.z), (1.0, -1.0));
        assert_eq!(back, edit);
        for cut in 0..w.bytes.len() {
            assert!(read_edit(&mut ByteReader::new(&w.bytes[..cut])).is_err(), "cut at {cut}");
        }
    }
}
