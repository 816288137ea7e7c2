//! Little-endian binary records and their base64 text: a writer, and a reader that checks every
//! length against the bytes left before it reads or allocates.

use glam::{Affine3A, Quat, Vec3};

use super::RecordError;

/// Appends little-endian values to a byte buffer.
#[derive(Debug, Default)]
pub struct ByteWriter {
    /// The bytes so far.
    pub bytes: Vec<u8>,
}

impl ByteWriter {
    /// One byte.
    pub fn u8(&mut self, v: u8) {
        self.bytes.push(v);
    }
    /// A u16, 2 bytes.
    pub fn u16(&mut self, v: u16) {
        self.bytes.extend_from_slice(&v.to_le_bytes());
    }
    /// A u32, 4 bytes.
    pub fn u32(&mut self, v: u32) {
        self.bytes.extend_from_slice(&v.to_le_bytes());
    }
    /// A u64, 8 bytes.
    pub fn u64(&mut self, v: u64) {
        self.bytes.extend_from_slice(&v.to_le_bytes());
    }
    /// An f32 by its bits, 4 bytes.
    pub fn f32(&mut self, v: f32) {
        self.u32(v.to_bits());
    }
    /// Three f32.
    pub fn vec3(&mut self, v: Vec3) {
        v.to_array().into_iter().for_each(|c| self.f32(c));
    }
    /// Four f32 (x, y, z, w).
    pub fn quat(&mut self, q: Quat) {
        q.to_array().into_iter().for_each(|c| self.f32(c));
    }
    /// Twelve f32: the matrix columns, then the translation.
    pub fn affine(&mut self, a: Affine3A) {
        a.to_cols_array().into_iter().for_each(|c| self.f32(c));
    }
    /// An unsigned LEB128 varint, 1–10 bytes.
    pub fn varint(&mut self, mut v: u64) {
        while v >= 0x80 {
            self.bytes.push((v as u8) | 0x80);
            v >>= 7;
        }
        self.bytes.push(v as u8);
    }
    /// A string of any length: its byte length as a varint, then its UTF-8 bytes.
    pub fn text(&mut self, s: &str) {
        self.varint(s.len() as u64);
        self.bytes.extend_from_slice(s.as_bytes());
    }
    /// A short string: its length (one byte, ≤ 255) and UTF-8 bytes; longer ones are cut at a
    /// character boundary.
    pub fn short_str(&mut self, s: &str) {
        let mut end = s.len().min(255);
        while !s.is_char_boundary(end) {
            end -= 1;
        }
        self.u8(end as u8);
        self.bytes.extend_from_slice(&s.as_bytes()[..end]);
    }
}

/// Reads little-endian values from a byte slice, refusing to read past its end.
#[derive(Debug)]
pub struct ByteReader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> ByteReader<'a> {
    /// A reader at the start of `bytes`.
    pub fn new(bytes: &'a [u8]) -> Self {
        Self { bytes, at: 0 }
    }

    /// Bytes not read yet.
    pub fn remaining(&self) -> usize {
        self.bytes.len() - self.at
    }

    /// The next `n` bytes.
    pub fn take(&mut self, n: usize, what: &'static str) -> Result<&'a [u8], RecordError> {
        if n > self.remaining() {
            return Err(RecordError::Truncated { what, needed: n, available: self.remaining() });
        }
        let out = &self.bytes[self.at..self.at + n];
        self.at += n;
        Ok(out)
    }

    /// One byte.
    pub fn u8(&mut self, what: &'static str) -> Result<u8, RecordError> {
        Ok(self.take(1, what)?[0])
    }
    /// A u16.
    pub fn u16(&mut self, what: &'static str) -> Result<u16, RecordError> {
        let b = self.take(2, what)?;
        Ok(u16::from_le_bytes([b[0], b[1]]))
    }
    /// A u32.
    pub fn u32(&mut self, what: &'static str) -> Result<u32, RecordError> {
        Ok(u32::from_le_bytes(self.take(4, what)?.try_into().expect("4 bytes")))
    }
    /// A u64.
    pub fn u64(&mut self, what: &'static str) -> Result<u64, RecordError> {
        Ok(u64::from_le_bytes(self.take(8, what)?.try_into().expect("8 bytes")))
    }
    /// An f32 from its bits.
    pub fn f32(&mut self, what: &'static str) -> Result<f32, RecordError> {
        self.u32(what).map(f32::from_bits)
    }
    /// Three f32.
    pub fn vec3(&mut self, what: &'static str) -> Result<Vec3, RecordError> {
        Ok(Vec3::new(self.f32(what)?, self.f32(what)?, self.f32(what)?))
    }
    /// Four f32.
    pub fn quat(&mut self, what: &'static str) -> Result<Quat, RecordError> {
        Ok(Quat::from_xyzw(self.f32(what)?, self.f32(what)?, self.f32(what)?, self.f32(what)?))
    }
    /// Twelve f32.
    pub fn affine(&mut self, what: &'static str) -> Result<Affine3A, RecordError> {
        let mut cols = [0.0f32; 12];
        for c in &mut cols {
            *c = self.f32(what)?;
        }
        Ok(Affine3A::from_cols_array(&cols))
    }
    /// An unsigned LEB128 varint of at most 64 bits.
    pub fn varint(&mut self, what: &'static str) -> Result<u64, RecordError> {
        let mut value = 0u64;
        for shift in (0..64).step_by(7) {
            let byte = self.u8(what)?;
            let bits = u64::from(byte & 0x7f);
            if shift == 63 && bits > 1 {
                break;
            }
            value |= bits << shift;
            if byte & 0x80 == 0 {
                return Ok(value);
            }
        }
        Err(RecordError::Malformed(format!("{what}: varint longer than 64 bits")))
    }
    /// A varint that must fit a u32.
    pub fn varint32(&mut self, what: &'static str) -> Result<u32, RecordError> {
        let v = self.varint(what)?;
        u32::try_from(v).map_err(|_| RecordError::Malformed(format!("{what}: {v} does not fit 32 bits")))
    }
    /// A count of items of at least `item_bytes` bytes each, refused when the bytes left
    /// cannot hold that many (so nothing absurd is allocated) or when it passes `limit`.
    pub fn count(&mut self, what: &'static str, item_bytes: usize, limit: u64) -> Result<usize, RecordError> {
        let n = self.varint(what)?;
        if n > limit {
            return Err(RecordError::TooLarge { what, count: n, limit });
        }
        let needed = (n as usize).saturating_mul(item_bytes.max(1));
        if needed > self.remaining() {
            return Err(RecordError::Truncated { what, needed, available: self.remaining() });
        }
        Ok(n as usize)
    }
    /// A string (see [`ByteWriter::text`]) of at most `limit` bytes, its length checked
    /// against the bytes left before it is read.
    pub fn text(&mut self, what: &'static str, limit: u64) -> Result<String, RecordError> {
        let n = self.count(what, 1, limit)?;
        let bytes = self.take(n, what)?;
        String::from_utf8(bytes.to_vec()).map_err(|_| RecordError::Malformed(format!("{what}: not UTF-8")))
    }
    /// A short string (see [`ByteWriter::short_str`]).
    pub fn short_str(&mut self, what: &'static str) -> Result<String, RecordError> {
        let n = self.u8(what)? as usize;
        let bytes = self.take(n, what)?;
        String::from_utf8(bytes.to_vec()).map_err(|_| RecordError::Malformed(format!("{what}: not UTF-8")))
    }
}

const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

/// Standard base64 (RFC 4648, with `=` padding).
pub fn base64_encode(bytes: &[u8]) -> String {
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [chunk[0], *chunk.get(1).unwrap_or(&0), *chunk.get(2).unwrap_or(&0)];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[((n >> (18 - 6 * k)) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// Decodes standard base64 with padding; `what` names the field in errors.
pub fn base64_decode(text: &str, what: &str) -> Result<Vec<u8>, RecordError> {
    let bad = |why: &str| RecordError::Malformed(format!("{what}: {why}"));
    let text = text.as_bytes();
    if !text.len().is_multiple_of(4) {
        return Err(bad("base64 length is not a multiple of 4 (truncated?)"));
    }
    let mut out = Vec::with_capacity(text.len() / 4 * 3);
    for (k, chunk) in text.chunks(4).enumerate() {
        let last = k + 1 == text.len() / 4;
        let pad = chunk.iter().rev().take_while(|&&c| c == b'=').count();
        if pad > 2 || (pad > 0 && !last) {
            return Err(bad("misplaced base64 padding"));
        }
        let mut n = 0u32;
        for &c in &chunk[..4 - pad] {
            let v = ALPHABET.iter().position(|&a| a == c).ok_or_else(|| bad("not base64"))?;
            n = (n << 6) | v as u32;
        }
        n <<= 6 * pad as u32;
        let bytes = [(n >> 16) as u8, (n >> 8) as u8, n as u8];
        out.extend_from_slice(&bytes[..3 - pad]);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_and_varints_round_trip() {
        for (plain, coded) in [("", ""), ("f", "Zg=="), ("fo", "Zm8="), ("foo", "Zm9v"), ("foobar", "Zm9vYmFy")] {
            assert_eq!(base64_encode(plain.as_bytes()), coded);
            assert_eq!(base64_decode(coded, "t").unwrap(), plain.as_bytes());
        }
        assert!(base64_decode("Zm9", "t").is_err());
        assert!(base64_decode("Z===", "t").is_err());
        let mut w = ByteWriter::default();
        for v in [0, 127, 128, 300, u64::from(u32::MAX), u64::MAX] {
            w.varint(v);
        }
        let mut r = ByteReader::new(&w.bytes);
        for v in [0, 127, 128, 300, u64::from(u32::MAX), u64::MAX] {
            assert_eq!(r.varint("v").unwrap(), v);
        }
        assert!(matches!(r.u8("end"), Err(RecordError::Truncated { .. })));
    }

    #[test]
    fn absurd_counts_are_refused_before_allocating() {
        let mut w = ByteWriter::default();
        w.varint(1 << 40);
        assert!(matches!(ByteReader::new(&w.bytes).count("items", 12, 1 << 50), Err(RecordError::Truncated { .. })));
        assert!(matches!(ByteReader::new(&w.bytes).count("items", 12, 1000), Err(RecordError::TooLarge { .. })));
    }
}
