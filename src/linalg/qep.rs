//! The quadratic eigenproblem `(λ²M + λD + K) x = 0` by the spectral transformation of
//! Eq. (18)–(21): with the first-companion pencil `A z = λ B z`,
//! `A = [−D −K; I 0]`, `B = diag(M, I)`, `z = [λx; x]`, the eigenvalues ν of
//! `(A − σB)⁻¹ B` give `λ = σ + 1/ν`. M is never inverted, so a singular M (a shunt
//! branch with L = 0) only produces ν = 0 (λ = ∞), which is dropped.

use super::LinalgError;
use faer::{c64, linalg::solvers::Solve, Mat, MatRef};

/// Relative size below which ν = 1/(λ − σ) is an infinite eigenvalue of a singular M.
/// Eigenvalues of |λ| > 1e12·|λ_min| are far beyond any modelled physics (the largest
/// whirl frequencies are ~1e5 rad/s), while round-off in ν of an exact zero is ~1e-16.
const INFINITE_NU_RELATIVE: f64 = 1e-12;

/// Finite eigenpairs of a QEP.
#[derive(Debug, Clone)]
pub struct QepSolution {
    /// Eigenvalues λ (1/s): Im λ is the whirl frequency, −Re λ the decay rate.
    pub values: Vec<c64>,
    /// Right eigenvectors x (columns, unit 2-norm), same order as `values`.
    pub vectors: Mat<c64>,
}

/// Solve `(λ²M + λD + K) x = 0` with real shift `shift` (1/s), which must not be an
/// eigenvalue; a small positive shift is safe for any passive (stable) system.
pub fn solve_qep(
    m: MatRef<'_, f64>,
    d: MatRef<'_, c64>,
    k: MatRef<'_, f64>,
    shift: f64,
) -> Result<QepSolution, LinalgError> {
    let n = m.nrows();
    let re = |x: f64| c64::new(x, 0.0);
    // A − σB = [−D − σM, −K; I, −σI].
    let shifted = Mat::from_fn(2 * n, 2 * n, |i, j| match (i < n, j < n) {
        (true, true) => -d[(i, j)] - re(shift * m[(i, j)]),
        (true, false) => re(-k[(i, j - n)]),
        (false, true) => re(if i - n == j { 1.0 } else { 0.0 }),
        (false, false) => re(if i == j { -shift } else { 0.0 }),
    });
    if shifted.norm_max().is_nan() || !shifted.norm_max().is_finite() {
        return Err(LinalgError::NonFinite { what: "QEP" });
    }
    let b = Mat::from_fn(2 * n, 2 * n, |i, j| match (i < n, j < n) {
        (true, true) => re(m[(i, j)]),
        (false, false) => re(if i == j { 1.0 } else { 0.0 }),
        _ => re(0.0),
    });
    let t = shifted.partial_piv_lu().solve(&b);
    if !t.norm_max().is_finite() {
        return Err(LinalgError::SingularShift { shift });
    }
    let evd = t.eigen().map_err(|_| LinalgError::NoConvergence { what: "QEP" })?;
    let nu = evd.S().column_vector();
    let nu_max = (0..2 * n).map(|i| nu[i].norm()).fold(0.0, f64::max);
    let mut values = Vec::new();
    let mut columns = Vec::new();
    for i in 0..2 * n {
        if nu[i].norm() > INFINITE_NU_RELATIVE * nu_max {
            values.push(re(shift) + nu[i].inv());
            columns.push(i);
        }
    }
    let u = evd.U();
    let mut vectors = Mat::<c64>::zeros(n, columns.len());
    for (c, &col) in columns.iter().enumerate() {
        let norm = (0..n).map(|r| u[(n + r, col)].norm_sqr()).sum::<f64>().sqrt();
        for r in 0..n {
            vectors[(r, c)] = u[(n + r, col)] / norm;
        }
    }
    Ok(QepSolution { values, vectors })
}

/// Relative residual `‖(λ²M + λD + K)x‖ / ((|λ|²‖M‖ + |λ|‖D‖ + ‖K‖)‖x‖)` in max norms.
pub fn qep_residual(
    m: MatRef<'_, f64>,
    d: MatRef<'_, c64>,
    k: MatRef<'_, f64>,
    lambda: c64,
    x: faer::ColRef<'_, c64>,
) -> f64 {
    let n = m.nrows();
    let l2 = lambda * lambda;
    let mut worst: f64 = 0.0;
    for i in 0..n {
        let mut acc = c64::new(0.0, 0.0);
        for j in 0..n {
            acc += (l2 * m[(i, j)] + lambda * d[(i, j)] + c64::new(k[(i, j)], 0.0)) * x[j];
        }
        worst = worst.max(acc.norm());
    }
    let scale = (lambda.norm_sqr() * m.norm_max() + lambda.norm() * d.norm_max() + k.norm_max())
        * (0..n).map(|i| x[i].norm()).fold(0.0, f64::max);
    worst / scale
}
