//! dentbend on a device the application created: make a wgpu device as an engine would, hand it
//! to `GpuContext::from_device`, record one dent batch into the application's own encoder,
//! submit it, and print how deep the block was dented. Prints why and exits 0 without an adapter.

use dentbend::dent::{DentJob, DentParams, Impact};
use dentbend::glam::{Affine3A, Vec3};
use dentbend::gpu::{GpuContext, GpuDenter};
use dentbend::{mesh, wgpu};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // The application's own instance, adapter and device (downlevel limits: any adapter).
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter = match pollster::block_on(wgpu::util::initialize_adapter_from_env_or_default(&instance, None)) {
        Ok(adapter) => adapter,
        Err(error) => {
            println!("no GPU adapter ({error}); install a Vulkan driver such as Mesa's lavapipe");
            return Ok(());
        }
    };
    let descriptor =
        wgpu::DeviceDescriptor { required_limits: wgpu::Limits::downlevel_defaults(), ..Default::default() };
    let (device, queue) = pollster::block_on(adapter.request_device(&descriptor))?;
    // dentbend wraps the handles (checking their limits) and keeps clones; the app keeps its own.
    let context = GpuContext::from_device(device.clone(), queue.clone())?;
    let block = mesh::builtin("block")?;
    let mut ball = mesh::builtin("sphere")?;
    ball.transform(Affine3A::from_scale_rotation_translation(Vec3::splat(0.6), Default::default(), Vec3::Y * 5.0))?;
    let mut denter = GpuDenter::new(&context, std::slice::from_ref(&block))?;
    let job = DentJob {
        target: 0,
        projectile: &ball,
        impact: Impact { point: Vec3::new(0.0, 0.5, 0.0), normal: -Vec3::Y, relative_velocity: -Vec3::Y * 3.0 },
        // A recorded batch runs the kernels alone: the paper's dent, no host stage.
        params: DentParams::new(0.2).without_host_stages(),
    };
    // Recorded into the application's encoder: nothing runs until the application submits.
    let mut encoder = device.create_command_encoder(&Default::default());
    denter.record_batch(&mut encoder, &[job])?;
    queue.submit([encoder.finish()]);
    // Only the moved vertices come back; the depth is the largest drop of any of them.
    let moved = denter.read_moved(0)?;
    let drop = |(&v, p): (&u32, &Vec3)| block.positions()[v as usize].y - p.y;
    let depth = moved.indices.iter().zip(&moved.positions).map(drop).fold(0.0, f32::max);
    println!("{}: {} vertices moved, dent depth {depth:.4} m", context.adapter_name(), moved.indices.len());
    Ok(())
}
