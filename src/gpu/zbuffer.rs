//! GPU twin of `cpu::zbuffer` (being written).
