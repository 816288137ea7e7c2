//! Independent joint groups solved in parallel. Groups share no body that takes impulses, so
//! each can be solved without seeing the others: the groups are dealt into a few batches of
//! similar size, each solved on its own copy of the velocities and of its own joints (numbered
//! from 0 in group order), and what each batch changed is copied back. The result does not
//! depend on how the groups were batched.

use rayon::prelude::*;

use super::Joint;
use super::system::{self, Mobility, Motion};

/// Runs `work(joints, groups, v)` on batches of `groups` (joint indices) in parallel: `joints`
/// are the batch's own, numbered from 0, and `groups` index them; `v` is the batch's copy of
/// every body's velocities. The joints and the velocities of the bodies that take impulses
/// come back; returns the sum of what `work` returned.
pub(crate) fn in_batches(
    joints: &mut [Joint],
    groups: &[Vec<usize>],
    mob: &[Mobility],
    v: &mut [Motion],
    work: impl Fn(&mut [Joint], &[Vec<usize>], &mut [Motion]) -> usize + Sync,
) -> usize {
    if groups.is_empty() {
        return 0;
    }
    let batches = batches(groups, rayon::current_num_threads());
    let (shared, start): (&[Joint], &[Motion]) = (joints, v);
    let solved: Vec<(Solved, usize)> = batches
        .par_iter()
        .map(|batch| {
            let mut v = start.to_vec();
            let mut local: Vec<Joint> = Vec::new();
            let local_groups: Vec<Vec<usize>> = batch
                .iter()
                .map(|&g| {
                    let first = local.len();
                    local.extend(groups[g].iter().map(|&k| shared[k].clone()));
                    (first..local.len()).collect()
                })
                .collect();
            let count = work(&mut local, &local_groups, &mut v);
            let moved = local.iter().flat_map(|joint| [joint.a, joint.b]);
            let moved: Vec<(usize, Motion)> =
                moved.filter(|&i| system::takes_impulses(&mob[i])).map(|i| (i, v[i])).collect();
            ((moved, local), count)
        })
        .collect();
    let count = solved.iter().map(|(_, count)| count).sum();
    for (batch, ((moved, local), _)) in batches.iter().zip(solved) {
        for (i, m) in moved {
            v[i] = m;
        }
        let global = batch.iter().flat_map(|&g| &groups[g]);
        for (&k, joint) in global.zip(local) {
            joints[k] = joint;
        }
    }
    count
}

/// What a batch of groups changed: the velocities of its bodies that take impulses and its
/// joints in group order.
type Solved = (Vec<(usize, Motion)>, Vec<Joint>);

/// `groups` (indices) split into at most `count` batches of about equal joint counts, in order.
fn batches(groups: &[Vec<usize>], count: usize) -> Vec<Vec<usize>> {
    let total: usize = groups.iter().map(Vec::len).sum();
    let share = total.div_ceil(count.max(1)).max(1);
    let mut out: Vec<Vec<usize>> = vec![Vec::new()];
    let mut filled = 0;
    for (g, group) in groups.iter().enumerate() {
        if filled >= share {
            out.push(Vec::new());
            filled = 0;
        }
        if let Some(batch) = out.last_mut() {
            batch.push(g);
        }
        filled += group.len();
    }
    out
}
