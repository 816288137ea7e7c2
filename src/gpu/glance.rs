//! GPU twin of `cpu::glance` (being written).
