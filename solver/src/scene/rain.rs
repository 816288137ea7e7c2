//! Figure 10: a rain of dentable spheres on dentable targets. Full: 1,500 small spheres, 4
//! medium and 3 large on a dense bunny (58,784 triangles), a block, a cylinder and a box; demo:
//! 150 small, 2 medium and 1 large on a bunny (3,674 triangles) and a slab.

use glam::Vec3;

use super::figures::target;
use super::kit::frames;
use super::kit::{BLUE, GROUND, Lcg, ORANGE, SAND, STEEL, ball, dentable, finish, scaled};
use super::{Scene, SceneSize};
use crate::sim::{BodyDesc, BodyKind, ColliderKind, DentSettings, SimError};
use dentbend::mesh;

/// Radius of the small spheres, m.
const SMALL_RADIUS: f32 = 0.15;
/// Speed every sphere starts with, downwards, m/s.
const START_SPEED: f32 = 3.0;

/// How the cloud of small spheres is laid out before jitter.
struct Cloud {
    /// Spheres along x, y and z.
    cells: [u32; 3],
    /// Distance between neighbours, m.
    spacing: f32,
    /// x and z of the grid's centre and y of its lowest layer, m.
    centre: Vec3,
}

pub(super) fn rain(size: SceneSize) -> Result<Scene, SimError> {
    let mut world = super::kit::world(super::kit::GRAVITY)?;
    // Targets: 0.006 m per m/s above 2 m/s, at most 0.08 m; small spheres land at 10–14 m/s.
    let target_dent = dentable(2.0, 0.006, 0.08, None);
    let (ground_size, cloud, medium, large) = match size {
        SceneSize::Full => {
            let bunny = scaled("bunny-dense", Vec3::splat(0.35))?;
            world.add(target("bunny", bunny, Vec3::ZERO, SAND).dentable(target_dent.clone()))?;
            let block = scaled("block", Vec3::splat(0.75))?;
            world.add(target("block", block, Vec3::new(4.5, 0.375, 0.0), STEEL).dentable(target_dent.clone()))?;
            let cylinder = mesh::subdivide_midpoint(&scaled("cylinder", Vec3::splat(1.5))?);
            world.add(target("cylinder", cylinder, Vec3::new(-4.5, 1.5, 0.0), STEEL).dentable(target_dent.clone()))?;
            let cube = scaled("box", Vec3::splat(0.8))?;
            world.add(target("box", cube, Vec3::new(0.0, 0.8, -3.2), STEEL).dentable(target_dent))?;
            let cloud = Cloud { cells: [20, 5, 15], spacing: 0.6, centre: Vec3::new(0.0, 8.0, 0.0) };
            let medium = vec![
                Vec3::new(-2.2, 6.0, -2.2),
                Vec3::new(2.2, 6.0, -2.2),
                Vec3::new(-2.2, 6.0, 2.2),
                Vec3::new(2.2, 6.0, 2.2),
            ];
            let large = vec![Vec3::new(-4.5, 6.0, 0.0), Vec3::new(0.0, 6.5, 0.0), Vec3::new(4.5, 6.0, 0.0)];
            (Vec3::new(24.0, 1.0, 20.0), cloud, medium, large)
        }
        SceneSize::Demo => {
            let bunny = scaled("bunny", Vec3::splat(0.35))?;
            world.add(target("bunny", bunny, Vec3::ZERO, SAND).dentable(target_dent.clone()))?;
            let slab = scaled("box", Vec3::new(1.5, 0.4, 1.5))?;
            world.add(target("slab", slab, Vec3::new(3.5, 0.4, 0.0), STEEL).dentable(target_dent))?;
            let cloud = Cloud { cells: [10, 3, 5], spacing: 0.65, centre: Vec3::new(1.5, 6.0, 0.0) };
            let medium = vec![Vec3::new(-0.9, 4.5, 0.9), Vec3::new(0.9, 4.5, -0.9)];
            let large = vec![Vec3::new(3.5, 4.5, 0.0)];
            (Vec3::new(18.0, 1.0, 12.0), cloud, medium, large)
        }
    };
    let ground = mesh::subdivided_box(ground_size, [1, 1, 1])?;
    let ground = BodyDesc::new("ground", ground).kind(BodyKind::Static).at(Vec3::new(0.0, -0.5, 0.0));
    world.add(BodyDesc { collider: ColliderKind::Cuboid, color: GROUND, ..ground })?;

    // The spheres dent too, a little: at most a quarter of their radius.
    let spheres = [
        ("medium", 0.35, 3, medium, dentable(3.0, 0.01, 0.08, None), BLUE),
        ("large", 0.7, 4, large, dentable(3.0, 0.015, 0.12, None), ORANGE),
    ];
    for (label, radius, subdivisions, centres, dent, color) in spheres {
        let mesh = ball(radius, subdivisions)?;
        for (k, centre) in centres.into_iter().enumerate() {
            world.add(sphere(format!("{label}-{}", k + 1), mesh.clone(), centre, dent.clone(), color))?;
        }
    }
    let small = ball(SMALL_RADIUS, 2)?;
    let small_dent = dentable(3.0, 0.004, 0.04, None);
    let mut random = Lcg(0x5EED_DE47);
    let [nx, ny, nz] = cloud.cells;
    // Jitter keeps neighbours apart: spacing − 2·radius > 2·jitter.
    let jitter = 0.4 * (cloud.spacing - 2.0 * SMALL_RADIUS);
    let corner = cloud.centre - 0.5 * cloud.spacing * Vec3::new((nx - 1) as f32, 0.0, (nz - 1) as f32);
    for (k, (i, j, l)) in (0..ny).flat_map(|j| (0..nz).flat_map(move |l| (0..nx).map(move |i| (i, j, l)))).enumerate() {
        let offset = Vec3::new(random.symmetric(), random.symmetric(), random.symmetric()) * jitter;
        let centre = corner + cloud.spacing * Vec3::new(i as f32, j as f32, l as f32) + offset;
        let shade = 0.75 + 0.25 * random.unit();
        let color = [0.3 * shade, 0.55 * shade, 0.85 * shade];
        world.add(sphere(format!("drop-{k:04}"), small.clone(), centre, small_dent.clone(), color))?;
    }
    let frames = frames(size, 240, 120);
    let description = "Figure 10: a rain of dentable spheres (small, medium and large) dents a dense bunny and \
                       procedural targets on the ground; the spheres dent too.";
    Ok(finish("rain", world, Vec3::new(0.0, -0.5, -1.0), |name| name != "ground", frames, description))
}

/// A dynamic dentable sphere with a ball collider, falling at [`START_SPEED`].
fn sphere(name: String, mesh: mesh::TriMesh, centre: Vec3, dent: DentSettings, color: [f32; 3]) -> BodyDesc {
    let desc = BodyDesc::new(name, mesh)
        .at(centre)
        .velocity(Vec3::new(0.0, -START_SPEED, 0.0))
        .collider(ColliderKind::Ball)
        .dentable(dent);
    BodyDesc { color, ..desc }
}
