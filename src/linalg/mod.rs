//! Thin wrappers over faer: the quadratic eigenproblem in a structure-keeping first-order
//! form, and by shift-invert (Eq. 18–21) where that form does not apply, the
//! symmetric-definite generalised eigenproblem (buckling, undamped modes), the matrix
//! exponential and complex products as real ones. Every faer kernel is called with its
//! parallelism passed explicitly ([`seq`]): the library never reads or sets faer's global
//! parallelism.

mod balance;
mod expm;
mod krylov;
mod krylov_faer;
mod qep;
mod qep_real;
pub mod seq;
mod split;
mod symmetric;

pub use balance::balance;
pub use expm::{expm, norm1, with_modulus};
pub use krylov::{NearestEigen, ShiftInvert, KRYLOV_BLOCK, KRYLOV_TOLERANCE};
pub use qep::{
    qep_residual, qep_residual_with, solve_qep, solve_qep_definite, QepNorms, QepSolution, DEFINITE_FORM_SPREAD,
};
pub use qep_real::solve_qep_real;
pub use split::{ExpWorkspace, SplitMatrix};
pub use symmetric::{definite_eigen, DefiniteEigen};

use thiserror::Error;

/// Failures of the dense linear algebra.
#[derive(Debug, Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum LinalgError {
    /// The eigenvalue iteration did not converge.
    #[error("the {what} eigenvalue iteration did not converge")]
    NoConvergence {
        /// Which decomposition.
        what: &'static str,
    },
    /// A matrix that must be positive definite is not (e.g. the stiffness after a load
    /// at or above buckling).
    #[error("the {what} matrix is not positive definite")]
    NotPositiveDefinite {
        /// Which matrix.
        what: &'static str,
    },
    /// The shifted pencil is singular: the shift hit an eigenvalue.
    #[error("the shifted pencil (A − σB) is singular at σ = {shift} rad/s", shift = crate::numbers::number(*shift))]
    SingularShift {
        /// The shift (rad/s).
        shift: f64,
    },
    /// A matrix contains NaN or infinite entries.
    #[error("the {what} matrix has non-finite entries")]
    NonFinite {
        /// Which matrix.
        what: &'static str,
    },
}

/// Test helpers shared by the exponentials' and the QEP solvers' tests.
#[cfg(test)]
pub(crate) mod testing {
    use faer::{c64, Mat};

    /// An n × n matrix of entries in [−0.5, 0.5) from a linear congruential sequence:
    /// the same matrix for the same seed on every machine.
    pub fn random(n: usize, seed: u64) -> Mat<f64> {
        let mut state = seed;
        Mat::from_fn(n, n, |_, _| {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        })
    }

    /// A·Aᵀ + shift·I of a [`random`] A: symmetric positive (semi-)definite.
    pub fn spd(n: usize, seed: u64, shift: f64) -> Mat<f64> {
        let a = random(n, seed);
        let p = super::seq::product(a.as_ref(), a.transpose());
        Mat::from_fn(n, n, |i, j| p[(i, j)] + if i == j { shift } else { 0.0 })
    }

    /// Eigenvalues sorted by imaginary, then real part, to compare two solvers' lists.
    pub fn sorted(mut v: Vec<c64>) -> Vec<c64> {
        v.sort_by(|a, b| a.im.total_cmp(&b.im).then(a.re.total_cmp(&b.re)));
        v
    }

    /// The largest entry error of `ours` against nalgebra's Padé exp of `a`, relative to
    /// the largest entry of e^A (nalgebra is accurate to 1e-14 relative at ‖A‖ = 10,
    /// checked when the dependency was chosen).
    pub fn exp_error_against_nalgebra(a: &Mat<c64>, ours: &Mat<c64>) -> f64 {
        use nalgebra::DMatrix;
        use num_complex::Complex;
        let n = a.nrows();
        let na = DMatrix::<Complex<f64>>::from_fn(n, n, |i, j| a[(i, j)]).exp();
        let norm = na.iter().map(|z| z.norm()).fold(0.0, f64::max);
        let err = (0..n)
            .flat_map(|i| (0..n).map(move |j| (i, j)))
            .map(|(i, j)| (ours[(i, j)] - na[(i, j)]).norm())
            .fold(0.0, f64::max);
        err / norm
    }
}
