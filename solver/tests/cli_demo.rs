//! The README's first command: `dentbend demo` writes every picture and mesh it promises, and
//! `dent --projectile-out` dents both bodies.

mod common;

use common::{TempDir, dentbend, text};

#[test]
fn demo_writes_every_picture_and_mesh() {
    let dir = TempDir::new("demo");
    let out = dir.path("out");
    // Pictures of an earlier run in the same folder: the gallery must not list them.
    std::fs::create_dir_all(out.join("scenes/pair/frames")).unwrap();
    for stale in ["stale.png", "scenes/pair/frames/9999.png"] {
        std::fs::write(out.join(stale), b"not this run's").unwrap();
        let old = std::time::SystemTime::now() - std::time::Duration::from_secs(3600);
        std::fs::File::options().write(true).open(out.join(stale)).unwrap().set_modified(old).unwrap();
    }
    let output = dentbend(&["demo", "--out", out.to_str().unwrap()]);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let expected = [
        "fig07_bunny/zbuffer.png",
        "fig07_bunny/envelope.png",
        "fig07_bunny/smoothed.png",
        "fig07_bunny/dentmap.png",
        "fig07_bunny/dentmap.json",
        "fig07_bunny/smoothed.npy",
        "block_sphere.obj",
        "block_sphere.png",
        "block_bunny.obj",
        "block_bunny.png",
        "block_glancing.obj",
        "block_glancing.png",
        "pair_lower.obj",
        "pair_upper.obj",
        "pair.png",
        "crate.obj",
        "crate.png",
        "gallery.html",
        "scenes/pair/summary.json",
        "scenes/pair/frames/0060.png",
        "scenes/pair/meshes/left_0060.glb",
        "scenes/ball-block/summary.json",
        "scenes/bunny-block/summary.json",
        "scenes/glancing/summary.json",
        "scenes/resolution/summary.json",
        "scenes/rain/summary.json",
        "scenes/rain/frames/0120.png",
        "scenes/plank/summary.json",
        "scenes/plank/frames/0045.png",
        "scenes/spring/summary.json",
        "scenes/bunny-bones/summary.json",
        "scenes/tetrahedra/summary.json",
        "scenes/arm/summary.json",
        "scenes/wall/summary.json",
        "scenes/wall/damage.json",
        "scenes/wall-replay/meshes/frame_0120.glb",
    ];
    for file in expected {
        let path = out.join(file);
        let size = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
        assert!(size > 0, "{file} missing or empty");
    }
    let picture = image::open(out.join("block_bunny.png")).unwrap().to_rgb8();
    assert_eq!(picture.dimensions(), (960, 640));
    // Every step is echoed as the command that reproduces it.
    let stdout = text(&output.stdout);
    assert_eq!(stdout.lines().filter(|l| l.starts_with("$ dentbend ")).count(), 24, "{stdout}");
    // How many entries a scene's summary lists under `key`.
    let listed = |scene: &str, key: &str| {
        let summary = std::fs::read_to_string(out.join("scenes").join(scene).join("summary.json")).unwrap();
        let summary: serde_json::Value = serde_json::from_str(&summary).unwrap();
        summary[key].as_array().unwrap().len()
    };
    // Every denting scene dented something, and the gallery shows the scene frames.
    for scene in ["pair", "ball-block", "bunny-block", "glancing", "resolution", "rain"] {
        assert!(listed(scene, "dents") > 0, "{scene} made no dent");
    }
    // Joints appear where hits land on the plank and the tetrahedra's struts; the plank, the
    // tetrahedra and the arm bend.
    for scene in ["plank", "tetrahedra"] {
        assert!(listed(scene, "joints") > 0, "{scene} made no joint");
    }
    for scene in ["plank", "tetrahedra", "arm"] {
        assert!(listed(scene, "bends") > 0, "{scene} did not bend");
    }
    // The prescored wall breaks (Figure 3), and its replayed last frame is the run's, byte for byte.
    assert!(listed("wall", "fractures") > 0, "the wall did not break");
    let last = |dir: &str| std::fs::read(out.join("scenes").join(dir).join("meshes/frame_0120.glb")).unwrap();
    assert!(last("wall") == last("wall-replay"), "the replayed wall differs from the run's");
    let gallery = std::fs::read_to_string(out.join("gallery.html")).unwrap();
    assert!(gallery.contains("scenes/rain/frames/0120.png") && gallery.contains("fig07_bunny/smoothed.png"));
    assert!(gallery.contains("scenes/plank/frames/0045.png"));
    assert!(!gallery.contains("stale.png") && !gallery.contains("9999.png"), "stale pictures listed");
    // Each picture comes with its caption and the command that made it.
    assert!(gallery.contains("Paper Figure 7") && gallery.contains("dentbend dentmap --projectile bunny"));
    assert!(gallery.contains("dentbend run rain --size demo"));
    // A dent and the render of its mesh share one caption: both commands, then the picture.
    let figure_2c = gallery.split("<h2>").find(|s| s.starts_with("Paper Figure 2c")).expect("Figure 2c caption");
    assert!(figure_2c.contains("dentbend dent --target block-fine") && figure_2c.contains("dentbend render --mesh"));
    assert!(figure_2c.contains("block_sphere.png"));
}

#[test]
fn projectile_out_dents_both_bodies_as_mirror_images() {
    let dir = TempDir::new("pair");
    let (lower, upper) = (dir.path("lower.obj"), dir.path("upper.obj"));
    let output = dentbend(&[
        "dent",
        "--target",
        "sphere",
        "--projectile",
        "sphere",
        "--translate",
        "0,2,0",
        "--point",
        "0,1,0",
        "--normal",
        "0,-1,0",
        "--dent-distance",
        "0.3",
        "--out",
        lower.to_str().unwrap(),
        "--projectile-out",
        upper.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let (a, b) = (dentbend::mesh::load(&lower).unwrap(), dentbend::mesh::load(&upper).unwrap());
    // The vertices that touched, (0, 1, 0) on each ball, each move d = 0.3 away from the contact
    // (1 % of d: the dome's top is flat to that over the central cells).
    let sphere = dentbend::mesh::builtin("sphere").unwrap();
    let top = sphere.positions().iter().position(|p| (p.y - 1.0).abs() < 1e-6).unwrap();
    let bottom = sphere.positions().iter().position(|p| (p.y + 1.0).abs() < 1e-6).unwrap();
    let (a_top, b_bottom) = (a.positions()[top].y, b.positions()[bottom].y);
    assert!((a_top - 0.7).abs() < 0.003, "lower ball's top at {a_top}");
    assert!((b_bottom - 1.3).abs() < 0.003, "upper ball's bottom at {b_bottom}");
    // Mirror images through y = 1.
    let worst = a
        .positions()
        .iter()
        .map(|p| {
            let m = dentbend::glam::Vec3::new(p.x, 2.0 - p.y, p.z);
            b.positions().iter().map(|q| q.distance(m)).fold(f32::INFINITY, f32::min)
        })
        .fold(0.0, f32::max);
    assert!(worst < 1e-4, "asymmetry {worst}");
}
