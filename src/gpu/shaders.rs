//! The WGSL sources, embedded at compile time.

/// Every kernel's stem and WGSL source (without the shared declarations).
pub const SHADERS: &[(&str, &str)] = &[];

/// The WGSL source of kernel `stem` with the shared declarations prepended, as compiled.
pub fn shader_source(stem: &str) -> Option<String> {
    SHADERS.iter().find(|(s, _)| *s == stem).map(|(_, body)| format!("{}\n{body}", super::SHARED_WGSL))
}
