//! The edges a cut has split, as a table without hashing: each split edge (lo, hi), lo < hi,
//! hangs in a short chain under its lower vertex id, so a lookup reads a few entries of one
//! chain (a vertex is the lower end of few split edges).

/// Split edges: unordered vertex pair → the vertex made between them.
#[derive(Debug, Clone, Default)]
pub(crate) struct SplitTable {
    /// Per vertex id: the newest entry whose edge has it as its lower end (`NONE` if none).
    head: Vec<u32>,
    entries: Vec<Entry>,
}

#[derive(Debug, Clone, Copy)]
struct Entry {
    lo: u32,
    hi: u32,
    mid: u32,
    /// The entry before it in the same chain (`NONE` at the end).
    next: u32,
}

const NONE: u32 = u32::MAX;

impl SplitTable {
    /// The vertex between `lo` and `hi` (lo < hi), if that edge was split.
    pub(crate) fn get(&self, lo: u32, hi: u32) -> Option<u32> {
        let mut k = *self.head.get(lo as usize)?;
        while k != NONE {
            let entry = self.entries[k as usize];
            if entry.hi == hi {
                return Some(entry.mid);
            }
            k = entry.next;
        }
        None
    }

    /// Records that edge (`lo`, `hi`), lo < hi and not recorded yet, was split at `mid`.
    pub(crate) fn insert(&mut self, lo: u32, hi: u32, mid: u32) {
        if self.head.len() <= lo as usize {
            self.head.resize(lo as usize + 1, NONE);
        }
        let next = self.head[lo as usize];
        self.head[lo as usize] = self.entries.len() as u32;
        self.entries.push(Entry { lo, hi, mid, next });
    }

    /// Every split edge as (lo, hi), in the order they were split.
    pub(crate) fn edges(&self) -> impl Iterator<Item = (u32, u32)> + '_ {
        self.entries.iter().map(|e| (e.lo, e.hi))
    }

    /// Forgets every edge, keeping the memory.
    pub(crate) fn clear(&mut self) {
        for entry in &self.entries {
            self.head[entry.lo as usize] = NONE;
        }
        self.entries.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Lookups find exactly the inserted edges, by both ends, also after a clear and reuse.
    #[test]
    fn finds_what_was_inserted_and_nothing_else() {
        let mut table = SplitTable::default();
        table.insert(3, 9, 20);
        table.insert(3, 5, 21);
        table.insert(0, 3, 22);
        assert_eq!(table.get(3, 9), Some(20));
        assert_eq!(table.get(3, 5), Some(21));
        assert_eq!(table.get(0, 3), Some(22));
        assert_eq!(table.get(5, 9), None);
        assert_eq!(table.get(3, 4), None);
        assert_eq!(table.get(100, 101), None);
        assert_eq!(table.edges().collect::<Vec<_>>(), [(3, 9), (3, 5), (0, 3)]);
        table.clear();
        assert_eq!(table.get(3, 9), None);
        assert_eq!(table.edges().count(), 0);
        table.insert(3, 5, 7);
        assert_eq!((table.get(3, 5), table.get(3, 9)), (Some(7), None));
    }
}
