//! The GPU path end to end on Bevy's own device (lavapipe in CI): a dent made through the
//! contact hook shows in the next frames where it is and nowhere far from it, reaches the screen
//! without passing through the main world (no render read-back), lands in Bevy's vertex slab at
//! the mesh's offset and stride without touching its other attributes, and matches the CPU path.

use crate::common;
use libtest_mimic::Trial;

use bevy::prelude::*;
use bevy_dentbend::demo::Frame;
use bevy_dentbend::dentbend::TriMesh;
use bevy_dentbend::{Dentable, slab_layout};
use common::{Scene, scene};

/// Where the scripted dents land (x, z on the plate's top face, m) and how fast the ball falls.
const HIT: (f32, f32) = (0.25, 0.15);
const SPEED: f32 = 6.0;

/// Vertices of `after` that differ from `before`.
fn moved(before: &TriMesh, after: &TriMesh) -> Vec<usize> {
    (0..before.vertex_count()).filter(|&v| before.positions()[v] != after.positions()[v]).collect()
}

/// Per pixel, whether any channel differs between `a` and `b` by more than `by` (of 255).
fn differs(a: &Frame, b: &Frame, by: u8) -> Vec<bool> {
    assert_eq!(a.size, b.size);
    a.rgba
        .chunks_exact(4)
        .zip(b.rgba.chunks_exact(4))
        .map(|(p, q)| p.iter().zip(q).any(|(x, y)| x.abs_diff(*y) > by))
        .collect()
}

/// The frame before and after one dent differ where the dent is and nowhere far from it:
/// - near: pixels within the projection of the moved vertices' extent around the impact, plus
///   two cells (the normals kernel refreshes one ring of faces past the moved vertices, and a
///   cell is 2/48 m) and 3 pixels for rasterisation;
/// - at least 30 pixels there change by more than 8/255 (the dent shades a patch of hundreds);
/// - no pixel outside changes at all (the renderer is deterministic: same scene, same pixels).
fn the_frame_changes_at_the_dent_and_nowhere_far(gpu: bool) {
    let mut s = scene(gpu, true);
    s.warm_up(gpu);
    let before = s.capture_settled();
    s.hit(HIT.0, HIT.1, SPEED);
    s.settle(1);
    let after = s.capture_settled();

    let now = s.target_now();
    let moved = moved(&s.target_mesh, &now);
    assert!(moved.len() > 20, "the dent moved only {} vertices", moved.len());
    let impact = Vec3::new(HIT.0, 0.0, HIT.1);
    let reach = moved
        .iter()
        .map(|&v| (s.target_mesh.positions()[v] - Vec3::new(0.0, 0.1, 0.0)).distance(impact))
        .fold(0.0, f32::max)
        + 2.0 * 2.0 / 48.0;
    let centre = s.project(impact);
    let radius = (0..32)
        .map(|k| {
            let a = k as f32 / 32.0 * std::f32::consts::TAU;
            s.project(impact + reach * Vec3::new(a.cos(), 0.0, a.sin())).distance(centre)
        })
        .fold(0.0, f32::max)
        + 3.0;
    let w = before.size.x as usize;
    let near = |i: usize| Vec2::new((i % w) as f32 + 0.5, (i / w) as f32 + 0.5).distance(centre) <= radius;
    let strong = differs(&before, &after, 8);
    let any = differs(&before, &after, 0);
    let inside = (0..strong.len()).filter(|&i| strong[i] && near(i)).count();
    let outside: Vec<usize> = (0..any.len()).filter(|&i| any[i] && !near(i)).collect();
    assert!(inside >= 30, "only {inside} pixels changed near the dent (centre {centre}, radius {radius} px)");
    assert!(
        outside.is_empty(),
        "{} pixels changed far from the dent, e.g. at ({}, {}) (centre {centre}, radius {radius} px)",
        outside.len(),
        outside[0] % w,
        outside[0] / w
    );
    eprintln!("{inside} pixels changed near the dent (radius {radius:.0} px), none elsewhere");
}

fn frame_changes_gpu_path() {
    the_frame_changes_at_the_dent_and_nowhere_far(true);
}

fn frame_changes_cpu_path() {
    the_frame_changes_at_the_dent_and_nowhere_far(false);
}

/// On the GPU path the dent reaches the screen without the main world: the plate's mesh asset
/// keeps its undented positions (no round trip through it) while the frame shows the dent
/// (previous test) and the main world's mesh (from the collider read-back) holds it; the
/// collider read-back was 4 bytes plus 16 per moved vertex.
fn no_render_read_back_on_the_gpu_path() {
    let mut s = scene(true, false);
    s.warm_up(true);
    s.hit(HIT.0, HIT.1, SPEED);
    s.settle(1);
    let stats = s.stats();
    assert_eq!((stats.dents, stats.gpu_dents), (1, 1));
    let moved = moved(&s.target_mesh, &s.target_now());
    assert!(!moved.is_empty(), "the main world never learnt of the dent");
    assert_eq!(stats.collider_readback_bytes, 4 + 16 * moved.len() as u64);
    assert_eq!(s.target_asset_positions(), s.target_mesh.positions(), "the mesh asset changed: a CPU round trip");
}

/// What Bevy draws: the plate's vertices in Bevy's vertex slab, read back (test only). Positions
/// are the GPU's dented positions bit for bit (the main world's copy came from the same
/// buffer); normals are unit and within 1e-3 of the CPU's normals of those positions (the
/// kernel's stated agreement is a few ulps times the conditioning, far below; a misplaced write
/// would be off by O(1)); the UVs are the spawned ones, bit for bit.
fn the_slab_holds_the_dent_at_bevys_offset_and_stride() {
    let mut s = scene(true, false);
    s.warm_up(true);
    s.hit(HIT.0, HIT.1, SPEED);
    s.hit(-0.4, -0.3, 4.0);
    s.settle(2);
    let handle = s.app.world().get::<Mesh3d>(s.target).expect("a mesh").0.clone();
    let layout =
        slab_layout(s.app.world().resource::<Assets<Mesh>>().get(&handle).expect("the asset")).expect("a layout");
    assert_eq!(layout.stride, 32, "position, normal, UV");
    s.probe.request(handle.id(), layout.stride);
    s.frames(2);
    let bytes = s.probe.take().expect("the slab was read");
    let now = s.target_now();
    assert_eq!(bytes.len(), now.vertex_count() * 32);
    let f = |v: usize, at: usize| f32::from_le_bytes(bytes[v * 32 + at..v * 32 + at + 4].try_into().unwrap());
    let original = common::with_uvs(&s.target_mesh);
    let Some(bevy::mesh::VertexAttributeValues::Float32x2(uvs)) = original.attribute(Mesh::ATTRIBUTE_UV_0) else {
        panic!("UVs")
    };
    for (v, uv) in uvs.iter().enumerate() {
        let p = Vec3::new(f(v, 0), f(v, 4), f(v, 8));
        assert_eq!(p, now.positions()[v], "vertex {v}: position in the slab");
        let n = Vec3::new(f(v, 12), f(v, 16), f(v, 20));
        assert!((n.length() - 1.0).abs() < 1e-5, "vertex {v}: normal {n} is not unit");
        assert!((n - now.normals()[v]).abs().max_element() < 1e-3, "vertex {v}: normal {n} vs {}", now.normals()[v]);
        assert_eq!([f(v, 24), f(v, 28)], *uv, "vertex {v}: UV touched");
    }
    assert!(moved(&s.target_mesh, &now).len() > 40, "two dents expected");
}

/// Tolerance per coordinate between the two paths after `dents` dents of at most `d` m: each
/// dent moves a vertex by at most d with the map's 2e-5·d error plus a few ulps of the
/// coordinate (tests/parity_moved.rs in the core crate), margin 3.
fn tolerance(dents: usize, d: f32) -> f32 {
    dents as f32 * 3.0 * (2e-5 * d + 8.0 * f32::EPSILON * 1.5)
}

/// The same contacts on both paths give the same dented plate (the main world's mesh: on the GPU
/// path from the read-backs, which copy the buffer the slab writes come from): the same vertices
/// moved, each within the kernels' tolerance. Three dents: two in one frame (one batch,
/// overlapping), one later. On the CPU path the mesh asset holds the dents too. With `dentable`:
/// the default settings (the game dent, host stages around the kernels) and the paper's dent
/// (the kernels alone, recorded into the frame).
fn the_gpu_and_cpu_paths_make_the_same_dents(dentable: fn() -> Dentable) {
    let run = |gpu: bool| -> (TriMesh, Vec<Vec3>, Scene) {
        let mut s = common::scene_dentable(gpu, dentable());
        s.warm_up(gpu);
        s.hit(HIT.0, HIT.1, SPEED);
        s.hit(HIT.0 + 0.1, HIT.1, 5.0);
        s.frames(3);
        s.hit(-0.5, 0.4, 7.0);
        s.settle(3);
        (s.target_now(), s.target_asset_positions(), s)
    };
    let (gpu, _, gs) = run(true);
    let (cpu, cpu_asset, _) = run(false);
    let before = &gs.target_mesh;
    let (moved_gpu, moved_cpu) = (moved(before, &gpu), moved(before, &cpu));
    assert!(moved_cpu.len() > 40);
    assert_eq!(moved_gpu, moved_cpu, "the paths moved different vertices");
    let tol = tolerance(3, 0.08);
    let mut worst = 0.0f32;
    for v in moved_cpu {
        let e = (gpu.positions()[v] - cpu.positions()[v]).abs().max_element();
        worst = worst.max(e);
        assert!(e <= tol, "vertex {v}: GPU {} vs CPU {} ({e} > {tol})", gpu.positions()[v], cpu.positions()[v]);
    }
    assert_eq!(cpu_asset, cpu.positions(), "the CPU path's mesh asset lacks its dents");
    eprintln!("worst GPU/CPU difference {worst:e} m (tolerance {tol:e})");
}

/// The energy model reaches the dents: with `Dentable::with_hardness`, a plate four times harder
/// dents less deep under the same hit (the plastic work equals the same energy over a smaller
/// volume), and both dent.
fn the_energy_model_sets_the_depth() {
    let depth = |hardness: f32| -> f32 {
        let mut s = common::scene_dentable(true, bevy_dentbend::Dentable::new(1.0, 0.01, 0.08).with_hardness(hardness));
        s.warm_up(true);
        s.hit(HIT.0, HIT.1, SPEED);
        s.settle(1);
        let (before, after) = (s.target_mesh.clone(), s.target_now());
        (0..before.vertex_count()).map(|v| before.positions()[v].distance(after.positions()[v])).fold(0.0, f32::max)
    };
    let (soft, hard) = (depth(2e6), depth(8e6));
    assert!(hard > 0.0 && soft > 1.2 * hard, "soft {soft} m, hard {hard} m");
    eprintln!("deepest vertex: {soft} m (2 MPa), {hard} m (8 MPa)");
}

fn same_dents_game() {
    the_gpu_and_cpu_paths_make_the_same_dents(|| Dentable::new(1.0, 0.01, 0.08));
}

fn same_dents_paper() {
    the_gpu_and_cpu_paths_make_the_same_dents(|| Dentable::paper(1.0, 0.01, 0.08));
}

pub fn tests() -> Vec<Trial> {
    common::gpu_trials(
        module_path!(),
        vec![
            ("the_frame_changes_at_the_dent_and_nowhere_far::gpu", frame_changes_gpu_path),
            ("the_frame_changes_at_the_dent_and_nowhere_far::cpu", frame_changes_cpu_path),
            ("no_render_read_back_on_the_gpu_path", no_render_read_back_on_the_gpu_path),
            ("the_slab_holds_the_dent_at_bevys_offset_and_stride", the_slab_holds_the_dent_at_bevys_offset_and_stride),
            ("the_gpu_and_cpu_paths_make_the_same_dents::game", same_dents_game),
            ("the_gpu_and_cpu_paths_make_the_same_dents::paper", same_dents_paper),
            ("the_energy_model_sets_the_depth", the_energy_model_sets_the_depth),
        ],
    )
}
