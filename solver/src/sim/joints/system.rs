//! What every joint solve shares: how freely each body moves, where the position update will put
//! it, and one joint's linearized 6×6 system — how a linear impulse at the anchors and an
//! angular impulse (both applied to b, the opposite to a) change the relative anchor velocity and
//! the relative angular velocity — solved on a subset of its rows.

use glam::{DVec3, Mat3, Quat, Vec3};

use super::Joint;
use crate::sim::{BodyKind, RigidBody, WorldSettings};

/// Velocities of one body, world, m/s and rad/s.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Motion {
    pub linear: Vec3,
    pub angular: Vec3,
}

/// How a body responds to impulses and how the position update integrates it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Mobility {
    /// 1/kg (0 for bodies impulses do not move).
    pub inverse_mass: f32,
    /// World inverse inertia, 1/(kg·m²).
    pub inverse_inertia: Mat3,
    /// Factor on the angular velocity when positions are integrated (the world's angular damping).
    pub spin: f32,
    /// Whether the position update moves the body at all.
    pub moves: bool,
}

/// Mobilities as `World::step` treats the bodies: dynamic awake bodies take impulses and are
/// integrated with damped spin, kinematic ones only move, static and sleeping ones stay put, and
/// so do bodies condensed into a cluster (their joints to each other rest).
pub(crate) fn mobilities(bodies: &[RigidBody], settings: &WorldSettings) -> Vec<Mobility> {
    let spin = (1.0 - settings.angular_damping * settings.dt).max(0.0);
    bodies
        .iter()
        .map(|body| match body.kind {
            _ if !body.is_simulated() => {
                Mobility { inverse_mass: 0.0, inverse_inertia: Mat3::ZERO, spin: 1.0, moves: false }
            }
            BodyKind::Dynamic if !body.activity.asleep => Mobility {
                inverse_mass: body.inverse_mass,
                inverse_inertia: body.inverse_inertia_world(),
                spin,
                moves: true,
            },
            kind => Mobility {
                inverse_mass: 0.0,
                inverse_inertia: Mat3::ZERO,
                spin: 1.0,
                moves: kind == BodyKind::Kinematic,
            },
        })
        .collect()
}

/// Whether impulses move the body.
pub(crate) fn takes_impulses(m: &Mobility) -> bool {
    m.inverse_mass > 0.0
}

/// Whether the joint's impulses move either of its bodies (it has rows to solve).
pub(crate) fn joint_takes_impulses(joint: &Joint, mob: &[Mobility]) -> bool {
    takes_impulses(&mob[joint.a]) || takes_impulses(&mob[joint.b])
}

/// The orientation after one position update with angular velocity `w` (the same first-order
/// quaternion step as `World::step`'s position integration).
pub(crate) fn advance(q: Quat, w: Vec3, dt: f32) -> Quat {
    let spin = Quat::from_xyzw(w.x, w.y, w.z, 0.0) * q;
    (q + spin * (0.5 * dt)).normalize()
}

/// One joint's geometry for a solve: levers now and after the position update.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Frame {
    /// Anchor relative to each centre of mass where impulses act (now for a velocity-level
    /// frame, after the position update for a predicted one), m.
    pub ra: Vec3,
    pub rb: Vec3,
    /// The same after the position update (predicted), m.
    pub pa: Vec3,
    pub pb: Vec3,
    /// Predicted orientations.
    pub qa: Quat,
    pub qb: Quat,
    /// Predicted anchors on a and b, world, m.
    pub anchor_a: Vec3,
    pub anchor_b: Vec3,
    /// How the predicted orientation turns per change of angular velocity, over `dt`: the
    /// derivative of the position update's rotation (left perturbation, world axes) with respect
    /// to the body's angular velocity, divided by `dt` (the identity for a velocity-level frame).
    pub turn_a: Mat3,
    pub turn_b: Mat3,
}

/// The joint's frame after one position update with velocities `v` plus pseudo-velocities
/// `extra` over `dt`; `dt` = 0 gives the frame now (levers now, velocity level).
pub(crate) fn frame(
    joint: &Joint,
    bodies: &[RigidBody],
    mob: &[Mobility],
    v: &[Motion],
    extra: Option<&[Motion]>,
    dt: f32,
) -> Frame {
    let predict = |i: usize, local: Vec3| {
        let body = &bodies[i];
        let r = body.orientation * local;
        if dt == 0.0 || !mob[i].moves {
            let turn = if dt == 0.0 { Mat3::IDENTITY } else { Mat3::ZERO };
            return (r, r, body.orientation, body.position + r, turn);
        }
        let e = extra.map_or(Motion::default(), |e| e[i]);
        let position = body.position + (v[i].linear + e.linear) * dt;
        let w = v[i].angular * mob[i].spin + e.angular;
        let q = advance(body.orientation, w, dt);
        let p = q * local;
        // Impulses act at the predicted anchor (the constraint's gradient at the end of the
        // step), which keeps the Newton system symmetric and solvable even when bodies turn
        // far within a step; at the current anchor it can turn singular.
        (p, p, q, position + p, turn(w, dt) * mob[i].spin)
    };
    let (ra, pa, qa, anchor_a, turn_a) = predict(joint.a, joint.local_a);
    let (rb, pb, qb, anchor_b, turn_b) = predict(joint.b, joint.local_b);
    Frame { ra, rb, pa, pb, qa, qb, anchor_a, anchor_b, turn_a, turn_b }
}

/// Derivative of the rotation made by [`advance`] with angular velocity `w` over `dt` (as a
/// left perturbation, world axes) with respect to `w`, divided by `dt`. [`advance`] turns by
/// φ = 2·atan(|w|·dt/2) about w, so this is J_l(θ)·(∂θ/∂w)/dt with θ = φ·ŵ and J_l the left
/// Jacobian of SO(3); about 1 for small |w|·dt, it keeps Newton steps exact at high spin.
fn turn(w: Vec3, dt: f32) -> Mat3 {
    let speed = w.length();
    let half = 0.5 * speed * dt;
    if half < 1e-4 {
        return Mat3::IDENTITY;
    }
    let axis = w / speed;
    let angle = 2.0 * half.atan();
    let along = Mat3::from_cols(axis * axis.x, axis * axis.y, axis * axis.z);
    // ∂θ/∂w / dt: across the axis the angle per unit speed, along it the atan's slope.
    let d = (Mat3::IDENTITY - along) * (angle / (speed * dt)) + along * (1.0 / (1.0 + half * half));
    let theta = axis * angle;
    let skew = Mat3::from_cols(
        Vec3::new(0.0, theta.z, -theta.y),
        Vec3::new(-theta.z, 0.0, theta.x),
        Vec3::new(theta.y, -theta.x, 0.0),
    );
    let (sin, cos) = angle.sin_cos();
    let left = Mat3::IDENTITY
        + skew * ((1.0 - cos) / (angle * angle))
        + skew * skew * ((angle - sin) / (angle * angle * angle));
    left * d
}

/// The 6×6 response of a joint: row r, column c = change of row r's relative velocity (rows
/// 0–2: predicted relative anchor velocity along `basis[r]`; 3–5: relative angular velocity along
/// world x, y, z) per unit impulse c (0–2: linear along `basis[c]` at the anchors; 3–5: angular
/// about world x, y, z), b receiving +, a −.
pub(crate) type Matrix = [[f64; 6]; 6];

/// Builds the response matrix of the joint between `ma` and `mb` in frame `f`.
pub(crate) fn response(ma: &Mobility, mb: &Mobility, f: &Frame, basis: &[Vec3; 3]) -> Matrix {
    let mut m = [[0.0; 6]; 6];
    let axes = [Vec3::X, Vec3::Y, Vec3::Z];
    for c in 0..6 {
        let (j, l) = if c < 3 { (basis[c], Vec3::ZERO) } else { (Vec3::ZERO, axes[c - 3]) };
        let (linear, angular) = effect(ma, mb, f, j, l);
        for r in 0..3 {
            m[r][c] = f64::from(linear.dot(basis[r]));
            m[r + 3][c] = f64::from(angular.dot(axes[r]));
        }
    }
    m
}

/// Change of (relative anchor velocity as integrated, relative angular velocity as integrated)
/// when b receives linear impulse `j` at the anchor and angular impulse `l` (a the opposite).
fn effect(ma: &Mobility, mb: &Mobility, f: &Frame, j: Vec3, l: Vec3) -> (Vec3, Vec3) {
    let (da, db) = kick(ma, mb, f, j, l);
    drift(f, da, db)
}

/// Velocity changes of a and b when b receives linear impulse `j` at the anchor and angular
/// impulse `l`, a the opposite.
pub(crate) fn kick(ma: &Mobility, mb: &Mobility, f: &Frame, j: Vec3, l: Vec3) -> (Motion, Motion) {
    let db = Motion { linear: j * mb.inverse_mass, angular: mb.inverse_inertia * (f.rb.cross(j) + l) };
    let da = Motion { linear: -j * ma.inverse_mass, angular: -(ma.inverse_inertia * (f.ra.cross(j) + l)) };
    (da, db)
}

/// Change of (relative anchor velocity as integrated, relative angular velocity as integrated)
/// when the velocities of a and b change by `da` and `db` (the frame's linearization).
pub(crate) fn drift(f: &Frame, da: Motion, db: Motion) -> (Vec3, Vec3) {
    let (tb, ta) = (f.turn_b * db.angular, f.turn_a * da.angular);
    (db.linear + tb.cross(f.pb) - da.linear - ta.cross(f.pa), tb - ta)
}

/// Applies linear impulse `j` at the anchors and angular impulse `l` to b, the opposite to a.
pub(crate) fn apply(v: &mut [Motion], mob: &[Mobility], joint: &Joint, f: &Frame, j: Vec3, l: Vec3) {
    let (da, db) = kick(&mob[joint.a], &mob[joint.b], f, j, l);
    v[joint.a].linear += da.linear;
    v[joint.a].angular += da.angular;
    v[joint.b].linear += db.linear;
    v[joint.b].angular += db.angular;
}

/// Solves `m·x = rhs` on the rows and unknowns marked `active` (the others are 0) by Gaussian
/// elimination with partial pivoting; `None` when that block is singular.
pub(crate) fn solve(m: &Matrix, rhs: &[f64; 6], active: [bool; 6]) -> Option<[f64; 6]> {
    let index: Vec<usize> = (0..6).filter(|&k| active[k]).collect();
    let n = index.len();
    let mut a = [[0.0f64; 7]; 6];
    for (r, &i) in index.iter().enumerate() {
        for (c, &k) in index.iter().enumerate() {
            a[r][c] = m[i][k];
        }
        a[r][n] = rhs[i];
    }
    let scale = index.iter().map(|&i| m[i][i].abs()).fold(0.0, f64::max);
    if scale == 0.0 || !scale.is_finite() {
        return None;
    }
    for col in 0..n {
        let pivot = (col..n).max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))?;
        if a[pivot][col].abs() <= 1e-12 * scale {
            return None;
        }
        a.swap(col, pivot);
        let top = a[col];
        for row in a.iter_mut().take(n).skip(col + 1) {
            let factor = row[col] / top[col];
            for (value, above) in row.iter_mut().zip(top).take(n + 1).skip(col) {
                *value -= factor * above;
            }
        }
    }
    let mut x = [0.0; 6];
    let mut solved = [0.0f64; 6];
    for r in (0..n).rev() {
        let tail: f64 = (r + 1..n).map(|c| a[r][c] * solved[c]).sum();
        solved[r] = (a[r][n] - tail) / a[r][r];
    }
    for (r, &i) in index.iter().enumerate() {
        x[i] = solved[r];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// The linear impulse (world) and angular impulse of a solution `x` in `basis`.
pub(crate) fn impulses(x: &[f64; 6], basis: &[Vec3; 3]) -> (Vec3, Vec3) {
    let j = basis[0] * x[0] as f32 + basis[1] * x[1] as f32 + basis[2] * x[2] as f32;
    (j, Vec3::new(x[3] as f32, x[4] as f32, x[5] as f32))
}

/// The basis of a joint's linear rows: world axes, or for a prismatic joint two directions
/// across its sliding axis (the rows that hold) and the axis itself (free, the spring's).
pub(crate) fn linear_basis(joint: &Joint, qa: Quat) -> [Vec3; 3] {
    match joint.kind {
        super::JointKind::ElasticPrismatic { .. } => {
            let axis = (qa * joint.axis_local).normalize();
            let (t1, t2) = axis.any_orthonormal_pair();
            [t1, t2, axis]
        }
        _ => [Vec3::X, Vec3::Y, Vec3::Z],
    }
}

/// Which rows a joint holds: the anchors (all three, or the two across a prismatic axis) and,
/// when it locks rotation, the three angular rows.
pub(crate) fn held_rows(joint: &Joint) -> [bool; 6] {
    let prismatic = matches!(joint.kind, super::JointKind::ElasticPrismatic { .. });
    let angular = joint.kind.locks_rotation();
    [true, true, !prismatic, angular, angular, angular]
}

/// Row values of a linear vector `lin` in `basis` and an angular vector `ang` in world axes.
pub(crate) fn rows(lin: Vec3, ang: Vec3, basis: &[Vec3; 3]) -> [f64; 6] {
    let d = |v: Vec3| -> DVec3 { v.as_dvec3() };
    let l = d(lin);
    let w = d(ang);
    [l.dot(d(basis[0])), l.dot(d(basis[1])), l.dot(d(basis[2])), w.x, w.y, w.z]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `turn` is the derivative of `advance`'s rotation: a small change δw of the angular
    /// velocity turns the advanced orientation by turn(w)·δw·dt (left perturbation), checked by
    /// central differences in f64-sized steps at spins up to 3 rad per step.
    #[test]
    fn turn_is_the_derivative_of_advance() {
        let q = Quat::from_rotation_y(0.4) * Quat::from_rotation_x(-1.1);
        let dt = 1.0 / 60.0;
        for w in [Vec3::new(0.3, -0.2, 0.1), Vec3::new(20.0, 5.0, -9.0), Vec3::new(-100.0, 140.0, 60.0)] {
            let t = turn(w, dt);
            for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
                let h = 1e-2;
                let plus = advance(q, w + axis * h, dt);
                let minus = advance(q, w - axis * h, dt);
                let numeric =
                    crate::sim::joints::rotation_vector((plus * minus.inverse()).normalize()) / (2.0 * h * dt);
                let analytic = t * axis;
                assert!(
                    (numeric - analytic).length() < 2e-3 * (1.0 + analytic.length()),
                    "w {w} axis {axis}: {numeric} vs {analytic}"
                );
            }
        }
    }

    /// The response matrix is the derivative of the predicted rows: applying a small impulse and
    /// predicting again moves the rows by the matrix column times the impulse times dt, for
    /// spinning bodies on a rigid joint (anchor rows with the two bodies spinning differently,
    /// orientation rows — linearized about zero error — with the two spinning alike).
    #[test]
    fn response_is_the_derivative_of_the_prediction() {
        use crate::sim::{BodyDesc, JointKind};
        let mesh = dentbend::mesh::subdivided_box(Vec3::new(0.3, 0.06, 0.06), [1, 1, 1]).unwrap();
        let spin_a = Vec3::new(3.0, -20.0, 7.0);
        for (spin_b, rows_checked) in [(Vec3::new(-9.0, 4.0, 25.0), 0..3), (spin_a, 0..6)] {
            let mut bodies = Vec::new();
            for (name, at, w) in [("a", Vec3::ZERO, spin_a), ("b", Vec3::X * 0.3, spin_b)] {
                let mut desc = BodyDesc::new(name, mesh.clone()).at(at);
                desc.angular_velocity = w;
                desc.orientation = Quat::from_rotation_z(0.3) * Quat::from_rotation_x(0.2);
                bodies.push(RigidBody::new(desc).unwrap());
            }
            let joint = Joint::new(&bodies, 0, 1, Vec3::X * 0.15, JointKind::Rigid).unwrap();
            let settings = WorldSettings { angular_damping: 0.5, ..Default::default() };
            let mob = mobilities(&bodies, &settings);
            let dt = settings.dt;
            let v: Vec<Motion> =
                bodies.iter().map(|b| Motion { linear: b.linear_velocity, angular: b.angular_velocity }).collect();
            let extra = vec![Motion { linear: Vec3::Y * 0.1, angular: Vec3::new(0.5, 0.0, -1.0) }; 2];
            let f = frame(&joint, &bodies, &mob, &v, Some(&extra), dt);
            let basis = [Vec3::X, Vec3::Y, Vec3::Z];
            let m = response(&mob[0], &mob[1], &f, &basis);
            let predicted = |v: &[Motion]| {
                let g = frame(&joint, &bodies, &mob, v, Some(&extra), dt);
                let angular = crate::sim::joints::rotation_vector((g.qb * (g.qa * joint.target).inverse()).normalize());
                rows(g.anchor_b - g.anchor_a, angular, &basis)
            };
            let axes = [Vec3::X, Vec3::Y, Vec3::Z];
            for c in 0..6 {
                let h = 1e-3;
                let (j, l) = if c < 3 { (basis[c] * h, Vec3::ZERO) } else { (Vec3::ZERO, axes[c - 3] * h) };
                let (mut plus, mut minus) = (v.clone(), v.clone());
                apply(&mut plus, &mob, &joint, &f, j, l);
                apply(&mut minus, &mob, &joint, &f, -j, -l);
                let (p, q) = (predicted(&plus), predicted(&minus));
                for r in rows_checked.clone() {
                    let numeric = (p[r] - q[r]) / (2.0 * f64::from(h) * f64::from(dt));
                    let close = (numeric - m[r][c]).abs() < 1e-2 * (1.0 + m[r][c].abs());
                    assert!(close, "row {r} col {c}: {numeric} vs {}", m[r][c]);
                }
            }
        }
    }
}
