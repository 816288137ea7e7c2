//! Sparse linear solves for joint groups: a square system given by rows of (column, value)
//! pairs, stored as a band (its unknowns ordered so that coupled joints are close, see
//! `solve::order`) and solved by banded Gaussian elimination with partial pivoting — O(n·b²) for
//! bandwidth b, so a chain of any length costs about as much per joint as a single joint.
//! Optionally a Levenberg–Marquardt step (damped normal equations) instead of the plain solve.

/// A square sparse matrix by rows: row i's (column, value) entries, columns increasing.
pub(crate) struct Sparse {
    /// Row i's entries are `entries[starts[i]..starts[i + 1]]`.
    starts: Vec<usize>,
    entries: Vec<(usize, f64)>,
}

impl Sparse {
    /// The n × n matrix with `entries` (row, column, value), given column by column (columns
    /// increasing; any row order within a column): a counting sort by row keeps each row's
    /// columns increasing.
    pub(crate) fn by_columns(n: usize, entries: &[(usize, usize, f64)]) -> Self {
        let mut starts = vec![0usize; n + 1];
        for &(row, _, _) in entries {
            starts[row + 1] += 1;
        }
        for i in 0..n {
            starts[i + 1] += starts[i];
        }
        let mut next = starts.clone();
        let mut placed = vec![(0usize, 0.0f64); entries.len()];
        for &(row, col, value) in entries {
            placed[next[row]] = (col, value);
            next[row] += 1;
        }
        Self { starts, entries: placed }
    }

    /// The matrix with rows `rows[i]` ((column, value) pairs, columns < rows.len()).
    #[cfg(test)]
    fn from_rows(rows: &[Vec<(usize, f64)>]) -> Self {
        let mut entries: Vec<(usize, usize, f64)> =
            rows.iter().enumerate().flat_map(|(i, row)| row.iter().map(move |&(j, v)| (i, j, v))).collect();
        entries.sort_unstable_by_key(|&(i, j, _)| (j, i));
        Self::by_columns(rows.len(), &entries)
    }

    fn len(&self) -> usize {
        self.starts.len() - 1
    }

    fn row(&self, i: usize) -> &[(usize, f64)] {
        &self.entries[self.starts[i]..self.starts[i + 1]]
    }

    fn rows(&self) -> impl Iterator<Item = &[(usize, f64)]> {
        (0..self.len()).map(|i| self.row(i))
    }

    /// The system a·x = `rhs` with the unknowns where `is_fixed` holds set to `value(column)`
    /// and their rows dropped: (the reduced matrix, its right-hand side, the kept unknowns in
    /// order).
    pub(crate) fn without(
        &self,
        rhs: &[f64],
        is_fixed: impl Fn(usize) -> bool,
        value: impl Fn(usize) -> f64,
    ) -> (Self, Vec<f64>, Vec<usize>) {
        let n = self.len();
        let mut renumber = vec![usize::MAX; n];
        let free: Vec<usize> = (0..n).filter(|&i| !is_fixed(i)).collect();
        for (new, &old) in free.iter().enumerate() {
            renumber[old] = new;
        }
        let mut starts = Vec::with_capacity(free.len() + 1);
        starts.push(0);
        let mut entries = Vec::with_capacity(self.entries.len());
        let mut b = Vec::with_capacity(free.len());
        for &row in &free {
            let mut right = rhs[row];
            for &(col, a) in self.row(row) {
                if is_fixed(col) {
                    right -= a * value(col);
                } else {
                    entries.push((renumber[col], a));
                }
            }
            starts.push(entries.len());
            b.push(right);
        }
        (Self { starts, entries }, b, free)
    }
}

/// A diagonal pivot is kept while it is at least this fraction of its column's largest entry
/// below it (threshold partial pivoting, as sparse direct solvers use: growth stays bounded by
/// 1 / threshold per step, and row swaps, which widen the band, stay rare).
const PIVOT_THRESHOLD: f64 = 0.1;

/// Largest band storage (entries) a solve may use; wider systems are refused.
const MAX_ENTRIES: usize = 1 << 22;

/// Row-major band storage with `lower` sub-diagonals and room for `upper + lower`
/// super-diagonals (partial pivoting widens the upper band by up to `lower`).
struct Band {
    n: usize,
    lower: usize,
    upper: usize,
    data: Vec<f64>,
}

impl Band {
    fn new(n: usize, lower: usize, upper: usize) -> Option<Self> {
        let width = 2 * lower + upper + 1;
        let entries = n.checked_mul(width)?;
        (entries <= MAX_ENTRIES).then(|| Self { n, lower, upper, data: vec![0.0; entries] })
    }

    fn width(&self) -> usize {
        2 * self.lower + self.upper + 1
    }

    /// Slot of entry (i, j); j must lie in [i − lower, i + upper + lower].
    fn at(&self, i: usize, j: usize) -> usize {
        i * self.width() + (j + self.lower - i)
    }

    /// Solves in place by Gaussian elimination with threshold partial pivoting (the diagonal
    /// unless another entry of its column is over [`PIVOT_THRESHOLD`]⁻¹ times larger, which
    /// keeps the band as narrow as it came wherever the system is near-symmetric); `None` when
    /// a pivot is not above `tolerance` times the largest diagonal entry (singular).
    fn solve(mut self, b: &mut [f64], tolerance: f64) -> Option<Vec<f64>> {
        let n = self.n;
        let scale = (0..n).map(|i| self.data[self.at(i, i)].abs()).fold(0.0, f64::max);
        if n == 0 {
            return Some(Vec::new());
        }
        if !(scale > 0.0 && scale.is_finite()) {
            return None;
        }
        // Last column each row holds so far (row swaps and elimination widen it).
        let mut end: Vec<usize> = (0..n).map(|i| (i + self.upper).min(n - 1)).collect();
        let width = self.width();
        for k in 0..n {
            let bottom = (k + self.lower).min(n - 1);
            let magnitude = |row: usize| self.data[self.at(row, k)].abs();
            let largest = (k..=bottom).max_by(|&x, &y| magnitude(x).total_cmp(&magnitude(y)))?;
            let pivot = if magnitude(k) >= PIVOT_THRESHOLD * magnitude(largest) { k } else { largest };
            if magnitude(pivot) <= tolerance * scale {
                return None;
            }
            if pivot != k {
                for j in k..=end[k].max(end[pivot]) {
                    let (x, y) = (self.at(k, j), self.at(pivot, j));
                    self.data.swap(x, y);
                }
                end.swap(k, pivot);
                b.swap(k, pivot);
            }
            let diagonal = self.data[self.at(k, k)];
            // Row k's entries from column k on, and row i's over the same columns: contiguous.
            let span = end[k] - k + 1;
            let pivot_start = self.at(k, k);
            for i in k + 1..=bottom {
                let (head, tail) = self.data.split_at_mut(i * width);
                let pivot_row = &head[pivot_start..pivot_start + span];
                let row = &mut tail[k + self.lower - i..k + self.lower - i + span];
                let factor = row[0] / diagonal;
                if factor == 0.0 {
                    continue;
                }
                for (value, &above) in row.iter_mut().zip(pivot_row) {
                    *value -= factor * above;
                }
                end[i] = end[i].max(end[k]);
                b[i] -= factor * b[k];
            }
        }
        let mut x = vec![0.0f64; n];
        for i in (0..n).rev() {
            let tail: f64 = (i + 1..=end[i]).map(|j| self.data[self.at(i, j)] * x[j]).sum();
            x[i] = (b[i] - tail) / self.data[self.at(i, i)];
        }
        x.iter().all(|value| value.is_finite()).then_some(x)
    }
}

/// Solves the square system `a` for right-hand side `b`. With `damping` > 0 it takes the Levenberg–Marquardt step instead:
/// (aᵀa + damping·diag(aᵀa))·x = aᵀb, shorter and defined where the rows are nearly dependent.
/// `None` when singular or too wide to store.
pub(crate) fn solve(a: &Sparse, b: &[f64], damping: f64) -> Option<Vec<f64>> {
    let n = b.len();
    if damping > 0.0 {
        // Damped normal equations are positive definite: any positive pivot will do.
        return normal_equations(a, b, damping).and_then(|(normal, mut right)| normal.solve(&mut right, 0.0));
    }
    let (mut lower, mut upper) = (0, 0);
    for (i, row) in a.rows().enumerate() {
        for &(j, _) in row {
            lower = lower.max(i.saturating_sub(j));
            upper = upper.max(j.saturating_sub(i));
        }
    }
    let mut band = Band::new(n, lower, upper)?;
    for (i, row) in a.rows().enumerate() {
        for &(j, value) in row {
            let slot = band.at(i, j);
            band.data[slot] += value;
        }
    }
    let mut right = b.to_vec();
    band.solve(&mut right, 1e-12)
}

/// The damped normal equations of a·x = b as a band, with aᵀb.
fn normal_equations(a: &Sparse, b: &[f64], damping: f64) -> Option<(Band, Vec<f64>)> {
    let n = b.len();
    let mut half = 0;
    for row in a.rows() {
        let (low, high) = row.iter().fold((usize::MAX, 0), |(lo, hi), &(j, _)| (lo.min(j), hi.max(j)));
        if low <= high {
            half = half.max(high - low);
        }
    }
    let mut band = Band::new(n, half, half)?;
    let mut right = vec![0.0f64; n];
    for (row, &bk) in a.rows().zip(b) {
        for &(i, aki) in row {
            right[i] += aki * bk;
            for &(j, akj) in row {
                let slot = band.at(i, j);
                band.data[slot] += aki * akj;
            }
        }
    }
    for i in 0..n {
        let slot = band.at(i, i);
        band.data[slot] *= 1.0 + damping;
    }
    Some((band, right))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A random-ish banded non-symmetric system is solved to round-off, a zero diagonal is
    /// pivoted around, and the damped step of a consistent system approaches the solution as the
    /// damping vanishes.
    #[test]
    fn banded_systems_are_solved() {
        let n = 40;
        let mut rows = vec![Vec::new(); n];
        let value = |i: usize, j: usize| ((i * 7 + j * 13) % 11) as f64 - 5.0 + if i == j { 0.5 } else { 0.0 };
        for (i, row) in rows.iter_mut().enumerate() {
            for j in i.saturating_sub(2)..(i + 4).min(n) {
                row.push((j, value(i, j)));
            }
        }
        let truth: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let b: Vec<f64> = rows.iter().map(|row| row.iter().map(|&(j, v)| v * truth[j]).sum()).collect();
        let a = Sparse::from_rows(&rows);
        let x = solve(&a, &b, 0.0).unwrap();
        let error = x.iter().zip(&truth).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(error < 1e-9, "plain solve off by {error}");
        let damped = solve(&a, &b, 1e-9).unwrap();
        let error = damped.iter().zip(&truth).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(error < 1e-4, "damped solve off by {error}");
        assert!(solve(&Sparse::from_rows(&[vec![(0, 0.0)]]), &[1.0], 0.0).is_none(), "singular system solved");
        // A zero diagonal needs a row swap: x1 = 3, 2·x0 + x1 = 4.
        let swapped = solve(&Sparse::from_rows(&[vec![(1, 1.0)], vec![(0, 2.0), (1, 1.0)]]), &[3.0, 4.0], 0.0);
        let swapped = swapped.expect("a zero diagonal with a non-zero below it is not singular");
        assert!((swapped[0] - 0.5).abs() < 1e-12 && (swapped[1] - 3.0).abs() < 1e-12, "{swapped:?}");
    }
}
