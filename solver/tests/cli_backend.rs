//! `--backend`: the GPU kernels write the same dentmap files and dented meshes as the CPU ones,
//! and `dent --backend gpu` honours `--preserve-volume` and the intersection guard as the CPU does.

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

/// Enclosed volume of an OBJ file, f64.
fn obj_volume(path: &std::path::Path) -> f64 {
    common::enclosed_volume(&dentbend::mesh::load(path).unwrap())
}

/// `dentbend dent` of the block by the sphere resting on its top, d = 0.2, on `backend` with
/// `extra` flags, written to `out`; its summary line.
fn dent_block(out: &std::path::Path, backend: &str, extra: &[&str]) -> String {
    let (_, top) = dentbend::mesh::builtin("block").unwrap().bounds();
    let (low, _) = dentbend::mesh::builtin("sphere").unwrap().bounds();
    let translate = format!("0,{},0", top.y - low.y);
    let point = format!("0,{},0", top.y);
    let mut args = vec!["dent", "--target", "block", "--projectile", "sphere", "--translate", &translate];
    args.extend(["--point", &point, "--normal=0,-1,0", "--dent-distance", "0.2", "--backend", backend]);
    args.extend(["--out", out.to_str().unwrap()]);
    args.extend(extra);
    let output = dentbend(&args);
    assert!(output.status.success(), "{backend} {extra:?}: {}", text(&output.stderr));
    assert!(!text(&output.stderr).contains("CPU"), "no CPU-only notice: {}", text(&output.stderr));
    text(&output.stdout)
}

/// `dent --backend gpu --preserve-volume` keeps the block's volume within 2 % of the cavity the
/// same dent without it leaves (measured on the written OBJ files, whose shortest round-trip
/// decimals read back as the same f32 positions), reports both, and writes the CPU backend's
/// mesh to within the parity tolerance of tests/parity_pipeline.rs for two moves (dent and rim).
fn gpu_dent_preserves_volume_from_the_command_line(_: &'static GpuContext) {
    let dir = TempDir::new("backend-preserve");
    let (free, kept, cpu) = (dir.path("free.obj"), dir.path("kept.obj"), dir.path("cpu.obj"));
    let free_line = dent_block(&free, "gpu", &[]);
    let kept_line = dent_block(&kept, "gpu", &["--preserve-volume"]);
    dent_block(&cpu, "cpu", &["--preserve-volume"]);
    assert!(free_line.contains("volume change -") && free_line.contains("cavity"), "{free_line}");
    assert!(kept_line.contains("cavity"), "{kept_line}");
    let start = common::enclosed_volume(&dentbend::mesh::builtin("block").unwrap());
    let cavity = start - obj_volume(&free);
    assert!(cavity > 1e-3, "the dent takes volume: {cavity}");
    let change = obj_volume(&kept) - start;
    assert!(change.abs() <= 0.02 * cavity, "change {change:.3e}, cavity {cavity:.3e}");
    let (g, c) = (dentbend::mesh::load(&kept).unwrap(), dentbend::mesh::load(&cpu).unwrap());
    assert_eq!(g.faces(), c.faces());
    let worst = g.positions().iter().zip(c.positions()).map(|(a, b)| a.distance(*b)).fold(0.0, f32::max);
    // Two moves of 2e-5·d plus ulps of coordinates up to 2 (the block's half-width).
    let tol = 2.0 * (2e-5 * 0.2 + 8.0 * f32::EPSILON * 2.0);
    assert!(worst <= tol, "GPU and CPU meshes differ by {worst} (allowed {tol})");
}

fn an_unknown_backend_is_a_usage_error() {
    let output =
        dentbend(&["dentmap", "--projectile", "bunny", "--dent-distance", "1", "--backend", "cuda", "--out", "x"]);
    assert_eq!(output.status.code(), Some(2));
    assert!(text(&output.stderr).starts_with("error:"));
}

gpu_test_main! {
    plain: [an_unknown_backend_is_a_usage_error],
    gpu: [gpu_and_cpu_backends_write_the_same_dent_map, gpu_dent_preserves_volume_from_the_command_line],
}
