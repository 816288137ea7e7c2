//! The device limits `GpuContext::from_device` demands (`gpu::REQUIRED_LIMITS`) are exactly what
//! the WGSL kernels use, reflected from the shaders with naga (no GPU needed): storage and uniform
//! buffers and bindings per kernel, uniform binding sizes, workgroup sizes and workgroup memory.

use dentbend::gpu::{REQUIRED_LIMITS, SHADERS, shader_source};

/// What the kernels use, the largest over every shader and entry point.
#[derive(Debug, Default)]
struct Used {
    storage: u64,
    uniform: u64,
    bindings: u64,
    uniform_bytes: u64,
    workgroup: [u64; 3],
    invocations: u64,
    workgroup_bytes: u64,
}

fn reflect() -> Used {
    let mut used = Used::default();
    for (stem, _) in SHADERS {
        let source = shader_source(stem).unwrap();
        let module = naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| panic!("{stem}: {e}"));
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(module.to_ctx()).unwrap();
        let (mut storage, mut uniform, mut bindings, mut shared) = (0, 0, 0, 0);
        for (_, var) in module.global_variables.iter() {
            let bytes = u64::from(layouter[var.ty].size);
            match var.space {
                naga::AddressSpace::Storage { .. } => storage += 1,
                naga::AddressSpace::Uniform => {
                    uniform += 1;
                    used.uniform_bytes = used.uniform_bytes.max(bytes);
                }
                naga::AddressSpace::WorkGroup => shared += bytes,
                _ => {}
            }
            bindings += u64::from(var.binding.is_some());
        }
        used.storage = used.storage.max(storage);
        used.uniform = used.uniform.max(uniform);
        used.bindings = used.bindings.max(bindings);
        used.workgroup_bytes = used.workgroup_bytes.max(shared);
        for entry in &module.entry_points {
            let size = entry.workgroup_size.map(u64::from);
            (0..3).for_each(|k| used.workgroup[k] = used.workgroup[k].max(size[k]));
            used.invocations = used.invocations.max(size.iter().product());
        }
    }
    used
}

fn required(name: &str) -> u64 {
    REQUIRED_LIMITS.iter().find(|r| r.name == name).unwrap_or_else(|| panic!("{name} is not required")).needed
}

#[test]
fn the_required_limits_are_what_the_shaders_use() {
    let used = reflect();
    assert_eq!(required("max_storage_buffers_per_shader_stage"), used.storage, "{used:?}");
    assert_eq!(required("max_uniform_buffers_per_shader_stage"), used.uniform, "{used:?}");
    assert_eq!(required("max_bindings_per_bind_group"), used.bindings, "{used:?}");
    assert_eq!(required("max_uniform_buffer_binding_size"), used.uniform_bytes, "{used:?}");
    assert_eq!(required("max_compute_workgroup_size_x"), used.workgroup[0], "{used:?}");
    assert_eq!(required("max_compute_workgroup_size_y"), used.workgroup[1], "{used:?}");
    assert_eq!(required("max_compute_workgroup_size_z"), used.workgroup[2], "{used:?}");
    assert_eq!(required("max_compute_invocations_per_workgroup"), used.invocations, "{used:?}");
    assert_eq!(required("max_compute_workgroup_storage_size"), used.workgroup_bytes, "{used:?}");
    // Every kernel binds one group.
    assert_eq!(required("max_bind_groups"), 1);
}

/// WebGPU's downlevel defaults, what `GpuContext::new` requests, meet every requirement.
#[test]
fn downlevel_defaults_meet_the_requirements() {
    dentbend::gpu::check_limits(&wgpu::Limits::downlevel_defaults()).unwrap();
}
