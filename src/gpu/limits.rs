//! The device limits dentbend's compute pipelines need, and the check an application's device
//! must pass before [`GpuContext::from_device`](super::GpuContext::from_device) wraps it.
//!
//! The numbers are what the WGSL kernels in `shaders/` use (a test reflects them from the
//! shaders with naga, `tests/gpu_limits.rs`), all within WebGPU's downlevel defaults. Limits the
//! kernels adapt to (binding size, workgroups per dispatch) are read from the device at run time
//! and only need to be non-zero here.

use super::GpuError;

/// One limit a device must meet: its wgpu field name, the value needed, and how to read it.
#[derive(Debug, Clone, Copy)]
pub struct RequiredLimit {
    /// The field of [`wgpu::Limits`], e.g. `max_storage_buffers_per_shader_stage`.
    pub name: &'static str,
    /// The least value the kernels work with (a count, bytes or invocations, as the field says).
    pub needed: u64,
    /// Reads the field from a device's limits.
    pub read: fn(&wgpu::Limits) -> u64,
}

macro_rules! required {
    ($($field:ident = $needed:expr),* $(,)?) => {
        &[$(RequiredLimit { name: stringify!($field), needed: $needed, read: |l| u64::from(l.$field) }),*]
    };
}

/// Every limit the compute kernels depend on, with the least value they need:
/// - 4 storage buffers per stage (`displace`, `zbuffer`, the envelope passes, `normals`, `skin`,
///   `heat`, `interleave`, `moved`), 2 uniform buffers per stage (`skin`), 6 bindings in the one
///   bind group (`skin`);
/// - 16 KiB per uniform binding (`normals`: 512 × 32-byte parameter blocks; `skin`: 256 × 48-byte
///   bones);
/// - workgroups of 256 × 1 × 1 invocations (`heat`, `glance`, `zbuffer`) and 13,824 bytes of
///   workgroup memory (`heat`'s module: two copies of a 40 × 40 f32 tile with its halo for the
///   fused steps, 256 partial maxima for the peak; counted together, as the test reflects them);
/// - non-zero buffer, binding and dispatch sizes (the batch is cut to what the device allows).
pub const REQUIRED_LIMITS: &[RequiredLimit] = required![
    max_bind_groups = 1,
    max_bindings_per_bind_group = 6,
    max_storage_buffers_per_shader_stage = 4,
    max_uniform_buffers_per_shader_stage = 2,
    max_uniform_buffer_binding_size = 16 << 10,
    max_compute_workgroup_size_x = 256,
    max_compute_workgroup_size_y = 1,
    max_compute_workgroup_size_z = 1,
    max_compute_invocations_per_workgroup = 256,
    max_compute_workgroup_storage_size = 13_824,
    max_compute_workgroups_per_dimension = 1,
    max_storage_buffer_binding_size = 16,
    max_buffer_size = 16,
];

/// The first limit of [`REQUIRED_LIMITS`] that `limits` falls short of.
///
/// # Errors
/// [`GpuError::MissingLimits`] naming the limit, the value needed and the device's value.
pub fn check_limits(limits: &wgpu::Limits) -> Result<(), GpuError> {
    match REQUIRED_LIMITS.iter().find(|r| (r.read)(limits) < r.needed) {
        Some(r) => Err(GpuError::MissingLimits { limit: r.name, needed: r.needed, available: (r.read)(limits) }),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The downlevel defaults `GpuContext::new` requests meet every requirement, and lowering one
    /// limit below its need is reported by name.
    #[test]
    fn downlevel_defaults_pass_and_a_shortfall_is_named() {
        check_limits(&wgpu::Limits::downlevel_defaults()).unwrap();
        let short = wgpu::Limits { max_storage_buffers_per_shader_stage: 2, ..wgpu::Limits::downlevel_defaults() };
        let error = check_limits(&short).unwrap_err();
        assert!(
            matches!(
                error,
                GpuError::MissingLimits { limit: "max_storage_buffers_per_shader_stage", needed: 4, available: 2 }
            ),
            "{error}"
        );
    }
}
