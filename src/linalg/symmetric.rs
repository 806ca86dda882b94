//! `B x = θ A x` for real symmetric A (positive definite) and B (semi-definite).

use super::LinalgError;
use faer::{linalg::solvers::Solve, Mat, MatRef, Side};

/// Eigenpairs of `B x = θ A x`, sorted by θ descending; `vectors` are A-orthonormal.
#[derive(Debug, Clone)]
pub struct DefiniteEigen {
    /// θ, descending.
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
    let llt = a.llt(Side::Lower).map_err(|_| LinalgError::NotPositiveDefinite { what: "stiffness" })?;
    let l = llt.L();
    // W = L⁻¹ B L⁻ᵀ = L⁻¹ (L⁻¹ B)ᵀ since B is symmetric.
    let mut x = b.to_owned();
    l.solve_lower_triangular_in_place(x.as_mut());
    let mut w = x.transpose().to_owned();
    l.solve_lower_triangular_in_place(w.as_mut());
    let w = Mat::from_fn(n, n, |i, j| 0.5 * (w[(i, j)] + w[(j, i)]));
    let evd = w.self_adjoint_eigen(Side::Lower).map_err(|_| LinalgError::NoConvergence { what: "symmetric" })?;
    let s = evd.S().column_vector();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&i, &j| s[j].total_cmp(&s[i]));
    let values = order.iter().map(|&i| s[i]).collect();
    let y = Mat::from_fn(n, n, |i, k| evd.U()[(i, order[k])]);
    // x = L⁻ᵀ y.
    let vectors = llt.L().transpose().to_owned().partial_piv_lu().solve(&y);
    Ok(DefiniteEigen { values, vectors })
}

fn finite(a: MatRef<'_, f64>) -> bool {
    (0..a.nrows()).all(|i| (0..a.ncols()).all(|j| a[(i, j)].is_finite()))
}
