//! How much each body is dented, for the dent limit of [`FractureSettings`](super::FractureSettings):
//! a body's accumulated dent is the sum over its dents of how deep each went, where the repeated
//! hits of one progressive contact (a record each step, each with the contact's accumulated
//! distance) count once, at their deepest.

/// One progressive contact's deepest dent so far.
#[derive(Debug, Clone, Copy)]
struct Contact<K> {
    target: K,
    projectile: K,
    distance: f32,
    last_step: u64,
}

/// Accumulated dents, keyed by the caller's body ids.
#[derive(Debug, Clone)]
pub struct DentTally<K> {
    settled: Vec<(K, f32)>,
    contacts: Vec<Contact<K>>,
}

impl<K> Default for DentTally<K> {
    fn default() -> Self {
        Self { settled: Vec::new(), contacts: Vec::new() }
    }
}

impl<K: Copy + PartialEq> DentTally<K> {
    /// Counts a dent of `target` by `projectile`, `distance` m deep, made at `step`.
    /// `progressive`: the target's dents deepen while a contact lasts (a record is the
    /// contact's accumulated distance, which replaces the contact's last one when the contact
    /// was hit at `step` − 1 or later).
    pub fn add(&mut self, target: K, projectile: K, distance: f32, step: u64, progressive: bool) {
        let distance = if distance.is_finite() { distance.max(0.0) } else { 0.0 };
        if !progressive {
            self.settle(target, distance);
            return;
        }
        let live = self.contacts.iter().position(|c| c.target == target && c.projectile == projectile);
        match live {
            Some(k) if self.contacts[k].last_step + 1 >= step => {
                let contact = &mut self.contacts[k];
                contact.distance = contact.distance.max(distance);
                contact.last_step = step;
            }
            Some(k) => {
                let old = self.contacts[k];
                self.settle(target, old.distance);
                self.contacts[k] = Contact { target, projectile, distance, last_step: step };
            }
            None => self.contacts.push(Contact { target, projectile, distance, last_step: step }),
        }
    }

    /// The accumulated dent of `body`, m.
    pub fn total(&self, body: K) -> f32 {
        let settled: f32 = self.settled.iter().filter(|(k, _)| *k == body).map(|(_, d)| d).sum();
        settled + self.contacts.iter().filter(|c| c.target == body).map(|c| c.distance).sum::<f32>()
    }

    /// Forgets `body` (it broke, or was removed): its count starts again from zero.
    pub fn forget(&mut self, body: K) {
        self.settled.retain(|(k, _)| *k != body);
        self.contacts.retain(|c| c.target != body && c.projectile != body);
    }

    fn settle(&mut self, target: K, distance: f32) {
        match self.settled.iter_mut().find(|(k, _)| *k == target) {
            Some((_, total)) => *total += distance,
            None => self.settled.push((target, distance)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A progressive contact's records (0.1, 0.2, 0.3 m in consecutive steps) count as 0.3 m; a
    /// new contact after a gap adds its own; plain dents add up.
    #[test]
    fn progressive_records_count_once_at_their_deepest() {
        let mut tally = DentTally::default();
        for (step, d) in [(1, 0.1), (2, 0.2), (3, 0.3)] {
            tally.add(0u32, 1, d, step, true);
        }
        assert!((tally.total(0) - 0.3).abs() < 1e-6);
        tally.add(0, 1, 0.05, 10, true);
        assert!((tally.total(0) - 0.35).abs() < 1e-6);
        tally.add(2, 1, 0.1, 1, false);
        tally.add(2, 1, 0.1, 2, false);
        assert!((tally.total(2) - 0.2).abs() < 1e-6);
        tally.forget(0);
        assert_eq!(tally.total(0), 0.0);
    }
}
