//! faer's dense kernels with their parallelism passed explicitly, always `Par::Seq`.
//!
//! faer's operators on matrices (`&a * &b`) and its decomposition methods
//! (`.partial_piv_lu()`, `.llt()`, `.eigen()`, `.self_adjoint_eigen()`, `.eigenvalues()`,
//! `Solve::solve`, …) read the process-wide `faer::get_global_parallelism()`. The library
//! calls faer only through entry points that take a `Par` argument, these wrappers among
//! them, so that it neither depends on nor changes a caller's global setting. The
//! parallelism of the library is rayon over its outermost loops; faer's kernels, inside
//! those loops, run sequentially, so results do not depend on the thread count.
//!
//! Each wrapper makes the same calls, with the same default parameters, as the faer method
//! it replaces does with `Par::Seq`: the results are the same to the bit.

use faer::diag::Diag;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt;
use faer::linalg::evd::{self, ComputeEigenvectors, EvdError};
use faer::linalg::lu::partial_pivoting;
use faer::linalg::matmul::matmul;
use faer::linalg::solvers::LltError;
use faer::traits::math_utils::{one, real, zero};
use faer::traits::ComplexField;
use faer::{c64, Accum, Conj, Mat, MatRef, Par};

/// The parallelism passed to every faer kernel the library calls.
const PAR: Par = Par::Seq;

/// Eigenvalues and eigenvectors (columns, in the same order) of a decomposition.
#[derive(Debug, Clone)]
pub struct Eigenpairs<V, T> {
    /// The eigenvalues, in faer's order.
    pub values: Vec<V>,
    /// The eigenvectors as columns; column k belongs to `values[k]`.
    pub vectors: Mat<T>,
}

/// The product A·B.
pub fn product<T: ComplexField>(a: MatRef<'_, T>, b: MatRef<'_, T>) -> Mat<T> {
    let mut out = Mat::<T>::zeros(a.nrows(), b.ncols());
    matmul(out.as_mut(), Accum::Replace, a, b, one::<T>(), PAR);
    out
}

/// X = A⁻¹·B for a square A, by LU with partial (row) pivoting. A singular A gives
/// non-finite entries, as faer's `partial_piv_lu().solve()` does.
pub fn lu_solve<T: ComplexField>(a: MatRef<'_, T>, b: MatRef<'_, T>) -> Mat<T> {
    let n = a.nrows();
    let mut lu = a.to_owned();
    let mut perm = vec![0usize; n];
    let mut perm_inv = vec![0usize; n];
    let mut factor_mem =
        MemBuffer::new(partial_pivoting::factor::lu_in_place_scratch::<usize, T>(n, n, PAR, Default::default()));
    let (_, p) = partial_pivoting::factor::lu_in_place(
        lu.as_mut(),
        &mut perm,
        &mut perm_inv,
        PAR,
        MemStack::new(&mut factor_mem),
        Default::default(),
    );
    let mut x = b.to_owned();
    let mut solve_mem = MemBuffer::new(partial_pivoting::solve::solve_in_place_scratch::<usize, T>(n, x.ncols(), PAR));
    // The unit lower solve reads only the strict lower triangle of `lu` and the upper
    // solve only its upper triangle: the packed factors serve as both L and U.
    partial_pivoting::solve::solve_in_place_with_conj(
        lu.as_ref(),
        lu.as_ref(),
        p,
        Conj::No,
        x.as_mut(),
        PAR,
        MemStack::new(&mut solve_mem),
    );
    x
}

/// The lower Cholesky factor L of A = L·Lᴴ (from A's lower triangle; the strict upper
/// triangle of L is zero). Fails when A is not positive definite.
pub fn cholesky<T: ComplexField>(a: MatRef<'_, T>) -> Result<Mat<T>, LltError> {
    let n = a.nrows();
    let mut l = Mat::<T>::zeros(n, n);
    l.copy_from_triangular_lower(a);
    let mut mem = MemBuffer::new(llt::factor::cholesky_in_place_scratch::<T>(n, PAR, Default::default()));
    llt::factor::cholesky_in_place(l.as_mut(), Default::default(), PAR, MemStack::new(&mut mem), Default::default())?;
    for j in 1..n {
        for i in 0..j {
            l[(i, j)] = zero::<T>();
        }
    }
    Ok(l)
}

/// X = A⁻¹·B from the lower Cholesky factor L of A ([`cholesky`]).
pub fn cholesky_solve<T: ComplexField>(l: MatRef<'_, T>, b: MatRef<'_, T>) -> Mat<T> {
    let mut x = b.to_owned();
    let mut mem = MemBuffer::new(llt::solve::solve_in_place_scratch::<T>(l.nrows(), x.ncols(), PAR));
    llt::solve::solve_in_place_with_conj(l, Conj::No, x.as_mut(), PAR, MemStack::new(&mut mem));
    x
}

/// Eigenpairs of a self-adjoint A from its lower triangle: real eigenvalues ascending,
/// orthonormal eigenvectors.
pub fn self_adjoint_eigen<T: ComplexField>(a: MatRef<'_, T>) -> Result<Eigenpairs<T::Real, T>, EvdError> {
    let n = a.nrows();
    let mut u = Mat::<T>::zeros(n, n);
    let mut s = Diag::<T>::zeros(n);
    let mut mem =
        MemBuffer::new(evd::self_adjoint_evd_scratch::<T>(n, ComputeEigenvectors::Yes, PAR, Default::default()));
    evd::self_adjoint_evd(a, s.as_mut(), Some(u.as_mut()), PAR, MemStack::new(&mut mem), Default::default())?;
    let values = s.column_vector().iter().map(real).collect();
    Ok(Eigenpairs { values, vectors: u })
}

/// Eigenpairs of a general complex A (right eigenvectors).
pub fn eigen(a: MatRef<'_, c64>) -> Result<Eigenpairs<c64, c64>, EvdError> {
    let n = a.nrows();
    let mut u = Mat::<c64>::zeros(n, n);
    let mut s = Diag::<c64>::zeros(n);
    let mut mem = MemBuffer::new(evd::evd_scratch::<c64>(
        n,
        ComputeEigenvectors::No,
        ComputeEigenvectors::Yes,
        PAR,
        Default::default(),
    ));
    evd::evd_cplx(a, s.as_mut(), None, Some(u.as_mut()), PAR, MemStack::new(&mut mem), Default::default())?;
    Ok(Eigenpairs { values: s.column_vector().iter().copied().collect(), vectors: u })
}

/// Eigenvalues of a general complex A (no eigenvectors computed).
pub fn eigenvalues(a: MatRef<'_, c64>) -> Result<Vec<c64>, EvdError> {
    let n = a.nrows();
    let mut s = Diag::<c64>::zeros(n);
    let mut mem = MemBuffer::new(evd::evd_scratch::<c64>(
        n,
        ComputeEigenvectors::No,
        ComputeEigenvectors::No,
        PAR,
        Default::default(),
    ));
    evd::evd_cplx(a, s.as_mut(), None, None, PAR, MemStack::new(&mut mem), Default::default())?;
    Ok(s.column_vector().iter().copied().collect())
}

/// Eigenpairs of a general real A (right eigenvectors), as complex values and vectors:
/// a real eigenvalue with its real vector, a conjugate pair as two columns (λ, x) and
/// (λ̄, x̄). A real Schur decomposition: half the work of [`eigen`] on the same matrix
/// held as complex.
pub fn eigen_real(a: MatRef<'_, f64>) -> Result<Eigenpairs<c64, c64>, EvdError> {
    let n = a.nrows();
    let mut u = Mat::<f64>::zeros(n, n);
    let mut s_re = Diag::<f64>::zeros(n);
    let mut s_im = Diag::<f64>::zeros(n);
    let mut mem = MemBuffer::new(evd::evd_scratch::<f64>(
        n,
        ComputeEigenvectors::No,
        ComputeEigenvectors::Yes,
        PAR,
        Default::default(),
    ));
    evd::evd_real(
        a,
        s_re.as_mut(),
        s_im.as_mut(),
        None,
        Some(u.as_mut()),
        PAR,
        MemStack::new(&mut mem),
        Default::default(),
    )?;
    let (re, im) = (s_re.column_vector(), s_im.column_vector());
    let mut values = Vec::with_capacity(n);
    let mut vectors = Mat::<c64>::zeros(n, n);
    let mut i = 0;
    while i < n {
        if im[i] == 0.0 || i + 1 == n {
            values.push(c64::new(re[i], 0.0));
            for r in 0..n {
                vectors[(r, i)] = c64::new(u[(r, i)], 0.0);
            }
            i += 1;
        } else {
            values.push(c64::new(re[i], im[i]));
            values.push(c64::new(re[i + 1], im[i + 1]));
            for r in 0..n {
                let z = c64::new(u[(r, i)], u[(r, i + 1)]);
                vectors[(r, i)] = z;
                vectors[(r, i + 1)] = z.conj();
            }
            i += 2;
        }
    }
    Ok(Eigenpairs { values, vectors })
}

/// A real LU factorisation with partial (row) pivoting, kept to solve many right-hand sides:
/// the factor of [`lu_solve`], computed once.
#[derive(Debug, Clone)]
pub struct Lu {
    /// The packed factors: L's strict lower triangle (unit diagonal) and U.
    lu: Mat<f64>,
    /// The row permutation and its inverse.
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
}

impl Lu {
    /// The factorisation of a square A.
    pub fn new(a: MatRef<'_, f64>) -> Lu {
        let n = a.nrows();
        let mut lu = a.to_owned();
        let mut perm = vec![0usize; n];
        let mut perm_inv = vec![0usize; n];
        let mut mem =
            MemBuffer::new(partial_pivoting::factor::lu_in_place_scratch::<usize, f64>(n, n, PAR, Default::default()));
        let _ = partial_pivoting::factor::lu_in_place(
            lu.as_mut(),
            &mut perm,
            &mut perm_inv,
            PAR,
            MemStack::new(&mut mem),
            Default::default(),
        );
        Lu { lu, perm, perm_inv }
    }

    /// The smallest and the largest modulus of U's diagonal: a zero or non-finite pivot
    /// means A is singular (or not finite) and the solves are not to be used.
    pub fn pivot_range(&self) -> (f64, f64) {
        let n = self.lu.nrows();
        (0..n).map(|i| self.lu[(i, i)].abs()).fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
            (lo.min(v), if v.is_finite() { hi.max(v) } else { f64::INFINITY })
        })
    }

    /// X := A⁻¹·X.
    pub fn solve_in_place(&self, x: faer::MatMut<'_, f64>) {
        let n = self.lu.nrows();
        let p = faer::perm::PermRef::new_checked(&self.perm, &self.perm_inv, n);
        let mut mem = MemBuffer::new(partial_pivoting::solve::solve_in_place_scratch::<usize, f64>(n, x.ncols(), PAR));
        partial_pivoting::solve::solve_in_place_with_conj(
            self.lu.as_ref(),
            self.lu.as_ref(),
            p,
            Conj::No,
            x,
            PAR,
            MemStack::new(&mut mem),
        );
    }
}
