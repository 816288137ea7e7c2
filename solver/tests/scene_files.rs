//! Scene files and built-in scenes: every built-in scene builds at both sizes with the bodies it
//! promises, the example file loads, and every kind of bad scene file is refused with the file,
//! the line and the field in the message, without writing anything.

use std::path::{Path, PathBuf};
use std::time::SystemTime;

use dentbend::dent::{Attenuation, Resolution};
use dentbend::glam::Vec3;
use dentbend_solver::scene::{
    self, BUILTIN_SCENES, Scene, SceneError, SceneSize, builtin_scene, load_scene, parse_scene,
};
use dentbend_solver::sim::{BodyKind, RigidBody};

fn body<'a>(scene: &'a Scene, name: &str) -> &'a RigidBody {
    let index = scene.world.find(name).unwrap_or_else(|| panic!("scene {} has no body \"{name}\"", scene.name));
    &scene.world.bodies()[index]
}

/// A file of the repository (the solver crate's parent folder).
fn repo_file(relative: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(relative)
}

/// Every built-in scene at both sizes, with its body count.
#[test]
fn builtin_scenes_build_at_both_sizes() {
    let expected = [
        ("pair", 2, 2),
        ("ball-block", 4, 4),
        ("bunny-block", 8, 8),
        ("glancing", 6, 6),
        ("resolution", 8, 8),
        ("rain", 4 + 1 + 4 + 3 + 1500, 2 + 1 + 2 + 1 + 150),
        // Bending scenes: their bending body is one world body per bone.
        ("plank", 2 + 1 + 1 + 1, 2 + 1 + 1 + 1),
        ("spring", 1 + 2, 1 + 2),
        // Ground, four frames of 12 bars, tetrahedra of 4 balls and 6 one-bone struts.
        ("tetrahedra", 1 + 48 + 400 * 10, 1 + 48 + 16 * 10),
        // A stand, two balls and the bunny's four bones.
        ("bunny-bones", 1 + 2 + 4, 1 + 2 + 4),
        // A stand, a ball and the body's torso bones (20 full, 12 demo) and four arm bones.
        ("arm", 1 + 1 + 20 + 4, 1 + 1 + 12 + 4),
        // The prescored wall and three balls.
        ("wall", 1 + 3, 1 + 3),
    ];
    assert_eq!(BUILTIN_SCENES.len(), expected.len());
    for (name, full, demo) in expected {
        for (size, count) in [(SceneSize::Full, full), (SceneSize::Demo, demo)] {
            let scene = builtin_scene(name, size).unwrap_or_else(|e| panic!("{name} {size:?}: {e}"));
            assert_eq!(scene.name, name);
            assert_eq!(scene.world.bodies().len(), count, "{name} {size:?}");
            assert!(scene.frames >= 30, "{name} {size:?}: {} frames", scene.frames);
            assert!(!scene.description.is_empty());
            let camera = scene.camera;
            assert!(camera.eye.is_finite() && camera.target.is_finite() && camera.eye != camera.target);
            let dents = scene.world.bodies().iter().any(|b| b.dent.is_some());
            assert!(dents || !scene.bending.is_empty(), "{name}: nothing dents or bends");
        }
    }
    assert!(matches!(builtin_scene("nope", SceneSize::Demo), Err(SceneError::UnknownScene { .. })));
}

/// Figure 1: `left` and `right` are equal dentable balls flying at each other, no gravity.
#[test]
fn pair_is_symmetric() {
    for size in [SceneSize::Full, SceneSize::Demo] {
        let scene = builtin_scene("pair", size).unwrap();
        let (left, right) = (body(&scene, "left"), body(&scene, "right"));
        assert_eq!(scene.world.settings().gravity, Vec3::ZERO);
        assert!(left.mesh().face_count() >= 5000, "{} triangles", left.mesh().face_count());
        assert_eq!(left.mesh().face_count(), right.mesh().face_count());
        assert!((left.mass - right.mass).abs() < 1e-3 * left.mass);
        assert_eq!(left.linear_velocity, -right.linear_velocity);
        assert!(left.linear_velocity.x > 0.0 && left.position.x < right.position.x);
        let (a, b) = (left.dent.as_ref().unwrap(), right.dent.as_ref().unwrap());
        assert_eq!(a.material, b.material);
    }
}

/// Figure 2: both attenuation variants in one run, each block with a ball above it.
#[test]
fn ball_block_has_both_attenuations() {
    let scene = builtin_scene("ball-block", SceneSize::Demo).unwrap();
    let attenuated = body(&scene, "block-attenuated").dent.as_ref().unwrap();
    let unattenuated = body(&scene, "block-unattenuated").dent.as_ref().unwrap();
    assert!(matches!(attenuated.params.attenuation, Attenuation::Logistic));
    assert!(matches!(unattenuated.params.attenuation, Attenuation::None));
    for ball in ["ball-1", "ball-2"] {
        let ball = body(&scene, ball);
        assert_eq!(ball.kind, BodyKind::Dynamic);
        assert!(ball.linear_velocity.y < 0.0 && ball.position.y > 0.5);
    }
}

/// Figure 5: non-dentable bunnies over blocks of growing dent distance and σ.
#[test]
fn bunny_block_grows_dent_distance_and_sigma() {
    let scene = builtin_scene("bunny-block", SceneSize::Full).unwrap();
    let mut last = (0.0, 0.0);
    for k in 1..=4 {
        assert!(body(&scene, &format!("bunny-{k}")).dent.is_none());
        let dent = body(&scene, &format!("block-{k}")).dent.clone().unwrap();
        let now = (dent.material.cap, dent.params.sigma.unwrap());
        assert!(now.0 > last.0 && now.1 > last.1, "block-{k}: {now:?} after {last:?}");
        last = now;
    }
}

/// Figure 8: the balls come in at growing angles from the normal.
#[test]
fn glancing_angles_grow() {
    let scene = builtin_scene("glancing", SceneSize::Demo).unwrap();
    let gravity = scene.world.settings().gravity;
    let mut last = -1.0;
    for name in ["ball-0deg", "ball-30deg", "ball-60deg"] {
        let ball = body(&scene, name);
        // Velocity at the top face, 0.25 s after the start (as the scene launches them).
        let v = ball.linear_velocity + gravity * 0.25;
        let angle = v.normalize().dot(Vec3::NEG_Y).acos().to_degrees();
        assert!(angle > last + 20.0 || last < 0.0, "{name}: {angle}° after {last}°");
        last = angle;
    }
    assert!((last - 60.0).abs() < 1.0);
}

/// Figure 11: fixed grids of 20, 50, 100 and 200 cells.
#[test]
fn resolution_scene_fixes_the_grid() {
    let scene = builtin_scene("resolution", SceneSize::Demo).unwrap();
    for cells in [20, 50, 100, 200] {
        let dent = body(&scene, &format!("block-res{cells}")).dent.as_ref().unwrap();
        assert_eq!(dent.params.resolution, Resolution::Fixed(cells));
        assert!(body(&scene, &format!("ball-res{cells}")).dent.is_none());
    }
}

/// Figure 10 at full size: ≥ 1,507 dynamic dentable balls and a dense dentable bunny.
#[test]
fn rain_full_has_the_papers_counts() {
    let scene = builtin_scene("rain", SceneSize::Full).unwrap();
    let spheres = scene
        .world
        .bodies()
        .iter()
        .filter(|b| b.kind == BodyKind::Dynamic && b.dent.is_some() && b.shape().as_ball().is_some())
        .count();
    assert!(spheres >= 1507, "{spheres} dynamic dentable spheres");
    let bunny = body(&scene, "bunny");
    assert_eq!(bunny.kind, BodyKind::Static);
    assert!(bunny.dent.is_some());
    assert!(bunny.mesh().face_count() >= 30_000, "{} triangles", bunny.mesh().face_count());
    assert!(body(&scene, "ground").kind == BodyKind::Static);
    // No two spheres start overlapping.
    let mut balls: Vec<(Vec3, f32)> =
        scene.world.bodies().iter().filter_map(|b| b.shape().as_ball().map(|ball| (b.position, ball.radius))).collect();
    balls.sort_by(|a, b| a.0.x.total_cmp(&b.0.x));
    for (i, &(p, r)) in balls.iter().enumerate() {
        for &(q, s) in balls[i + 1..].iter().take_while(|(q, s)| q.x - p.x < r + s + 1.5) {
            assert!(p.distance(q) > r + s, "spheres at {p} and {q} overlap");
        }
    }
    let demo = builtin_scene("rain", SceneSize::Demo).unwrap();
    assert!(demo.world.bodies().len() < 200);
}

/// The example file loads, with the fields it sets.
#[test]
fn example_file_loads() {
    let scene = load_scene(&repo_file("scenes/example.toml")).unwrap();
    assert_eq!((scene.name.as_str(), scene.frames, scene.world.bodies().len()), ("example", 120, 3));
    assert_eq!(scene.camera.eye, Vec3::new(0.0, 4.5, 9.0));
    let ball = body(&scene, "ball");
    assert!((ball.mass - 500.0).abs() < 0.5, "mass {}", ball.mass);
    assert_eq!(ball.linear_velocity, Vec3::new(0.0, -4.0, 0.0));
    let block = body(&scene, "block");
    assert_eq!(block.kind, BodyKind::Static);
    let dent = block.dent.as_ref().unwrap();
    assert_eq!((dent.material.cap, dent.params.sigma, dent.move_projectile), (0.3, Some(0.08), true));
    // Rotation is axis-angle in degrees: 180° about x turns the bunny upside down.
    let bunny = body(&scene, "bunny");
    assert!((bunny.orientation * Vec3::Y).dot(Vec3::NEG_Y) > 0.999);
    // `load` takes a path as well as a built-in name.
    let path = repo_file("scenes/example.toml");
    assert_eq!(scene::load(path.to_str().unwrap()).unwrap().name, "example");
    assert_eq!(scene::load_sized("pair", SceneSize::Demo).unwrap().name, "pair");
    assert!(matches!(scene::load("no-such-scene"), Err(SceneError::UnknownScene { .. })));
}

/// A valid scene with `line` inserted as line 5, in the body named "ball".
fn with_line(line: &str) -> String {
    format!("frames = 60\n\n[[body]]\nname = \"ball\"\n{line}\nmesh = \"sphere\"\n")
}

/// Parses `text` as `file` and returns the error message.
fn error(text: &str, file: &str) -> String {
    match parse_scene(text, &repo_file("scenes").join(file)) {
        Ok(_) => panic!("{file} was accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

/// The message names the file, `file:line:`, and the field.
fn assert_names(message: &str, file: &str, line: usize, field: &str) {
    assert!(message.contains(&format!("{file}:{line}:")), "no {file}:{line}: in {message}");
    assert!(message.contains(field), "no {field} in {message}");
}

#[test]
fn unknown_field_is_refused() {
    let message = error(&with_line("bounciness = 0.5"), "unknown.toml");
    assert_names(&message, "unknown.toml", 5, "bounciness");
    assert!(message.contains("body \"ball\""), "{message}");
    // In a sub-table, an inline table and the world table too.
    let text = "[[body]]\nname = \"b\"\nmesh = \"sphere\"\n[body.dent]\ncap = 0.2\nsigmaa = 0.1\n";
    assert_names(&error(text, "dent.toml"), "dent.toml", 6, "dent.sigmaa");
    let text = "[[body]]\nname = \"b\"\nmesh = \"sphere\"\ndent = { cap = 0.2, depth = 1 }\n";
    assert_names(&error(text, "inline.toml"), "inline.toml", 4, "dent.depth");
    assert_names(
        &error("frames = 10\n[world]\ngravity = [0, -9.81, 0]\ntimestep = 0.01\n", "w.toml"),
        "w.toml",
        4,
        "timestep",
    );
}

#[test]
fn missing_required_field_names_the_body() {
    let text = "[[body]]\nname = \"a\"\nmesh = \"sphere\"\n\n[[body]]\nname = \"b\"\nmass = 2\n";
    let message = error(text, "no-mesh.toml");
    assert_names(&message, "no-mesh.toml", 5, "mesh");
    assert!(message.contains("body \"b\""), "{message}");
    // Rotation is axis-angle, three numbers: a quaternion is refused, not misread.
    assert_names(&error(&with_line("rotation = [0, 0, 0, 1]"), "quat.toml"), "quat.toml", 5, "rotation");
}

#[test]
fn missing_mesh_file_is_refused() {
    let text = "[[body]]\nname = \"thing\"\nmesh = \"meshes/no-such-mesh.obj\"\n";
    let message = error(text, "missing.toml");
    assert_names(&message, "missing.toml", 3, "mesh");
    assert!(message.contains("no-such-mesh.obj") && message.contains("not found"), "{message}");
}

#[test]
fn negative_mass_and_bad_numbers_are_refused() {
    assert_names(&error(&with_line("mass = -2.0"), "mass.toml"), "mass.toml", 5, "mass");
    assert_names(&error(&with_line("density = 0"), "density.toml"), "density.toml", 5, "density");
    assert_names(&error(&with_line("mass = 1\ndensity = 2"), "both.toml"), "both.toml", 5, "mass");
    assert_names(&error(&with_line("velocity = [nan, 0, 0]"), "nan.toml"), "nan.toml", 5, "velocity");
    assert_names(&error(&with_line("position = [0, inf, 0]"), "inf.toml"), "inf.toml", 5, "position");
    assert_names(&error(&with_line("scale = [1, 0, 1]"), "scale.toml"), "scale.toml", 5, "scale");
    assert_names(&error(&with_line("restitution = 1.5"), "rest.toml"), "rest.toml", 5, "restitution");
    assert_names(&error(&with_line("mass = \"heavy\""), "type.toml"), "type.toml", 5, "mass");
    assert_names(&error(&with_line("kind = \"floating\""), "kind.toml"), "kind.toml", 5, "kind");
    let text = "[world]\ngravity = [0, -9.81, 0]\ndt = -0.01\n";
    assert_names(&error(text, "dt.toml"), "dt.toml", 3, "world.dt");
}

#[test]
fn bad_dent_parameters_are_refused() {
    let dent =
        |line: &str| format!("[[body]]\nname = \"b\"\nmesh = \"block\"\nkind = \"static\"\n[body.dent]\n{line}\n");
    assert_names(&error(&dent("sigma = -0.1"), "sigma.toml"), "sigma.toml", 6, "dent.sigma");
    assert_names(&error(&dent("heat_rate = 0.5"), "rate.toml"), "rate.toml", 6, "dent.heat_rate");
    assert_names(&error(&dent("cap = 0"), "cap.toml"), "cap.toml", 6, "dent.cap");
    assert_names(&error(&dent("resolution = \"fine\""), "res.toml"), "res.toml", 6, "resolution");
    assert_names(&error(&dent("attenuation = \"cubic\""), "att.toml"), "att.toml", 6, "attenuation");
}

#[test]
fn duplicate_names_are_refused() {
    let text = "[[body]]\nname = \"twin\"\nmesh = \"sphere\"\n\n[[body]]\nname = \"twin\"\nmesh = \"sphere\"\n";
    let message = error(text, "twins.toml");
    assert_names(&message, "twins.toml", 6, "name");
    assert!(message.contains("duplicate") && message.contains("line 2"), "{message}");
}

#[test]
fn bad_syntax_is_refused() {
    let message = error(&with_line("mass = 1.0.0"), "syntax.toml");
    assert_names(&message, "syntax.toml", 5, "mass");
    // An unclosed array runs on into the next line, where the parser stops; the message says
    // where the value began.
    let message = error(&with_line("velocity = [1, 2"), "unclosed.toml");
    assert_names(&message, "unclosed.toml", 6, "velocity");
    assert!(message.contains("starts on line 5"), "{message}");
    let message = error("frames = 10\n[[body]\nname = \"x\"\n", "header.toml");
    assert_names(&message, "header.toml", 2, "");
    let message = error(&with_line("friction = 0.5 0.6"), "two.toml");
    assert_names(&message, "two.toml", 5, "friction");
}

#[test]
fn unreadable_file_is_a_read_error() {
    let missing = repo_file("scenes/no-such-scene.toml");
    assert!(matches!(load_scene(&missing), Err(SceneError::Read { .. })));
}

/// Loading and building scenes leaves the repository's files as they were.
#[test]
fn nothing_is_written() {
    let listing = |dir: &Path| -> Vec<(PathBuf, Option<SystemTime>)> {
        let mut entries: Vec<_> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| {
                let e = e.unwrap();
                (e.path(), e.metadata().ok().and_then(|m| m.modified().ok()))
            })
            .collect();
        entries.sort();
        entries
    };
    // Only scenes/ is watched: others may be editing files elsewhere in the repository.
    let dirs = [repo_file("scenes")];
    let before: Vec<_> = dirs.iter().map(|d| listing(d)).collect();
    load_scene(&repo_file("scenes/example.toml")).unwrap();
    let _ = error(&with_line("mass = -1"), "written.toml");
    let _ = error("[[body]]\nname = \"x\"\nmesh = \"gone.obj\"\n", "gone.toml");
    builtin_scene("ball-block", SceneSize::Demo).unwrap();
    let after: Vec<_> = dirs.iter().map(|d| listing(d)).collect();
    assert_eq!(before, after);
    assert!(!repo_file("scenes/written.toml").exists() && !repo_file("scenes/gone.toml").exists());
}
