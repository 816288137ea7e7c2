//! GPU twin of `cpu::envelope_rows` (being written).
