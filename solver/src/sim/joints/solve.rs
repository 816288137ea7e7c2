//! Solving the joints' linearized rows for impulses, all joints of a group together.
//!
//! Joints that share a body that takes impulses form a group. Each group is solved exactly: its
//! rows' response to every joint impulse is assembled into one sparse matrix, its joints ordered
//! (reverse Cuthill–McKee) so that the matrix is banded — a chain becomes block-tridiagonal — and
//! solved by banded Gaussian elimination (see `band`), linear in the length of a chain, where
//! Gauss–Seidel over a chain needs hundreds of sweeps. Plastic joints clamp by active set: a
//! joint whose accumulated angular impulse would pass its strength gets that impulse fixed on the
//! strength sphere and the rest of the group is solved again. A group whose matrix is singular
//! or too wide falls back to Gauss–Seidel over its joints, one exact 6×6 block solve per visit.

use std::collections::VecDeque;

use rustc_hash::FxHashMap;

use glam::Vec3;

use super::system::{self, Frame, Matrix, Mobility, Motion};
use super::{Joint, JointKind, band, plastic};
use crate::sim::union_find::UnionFind;
use dentbend::bend::JointRule;

/// Most Gauss–Seidel sweeps over a group that cannot be solved directly.
const SWEEPS: usize = 48;
/// Levenberg–Marquardt damping of a group whose plain system is singular.
const REDUNDANT_DAMPING: f64 = 1e-9;

/// A joint's rows linearized at the current velocities.
pub(crate) struct Rows {
    pub frame: Frame,
    pub basis: [Vec3; 3],
    /// Row values now, in velocity units (m/s, rad/s): the solve drives them to zero.
    pub error: [f64; 6],
    /// Row tolerances in the same units.
    pub tolerance: [f64; 6],
    /// The joint's own 6×6 response.
    pub matrix: Matrix,
}

/// Changes `v` by joint impulses that zero every joint's linearized held rows. With `clamp`,
/// plastic joints cap their accumulated angular impulse at their strength (and record whether
/// they did); without it they are rigid. `damping` > 0 makes the direct solves
/// Levenberg–Marquardt steps (least squares with the normal equations' diagonal raised by that
/// fraction), shorter and safe where the rows are nearly dependent. `groups` are the joints
/// with rows grouped (see [`groups`]); groups whose held rows are all within their tolerances
/// are left alone.
pub(crate) fn solve_rows(
    joints: &mut [Joint],
    groups: &[Vec<usize>],
    rows: &[Option<Rows>],
    mob: &[Mobility],
    v: &mut [Motion],
    clamp: bool,
    damping: f64,
) {
    let within = |joints: &[Joint], k: usize| {
        let (Some(r), h) = (&rows[k], held(&joints[k])) else { return true };
        (0..6).all(|i| !h[i] || r.error[i].abs() <= r.tolerance[i])
    };
    for group in groups {
        if group.iter().all(|&k| within(joints, k)) {
            continue;
        }
        let layout = Layout::new(joints, group, mob);
        solve_group(&layout, joints, rows, mob, v, clamp, damping);
    }
}

/// [`solve_rows`] for the joints of one group laid out by [`Layout::new`]; `rows` outside it
/// are not read.
pub(crate) fn solve_group(
    layout: &Layout,
    joints: &mut [Joint],
    rows: &[Option<Rows>],
    mob: &[Mobility],
    v: &mut [Motion],
    clamp: bool,
    damping: f64,
) {
    // Redundant joints (closed loops of rigid joints) make the plain system singular; the
    // slightly damped least-squares step still solves it.
    let solved = direct(layout, joints, rows, mob, v, clamp, damping)
        || damping == 0.0 && direct(layout, joints, rows, mob, v, clamp, REDUNDANT_DAMPING);
    if !solved {
        gauss_seidel(joints, &layout.group, rows, mob, v, clamp);
    }
}

/// The rows a joint's impulses solve for (plastic joints all six; the clamp is separate).
fn held(joint: &Joint) -> [bool; 6] {
    system::held_rows(joint)
}

/// Joints with rows (`has_rows(joint)`), grouped by shared bodies that take impulses.
pub(crate) fn groups(joints: &[Joint], has_rows: impl Fn(usize) -> bool, mob: &[Mobility]) -> Vec<Vec<usize>> {
    let mut sets = UnionFind::new(joints.len());
    let mut owner: FxHashMap<usize, usize> = FxHashMap::default();
    for (k, joint) in joints.iter().enumerate() {
        if !has_rows(k) {
            continue;
        }
        for body in [joint.a, joint.b] {
            if !system::takes_impulses(&mob[body]) {
                continue;
            }
            if let Some(&other) = owner.get(&body) {
                sets.join(k, other);
            } else {
                owner.insert(body, k);
            }
        }
    }
    let mut out: Vec<Vec<usize>> = Vec::new();
    let mut slot: FxHashMap<usize, usize> = FxHashMap::default();
    for k in (0..joints.len()).filter(|&k| has_rows(k)) {
        let r = sets.root(k);
        let index = *slot.entry(r).or_insert_with(|| {
            out.push(Vec::new());
            out.len() - 1
        });
        out[index].push(k);
    }
    out
}

/// How one group's system is laid out: its unknowns (the held rows of each joint, in band
/// order) and which joints' rows each joint's impulses reach. It depends only on which joints
/// share bodies and on their kinds, so Newton iterations on one group reuse it.
pub(crate) struct Layout {
    /// The group's joints, sorted (as [`groups`] makes them).
    group: Vec<usize>,
    /// Unknown i is row `.1` of joint `.0`, in band order.
    unknowns: Vec<(usize, usize)>,
    /// Per joint (by place in `group`), its unknowns' indices by row (`usize::MAX`: not held).
    slots: Vec<[usize; 6]>,
    /// Per joint (by place in `group`), the group's joints sharing a body with it, itself
    /// included, sorted.
    neighbours: Vec<Vec<usize>>,
}

impl Layout {
    /// The layout of `group` (sorted joint indices that share bodies taking impulses).
    pub(crate) fn new(joints: &[Joint], group: &[usize], mob: &[Mobility]) -> Self {
        let incidence = GroupIndex::new(joints, group, mob);
        let neighbours: Vec<Vec<usize>> = group.iter().map(|&k| incidence.neighbours(&joints[k])).collect();
        let order = order(group, &neighbours);
        let mut unknowns: Vec<(usize, usize)> = Vec::with_capacity(6 * group.len());
        let mut slots: Vec<[usize; 6]> = vec![[usize::MAX; 6]; group.len()];
        for &k in &order {
            let h = held(&joints[k]);
            let slot = &mut slots[incidence.local(k)];
            for r in (0..6).filter(|&r| h[r]) {
                slot[r] = unknowns.len();
                unknowns.push((k, r));
            }
        }
        Self { group: group.to_vec(), unknowns, slots, neighbours }
    }

    /// Joint `joint`'s place in the group.
    fn local(&self, joint: usize) -> usize {
        self.group.partition_point(|&k| k < joint)
    }

    /// Index of the unknown for row `r` of joint `k`.
    fn position(&self, k: usize, r: usize) -> usize {
        self.slots[self.local(k)][r]
    }
}

/// Solves one group exactly. Returns `false` (nothing applied) when its matrix is singular or
/// too wide.
fn direct(
    layout: &Layout,
    joints: &mut [Joint],
    rows: &[Option<Rows>],
    mob: &[Mobility],
    v: &mut [Motion],
    clamp: bool,
    damping: f64,
) -> bool {
    let (group, index) = (&layout.group, &layout.unknowns);
    let n = index.len();
    // The matrix by entries (row, column, value): column q·c is the held rows' response to a
    // unit impulse on row c of joint q.
    let mut entries: Vec<(usize, usize, f64)> = Vec::with_capacity(n * 12);
    let axes = [Vec3::X, Vec3::Y, Vec3::Z];
    for (col, &(q, c)) in index.iter().enumerate() {
        let Some(rq) = &rows[q] else { continue };
        let (j, l) = if c < 3 { (rq.basis[c], Vec3::ZERO) } else { (Vec3::ZERO, axes[c - 3]) };
        let jq = &joints[q];
        let kick = system::kick(&mob[jq.a], &mob[jq.b], &rq.frame, j, l);
        let moved = |body: usize| {
            let mut m = Motion::default();
            for (who, delta) in [(jq.a, kick.0), (jq.b, kick.1)] {
                if who == body {
                    m.linear += delta.linear;
                    m.angular += delta.angular;
                }
            }
            m
        };
        for &p in &layout.neighbours[layout.local(q)] {
            let Some(rp) = &rows[p] else { continue };
            let jp = &joints[p];
            let (lin, ang) = system::drift(&rp.frame, moved(jp.a), moved(jp.b));
            let values = system::rows(lin, ang, &rp.basis);
            let h = held(jp);
            for r in (0..6).filter(|&r| h[r] && values[r] != 0.0) {
                entries.push((layout.position(p, r), col, values[r]));
            }
        }
    }
    let matrix = band::Sparse::by_columns(n, &entries);
    let rhs: Vec<f64> = index.iter().map(|&(k, r)| rows[k].as_ref().map_or(0.0, |x| -x.error[r])).collect();
    // Active set over the plastic joints' angular impulses.
    // Per joint of the group (by its place in `group`), a plastic joint's angular impulse fixed
    // on its strength sphere.
    let mut fixed: Vec<Option<Vec3>> = vec![None; group.len()];
    let mut x;
    loop {
        let solution = if fixed.iter().all(Option::is_none) {
            band::solve(&matrix, &rhs, damping)
        } else {
            let is_fixed = |i: usize| index[i].1 >= 3 && fixed[layout.local(index[i].0)].is_some();
            let fixed_impulse = |col: usize| {
                let (k, c) = index[col];
                fixed[layout.local(k)].map_or(0.0, |l| f64::from(l[c - 3]))
            };
            let (sub, b, free) = matrix.without(&rhs, is_fixed, fixed_impulse);
            band::solve(&sub, &b, damping).map(|solution| {
                let mut full = vec![0.0f64; n];
                for (&col, value) in free.iter().zip(solution) {
                    full[col] = value;
                }
                full
            })
        };
        let Some(solution) = solution else {
            return false;
        };
        x = solution;
        if !clamp || !clamp_plastic(joints, group, &mut fixed, |k, c| x[layout.position(k, c)]) {
            break;
        }
    }
    for (&k, &fixed) in group.iter().zip(&fixed) {
        let Some(r) = &rows[k] else { continue };
        let h = held(&joints[k]);
        let mut solution = [0.0f64; 6];
        for c in (0..6).filter(|&c| h[c]) {
            solution[c] = x[layout.position(k, c)];
        }
        let (j, mut l) = system::impulses(&solution, &r.basis);
        if let Some(fixed) = fixed {
            l = fixed;
        }
        if clamp && matches!(joints[k].kind, JointKind::Bend(JointRule::Plastic { .. })) {
            joints[k].clamped = fixed.is_some();
            joints[k].accumulated += l;
        }
        system::apply(v, mob, &joints[k], &r.frame, j, l);
    }
    true
}

/// Fixes on its strength sphere the angular impulse of every plastic joint of `group` not fixed
/// yet (`fixed`, by place in `group`) whose accumulated angular impulse plus the solution's
/// (`x(joint, row)`, rows 3–5) would pass its strength. Returns whether any was fixed (the
/// group must be solved again).
fn clamp_plastic(
    joints: &[Joint],
    group: &[usize],
    fixed: &mut [Option<Vec3>],
    x: impl Fn(usize, usize) -> f64,
) -> bool {
    let mut changed = false;
    for (&k, fixed) in group.iter().zip(fixed.iter_mut()) {
        let JointKind::Bend(JointRule::Plastic { strength, .. }) = joints[k].kind else { continue };
        if fixed.is_some() {
            continue;
        }
        let l = Vec3::new(x(k, 3) as f32, x(k, 4) as f32, x(k, 5) as f32);
        let wanted = joints[k].accumulated + l;
        if wanted.length() > strength {
            *fixed = Some(wanted * (strength / wanted.length()) - joints[k].accumulated);
            changed = true;
        }
    }
    changed
}

/// A group's joints (sorted, as [`groups`] makes them) by their place in it, and which of them
/// act on each body that takes impulses.
struct GroupIndex<'g> {
    group: &'g [usize],
    /// (body, joint) pairs sorted by body.
    incidence: Vec<(usize, usize)>,
}

impl<'g> GroupIndex<'g> {
    fn new(joints: &[Joint], group: &'g [usize], mob: &[Mobility]) -> Self {
        debug_assert!(group.is_sorted(), "joint groups are sorted");
        let mut incidence: Vec<(usize, usize)> = group
            .iter()
            .flat_map(|&k| [(joints[k].a, k), (joints[k].b, k)])
            .filter(|&(body, _)| system::takes_impulses(&mob[body]))
            .collect();
        incidence.sort_unstable();
        Self { group, incidence }
    }

    /// Joint `joint`'s place in the group.
    fn local(&self, joint: usize) -> usize {
        self.group.partition_point(|&k| k < joint)
    }

    /// The group's joints on `body`.
    fn on(&self, body: usize) -> impl Iterator<Item = usize> + '_ {
        let start = self.incidence.partition_point(|&(b, _)| b < body);
        self.incidence[start..].iter().take_while(move |&&(b, _)| b == body).map(|&(_, k)| k)
    }

    /// The group's joints sharing a body with `joint`, itself included, sorted, without repeats.
    fn neighbours(&self, joint: &Joint) -> Vec<usize> {
        let mut out: Vec<usize> = self.on(joint.a).chain(self.on(joint.b)).collect();
        out.sort_unstable();
        out.dedup();
        out
    }
}

/// The group's joints in reverse Cuthill–McKee order (breadth first from a joint of least
/// coupling, neighbours by increasing coupling, reversed), which keeps coupled joints close and
/// the system's band narrow: a chain becomes block-tridiagonal. `neighbours` are per joint (by
/// place in `group`), each including the joint itself.
fn order(group: &[usize], neighbours: &[Vec<usize>]) -> Vec<usize> {
    let local = |k: usize| group.partition_point(|&g| g < k);
    let degree = |k: usize| neighbours[local(k)].len();
    let mut seen = vec![false; group.len()];
    let mut out = Vec::with_capacity(group.len());
    let mut starts: Vec<usize> = group.to_vec();
    starts.sort_by_key(|&k| (degree(k), k));
    let mut queue = VecDeque::with_capacity(group.len());
    let mut next: Vec<usize> = Vec::new();
    for &start in &starts {
        if std::mem::replace(&mut seen[local(start)], true) {
            continue;
        }
        queue.push_back(start);
        while let Some(k) = queue.pop_front() {
            out.push(k);
            next.clear();
            next.extend(neighbours[local(k)].iter().copied().filter(|&p| !seen[local(p)]));
            next.sort_by_key(|&p| (degree(p), p));
            for &p in &next {
                seen[local(p)] = true;
                queue.push_back(p);
            }
        }
    }
    out.reverse();
    out
}

/// Gauss–Seidel over one group: each visit removes a joint's current linearized error (its
/// error at linearization plus the drift of the velocity changes since) by an exact block solve.
fn gauss_seidel(
    joints: &mut [Joint],
    group: &[usize],
    rows: &[Option<Rows>],
    mob: &[Mobility],
    v: &mut [Motion],
    clamp: bool,
) {
    let start = v.to_vec();
    for sweep in 0..SWEEPS {
        let mut worst = 0.0f64;
        for i in 0..group.len() {
            let k = group[if sweep % 2 == 0 { i } else { group.len() - 1 - i }];
            let Some(r) = &rows[k] else { continue };
            worst = worst.max(visit(&mut joints[k], r, mob, v, &start, clamp));
        }
        if worst < 1.0 {
            break;
        }
    }
}

/// One Gauss–Seidel visit; returns the joint's largest row error before it, in tolerances.
fn visit(joint: &mut Joint, r: &Rows, mob: &[Mobility], v: &mut [Motion], start: &[Motion], clamp: bool) -> f64 {
    let change = |i: usize| Motion { linear: v[i].linear - start[i].linear, angular: v[i].angular - start[i].angular };
    let (linear, angular) = system::drift(&r.frame, change(joint.a), change(joint.b));
    let moved = system::rows(linear, angular, &r.basis);
    let error: [f64; 6] = std::array::from_fn(|i| r.error[i] + moved[i]);
    let rhs: [f64; 6] = error.map(|e| -e);
    let mut rows = held(joint);
    let solution = match (clamp, joint.kind) {
        (true, JointKind::Bend(JointRule::Plastic { strength, .. })) => {
            plastic::clamped_solve(&r.matrix, &rhs, rows, joint.accumulated, strength).map(|(x, clamped)| {
                joint.clamped = clamped;
                if clamped {
                    rows[3..].fill(false);
                }
                let (_, l) = system::impulses(&x, &r.basis);
                joint.accumulated += l;
                x
            })
        }
        _ => system::solve(&r.matrix, &rhs, rows),
    };
    let Some(x) = solution else {
        return 0.0;
    };
    let (j, l) = system::impulses(&x, &r.basis);
    system::apply(v, mob, joint, &r.frame, j, l);
    (0..6).filter(|&i| rows[i]).map(|i| error[i].abs() / r.tolerance[i]).fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Neighbour lists (by place, each including itself) of joints given by the two bodies
    /// they join: joints sharing a body are coupled.
    fn coupling(ends: &[(usize, usize)]) -> Vec<Vec<usize>> {
        let shares = |p: (usize, usize), q: (usize, usize)| p.0 == q.0 || p.0 == q.1 || p.1 == q.0 || p.1 == q.1;
        ends.iter().map(|&p| (0..ends.len()).filter(|&q| shares(p, ends[q])).collect()).collect()
    }

    /// The largest distance in `order` between coupled joints.
    fn bandwidth(neighbours: &[Vec<usize>], order: &[usize]) -> usize {
        let mut place = vec![0; order.len()];
        for (i, &k) in order.iter().enumerate() {
            place[k] = i;
        }
        let pairs = neighbours.iter().enumerate().flat_map(|(p, around)| around.iter().map(move |&q| (p, q)));
        pairs.map(|(p, q)| place[p].abs_diff(place[q])).max().unwrap_or(0)
    }

    /// A shuffled chain of joints comes out in chain order (block-tridiagonal: each joint
    /// next to the ones it shares a body with), and a tetrahedron's twelve joints (four balls,
    /// six struts) in a permutation of the group.
    #[test]
    fn a_chain_is_ordered_along_itself() {
        let links = [3, 7, 0, 9, 4, 1, 8, 5, 2, 6];
        let chain: Vec<(usize, usize)> = links.iter().map(|&i| (i, i + 1)).collect();
        let group: Vec<usize> = (0..chain.len()).collect();
        let neighbours = coupling(&chain);
        assert_eq!(bandwidth(&neighbours, &order(&group, &neighbours)), 1);

        let mut tetrahedron = Vec::new();
        let mut strut = 4;
        for i in 0..4 {
            for j in i + 1..4 {
                tetrahedron.extend([(i, strut), (j, strut)]);
                strut += 1;
            }
        }
        let group: Vec<usize> = (0..tetrahedron.len()).collect();
        let mut sorted = order(&group, &coupling(&tetrahedron));
        sorted.sort_unstable();
        assert_eq!(sorted, group, "a permutation of the group");
    }
}
