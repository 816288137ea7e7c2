//! Sleeping by islands. Bodies joined by contacts (or joints) form an island; an island falls
//! asleep when every body in it has been still for `sleep_time`, and wakes as a whole when a
//! moving body touches any of its bodies. "Still" is judged on velocities smoothed over
//! [`SMOOTHING_TIME`], so the sub-millimetre settling of a deep pile (speculative contacts close
//! tiny gaps at gap/dt, then stop) does not keep it awake while a rolling ball does.

use glam::Vec3;

use super::union_find::UnionFind;
use super::{BodyKind, RigidBody, WorldSettings};

/// Time constant of the velocity smoothing, s.
pub(crate) const SMOOTHING_TIME: f32 = 0.1;

/// After a step: smooths each awake dynamic body's velocities, counts its still time (speed =
/// centre plus rim at `radius[i]` m, its bounding radius), and puts to sleep every island (bodies
/// joined by `links`) whose bodies have all been still for `sleep_time`. `step` numbers the
/// islands so two islands never share an id.
pub(crate) fn settle(
    bodies: &mut [RigidBody],
    radius: &[f32],
    links: &[(usize, usize)],
    settings: &WorldSettings,
    step: u64,
) {
    if settings.sleep_time <= 0.0 {
        return;
    }
    let alpha = settings.dt / (SMOOTHING_TIME + settings.dt);
    for (body, &radius) in bodies
        .iter_mut()
        .zip(radius)
        .filter(|(b, _)| b.kind == BodyKind::Dynamic && !b.activity.asleep && b.is_simulated())
    {
        let activity = &mut body.activity;
        activity.smoothed[0] += alpha * (body.linear_velocity - activity.smoothed[0]);
        activity.smoothed[1] += alpha * (body.angular_velocity - activity.smoothed[1]);
        let speed = activity.smoothed[0].length() + activity.smoothed[1].length() * radius;
        activity.still_for = if speed < settings.sleep_speed { activity.still_for + settings.dt } else { 0.0 };
    }
    let awake = |b: &RigidBody| b.kind == BodyKind::Dynamic && !b.activity.asleep && b.is_simulated();
    let mut islands = UnionFind::new(bodies.len());
    for &(i, j) in links {
        if awake(&bodies[i]) && awake(&bodies[j]) {
            islands.join(i, j);
        }
    }
    // An island sleeps only if its stillest-for-least body has been still long enough.
    let roots: Vec<Option<usize>> = (0..bodies.len()).map(|i| awake(&bodies[i]).then(|| islands.root(i))).collect();
    let mut least = vec![f32::INFINITY; bodies.len()];
    for (body, root) in bodies.iter().zip(&roots) {
        if let Some(root) = *root {
            least[root] = least[root].min(body.activity.still_for);
        }
    }
    let bound = bodies.len() as u64 + 1;
    for (body, root) in bodies.iter_mut().zip(&roots) {
        if let Some(root) = root.filter(|&r| least[r] >= settings.sleep_time) {
            body.activity.asleep = true;
            body.activity.island = step * bound + root as u64;
            body.linear_velocity = Vec3::ZERO;
            body.angular_velocity = Vec3::ZERO;
        }
    }
}

/// Wakes every body of the island body `k` sleeps with.
pub(crate) fn wake_island(bodies: &mut [RigidBody], k: usize) {
    if !bodies[k].activity.asleep {
        return;
    }
    let island = bodies[k].activity.island;
    for body in bodies.iter_mut().filter(|b| b.activity.asleep && b.activity.island == island && b.is_simulated()) {
        body.activity.wake();
    }
}
