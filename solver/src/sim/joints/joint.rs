//! Joints between two bodies in maximal coordinates: what they hold (anchor, target relative
//! orientation), how they hold it ([`JointKind`]), their validation, and what they measure.

use glam::{Quat, Vec3};
use serde::Serialize;

use crate::sim::error::invalid;
use crate::sim::{BodyKind, RigidBody, SimError};
use dentbend::bend::JointRule;

/// How a [`Joint`] holds its two bodies together. Every kind keeps the two anchors together
/// (a point joint, except [`ElasticPrismatic`](Self::ElasticPrismatic), which lets them slide
/// along its axis); they differ in what they do with the relative orientation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JointKind {
    /// Ball (point) joint: the anchors coincide, the relative orientation is free.
    Ball,
    /// Rigid joint: the anchors coincide and the relative orientation is locked at its target.
    Rigid,
    /// A bending joint (paper §4.1, §4.3): a point joint whose relative orientation follows the
    /// rule, plastic (rigid until the angular impulse needed to keep it rigid within one step
    /// exceeds its strength, then bent to a new target) or elastic (a torsional spring and
    /// damper pulling it back to the rest orientation captured when the joint is made,
    /// integrated analytically).
    Bend(JointRule),
    /// Elastic prismatic joint (paper §4.3, "both angular and prismatic"): the relative
    /// orientation is locked, the anchors may slide apart along `axis` only, and a linear spring
    /// and damper pull them back together, integrated analytically.
    ElasticPrismatic {
        /// Sliding direction in world axes when the joint is made (finite, non-zero; it turns
        /// with body a afterwards).
        axis: Vec3,
        /// Spring constant, N/m (finite, > 0).
        stiffness: f32,
        /// Damping coefficient, N·s/m (finite, ≥ 0).
        damping: f32,
    },
}

impl JointKind {
    /// Checks every number.
    ///
    /// # Errors
    /// [`SimError::Invalid`] naming the first bad field.
    pub fn validate(&self) -> Result<(), SimError> {
        let positive = |what: &str, v: f32| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(invalid(format!("joint {what}"), v, "must be finite and > 0"))
            }
        };
        let non_negative = |what: &str, v: f32| {
            if v.is_finite() && v >= 0.0 {
                Ok(())
            } else {
                Err(invalid(format!("joint {what}"), v, "must be finite and >= 0"))
            }
        };
        match *self {
            Self::Ball | Self::Rigid => Ok(()),
            Self::Bend(JointRule::Plastic { strength, damping_constant, damping_proportional }) => {
                positive("strength", strength)?;
                non_negative("damping_constant", damping_constant)?;
                non_negative("damping_proportional", damping_proportional)
            }
            Self::Bend(JointRule::Elastic { stiffness, damping }) => {
                positive("stiffness", stiffness)?;
                non_negative("damping", damping)
            }
            Self::ElasticPrismatic { axis, stiffness, damping } => {
                if !axis.is_finite() || axis.length_squared() < 1e-12 {
                    return Err(invalid("joint axis", axis, "must be finite and non-zero"));
                }
                positive("stiffness", stiffness)?;
                non_negative("damping", damping)
            }
        }
    }

    /// Whether the relative orientation is held by the joint's impulses (rigid, plastic,
    /// prismatic) rather than left free or to a spring.
    pub(crate) fn locks_rotation(&self) -> bool {
        matches!(self, Self::Rigid | Self::Bend(JointRule::Plastic { .. }) | Self::ElasticPrismatic { .. })
    }
}

/// A plastic joint bent during a step (reported in
/// [`StepReport::bends`](crate::sim::StepReport::bends)).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BendEvent {
    /// Index of the joint in [`World::joints`](crate::sim::World::joints).
    pub joint: usize,
    /// Angle between the joint's target relative orientation before and after the step, rad.
    pub angle: f32,
    /// Angle between the joint's rest orientation (when it was made) and its target now, rad.
    pub total_angle: f32,
}

/// A joint between bodies `a` and `b` at an anchor point fixed in both bodies, holding a target
/// relative orientation `q_a⁻¹·q_b` (see [`JointKind`]). Made by
/// [`World::add_joint`](crate::sim::World::add_joint).
#[derive(Debug, Clone)]
pub struct Joint {
    pub(crate) a: usize,
    pub(crate) b: usize,
    pub(crate) kind: JointKind,
    /// The anchor relative to each centre of mass, in that body's axes, m.
    pub(crate) local_a: Vec3,
    pub(crate) local_b: Vec3,
    /// The prismatic sliding direction in body a's axes (unit; +x for other kinds).
    pub(crate) axis_local: Vec3,
    /// Wanted relative orientation `q_a⁻¹·q_b`.
    pub(crate) target: Quat,
    /// The relative orientation when the joint was made.
    pub(crate) rest: Quat,
    /// Angular impulse applied to b (a got the opposite) by this step's pre-stabilization, N·m·s.
    pub(crate) accumulated: Vec3,
    /// Whether this step's pre-stabilization clamped the accumulated angular impulse.
    pub(crate) clamped: bool,
    /// Damped relative angular velocity a bending plastic joint keeps, in body a's axes, rad/s
    /// (zero when the joint is not bending).
    pub(crate) bend_rate: Vec3,
    /// An elastic joint's analytic spring velocity at the end of the last step minus the
    /// velocity its impulse gave the bodies (the secant that lands on the analytic position):
    /// along the spring axis, in body a's axes, rad/s (prismatic: the x component, m/s).
    pub(crate) spring_lag: Vec3,
}

impl Joint {
    /// A joint between `bodies[a]` and `bodies[b]` at world point `anchor`, holding the bodies'
    /// current relative orientation.
    pub(crate) fn new(
        bodies: &[RigidBody],
        a: usize,
        b: usize,
        anchor: Vec3,
        kind: JointKind,
    ) -> Result<Self, SimError> {
        let count = bodies.len();
        for (what, index) in [("joint body a", a), ("joint body b", b)] {
            if index >= count {
                return Err(invalid(what, index, "is not a body of the world"));
            }
        }
        if a == b {
            return Err(invalid("joint bodies", (a, b), "must be two different bodies"));
        }
        if !anchor.is_finite() {
            return Err(invalid("joint anchor", anchor, "must be finite"));
        }
        kind.validate()?;
        let (body_a, body_b) = (&bodies[a], &bodies[b]);
        if body_a.kind != BodyKind::Dynamic && body_b.kind != BodyKind::Dynamic {
            return Err(invalid("joint bodies", (a, b), "at least one must be dynamic"));
        }
        let inverse_a = body_a.orientation.inverse();
        let axis_local = match kind {
            JointKind::ElasticPrismatic { axis, .. } => inverse_a * axis.normalize(),
            _ => Vec3::X,
        };
        let rest = (inverse_a * body_b.orientation).normalize();
        Ok(Self {
            a,
            b,
            kind,
            local_a: inverse_a * (anchor - body_a.position),
            local_b: body_b.orientation.inverse() * (anchor - body_b.position),
            axis_local,
            target: rest,
            rest,
            accumulated: Vec3::ZERO,
            clamped: false,
            bend_rate: Vec3::ZERO,
            spring_lag: Vec3::ZERO,
        })
    }

    /// Keeps the joint where it is in the world when `body` (one of its two) is rebuilt from
    /// pose `old` (centre of mass, orientation) to pose `new`: anchors, sliding axis, target and
    /// rest are re-expressed in the new body frame.
    pub(crate) fn rebase(&mut self, body: usize, old: (Vec3, Quat), new: (Vec3, Quat)) {
        // The new frame relative to the old one: q_new = q_old · turn.
        let turn = (old.1.inverse() * new.1).normalize();
        let inverse_new = new.1.inverse();
        if self.a == body {
            self.local_a = inverse_new * (old.0 + old.1 * self.local_a - new.0);
            self.axis_local = turn.inverse() * self.axis_local;
            self.target = (turn.inverse() * self.target).normalize();
            self.rest = (turn.inverse() * self.rest).normalize();
        }
        if self.b == body {
            self.local_b = inverse_new * (old.0 + old.1 * self.local_b - new.0);
            self.target = (self.target * turn).normalize();
            self.rest = (self.rest * turn).normalize();
        }
    }

    /// Index of body a.
    pub fn a(&self) -> usize {
        self.a
    }

    /// Index of body b.
    pub fn b(&self) -> usize {
        self.b
    }

    /// The kind.
    pub fn kind(&self) -> &JointKind {
        &self.kind
    }

    /// The target relative orientation `q_a⁻¹·q_b` (changed by plastic bends).
    pub fn target(&self) -> Quat {
        self.target
    }

    /// The relative orientation `q_a⁻¹·q_b` when the joint was made (an elastic joint's rest).
    pub fn rest(&self) -> Quat {
        self.rest
    }

    /// Net plastic bend: the angle between the rest and the target relative orientations, rad.
    pub fn bend_angle(&self) -> f32 {
        angle_between(self.rest, self.target)
    }

    /// Whether a plastic joint is still bending after a hit (its damped relative angular velocity
    /// has not died out yet).
    pub fn is_bending(&self) -> bool {
        self.bend_rate != Vec3::ZERO
    }

    /// World positions of the anchor as carried by body a and by body b, m; `None` when `bodies`
    /// is not the joint's world.
    pub fn anchors(&self, bodies: &[RigidBody]) -> Option<(Vec3, Vec3)> {
        let (a, b) = (bodies.get(self.a)?, bodies.get(self.b)?);
        Some((a.position + a.orientation * self.local_a, b.position + b.orientation * self.local_b))
    }

    /// b's anchor minus a's anchor, world, m (zero when the joint holds).
    pub fn separation(&self, bodies: &[RigidBody]) -> Option<Vec3> {
        self.anchors(bodies).map(|(a, b)| b - a)
    }

    /// The prismatic sliding direction now (unit, world axes); +x of body a for other kinds.
    pub fn axis(&self, bodies: &[RigidBody]) -> Option<Vec3> {
        bodies.get(self.a).map(|a| a.orientation * self.axis_local)
    }

    /// The relative orientation now, `q_a⁻¹·q_b`.
    pub fn relative_orientation(&self, bodies: &[RigidBody]) -> Option<Quat> {
        let (a, b) = (bodies.get(self.a)?, bodies.get(self.b)?);
        Some((a.orientation.inverse() * b.orientation).normalize())
    }

    /// Rotation vector (axis × angle, rad, in body a's axes) that takes the target relative
    /// orientation to the current one: zero when the angular constraint holds; for an elastic
    /// joint, the spring's displacement θ − θ₀.
    pub fn deviation(&self, bodies: &[RigidBody]) -> Option<Vec3> {
        self.relative_orientation(bodies).map(|relative| rotation_vector(relative * self.target.inverse()))
    }
}

/// Rotation vector (unit axis × angle in [0, π], rad) of a unit quaternion, shortest way round.
pub(crate) fn rotation_vector(q: Quat) -> Vec3 {
    let q = if q.w < 0.0 { -q } else { q };
    let xyz = Vec3::new(q.x, q.y, q.z);
    let sine = xyz.length();
    if sine < 1e-7 {
        // angle ≈ 2·sin(angle/2)
        return 2.0 * xyz;
    }
    xyz * (2.0 * sine.atan2(q.w) / sine)
}

/// Angle between two orientations, rad, in [0, π].
pub(crate) fn angle_between(p: Quat, q: Quat) -> f32 {
    rotation_vector((p.inverse() * q).normalize()).length()
}
