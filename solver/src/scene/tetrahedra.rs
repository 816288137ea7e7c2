//! Figure 13: articulated tetrahedra, four balls and six struts each, fall on four static cube
//! frames and bend: every strut is a bending body whose bone splits where a fast hit lands
//! (dynamic articulation, plastic joints), and quiet tetrahedra are condensed into one rigid
//! cluster each.

use glam::{Quat, Vec3};

use super::kit::frames;
use super::kit::{GRAVITY, GROUND, Lcg, STEEL, ball, finish, world};
use super::{Scene, SceneSize};
use crate::coupling::{BendableDesc, Bending, CondenseSettings, DynamicArticulation, SkeletonSpec};
use crate::sim::{BodyDesc, BodyKind, ColliderKind, JointKind, SimError, SurfaceMaterial, World};
use dentbend::bend::JointRule;
use dentbend::bend::WeightParams;
use dentbend::mesh::{self, TriMesh};

/// Edge length of a tetrahedron (ball centre to ball centre), m.
pub const TETRA_EDGE: f32 = 0.6;
/// Ball radius, m.
const BALL_RADIUS: f32 = 0.07;
/// Strut radius, m.
const STRUT_RADIUS: f32 = 0.025;
/// Where a strut starts, from its ball's centre, m: inside the ball, and far enough out that
/// the three struts leaving a ball (60° apart) clear each other by 1 cm.
const STRUT_INSET: f32 = 0.06;
/// Side of a cube frame, m, and the thickness of its bars.
const FRAME_SIZE: f32 = 1.6;
const FRAME_BAR: f32 = 0.08;
/// Closing speed above which a hit splits a strut, m/s.
const SPLIT_SPEED: f32 = 3.0;
/// The plastic joints made in struts: a strut bends where a hit of a few metres per second
/// lands, not under its tetrahedron's weight.
const STRUT_JOINT: JointKind =
    JointKind::Bend(JointRule::Plastic { strength: 1.0, damping_constant: 1.0, damping_proportional: 6.0 });

/// Full: 400 tetrahedra (8 × 8 in each of 7 layers, the last one partly filled) over four
/// frames; demo: 16 (4 × 4 in one layer). Each tetrahedron has 10 bodies and 12 joints.
pub(super) fn tetrahedra(size: SceneSize) -> Result<Scene, SimError> {
    match size {
        SceneSize::Full => tetrahedra_grid(400, 8, size),
        SceneSize::Demo => tetrahedra_grid(16, 4, size),
    }
}

/// The `tetrahedra` scene with `count` tetrahedra in layers of `per_row` × `per_row`, 1 m
/// apart, the lowest 2.6 m up (`size` picks the number of frames). Smaller piles than the full
/// scene's for tests of what its higher layers do.
///
/// # Errors
/// [`SimError::Invalid`] when `count` or `per_row` is 0 or `count` exceeds 1,000.
pub fn tetrahedra_grid(count: usize, per_row: usize, size: SceneSize) -> Result<Scene, SimError> {
    if count == 0 || per_row == 0 || count > 1000 {
        return Err(SimError::Invalid {
            what: "tetrahedra grid".into(),
            value: format!("{count} tetrahedra, {per_row} per row"),
            reason: "needs 1..=1000 tetrahedra and at least 1 per row",
        });
    }
    let mut world = world(GRAVITY)?;
    let ground = mesh::subdivided_box(Vec3::new(12.0, 0.2, 12.0), [1, 1, 1])?;
    let desc = BodyDesc::new("ground", ground).kind(BodyKind::Static).at(Vec3::new(0.0, -0.1, 0.0));
    world.add(BodyDesc { color: GROUND, ..desc.collider(ColliderKind::Cuboid) })?;
    for (k, (x, z)) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)].into_iter().enumerate() {
        add_frame(&mut world, &format!("frame{k}"), Vec3::new(1.1 * x, FRAME_SIZE / 2.0, 1.1 * z))?;
    }
    let mut bending = Bending::new();
    let strut = mesh::cylinder(STRUT_RADIUS, TETRA_EDGE - 2.0 * STRUT_INSET, 8, 8)?;
    let ball_mesh = ball(BALL_RADIUS, 1)?;
    let mut random = Lcg(0x7E7A_4ED4);
    let spacing = 1.0;
    let corner = -0.5 * spacing * (per_row - 1) as f32;
    for t in 0..count {
        let (i, l, j) = (t % per_row, (t / per_row) % per_row, t / (per_row * per_row));
        let jitter = Vec3::new(random.symmetric(), random.symmetric(), random.symmetric()) * 0.05;
        let centre = Vec3::new(corner + spacing * i as f32, 2.6 + spacing * j as f32, corner + spacing * l as f32);
        let axis = Vec3::new(random.symmetric(), random.symmetric(), random.symmetric()).normalize_or(Vec3::Y);
        let turn = Quat::from_axis_angle(axis, std::f32::consts::PI * random.unit());
        let shade = 0.7 + 0.3 * random.unit();
        add_tetrahedron(&mut world, &mut bending, t, centre + jitter, turn, (&ball_mesh, &strut), shade)?;
    }
    bending.condense(CondenseSettings { wake_speed: SPLIT_SPEED, ..CondenseSettings::default() })?;
    let description = "Figure 13: articulated tetrahedra of four balls and six struts fall on four static cube \
                       frames; struts bend through plastic joints made where fast hits land, and quiet \
                       tetrahedra are simulated as one rigid cluster each.";
    let mut scene =
        finish("tetrahedra", world, Vec3::new(-0.6, -0.6, -1.0), |n| n != "ground", frames(size, 240, 90), description);
    scene.bending = bending;
    Ok(scene)
}

/// A static cube frame: its twelve edges as bars `name/bar<k>` around `centre`.
fn add_frame(world: &mut World, name: &str, centre: Vec3) -> Result<(), SimError> {
    let half = 0.5 * (FRAME_SIZE - FRAME_BAR);
    let mut k = 0;
    for axis in 0..3 {
        for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
            let mut size = Vec3::splat(FRAME_BAR);
            size[axis] = FRAME_SIZE;
            let mut offset = Vec3::ZERO;
            offset[(axis + 1) % 3] = a * half;
            offset[(axis + 2) % 3] = b * half;
            let bar = mesh::subdivided_box(size, [1, 1, 1])?;
            let desc = BodyDesc::new(format!("{name}/bar{k}"), bar).kind(BodyKind::Static).at(centre + offset);
            world.add(BodyDesc { color: STEEL, ..desc.collider(ColliderKind::Cuboid) })?;
            k += 1;
        }
    }
    Ok(())
}

/// Tetrahedron `t`: balls `tetra<t>/ball<k>` at the corners and bending struts
/// `tetra<t>/strut<k>` along the edges, each strut pinned to its two balls' centres by ball
/// joints: a truss, rigid until a strut bends (the balls and struts may still spin in place).
fn add_tetrahedron(
    world: &mut World,
    bending: &mut Bending,
    t: usize,
    centre: Vec3,
    turn: Quat,
    (ball_mesh, strut): (&TriMesh, &TriMesh),
    shade: f32,
) -> Result<(), SimError> {
    let r = TETRA_EDGE / (2.0 * std::f32::consts::SQRT_2);
    let corners =
        [Vec3::new(1.0, 1.0, 1.0), Vec3::new(1.0, -1.0, -1.0), Vec3::new(-1.0, 1.0, -1.0), Vec3::new(-1.0, -1.0, 1.0)]
            .map(|c| centre + turn * (c * r));
    let surface = SurfaceMaterial { restitution: 0.1, friction: 0.5 };
    let density = 1500.0;
    let mut balls = [0; 4];
    for (k, &corner) in corners.iter().enumerate() {
        let desc =
            BodyDesc::new(format!("tetra{t:03}/ball{k}"), ball_mesh.clone()).at(corner).collider(ColliderKind::Ball);
        let color = [0.85 * shade, 0.4 * shade, 0.15 * shade];
        balls[k] = world.add(BodyDesc { density, surface, color, ..desc })?;
    }
    let edges = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)];
    let mut struts = [0; 6];
    for (k, &(a, b)) in edges.iter().enumerate() {
        let direction = (corners[b] - corners[a]).normalize();
        let mut desc = BendableDesc::new(format!("tetra{t:03}/strut{k}"), strut.clone());
        desc.position = 0.5 * (corners[a] + corners[b]);
        desc.orientation = Quat::from_rotation_arc(Vec3::Y, direction);
        desc.density = density;
        desc.surface = surface;
        desc.collider = ColliderKind::Capsule;
        desc.color = [0.2 * shade, 0.45 * shade, 0.85 * shade];
        desc.skeleton = SkeletonSpec::Auto { bones: 1 };
        desc.weights = WeightParams { resolution: 32, ..WeightParams::default() };
        desc.dynamic =
            Some(DynamicArticulation { max_joints: 1, ..DynamicArticulation::new(SPLIT_SPEED, STRUT_JOINT, 0.1) });
        let index = bending.add(world, desc)?;
        let body = bending.bodies()[index].body_indices()[0];
        struts[k] = body;
        world.add_joint(balls[a], body, corners[a], JointKind::Ball)?;
        world.add_joint(balls[b], body, corners[b], JointKind::Ball)?;
    }
    // Struts meeting at a ball pass 1 cm apart there: too close for the contact margin, never
    // touching unless bent double.
    for (k, &(a, b)) in edges.iter().enumerate() {
        for (l, &(c, d)) in edges.iter().enumerate().skip(k + 1) {
            if a == c || a == d || b == c || b == d {
                world.ignore_collisions(struts[k], struts[l])?;
            }
        }
    }
    Ok(())
}
