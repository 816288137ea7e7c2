//! PLY data sources: one text line per element entry (ASCII) or a byte stream (binary, either
//! endianness), each checking declared counts against the data actually present.

use super::ply_header::{Header, Scalar};

/// Where values come from: one text line per element entry, or a binary stream.
pub(super) trait Source {
    /// Checks that the declared element counts fit in the data present.
    fn check_counts(&self, header: &Header) -> Result<(), String>;
    /// Starts the next entry.
    fn begin(&mut self) -> Result<(), String>;
    /// Reads one value of type `ty`.
    fn value(&mut self, ty: Scalar) -> Result<f64, String>;
    /// Reads a list length, checked against the data left for items of type `item`.
    fn list_len(&mut self, count: Scalar, item: Scalar) -> Result<u64, String>;
    /// Ends the current entry.
    fn end(&mut self) -> Result<(), String>;
    /// Checks that nothing but whitespace follows the last element.
    fn finish(&mut self) -> Result<(), String>;
}

fn too_much_declared(entries: u128, available: String) -> String {
    format!("the header declares {entries} entries in all but only {available} (truncated file or wrong counts)")
}

/// ASCII data: one text line per element entry, values separated by whitespace.
pub(super) struct AsciiSource<'a> {
    data: &'a [u8],
    pos: usize,
    /// Number of the line last read (1-based, counting the header).
    line: usize,
    tokens: Vec<&'a str>,
    next: usize,
}

impl<'a> AsciiSource<'a> {
    pub(super) fn new(data: &'a [u8], header_lines: usize) -> Self {
        Self { data, pos: 0, line: header_lines, tokens: Vec::new(), next: 0 }
    }

    /// The next line, or `None` at the end of the data.
    fn next_line(&mut self) -> Result<Option<&'a str>, String> {
        if self.pos >= self.data.len() {
            return Ok(None);
        }
        let rest = &self.data[self.pos..];
        let len = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
        self.pos += len + 1;
        self.line += 1;
        let text = std::str::from_utf8(&rest[..len]).map_err(|_| format!("line {}: not ASCII text", self.line))?;
        Ok(Some(text))
    }
}

impl Source for AsciiSource<'_> {
    fn check_counts(&self, header: &Header) -> Result<(), String> {
        let entries: u128 = header.elements.iter().map(|e| u128::from(e.count)).sum();
        let lines = self.data.split(|&b| b == b'\n').filter(|l| l.iter().any(|b| !b.is_ascii_whitespace())).count();
        if entries > lines as u128 {
            return Err(too_much_declared(entries, format!("{lines} non-blank data lines follow")));
        }
        Ok(())
    }

    fn begin(&mut self) -> Result<(), String> {
        loop {
            let Some(text) = self.next_line()? else {
                return Err(format!("line {}: unexpected end of file", self.line + 1));
            };
            self.tokens.clear();
            self.tokens.extend(text.split_ascii_whitespace());
            self.next = 0;
            if !self.tokens.is_empty() {
                return Ok(());
            }
        }
    }

    fn value(&mut self, ty: Scalar) -> Result<f64, String> {
        let line = self.line;
        let token = *self.tokens.get(self.next).ok_or_else(|| format!("line {line}: too few values"))?;
        self.next += 1;
        let bad = || format!("line {line}: '{token}' is not a valid {} value", ty.name());
        if ty.is_integer() {
            let (lo, hi) = ty.int_range();
            let v: i64 = token.parse().map_err(|_| bad())?;
            if v < lo || v > hi {
                return Err(bad());
            }
            Ok(v as f64)
        } else {
            token.parse().map_err(|_| bad())
        }
    }

    fn list_len(&mut self, count: Scalar, _item: Scalar) -> Result<u64, String> {
        let len = self.value(count)?;
        let left = self.tokens.len() - self.next;
        if len < 0.0 || len > left as f64 {
            return Err(format!("line {}: list of {len} items but {left} values are left on the line", self.line));
        }
        Ok(len as u64)
    }

    fn end(&mut self) -> Result<(), String> {
        match self.tokens.len() - self.next {
            0 => Ok(()),
            extra => Err(format!("line {}: {extra} more values than the header declares", self.line)),
        }
    }

    fn finish(&mut self) -> Result<(), String> {
        while let Some(text) = self.next_line()? {
            if !text.trim().is_empty() {
                return Err(format!("line {}: data after the last declared element (counts too small?)", self.line));
            }
        }
        Ok(())
    }
}

/// Binary data: values packed back to back in the file's byte order.
pub(super) struct BinarySource<'a> {
    data: &'a [u8],
    pos: usize,
    /// File offset of `data[0]`, for messages.
    base: usize,
    big_endian: bool,
}

impl<'a> BinarySource<'a> {
    /// Reads `data`, which starts at byte `base` of the file.
    pub(super) fn new(data: &'a [u8], base: usize, big_endian: bool) -> Self {
        Self { data, pos: 0, base, big_endian }
    }
}

impl Source for BinarySource<'_> {
    fn check_counts(&self, header: &Header) -> Result<(), String> {
        let entries: u128 = header.elements.iter().map(|e| u128::from(e.count)).sum();
        let needed: u128 = header.elements.iter().map(|e| u128::from(e.count) * u128::from(e.min_binary_size())).sum();
        if needed > self.data.len() as u128 {
            let available = format!("{} data bytes follow where at least {needed} are needed", self.data.len());
            return Err(too_much_declared(entries, available));
        }
        Ok(())
    }

    fn begin(&mut self) -> Result<(), String> {
        Ok(())
    }

    fn value(&mut self, ty: Scalar) -> Result<f64, String> {
        let size = ty.size();
        let Some(chunk) = self.data.get(self.pos..self.pos + size) else {
            return Err(format!("the data ends at byte {} (truncated file?)", self.base + self.data.len()));
        };
        self.pos += size;
        let mut b = [0u8; 8];
        b[..size].copy_from_slice(chunk);
        if self.big_endian {
            b[..size].reverse();
        }
        Ok(match ty {
            Scalar::I8 => f64::from(b[0] as i8),
            Scalar::U8 => f64::from(b[0]),
            Scalar::I16 => f64::from(i16::from_le_bytes([b[0], b[1]])),
            Scalar::U16 => f64::from(u16::from_le_bytes([b[0], b[1]])),
            Scalar::I32 => f64::from(i32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::U32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F64 => f64::from_le_bytes(b),
        })
    }

    fn list_len(&mut self, count: Scalar, item: Scalar) -> Result<u64, String> {
        let at = self.base + self.pos;
        let len = self.value(count)?;
        let left = (self.data.len() - self.pos) as f64;
        if len < 0.0 || len * item.size() as f64 > left {
            return Err(format!(
                "list at byte {at} declares {len} items but only {left} bytes are left (truncated file?)"
            ));
        }
        Ok(len as u64)
    }

    fn end(&mut self) -> Result<(), String> {
        Ok(())
    }

    fn finish(&mut self) -> Result<(), String> {
        match self.data.len() - self.pos {
            0 => Ok(()),
            extra => Err(format!("{extra} bytes of data after the last declared element (counts too small?)")),
        }
    }
}
