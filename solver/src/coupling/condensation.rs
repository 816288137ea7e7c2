//! When to condense (paper §4.2): bodies joined by joints that have been quiet for a while are
//! simulated as one rigid cluster ([`World::condense`]); a hit that could bend them dissolves
//! the cluster for the step that takes it; afterwards every joint that did not bend is quiet
//! again, so the bodies on either side of a bending joint collapse into two clusters and a
//! detailed skeleton costs one joint's work.

use glam::Vec3;
use serde::Serialize;

use crate::sim::{CollisionEvent, JointKind, SimError, StepReport, World};
use dentbend::bend::JointRule;

/// How condensation decides.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CondenseSettings {
    /// A hit on a cluster closing faster than this dissolves it for the step, m/s (finite,
    /// ≥ 0). Hits on bending bodies with dynamic articulation also dissolve it above their
    /// split threshold.
    pub wake_speed: f32,
    /// A joint is quiet once it has not bent, turned or sprung for this long, s (finite, ≥ 0).
    pub quiet_time: f32,
    /// Relative angular speed below which a joint is not turning, rad/s (finite, > 0).
    pub quiet_spin: f32,
    /// Deflection of an elastic joint from its rest below which its spring is at rest, rad or
    /// m (finite, > 0).
    pub quiet_deflection: f32,
}

impl Default for CondenseSettings {
    /// Hits above 1 m/s wake; quiet after 0.1 s below 0.05 rad/s and 1 mrad (1 mm).
    fn default() -> Self {
        Self { wake_speed: 1.0, quiet_time: 0.1, quiet_spin: 0.05, quiet_deflection: 1e-3 }
    }
}

impl CondenseSettings {
    /// Checks every number.
    ///
    /// # Errors
    /// [`SimError::Invalid`] naming the first bad field.
    pub fn validate(&self) -> Result<(), SimError> {
        let bad = |what: &str, value: f32, reason| SimError::Invalid {
            what: format!("condensation {what}"),
            value: value.to_string(),
            reason,
        };
        for (what, value) in [("wake_speed", self.wake_speed), ("quiet_time", self.quiet_time)] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(bad(what, value, "must be finite and >= 0"));
            }
        }
        for (what, value) in [("quiet_spin", self.quiet_spin), ("quiet_deflection", self.quiet_deflection)] {
            if !(value.is_finite() && value > 0.0) {
                return Err(bad(what, value, "must be finite and > 0"));
            }
        }
        Ok(())
    }
}

/// The condensation state of a world: when each joint was last active.
#[derive(Debug, Clone)]
pub(crate) struct Condenser {
    pub settings: CondenseSettings,
    /// Per joint, the last step at which it bent, turned or sprung (or was woken by a hit).
    last_active: Vec<u64>,
}

impl Condenser {
    pub fn new(settings: CondenseSettings) -> Self {
        Self { settings, last_active: Vec::new() }
    }

    /// Clusters that `events` hit faster than the wake speed, or than `split_speed(body)` for a
    /// body that a fast hit would split (`None`: no such threshold), in order, without repeats.
    pub fn hit_clusters(
        &self,
        world: &World,
        events: &[CollisionEvent],
        split_speed: impl Fn(usize) -> Option<f32>,
    ) -> Vec<usize> {
        let mut hit = Vec::new();
        for event in events {
            for body in [event.a, event.b] {
                let Some(cluster) = world.cluster_of(body) else { continue };
                let threshold = split_speed(body).map_or(self.settings.wake_speed, |s| s.min(self.settings.wake_speed));
                if event.normal_speed > threshold && !hit.contains(&cluster) {
                    hit.push(cluster);
                }
            }
        }
        hit
    }

    /// Dissolves `clusters` (before the step is solved) and marks their joints active, so
    /// the hit is taken with every joint free.
    pub fn wake(&mut self, world: &mut World, clusters: &[usize]) -> Result<(), SimError> {
        let now = world.steps();
        self.grow(world);
        let mut woken = vec![false; world.bodies().len()];
        for &cluster in clusters {
            for member in world.cluster_members(cluster).unwrap_or_default() {
                woken[member] = true;
            }
            world.uncondense(cluster)?;
        }
        if clusters.is_empty() {
            return Ok(());
        }
        for joint in 0..world.joints().len() {
            if let Some((a, b)) = world.joint_ends(joint)
                && (woken[a] || woken[b])
            {
                self.last_active[joint] = now;
            }
        }
        Ok(())
    }

    /// After the step that stands: notes which joints were active, then condenses every group of
    /// bodies joined by quiet joints that is not one cluster yet (dissolving the smaller clusters
    /// it swallows). Bodies that cannot be condensed (static, dentable, triangle-mesh
    /// colliders) stay out of clusters.
    pub fn update(&mut self, world: &mut World, report: &StepReport) -> Result<(), SimError> {
        self.grow(world);
        let now = world.steps();
        for bend in &report.bends {
            self.last_active[bend.joint] = now;
        }
        let quiet_steps = (self.settings.quiet_time / world.settings().dt).ceil() as u64;
        let mut groups = crate::sim::UnionFind::new(world.bodies().len());
        let mut active = Vec::new();
        for joint in 0..world.joints().len() {
            if self.is_active(world, joint) {
                self.last_active[joint] = now;
                active.push(joint);
                continue;
            }
            if now.saturating_sub(self.last_active[joint]) < quiet_steps {
                active.push(joint);
                continue;
            }
            if let Some((a, b)) = world.joint_ends(joint)
                && world.clusterable(a)
                && world.clusterable(b)
            {
                groups.join(a, b);
            }
        }
        let mut members: Vec<Vec<usize>> = vec![Vec::new(); world.bodies().len()];
        for body in 0..world.bodies().len() {
            if world.clusterable(body) {
                members[groups.root(body)].push(body);
            }
        }
        let tangled = tangled_groups(world, &active, &mut groups);
        for group in members.into_iter().filter(|g| g.len() >= 2 && !tangled[groups.root(g[0])]) {
            let current = world.cluster_of(group[0]);
            if current.is_some_and(|c| world.cluster_members(c).is_some_and(|m| same_set(&m, &group))) {
                continue;
            }
            let swallowed: Vec<usize> = {
                let mut ids: Vec<usize> = group.iter().filter_map(|&b| world.cluster_of(b)).collect();
                ids.dedup();
                ids
            };
            for cluster in swallowed {
                if world.cluster_members(cluster).is_some() {
                    world.uncondense(cluster)?;
                }
            }
            if let Err(e) = world.condense(&group) {
                log::debug!("condensation skipped a group of {} bodies: {e}", group.len());
            }
        }
        Ok(())
    }

    /// Whether joint `joint` is bending, turning or springing now (joints resting inside a
    /// cluster are not).
    fn is_active(&self, world: &World, joint: usize) -> bool {
        let j = &world.joints()[joint];
        let bodies = world.bodies();
        let (a, b) = (&bodies[j.a()], &bodies[j.b()]);
        if a.is_condensed() && b.is_condensed() {
            return false;
        }
        if j.is_bending() {
            return true;
        }
        let relative_spin = b.angular_velocity - a.angular_velocity;
        match j.kind() {
            JointKind::Ball => {
                let centres = [a.position, b.position];
                swings_about_anchor(j.anchors(bodies), centres, relative_spin, self.settings.quiet_spin)
            }
            _ if relative_spin.length() > self.settings.quiet_spin => true,
            JointKind::Bend(JointRule::Elastic { .. }) => {
                j.deviation(bodies).is_some_and(|d| d.length() > self.settings.quiet_deflection)
            }
            JointKind::ElasticPrismatic { .. } => {
                j.separation(bodies).is_some_and(|s| s.length() > self.settings.quiet_deflection)
            }
            _ => false,
        }
    }

    /// Makes room for joints added since the last call (active now).
    fn grow(&mut self, world: &World) {
        let now = world.steps();
        self.last_active.resize(world.joints().len(), now);
    }
}

/// Whether the relative spin of a ball joint's bodies (rad/s) changes the pair's shape faster
/// than `quiet_spin`. A body spinning in place about the anchor changes nothing that matters
/// here: any spin of a body whose centre of mass (world, m) is at the anchor (a ball pinned at
/// its centre), and spin about the line from the anchor through its centre (a strut about its
/// axis). Only the rest of the relative spin keeps the joint active.
fn swings_about_anchor(
    anchors: Option<(Vec3, Vec3)>,
    centres: [Vec3; 2],
    relative_spin: Vec3,
    quiet_spin: f32,
) -> bool {
    /// Arms shorter than this put the centre of mass at the anchor, m.
    const AT_ANCHOR: f32 = 1e-3;
    let Some((on_a, on_b)) = anchors else { return relative_spin.length() > quiet_spin };
    let mut axes = [Vec3::ZERO; 2];
    for (axis, (anchor, centre)) in axes.iter_mut().zip([(on_a, centres[0]), (on_b, centres[1])]) {
        let arm = centre - anchor;
        if arm.length() < AT_ANCHOR {
            return false;
        }
        *axis = arm.normalize();
    }
    let normal = axes[0].cross(axes[1]);
    let residual = if normal.length() > AT_ANCHOR {
        relative_spin.dot(normal.normalize()).abs()
    } else {
        relative_spin.reject_from_normalized(axes[0]).length()
    };
    residual > quiet_spin
}

/// Which quiet groups (by their root in `groups`) must stay uncondensed: those that joints not
/// quiet yet (`active`) tie into a closed loop of groups. Condensed, such a loop would hold a
/// bending joint inside one rigid cluster (both its ends in one group) or between two clusters
/// also joined elsewhere (a strut bent twice, a corner whose three struts all bend): redundant
/// rows whose bend rates cannot all be met. Groups tied in a tree are condensed as usual.
fn tangled_groups(world: &World, active: &[usize], groups: &mut crate::sim::UnionFind) -> Vec<bool> {
    let n = world.bodies().len();
    let mut linked = crate::sim::UnionFind::new(n);
    let mut edges = Vec::new();
    for &joint in active {
        if let Some((a, b)) = world.joint_ends(joint)
            && world.clusterable(a)
            && world.clusterable(b)
        {
            let (ra, rb) = (groups.root(a), groups.root(b));
            linked.join(ra, rb);
            edges.push((ra, rb));
        }
    }
    // Per component of groups linked by active joints: edges and distinct groups. A connected
    // graph is a tree exactly when it has one edge fewer than nodes.
    let mut edge_count = vec![0usize; n];
    let mut node_count = vec![0usize; n];
    let mut counted = vec![false; n];
    for &(ra, rb) in &edges {
        let component = linked.root(ra);
        edge_count[component] += 1;
        for r in [ra, rb] {
            if !std::mem::replace(&mut counted[r], true) {
                node_count[component] += 1;
            }
        }
    }
    let mut tangled = vec![false; n];
    for &(ra, rb) in &edges {
        let component = linked.root(ra);
        if edge_count[component] >= node_count[component] {
            tangled[ra] = true;
            tangled[rb] = true;
        }
    }
    tangled
}

/// Whether two index lists hold the same bodies.
fn same_set(a: &[usize], b: &[usize]) -> bool {
    let (mut a, mut b) = (a.to_vec(), b.to_vec());
    a.sort_unstable();
    b.sort_unstable();
    a == b
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::{swings_about_anchor, tangled_groups};
    use crate::sim::{BodyDesc, ColliderKind, JointKind, UnionFind, World, WorldSettings};
    use dentbend::mesh;

    /// The default quiet spin, rad/s.
    const QUIET: f32 = 0.05;

    /// A ball pinned at its centre (arm 0) spins in place whatever its spin: never active, even
    /// at 100 rad/s, 2,000 times the quiet spin.
    #[test]
    fn a_ball_pinned_at_its_centre_never_swings() {
        let anchor = Vec3::new(0.3, 1.0, -0.2);
        let strut = anchor + Vec3::new(0.0, 0.0, 0.3);
        for spin in [Vec3::X, Vec3::Y, Vec3::Z, Vec3::new(1.0, -2.0, 0.5).normalize()] {
            assert!(!swings_about_anchor(Some((anchor, anchor)), [anchor, strut], 100.0 * spin, QUIET), "{spin}");
            assert!(!swings_about_anchor(Some((anchor, anchor)), [strut, anchor], 100.0 * spin, QUIET), "{spin}");
        }
    }

    /// Two struts in line through the anchor spinning about their common axis: in place, not
    /// active at 10 rad/s; the same spin about a perpendicular axis at 0.1 rad/s (twice the
    /// quiet spin) swings them: active.
    #[test]
    fn spin_about_a_strut_axis_is_quiet_and_a_swing_is_not() {
        let anchor = Vec3::new(0.0, 2.0, 0.0);
        let axis = Vec3::new(1.0, 1.0, 0.0).normalize();
        let centres = [anchor - 0.3 * axis, anchor + 0.3 * axis];
        let anchors = Some((anchor, anchor));
        assert!(!swings_about_anchor(anchors, centres, 10.0 * axis, QUIET));
        let across = axis.cross(Vec3::Z);
        assert!(swings_about_anchor(anchors, centres, 2.0 * QUIET * across, QUIET));
        // Half the quiet spin across: quiet.
        assert!(!swings_about_anchor(anchors, centres, 0.5 * QUIET * across, QUIET));
    }

    /// Two struts meeting at an anchor at 60° (a tetrahedron's corner): only the spin about the
    /// normal of their plane changes the angle between them. 10 rad/s in their plane is quiet;
    /// twice the quiet spin about the normal is active, whichever way.
    #[test]
    fn struts_at_an_angle_swing_only_about_their_plane_normal() {
        let anchor = Vec3::ZERO;
        let (u, v) = (Vec3::X, Vec3::new(0.5, 0.75f32.sqrt(), 0.0));
        let centres = [anchor + 0.3 * u, anchor + 0.3 * v];
        let anchors = Some((anchor, anchor));
        assert!(!swings_about_anchor(anchors, centres, 10.0 * u, QUIET));
        assert!(!swings_about_anchor(anchors, centres, 10.0 * (u + v).normalize(), QUIET));
        assert!(swings_about_anchor(anchors, centres, 2.0 * QUIET * Vec3::Z, QUIET));
        assert!(swings_about_anchor(anchors, centres, -2.0 * QUIET * Vec3::Z, QUIET));
    }

    /// Without anchors the whole relative spin counts.
    #[test]
    fn without_anchors_any_spin_faster_than_quiet_is_active() {
        let centres = [Vec3::ZERO, Vec3::X];
        assert!(swings_about_anchor(None, centres, 2.0 * QUIET * Vec3::X, QUIET));
        assert!(!swings_about_anchor(None, centres, 0.5 * QUIET * Vec3::X, QUIET));
    }

    /// A world of `n` free boxes in a row and ball joints between the given pairs.
    fn boxes(n: usize, joints: &[(usize, usize)]) -> World {
        let mut world = World::new(WorldSettings::default()).unwrap();
        let cube = mesh::subdivided_box(Vec3::splat(0.2), [1, 1, 1]).unwrap();
        for k in 0..n {
            let desc = BodyDesc::new(format!("box{k}"), cube.clone()).at(Vec3::new(k as f32, 1.0, 0.0));
            world.add(desc.collider(ColliderKind::Cuboid)).unwrap();
        }
        for &(a, b) in joints {
            let anchor = 0.5 * (world.bodies()[a].position + world.bodies()[b].position);
            world.add_joint(a, b, anchor, JointKind::Ball).unwrap();
        }
        world
    }

    /// Groups {0, 1} and {2, 3} (quiet joints 0 and 1) tied by two active joints (2 and 3) form
    /// a loop: both tangled.
    #[test]
    fn two_groups_joined_twice_are_tangled() {
        let world = boxes(4, &[(0, 1), (2, 3), (1, 2), (0, 3)]);
        let mut groups = UnionFind::new(4);
        groups.join(0, 1);
        groups.join(2, 3);
        let tangled = tangled_groups(&world, &[2, 3], &mut groups);
        assert!(tangled[groups.root(0)] && tangled[groups.root(2)], "{tangled:?}");
        // Only one of the two ties active: a tree of two groups, not tangled.
        let tangled = tangled_groups(&world, &[2], &mut groups);
        assert!(!tangled[groups.root(0)] && !tangled[groups.root(2)], "{tangled:?}");
    }

    /// A chain of three single-body groups tied by two active joints is a tree: not tangled.
    /// An active joint with both ends in one group (a bending joint inside it) is a loop.
    #[test]
    fn a_chain_is_not_tangled_and_a_joint_inside_a_group_is() {
        let world = boxes(5, &[(0, 1), (1, 2), (3, 4)]);
        let mut groups = UnionFind::new(5);
        groups.join(3, 4);
        let tangled = tangled_groups(&world, &[0, 1, 2], &mut groups);
        assert!((0..3).all(|k| !tangled[groups.root(k)]), "chain tangled: {tangled:?}");
        assert!(tangled[groups.root(3)], "a group holding an active joint is not tangled: {tangled:?}");
    }
}
