//! The joint–contact rounds of a step: contacts are solved before the joints' pre-stabilization,
//! so a jointed body's supports never saw what its joints push into them (a chain resting on two
//! supports sank through them). A few rounds of contact sweeps on the jointed bodies' contacts,
//! each followed by more pre-stabilization, let the supports take that up. The contact sweeps
//! of the next round change the velocities again, so the step's first pre-stabilization and each
//! round's take one Newton iteration; a last pass with the full Newton budget, after the energy
//! check below, leaves the joints holding.
//!
//! The rounds are a block Gauss–Seidel between two constraint sets, and it diverges where they
//! cannot both hold (a strut of a jointed loop wedged between two bars: its joints pull it
//! where its contacts forbid it to go, and every round pushes harder; the warm-started contact
//! impulses carry the growth into the next step). Neither contacts nor joints at velocity level
//! add kinetic energy, so an island — bodies linked by the jointed contacts and the joints —
//! whose kinetic energy the rounds raise is put back as it was before them: its velocities,
//! its contacts' impulses and its joints' accumulated impulses.

use glam::Vec3;

use super::contact_parts::Parts;
use super::joints::{self, Joint};
use super::solver::{self, Constraint, SolverBody};
use super::union_find::UnionFind;
use super::{RigidBody, WorldSettings};

/// Rounds of contact sweeps and joint pre-stabilization after the first of each.
const ROUNDS: usize = 3;
/// An island whose kinetic energy the rounds raise by more than this fraction (plus
/// [`ENERGY_FLOOR`]) is put back: the rounds only move momentum between its bodies and
/// their supports, and round-off stays far below it.
const ENERGY_GAIN: f64 = 0.05;
/// Absolute slack of the energy test, J: a resting island's energy is near zero, and a
/// millijoule is a 10 kg body moving at 1.4 cm/s.
const ENERGY_FLOOR: f64 = 1e-3;

/// The step's contacts as the rounds see them.
pub(crate) struct JointedContacts<'a> {
    /// Every contact constraint of the step, in the order of `parts`.
    pub constraints: &'a mut [Constraint],
    /// How the sweeps split the constraints (see `contact_parts`).
    pub parts: &'a Parts,
    /// The constraints on jointed bodies (indices, increasing).
    pub jointed: &'a [usize],
}

/// Runs the rounds on the jointed contacts, changing `solver` velocities, the constraints'
/// impulses and `joints`' accumulated impulses; returns how many islands were put back because
/// the rounds raised their energy.
pub(crate) fn joint_contact_rounds(
    joints: &mut [Joint],
    bodies: &[RigidBody],
    solver: &mut [SolverBody],
    contacts: JointedContacts,
    pseudo: &mut [(Vec3, Vec3)],
    settings: &WorldSettings,
) -> usize {
    let JointedContacts { constraints, parts, jointed } = contacts;
    if jointed.is_empty() {
        return 0;
    }
    let saved = Saved {
        velocities: solver.to_vec(),
        contacts: jointed.iter().map(|&k| constraints[k]).collect(),
        impulses: joints.iter().map(|j| (j.accumulated, j.clamped)).collect(),
    };
    for _ in 0..ROUNDS {
        solver::contact_sweeps(solver, constraints, parts, jointed, settings, settings.contact_iterations / 2);
        // Joints that still hold after the sweeps push nothing more into the contacts.
        if joints::prestabilize(joints, bodies, solver, pseudo, settings, false, 1) == 0 {
            break;
        }
    }
    let count = put_back_energetic_islands(joints, bodies, solver, constraints, jointed, saved);
    // The rounds' pre-stabilization took one Newton iteration each: finish it.
    joints::prestabilize(joints, bodies, solver, pseudo, settings, false, joints::NEWTON);
    count
}

/// What the rounds started from: every body's velocities, the jointed contacts (in the order of
/// `jointed`) and every joint's accumulated impulse and clamp.
struct Saved {
    velocities: Vec<SolverBody>,
    contacts: Vec<Constraint>,
    impulses: Vec<(Vec3, bool)>,
}

/// Puts every island whose kinetic energy the rounds raised back as it was in `saved`; returns
/// how many were put back.
fn put_back_energetic_islands(
    joints: &mut [Joint],
    bodies: &[RigidBody],
    solver: &mut [SolverBody],
    constraints: &mut [Constraint],
    jointed: &[usize],
    saved: Saved,
) -> usize {
    let Saved { velocities, contacts, impulses } = saved;
    let mut islands = UnionFind::new(solver.len());
    let takes: Vec<bool> = solver.iter().map(|b| b.inverse_mass > 0.0).collect();
    let moving = |i: usize| takes[i];
    let links = jointed.iter().map(|&k| (constraints[k].a, constraints[k].b)).chain(joints.iter().map(|j| (j.a, j.b)));
    for (a, b) in links {
        if moving(a) && moving(b) {
            islands.join(a, b);
        }
    }
    let mut before = vec![0.0f64; solver.len()];
    let mut after = vec![0.0f64; solver.len()];
    let energy = |i: usize, v: &SolverBody| f64::from(bodies[i].kinetic_energy_at(v.linear, v.angular));
    for i in (0..solver.len()).filter(|&i| moving(i)) {
        let root = islands.root(i);
        before[root] += energy(i, &velocities[i]);
        after[root] += energy(i, &solver[i]);
    }
    let put_back: Vec<bool> =
        (0..solver.len()).map(|i| after[i] > before[i] * (1.0 + ENERGY_GAIN) + ENERGY_FLOOR).collect();
    let count = put_back.iter().filter(|&&p| p).count();
    if count == 0 {
        return 0;
    }
    let mut back = |i: usize| put_back[islands.root(i)];
    for i in 0..solver.len() {
        if moving(i) && back(i) {
            solver[i] = velocities[i];
        }
    }
    for (&k, saved) in jointed.iter().zip(&contacts) {
        let c = &constraints[k];
        if (moving(c.a) && back(c.a)) || (moving(c.b) && back(c.b)) {
            constraints[k] = *saved;
        }
    }
    for (joint, &(accumulated, clamped)) in joints.iter_mut().zip(&impulses) {
        if (moving(joint.a) && back(joint.a)) || (moving(joint.b) && back(joint.b)) {
            (joint.accumulated, joint.clamped) = (accumulated, clamped);
        }
    }
    log::debug!("joint-contact rounds put back {count} island(s) whose kinetic energy they raised");
    count
}
