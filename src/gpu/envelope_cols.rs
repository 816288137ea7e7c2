//! GPU twin of `cpu::envelope_cols` (being written).
