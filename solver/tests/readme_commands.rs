//! The README's commands: every file they write goes under `out/`, and the dent-map
//! command makes the Figure 7 pictures the README shows.

mod common;

use common::temp::TempDir;
use common::{dentbend, text};

/// A file of the repository (the solver crate's parent folder).
fn repo_file(relative: &str) -> String {
    format!("{}/../{relative}", env!("CARGO_MANIFEST_DIR"))
}

/// The `cargo run` commands of the ```sh blocks of the repository's `file`, continuation lines
/// joined.
fn commands(file: &str) -> Vec<String> {
    let source = std::fs::read_to_string(repo_file(file)).unwrap();
    let mut commands = Vec::new();
    let mut in_block = false;
    let mut pending = String::new();
    for line in source.lines() {
        if line.starts_with("```") {
            in_block = line.trim() == "```sh";
            continue;
        }
        if !in_block || line.trim_start().starts_with('#') {
            continue;
        }
        let code = line.split("  #").next().unwrap_or_default().trim();
        pending.push_str(code.trim_end_matches('\\'));
        pending.push(' ');
        if !code.ends_with('\\') {
            if pending.contains("cargo run") {
                commands.push(pending.split_whitespace().collect::<Vec<_>>().join(" "));
            }
            pending.clear();
        }
    }
    commands
}

/// The values of the flags that name something a command writes.
fn written_paths(command: &str) -> Vec<&str> {
    let words: Vec<&str> = command.split_whitespace().collect();
    words.windows(2).filter(|w| matches!(w[0], "--out" | "--projectile-out" | "--json")).map(|w| w[1]).collect()
}

#[test]
fn every_command_in_the_docs_writes_under_out() {
    let mut checked = 0;
    for file in ["README.md", "docs/simulation.md"] {
        for command in commands(file) {
            for path in written_paths(&command) {
                assert!(path == "out" || path.starts_with("out/"), "{file}: `{command}` writes {path} outside out/");
                checked += 1;
            }
        }
    }
    // The README alone has the demo, dentmap, two dents (three files), render and two Rapier runs.
    assert!(checked >= 8, "only {checked} output paths found: is the parser still reading the ```sh blocks?");
}

#[test]
fn the_readme_dentmap_command_makes_its_figure_7_pictures() {
    let command = commands("README.md").into_iter().find(|c| c.contains("-- dentmap")).expect("a dentmap command");
    let dir = TempDir::new("readme-dentmap");
    let out = dir.path("bunny");
    let mut args: Vec<String> = command.split("-- ").nth(1).unwrap().split_whitespace().map(str::to_owned).collect();
    let at = args.iter().position(|a| a == "--out").unwrap();
    args[at + 1] = out.display().to_string();
    let output = dentbend(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(output.status.success(), "{}", text(&output.stderr));
    for stage in ["zbuffer", "envelope", "smoothed"] {
        let made = image::open(out.join(format!("{stage}.png"))).unwrap().to_rgb8();
        let shown = image::open(repo_file(&format!("docs/images/fig07_{stage}.png"))).unwrap().to_rgb8();
        assert_eq!(made.dimensions(), shown.dimensions(), "{stage}");
        // The same computation: every channel within 2 of 255 (rounding of f32 sums that a
        // different core count can reorder), and all but 0.1 % of pixels identical.
        let mut differing = 0;
        for (a, b) in made.pixels().zip(shown.pixels()) {
            let worst = a.0.iter().zip(b.0).map(|(x, y)| x.abs_diff(y)).max().unwrap();
            assert!(worst <= 2, "{stage}: a pixel differs by {worst}");
            differing += usize::from(worst > 0);
        }
        assert!(differing * 1000 <= made.pixels().len(), "{stage}: {differing} pixels differ");
    }
}
