//! The quadratic eigenproblem `(λ²M + λD + K) x = 0` by the spectral transformation of
//! Eq. (18)–(21): with the first-companion pencil `A z = λ B z`,
//! `A = [−D −K; I 0]`, `B = diag(M, I)`, `z = [λx; x]`, the eigenvalues ν of
//! `(A − σB)⁻¹ B` give `λ = σ + 1/ν`. M is never inverted, so a singular M (a shunt
//! branch with L = 0) only produces ν = 0 (λ = ∞), which is dropped.

use super::{seq, LinalgError};
use faer::{c64, Mat, MatRef};

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
    let t = seq::lu_solve(shifted.as_ref(), b.as_ref());
    if !t.norm_max().is_finite() {
        return Err(LinalgError::SingularShift { shift });
    }
    let evd = seq::eigen(t.as_ref()).map_err(|_| LinalgError::NoConvergence { what: "QEP" })?;
    let nu = &evd.values;
    let nu_max = (0..2 * n).map(|i| nu[i].norm()).fold(0.0, f64::max);
    let mut values = Vec::new();
    let mut columns = Vec::new();
    for (i, v) in nu.iter().enumerate() {
        if v.norm() > INFINITE_NU_RELATIVE * nu_max {
            values.push(re(shift) + v.inv());
            columns.push(i);
        }
    }
    let u = &evd.vectors;
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
/// Numerator and denominator are both divided by s² = max(1, |λ|)² first, so that no
/// finite λ overflows them (|λ|² does beyond 1e154); NaN only for non-finite input.
pub fn qep_residual(
    m: MatRef<'_, f64>,
    d: MatRef<'_, c64>,
    k: MatRef<'_, f64>,
    lambda: c64,
    x: faer::ColRef<'_, c64>,
) -> f64 {
    qep_residual_with(&QepNorms::of(m, d, k), m, d, k, lambda, x)
}

/// The max norms of M, D and K that [`qep_residual`] scales by, computed once for the
/// many eigenpairs of one pencil.
#[derive(Debug, Clone, Copy)]
pub struct QepNorms {
    m: f64,
    d: f64,
    k: f64,
}

impl QepNorms {
    /// ‖M‖, ‖D‖, ‖K‖ in max norm.
    pub fn of(m: MatRef<'_, f64>, d: MatRef<'_, c64>, k: MatRef<'_, f64>) -> QepNorms {
        QepNorms { m: m.norm_max(), d: d.norm_max(), k: k.norm_max() }
    }
}

/// [`qep_residual`] with the pencil's norms given. The product runs column by column
/// (contiguous in the column-major matrices); each row's sum still adds its terms in
/// column order, so the result is the same to the bit.
pub fn qep_residual_with(
    norms: &QepNorms,
    m: MatRef<'_, f64>,
    d: MatRef<'_, c64>,
    k: MatRef<'_, f64>,
    lambda: c64,
    x: faer::ColRef<'_, c64>,
) -> f64 {
    let n = m.nrows();
    let s = lambda.norm().max(1.0);
    let mu = lambda / s;
    let (a, b, c) = (mu * mu, mu / s, 1.0 / (s * s));
    let x_max = (0..n).map(|i| x[i].norm()).fold(0.0, f64::max);
    let mut acc = vec![c64::new(0.0, 0.0); n];
    for j in 0..n {
        let xj = x[j] / x_max;
        for (i, acc) in acc.iter_mut().enumerate() {
            *acc += (a * m[(i, j)] + b * d[(i, j)] + c64::new(c * k[(i, j)], 0.0)) * xj;
        }
    }
    let worst = acc.iter().fold(0.0_f64, |w, v| w.max(v.norm()));
    let scale = a.norm() * norms.m + b.norm() * norms.d + c * norms.k;
    worst / scale
}

/// Widest spread of eigenvalue moduli |λ|_max/|λ|_min for which [`solve_qep_definite`]
/// answers: its eigenvalues are accurate to ~ε·|λ|_max absolute, so at this spread the
/// lowest whirl keeps ~1e-8 relative accuracy; beyond it (e.g. a charge mass of 1e-290 kg
/// next to kg-scale masses), shift-invert, whose error grows the other way, is the better
/// solver.
pub const DEFINITE_FORM_SPREAD: f64 = 1e8;

/// Solve `(λ²M + λD + K) x = 0` for real symmetric M ⪰ 0, K ≻ 0 and D = C + j·G̃ with C,
/// G̃ real symmetric (a gyroscopic system: C the damping, G̃ = −ΩG), in a first-order
/// form that keeps the structure:
///
/// with M = L_M·L_Mᵀ, K = L_K·L_Kᵀ (Cholesky) and z = [L_Mᵀ·λx; L_Kᵀ·x],
/// λz = A·z, A = [[−L_M⁻¹·D·L_M⁻ᵀ, −F], [Fᵀ, 0]], F = L_M⁻¹·L_K.
///
/// Every block of A is of the size of the whirl frequencies (its singular values are
/// the ω's), so eigenvalues come out with an absolute error ~ε·ω_max and damping ratios
/// with ~ε·ω_max/ω — where shift-invert on the physical pencil leaves ±1e-3 of spurious
/// damping on the high modes of an undamped model (docs/decisions.md). Undamped (C = 0),
/// A is skew-Hermitian: λ = −jμ with μ the real eigenvalues of the Hermitian j·A, so
/// the damping is exactly zero, as it is for any conservative gyroscopic system.
///
/// Massless DOFs (rows of M that are zero, e.g. a shunt branch with L = 0) are condensed
/// statically when D vanishes on them. Returns `None` where the form does not apply (a
/// massless DOF with damping or gyroscopic terms, M or K not positive definite, spread
/// of |λ| above [`DEFINITE_FORM_SPREAD`], non-finite results): the caller uses
/// [`solve_qep`] there.
pub fn solve_qep_definite(m: MatRef<'_, f64>, d: MatRef<'_, c64>, k: MatRef<'_, f64>) -> Option<QepSolution> {
    use faer::linalg::triangular_solve::{solve_lower_triangular_in_place, solve_upper_triangular_in_place};
    use faer::Par;
    let n = m.nrows();
    let massless: Vec<bool> = (0..n).map(|i| (0..n).all(|j| m[(i, j)] == 0.0)).collect();
    if (0..n).any(|i| massless[i] && (0..n).any(|j| d[(i, j)] != c64::new(0.0, 0.0))) {
        return None;
    }
    let kept: Vec<usize> = (0..n).filter(|&i| !massless[i]).collect();
    let gone: Vec<usize> = (0..n).filter(|&i| massless[i]).collect();
    let r = kept.len();
    if r == 0 {
        return None;
    }
    let sub = |a: MatRef<'_, f64>, rows: &[usize], cols: &[usize]| {
        Mat::from_fn(rows.len(), cols.len(), |i, j| a[(rows[i], cols[j])])
    };
    // Static condensation K_c = K_rr − K_rm·K_mm⁻¹·K_mr, and X = K_mm⁻¹·K_mr for the
    // massless part of the shapes, x_m = −X·x_r.
    let (k_c, x_gone) = if gone.is_empty() {
        (sub(k, &kept, &kept), None)
    } else {
        let k_mm = sub(k, &gone, &gone);
        let l_mm = seq::cholesky(k_mm.as_ref()).ok()?;
        let x = seq::cholesky_solve(l_mm.as_ref(), sub(k, &gone, &kept).as_ref());
        let k_rm = sub(k, &kept, &gone);
        let k_rr = sub(k, &kept, &kept);
        let k_c = &k_rr - seq::product(k_rm.as_ref(), x.as_ref());
        (Mat::from_fn(r, r, |i, j| 0.5 * (k_c[(i, j)] + k_c[(j, i)])), Some(x))
    };
    let l_m = seq::cholesky(sub(m, &kept, &kept).as_ref()).ok()?;
    let l_k = seq::cholesky(k_c.as_ref()).ok()?;
    // F = L_M⁻¹·L_K.
    let mut f = l_k.clone();
    solve_lower_triangular_in_place(l_m.as_ref(), f.as_mut(), Par::Seq);
    // L_M⁻¹·P·L_M⁻ᵀ of a real symmetric P, symmetrised.
    let congruent = |p: Mat<f64>| {
        let mut x = p;
        solve_lower_triangular_in_place(l_m.as_ref(), x.as_mut(), Par::Seq);
        let mut y = x.transpose().to_owned();
        solve_lower_triangular_in_place(l_m.as_ref(), y.as_mut(), Par::Seq);
        Mat::from_fn(r, r, |i, j| 0.5 * (y[(i, j)] + y[(j, i)]))
    };
    let c_rr = Mat::from_fn(r, r, |i, j| d[(kept[i], kept[j])].re);
    let undamped = (0..r).all(|j| (0..r).all(|i| c_rr[(i, j)] == 0.0));
    let c_hat = congruent(c_rr);
    let g_hat = congruent(Mat::from_fn(r, r, |i, j| d[(kept[i], kept[j])].im));
    let re = |x: f64| c64::new(x, 0.0);
    let (values, z): (Vec<c64>, Mat<c64>) = if undamped {
        // j·A = [[Ĝ, −jF], [jFᵀ, 0]], Hermitian.
        let h = Mat::from_fn(2 * r, 2 * r, |i, j| match (i < r, j < r) {
            (true, true) => re(g_hat[(i, j)]),
            (true, false) => c64::new(0.0, -f[(i, j - r)]),
            (false, true) => c64::new(0.0, f[(j, i - r)]),
            (false, false) => re(0.0),
        });
        if !h.norm_max().is_finite() {
            return None;
        }
        let u = seq::self_adjoint_eigen(h.as_ref()).ok()?.vectors;
        // μ as the Rayleigh quotients zᴴHz of the (orthonormal) eigenvectors: second-order
        // accurate in their error. faer's eigenvalues from the decomposition with vectors
        // were 1e-9 off on the Table 2 rotor (9953.677238 against 9953.677229 rad/s from
        // its eigenvalues-only routine and from inverse iteration).
        let hu = seq::product(h.as_ref(), u.as_ref());
        let mu = (0..2 * r).map(|c| (0..2 * r).map(|i| u[(i, c)].conj() * hu[(i, c)]).sum::<c64>().re);
        (mu.map(|m| c64::new(0.0, -m)).collect(), u)
    } else {
        let a = Mat::from_fn(2 * r, 2 * r, |i, j| match (i < r, j < r) {
            (true, true) => c64::new(-c_hat[(i, j)], -g_hat[(i, j)]),
            (true, false) => re(-f[(i, j - r)]),
            (false, true) => re(f[(j, i - r)]),
            (false, false) => re(0.0),
        });
        if !a.norm_max().is_finite() {
            return None;
        }
        let evd = seq::eigen(a.as_ref()).ok()?;
        (evd.values, evd.vectors)
    };
    let moduli = values.iter().map(|v| v.norm());
    let (lo, hi) = moduli.fold((f64::INFINITY, 0.0f64), |(lo, hi), x| (lo.min(x), hi.max(x)));
    if !(hi.is_finite() && lo > 0.0 && hi <= DEFINITE_FORM_SPREAD * lo) {
        return None;
    }
    // x_r = L_K⁻ᵀ·z₂, x_m = −X·x_r, unit 2-norm.
    let l_kt = Mat::from_fn(r, r, |i, j| re(l_k[(j, i)]));
    let mut x_r = Mat::from_fn(r, 2 * r, |i, j| z[(r + i, j)]);
    solve_upper_triangular_in_place(l_kt.as_ref(), x_r.as_mut(), Par::Seq);
    let mut vectors = Mat::<c64>::zeros(n, 2 * r);
    for col in 0..2 * r {
        for (a, &i) in kept.iter().enumerate() {
            vectors[(i, col)] = x_r[(a, col)];
        }
        if let Some(x) = &x_gone {
            for (b, &i) in gone.iter().enumerate() {
                vectors[(i, col)] = -(0..r).map(|a| x_r[(a, col)] * x[(b, a)]).sum::<c64>();
            }
        }
        unit_column(&mut vectors, col)?;
    }
    Some(QepSolution { values, vectors })
}

/// Scales column `col` of `vectors` to unit 2-norm; `None` when its norm is zero or not
/// finite (a vector the definite form could not recover).
pub(super) fn unit_column(vectors: &mut Mat<c64>, col: usize) -> Option<()> {
    let n = vectors.nrows();
    let norm = (0..n).map(|i| vectors[(i, col)].norm_sqr()).sum::<f64>().sqrt();
    if !(norm.is_finite() && norm > 0.0) {
        return None;
    }
    for i in 0..n {
        vectors[(i, col)] /= norm;
    }
    Some(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::testing::{random, sorted, spd};

    #[test]
    fn definite_form_agrees_with_shift_invert_and_keeps_zero_damping() {
        let n = 6;
        let (m, k) = (spd(n, 1, 0.5), spd(n, 2, 3.0));
        let g = random(n, 3);
        let g = Mat::from_fn(n, n, |i, j| g[(i, j)] + g[(j, i)]);
        let c = spd(n, 4, 0.0);
        for damped in [false, true] {
            let d = Mat::from_fn(n, n, |i, j| c64::new(if damped { 0.1 * c[(i, j)] } else { 0.0 }, -5.0 * g[(i, j)]));
            let a = solve_qep_definite(m.as_ref(), d.as_ref(), k.as_ref()).expect("applies");
            let b = solve_qep(m.as_ref(), d.as_ref(), k.as_ref(), 0.01).unwrap();
            assert_eq!(a.values.len(), 2 * n);
            for (x, y) in sorted(a.values.clone()).iter().zip(sorted(b.values)) {
                assert!((x - y).norm() < 1e-10 * y.norm(), "{x} vs {y}");
            }
            for (col, lambda) in a.values.iter().enumerate() {
                assert!(qep_residual(m.as_ref(), d.as_ref(), k.as_ref(), *lambda, a.vectors.col(col)) < 1e-13);
                if !damped {
                    assert_eq!(lambda.re, 0.0, "undamped: exactly imaginary");
                }
            }
        }
    }

    #[test]
    fn massless_undamped_dofs_are_condensed_and_damped_ones_refused() {
        // DOF 0 without mass: two infinite eigenvalues; the finite ones are those of the
        // pencil condensed on the others, as shift-invert finds them.
        let n = 5;
        let k = spd(n, 7, 2.0);
        let mut m = spd(n, 8, 0.5);
        for j in 0..n {
            m[(0, j)] = 0.0;
            m[(j, 0)] = 0.0;
        }
        let mut d = Mat::from_fn(n, n, |_, _| c64::new(0.0, 0.0));
        d[(1, 2)] = c64::new(0.0, 0.7);
        d[(2, 1)] = c64::new(0.0, 0.7);
        let a = solve_qep_definite(m.as_ref(), d.as_ref(), k.as_ref()).expect("applies");
        let b = solve_qep(m.as_ref(), d.as_ref(), k.as_ref(), 0.01).unwrap();
        assert_eq!((a.values.len(), b.values.len()), (2 * (n - 1), 2 * (n - 1)));
        for (x, y) in sorted(a.values.clone()).iter().zip(sorted(b.values)) {
            assert!((x - y).norm() < 1e-9 * y.norm(), "{x} vs {y}");
        }
        for (col, lambda) in a.values.iter().enumerate() {
            assert!(qep_residual(m.as_ref(), d.as_ref(), k.as_ref(), *lambda, a.vectors.col(col)) < 1e-12);
        }
        // A massless DOF with damping has first-order dynamics: not this form.
        d[(0, 0)] = c64::new(1.0, 0.0);
        assert!(solve_qep_definite(m.as_ref(), d.as_ref(), k.as_ref()).is_none());
    }

    #[test]
    fn residual_is_finite_for_huge_eigenvalues() {
        let (m, k) = (spd(3, 11, 1.0), spd(3, 12, 1.0));
        let d = Mat::from_fn(3, 3, |_, _| c64::new(0.0, 0.0));
        let x = faer::Col::from_fn(3, |i| c64::new(1.0 + i as f64, 0.0));
        // |λ|² = 1e400 overflows unscaled (inf/inf = NaN); scaled, the λ²M term dominates
        // and the residual is ‖Mx‖∞/(‖M‖max·‖x‖∞).
        let r = qep_residual(m.as_ref(), d.as_ref(), k.as_ref(), c64::new(0.0, 1e200), x.as_ref());
        let mx = (0..3).map(|i| (0..3).map(|j| m[(i, j)] * x[j].re).sum::<f64>().abs()).fold(0.0, f64::max);
        let expected = mx / (m.norm_max() * 3.0);
        assert!(r.is_finite() && (r - expected).abs() < 1e-12, "{r} vs {expected}");
    }
}
