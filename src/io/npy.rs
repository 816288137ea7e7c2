//! NumPy `.npy` arrays of little-endian f32 (format version 1.0 written; 1.0, 2.0 and 3.0 read).
//!
//! Layout: the magic `\x93NUMPY`, two version bytes, the header length (u16 LE in version 1, u32
//! LE in versions 2 and 3), then an ASCII Python dict literal such as
//! `{'descr': '<f4', 'fortran_order': False, 'shape': (64, 64), }` padded with spaces and ended
//! by `\n` so that the data starts at a multiple of 64 bytes, then the raw values in C order.

use std::fs;
use std::io::Write;
use std::path::Path;

use super::IoError;

/// The six magic bytes every `.npy` file starts with.
const MAGIC: &[u8; 6] = b"\x93NUMPY";

/// Data alignment of the files written, bytes.
const ALIGN: usize = 64;

/// Writes `data`, a C-order (row-major, last index fastest) array of the given `shape`, as a
/// NumPy version 1.0 `.npy` file of little-endian f32 (`dtype('<f4')`).
///
/// # Errors
/// [`IoError::InvalidArgument`] when `shape`'s product is not `data.len()`;
/// [`IoError::Io`] when the file cannot be written.
///
/// # Example
/// ```
/// # let dir = std::env::temp_dir().join(format!("dentbend-npy-doc-{}", std::process::id()));
/// # std::fs::create_dir_all(&dir).unwrap();
/// let path = dir.join("a.npy");
/// dentbend::io::write_npy_f32(&path, &[2, 3], &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0]).unwrap();
/// let (shape, data) = dentbend::io::read_npy_f32(&path).unwrap();
/// assert_eq!((shape, data[4]), (vec![2, 3], 4.0));
/// # std::fs::remove_dir_all(&dir).unwrap();
/// ```
pub fn write_npy_f32(path: impl AsRef<Path>, shape: &[usize], data: &[f32]) -> Result<(), IoError> {
    let path = path.as_ref();
    let count = shape.iter().try_fold(1usize, |acc, &n| acc.checked_mul(n));
    if count != Some(data.len()) {
        return Err(IoError::InvalidArgument(format!(
            "npy shape {shape:?} does not hold the {} values given",
            data.len()
        )));
    }
    let header = header_bytes(shape)?;
    let mut bytes = Vec::with_capacity(header.len() + 4 * data.len());
    bytes.extend_from_slice(&header);
    for v in data {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    crate::mesh::write_file_atomically(path, |out| out.write_all(&bytes)).map_err(|e| IoError::io(path, e))
}

/// Reads a `.npy` file of little-endian f32 (`descr` `'<f4'`) in C order, returning its shape
/// and values (row-major, last index fastest). A zero-dimensional array has shape `[]` and one
/// value.
///
/// # Errors
/// [`IoError::Io`] when the file cannot be read; [`IoError::Npy`] when it is not a `.npy` file,
/// holds another dtype, is in Fortran order, or its size disagrees with its shape.
pub fn read_npy_f32(path: impl AsRef<Path>) -> Result<(Vec<usize>, Vec<f32>), IoError> {
    let path = path.as_ref();
    let bytes = fs::read(path).map_err(|e| IoError::io(path, e))?;
    let bad = |message: &str| IoError::npy(path, message);
    if bytes.len() < 10 || &bytes[..6] != MAGIC {
        return Err(bad("missing the \\x93NUMPY magic"));
    }
    let (header_len, header_start): (usize, usize) = match bytes[6] {
        1 => (u16::from_le_bytes([bytes[8], bytes[9]]) as usize, 10),
        2 | 3 if bytes.len() >= 12 => (u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]) as usize, 12),
        major => {
            return Err(bad(&format!("unsupported format version {major}.{}", bytes[7])));
        }
    };
    let data_start = header_start
        .checked_add(header_len)
        .filter(|&end| end <= bytes.len())
        .ok_or_else(|| bad("the header runs past the end of the file"))?;
    let header = std::str::from_utf8(&bytes[header_start..data_start]).map_err(|_| bad("the header is not text"))?;
    let dict = parse_header(header).map_err(|message| bad(&message))?;
    if dict.descr != "<f4" {
        return Err(bad(&format!("dtype '{}' is not supported (only '<f4', little-endian f32)", dict.descr)));
    }
    if dict.fortran_order && dict.shape.iter().filter(|&&n| n > 1).count() > 1 {
        return Err(bad("Fortran-order arrays are not supported"));
    }
    let payload = &bytes[data_start..];
    let count = dict
        .shape
        .iter()
        .try_fold(1usize, |acc, &n| acc.checked_mul(n))
        .filter(|c| c.checked_mul(4) == Some(payload.len()))
        .ok_or_else(|| {
            bad(&format!("shape {:?} does not match the {} data bytes present", dict.shape, payload.len()))
        })?;
    let data: Vec<f32> = payload.chunks_exact(4).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
    debug_assert_eq!(data.len(), count);
    Ok((dict.shape, data))
}

/// Magic, version 1.0, header length and the padded header dict, `ALIGN`-byte aligned.
fn header_bytes(shape: &[usize]) -> Result<Vec<u8>, IoError> {
    let dims = match shape {
        [n] => format!("({n},)"),
        _ => format!("({})", shape.iter().map(usize::to_string).collect::<Vec<_>>().join(", ")),
    };
    let mut dict = format!("{{'descr': '<f4', 'fortran_order': False, 'shape': {dims}, }}");
    let unpadded = MAGIC.len() + 4 + dict.len() + 1;
    dict.extend(std::iter::repeat_n(' ', unpadded.next_multiple_of(ALIGN) - unpadded));
    dict.push('\n');
    let header_len = u16::try_from(dict.len())
        .map_err(|_| IoError::InvalidArgument(format!("npy shape {shape:?} has too many dimensions")))?;
    let mut bytes = Vec::with_capacity(MAGIC.len() + 4 + dict.len());
    bytes.extend_from_slice(MAGIC);
    bytes.extend_from_slice(&[1, 0]);
    bytes.extend_from_slice(&header_len.to_le_bytes());
    bytes.extend_from_slice(dict.as_bytes());
    Ok(bytes)
}

/// The three entries of a `.npy` header dict.
struct Header {
    descr: String,
    fortran_order: bool,
    shape: Vec<usize>,
}

/// Parses the Python dict literal of a `.npy` header (keys `descr`, `fortran_order`, `shape`).
fn parse_header(text: &str) -> Result<Header, String> {
    let mut p = Parser { rest: text.trim_end_matches(['\n', ' ', '\0']) };
    p.expect('{')?;
    let (mut descr, mut fortran_order, mut shape) = (None, None, None);
    while !p.eat('}') {
        let key = p.string()?;
        p.expect(':')?;
        match key.as_str() {
            "descr" => descr = Some(p.string()?),
            "fortran_order" => fortran_order = Some(p.boolean()?),
            "shape" => shape = Some(p.tuple()?),
            other => return Err(format!("unknown header key '{other}'")),
        }
        if !p.eat(',') {
            p.expect('}')?;
            break;
        }
    }
    if !p.rest.trim().is_empty() {
        return Err("unexpected text after the header dict".into());
    }
    Ok(Header {
        descr: descr.ok_or("the header has no 'descr'")?,
        fortran_order: fortran_order.ok_or("the header has no 'fortran_order'")?,
        shape: shape.ok_or("the header has no 'shape'")?,
    })
}

/// A cursor over header text.
struct Parser<'a> {
    rest: &'a str,
}

impl Parser<'_> {
    /// Skips blanks, then consumes `c` if it comes next.
    fn eat(&mut self, c: char) -> bool {
        self.rest = self.rest.trim_start();
        match self.rest.strip_prefix(c) {
            Some(rest) => {
                self.rest = rest;
                true
            }
            None => false,
        }
    }

    fn expect(&mut self, c: char) -> Result<(), String> {
        if self.eat(c) { Ok(()) } else { Err(format!("expected '{c}' in the header")) }
    }

    /// A single- or double-quoted string without escapes.
    fn string(&mut self) -> Result<String, String> {
        self.rest = self.rest.trim_start();
        let quote = self.rest.chars().next().filter(|c| *c == '\'' || *c == '"').ok_or("expected a quoted string")?;
        let body = &self.rest[1..];
        let end = body.find(quote).ok_or("unterminated string in the header")?;
        self.rest = &body[end + 1..];
        Ok(body[..end].to_owned())
    }

    fn boolean(&mut self) -> Result<bool, String> {
        self.rest = self.rest.trim_start();
        for (word, value) in [("True", true), ("False", false)] {
            if let Some(rest) = self.rest.strip_prefix(word) {
                self.rest = rest;
                return Ok(value);
            }
        }
        Err("expected True or False for 'fortran_order'".into())
    }

    /// A tuple of non-negative integers: `()`, `(5,)`, `(3, 4)`.
    fn tuple(&mut self) -> Result<Vec<usize>, String> {
        self.expect('(')?;
        let mut dims = Vec::new();
        while !self.eat(')') {
            self.rest = self.rest.trim_start();
            let digits = self.rest.find(|c: char| !c.is_ascii_digit()).unwrap_or(self.rest.len());
            let dim = self.rest[..digits].parse::<usize>().map_err(|_| "expected an integer in 'shape'")?;
            self.rest = &self.rest[digits..];
            dims.push(dim);
            if !self.eat(',') {
                self.expect(')')?;
                break;
            }
        }
        Ok(dims)
    }
}
