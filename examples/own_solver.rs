//! Dents fed from your own solver: a hand-written contact list stands in for one step of any
//! rigid-body engine. Bodies are named by the engine's own ids (here `u32`); the damage API
//! decides each dent from the contact and both bodies' states, and hands back new meshes, the
//! vertices that moved (refit your collider over those) and how far to push each projectile
//! into its dent. Nothing of yours changes until you apply them.

use dentbend::damage::{CpuBackend, Damage, Hit, TargetSet};
use dentbend::dent::{BodyState, DentSettings, Impact, Surface};
use dentbend::glam::{Affine3A, Mat3, Vec3};
use dentbend::mesh;

const FLOOR: u32 = 1;
const BALL: u32 = 2;
const CRATE: u32 = 3;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // What the engine knows of its bodies: the floor and the crate dent, the ball does not.
    let mut settings = DentSettings::new(1.0, 0.02, 0.15); // 1 m/s threshold, 2 cm per m/s, 15 cm cap
    settings.move_projectile = true;
    let mut bodies = TargetSet::new();
    bodies.insert(
        FLOOR,
        mesh::subdivided_box(Vec3::new(8.0, 0.5, 8.0), [64, 4, 64])?,
        Affine3A::IDENTITY,
        settings.clone(),
    )?;
    let crate_at = Affine3A::from_translation(Vec3::new(2.0, 0.75, 0.0));
    bodies.insert(CRATE, mesh::subdivided_box(Vec3::new(1.0, 1.0, 1.0), [16, 16, 16])?, crate_at, settings)?;
    bodies.insert_rigid(BALL);
    let ball = mesh::icosphere(0.3, 3)?;

    // One step's contacts, as the solver reported them before resolving them. The states take
    // the world inverse inertia: a solid 2 kg ball of radius 0.3 m has I = 0.4·m·r², a 10 kg
    // cube of side 1 m has I = m·(1² + 1²)/12 about each axis.
    let (ball_mass, crate_mass) = (2.0, 10.0);
    let ball_inverse_inertia = Mat3::IDENTITY / (0.4 * ball_mass * 0.3 * 0.3);
    let crate_inverse_inertia = Mat3::IDENTITY / (crate_mass * 2.0 / 12.0);
    let ball_state = BodyState::moving(
        Vec3::new(0.0, 0.55, 0.0),
        Vec3::new(1.0, -8.0, 0.0),
        Vec3::ZERO,
        ball_mass,
        ball_inverse_inertia,
    );
    let crate_state = BodyState::moving(
        crate_at.translation.into(),
        Vec3::new(0.0, -3.0, 0.0),
        Vec3::new(0.0, 0.0, 2.0),
        crate_mass,
        crate_inverse_inertia,
    );
    let crate_mesh = bodies.mesh(CRATE).expect("inserted").clone();
    let contacts = [
        // (target, projectile, point, normal into the target, states, projectile's surface)
        (
            FLOOR,
            BALL,
            Vec3::new(0.0, 0.25, 0.0),
            -Vec3::Y,
            BodyState::FIXED,
            ball_state,
            Surface { mesh: &ball, to_world: Affine3A::from_translation(ball_state.center_of_mass) },
        ),
        (
            FLOOR,
            CRATE,
            Vec3::new(2.0, 0.25, 0.3),
            -Vec3::Y,
            BodyState::FIXED,
            crate_state,
            Surface { mesh: &crate_mesh, to_world: crate_at },
        ),
    ];
    let mut hits = Vec::new();
    for (target, projectile, point, normal, target_state, projectile_state, projectile_surface) in contacts {
        let impact = Impact::from_contact(point, normal, &target_state, &projectile_state)?;
        hits.push(Hit { target, projectile, impact, target_state, projectile_state, projectile_surface });
    }

    let mut damage = Damage::new();
    let plan = damage.plan(&bodies, &hits, 1, &mut CpuBackend)?;
    for dent in &plan.dents {
        println!(
            "body {} dented by body {}: {:.3} m deep; move the projectile by {:?} m",
            dent.target, dent.projectile, dent.dent_distance, dent.projectile_offset
        );
    }
    // A target refined under its dent (a coarse mesh) has new vertices and faces: rebuild its
    // collider; otherwise refit it over the moved vertices.
    let rebuilt: Vec<u32> = plan.targets.iter().filter(|t| t.topology_changed).map(|t| t.key).collect();
    for (body, moved) in bodies.apply(plan.targets) {
        if rebuilt.contains(&body) {
            println!("body {body}: refined under the dent, rebuild its collider from the new mesh");
        } else {
            println!("body {body}: refit the collider over {} moved vertices", moved.len());
        }
    }
    Ok(())
}
