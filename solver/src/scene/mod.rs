//! Scenes: a [`World`](crate::sim::World) with its bodies, a camera and a frame count, read from
//! a TOML scene file ([`load_scene`], [`parse_scene`]) or built in ([`builtin_scene`], one per
//! paper figure: [`BUILTIN_SCENES`]). [`load`] takes either.
//!
//! # Scene files
//!
//! Units are metres, seconds and kilograms, y is up. Every table refuses unknown fields, and
//! every error names the file, the line and column, the body and the field:
//!
//! ```text
//! scenes/drop.toml:14:12: body "ball": velocity: [NaN, 0.0, 0.0] must be finite (no nan or inf)
//! ```
//!
//! Top level: `name` (default: the file's stem), `description`, `frames` (default number of
//! frames to run, one world step each; default 120).
//!
//! `[world]`: any field of [`WorldSettings`](crate::sim::WorldSettings) (`gravity` as
//! `[x, y, z]` m/s², `dt` s, `collision_iterations`, `contact_iterations`,
//! `restitution_threshold` m/s, `slop` m, `baumgarte`, `margin` m, `shock_propagation`,
//! `sleep_speed` m/s, `sleep_time` s, `angular_damping` 1/s, `rolling_resistance`, `max_turn` rad
//! per step, `joint_correction_speed` m/s, `joint_correction_spin` rad/s); the others keep their
//! defaults.
//!
//! `[camera]` (optional; without it the camera frames every body from the front, a little
//! above): `eye` and `target` `[x, y, z]` m, `up` (default `[0, 1, 0]`), `fov_deg` (vertical,
//! degrees, default 30).
//!
//! `[[body]]`, one per body:
//!
//! | field              | meaning                                                                | default     |
//! |--------------------|------------------------------------------------------------------------|-------------|
//! | `name`             | unique name                                                            | required    |
//! | `mesh`             | built-in mesh name ([`mesh::BUILTIN_NAMES`](dentbend::mesh::BUILTIN_NAMES)) or `.obj`/`.ply` path relative to the scene file | required |
//! | `scale`            | number or `[x, y, z]`, > 0, applied to the mesh first                  | 1           |
//! | `kind`             | `"static"`, `"dynamic"` or `"kinematic"`                               | `"dynamic"` |
//! | `position`         | where the mesh's origin goes, `[x, y, z]` m                            | origin      |
//! | `rotation`         | axis-angle `[x, y, z]`: the axis, with length = the angle in degrees   | none        |
//! | `velocity`         | `[x, y, z]` m/s                                                        | rest        |
//! | `angular_velocity` | `[x, y, z]` rad/s, world axes                                          | rest        |
//! | `density`          | kg/m³ (dynamic bodies)                                                 | 1000        |
//! | `mass`             | kg, instead of `density`: density = mass / the scaled mesh's volume    |             |
//! | `collider`         | `"auto"`, `"ball"`, `"cuboid"`, `"capsule"`, `"convex-hull"`, `"tri-mesh"`| `"auto"`    |
//! | `restitution`      | in [0, 1]                                                              | 0.3         |
//! | `friction`         | ≥ 0                                                                    | 0.5         |
//! | `color`            | linear RGB `[r, g, b]`                                                 | grey        |
//!
//! `[body.dent]` (optional; present = the body dents), the material (d = `gain`·(v_n −
//! `threshold`), at most `cap`) and the dent's shape
//! ([`DentParams`](dentbend::dent::DentParams)):
//!
//! | field               | meaning                                                               | default      |
//! |---------------------|-----------------------------------------------------------------------|--------------|
//! | `threshold`         | normal impact speed below which nothing dents, m/s                    | 1            |
//! | `gain`              | dent distance per m/s above the threshold, m/(m/s)                    | 0.04         |
//! | `cap`               | largest dent distance, m                                              | 0.3          |
//! | `hardness`          | energy model instead of gain: plastic work per swept volume, Pa       | none         |
//! | `move_projectile`   | move the projectile into its dent                                     | false        |
//! | `progressive`       | repeated hits of one contact deepen one dent                          | false        |
//! | `sigma`             | Gaussian width, m                                                     | d / 2        |
//! | `resolution`        | dent grid cells per side, or `"auto"` (25..=400 from edge lengths)    | `"auto"`     |
//! | `heat_iters`        | plain smoothing steps k₁                                              | 8            |
//! | `clamp_iters`       | clamped smoothing steps k₂                                            | 16           |
//! | `heat_rate`         | α of a smoothing step, in (0, ¼]                                      | 0.2          |
//! | `attenuation`       | falloff with depth: `"logistic"`, `"linear"` or `"none"`              | `"logistic"` |
//! | `attenuation_scale` | with `"linear"`: depth where the dent has faded, in dent distances    | 1            |
//! | `min_cos`           | lower clamp of cos θ for glancing hits, in [0.01, 1]                  | 0.1          |
//! | `widen`             | widening t of glancing dents, 1/m                                     | 0            |
//! | `material`          | `"solid"` (dents push material into a rim) or `"sheet"` (dents thin it) | none        |
//! | `preserve_volume`   | raise a rim that keeps the volume; default true for `"solid"`         | false        |
//!
//! `[body.fracture]` (optional; present = the body breaks, paper Figure 3: when one hit removes
//! more than `toughness` of kinetic energy along the normal, or its dents add up to more than
//! `dent_limit`, it breaks along a pattern of Voronoi cells, finer near the hit, placed at the
//! hit and aligned with its normal: each cell within `radius` becomes a dynamic piece, the rest
//! stays the body; see [`dentbend::fracture`]). Give `toughness`, `dent_limit` or both:
//!
//! | field        | meaning                                                                  | default       |
//! |--------------|--------------------------------------------------------------------------|---------------|
//! | `radius`     | radius of the broken region about the hit, m                             | required      |
//! | `cells`      | Voronoi cells of the pattern, 1..=256                                    | 32            |
//! | `seed`       | seed of the pattern (the same seed, the same pattern)                    | 0             |
//! | `toughness`  | impact energy that breaks the body, J                                    | none          |
//! | `dent_limit` | accumulated dent distance that breaks it, m                              | none          |
//! | `density`    | density of the pieces of a static or kinematic body, kg/m³               | the body's    |
//!
//! `[body.bend]` (optional; present = the body bends, paper §4: it is simulated as one rigid
//! sub-body per bone, `<name>/bone<k>`, joined at the skeleton's joints, and drawn as its rest
//! mesh skinned to them). A bending body is dynamic, with the automatic collider and a
//! `density` (no `mass`, no `[body.dent]`); its pose, velocities and material apply to all of it.
//!
//! | field                | meaning                                                                  | default  |
//! |----------------------|--------------------------------------------------------------------------|----------|
//! | `skeleton`           | `"auto"` (a chain along the principal axis) or an array of bone tables   | `"auto"` |
//! | `bones`              | with `"auto"`: number of bones, 1..=256                                  | 1        |
//! | `[[body.bend.bone]]` | one bone each: `head`, `tail` `[x, y, z]` m in the mesh's frame after `scale`; `parent` = index of another bone (0-based, in file order), left out for the one root; `joint` = a joint table for the joint at this bone's head, if not `joint`'s kind (not on the root) | |
//! | `resolution`         | level-set cells along the longest side, 8..=256                          | 64       |
//! | `influences`         | bones per vertex, 1..=8                                                  | 4        |
//! | `falloff`            | exponent p of the weights w ∝ d⁻ᵖ, in (0, 16]                            | 4        |
//! | `joint`              | the joints at the skeleton's joints, a joint table (below)               | rigid    |
//!
//! A joint table has `kind = "rigid" | "ball" | "plastic" | "elastic" | "elastic-prismatic"` and
//! exactly the numbers of its kind ([`JointKind`](crate::sim::JointKind)), all required: plastic
//! `strength` N·m·s, `damping_constant` rad/s², `damping_proportional` 1/s; elastic `stiffness`
//! N·m/rad, `damping` N·m·s/rad; elastic-prismatic `axis` `[x, y, z]`, `stiffness` N/m,
//! `damping` N·s/m.
//!
//! `[body.bend.dynamic]` (optional; dynamic articulation, paper §4.2): a hit closing faster than
//! `speed_threshold` m/s splits the bone it lands on there and joins the halves with a joint of
//! the joint table `joint`, leaving no bone shorter than `min_bone_length` m, at most
//! `max_joints` times (default 16). `scenes/bent_bar.toml` is an example.
//!
//! A full example (also `scenes/example.toml`):
//!
//! ```toml
//! name = "example"
//! description = "A ball and a bunny dent a block; the bunny is dropped ears first."
//! frames = 120
//!
//! [world]
//! gravity = [0.0, -9.81, 0.0]
//! dt = 0.016666668
//!
//! [camera]
//! eye = [0.0, 4.5, 9.0]
//! target = [0.0, 0.5, 0.0]
//! fov_deg = 30.0
//!
//! [[body]]
//! name = "block"
//! mesh = "block"
//! kind = "static"
//! collider = "tri-mesh"
//! color = [0.62, 0.64, 0.68]
//!
//! [body.dent]
//! threshold = 1.0
//! gain = 0.04
//! cap = 0.3
//! sigma = 0.08
//! resolution = "auto"
//! attenuation = "logistic"
//! move_projectile = true
//!
//! [[body]]
//! name = "ball"
//! mesh = "sphere"
//! scale = 0.6
//! position = [-1.0, 2.5, 0.0]
//! velocity = [0.0, -4.0, 0.0]
//! mass = 500.0
//! collider = "ball"
//! restitution = 0.2
//!
//! [[body]]
//! name = "bunny"
//! mesh = "bunny"
//! scale = 0.15
//! position = [1.0, 3.2, 0.0]
//! rotation = [180.0, 0.0, 0.0]
//! angular_velocity = [0.0, 1.0, 0.0]
//! density = 800.0
//! ```
//!
//! Loading a scene reads the scene file and the mesh files it names and writes nothing.

mod arm;
mod arm_shape;
mod bending_scenes;
mod builtin;
mod bunny_bones;
mod camera;
mod error;
mod figures;
mod file;
mod file_bend;
mod file_fracture;
mod file_values;
mod kit;
mod options;
mod parse;
mod parse_bend;
mod parse_body;
mod rain;
mod source;
mod tetrahedra;
mod types;
mod wall;

pub use arm::ARM_BONES;
pub use bending_scenes::{PLANK_DENT, PLANK_HIT, PLANK_SIZE};
pub use builtin::{BUILTIN_SCENES, builtin_scene, load, load_sized, load_with};
pub use bunny_bones::{BUNNY_FALLOFF, BUNNY_SCALE};
pub use camera::Camera;
pub use error::SceneError;
pub use file_fracture::DEFAULT_FRACTURE_CELLS;
pub use options::{LoadOptions, MeshPaths};
pub(crate) use parse::load_scene_with;
pub use parse::{load_scene, parse_scene, parse_scene_with_meshes};
pub use parse_body::MeshResolver;
pub use tetrahedra::tetrahedra_grid;
#[cfg(feature = "render")]
pub(crate) use types::fit_camera;
pub(crate) use types::{DEFAULT_FRAMES, framing_camera};
pub use types::{Scene, SceneSize};
pub use wall::{WALL_DENT_LIMIT, WALL_SIZE};
