//! The quadratic eigenproblem of the real coordinates, `(λ²M + λD + K) x = 0` with M real
//! symmetric positive definite, D real (damping plus the skew gyroscopic Ω·G_r) and K
//! real with a positive definite symmetric part (the supports' cross-coupling makes it
//! unsymmetric): the first-order form of [`super::solve_qep_definite`] generalised.

use super::qep::{unit_column, QepSolution, DEFINITE_FORM_SPREAD};
use super::seq;
use faer::linalg::triangular_solve::{solve_lower_triangular_in_place, solve_upper_triangular_in_place};
use faer::{c64, Mat, MatRef, Par};

/// Solve `(λ²M + λD + K) x = 0` for real M ≻ 0, D and K with K_s = (K + Kᵀ)/2 ≻ 0.
///
/// With M = L_M·L_Mᵀ, K_s = L_S·L_Sᵀ and z = [L_Mᵀ·λx; L_Sᵀ·x]:
/// λz = A·z, A = [[−L_M⁻¹·D·L_M⁻ᵀ, −F − L_M⁻¹·K_a·L_S⁻ᵀ], [Fᵀ, 0]], F = L_M⁻¹·L_S, K_a the
/// skew part of K. Every block is of the size of the whirl frequencies, as in the
/// symmetric form. When D is skew (no damping: gyroscopic terms only) and K symmetric, A
/// is real skew-symmetric and j·A Hermitian: the eigenvalues are exactly imaginary.
/// A real A otherwise, solved by the real Schur form. Returns `None` where the form does
/// not apply (a massless DOF, M or K_s not positive definite, a spread of |λ| above
/// [`DEFINITE_FORM_SPREAD`], non-finite results): the caller uses shift-invert there.
pub fn solve_qep_real(m: MatRef<'_, f64>, d: MatRef<'_, f64>, k: MatRef<'_, f64>) -> Option<QepSolution> {
    let n = m.nrows();
    if (0..n).any(|i| (0..n).all(|j| m[(i, j)] == 0.0)) {
        return None;
    }
    let k_s = Mat::from_fn(n, n, |i, j| 0.5 * (k[(i, j)] + k[(j, i)]));
    let skew_k = (0..n).any(|i| (0..n).any(|j| k[(i, j)] != k[(j, i)]));
    let l_m = seq::cholesky(m).ok()?;
    let l_s = seq::cholesky(k_s.as_ref()).ok()?;
    // F = L_M⁻¹·L_S.
    let mut f = l_s.clone();
    solve_lower_triangular_in_place(l_m.as_ref(), f.as_mut(), Par::Seq);
    // L_M⁻¹·D·L_M⁻ᵀ = L_M⁻¹·(L_M⁻¹·Dᵀ)ᵀ.
    let mut x = d.transpose().to_owned();
    solve_lower_triangular_in_place(l_m.as_ref(), x.as_mut(), Par::Seq);
    let mut d_hat = x.transpose().to_owned();
    solve_lower_triangular_in_place(l_m.as_ref(), d_hat.as_mut(), Par::Seq);
    // L_M⁻¹·K_a·L_S⁻ᵀ = L_M⁻¹·(L_S⁻¹·K_aᵀ)ᵀ.
    let mut top_right = Mat::from_fn(n, n, |i, j| -f[(i, j)]);
    if skew_k {
        let mut y = Mat::from_fn(n, n, |i, j| 0.5 * (k[(j, i)] - k[(i, j)]));
        solve_lower_triangular_in_place(l_s.as_ref(), y.as_mut(), Par::Seq);
        let mut z = y.transpose().to_owned();
        solve_lower_triangular_in_place(l_m.as_ref(), z.as_mut(), Par::Seq);
        for j in 0..n {
            for i in 0..n {
                top_right[(i, j)] -= z[(i, j)];
            }
        }
    }
    let undamped = !skew_k && (0..n).all(|i| (0..=i).all(|j| d[(i, j)] + d[(j, i)] == 0.0));
    let a = Mat::from_fn(2 * n, 2 * n, |i, j| match (i < n, j < n) {
        (true, true) => -d_hat[(i, j)],
        (true, false) => top_right[(i, j - n)],
        (false, true) => f[(j, i - n)],
        (false, false) => 0.0,
    });
    if !a.norm_max().is_finite() {
        return None;
    }
    let (values, z): (Vec<c64>, Mat<c64>) = if undamped {
        // j·A, Hermitian: A is skew-symmetric (the skew part of −D̂ and [[·, −F], [Fᵀ, ·]]).
        let h = Mat::from_fn(2 * n, 2 * n, |i, j| c64::new(0.0, 0.5 * (a[(i, j)] - a[(j, i)])));
        let u = seq::self_adjoint_eigen(h.as_ref()).ok()?.vectors;
        // μ as the Rayleigh quotients of the orthonormal eigenvectors (as the symmetric form).
        let hu = seq::product(h.as_ref(), u.as_ref());
        let mu = (0..2 * n).map(|c| (0..2 * n).map(|i| u[(i, c)].conj() * hu[(i, c)]).sum::<c64>().re);
        (mu.map(|m| c64::new(0.0, -m)).collect(), u)
    } else {
        let evd = seq::eigen_real(a.as_ref()).ok()?;
        (evd.values, evd.vectors)
    };
    let moduli = values.iter().map(|v| v.norm());
    let (lo, hi) = moduli.fold((f64::INFINITY, 0.0f64), |(lo, hi), x| (lo.min(x), hi.max(x)));
    if !(hi.is_finite() && lo > 0.0 && hi <= DEFINITE_FORM_SPREAD * lo) {
        return None;
    }
    // x = L_S⁻ᵀ·z₂, unit 2-norm.
    let l_st = Mat::from_fn(n, n, |i, j| c64::new(l_s[(j, i)], 0.0));
    let mut vectors = Mat::from_fn(n, 2 * n, |i, j| z[(n + i, j)]);
    solve_upper_triangular_in_place(l_st.as_ref(), vectors.as_mut(), Par::Seq);
    for col in 0..2 * n {
        unit_column(&mut vectors, col)?;
    }
    Some(QepSolution { values, vectors })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::testing::{random, sorted, spd};
    use crate::linalg::{qep_residual, solve_qep};

    #[test]
    fn real_form_agrees_with_shift_invert_on_cross_coupled_and_gyroscopic_systems() {
        let n = 6;
        let (m, k0) = (spd(n, 1, 0.5), spd(n, 2, 3.0));
        let g = random(n, 3);
        let skew = Mat::from_fn(n, n, |i, j| g[(i, j)] - g[(j, i)]);
        let c = spd(n, 4, 0.0);
        let cross = random(n, 5);
        for (damped, coupled) in [(false, false), (true, false), (false, true), (true, true)] {
            let d = Mat::from_fn(n, n, |i, j| 3.0 * skew[(i, j)] + if damped { 0.1 * c[(i, j)] } else { 0.0 });
            let k = Mat::from_fn(n, n, |i, j| {
                k0[(i, j)] + if coupled { 0.2 * (cross[(i, j)] - cross[(j, i)]) } else { 0.0 }
            });
            let a = solve_qep_real(m.as_ref(), d.as_ref(), k.as_ref()).expect("applies");
            let dc = Mat::from_fn(n, n, |i, j| c64::new(d[(i, j)], 0.0));
            let b = solve_qep(m.as_ref(), dc.as_ref(), k.as_ref(), 0.01).unwrap();
            for (x, y) in sorted(a.values.clone()).iter().zip(sorted(b.values)) {
                assert!((x - y).norm() < 1e-10 * y.norm(), "{x} vs {y}");
            }
            for (col, lambda) in a.values.iter().enumerate() {
                let r = qep_residual(m.as_ref(), dc.as_ref(), k.as_ref(), *lambda, a.vectors.col(col));
                assert!(r < 1e-13, "{r}");
                if !damped && !coupled {
                    assert_eq!(lambda.re, 0.0, "undamped gyroscopic: exactly imaginary");
                }
            }
        }
    }
}
