//! GPU twin of `cpu::heat` (being written).
