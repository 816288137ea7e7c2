//! A step's contact constraints split into spatial parts that sequential impulses sweep at the
//! same time.
//!
//! A sweep of sequential impulses visits the constraints one after another, each seeing the
//! velocities the previous ones left. Constraints that share no moving body cannot see each
//! other, so they can be visited on different threads. The moving bodies that touch a contact
//! are cut into [`PARTS`] slabs along the widest axis of their centres, each slab holding about
//! as many contacts; a constraint whose moving bodies all lie in one slab belongs to that part,
//! and one across a cut to the boundary. A sweep visits the parts' constraints in parallel, each
//! part on its own copy of the velocities, then the boundary's constraints on the merged
//! velocities. Every constraint is still visited once per sweep, in an order the scene fixes
//! (not the thread count), so a run gives the same result on any machine.
//!
//! The constraints are reordered once per step so that each part's are contiguous, in their
//! original relative order (a pair's constraints stay together), the boundary's last.

use rayon::prelude::*;

use glam::Vec3;

/// A constraint as the parts see it: the two bodies it joins (indices into the step's bodies).
pub(crate) trait Joins: Copy + Send + Sync {
    /// The two bodies.
    fn bodies(&self) -> [usize; 2];
}

/// A body as the parts see it: where it is and whether it moves during the step.
pub(crate) trait Placed: Copy + Send + Sync {
    /// Centre of mass, world, m.
    fn position(&self) -> Vec3;
    /// Fixed during the step (static, kinematic, asleep or frozen).
    fn is_fixed(&self) -> bool;
}

/// Spatial parts a step's constraints are split into.
pub(crate) const PARTS: usize = 2;

/// Steps with fewer constraints are swept in their original order on one thread: a parallel
/// sweep's fixed cost (copying the velocities, waking a thread) is worth it only on many.
pub(crate) const MIN_PARALLEL: usize = 2048;

/// Where a step's parts lie in its (reordered) constraints and which bodies each part changes.
#[derive(Debug, Clone, Default)]
pub(crate) struct Parts {
    /// Part p's constraints are `bounds[p]..bounds[p + 1]`; the boundary's are
    /// `bounds[PARTS]..` (all of them when the step is swept serially).
    bounds: [usize; PARTS + 1],
    /// Per part, the moving bodies in its slab (merged back after each parallel sweep).
    members: [Vec<usize>; PARTS],
    /// Moving bodies the boundary's constraints change, with their part.
    crossing: Vec<(usize, usize)>,
}

impl Parts {
    /// Splits `constraints` (over `bodies`) into parts, reordering them; a step with fewer than
    /// [`MIN_PARALLEL`] constraints is left in order, all of it boundary.
    pub(crate) fn split<C: Joins, B: Placed>(constraints: &mut Vec<C>, bodies: &[B]) -> Self {
        if constraints.len() < MIN_PARALLEL {
            return Self::default();
        }
        let part_of = slabs(constraints, bodies);
        // A constraint's part: that of its moving bodies when they agree, else the boundary.
        let class = |c: &C| {
            let parts = c.bodies().map(|i| part_of[i]);
            match parts {
                [Some(p), Some(q)] if p == q => p,
                [Some(p), None] | [None, Some(p)] => p,
                _ => PARTS,
            }
        };
        let classes: Vec<usize> = constraints.iter().map(class).collect();
        let mut bounds = [0usize; PARTS + 1];
        for &k in &classes {
            if k < PARTS {
                bounds[k + 1] += 1;
            }
        }
        for p in 0..PARTS {
            bounds[p + 1] += bounds[p];
        }
        // Stable counting sort by class.
        let mut next = [0usize; PARTS + 1];
        next[..].copy_from_slice(&bounds);
        let mut order = vec![0usize; constraints.len()];
        for (k, &class) in classes.iter().enumerate() {
            order[next[class]] = k;
            next[class] += 1;
        }
        let sorted: Vec<C> = order.iter().map(|&k| constraints[k]).collect();
        *constraints = sorted;
        let mut members: [Vec<usize>; PARTS] = Default::default();
        for (i, part) in part_of.iter().enumerate() {
            if let Some(p) = *part {
                members[p].push(i);
            }
        }
        let mut crossing: Vec<(usize, usize)> = constraints[bounds[PARTS]..]
            .iter()
            .flat_map(|c| c.bodies())
            .filter_map(|i| part_of[i].map(|p| (i, p)))
            .collect();
        crossing.sort_unstable();
        crossing.dedup();
        Self { bounds, members, crossing }
    }

    /// Whether the step's sweeps run part by part (else in the original order, serially).
    fn parallel(&self) -> bool {
        self.bounds[PARTS] > 0
    }

    /// `count` sweeps of `visit` over the constraints `selection` (indices, increasing): each
    /// part's in parallel on its own copy of `bodies`, then the boundary's, each in its order.
    pub(crate) fn sweeps<C: Joins, B: Placed>(
        &self,
        bodies: &mut [B],
        constraints: &mut [C],
        selection: &[usize],
        count: usize,
        visit: impl Fn(&mut [B], &mut C) + Sync,
    ) {
        debug_assert!(selection.is_sorted(), "a selection of constraints is sorted");
        let boundary_start = self.bounds[PARTS];
        let boundary = &selection[selection.partition_point(|&k| k < boundary_start)..];
        if !self.parallel() || boundary.len() == selection.len() {
            for _ in 0..count {
                for &k in selection {
                    visit(bodies, &mut constraints[k]);
                }
            }
            return;
        }
        // Each part's selected constraints, numbered within its own slice of the constraints.
        let (parts, boundary_constraints) = constraints.split_at_mut(boundary_start);
        let mut work: Vec<(&mut [C], Vec<usize>, Vec<B>)> = Vec::with_capacity(PARTS);
        let mut rest = parts;
        for p in 0..PARTS {
            let (start, end) = (self.bounds[p], self.bounds[p + 1]);
            let (mine, after) = rest.split_at_mut(end - start);
            rest = after;
            let from = selection.partition_point(|&k| k < start);
            let to = selection.partition_point(|&k| k < end);
            let local: Vec<usize> = selection[from..to].iter().map(|&k| k - start).collect();
            work.push((mine, local, bodies.to_vec()));
        }
        for _ in 0..count {
            work.par_iter_mut().for_each(|(mine, local, copy)| {
                for &k in local.iter() {
                    visit(copy, &mut mine[k]);
                }
            });
            for ((_, _, copy), members) in work.iter().zip(&self.members) {
                for &i in members {
                    bodies[i] = copy[i];
                }
            }
            for &k in boundary {
                visit(bodies, &mut boundary_constraints[k - boundary_start]);
            }
            for &(i, p) in &self.crossing {
                work[p].2[i] = bodies[i];
            }
        }
    }
}

/// Each moving body's part (`None` for fixed bodies and bodies without contacts): slabs along
/// the widest axis of the touching bodies' centres, cut where the running count of contacts
/// on the bodies passes each p / [`PARTS`] of the total.
fn slabs<C: Joins, B: Placed>(constraints: &[C], bodies: &[B]) -> Vec<Option<usize>> {
    let mut weight = vec![0usize; bodies.len()];
    for c in constraints {
        for i in c.bodies() {
            if !bodies[i].is_fixed() {
                weight[i] += 1;
            }
        }
    }
    let mut touched: Vec<usize> = (0..bodies.len()).filter(|&i| weight[i] > 0).collect();
    let mut part_of = vec![None; bodies.len()];
    let Some(&first) = touched.first() else { return part_of };
    let (mut low, mut high) = (bodies[first].position(), bodies[first].position());
    for &i in &touched {
        low = low.min(bodies[i].position());
        high = high.max(bodies[i].position());
    }
    let axis = (high - low).max_position();
    touched.sort_by(|&i, &j| bodies[i].position()[axis].total_cmp(&bodies[j].position()[axis]).then(i.cmp(&j)));
    let total: usize = touched.iter().map(|&i| weight[i]).sum();
    let mut running = 0;
    for &i in &touched {
        // The part whose share of the total the running count is in.
        let part = (running * PARTS / total.max(1)).min(PARTS - 1);
        part_of[i] = Some(part);
        running += weight[i];
    }
    part_of
}

#[cfg(test)]
mod tests {
    use glam::{Mat3, Vec3};

    use super::*;

    use crate::sim::solver::{self, Constraint, SolverBody};
    use crate::sim::{ContactPoint, PairContacts};

    /// Constraints of one contact point per pair (a, b), halfway between the bodies.
    fn constraints_between(pairs: &[(usize, usize)], bodies: &[SolverBody]) -> Vec<Constraint> {
        let contacts: Vec<PairContacts> = pairs
            .iter()
            .map(|&(a, b)| {
                let middle = 0.5 * (bodies[a].position + bodies[b].position);
                let point =
                    ContactPoint { on_a: middle, on_b: middle, normal: Vec3::X, distance: 0.0, part_a: 0, part_b: 0 };
                PairContacts { a, b, points: vec![point] }
            })
            .collect();
        solver::constraints(&contacts, bodies, 0.01, |_, _| (0.0, 0.5, 0.0))
    }

    /// A made-up visit that moves both bodies by their inverse masses (fixed ones stay).
    fn even_out(bodies: &mut [SolverBody], c: &mut Constraint) {
        let change = 0.5 * (bodies[c.b].linear - bodies[c.a].linear) + c.ra * 0.01;
        bodies[c.a].linear += change * bodies[c.a].inverse_mass;
        bodies[c.b].linear -= change * bodies[c.b].inverse_mass;
        bodies[c.b].angular += c.rb.cross(change) * bodies[c.b].inverse_mass;
    }

    fn body(x: f32, inverse_mass: f32) -> SolverBody {
        SolverBody {
            linear: Vec3::ZERO,
            angular: Vec3::ZERO,
            position: Vec3::new(x, 0.0, 0.0),
            inverse_mass,
            inverse_inertia: Mat3::IDENTITY * inverse_mass,
            height: 0.0,
        }
    }

    /// A row of bodies along x, each touching the next and a fixed floor (body 0): the cut
    /// falls in the middle, the one contact across it is the boundary's, and the floor is in
    /// no part.
    #[test]
    fn a_row_splits_in_the_middle_with_one_contact_across() {
        let n = 1200;
        let mut bodies = vec![body(0.0, 0.0)];
        bodies.extend((1..=n).map(|i| body(i as f32, 1.0)));
        let mut pairs = Vec::new();
        for i in 1..=n {
            pairs.push((0, i));
            if i < n {
                pairs.push((i, i + 1));
            }
        }
        let mut constraints = constraints_between(&pairs, &bodies);
        let original = constraints.clone();
        let parts = Parts::split(&mut constraints, &bodies);
        assert!(parts.parallel());
        assert_eq!(constraints.len(), original.len(), "no constraint lost or repeated");
        assert_eq!(constraints.len() - parts.bounds[PARTS], 1, "one contact crosses the cut");
        assert_eq!(parts.crossing.len(), 2, "the two bodies of that contact");
        let part_sizes = [parts.bounds[1] - parts.bounds[0], parts.bounds[2] - parts.bounds[1]];
        assert!(part_sizes[0].abs_diff(part_sizes[1]) <= 4, "parts hold about as many contacts: {part_sizes:?}");
        assert!(parts.members.iter().all(|m| !m.contains(&0)), "the fixed floor is in no part");
        // Within each part the original order is kept.
        for p in 0..PARTS {
            let slice = &constraints[parts.bounds[p]..parts.bounds[p + 1]];
            let keys: Vec<(usize, usize)> = slice.iter().map(|c| (c.a, c.b)).collect();
            let position = |key: &(usize, usize)| original.iter().position(|c| (c.a, c.b) == *key).unwrap();
            assert!(keys.windows(2).all(|w| position(&w[0]) < position(&w[1])), "part {p} reordered");
        }
    }

    /// Part-by-part sweeps give the same velocities as visiting the reordered constraints one
    /// after another in the same order (parts first, boundary last): the parts share no moving
    /// body, so running them side by side changes nothing.
    #[test]
    fn parallel_sweeps_match_the_same_order_run_serially() {
        let n = 1500;
        let mut bodies = vec![body(0.0, 0.0)];
        bodies.extend((1..=n).map(|i| body(i as f32 * 0.5, 1.0 + (i % 7) as f32 * 0.1)));
        for (i, b) in bodies.iter_mut().enumerate() {
            b.linear = Vec3::new((i as f32 * 0.37).sin(), -1.0, 0.0);
        }
        let mut pairs = Vec::new();
        for i in 1..=n {
            pairs.push((0, i));
            if i + 2 <= n {
                pairs.push((i, i + 2));
            }
        }
        let mut constraints = constraints_between(&pairs, &bodies);
        let parts = Parts::split(&mut constraints, &bodies);
        assert!(parts.parallel());
        let visit = even_out;
        let (mut serial_bodies, mut serial_constraints) = (bodies.clone(), constraints.clone());
        for _ in 0..3 {
            for c in serial_constraints.iter_mut() {
                visit(&mut serial_bodies, c);
            }
        }
        let all: Vec<usize> = (0..constraints.len()).collect();
        parts.sweeps(&mut bodies, &mut constraints, &all, 3, visit);
        for (i, (x, y)) in bodies.iter().zip(&serial_bodies).enumerate() {
            assert_eq!((x.linear, x.angular), (y.linear, y.angular), "body {i}");
        }
    }
}
