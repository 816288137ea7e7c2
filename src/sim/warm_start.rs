//! Warm starting: the contact phase of a step starts from the impulses the same contacts needed
//! in the step before, so a resting pile holds its weight from the first sweep instead of
//! re-solving it from zero (which leaves centimetres per second of jitter in a deep pile).
//!
//! Contacts are matched per pair by their point in body a's frame: a point that moved less than
//! [`MATCH_DISTANCE`] relative to a is the same contact.

use rustc_hash::FxHashMap;

use glam::{Quat, Vec3};

use super::solver::Constraint;

/// How far a contact point may move in body a's frame between two steps and still be matched, m.
pub(crate) const MATCH_DISTANCE: f32 = 0.02;

/// One contact's impulses at the end of the last contact phase.
#[derive(Debug, Clone, Copy)]
struct Cached {
    /// The contact point in body a's frame (relative to its centre of mass), m.
    local: Vec3,
    /// Normal impulse, N·s.
    normal: f32,
    /// Friction impulse, world, N·s.
    friction: Vec3,
    /// Rolling-resistance angular impulse on b, world, N·m·s.
    rolling: Vec3,
}

/// Last step's contact impulses, per pair of bodies.
#[derive(Debug, Clone, Default)]
pub(crate) struct ContactCache {
    pairs: FxHashMap<(usize, usize), Vec<Cached>>,
}

impl ContactCache {
    /// Seeds each constraint's starting impulses from the cached contact of the same pair whose
    /// point is nearest in body a's frame. `orientation(i)` is body i's orientation.
    pub fn seed(&self, constraints: &mut [Constraint], orientation: impl Fn(usize) -> Quat) {
        if self.pairs.is_empty() {
            return;
        }
        for c in constraints.iter_mut() {
            let Some(cached) = self.pairs.get(&(c.a, c.b)) else { continue };
            let local = orientation(c.a).inverse() * c.ra;
            let nearest = cached
                .iter()
                .map(|k| (k.local.distance_squared(local), k))
                .min_by(|x, y| x.0.total_cmp(&y.0))
                .filter(|(d2, _)| *d2 <= MATCH_DISTANCE * MATCH_DISTANCE);
            if let Some((_, k)) = nearest {
                // All of last step's impulse: the impulses are accumulated and clamped, so the
                // sweeps can still take back what an opening contact does not need, while any
                // fraction below 1 makes every step re-solve part of a pile's weight that 12
                // sweeps cannot recover — 0.9 left a 1,500-sphere pile holding ~90 % of its
                // weight and friction limits (μ × normal impulse) short by as much, so it crept
                // at ~1 cm/s and never slept.
                c.warm_normal = k.normal;
                let friction = k.friction - k.friction.dot(c.normal) * c.normal;
                c.warm_tangent = [friction.dot(c.tangents[0]), friction.dot(c.tangents[1])];
                c.warm_rolling = k.rolling;
            }
        }
    }

    /// Remembers the contact phase's impulses of this step's constraints.
    pub fn store(&mut self, constraints: &[Constraint], orientation: impl Fn(usize) -> Quat) {
        self.pairs.clear();
        for c in constraints {
            let (normal, friction) = c.contact_impulses();
            if normal <= 0.0 {
                continue;
            }
            let local = orientation(c.a).inverse() * c.ra;
            let rolling = c.rolling_impulse();
            self.pairs.entry((c.a, c.b)).or_default().push(Cached { local, normal, friction, rolling });
        }
    }

    /// Drops the cached contacts of body `body` (its shape was replaced).
    pub fn forget(&mut self, body: usize) {
        self.pairs.retain(|&(a, b), _| a != body && b != body);
    }
}
