//! Impulses at contact points, in the Guendelman–Bridson–Fedkiw order (ARCHITECTURE.md §2): an elastic
//! collision phase (restitution) on contacts the step would close, then — after gravity — an
//! inelastic contact phase that stops penetration, its last sweep with shock propagation. Both
//! phases apply Coulomb friction; the contact phase also rolling resistance. Sequential impulses
//! with accumulated, clamped magnitudes. Each sweep runs part by part (see `contact_parts`).

use glam::{Mat3, Vec3};

use super::contact_parts::{Joins, Parts, Placed};
use super::{ContactPoint, PairContacts, WorldSettings};

/// Velocities and inverse mass of one body during a step.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SolverBody {
    pub linear: Vec3,
    pub angular: Vec3,
    pub position: Vec3,
    /// 1/kg; 0 for a body fixed during the step, whose `inverse_inertia` is zero too.
    pub inverse_mass: f32,
    /// World inverse inertia, 1/(kg·m²).
    pub inverse_inertia: Mat3,
    /// Height along −gravity, for shock propagation, m.
    pub height: f32,
}

/// One contact point's constraint.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Constraint {
    /// Index of the pair in the step's pair list.
    pub pair: usize,
    pub a: usize,
    pub b: usize,
    /// Contact point relative to each centre of mass, m.
    pub ra: Vec3,
    pub rb: Vec3,
    pub point: Vec3,
    pub normal: Vec3,
    pub tangents: [Vec3; 2],
    pub distance: f32,
    pub restitution: f32,
    pub friction: f32,
    /// Rolling resistance lever: the angular impulse resisting relative rotation is at most this
    /// × the normal impulse, m (coefficient × rolling radius).
    pub rolling: f32,
    /// Normal relative velocity before the step, m/s (negative: closing).
    pub approach: f32,
    /// Relative velocity of b with respect to a at the point before the step, m/s.
    pub relative_velocity: Vec3,
    /// Whether the collision phase handles it (it closes within the step).
    pub colliding: bool,
    /// Effective masses along the normal and the two tangents, kg (the bodies' masses and
    /// world inertias are fixed within a step), 0 when both bodies are fixed.
    masses: [f32; 3],
    /// Per body (a, b), its angular velocity change per unit impulse on b along the normal and
    /// the two tangents (I⁻¹ (r × d), a's negated when applied), rad/s per N·s: a visit applies
    /// impulses without multiplying by the inertia.
    turns: [[Vec3; 3]; 2],
    normal_impulse: f32,
    tangent_impulse: [f32; 2],
    /// Accumulated rolling-resistance angular impulse on b (a gets the opposite), N·m·s.
    rolling_impulse: Vec3,
    /// Normal impulse the contact phase starts from (warm start), N·s.
    pub warm_normal: f32,
    /// Friction impulses along `tangents` the contact phase starts from, N·s.
    pub warm_tangent: [f32; 2],
    /// Rolling-resistance angular impulse on b the contact phase starts from, N·m·s.
    pub warm_rolling: Vec3,
    /// Total impulse applied to b over the step (a gets the opposite), N·s.
    pub total: Vec3,
}

/// A pair's surface: restitution, friction coefficient, rolling resistance coefficient.
pub(crate) type Surface = (f32, f32, f32);

/// Builds the constraints of `contacts`; `surface(a, b)` gives the pair's [`Surface`].
pub(crate) fn constraints(
    contacts: &[PairContacts],
    bodies: &[SolverBody],
    dt: f32,
    surface: impl Fn(usize, usize) -> Surface,
) -> Vec<Constraint> {
    let mut out = Vec::new();
    for (pair, contact) in contacts.iter().enumerate() {
        let surface = surface(contact.a, contact.b);
        for point in &contact.points {
            out.push(constraint(pair, contact.a, contact.b, point, bodies, dt, surface));
        }
    }
    out
}

fn constraint(
    pair: usize,
    a: usize,
    b: usize,
    contact: &ContactPoint,
    bodies: &[SolverBody],
    dt: f32,
    (restitution, friction, rolling_resistance): Surface,
) -> Constraint {
    let point = contact.point();
    let (ra, rb) = (point - bodies[a].position, point - bodies[b].position);
    let normal = contact.normal;
    let relative_velocity = velocity_at(&bodies[b], rb) - velocity_at(&bodies[a], ra);
    let approach = relative_velocity.dot(normal);
    let (t1, t2) = normal.any_orthonormal_pair();
    // The rolling radius: the shorter lever, so a ball on a large slab rolls on its own radius.
    let radius = ra.length().min(rb.length());
    let masses = effective_masses(&bodies[a], &bodies[b], ra, rb, [normal, t1, t2]);
    let turn = |body: &SolverBody, r: Vec3| [normal, t1, t2].map(|d| body.inverse_inertia * r.cross(d));
    Constraint {
        pair,
        a,
        b,
        ra,
        rb,
        point,
        normal,
        tangents: [t1, t2],
        distance: contact.distance,
        restitution,
        friction,
        rolling: rolling_resistance * radius,
        approach,
        relative_velocity,
        colliding: approach < 0.0 && contact.distance + approach * dt <= 0.0,
        masses,
        turns: [turn(&bodies[a], ra), turn(&bodies[b], rb)],
        normal_impulse: 0.0,
        tangent_impulse: [0.0; 2],
        rolling_impulse: Vec3::ZERO,
        warm_normal: 0.0,
        warm_tangent: [0.0; 2],
        warm_rolling: Vec3::ZERO,
        total: Vec3::ZERO,
    }
}

impl Constraint {
    /// The contact phase's accumulated impulses: (normal magnitude, friction vector), N·s.
    pub fn contact_impulses(&self) -> (f32, Vec3) {
        (self.normal_impulse, self.tangents[0] * self.tangent_impulse[0] + self.tangents[1] * self.tangent_impulse[1])
    }

    /// The contact phase's accumulated rolling-resistance angular impulse on b, N·m·s.
    pub fn rolling_impulse(&self) -> Vec3 {
        self.rolling_impulse
    }
}

fn velocity_at(body: &SolverBody, r: Vec3) -> Vec3 {
    body.linear + body.angular.cross(r)
}

/// [`effective_mass`] along each of `directions` (normal, tangents), kg.
fn effective_masses(a: &SolverBody, b: &SolverBody, ra: Vec3, rb: Vec3, directions: [Vec3; 3]) -> [f32; 3] {
    directions.map(|d| effective_mass(a, b, ra, rb, d))
}

/// 1 / (effective inverse mass along `direction` at the contact), 0 when both bodies are fixed.
fn effective_mass(a: &SolverBody, b: &SolverBody, ra: Vec3, rb: Vec3, direction: Vec3) -> f32 {
    let angular = |body: &SolverBody, r: Vec3| {
        let rn = r.cross(direction);
        (body.inverse_inertia * rn).dot(rn)
    };
    let k = a.inverse_mass + b.inverse_mass + angular(a, ra) + angular(b, rb);
    if k > 0.0 { 1.0 / k } else { 0.0 }
}

/// Applies the impulse `amounts` (along the normal and the two tangents, N·s) to b and its
/// opposite to a. Fixed bodies (no inverse mass, or frozen by shock propagation) do not move.
fn apply(bodies: &mut [SolverBody], c: &mut Constraint, amounts: [f32; 3]) {
    let impulse = c.normal * amounts[0] + c.tangents[0] * amounts[1] + c.tangents[1] * amounts[2];
    let turn = |t: &[Vec3; 3]| t[0] * amounts[0] + t[1] * amounts[1] + t[2] * amounts[2];
    let a = &mut bodies[c.a];
    if a.inverse_mass > 0.0 {
        a.linear -= impulse * a.inverse_mass;
        a.angular -= turn(&c.turns[0]);
    }
    let b = &mut bodies[c.b];
    if b.inverse_mass > 0.0 {
        b.linear += impulse * b.inverse_mass;
        b.angular += turn(&c.turns[1]);
    }
    c.total += impulse;
}

/// One sequential-impulse visit of a constraint: the normal impulse keeps the normal velocity at
/// least `target`, then friction within the Coulomb cone of the accumulated normal impulse, then
/// (if `rolling`) rolling resistance.
fn solve(bodies: &mut [SolverBody], c: &mut Constraint, target: f32, frozen: Option<usize>, rolling: bool) {
    // Shock propagation: the lower body of the pair acts as if it were fixed for this visit.
    let saved = frozen.map(|k| {
        let mass = (bodies[k].inverse_mass, bodies[k].inverse_inertia);
        bodies[k].inverse_mass = 0.0;
        bodies[k].inverse_inertia = Mat3::ZERO;
        (k, mass)
    });
    let masses = match saved {
        // The frozen body's mass is gone for this visit.
        Some(_) => effective_masses(&bodies[c.a], &bodies[c.b], c.ra, c.rb, [c.normal, c.tangents[0], c.tangents[1]]),
        None => c.masses,
    };
    solve_normal_and_friction(bodies, c, target, masses);
    if rolling {
        solve_rolling(bodies, c);
    }
    if let Some((k, (inverse_mass, inverse_inertia))) = saved {
        bodies[k].inverse_mass = inverse_mass;
        bodies[k].inverse_inertia = inverse_inertia;
    }
}

/// The normal and friction impulses of one visit, with the pair's effective `masses` (normal,
/// tangents; kg).
fn solve_normal_and_friction(bodies: &mut [SolverBody], c: &mut Constraint, target: f32, masses: [f32; 3]) {
    let relative = velocity_at(&bodies[c.b], c.rb) - velocity_at(&bodies[c.a], c.ra);
    let mass = masses[0];
    if mass == 0.0 {
        return;
    }
    let accumulated = (c.normal_impulse + (target - relative.dot(c.normal)) * mass).max(0.0);
    let delta = accumulated - c.normal_impulse;
    c.normal_impulse = accumulated;
    apply(bodies, c, [delta, 0.0, 0.0]);
    if c.friction <= 0.0 {
        return;
    }
    let relative = velocity_at(&bodies[c.b], c.rb) - velocity_at(&bodies[c.a], c.ra);
    let limit = c.friction * c.normal_impulse;
    let mut wanted = [0.0; 2];
    for (k, tangent) in c.tangents.iter().enumerate() {
        wanted[k] = c.tangent_impulse[k] - relative.dot(*tangent) * masses[k + 1];
    }
    let length = (wanted[0] * wanted[0] + wanted[1] * wanted[1]).sqrt();
    if length > limit {
        let scale = limit / length;
        wanted = [wanted[0] * scale, wanted[1] * scale];
    }
    let change = [0.0, wanted[0] - c.tangent_impulse[0], wanted[1] - c.tangent_impulse[1]];
    c.tangent_impulse = wanted;
    apply(bodies, c, change);
}

/// Rolling resistance: an angular impulse towards no relative rotation of the two bodies,
/// accumulated and clamped to `rolling` × the accumulated normal impulse (a resting contact's
/// patch resists rolling and spinning; a lifting one does not).
fn solve_rolling(bodies: &mut [SolverBody], c: &mut Constraint) {
    let limit = c.rolling * c.normal_impulse;
    if limit <= 0.0 && c.rolling_impulse == Vec3::ZERO {
        return;
    }
    let (a, b) = (&bodies[c.a], &bodies[c.b]);
    let k = a.inverse_inertia + b.inverse_inertia;
    let determinant = k.determinant();
    if !(determinant > 0.0 && determinant.is_finite()) {
        return; // both bodies fixed (or frozen)
    }
    let spin = b.angular - a.angular;
    let mut wanted = c.rolling_impulse - k.inverse() * spin;
    let length = wanted.length();
    if length > limit {
        wanted *= limit.max(0.0) / length;
    }
    let delta = wanted - c.rolling_impulse;
    c.rolling_impulse = wanted;
    let (ia, ib) = (bodies[c.a].inverse_inertia, bodies[c.b].inverse_inertia);
    bodies[c.a].angular -= ia * delta;
    bodies[c.b].angular += ib * delta;
}

/// The collision phase: restitution impulses on the contacts the step closes.
pub(crate) fn collide(
    bodies: &mut [SolverBody],
    constraints: &mut [Constraint],
    parts: &Parts,
    settings: &WorldSettings,
) {
    let colliding: Vec<usize> = (0..constraints.len()).filter(|&k| constraints[k].colliding).collect();
    let threshold = settings.restitution_threshold;
    parts.sweeps(bodies, constraints, &colliding, settings.collision_iterations as usize, |bodies, c| {
        let bounce = if -c.approach > threshold { -c.restitution * c.approach } else { 0.0 };
        solve(bodies, c, bounce, None, false);
    });
}

/// The contact phase's goal for a contact's normal velocity: a gap may close within the step
/// but no further (speculative); overlap is removed by the split position correction, never by
/// velocity (which would pump energy into a pile), m/s.
fn closing_goal(c: &Constraint, dt: f32) -> f32 {
    (-c.distance / dt).min(0.0)
}

/// The contact phase: impulses that keep every contact from closing further than its gap,
/// starting from each contact's warm-start impulses (last step's, see `warm_start`).
pub(crate) fn contact(
    bodies: &mut [SolverBody],
    constraints: &mut [Constraint],
    parts: &Parts,
    settings: &WorldSettings,
) {
    let dt = settings.dt;
    let all: Vec<usize> = (0..constraints.len()).collect();
    parts.sweeps(bodies, constraints, &all, 1, warm_start);
    let iterations = settings.contact_iterations as usize;
    let shock = usize::from(settings.shock_propagation);
    parts.sweeps(bodies, constraints, &all, iterations.saturating_sub(shock), |bodies, c| {
        solve(bodies, c, closing_goal(c, dt), None, true);
    });
    if shock == 1 {
        // Bottom-up, each pair's lower body fixed: a stack's top cannot push its base down.
        for k in shock_order(bodies, constraints) {
            let c = &mut constraints[k];
            let frozen = frozen_body(bodies, c);
            solve(bodies, c, closing_goal(c, dt), frozen, true);
        }
    }
}

/// Starts a contact from its warm-start impulses: they become its accumulated impulses and are
/// applied to its bodies.
fn warm_start(bodies: &mut [SolverBody], c: &mut Constraint) {
    c.normal_impulse = c.warm_normal;
    c.tangent_impulse = c.warm_tangent;
    c.rolling_impulse = c.warm_rolling;
    apply(bodies, c, [c.warm_normal, c.warm_tangent[0], c.warm_tangent[1]]);
    let (a, b) = (c.a, c.b);
    bodies[a].angular -= bodies[a].inverse_inertia * c.warm_rolling;
    bodies[b].angular += bodies[b].inverse_inertia * c.warm_rolling;
}

/// More contact-phase sweeps over the constraints `only` (indices), continuing from their
/// accumulated impulses: after the joints' pre-stabilization impulses changed the velocities,
/// the contacts of jointed bodies take up what the joints push into them.
pub(crate) fn contact_sweeps(
    bodies: &mut [SolverBody],
    constraints: &mut [Constraint],
    parts: &Parts,
    only: &[usize],
    settings: &WorldSettings,
    iterations: u32,
) {
    let dt = settings.dt;
    parts.sweeps(bodies, constraints, only, iterations as usize, |bodies, c| {
        solve(bodies, c, closing_goal(c, dt), None, true);
    });
}

impl Joins for Constraint {
    fn bodies(&self) -> [usize; 2] {
        [self.a, self.b]
    }
}

impl Placed for SolverBody {
    fn position(&self) -> Vec3 {
        self.position
    }

    fn is_fixed(&self) -> bool {
        fixed(self)
    }
}

/// Whether the body is fixed during the step (static, kinematic or asleep: no inverse mass).
pub(crate) fn fixed(body: &SolverBody) -> bool {
    body.inverse_mass == 0.0
}

/// The height at which shock propagation visits a contact: its lower body's, or the moving
/// body's when the other is fixed (a wall's centre may be above the ball it holds), m.
fn shock_height(bodies: &[SolverBody], c: &Constraint) -> f32 {
    let (a, b) = (&bodies[c.a], &bodies[c.b]);
    match (fixed(a), fixed(b)) {
        (true, false) => b.height,
        (false, true) => a.height,
        _ => a.height.min(b.height),
    }
}

/// Shock propagation's visiting order: bottom-up by [`shock_height`]; at the same height the
/// contacts with fixed bodies first, so a body's velocity is final before it is frozen.
fn shock_order(bodies: &[SolverBody], constraints: &[Constraint]) -> Vec<usize> {
    // Keys computed once: (height, both bodies moving, index), a total order.
    let mut keyed: Vec<(f32, bool, usize)> = constraints
        .iter()
        .enumerate()
        .map(|(k, c)| (shock_height(bodies, c), !(fixed(&bodies[c.a]) || fixed(&bodies[c.b])), k))
        .collect();
    keyed.sort_unstable_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)).then(x.2.cmp(&y.2)));
    keyed.into_iter().map(|(_, _, k)| k).collect()
}

/// The body shock propagation freezes for a contact: the lower one when both move, none when
/// one is fixed already (freezing the other would leave the contact unsolved).
fn frozen_body(bodies: &[SolverBody], c: &Constraint) -> Option<usize> {
    if fixed(&bodies[c.a]) || fixed(&bodies[c.b]) {
        None
    } else if bodies[c.a].height <= bodies[c.b].height {
        Some(c.a)
    } else {
        Some(c.b)
    }
}

/// Split position correction: pseudo-velocities (kept out of the bodies' real velocities) that
/// push overlapping contacts apart by `baumgarte` × the overlap beyond the slop over the step.
/// Returns each body's (linear, angular) pseudo-velocity, to be integrated with the real ones.
pub(crate) fn position_correction(
    bodies: &[SolverBody],
    constraints: &mut [Constraint],
    parts: &Parts,
    settings: &WorldSettings,
) -> Vec<(Vec3, Vec3)> {
    let mut pseudo: Vec<SolverBody> =
        bodies.iter().map(|b| SolverBody { linear: Vec3::ZERO, angular: Vec3::ZERO, ..*b }).collect();
    let overlapping: Vec<usize> =
        (0..constraints.len()).filter(|&k| constraints[k].distance < -settings.slop).collect();
    if !overlapping.is_empty() {
        let saved: Vec<(Vec3, [f32; 2], f32)> = overlapping
            .iter()
            .map(|&k| (constraints[k].total, constraints[k].tangent_impulse, constraints[k].normal_impulse))
            .collect();
        for &k in &overlapping {
            constraints[k].normal_impulse = 0.0;
        }
        let (baumgarte, slop, dt) = (settings.baumgarte, settings.slop, settings.dt);
        parts.sweeps(&mut pseudo, constraints, &overlapping, settings.contact_iterations as usize, |pseudo, c| {
            let push = baumgarte * (-c.distance - slop) / dt;
            let friction = std::mem::replace(&mut c.friction, 0.0);
            let masses = c.masses;
            solve_normal_and_friction(pseudo, c, push, masses);
            c.friction = friction;
        });
        // The pseudo impulses are not physical: the constraints keep the step's real ones.
        for (&k, (total, tangent, normal)) in overlapping.iter().zip(saved) {
            constraints[k].total = total;
            constraints[k].tangent_impulse = tangent;
            constraints[k].normal_impulse = normal;
        }
    }
    pseudo.iter().map(|b| (b.linear, b.angular)).collect()
}
