//! The built-in scene `wall` (paper Figure 3) with its wall made dynamic.

use dentbend::glam::Vec3;
use dentbend::mesh;
use dentbend_solver::scene::{SceneSize, builtin_scene};
use dentbend_solver::sim::{BodyDesc, BodyKind, ColliderKind, World};

/// The demo-sized scene `wall` with the wall dynamic (2,400 kg/m³, a convex-hull collider) and
/// its mesh 0.31 m, −0.17 m off its centre of mass, so that the body, its rest and its pieces
/// each sit in coordinates of their own; the same dent and fracture settings as the scene's.
pub fn moving_wall() -> World {
    let mut world = builtin_scene("wall", SceneSize::Demo).unwrap().world;
    let k = world.find("wall").unwrap();
    let old = world.bodies()[k].clone();
    let off = Vec3::new(0.31, -0.17, 0.0);
    let mut mesh = mesh::subdivided_box(Vec3::new(3.0, 2.0, 0.2), [30, 20, 2]).unwrap();
    mesh.transform(dentbend::glam::Affine3A::from_translation(off)).unwrap();
    let mut desc = BodyDesc::new("wall", mesh)
        .kind(BodyKind::Dynamic)
        .at(old.transform().transform_point3(Vec3::ZERO) - off)
        .collider(ColliderKind::ConvexHull);
    (desc.dent, desc.fracture, desc.density, desc.surface) =
        (old.dent.clone(), old.fracture.clone(), 2400.0, old.surface);
    world.rebuild_body(k, desc).unwrap();
    world
}
