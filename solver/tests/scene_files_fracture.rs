//! `[body.fracture]` in scene files: a breakable body is read with its
//! pattern and toughness, breaks in the simulation, and bad tables are refused by a message that
//! names the file, the line of the offending value, the body and the field.

use std::path::Path;

use dentbend::fracture::FractureCause;
use dentbend_solver::coupling::Simulation;
use dentbend_solver::scene::{DEFAULT_FRACTURE_CELLS, load_scene, parse_scene};

/// A static 3 × 2 × 0.2 m wall with `fracture` lines in its `[body.fracture]` table (and `body` lines before).
fn wall(body: &str, fracture: &str) -> String {
    format!(
        "frames = 10\n\n[[body]]\nname = \"wall\"\nmesh = \"box\"\nscale = [1.5, 1.0, 0.1]\nkind = \"static\"\n{body}\n\
         [body.fracture]\n{fracture}\n"
    )
}

/// Parses `text`, expects a refusal on the line holding `at`, naming body "wall" and `field`.
fn refused(text: &str, at: &str, field: &str) -> String {
    let line = text.lines().position(|l| l.contains(at)).unwrap_or_else(|| panic!("no {at} in\n{text}")) + 1;
    let message = match parse_scene(text, Path::new("wall.toml")) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.to_string(),
    };
    assert!(message.starts_with(&format!("wall.toml:{line}:")), "expected line {line}: {message}\n{text}");
    assert!(message.contains("body \"wall\""), "no body in {message}");
    assert!(message.contains(&format!(" {field}: ")), "no field {field} in {message}");
    message
}

#[test]
fn a_fracture_table_is_read() {
    let text = wall("density = 2000.0", "radius = 0.5\ncells = 12\nseed = 42\ntoughness = 80.0\ndent_limit = 0.2");
    let scene = parse_scene(&text, Path::new("wall.toml")).unwrap();
    let settings = scene.world.bodies()[0].fracture.as_ref().expect("the wall breaks");
    let params = settings.pattern.params();
    assert_eq!((params.cells, params.seed, params.radius), (12, 42, 0.5));
    assert_eq!((settings.toughness, settings.dent_limit, settings.density), (Some(80.0), Some(0.2), 2000.0));
    let text = wall("", "radius = 0.5\ntoughness = 80.0\ndensity = 2500.0");
    let scene = parse_scene(&text, Path::new("wall.toml")).unwrap();
    let settings = scene.world.bodies()[0].fracture.as_ref().unwrap();
    assert_eq!((settings.pattern.params().cells, settings.pattern.params().seed), (DEFAULT_FRACTURE_CELLS, 0));
    assert_eq!((settings.dent_limit, settings.density), (None, 2500.0));
    assert_eq!(settings.max_pieces, dentbend::fracture::DEFAULT_MAX_PIECES);
    let text = wall("", "radius = 0.5\ntoughness = 80.0\nmax_pieces = 64");
    let scene = parse_scene(&text, Path::new("wall.toml")).unwrap();
    assert_eq!(scene.world.bodies()[0].fracture.as_ref().unwrap().max_pieces, 64);
}

#[test]
fn bad_fracture_tables_are_refused() {
    refused(&wall("", "radius = nan\ntoughness = 1.0"), "radius =", "fracture.radius");
    refused(&wall("", "radius = -0.5\ntoughness = 1.0"), "radius =", "fracture.radius");
    refused(&wall("", "radius = 0.5\ncells = 0\ntoughness = 1.0"), "cells =", "fracture.cells");
    refused(&wall("", "radius = 0.5\ncells = 100000\ntoughness = 1.0"), "cells =", "fracture.cells");
    refused(&wall("", "radius = 0.5\ncells = -3\ntoughness = 1.0"), "cells =", "fracture.cells");
    refused(&wall("", "radius = 0.5\ntoughness = nan"), "toughness =", "fracture.toughness");
    refused(&wall("", "radius = 0.5\ntoughness = -5.0"), "toughness =", "fracture.toughness");
    refused(&wall("", "radius = 0.5\ndent_limit = -0.1"), "dent_limit =", "fracture.dent_limit");
    refused(&wall("", "radius = 0.5\ntoughness = 1.0\ndensity = 0.0"), "density =", "fracture.density");
    refused(&wall("", "radius = 0.5\ntoughness = 1.0\nseed = -1"), "seed =", "fracture.seed");
    refused(&wall("", "radius = 0.5\ntoughness = 1.0\nmax_pieces = 0"), "max_pieces =", "fracture.max_pieces");
    refused(&wall("", "radius = 0.5\ntoughness = 1.0\ncels = 3"), "cels =", "fracture.cels");
    // Neither a toughness nor a dent limit: the table is at fault.
    refused(&wall("", "radius = 0.5"), "[body.fracture]", "fracture");
    // No radius.
    refused(&wall("", "toughness = 1.0"), "[body.fracture]", "fracture");
    // A bending body cannot break.
    let text = "[[body]]\nname = \"wall\"\nmesh = \"box\"\n\n[body.bend]\nresolution = 16\n\n\
                [body.fracture]\nradius = 0.5\ntoughness = 1.0\n";
    refused(text, "[body.fracture]", "fracture");
}

/// The example scene file breaks its wall at the ball's first hit (about 1,000 J removed along
/// the normal against a toughness of 300 J), into dynamic pieces.
#[test]
fn the_example_wall_breaks_at_the_first_hit() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/prescored_wall.toml");
    let scene = load_scene(&path).unwrap();
    let mut sim = Simulation::new(scene.world, None).unwrap();
    for _ in 0..30 {
        sim.step().unwrap();
    }
    let fractures = sim.fractures();
    assert_eq!(fractures.len(), 1, "{fractures:?}");
    assert_eq!(fractures[0].cause, FractureCause::Energy);
    assert!(fractures[0].energy > 300.0 && fractures[0].pieces.len() >= 5, "{:?}", fractures[0]);
}
