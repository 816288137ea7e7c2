//! The smallest dent: a ball hits a block at 3 m/s and leaves a 0.2 m dent. Saves the block as
//! `minimal_dent.obj` in the system's temporary directory.

use dentbend::glam::{Affine3A, Vec3};
use dentbend::{DentParams, Impact, dent, mesh};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut block = mesh::builtin("block")?; // 4 × 1 × 4 m, top face at y = 0.5
    let mut ball = mesh::builtin("sphere")?; // unit ball
    ball.transform(Affine3A::from_translation(Vec3::new(0.0, 1.5, 0.0)))?;
    // Denting normal into the block; the ball's velocity relative to the block.
    let impact = Impact { point: Vec3::new(0.0, 0.5, 0.0), normal: -Vec3::Y, relative_velocity: -3.0 * Vec3::Y };
    let report = dent(&mut block, &ball, &impact, &DentParams::new(0.2))?;
    let out = std::env::temp_dir().join("minimal_dent.obj");
    mesh::save(&out, &block)?;
    println!(
        "{} vertices moved, {:.3} m deep; saved {}",
        report.moved_vertices,
        report.max_displacement,
        out.display()
    );
    Ok(())
}
