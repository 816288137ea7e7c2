//! PLY header: the scalar types, elements and properties it declares, and what each element
//! contributes to the mesh.

/// A PLY scalar type.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    /// The type of a PLY type name (either spelling), if known.
    pub(super) fn parse(name: &str) -> Option<Self> {
        Some(match name {
            "char" | "int8" => Self::I8,
            "uchar" | "uint8" => Self::U8,
            "short" | "int16" => Self::I16,
            "ushort" | "uint16" => Self::U16,
            "int" | "int32" => Self::I32,
            "uint" | "uint32" => Self::U32,
            "float" | "float32" => Self::F32,
            "double" | "float64" => Self::F64,
            _ => return None,
        })
    }

    /// The PLY type name.
    pub(super) fn name(self) -> &'static str {
        match self {
            Self::I8 => "char",
            Self::U8 => "uchar",
            Self::I16 => "short",
            Self::U16 => "ushort",
            Self::I32 => "int",
            Self::U32 => "uint",
            Self::F32 => "float",
            Self::F64 => "double",
        }
    }

    /// Bytes per value in binary files.
    pub(super) fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }

    /// Whether values of this type are integers.
    pub(super) fn is_integer(self) -> bool {
        !matches!(self, Self::F32 | Self::F64)
    }

    /// Inclusive range of an integer type.
    pub(super) fn int_range(self) -> (i64, i64) {
        match self {
            Self::I8 => (i8::MIN.into(), i8::MAX.into()),
            Self::U8 => (0, u8::MAX.into()),
            Self::I16 => (i16::MIN.into(), i16::MAX.into()),
            Self::U16 => (0, u16::MAX.into()),
            Self::I32 => (i32::MIN.into(), i32::MAX.into()),
            _ => (0, u32::MAX.into()),
        }
    }
}

/// The shape of a property: one value, or a length-prefixed list.
pub(super) enum Kind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

/// One declared property of an element.
pub(super) struct Property {
    pub(super) name: String,
    pub(super) kind: Kind,
}

/// What an element contributes to the mesh.
pub(super) enum Role {
    /// Property indices of x, y and z.
    Vertex([usize; 3]),
    /// Property index of the vertex index list.
    Face(usize),
    /// Read past.
    Skip,
}

/// One declared element: its name, entry count and properties.
pub(super) struct Element {
    pub(super) name: String,
    pub(super) count: u64,
    pub(super) properties: Vec<Property>,
    pub(super) role: Role,
}

/// How the data after the header is encoded.
pub(super) enum Format {
    Ascii,
    Binary { big_endian: bool },
}

/// A parsed and checked PLY header.
pub(super) struct Header {
    pub(super) format: Format,
    pub(super) elements: Vec<Element>,
    /// Byte offset of the first data byte.
    pub(super) data_offset: usize,
    /// Number of header lines, `end_header` included.
    pub(super) lines: usize,
}

impl Header {
    /// Parses the header at the start of `bytes`, checking that the vertex and face elements
    /// have what the mesh needs.
    pub(super) fn parse(bytes: &[u8]) -> Result<Self, String> {
        let mut format = None;
        let mut elements: Vec<Element> = Vec::new();
        let (mut pos, mut line) = (0, 0);
        loop {
            let Some(len) = bytes[pos..].iter().position(|&b| b == b'\n') else {
                return Err(if line == 0 {
                    "not a PLY file (no 'ply' line)".to_owned()
                } else {
                    "the header has no 'end_header' line".to_owned()
                });
            };
            let raw = &bytes[pos..pos + len];
            pos += len + 1;
            line += 1;
            if line == 1 {
                if raw.trim_ascii() != b"ply" {
                    return Err("not a PLY file (the first line is not 'ply')".to_owned());
                }
                continue;
            }
            let text = std::str::from_utf8(raw).map_err(|_| format!("line {line}: the header is not ASCII text"))?;
            let bad = |what: &str| format!("line {line}: {what} in '{}'", text.trim());
            let tokens: Vec<&str> = text.split_ascii_whitespace().collect();
            match tokens.as_slice() {
                [] | ["comment" | "obj_info", ..] => {}
                ["format", name, version] => {
                    if *version != "1.0" {
                        return Err(bad("unsupported PLY version (only 1.0 is read)"));
                    }
                    format = Some(match *name {
                        "ascii" => Format::Ascii,
                        "binary_little_endian" => Format::Binary { big_endian: false },
                        "binary_big_endian" => Format::Binary { big_endian: true },
                        _ => return Err(bad("unknown format")),
                    });
                }
                ["element", name, count] => {
                    let count = count.parse().map_err(|_| bad("element count is not a non-negative integer"))?;
                    if elements.iter().any(|e| e.name == *name) {
                        return Err(bad("duplicate element"));
                    }
                    let name = (*name).to_owned();
                    elements.push(Element { name, count, properties: Vec::new(), role: Role::Skip });
                }
                ["property", rest @ ..] => {
                    let element = elements.last_mut().ok_or_else(|| bad("property before any element"))?;
                    let scalar = |t: &str| Scalar::parse(t).ok_or_else(|| bad("unknown property type"));
                    let (kind, name) = match rest {
                        ["list", count, item, name] => {
                            let count = scalar(count)?;
                            if !count.is_integer() {
                                return Err(bad("list count type must be an integer type"));
                            }
                            (Kind::List { count, item: scalar(item)? }, *name)
                        }
                        [ty, name] => (Kind::Scalar(scalar(ty)?), *name),
                        _ => return Err(bad("malformed property")),
                    };
                    element.properties.push(Property { name: name.to_owned(), kind });
                }
                ["end_header"] => break,
                _ => return Err(bad("unknown or malformed header line")),
            }
        }
        let format = format.ok_or("the header has no 'format' line")?;
        for element in &mut elements {
            element.assign_role()?;
        }
        if !elements.iter().any(|e| matches!(e.role, Role::Vertex(_))) {
            return Err("the header declares no 'vertex' element".to_owned());
        }
        Ok(Self { format, elements, data_offset: pos, lines: line })
    }
}

impl Element {
    fn assign_role(&mut self) -> Result<(), String> {
        if self.count > 0 && self.properties.is_empty() {
            return Err(format!("element '{}' has {} entries but no properties", self.name, self.count));
        }
        let find = |names: &[&str]| self.properties.iter().position(|p| names.contains(&p.name.as_str()));
        match self.name.as_str() {
            "vertex" => {
                if self.count > u64::from(u32::MAX) {
                    return Err(format!("{} vertices are more than this reader indexes", self.count));
                }
                let mut xyz = [0; 3];
                for (slot, axis) in xyz.iter_mut().zip(["x", "y", "z"]) {
                    *slot = find(&[axis]).ok_or_else(|| format!("the vertex element has no '{axis}' property"))?;
                    if !matches!(self.properties[*slot].kind, Kind::Scalar(_)) {
                        return Err(format!("vertex property '{axis}' is a list, expected a number"));
                    }
                }
                self.role = Role::Vertex(xyz);
            }
            "face" => {
                let list =
                    find(&["vertex_indices", "vertex_index"]).ok_or("the face element has no 'vertex_indices' list")?;
                match self.properties[list].kind {
                    Kind::List { item, .. } if item.is_integer() => self.role = Role::Face(list),
                    _ => return Err("face 'vertex_indices' must be a list of integers".to_owned()),
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// Fewest bytes one entry can take in binary form.
    pub(super) fn min_binary_size(&self) -> u64 {
        let size = |p: &Property| match p.kind {
            Kind::Scalar(t) | Kind::List { count: t, .. } => t.size() as u64,
        };
        self.properties.iter().map(size).sum()
    }
}
