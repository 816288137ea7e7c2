//! GPU twin of `cpu::normals` (being written).
