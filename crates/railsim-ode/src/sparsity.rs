//! The structure of a Jacobian and the column groups that estimate it with fewer evaluations.
//!
//! A finite-difference Jacobian costs one right-hand side per column. When the system tells
//! which derivatives f_i may depend on which state variables x_j ([`JacobianPattern`]),
//! columns whose row sets do not overlap can be perturbed together: one evaluation then gives
//! all of them, each entry read from its own rows (Curtis, Powell & Reid, "On the estimation
//! of sparse Jacobian matrices", J. Inst. Maths Applics 13, 1974, 117–119). Choosing the
//! groups is a colouring of the columns' intersection graph; [`JacobianPattern::column_groups`]
//! colours greedily in the largest-first order (Coleman & Moré, "Estimation of sparse
//! Jacobian matrices and graph coloring problems", SIAM J. Numer. Anal. 20, 1983, 187–209).
//!
//! The pattern must hold every dependence that can occur, at any state: an entry left out is
//! read as zero, and a column grouped with one it interferes with is estimated wrongly.

use crate::OdeError;

/// For each state variable x_j, the derivatives f_i that may depend on it (the structural
/// non-zeros of ∂f/∂x, column by column; rows sorted, each once).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct JacobianPattern {
    cols: Vec<Vec<usize>>,
}

impl JacobianPattern {
    /// An empty pattern of a system with `n` state variables (every derivative constant).
    pub fn new(n: usize) -> Self {
        Self {
            cols: vec![Vec::new(); n],
        }
    }

    /// A dense pattern: every derivative may depend on every state variable.
    pub fn dense(n: usize) -> Self {
        Self {
            cols: vec![(0..n).collect(); n],
        }
    }

    /// Number of state variables.
    pub fn dim(&self) -> usize {
        self.cols.len()
    }

    /// Declares that derivative `row` may depend on state variable `col`. Both must be below
    /// [`JacobianPattern::dim`].
    pub fn insert(&mut self, row: usize, col: usize) -> Result<(), OdeError> {
        let n = self.cols.len();
        if row >= n || col >= n {
            return Err(OdeError::PatternOutOfRange { row, col, dim: n });
        }
        let rows = &mut self.cols[col];
        if let Err(k) = rows.binary_search(&row) {
            rows.insert(k, row);
        }
        Ok(())
    }

    /// The derivatives that may depend on state variable `col`, sorted.
    pub fn rows(&self, col: usize) -> &[usize] {
        &self.cols[col]
    }

    /// Number of structural non-zeros.
    pub fn nonzeros(&self) -> usize {
        self.cols.iter().map(Vec::len).sum()
    }

    /// Columns grouped so that no two columns of a group share a row: perturbing a group's
    /// columns together, each derivative that changes belongs to exactly one of them. Greedy
    /// colouring in the largest-first order (columns with more rows first, ties by index);
    /// each group's columns in increasing order, the groups in the order they were opened.
    pub fn column_groups(&self) -> Vec<Vec<usize>> {
        let n = self.cols.len();
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&a, &b| self.cols[b].len().cmp(&self.cols[a].len()).then(a.cmp(&b)));
        let mut groups: Vec<Vec<usize>> = Vec::new();
        // rows already taken by each group
        let mut taken: Vec<Vec<bool>> = Vec::new();
        for j in order {
            let rows = &self.cols[j];
            let free = taken.iter().position(|t| rows.iter().all(|&i| !t[i]));
            let g = free.unwrap_or_else(|| {
                groups.push(Vec::new());
                taken.push(vec![false; n]);
                groups.len() - 1
            });
            groups[g].push(j);
            for &i in rows {
                taken[g][i] = true;
            }
        }
        for g in &mut groups {
            g.sort_unstable();
        }
        groups
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tridiagonal pattern needs three groups whatever its size (columns j, j+3, … share no
    /// row), a dense one n, a diagonal one 1.
    #[test]
    fn groups_of_banded_dense_and_diagonal_patterns() {
        let n = 10;
        let mut tri = JacobianPattern::new(n);
        for j in 0..n {
            for i in j.saturating_sub(1)..(j + 2).min(n) {
                tri.insert(i, j).unwrap();
            }
        }
        assert_eq!(tri.nonzeros(), 3 * n - 2);
        let g = tri.column_groups();
        assert_eq!(g.len(), 3, "{g:?}");
        assert_no_shared_rows(&tri, &g);
        let dense = JacobianPattern::dense(n);
        assert_eq!(dense.column_groups().len(), n);
        let mut diag = JacobianPattern::new(n);
        for j in 0..n {
            diag.insert(j, j).unwrap();
        }
        let g = diag.column_groups();
        assert_eq!(g, vec![(0..n).collect::<Vec<_>>()]);
    }

    /// Every column is in exactly one group and no two columns of a group share a row, on an
    /// irregular pattern.
    #[test]
    fn groups_partition_the_columns_without_shared_rows() {
        let n = 40;
        let mut p = JacobianPattern::new(n);
        let mut s: u64 = 12345;
        for _ in 0..160 {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let i = (s >> 33) as usize % n;
            let j = (s >> 13) as usize % n;
            p.insert(i, j).unwrap();
            p.insert(i, j).unwrap();
        }
        let g = p.column_groups();
        assert!(g.len() < n, "{} groups", g.len());
        assert_no_shared_rows(&p, &g);
        let mut all: Vec<usize> = g.concat();
        all.sort_unstable();
        assert_eq!(all, (0..n).collect::<Vec<_>>());
        for j in 0..n {
            assert!(p.rows(j).windows(2).all(|w| w[0] < w[1]));
        }
    }

    #[test]
    fn an_entry_outside_the_dimension_is_an_error() {
        let mut p = JacobianPattern::new(3);
        assert_eq!(
            p.insert(3, 0),
            Err(OdeError::PatternOutOfRange {
                row: 3,
                col: 0,
                dim: 3
            })
        );
        assert!(p.insert(0, 5).is_err());
        assert_eq!(p.nonzeros(), 0);
    }

    fn assert_no_shared_rows(p: &JacobianPattern, groups: &[Vec<usize>]) {
        for g in groups {
            let mut seen = vec![false; p.dim()];
            for &j in g {
                for &i in p.rows(j) {
                    assert!(!seen[i], "row {i} shared in group {g:?}");
                    seen[i] = true;
                }
            }
        }
    }
}
