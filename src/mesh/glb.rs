//! The binary glTF (`.glb`) container: a 12-byte header, a JSON chunk and an optional BIN chunk,
//! all little-endian and 4-byte aligned (glTF 2.0 specification, section "GLB File Format").

/// `"glTF"` read as a little-endian u32: the first four bytes of every `.glb` file.
pub(crate) const MAGIC: u32 = 0x4654_6C67;
/// The only container version this crate reads and writes.
const VERSION: u32 = 2;
/// Chunk type of the JSON chunk (`"JSON"`).
const CHUNK_JSON: u32 = 0x4E4F_534A;
/// Chunk type of the binary buffer chunk (`"BIN\0"`).
const CHUNK_BIN: u32 = 0x004E_4942;
/// Bytes in the file header (magic, version, total length).
const HEADER_LEN: usize = 12;
/// Bytes in a chunk header (length, type).
const CHUNK_HEADER_LEN: usize = 8;

/// The chunks of a `.glb` file, borrowed from its bytes.
pub(crate) struct Chunks<'a> {
    /// The glTF JSON document (UTF-8, possibly followed by padding spaces).
    pub json: &'a [u8],
    /// The binary buffer, if the file has one (possibly followed by up to 3 padding bytes).
    pub bin: Option<&'a [u8]>,
}

/// Packs a JSON document and a binary buffer into `.glb` bytes: the JSON chunk padded with
/// spaces and the BIN chunk (left out when `bin` is empty) padded with zeros to 4 bytes.
///
/// # Errors
/// A message if the file would exceed the format's 4 GiB limit.
pub(crate) fn pack(json: &[u8], bin: &[u8]) -> Result<Vec<u8>, String> {
    let json_len = json.len().next_multiple_of(4);
    let bin_len = bin.len().next_multiple_of(4);
    let bin_total = if bin.is_empty() { 0 } else { CHUNK_HEADER_LEN + bin_len };
    let total = HEADER_LEN + CHUNK_HEADER_LEN + json_len + bin_total;
    let too_big = || format!("the .glb file would take {total} bytes, more than the format's limit of 4 GiB");
    let total_u32 = u32::try_from(total).map_err(|_| too_big())?;
    let mut out = Vec::with_capacity(total);
    for word in [MAGIC, VERSION, total_u32, json_len as u32, CHUNK_JSON] {
        out.extend_from_slice(&word.to_le_bytes());
    }
    out.extend_from_slice(json);
    out.resize(HEADER_LEN + CHUNK_HEADER_LEN + json_len, b' ');
    if !bin.is_empty() {
        out.extend_from_slice(&(bin_len as u32).to_le_bytes());
        out.extend_from_slice(&CHUNK_BIN.to_le_bytes());
        out.extend_from_slice(bin);
        out.resize(total, 0);
    }
    Ok(out)
}

/// Splits `.glb` bytes into their chunks, checking every length against the data present.
/// Chunks of unknown type are skipped, as the specification requires; the first BIN chunk is
/// the buffer.
///
/// # Errors
/// A message for a bad magic number or version, a header or chunk that runs past the end of the
/// data, or a first chunk that is not JSON.
pub(crate) fn split(bytes: &[u8]) -> Result<Chunks<'_>, String> {
    let (Some(magic), Some(version), Some(length)) = (word(bytes, 0), word(bytes, 4), word(bytes, 8)) else {
        return Err(format!("binary glTF header needs {HEADER_LEN} bytes, the file has {}", bytes.len()));
    };
    if magic != MAGIC {
        return Err(format!("not a binary glTF file (magic number {magic:#010x}, expected {MAGIC:#010x})"));
    }
    if version != VERSION {
        return Err(format!("binary glTF version {version} is not supported (expected {VERSION})"));
    }
    let length = length as usize;
    if length > bytes.len() {
        return Err(format!("truncated: the header gives a length of {length} bytes, the file has {}", bytes.len()));
    }
    let bytes = &bytes[..length];
    let mut at = HEADER_LEN;
    let (mut json, mut bin) = (None, None);
    while at < bytes.len() {
        let (Some(chunk_len), Some(chunk_type)) = (word(bytes, at), word(bytes, at + 4)) else {
            return Err(format!("truncated chunk header at byte {at}"));
        };
        let start = at + CHUNK_HEADER_LEN;
        let end = start.checked_add(chunk_len as usize).filter(|&end| end <= bytes.len()).ok_or_else(|| {
            format!(
                "chunk at byte {at} declares {chunk_len} bytes, but only {} remain",
                bytes.len().saturating_sub(start)
            )
        })?;
        let data = &bytes[start..end];
        match chunk_type {
            CHUNK_JSON if json.is_none() && at == HEADER_LEN => json = Some(data),
            _ if json.is_none() => return Err("the first chunk is not the JSON chunk".to_owned()),
            CHUNK_BIN if bin.is_none() => bin = Some(data),
            _ => {}
        }
        at = end;
    }
    let json = json.ok_or("the file has no JSON chunk")?;
    Ok(Chunks { json, bin })
}

/// The little-endian u32 at byte `at`, if all four bytes are there.
fn word(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}
