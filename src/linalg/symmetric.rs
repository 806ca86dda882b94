//! `B x = θ A x` for real symmetric A (positive definite) and B (semi-definite).

use super::{seq, LinalgError};
use faer::linalg::triangular_solve::solve_lower_triangular_in_place;
use faer::{Mat, MatRef, Par};

/// Eigenpairs of `B x = θ A x`, sorted by θ descending; `vectors` are A-orthonormal.
#[derive(Debug, Clone)]
pub struct DefiniteEigen {
    /// Eigenvalues θ, descending: with A = K, 1/P (1/N) for B = S and 1/ω² (s²) for B = M.
    pub values: Vec<f64>,
    /// Columns x with xᵀ A x = 1.
    pub vectors: Mat<f64>,
}

/// Solve `B x = θ A x` through the Cholesky factor of A: `L⁻¹ B L⁻ᵀ y = θ y`, x = L⁻ᵀ y.
/// With A = K this gives θ = 1/P for buckling (B = S) and θ = 1/ω² for undamped modes
/// (B = M); a singular B (massless charge DOFs) just gives θ = 0, never a division.
pub fn definite_eigen(a: MatRef<'_, f64>, b: MatRef<'_, f64>) -> Result<DefiniteEigen, LinalgError> {
    let n = a.nrows();
    if !finite(a) || !finite(b) {
        return Err(LinalgError::NonFinite { what: "stiffness or mass" });
    }
    let l = seq::cholesky(a).map_err(|_| LinalgError::NotPositiveDefinite { what: "stiffness" })?;
    // W = L⁻¹ B L⁻ᵀ = L⁻¹ (L⁻¹ B)ᵀ since B is symmetric.
    let mut x = b.to_owned();
    solve_lower_triangular_in_place(l.as_ref(), x.as_mut(), Par::Seq);
    let mut w = x.transpose().to_owned();
    solve_lower_triangular_in_place(l.as_ref(), w.as_mut(), Par::Seq);
    let w = Mat::from_fn(n, n, |i, j| 0.5 * (w[(i, j)] + w[(j, i)]));
    let evd = seq::self_adjoint_eigen(w.as_ref()).map_err(|_| LinalgError::NoConvergence { what: "symmetric" })?;
    let s = &evd.values;
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&i, &j| s[j].total_cmp(&s[i]));
    let values = order.iter().map(|&i| s[i]).collect();
    let y = Mat::from_fn(n, n, |i, k| evd.vectors[(i, order[k])]);
    // x = L⁻ᵀ y.
    let vectors = seq::lu_solve(l.transpose().to_owned().as_ref(), y.as_ref());
    Ok(DefiniteEigen { values, vectors })
}

fn finite(a: MatRef<'_, f64>) -> bool {
    (0..a.nrows()).all(|i| (0..a.ncols()).all(|j| a[(i, j)].is_finite()))
}
