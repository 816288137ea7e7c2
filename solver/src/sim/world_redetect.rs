//! Detecting again after a few bodies changed. The bending layer detects, looks at what the
//! step is about to hit, splits the bodies hit hard and wakes the clusters hit (paper §4), then
//! must detect again on the edited world. Only pairs with an edited body can have changed: the
//! others keep the contacts found the first time, and the broad and narrow phases run only for
//! the edited bodies. The result is the one a fresh [`World::detect`] would give.
//!
//! A child module of `world` (declared there with `#[path]`), beside `world_step`.

use std::time::Instant;

use super::World;
use super::world_step::Detection;
use crate::sim::PairContacts;

/// Above this share of changed simulated bodies, [`World::redetect`] detects afresh: testing
/// each changed body against every other costs more than the sweep.
const FRESH_SHARE: f32 = 0.05;

impl World {
    /// Detects again after edits of a few bodies since `previous` (a detection of this step):
    /// pairs of unchanged bodies keep `previous`'s contacts, pairs with a changed or new body
    /// go through the broad and narrow phase. Detects afresh instead after a detection of
    /// another step, with fewer bodies than `previous` saw, after an edit that let a pair
    /// collide again (a skipped pair of unchanged bodies is not looked at), or with more than
    /// [`FRESH_SHARE`] of the simulated bodies changed (each is tested against all).
    pub(crate) fn redetect(&mut self, previous: Detection) -> Detection {
        let started = Instant::now();
        let stale = previous.step != self.steps
            || self.bodies.len() < previous.bodies
            || previous.filters_lifted != self.filters_lifted;
        if stale {
            return self.detect();
        }
        let changed: Vec<bool> = (0..self.bodies.len())
            .map(|i| previous.seen.get(i).is_none_or(|seen| !seen.matches(&self.bodies[i])))
            .collect();
        let live = self.live();
        let changed_live = live.iter().filter(|&&i| changed[i]).count();
        if changed_live as f32 > FRESH_SHARE * live.len() as f32 {
            return self.detect();
        }
        let (radius, reach) = self.extents();
        let unchanged_pair = |&(a, b): &(usize, usize)| !changed[a] && !changed[b] && !self.skip_pair(a, b);
        let kept_pairs: Vec<(usize, usize)> = previous.pairs.iter().copied().filter(unchanged_pair).collect();
        let kept_found: Vec<PairContacts> =
            previous.found.into_iter().filter(|p| unchanged_pair(&(p.a, p.b))).collect();
        let new_pairs = self.pairs_with_changed(&live, &changed, &reach);
        let new_found = self.contacts_of(&new_pairs, &reach);
        let pairs = merge_sorted(kept_pairs, new_pairs, |&pair| pair);
        let found = merge_sorted(kept_found, new_found, |p| (p.a, p.b));
        self.finish_detection(started, radius, pairs, found)
    }

    /// The broad phase's pairs with at least one `changed` body, sorted: each changed simulated
    /// body's swept box against every simulated (`live`) body's.
    fn pairs_with_changed(&self, live: &[usize], changed: &[bool], reach: &[f32]) -> Vec<(usize, usize)> {
        let boxes = self.swept_boxes(live, reach);
        let mut pairs = Vec::new();
        for (x, &i) in live.iter().enumerate().filter(|&(_, &i)| changed[i]) {
            for (y, &j) in live.iter().enumerate() {
                // A pair of two changed bodies is met twice: kept from its first body.
                if j == i || changed[j] && j < i || !boxes[x].overlaps(&boxes[y]) {
                    continue;
                }
                let pair = (i.min(j), i.max(j));
                if !self.skip_pair(pair.0, pair.1) {
                    pairs.push(pair);
                }
            }
        }
        pairs.sort_unstable();
        pairs
    }
}

/// The union of two lists sorted by `key` (no key in both), sorted.
fn merge_sorted<T, K: Ord>(a: Vec<T>, b: Vec<T>, key: impl Fn(&T) -> K) -> Vec<T> {
    let mut out = Vec::with_capacity(a.len() + b.len());
    let (mut a, mut b) = (a.into_iter().peekable(), b.into_iter().peekable());
    loop {
        let take_a = match (a.peek(), b.peek()) {
            (Some(x), Some(y)) => key(x) < key(y),
            (Some(_), None) => true,
            (None, Some(_)) => false,
            (None, None) => return out,
        };
        out.extend(if take_a { a.next() } else { b.next() });
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::super::{World, WorldSettings};
    use crate::sim::{BodyDesc, BodyKind, ColliderKind, JointKind};
    use dentbend::mesh;

    /// After edits like a split's (a body rebuilt with another collider, a body moved, a body
    /// sped up, a body added), detecting again from the first detection finds exactly the
    /// pairs and contacts, in the same order, that a fresh detection of the edited world finds.
    #[test]
    fn detecting_again_after_edits_matches_a_fresh_detection() {
        let mut world = World::new(WorldSettings::default()).unwrap();
        let cube = mesh::subdivided_box(Vec3::splat(0.2), [1, 1, 1]).unwrap();
        let floor = mesh::subdivided_box(Vec3::new(4.0, 0.2, 4.0), [1, 1, 1]).unwrap();
        world.add(BodyDesc::new("floor", floor).kind(BodyKind::Static).at(Vec3::new(0.0, -0.1, 0.0))).unwrap();
        let desc = |k: usize, at: Vec3| BodyDesc::new(format!("box{k}"), cube.clone()).at(at);
        // A 5 × 5 grid of touching boxes on the floor, two layers.
        let mut k = 0;
        for layer in 0..2 {
            for x in 0..5 {
                for z in 0..5 {
                    let at = Vec3::new(x as f32 * 0.2, 0.1 + layer as f32 * 0.2, z as f32 * 0.2);
                    world.add(desc(k, at).collider(ColliderKind::ConvexHull)).unwrap();
                    k += 1;
                }
            }
        }
        for _ in 0..3 {
            world.step();
        }
        let first = world.detect();
        assert!(first.found.len() > 50, "the grid touches itself and the floor: {} pairs", first.found.len());
        world.rebuild_body(8, desc(7, Vec3::new(0.3, 0.12, 0.2)).collider(ColliderKind::Cuboid)).unwrap();
        world.bodies_mut()[12].position += Vec3::new(0.05, 0.0, 0.0);
        world.bodies_mut()[30].linear_velocity = Vec3::new(0.0, -3.0, 0.0);
        world.add(desc(99, Vec3::new(0.4, 0.5, 0.4))).unwrap();
        let mut fresh_world = world.clone();
        let again = world.redetect(first);
        let fresh = fresh_world.detect();
        assert_eq!(again.pairs, fresh.pairs);
        assert_eq!(again.found, fresh.found);
        assert_eq!(again.seen.len(), fresh.seen.len());
    }

    /// An edit that lets two unchanged bodies collide again (a joint moved off their pair) is
    /// seen: their contacts are found, as a fresh detection finds them.
    #[test]
    fn a_lifted_joint_filter_brings_the_pair_back() {
        let mut world = World::new(WorldSettings::default()).unwrap();
        let cube = mesh::subdivided_box(Vec3::splat(0.2), [1, 1, 1]).unwrap();
        for k in 0..3 {
            let at = Vec3::new(0.0, 0.0, k as f32 * 0.2);
            world.add(BodyDesc::new(format!("box{k}"), cube.clone()).at(at).collider(ColliderKind::Cuboid)).unwrap();
        }
        let joint = world.add_joint(0, 1, Vec3::new(0.0, 0.0, 0.1), JointKind::Ball).unwrap();
        let first = world.detect();
        assert!(!first.pairs.contains(&(0, 1)), "a joined pair is skipped");
        world.retarget_joint(joint, 1, 2).unwrap();
        let mut fresh_world = world.clone();
        let again = world.redetect(first);
        let fresh = fresh_world.detect();
        assert!(fresh.found.iter().any(|p| (p.a, p.b) == (0, 1)), "the touching pair collides again");
        assert_eq!(again.pairs, fresh.pairs);
        assert_eq!(again.found, fresh.found);
    }
}
