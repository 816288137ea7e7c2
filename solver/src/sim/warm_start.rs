//! Warm starting: the contact phase of a step starts from the impulses the same contacts needed
//! in the step before, so a resting pile holds its weight from the first sweep instead of
//! re-solving it from zero (which leaves centimetres per second of jitter in a deep pile).
//!
//! Contacts are matched per pair by their point and normal in body a's frame: a contact whose
//! point moved less than [`MATCH_DISTANCE`] and whose normal turned less than [`MATCH_TURN`]
//! relative to a is the same contact, and each of last step's contacts is matched to at most one
//! of this step's (the nearest pairs first). A last-step impulse handed to two contacts, or to a
//! contact facing another way, is an impulse no contact needed: where many contacts crowd
//! together — two condensed tetrahedra whose struts and balls touch in dozens of places, points
//! a centimetre apart with normals in every direction — the wrong seeds squeezed the pair with
//! hundreds of newton-seconds that twelve sweeps could not take back, and the contact phase
//! handed out kinetic energy step after step.

use rustc_hash::FxHashMap;

use glam::{Quat, Vec3};

use super::solver::Constraint;

/// How far a contact point may move in body a's frame between two steps and still be matched, m.
pub(crate) const MATCH_DISTANCE: f32 = 0.02;
/// How far a contact normal may turn in body a's frame between two steps and still be matched,
/// rad (20°).
pub(crate) const MATCH_TURN: f32 = 0.35;

/// One contact's impulses at the end of the last contact phase.
#[derive(Debug, Clone, Copy)]
struct Cached {
    /// The contact point in body a's frame (relative to its centre of mass), m.
    local: Vec3,
    /// The contact normal in body a's frame (unit).
    normal_local: Vec3,
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
    /// Seeds each constraint's starting impulses from the cached contact of the same pair that
    /// [`pair_up`] matches it with. `orientation(i)` is body i's orientation.
    pub fn seed(&self, constraints: &mut [Constraint], orientation: impl Fn(usize) -> Quat) {
        if self.pairs.is_empty() {
            return;
        }
        // A pair's constraints are contiguous (the parts reorder pairs, not points).
        let mut start = 0;
        while start < constraints.len() {
            let pair = constraints[start].pair;
            let end = start + constraints[start..].iter().take_while(|c| c.pair == pair).count();
            let run = &mut constraints[start..end];
            start = end;
            let Some(cached) = self.pairs.get(&(run[0].a, run[0].b)) else { continue };
            let turn = orientation(run[0].a).inverse();
            let now: Vec<(Vec3, Vec3)> = run.iter().map(|c| (turn * c.ra, turn * c.normal)).collect();
            let before: Vec<(Vec3, Vec3)> = cached.iter().map(|k| (k.local, k.normal_local)).collect();
            for (c, matched) in run.iter_mut().zip(pair_up(&now, &before)) {
                let Some(k) = matched else { continue };
                let old = &cached[k];
                // All of last step's impulse: the impulses are accumulated and clamped, so the
                // sweeps can still take back what an opening contact does not need, while any
                // fraction below 1 makes every step re-solve part of a pile's weight that 12
                // sweeps cannot recover — 0.9 left a 1,500-sphere pile holding ~90 % of its
                // weight and friction limits (μ × normal impulse) short by as much, so it crept
                // at ~1 cm/s and never slept.
                c.warm_normal = old.normal;
                let friction = old.friction - old.friction.dot(c.normal) * c.normal;
                c.warm_tangent = [friction.dot(c.tangents[0]), friction.dot(c.tangents[1])];
                c.warm_rolling = old.rolling;
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
            let turn = orientation(c.a).inverse();
            let (local, normal_local) = (turn * c.ra, turn * c.normal);
            let rolling = c.rolling_impulse();
            self.pairs.entry((c.a, c.b)).or_default().push(Cached { local, normal_local, normal, friction, rolling });
        }
    }

    /// Drops the cached contacts of body `body` (its shape was replaced).
    pub fn forget(&mut self, body: usize) {
        self.pairs.retain(|&(a, b), _| a != body && b != body);
    }
}

/// Matches one pair's contacts `now` to its cached contacts `before`, both (point, unit normal)
/// in body a's frame: each contact gets the cached one within [`MATCH_DISTANCE`] and
/// [`MATCH_TURN`] of it, closest pairs first, and each cached contact goes to at most one
/// contact. Returns per contact of `now` the index into `before` it takes, if any.
fn pair_up(now: &[(Vec3, Vec3)], before: &[(Vec3, Vec3)]) -> Vec<Option<usize>> {
    let cosine = MATCH_TURN.cos();
    // Every (distance², contact, cached contact) close enough in point and normal.
    let mut candidates: Vec<(f32, usize, usize)> = Vec::new();
    for (i, &(point, normal)) in now.iter().enumerate() {
        for (k, &(old_point, old_normal)) in before.iter().enumerate() {
            let d2 = old_point.distance_squared(point);
            if d2 <= MATCH_DISTANCE * MATCH_DISTANCE && old_normal.dot(normal) >= cosine {
                candidates.push((d2, i, k));
            }
        }
    }
    candidates.sort_unstable_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)).then(x.2.cmp(&y.2)));
    let mut matched = vec![None; now.len()];
    let mut taken = vec![false; before.len()];
    for (_, i, k) in candidates {
        if matched[i].is_none() && !taken[k] {
            matched[i] = Some(k);
            taken[k] = true;
        }
    }
    matched
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two contacts crowding one cached contact: only the nearer takes its impulse; a contact
    /// at the same point whose normal faces the other way (another feature of a compound
    /// collider) takes none; a contact 3 cm away takes none; the second cached contact goes
    /// to the contact near it.
    #[test]
    fn each_cached_contact_seeds_one_contact_facing_its_way() {
        let up = Vec3::Y;
        let before = [(Vec3::ZERO, up), (Vec3::new(0.1, 0.0, 0.0), up)];
        let now = [
            (Vec3::new(0.005, 0.0, 0.0), up),
            (Vec3::new(0.002, 0.0, 0.0), up),
            (Vec3::new(0.001, 0.0, 0.0), -up),
            (Vec3::new(0.0, 0.0, 0.03), up),
            (Vec3::new(0.1, 0.0, 0.005), Vec3::new(0.2, 1.0, 0.0).normalize()),
        ];
        assert_eq!(pair_up(&now, &before), vec![None, Some(0), None, None, Some(1)]);
    }

    /// A normal turned by more than `MATCH_TURN` is another contact; less, the same.
    #[test]
    fn a_turned_normal_is_another_contact() {
        let turned = |angle: f32| Quat::from_rotation_z(angle) * Vec3::Y;
        let before = [(Vec3::ZERO, Vec3::Y)];
        assert_eq!(pair_up(&[(Vec3::ZERO, turned(MATCH_TURN * 0.9))], &before), vec![Some(0)]);
        assert_eq!(pair_up(&[(Vec3::ZERO, turned(MATCH_TURN * 1.1))], &before), vec![None]);
    }
}
