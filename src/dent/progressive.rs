//! Progressive dents (the paper's Figure 3): while a contact between a target and a projectile
//! lasts, each new hit rebuilds the dent from the surface as it was before the contact's first
//! dent, with the accumulated distance, so the dent deepens instead of stacking.

/// One (target, projectile) contact's progressive state; `M` is whatever the caller keeps of
/// the pre-dent surface (a mesh, a rest mesh).
#[derive(Debug, Clone)]
struct Progress<K, M> {
    target: K,
    projectile: K,
    pre_dent: M,
    accumulated: f32,
    last_step: u64,
}

/// Progressive dents under way, keyed by the caller's body ids.
#[derive(Debug, Clone)]
pub(crate) struct ProgressiveDents<K, M> {
    contacts: Vec<Progress<K, M>>,
}

impl<K, M> Default for ProgressiveDents<K, M> {
    fn default() -> Self {
        Self { contacts: Vec::new() }
    }
}

impl<K: Copy + PartialEq, M: Clone> ProgressiveDents<K, M> {
    /// None under way.
    pub fn new() -> Self {
        Self::default()
    }

    /// Forgets contacts not hit in step `step` − 1 or later: their contact has ended.
    pub fn end_stale(&mut self, step: u64) {
        self.contacts.retain(|p| p.last_step + 1 >= step);
    }

    /// The surface to rebuild `target`'s dent by `projectile` from at step `step`, and the
    /// distance (m) the dent will have after adding `more` m, at most `cap` m: the pre-dent
    /// surface of a contact under way (hit at `step` − 1 or later), else `current()` (the surface
    /// now, which becomes the contact's pre-dent one when [`record`](Self::record)ed).
    pub fn next(
        &self,
        target: K,
        projectile: K,
        step: u64,
        (more, cap): (f32, f32),
        current: impl FnOnce() -> M,
    ) -> (M, f32) {
        match self.find(target, projectile).filter(|&k| self.contacts[k].last_step + 1 >= step) {
            Some(k) => (self.contacts[k].pre_dent.clone(), (self.contacts[k].accumulated + more).min(cap)),
            None => (current(), more.min(cap)),
        }
    }

    /// Records that `target`'s dent by `projectile` is now `distance` m deep at `step`, built
    /// from `pre_dent` (as [`next`](Self::next) gave it).
    pub fn record(&mut self, target: K, projectile: K, pre_dent: M, distance: f32, step: u64) {
        match self.find(target, projectile) {
            Some(k) => {
                self.contacts[k].accumulated = distance;
                self.contacts[k].last_step = step;
            }
            None => {
                self.contacts.push(Progress { target, projectile, pre_dent, accumulated: distance, last_step: step })
            }
        }
    }

    /// Whether the contact of `target` and `projectile` is under way (recorded, stale or not).
    pub fn contains(&self, target: K, projectile: K) -> bool {
        self.find(target, projectile).is_some()
    }

    /// Takes `newer`'s contacts, replacing the same contacts here.
    pub fn absorb(&mut self, newer: Self) {
        for p in newer.contacts {
            match self.find(p.target, p.projectile) {
                Some(k) => self.contacts[k] = p,
                None => self.contacts.push(p),
            }
        }
    }

    /// Forgets every contact of `body` (as target or projectile): it was removed.
    pub fn forget(&mut self, body: K) {
        self.contacts.retain(|p| p.target != body && p.projectile != body);
    }

    fn find(&self, target: K, projectile: K) -> Option<usize> {
        self.contacts.iter().position(|p| p.target == target && p.projectile == projectile)
    }
}
