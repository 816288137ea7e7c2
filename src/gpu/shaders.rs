//! The WGSL sources, embedded at compile time.

/// Every kernel's stem and WGSL source, without the declarations every kernel shares
/// (`shaders/shared/layout.wgsl` and `sample.wgsl`, which [`shader_source`] and the kernel
/// builder prepend); the two envelope passes carry their shared line routine
/// (`shaders/shared/envelope_line.wgsl`).
pub const SHADERS: &[(&str, &str)] = &[
    ("zbuffer", include_str!("../../shaders/zbuffer.wgsl")),
    (
        "envelope_rows",
        concat!(
            include_str!("../../shaders/envelope_rows.wgsl"),
            "\n",
            include_str!("../../shaders/shared/envelope_line.wgsl")
        ),
    ),
    (
        "envelope_cols",
        concat!(
            include_str!("../../shaders/envelope_cols.wgsl"),
            "\n",
            include_str!("../../shaders/shared/envelope_line.wgsl")
        ),
    ),
    ("heat", include_str!("../../shaders/heat.wgsl")),
    ("glance", include_str!("../../shaders/glance.wgsl")),
    ("displace", include_str!("../../shaders/displace.wgsl")),
    ("normals", include_str!("../../shaders/normals.wgsl")),
    ("skin", include_str!("../../shaders/skin.wgsl")),
    ("interleave", include_str!("../../shaders/interleave.wgsl")),
    ("moved", include_str!("../../shaders/moved.wgsl")),
];

/// The WGSL source of kernel `stem` with the shared declarations prepended, as compiled.
pub fn shader_source(stem: &str) -> Option<String> {
    SHADERS.iter().find(|(s, _)| *s == stem).map(|(_, body)| format!("{}\n{body}", super::SHARED_WGSL))
}

/// The WGSL body of kernel `stem` (without the shared declarations).
pub(crate) fn body(stem: &str) -> &'static str {
    SHADERS.iter().find(|(s, _)| *s == stem).map_or("", |(_, body)| body)
}
