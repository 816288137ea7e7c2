//! Fracture through the world-free damage API: a breakable body keyed by the caller's id breaks
//! from an impact's energy or from its accumulated dent, after its dents (the pieces keep them);
//! pieces are closed, carry mass properties, inherited velocities and deterministic ids; the
//! projectile carries on less the energy used; a bad breakable body is refused and changes
//! nothing.

mod common;

use common::closed::assert_closed;
use dentbend::damage::{CpuBackend, Damage, DamageError, DamagePlan, Hit, TargetSet};
use dentbend::dent::{BodyState, DentSettings, Impact, Surface};
use dentbend::fracture::{FractureCause, FractureError, FractureSettings, PatternParams, replay};
use dentbend::glam::{Affine3A, Mat3, Quat, Vec3};
use dentbend::mesh::{self, TriMesh};

const WALL: u64 = 1;
const BALL: u64 = 2;

/// A 3 × 2 × 0.2 m wall in the xy plane (front face at z = 0.1), 60 × 40 × 2 cells.
fn wall() -> TriMesh {
    mesh::subdivided_box(Vec3::new(3.0, 2.0, 0.2), [60, 40, 2]).unwrap()
}

fn pattern() -> PatternParams {
    PatternParams { cells: 12, seed: 7, radius: 0.6 }
}

/// The wall at `to_world`, denting 0.02 m per m/s over 1 m/s (cap 0.05 m), breaking at
/// `toughness` J or `dent_limit` m.
fn wall_set(to_world: Affine3A, toughness: Option<f32>, dent_limit: Option<f32>) -> TargetSet<u64> {
    let mut set = TargetSet::new();
    set.insert(WALL, wall(), to_world, DentSettings::new(1.0, 0.02, 0.05)).unwrap();
    set.set_fracture(WALL, Some(FractureSettings::new(pattern(), toughness, dent_limit).unwrap())).unwrap();
    set.insert_rigid(BALL);
    set
}

fn ball_mesh() -> TriMesh {
    mesh::icosphere(0.2, 3).unwrap()
}

/// A 5 kg ball (inverse inertia 1/(0.4·5·0.2²)) touching the wall at `point` (world), moving at
/// `velocity` along −`normal`; `wall` is the wall's state.
fn hit<'a>(ball: &'a TriMesh, wall: BodyState, point: Vec3, normal: Vec3, speed: f32) -> Hit<'a, u64> {
    let centre = point - normal * 0.2;
    let inverse_inertia = Mat3::IDENTITY / (0.4 * 5.0 * 0.04);
    let ball_state = BodyState::moving(centre, normal * speed, Vec3::ZERO, 5.0, inverse_inertia);
    Hit {
        target: WALL,
        projectile: BALL,
        impact: Impact::from_contact(point, normal, &wall, &ball_state).unwrap(),
        target_state: wall,
        projectile_state: ball_state,
        projectile_surface: Surface { mesh: ball, to_world: Affine3A::from_translation(centre) },
    }
}

/// A head-on hit in the middle of the front face of the wall placed at `to_world`.
fn front_hit(ball: &TriMesh, wall: BodyState, to_world: Affine3A, speed: f32) -> Hit<'_, u64> {
    let point = to_world.transform_point3(Vec3::new(0.0, 0.0, 0.1));
    let normal = to_world.transform_vector3(-Vec3::Z);
    hit(ball, wall, point, normal, speed)
}

fn volume(mesh: &TriMesh) -> f64 {
    f64::from(mesh.volume().abs())
}

fn plan(set: &TargetSet<u64>, damage: &mut Damage<u64>, hits: &[Hit<'_, u64>], step: u64) -> DamagePlan<u64> {
    damage.plan(set, hits, step, &mut CpuBackend).unwrap()
}

/// A 12 m/s ball (360 J) on a fixed wall of toughness 100 J: the wall dents, then breaks
/// where it was hit. Pieces and rest are closed, their volumes add up to the dented wall's
/// (to 1e-4 relative: the cuts are exact in f64, only the f32 output rounds), pieces are at
/// the settings' density and still (a fixed wall's material does not move), ids count from 0,
/// and the ball carries on with (360 − 100)/360 of its energy.
#[test]
fn an_energetic_hit_dents_then_breaks_a_fixed_wall_into_closed_pieces() {
    let to_world = Affine3A::from_rotation_translation(Quat::from_rotation_y(0.4), Vec3::new(1.0, 2.0, -3.0));
    let mut set = wall_set(to_world, Some(100.0), None);
    let ball = ball_mesh();
    let mut damage = Damage::new();
    let hits = [front_hit(&ball, BodyState::FIXED, to_world, 12.0)];
    let plan = plan(&set, &mut damage, &hits, 1);
    assert_eq!(plan.dents.len(), 1, "the hit dents first");
    assert_eq!(plan.fractures.len(), 1);
    let f = &plan.fractures[0];
    assert_eq!((f.body, f.projectile, f.cause), (WALL, BALL, FractureCause::Energy));
    assert!((f.energy - 360.0).abs() < 1.0, "energy {} J (½·5·12²)", f.energy);
    assert_eq!(&f.broken_mesh, &plan.targets[0].mesh, "it breaks its dented mesh");
    assert!(f.pieces.len() >= 4, "{} pieces", f.pieces.len());
    let rest = f.rest.as_ref().expect("a 3 m wall outlives a 0.6 m pattern");
    assert_closed(rest, "rest");
    let mut total = volume(rest);
    for (k, piece) in f.pieces.iter().enumerate() {
        assert_closed(&piece.mesh, "piece");
        assert_eq!((piece.id.fracture, piece.id.index), (0, k as u32));
        assert!((f64::from(piece.mass.mass) - 1000.0 * volume(&piece.mesh)).abs() < 1e-3 * f64::from(piece.mass.mass));
        assert_eq!((piece.linear_velocity, piece.angular_velocity), (Vec3::ZERO, Vec3::ZERO));
        total += volume(&piece.mesh);
    }
    let before = volume(&f.broken_mesh);
    assert!((total - before).abs() < 1e-4 * before, "volume {total} against {before}");
    // Pieces are near the hit, in mesh coordinates.
    for piece in &f.pieces {
        assert!(piece.mass.center.truncate().length() < 0.7, "piece at {}", piece.mass.center);
    }
    let (linear, angular) = f.projectile_velocity.expect("the ball is dynamic");
    let kept = linear.length_squared() / 144.0;
    assert!((kept - 260.0 / 360.0).abs() < 1e-3, "kept {kept} of the energy");
    assert_eq!(angular, Vec3::ZERO);
    // The record rebuilds it bit for bit from the mesh it broke.
    let again = replay(&f.broken_mesh, &f.record).unwrap().unwrap();
    assert_eq!(again.rest.as_ref(), Some(rest));
    assert_eq!(again.pieces.len(), f.pieces.len());
    // The set takes the rest; the next fracture is numbered 1.
    set.apply(plan.targets.clone());
    set.apply_fracture(f);
    assert_eq!(set.mesh(WALL), Some(rest));
    assert_eq!(damage.fractures_made(), 1);
}

/// A dynamic wall moving at v and spinning at ω: each piece leaves at v + ω × r at its own
/// centre (world), spinning at ω, and its mass is the wall's density (its mass over its volume).
#[test]
fn pieces_inherit_the_velocity_of_the_body_where_they_were() {
    let to_world = Affine3A::from_translation(Vec3::new(0.0, 1.0, 0.0));
    let set = wall_set(to_world, Some(100.0), None);
    let ball = ball_mesh();
    let (v, w) = (Vec3::new(0.5, 0.0, 0.0), Vec3::new(0.0, 0.0, 2.0));
    let mass = 600.0;
    let wall_state = BodyState::moving(Vec3::new(0.0, 1.0, 0.0), v, w, mass, Mat3::IDENTITY * 0.01);
    let mut damage = Damage::new();
    let plan = plan(&set, &mut damage, &[front_hit(&ball, wall_state, to_world, 12.0)], 1);
    let f = &plan.fractures[0];
    let density = mass / volume(&f.broken_mesh) as f32;
    for piece in &f.pieces {
        let centre = to_world.transform_point3(piece.mass.center);
        let expected = v + w.cross(centre - wall_state.center_of_mass);
        assert!((piece.linear_velocity - expected).length() < 1e-5, "{} against {expected}", piece.linear_velocity);
        assert_eq!(piece.angular_velocity, w);
        assert!((piece.mass.mass - density * piece.mass.volume).abs() < 1e-3 * piece.mass.mass);
    }
}

/// Under its toughness the wall only dents; with a 0.06 m dent limit, three 0.025 m dents
/// (in three places) break it on the third, by its accumulated dent, and the count starts
/// again from zero.
#[test]
fn accumulated_dents_break_a_body_at_its_dent_limit() {
    let to_world = Affine3A::IDENTITY;
    let set = wall_set(to_world, Some(1.0e6), Some(0.06));
    let ball = ball_mesh();
    let mut damage = Damage::new();
    let mut current = set;
    // 2.25 m/s: 0.02·(2.25 − 1) = 0.025 m a dent, 12.7 J.
    for (step, x) in [(1u64, -0.8f32), (2, 0.0), (3, 0.8)] {
        let h = hit(&ball, BodyState::FIXED, Vec3::new(x, 0.0, 0.1), -Vec3::Z, 2.25);
        let plan = plan(&current, &mut damage, &[h], step);
        assert_eq!(plan.dents.len(), 1);
        if step < 3 {
            assert!(plan.fractures.is_empty(), "broke at step {step}");
            assert!((damage.accumulated_dent(WALL) - 0.025 * step as f32).abs() < 1e-4);
        } else {
            assert_eq!(plan.fractures.len(), 1);
            assert_eq!(plan.fractures[0].cause, FractureCause::Dent);
            assert!((plan.fractures[0].accumulated_dent - 0.075).abs() < 1e-4);
            assert_eq!(damage.accumulated_dent(WALL), 0.0);
        }
        current.apply(plan.targets);
    }
}

/// The same hits on the same bodies break them the same way, bit for bit, ids included.
#[test]
fn a_fracture_is_deterministic() {
    let to_world = Affine3A::IDENTITY;
    let ball = ball_mesh();
    let run = || {
        let set = wall_set(to_world, Some(100.0), None);
        plan(&set, &mut Damage::new(), &[front_hit(&ball, BodyState::FIXED, to_world, 12.0)], 1)
    };
    let (a, b) = (run(), run());
    let (a, b) = (&a.fractures[0], &b.fractures[0]);
    assert_eq!(a.rest, b.rest);
    assert_eq!(a.pieces.len(), b.pieces.len());
    for (p, q) in a.pieces.iter().zip(&b.pieces) {
        assert_eq!((p.id, &p.mesh, p.linear_velocity), (q.id, &q.mesh, q.linear_velocity));
    }
}

/// An open mesh cannot be made breakable, and a breakable body placed by a scaling transform
/// is refused at its breaking hit, naming the fix, with nothing changed (no fracture counted,
/// no accumulated dent).
#[test]
fn a_body_that_cannot_break_correctly_is_refused() {
    let mut set = TargetSet::new();
    // The wall with one face missing.
    let whole = wall();
    let faces = whole.faces()[1..].to_vec();
    let sheet = TriMesh::new(whole.positions().to_vec(), faces).unwrap();
    set.insert(WALL, sheet, Affine3A::IDENTITY, DentSettings::new(1.0, 0.02, 0.05)).unwrap();
    let settings = FractureSettings::new(pattern(), Some(100.0), None).unwrap();
    let open = set.set_fracture(WALL, Some(settings.clone()));
    assert!(matches!(open, Err(FractureError::OpenMesh { .. })), "{open:?}");
    assert!(set.set_fracture(99, Some(settings)).is_err(), "an unknown body");

    let scaled = Affine3A::from_scale(Vec3::splat(2.0));
    let set = wall_set(scaled, Some(100.0), Some(0.01));
    let ball = ball_mesh();
    let mut damage = Damage::new();
    let result = damage.plan(&set, &[front_hit(&ball, BodyState::FIXED, scaled, 12.0)], 1, &mut CpuBackend);
    let Err(error @ DamageError::Fracture { hit: 0, .. }) = result else { panic!("{result:?}") };
    assert!(error.to_string().contains("bake its scale into the mesh"), "{error}");
    assert_eq!((damage.fractures_made(), damage.accumulated_dent(WALL)), (0, 0.0));
}

/// A recorded breakable body records its dents and its fracture: replaying its damage file on
/// its undamaged mesh gives the rest the plan gave, bit for bit, and each piece under the name
/// `<name>/piece<index>`.
#[test]
fn a_recorded_fracture_replays_to_the_same_rest_and_pieces() {
    use dentbend::record::{DamageRecorder, DentForm, Projectiles, RecordForms, replay_body};
    let to_world = Affine3A::IDENTITY;
    let set = wall_set(to_world, Some(100.0), None);
    let base = set.mesh(WALL).unwrap().clone();
    let mut recorder = DamageRecorder::new(RecordForms::EDITS);
    recorder.track(WALL, "wall", &base);
    let ball = ball_mesh();
    let hits = [front_hit(&ball, BodyState::FIXED, to_world, 12.0)];
    let plan = plan(&set, &mut Damage::new(), &hits, 4);
    recorder.record(&set, &hits, &plan).unwrap();
    let file = recorder.file();
    let replayed = replay_body(&file.bodies[0], &base, DentForm::Edits, &Projectiles::new()).unwrap();
    let f = &plan.fractures[0];
    assert_eq!(Some(&replayed.mesh), f.rest.as_ref());
    assert_eq!(replayed.pieces.len(), f.pieces.len());
    for ((name, mesh), piece) in replayed.pieces.iter().zip(&f.pieces) {
        assert_eq!(name, &format!("wall/piece{}", piece.id.index));
        assert_eq!(mesh, &piece.mesh);
    }
}

/// The rest of a broken wall dents again, at the edge of the hole too, where the cut left
/// vertices a few µm apart joined by tiny edges (before, every dent there was refused as a
/// seam that nearly coincides): each dent moves vertices and the rest stays closed.
#[test]
fn the_rest_of_a_broken_wall_dents_again_at_the_edge_of_the_hole() {
    let mut set = wall_set(Affine3A::IDENTITY, Some(100.0), None);
    let ball = ball_mesh();
    let mut damage = Damage::new();
    let p = plan(&set, &mut damage, &[front_hit(&ball, BodyState::FIXED, Affine3A::IDENTITY, 12.0)], 1);
    set.apply(p.targets);
    set.apply_fracture(&p.fractures[0]);
    // Beside the hole (the pattern's 16-gon has an inradius of 0.6 m) and farther out.
    for (step, x) in [0.62f32, -0.65, 0.0, 1.0].into_iter().enumerate() {
        let point = Vec3::new(x, if x == 0.0 { 0.63 } else { 0.0 }, 0.1);
        let hits = [hit(&ball, BodyState::FIXED, point, -Vec3::Z, 3.0)];
        let p = damage.plan(&set, &hits, step as u64 + 2, &mut CpuBackend).expect("the rest dents");
        assert_eq!(p.dents.len(), 1, "a 3 m/s hit at ({x}, {}) dents", point.y);
        assert!(p.dents[0].moved_vertices > 0, "the dent at x = {x} moves vertices");
        set.apply(p.targets);
        assert_closed(set.mesh(WALL).unwrap(), "the dented rest");
    }
}

/// A break that would make more pieces than the settings allow is refused with a typed error
/// naming the fix, and nothing changes: the plan fails, the wall keeps its mesh, and the same
/// hit under the default limit breaks it into more pieces than the lowered limit.
#[test]
fn a_break_past_the_piece_limit_is_refused_and_changes_nothing() {
    let ball = ball_mesh();
    let hits = |ball| [front_hit(ball, BodyState::FIXED, Affine3A::IDENTITY, 12.0)];
    let mut set = wall_set(Affine3A::IDENTITY, Some(100.0), None);
    let made = plan(&set, &mut Damage::new(), &hits(&ball), 1).fractures[0].pieces.len();
    assert!(made >= 4, "{made} pieces under the default limit");
    let mut settings = FractureSettings::new(pattern(), Some(100.0), None).unwrap();
    settings.max_pieces = made as u32 - 1;
    set.set_fracture(WALL, Some(settings)).unwrap();
    let before = set.mesh(WALL).unwrap().clone();
    let mut damage = Damage::new();
    let error = damage.plan(&set, &hits(&ball), 1, &mut CpuBackend).expect_err("too many pieces");
    let text = error.to_string();
    assert!(
        matches!(error, DamageError::Fracture { error: FractureError::TooManyPieces { pieces, limit }, .. }
            if pieces == made && limit == made as u32 - 1),
        "{error:?}"
    );
    assert!(text.contains("max_pieces"), "the message names the fix: {text}");
    assert_eq!(set.mesh(WALL).unwrap(), &before, "the wall is unchanged");
    assert_eq!(damage.fractures_made(), 0, "no fracture was counted");
    // A limit of 0 is no limit a break can meet: refused when set.
    let mut zero = FractureSettings::new(pattern(), Some(100.0), None).unwrap();
    zero.max_pieces = 0;
    assert!(matches!(
        set.set_fracture(WALL, Some(zero)),
        Err(FractureError::InvalidParameter { name: "max_pieces", .. })
    ));
}
