//! glTF buffer data for the reader: buffers resolved on first use (the `.glb` BIN chunk, base64
//! `data:` URIs, files beside the `.gltf`) and accessors read with every index, offset, stride
//! and count checked against the bytes present, so a malformed file is an error, never a panic.
//!
//! Supported accessors: `POSITION` as f32 `VEC3`, indices as u8, u16 or u32 `SCALAR`, other
//! vertex attributes as f32 or normalized u8/u16 vectors and joints as u8/u16 `VEC4`, each with
//! a buffer view (interleaved or not). Sparse accessors are not supported.

use std::borrow::Cow;
use std::path::Path;

use glam::Vec3;
use gltf::json::Root;
use gltf::json::accessor::{ComponentType, GenericComponentType, Type};
use gltf::json::validation::Checked;

/// The buffers of one glTF document, loaded on first use.
pub(crate) struct Buffers<'a> {
    root: &'a Root,
    /// Directory that relative buffer URIs are resolved against (`None`: in-memory input,
    /// where they are refused).
    base: Option<&'a Path>,
    /// The `.glb` BIN chunk, if any.
    bin: Option<&'a [u8]>,
    loaded: Vec<Option<Cow<'a, [u8]>>>,
}

/// The elements of one accessor: `count` slices of `size` bytes, `stride` bytes apart.
struct Elements<'d> {
    bytes: &'d [u8],
    count: usize,
    size: usize,
    stride: usize,
    component: ComponentType,
}

impl<'d> Elements<'d> {
    fn iter(&self) -> impl Iterator<Item = &'d [u8]> + use<'d> {
        let Self { bytes, size, stride, .. } = *self;
        // The accessor was checked to fit: (count − 1)·stride + size ≤ bytes.len().
        (0..self.count).map(move |i| &bytes[i * stride..i * stride + size])
    }
}

impl<'a> Buffers<'a> {
    /// Buffers of `root`, with relative URIs resolved against `base` (refused when it is `None`)
    /// and `bin` as the buffer without a URI (binary glTF).
    pub(crate) fn new(root: &'a Root, base: Option<&'a Path>, bin: Option<&'a [u8]>) -> Self {
        Self { root, base, bin, loaded: vec![None; root.buffers.len()] }
    }

    /// Reads a `POSITION` accessor: f32 `VEC3` elements, world units of the mesh's frame.
    pub(crate) fn positions(&mut self, accessor: usize) -> Result<Vec<Vec3>, String> {
        let accepts =
            |kind, component, normalized: bool| kind == Type::Vec3 && component == ComponentType::F32 && !normalized;
        let elements = self.elements(accessor, "POSITION", "VEC3 of f32", accepts)?;
        let f32_at = |e: &[u8], k: usize| f32::from_le_bytes([e[k], e[k + 1], e[k + 2], e[k + 3]]);
        Ok(elements.iter().map(|e| Vec3::new(f32_at(e, 0), f32_at(e, 4), f32_at(e, 8))).collect())
    }

    /// Reads an index accessor: u8, u16 or u32 `SCALAR` elements, widened to u32.
    pub(crate) fn indices(&mut self, accessor: usize) -> Result<Vec<u32>, String> {
        let accepts = |kind, component, normalized: bool| {
            kind == Type::Scalar
                && matches!(component, ComponentType::U8 | ComponentType::U16 | ComponentType::U32)
                && !normalized
        };
        let elements = self.elements(accessor, "index", "SCALAR of u8, u16 or u32", accepts)?;
        let widen = |e: &[u8]| match elements.component {
            ComponentType::U8 => u32::from(e[0]),
            ComponentType::U16 => u32::from(u16::from_le_bytes([e[0], e[1]])),
            _ => u32::from_le_bytes([e[0], e[1], e[2], e[3]]),
        };
        Ok(elements.iter().map(widen).collect())
    }

    /// Reads a vertex attribute accessor as `role`: one of `kinds`, of f32 or normalized u8/u16
    /// components (scaled to [0, 1]); components the type lacks are taken from `pad`.
    pub(crate) fn floats(
        &mut self,
        accessor: usize,
        role: &str,
        kinds: &[Type],
        pad: [f32; 4],
    ) -> Result<Vec<[f32; 4]>, String> {
        let accepts = |kind, component, normalized: bool| {
            kinds.contains(&kind)
                && match component {
                    ComponentType::F32 => !normalized,
                    ComponentType::U8 | ComponentType::U16 => normalized,
                    _ => false,
                }
        };
        let elements = self.elements(accessor, role, "f32 or normalized u8/u16 vectors", accepts)?;
        let (size, component) = (elements.component.size(), elements.component);
        let value = |e: &[u8], k: usize| match component {
            ComponentType::U8 => f32::from(e[k]) / 255.0,
            ComponentType::U16 => f32::from(u16::from_le_bytes([e[2 * k], e[2 * k + 1]])) / 65535.0,
            _ => f32::from_le_bytes([e[4 * k], e[4 * k + 1], e[4 * k + 2], e[4 * k + 3]]),
        };
        let n = elements.size / size;
        Ok(elements.iter().map(|e| std::array::from_fn(|k| if k < n { value(e, k) } else { pad[k] })).collect())
    }

    /// Reads a `JOINTS_n` accessor: u8 or u16 `VEC4`, widened to u16.
    pub(crate) fn joints(&mut self, accessor: usize) -> Result<Vec<[u16; 4]>, String> {
        let accepts = |kind, component, normalized: bool| {
            kind == Type::Vec4 && matches!(component, ComponentType::U8 | ComponentType::U16) && !normalized
        };
        let elements = self.elements(accessor, "JOINTS", "VEC4 of u8 or u16", accepts)?;
        let wide = elements.component == ComponentType::U16;
        let value =
            |e: &[u8], k: usize| if wide { u16::from_le_bytes([e[2 * k], e[2 * k + 1]]) } else { u16::from(e[k]) };
        Ok(elements.iter().map(|e| std::array::from_fn(|k| value(e, k))).collect())
    }

    /// The element count of accessor `index` as declared (not checked against the data).
    pub(crate) fn count(&self, index: usize) -> Option<u64> {
        self.root.accessors.get(index).map(|a| a.count.0)
    }

    /// The checked element layout of accessor `index`, used as `role`, whose type and
    /// component type must satisfy `accepts` (`expected` says what it accepts).
    fn elements(
        &mut self,
        index: usize,
        role: &str,
        expected: &str,
        accepts: impl Fn(Type, ComponentType, bool) -> bool,
    ) -> Result<Elements<'_>, String> {
        let root = self.root;
        let accessor = root
            .accessors
            .get(index)
            .ok_or_else(|| format!("{role} accessor {index} does not exist (the file has {})", root.accessors.len()))?;
        let (Checked::Valid(kind), Checked::Valid(GenericComponentType(component))) =
            (accessor.type_, accessor.component_type)
        else {
            return Err(format!("accessor {index} has an invalid type or componentType"));
        };
        if !accepts(kind, component, accessor.normalized) {
            let normalized = if accessor.normalized { "normalized " } else { "" };
            return Err(format!(
                "{role} accessor {index} holds {kind:?} of {normalized}{component:?}, expected {expected}"
            ));
        }
        if accessor.sparse.is_some() {
            return Err(format!("{role} accessor {index} is sparse, which is not supported"));
        }
        let view_index =
            accessor.buffer_view.ok_or_else(|| format!("{role} accessor {index} has no bufferView"))?.value();
        let view = root.buffer_views.get(view_index).ok_or_else(|| {
            format!("bufferView {view_index} does not exist (the file has {})", root.buffer_views.len())
        })?;
        let buffer_index = view.buffer.value();
        let data = self.buffer(buffer_index)?;
        let (start, length) = (view.byte_offset.map_or(0, |o| o.0), view.byte_length.0);
        let view_bytes = range(start, length).and_then(|r| data.get(r)).ok_or_else(|| {
            format!(
                "bufferView {view_index} (bytes {start} to {start} + {length}) runs past the end of buffer \
                 {buffer_index} ({} bytes)",
                data.len()
            )
        })?;
        let size = component.size() * kind.multiplicity();
        let stride = view.byte_stride.map_or(0, |s| s.0);
        let stride = if stride == 0 { size } else { stride };
        if stride < size {
            return Err(format!("bufferView {view_index} has byteStride {stride}, less than the {size}-byte elements"));
        }
        let (offset, count) = (accessor.byte_offset.map_or(0, |o| o.0), accessor.count.0);
        let span = match count {
            0 => Some(0),
            _ => (count - 1).checked_mul(stride as u64).and_then(|s| s.checked_add(size as u64)),
        };
        let fits = span.and_then(|span| range(offset, span)).and_then(|r| view_bytes.get(r));
        let bytes = fits.ok_or_else(|| {
            format!(
                "{role} accessor {index} ({count} elements of {size} bytes, stride {stride}, offset {offset}) runs \
                 past the end of bufferView {view_index} ({length} bytes)"
            )
        })?;
        let count = usize::try_from(count).map_err(|_| format!("{role} accessor {index} is too large"))?;
        Ok(Elements { bytes, count, size, stride, component })
    }

    /// The bytes of buffer `index`, loaded on first use and cut to its declared `byteLength`.
    fn buffer(&mut self, index: usize) -> Result<&[u8], String> {
        let count = self.loaded.len();
        let slot =
            self.loaded.get(index).ok_or_else(|| format!("buffer {index} does not exist (the file has {count})"))?;
        if slot.is_none() {
            let data = self.load(index)?;
            self.loaded[index] = Some(data);
        }
        Ok(self.loaded[index].as_deref().unwrap_or_default())
    }

    fn load(&self, index: usize) -> Result<Cow<'a, [u8]>, String> {
        let buffer = &self.root.buffers[index];
        let mut data = match (buffer.uri.as_deref(), self.bin) {
            (Some(uri), _) => Cow::Owned(read_uri(uri, self.base).map_err(|e| format!("buffer {index}: {e}"))?),
            (None, Some(bin)) if index == 0 => Cow::Borrowed(bin),
            (None, _) if index == 0 => return Err("buffer 0 has no uri and the file has no BIN chunk".to_owned()),
            (None, _) => return Err(format!("buffer {index} has no uri (only buffer 0 of a .glb may omit it)")),
        };
        let declared = buffer.byte_length.0;
        match usize::try_from(declared).ok().filter(|&n| n <= data.len()) {
            Some(n) => match &mut data {
                Cow::Borrowed(bytes) => *bytes = &bytes[..n],
                Cow::Owned(bytes) => bytes.truncate(n),
            },
            None => return Err(format!("buffer {index} declares {declared} bytes but holds only {}", data.len())),
        }
        Ok(data)
    }
}

/// `start..start + length` as a usize range, if it does not overflow.
fn range(start: u64, length: u64) -> Option<std::ops::Range<usize>> {
    let start = usize::try_from(start).ok()?;
    Some(start..start.checked_add(usize::try_from(length).ok()?)?)
}

/// The bytes a buffer URI refers to: a base64 `data:` URI or a path relative to `base` (refused
/// without one).
fn read_uri(uri: &str, base: Option<&Path>) -> Result<Vec<u8>, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (_, payload) = rest.split_once(";base64,").ok_or("only base64 data: URIs are supported")?;
        return decode_base64(payload);
    }
    let scheme = uri.split_once(':').map(|(s, _)| s).filter(|s| {
        s.starts_with(|c: char| c.is_ascii_alphabetic())
            && s.chars().all(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.'))
    });
    if let Some(scheme) = scheme {
        return Err(format!("URI scheme '{scheme}:' is not supported (only data: URIs and relative paths)"));
    }
    let relative = percent_decode(uri)?;
    let Some(base) = base else {
        return Err(format!("URI '{relative}' names a file, which glTF read from memory cannot refer to"));
    };
    let path = super::confined::resolve_inside(base, &relative)?;
    std::fs::read(&path).map_err(|e| format!("cannot read {}: {e}", path.display()))
}

/// Decodes base64 (standard or URL-safe alphabet, padding optional).
fn decode_base64(text: &str) -> Result<Vec<u8>, String> {
    let text = text.trim_end_matches('=');
    let mut out = Vec::with_capacity(text.len() / 4 * 3 + 2);
    let (mut bits, mut pending) = (0u32, 0u32);
    for (at, c) in text.bytes().enumerate() {
        let value = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            _ => return Err(format!("invalid base64 character {:?} at offset {at}", char::from(c))),
        };
        bits = (bits << 6) | u32::from(value);
        pending += 6;
        if pending >= 8 {
            pending -= 8;
            out.push((bits >> pending) as u8);
            bits &= (1 << pending) - 1;
        }
    }
    if text.len() % 4 == 1 {
        return Err(format!("base64 data of {} characters is truncated", text.len()));
    }
    Ok(out)
}

/// Decodes `%XX` escapes in a relative URI.
fn percent_decode(uri: &str) -> Result<String, String> {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut at = 0;
    while let Some(&b) = bytes.get(at) {
        if b == b'%' {
            let hex = bytes.get(at + 1..at + 3).filter(|h| h.iter().all(u8::is_ascii_hexdigit));
            let hex = hex.and_then(|h| std::str::from_utf8(h).ok()).and_then(|h| u8::from_str_radix(h, 16).ok());
            out.push(hex.ok_or_else(|| format!("URI '{uri}' has a bad %-escape at byte {at}"))?);
            at += 3;
        } else {
            out.push(b);
            at += 1;
        }
    }
    String::from_utf8(out).map_err(|_| format!("URI '{uri}' does not decode to UTF-8"))
}
