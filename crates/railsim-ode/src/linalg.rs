//! Dense LU factorisation on faer's low-level in-place kernels.
//!
//! faer's high-level `partial_piv_lu()` allocates about three n×n buffers per call
//! (docs/dependencies.md §5). Here the matrix, the permutation and the scratch memory
//! are allocated once in [`DenseLu::new`]; [`DenseLu::factor`] and [`DenseLu::solve`]
//! never allocate.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::perm::PermRef;
use faer::traits::ComplexField;
use faer::{Mat, MatMut, Par, c64};

/// Scalars the LU is used with: real for the Radau real block, complex for its complex pair.
pub(crate) trait LuScalar: ComplexField + Copy {
    /// True when the pivot is usable (finite and not zero).
    fn usable_pivot(self) -> bool;
}

impl LuScalar for f64 {
    fn usable_pivot(self) -> bool {
        self.is_finite() && self != 0.0
    }
}

impl LuScalar for c64 {
    fn usable_pivot(self) -> bool {
        self.re.is_finite() && self.im.is_finite() && (self.re != 0.0 || self.im != 0.0)
    }
}

/// An n×n matrix factorised in place as P A = L U, with all storage owned.
pub(crate) struct DenseLu<T: LuScalar> {
    /// The matrix before [`Self::factor`], its L and U factors after.
    pub(crate) a: Mat<T>,
    fwd: Vec<usize>,
    inv: Vec<usize>,
    mem: MemBuffer,
    factored: bool,
}

impl<T: LuScalar> DenseLu<T> {
    pub(crate) fn new(n: usize) -> Self {
        let req = factor::lu_in_place_scratch::<usize, T>(n, n, Par::Seq, Default::default())
            .or(solve::solve_in_place_scratch::<usize, T>(n, 1, Par::Seq));
        Self {
            a: Mat::zeros(n, n),
            fwd: vec![0; n],
            inv: vec![0; n],
            mem: MemBuffer::new(req),
            factored: false,
        }
    }

    /// Factorises `self.a` in place. Returns false if a pivot is zero or not finite
    /// (the matrix is singular to working precision); the factors are then unusable.
    pub(crate) fn factor(&mut self) -> bool {
        let n = self.a.nrows();
        let _ = factor::lu_in_place(
            self.a.as_mut(),
            &mut self.fwd,
            &mut self.inv,
            Par::Seq,
            MemStack::new(&mut self.mem),
            Default::default(),
        );
        self.factored = (0..n).all(|i| self.a[(i, i)].usable_pivot());
        self.factored
    }

    /// Solves A x = b in place (`rhs` holds b on entry and x on return).
    pub(crate) fn solve(&mut self, rhs: &mut [T]) {
        debug_assert!(self.factored, "solve before a successful factor");
        let n = self.a.nrows();
        let perm = PermRef::new_checked(&self.fwd, &self.inv, n);
        let b = MatMut::from_column_major_slice_mut(rhs, n, 1);
        solve::solve_in_place(
            self.a.as_ref(),
            self.a.as_ref(),
            perm,
            b,
            Par::Seq,
            MemStack::new(&mut self.mem),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn real_solve_matches_product() {
        let n = 5;
        let mut lu = DenseLu::<f64>::new(n);
        let a =
            |i: usize, j: usize| 1.0 / (1.0 + i as f64 + j as f64) + if i == j { 2.0 } else { 0.0 };
        for i in 0..n {
            for j in 0..n {
                lu.a[(i, j)] = a(i, j);
            }
        }
        assert!(lu.factor());
        let x: Vec<f64> = (0..n).map(|i| i as f64 - 1.5).collect();
        let mut b: Vec<f64> = (0..n)
            .map(|i| (0..n).map(|j| a(i, j) * x[j]).sum())
            .collect();
        lu.solve(&mut b);
        for i in 0..n {
            assert!((b[i] - x[i]).abs() < 1e-13, "{} vs {}", b[i], x[i]);
        }
    }

    #[test]
    fn complex_solve_matches_product() {
        let n = 4;
        let mut lu = DenseLu::<c64>::new(n);
        let a = |i: usize, j: usize| {
            c64::new(
                (i * 3 + j) as f64 * 0.1 + if i == j { 3.0 } else { 0.0 },
                if i == j { 1.0 } else { 0.2 * j as f64 },
            )
        };
        for i in 0..n {
            for j in 0..n {
                lu.a[(i, j)] = a(i, j);
            }
        }
        assert!(lu.factor());
        let x: Vec<c64> = (0..n).map(|i| c64::new(i as f64, 1.0 - i as f64)).collect();
        let mut b: Vec<c64> = (0..n)
            .map(|i| (0..n).fold(c64::new(0.0, 0.0), |s, j| s + a(i, j) * x[j]))
            .collect();
        lu.solve(&mut b);
        for i in 0..n {
            assert!((b[i] - x[i]).norm() < 1e-13);
        }
    }

    #[test]
    fn singular_is_reported() {
        let mut lu = DenseLu::<f64>::new(3);
        lu.a[(0, 0)] = 1.0;
        lu.a[(1, 1)] = 1.0;
        assert!(!lu.factor());
    }
}
