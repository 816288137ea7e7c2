//! Where volume preservation is switched on: a scene body's `[body.dent]` (`material` and
//! `preserve_volume`), and `dentbend dent --preserve-volume`, whose output keeps the block's
//! volume and whose summary line reports the volume change and the cavity.

mod common;

use std::path::Path;

use common::{TempDir, dentbend, text};
use dentbend::VolumeMode;
use dentbend_solver::scene::parse_scene;

/// The dent table `dent` of a one-body scene, parsed; the body's volume mode.
fn volume_mode(dent: &str) -> VolumeMode {
    let text =
        format!("[[body]]\nname = \"block\"\nmesh = \"block\"\nkind = \"static\"\n\n[body.dent]\ncap = 0.1\n{dent}\n");
    let scene = parse_scene(&text, Path::new("volume.toml")).unwrap();
    scene.world.bodies()[0].dent.as_ref().unwrap().params.volume
}

#[test]
fn the_material_decides_and_the_key_overrides() {
    assert_eq!(volume_mode(""), VolumeMode::Free, "a body that does not say dents as in the paper");
    assert_eq!(volume_mode("material = \"solid\""), VolumeMode::Preserve);
    assert_eq!(volume_mode("material = \"sheet\""), VolumeMode::Free);
    assert_eq!(volume_mode("preserve_volume = true"), VolumeMode::Preserve);
    assert_eq!(volume_mode("material = \"solid\"\npreserve_volume = false"), VolumeMode::Free);
    assert_eq!(volume_mode("material = \"sheet\"\npreserve_volume = true"), VolumeMode::Preserve);
    let bad = "[[body]]\nname = \"b\"\nmesh = \"block\"\nkind = \"static\"\n[body.dent]\nmaterial = \"jelly\"\n";
    assert!(parse_scene(bad, Path::new("bad.toml")).is_err());
}

/// Signed volume of an OBJ's triangles (vertices and `f a b c` lines), f64.
fn obj_volume(path: &Path) -> f64 {
    let (mut vertices, mut volume) = (Vec::new(), 0.0);
    for line in std::fs::read_to_string(path).unwrap().lines() {
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.first() {
            Some(&"v") => vertices.push(dentbend::glam::DVec3::new(
                words[1].parse().unwrap(),
                words[2].parse().unwrap(),
                words[3].parse().unwrap(),
            )),
            Some(&"f") => {
                let corner = |w: &str| vertices[w.split('/').next().unwrap().parse::<usize>().unwrap() - 1];
                let (a, b, c) = (corner(words[1]), corner(words[2]), corner(words[3]));
                volume += a.dot(b.cross(c)) / 6.0;
            }
            _ => {}
        }
    }
    volume
}

#[test]
fn cli_preserve_volume_keeps_the_block_and_reports_it() {
    let dir = TempDir::new("preserve-volume");
    let (_, top) = dentbend::mesh::builtin("block").unwrap().bounds();
    let (low, _) = dentbend::mesh::builtin("sphere").unwrap().bounds();
    let translate = format!("0,{},0", top.y - low.y);
    let point = format!("0,{},0", top.y);
    let run = |out: &Path, extra: &[&str]| {
        let mut args = vec!["dent", "--target", "block", "--projectile", "sphere", "--translate", &translate];
        args.extend(["--point", &point, "--normal=0,-1,0", "--dent-distance", "0.2", "--backend", "cpu"]);
        args.extend(["--out", out.to_str().unwrap()]);
        args.extend(extra);
        let output = dentbend(&args);
        assert!(output.status.success(), "{}", text(&output.stderr));
        text(&output.stdout)
    };
    let (free, kept) = (dir.path("free.obj"), dir.path("kept.obj"));
    let free_line = run(&free, &[]);
    let kept_line = run(&kept, &["--preserve-volume"]);
    assert!(free_line.contains("volume change -") && free_line.contains("cavity"), "{free_line}");
    assert!(kept_line.contains("cavity"), "{kept_line}");
    let before = dentbend::mesh::builtin("block").unwrap();
    let start: f64 = {
        let p = before.positions();
        before
            .faces()
            .iter()
            .map(|f| {
                let [a, b, c] = f.map(|v| p[v as usize].as_dvec3());
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    };
    let cavity = start - obj_volume(&free);
    assert!(cavity > 0.0);
    // The OBJ's decimal positions round the rim's f32 positions: 2 % of the cavity still holds.
    let change = obj_volume(&kept) - start;
    assert!(change.abs() <= 0.02 * cavity, "change {change:.3e}, cavity {cavity:.3e}");
}
