//! `--backend`: the GPU kernels write the same dentmap files and dented meshes as the CPU ones.

mod common;

use common::{TempDir, dentbend, text};
use dentbend::gpu::GpuContext;
use dentbend::io::read_npy_f32;

fn dentmap(dir: &TempDir, backend: &str) -> Vec<(String, Vec<f32>)> {
    let out = dir.path(backend);
    let output = dentbend(&[
        "dentmap",
        "--projectile",
        "bunny",
        "--normal",
        "0,1,0",
        "--velocity",
        "0.5,1,0",
        "--dent-distance",
        "2",
        "--res",
        "80",
        "--backend",
        backend,
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{backend}: {}", text(&output.stderr));
    ["zbuffer", "envelope", "smoothed", "dentmap"]
        .iter()
        .map(|name| (name.to_string(), read_npy_f32(out.join(format!("{name}.npy"))).unwrap().1))
        .collect()
}

/// Same files, same shapes; values within 2e-5·d (the tolerance of tests/parity_pipeline.rs,
/// where its reasons are given).
fn gpu_and_cpu_backends_write_the_same_dent_map(_: &'static GpuContext) {
    let dir = TempDir::new("backend");
    let (cpu, gpu) = (dentmap(&dir, "cpu"), dentmap(&dir, "gpu"));
    for ((name, c), (_, g)) in cpu.iter().zip(&gpu) {
        assert_eq!(c.len(), g.len(), "{name}");
        let worst = c.iter().zip(g).map(|(a, b)| (a - b).abs()).fold(0.0, f32::max);
        assert!(worst <= 2e-5 * 2.0, "{name}: CPU and GPU differ by {worst}");
    }
    let json = |b: &str| std::fs::read_to_string(dir.path(b).join("dentmap.json")).unwrap();
    assert_eq!(json("cpu"), json("gpu"), "the recorded parameters and grids are the same");
}

fn an_unknown_backend_is_a_usage_error() {
    let output =
        dentbend(&["dentmap", "--projectile", "bunny", "--dent-distance", "1", "--backend", "cuda", "--out", "x"]);
    assert_eq!(output.status.code(), Some(2));
    assert!(text(&output.stderr).starts_with("error:"));
}

gpu_test_main! {
    plain: [an_unknown_backend_is_a_usage_error],
    gpu: [gpu_and_cpu_backends_write_the_same_dent_map],
}
