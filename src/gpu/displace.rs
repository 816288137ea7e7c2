//! GPU twin of `cpu::displace` (being written).
