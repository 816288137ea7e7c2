//! One contact per pair of things for denting: a projectile that touches several sub-bodies of a
//! bending body in one step (a ball landing on a joint touches both bones) makes one impact on
//! the body's mesh, not one per sub-body, or the dents would stack.

use std::collections::HashMap;

use glam::Vec3;

use crate::sim::CollisionEvent;

/// A side of a contact: a plain world body, or a bending body (index in [`Bending::bodies`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Side {
    Body(usize),
    Bending(usize),
}

/// `events` with, for every pair of sides of which at least one is a bending body, the pair's
/// events merged into one (at the place of its first): the contact point, normal, relative
/// velocity and normal speed averaged with weights |impulse| (the world's own events average a
/// pair's contact points that way; equal weights when no impulse was applied), the impulses
/// summed, and the bodies those of the heaviest-weighted event. A pair with one event keeps it
/// as it is, as do events between two sub-bodies of one bending body and between plain bodies.
/// `owner`: per world body, the bending body (index in [`Bending::bodies`](super::Bending::bodies))
/// whose sub-body it is (see [`Bending::owners`](super::Bending::owners)).
pub(crate) fn merge_contacts(owner: impl Fn(usize) -> Option<usize>, events: &[CollisionEvent]) -> Vec<CollisionEvent> {
    let side = |index: usize| owner(index).map_or(Side::Body(index), Side::Bending);
    // Each output slot: an event kept, or the index of a group (pair of sides, the first a
    // bending body; its events oriented from that side, and the first one as given).
    let mut slots: Vec<Result<CollisionEvent, usize>> = Vec::new();
    let mut groups: Vec<(Vec<Oriented>, CollisionEvent)> = Vec::new();
    let mut group_of: HashMap<(Side, Side), usize> = HashMap::new();
    for event in events {
        let (a, b) = (side(event.a), side(event.b));
        let (key, oriented) = match (a, b) {
            (Side::Body(_), Side::Body(_)) => {
                slots.push(Ok(*event));
                continue;
            }
            _ if a == b => {
                slots.push(Ok(*event));
                continue;
            }
            (Side::Bending(_), _) => ((a, b), Oriented::from(event, false)),
            _ => ((b, a), Oriented::from(event, true)),
        };
        match group_of.get(&key) {
            Some(&g) => groups[g].0.push(oriented),
            None => {
                group_of.insert(key, groups.len());
                slots.push(Err(groups.len()));
                groups.push((vec![oriented], *event));
            }
        }
    }
    slots
        .into_iter()
        .map(|slot| match slot {
            Ok(event) => event,
            Err(g) if groups[g].0.len() == 1 => groups[g].1,
            Err(g) => merge(&groups[g].0),
        })
        .collect()
}

/// An event seen from one side: `own` the bending body's sub-body, `other` the other body;
/// normal from `own` towards `other`, velocity of `other` relative to `own`, impulse on `other`.
#[derive(Debug, Clone, Copy)]
struct Oriented {
    own: usize,
    other: usize,
    point: Vec3,
    normal: Vec3,
    relative_velocity: Vec3,
    normal_speed: f32,
    impulse: Vec3,
}

impl Oriented {
    /// `event` seen from its body b when `flip`, else from a.
    fn from(event: &CollisionEvent, flip: bool) -> Self {
        let s = if flip { -1.0 } else { 1.0 };
        let (own, other) = if flip { (event.b, event.a) } else { (event.a, event.b) };
        Self {
            own,
            other,
            point: event.point,
            normal: s * event.normal,
            relative_velocity: s * event.relative_velocity,
            normal_speed: event.normal_speed,
            impulse: s * event.impulse,
        }
    }
}

/// One event for a group (not empty), bodies ordered a < b as the world's events are.
fn merge(list: &[Oriented]) -> CollisionEvent {
    let weights: Vec<f32> = list.iter().map(|o| o.impulse.length()).collect();
    let total: f32 = weights.iter().sum();
    let weights: Vec<f32> = match total > 0.0 && total.is_finite() {
        true => weights.iter().map(|w| w / total).collect(),
        false => vec![1.0 / list.len() as f32; list.len()],
    };
    let mean = |f: fn(&Oriented) -> Vec3| list.iter().zip(&weights).map(|(o, w)| f(o) * *w).sum::<Vec3>();
    let heaviest = &list[(0..list.len()).max_by(|&i, &j| weights[i].total_cmp(&weights[j])).unwrap_or(0)];
    let normal = mean(|o| o.normal).try_normalize().unwrap_or(heaviest.normal);
    let (own, other) = (heaviest.own, heaviest.other);
    // Back to a < b: seen from a, so flipped when `own` is b.
    let s = if own < other { 1.0 } else { -1.0 };
    CollisionEvent {
        a: own.min(other),
        b: own.max(other),
        point: mean(|o| o.point),
        normal: s * normal,
        relative_velocity: s * mean(|o| o.relative_velocity),
        normal_speed: list.iter().zip(&weights).map(|(o, w)| o.normal_speed * w).sum(),
        impulse: s * list.iter().map(|o| o.impulse).sum::<Vec3>(),
    }
}
