//! Bending in Bevy: a heavy ball lands on a plank lying across two supports; the plank's
//! plastic joints yield and it stays bent; on the GPU path its mesh in Bevy's vertex slab is the
//! rest mesh skinned by the bones' poses (dentbend's `skin` kernel, no read-back), equal to the
//! CPU twin within the skinning tolerance, and the CPU path bends the same way.

use crate::common;
use libtest_mimic::Trial;

use bevy::prelude::*;
use bevy_dentbend::demo::headless_app;
use bevy_dentbend::dentbend::bend::auto_skeleton;
use bevy_dentbend::dentbend::cpu::{SkinBone, SkinInfluence, SkinParams, skin};
use bevy_dentbend::dentbend::dent::DentSettings;
use bevy_dentbend::dentbend::glam::Vec3 as DVec3;
use bevy_dentbend::dentbend::mesh;
use bevy_dentbend::{BendSettings, Bendable, Bends, DentPath, DentProjectile, DentStats, bevy_mesh, slab_layout};
use bevy_rapier3d::prelude::*;

/// Plastic joints of strength 40 N·m·s over a 700 kg/m³ plank (dentbend-rapier's Figure 14).
fn plastic() -> BendSettings {
    BendSettings::plastic(700.0, 40.0)
}

/// dentbend-rapier's Figure 14 scene in Bevy: a plank 4 × 0.1 × 0.3 m of two bones across
/// supports 3.8 m apart, the ground 0.6 m below, a 60 kg ball (radius 0.2 m) falling at 6 m/s
/// onto it 0.3 m off the middle.
fn plank_scene(gpu: bool) -> (common::Scene, Entity) {
    plank_scene_with(gpu, false, false)
}

/// [`plank_scene`], the plank dentable (2 m/s threshold, 5 mm per m/s, at most 2 cm) and the
/// ball a projectile with a mesh when `dents`; with `split`, the plank is one bone that a hit
/// of 2 m/s or more splits where it lands.
fn plank_scene_with(gpu: bool, dents: bool, split: bool) -> (common::Scene, Entity) {
    let mut app = headless_app(gpu);
    let probe = common::slab::SlabProbe::install(&mut app);
    app.finish();
    app.cleanup();
    // Bodies join the Rapier context its start-up made.
    app.update();
    let plank = mesh::plank(4.0, 0.3, 0.1, 64).expect("a plank");
    let skeleton = auto_skeleton(&plank, if split { 1 } else { 2 }).expect("a skeleton");
    let world = app.world_mut();
    // dentbend-rapier's Figure 14 scene: supports 3.8 m apart, the ground 0.6 m below.
    for x in [-1.9, 1.9] {
        world.spawn((Transform::from_xyz(x, -0.3, 0.0), RigidBody::Fixed, Collider::cuboid(0.2, 0.3, 0.3)));
    }
    world.spawn((Transform::from_xyz(0.0, -0.7, 0.0), RigidBody::Fixed, Collider::cuboid(4.0, 0.1, 1.5)));
    let asset = world.resource_mut::<Assets<Mesh>>().add(bevy_mesh(&plank));
    let mut settings = plastic();
    if split {
        settings.split_speed = Some(2.0);
    }
    let mut bendable = Bendable::new(skeleton, settings);
    if dents {
        bendable = bendable.dentable(DentSettings::new(2.0, 0.005, 0.02));
    }
    let body = world.spawn((Mesh3d(asset), Transform::from_xyz(0.0, 0.052, 0.0), bendable)).id();
    let ball = world
        .spawn((
            RigidBody::Dynamic,
            Collider::ball(0.2),
            ColliderMassProperties::Mass(60.0),
            Velocity::linear(Vec3::new(0.0, -6.0, 0.0)),
            Transform::from_xyz(0.3, 0.7, 0.0),
        ))
        .id();
    if dents {
        let sphere = world.resource_mut::<Assets<Mesh>>().add(Sphere::new(0.2).mesh().ico(3).expect("a sphere"));
        world.entity_mut(ball).insert((Mesh3d(sphere), DentProjectile));
    }
    let scene = common::Scene {
        app,
        target: body,
        ball: Entity::PLACEHOLDER,
        camera: Entity::PLACEHOLDER,
        probe,
        target_mesh: plank,
    };
    (scene, body)
}

fn angles(s: &common::Scene, body: Entity) -> Vec<f32> {
    s.app.world().resource::<Bends>().bend_angles(body).expect("a bendable")
}

/// Per vertex and coordinate, the magnitude of the skinning's terms: Σ |wᵢ·Sᵢ| · (|p|, 1).
fn term_magnitude(bones: &[SkinBone], influence: &SkinInfluence, p: DVec3) -> [f32; 3] {
    let mut out = [0.0f32; 3];
    for (&b, &w) in influence.bones.iter().zip(&influence.weights) {
        for (r, row) in bones[b as usize].rows.iter().enumerate() {
            out[r] += w.abs()
                * (row[0].abs() * p.x.abs() + row[1].abs() * p.y.abs() + row[2].abs() * p.z.abs() + row[3].abs());
        }
    }
    out
}

/// The plank bends plastically where the ball lands (the joint yields by more than 3°; the
/// Rapier adapter's scene ends at 39°) and stays bent (two seconds later within 0.5°); Bevy's
/// slab holds
/// the rest mesh skinned by the bones the plug-in sent, within 16 ε of each coordinate's term
/// magnitude (the skin kernel's stated agreement with its CPU twin, tests/parity_skin.rs in the
/// core crate), and the slab moved from rest by more than 2 cm somewhere.
fn the_plank_bends_and_the_slab_is_skinned() {
    let (mut s, body) = plank_scene(true);
    s.until("the plank registered", 100, |w| w.resource::<Bends>().skinning_path(body) == Some(DentPath::Gpu));
    s.frames(120);
    let bent = angles(&s, body);
    let most = bent.iter().fold(0.0f32, |m, a| m.max(a.abs()));
    assert!(most > 3f32.to_radians(), "no joint yielded: {bent:?} rad");
    s.frames(120);
    let later = angles(&s, body);
    for (a, b) in bent.iter().zip(&later) {
        assert!((a - b).abs() < 0.5f32.to_radians(), "the plank did not stay bent: {bent:?} → {later:?}");
    }

    let handle = s.app.world().get::<Mesh3d>(body).expect("a mesh").0.clone();
    let layout = slab_layout(s.app.world().resource::<Assets<Mesh>>().get(&handle).unwrap()).unwrap();
    // The render world skins with the bones sent a frame or two before the slab is read (the
    // ball still rolls in the V): the slab must be the skin of one of the recent bone sets.
    let mut recent: Vec<Vec<SkinBone>> = Vec::new();
    s.probe.request(handle.id(), layout.stride);
    for _ in 0..3 {
        recent.push(s.app.world().resource::<Bends>().skinned_with(body).unwrap().to_vec());
        s.frames(1);
    }
    let bytes = s.probe.take().expect("the slab was read");
    let bends = s.app.world().resource::<Bends>();
    let (rest, influences) = bends.rest(body).unwrap();
    let n = rest.vertex_count();
    let stride = layout.stride as usize;
    let f = |v: usize, at: usize| f32::from_le_bytes(bytes[v * stride + at..v * stride + at + 4].try_into().unwrap());
    let slab: Vec<DVec3> = (0..n).map(|v| DVec3::new(f(v, 0), f(v, 4), f(v, 8))).collect();
    let matches = |bones: &[SkinBone]| -> Result<(), String> {
        let (mut positions, mut normals) = (vec![DVec3::ZERO; n], vec![DVec3::ZERO; n]);
        let params = SkinParams::new(n as u32, bones.len() as u32);
        skin(&params, bones, rest.positions(), rest.normals(), influences, &mut positions, &mut normals)
            .map_err(|e| e.to_string())?;
        for v in 0..n {
            let tol =
                term_magnitude(bones, &influences[v], rest.positions()[v]).map(|m| 16.0 * f32::EPSILON * m.max(1e-3));
            for k in 0..3 {
                let e = (slab[v][k] - positions[v][k]).abs();
                if e > tol[k] {
                    return Err(format!(
                        "vertex {v}: slab {} vs CPU skin {} ({e} > {})",
                        slab[v], positions[v], tol[k]
                    ));
                }
            }
        }
        Ok(())
    };
    let verdicts: Vec<Result<(), String>> = recent.iter().map(|b| matches(b)).collect();
    assert!(verdicts.iter().any(Result::is_ok), "the slab is the skin of no recent bone set: {verdicts:?}");
    let moved = (0..n).map(|v| slab[v].distance(rest.positions()[v])).fold(0.0f32, f32::max);
    assert!(moved > 0.02, "the slab's plank moved only {moved} m from rest");
}

/// The CPU path bends the same plank the same way: the physics does not depend on where the
/// mesh is skinned, so every joint ends within 1e-4 rad of the GPU path's (Rapier is
/// deterministic for the same inputs; the margin covers nothing but rounding); and on the CPU
/// path the mesh asset is the rest mesh skinned by the bones last sent (the same function, so
/// exactly), bent away from rest.
fn the_cpu_path_bends_the_same() {
    let run = |gpu: bool| {
        let (mut s, body) = plank_scene(gpu);
        let path = if gpu { DentPath::Gpu } else { DentPath::Cpu };
        s.until("the plank registered", 100, |w| w.resource::<Bends>().skinning_path(body) == Some(path));
        s.frames(150);
        if !gpu {
            let bends = s.app.world().resource::<Bends>();
            let (rest, influences) = bends.rest(body).unwrap();
            let bones = bends.skinned_with(body).unwrap();
            let n = rest.vertex_count();
            let (mut positions, mut normals) = (vec![DVec3::ZERO; n], vec![DVec3::ZERO; n]);
            let params = SkinParams::new(n as u32, bones.len() as u32);
            skin(&params, bones, rest.positions(), rest.normals(), influences, &mut positions, &mut normals).unwrap();
            assert_eq!(s.target_asset_positions(), positions, "the CPU path's asset is not the skinned mesh");
            assert_ne!(positions, rest.positions(), "the CPU path's plank did not bend");
        }
        angles(&s, body)
    };
    let (gpu, cpu) = (run(true), run(false));
    for (g, c) in gpu.iter().zip(&cpu) {
        assert!((g - c).abs() < 1e-4, "GPU path {gpu:?} vs CPU path {cpu:?}");
    }
}

/// A dentable plank keeps the ball's dent while it bends, on both paths: the dent lands in its
/// rest mesh (the same vertices and faces; at most the 2 cm cap deep, at least 2 mm), it is
/// counted as a bendable dent, and the mesh drawn is the new rest mesh skinned (on the CPU
/// path, the asset exactly).
fn a_dentable_plank_keeps_its_dent() {
    for gpu in [true, false] {
        let (mut s, body) = plank_scene_with(gpu, true, false);
        let path = if gpu { DentPath::Gpu } else { DentPath::Cpu };
        s.until("the plank registered", 100, |w| w.resource::<Bends>().skinning_path(body) == Some(path));
        let original = s.app.world().resource::<Bends>().rest(body).unwrap().0.clone();
        s.frames(60);
        let stats = s.app.world().resource::<DentStats>().clone();
        assert!(stats.bendable_dents >= 1, "{stats:?}");
        let bends = s.app.world().resource::<Bends>();
        let (rest, influences) = bends.rest(body).unwrap();
        assert_eq!((rest.vertex_count(), rest.faces()), (original.vertex_count(), original.faces()));
        let deepest =
            rest.positions().iter().zip(original.positions()).map(|(a, b)| a.distance(*b)).fold(0.0, f32::max);
        assert!((0.002..=0.0201).contains(&deepest), "gpu {gpu}: the rest mesh's dent is {deepest} m");
        if !gpu {
            let bones = bends.skinned_with(body).unwrap();
            let n = rest.vertex_count();
            let (mut positions, mut normals) = (vec![DVec3::ZERO; n], vec![DVec3::ZERO; n]);
            let params = SkinParams::new(n as u32, bones.len() as u32);
            skin(&params, bones, rest.positions(), rest.normals(), influences, &mut positions, &mut normals).unwrap();
            assert_eq!(s.target_asset_positions(), positions, "the asset is not the dented rest mesh skinned");
        }
    }
}

/// A one-bone plank with dynamic articulation: the ball's hit (about 6 m/s) splits its bone
/// where it lands, on both paths: two bone entities, one joint near the hit, and the plank
/// bends there by more than 3° (the plastic joint yields, as with the two-bone plank).
fn a_fast_hit_splits_the_bone_it_lands_on() {
    for gpu in [true, false] {
        let (mut s, body) = plank_scene_with(gpu, false, true);
        let path = if gpu { DentPath::Gpu } else { DentPath::Cpu };
        s.until("the plank registered", 100, |w| w.resource::<Bends>().skinning_path(body) == Some(path));
        assert_eq!(s.app.world().resource::<Bends>().pieces(body).map(<[Entity]>::len), Some(1));
        s.frames(120);
        assert_eq!(s.app.world().resource::<DentStats>().splits, 1, "gpu {gpu}");
        let bends = s.app.world().resource::<Bends>();
        assert_eq!(bends.pieces(body).map(<[Entity]>::len), Some(2), "gpu {gpu}");
        let bent = angles(&s, body);
        assert_eq!(bent.len(), 1, "one joint");
        assert!(bent[0].abs() > 3f32.to_radians(), "gpu {gpu}: the new joint bent {} rad", bent[0]);
    }
}

pub fn tests() -> Vec<Trial> {
    common::gpu_trials(
        module_path!(),
        vec![
            ("a_fast_hit_splits_the_bone_it_lands_on", a_fast_hit_splits_the_bone_it_lands_on),
            ("a_dentable_plank_keeps_its_dent", a_dentable_plank_keeps_its_dent),
            ("the_plank_bends_and_the_slab_is_skinned", the_plank_bends_and_the_slab_is_skinned),
            ("the_cpu_path_bends_the_same", the_cpu_path_bends_the_same),
        ],
    )
}
