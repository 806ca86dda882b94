//! Matrix exponential of a small dense complex matrix: Padé-13 with scaling and squaring
//! (Higham 2005, "The scaling and squaring method for the matrix exponential revisited").
//! faer has none; nalgebra's `exp()` is the accurate but slower reference used in tests.

use super::seq::{lu_solve, product as mul};
use faer::{c64, Mat, MatRef};

/// Most squarings of the scaling and squaring step.
const MAX_SQUARINGS: f64 = 1100.0;

/// Padé-13 coefficients b_0 … b_13.
const B: [f64; 14] = [
    64764752532480000.0,
    32382376266240000.0,
    7771770303897600.0,
    1187353796428800.0,
    129060195264000.0,
    10559470521600.0,
    670442572800.0,
    33522128640.0,
    1323241920.0,
    40840800.0,
    960960.0,
    16380.0,
    182.0,
    1.0,
];

/// θ_13: the 1-norm up to which Padé-13 meets unit round-off without scaling (Higham).
const THETA_13: f64 = 5.371920351148152;

/// Lower Padé orders m with their θ_m and coefficients b_0 … b_m (Higham 2005, Table 2.3):
/// below θ_m the order-m approximant already meets unit round-off, with fewer products.
const LOW_ORDERS: [(f64, &[f64]); 4] = [
    (1.495585217958292e-2, &[120.0, 60.0, 12.0, 1.0]),
    (2.53939833006323e-1, &[30240.0, 15120.0, 3360.0, 420.0, 30.0, 1.0]),
    (9.504178996162932e-1, &[17297280.0, 8648640.0, 1995840.0, 277200.0, 25200.0, 1512.0, 56.0, 1.0]),
    (
        2.097847961257068e0,
        &[17643225600.0, 8821612800.0, 2075673600.0, 302702400.0, 30270240.0, 2162160.0, 110880.0, 3960.0, 90.0, 1.0],
    ),
];

/// Padé approximant of order m = b.len() − 1 (odd, ≤ 9) without scaling.
fn pade_low(a: MatRef<'_, c64>, b: &[f64]) -> Mat<c64> {
    let n = a.nrows();
    let m = b.len() - 1;
    // Even powers A², A⁴, … up to A^{m−1}.
    let mut powers: Vec<Mat<c64>> = vec![Mat::identity(n, n)];
    let a2 = mul(a, a);
    powers.push(a2.clone());
    while 2 * (powers.len() - 1) < m - 1 {
        let Some(last) = powers.last() else { break };
        let next = mul(last.as_ref(), a2.as_ref());
        powers.push(next);
    }
    let mut u_sum = Mat::<c64>::zeros(n, n);
    let mut v = Mat::<c64>::zeros(n, n);
    for (k, p) in powers.iter().enumerate() {
        for j in 0..n {
            let (pc, uc, vc) = (p.col_as_slice(j), u_sum.col_as_slice_mut(j), v.col_as_slice_mut(j));
            for ((x, u), w) in pc.iter().zip(uc.iter_mut()).zip(vc.iter_mut()) {
                *u += x * b[2 * k + 1];
                *w += x * b[2 * k];
            }
        }
    }
    let u = mul(a, u_sum.as_ref());
    // (V − U)·X = V + U, formed in place: v becomes V + U, u becomes V − U.
    let (mut p, mut q) = (v, u);
    for j in 0..n {
        for (pv, qu) in p.col_as_slice_mut(j).iter_mut().zip(q.col_as_slice_mut(j).iter_mut()) {
            let (vv, uu) = (*pv, *qu);
            *pv = vv + uu;
            *qu = vv - uu;
        }
    }
    lu_solve(q.as_ref(), p.as_ref())
}

/// `measure` computed with the modulus |z| = √(re² + im²) of (re, im), and again with the
/// slower, overflow-safe `hypot` only where that is not finite (entries above ~1e154
/// overflow the square; `hypot` costs ~20 ns a call).
pub fn with_modulus(measure: impl Fn(fn(f64, f64) -> f64) -> f64) -> f64 {
    let fast = measure(|x, y| (x * x + y * y).sqrt());
    if fast.is_finite() {
        fast
    } else {
        measure(f64::hypot)
    }
}

/// The 1-norm (largest column sum of moduli, [`with_modulus`]).
pub fn norm1(a: MatRef<'_, c64>) -> f64 {
    with_modulus(|modulus| {
        (0..a.ncols())
            .map(|j| (0..a.nrows()).map(|i| modulus(a[(i, j)].re, a[(i, j)].im)).sum::<f64>())
            .fold(0.0, f64::max)
    })
}

/// e^A for a square complex matrix (sequential; safe inside rayon loops).
/// Returns a NaN-free result for finite input; non-finite input gives non-finite output.
pub fn expm(a: MatRef<'_, c64>) -> Mat<c64> {
    let n = a.nrows();
    let norm = norm1(a);
    if let Some((_, b)) = LOW_ORDERS.iter().find(|(theta, _)| norm <= *theta) {
        return pade_low(a, b);
    }
    // At most MAX_SQUARINGS: any finite norm needs fewer (log2 of f64::MAX is 1024), and an
    // infinite one must not loop ~2³¹ times.
    let s = if norm > THETA_13 { (norm / THETA_13).log2().ceil().min(MAX_SQUARINGS) as i32 } else { 0 };
    let scale = 0.5f64.powi(s);
    let a1 = Mat::from_fn(n, n, |i, j| a[(i, j)] * scale);
    let a2 = mul(a1.as_ref(), a1.as_ref());
    let a4 = mul(a2.as_ref(), a2.as_ref());
    let a6 = mul(a4.as_ref(), a2.as_ref());
    let id = |i: usize, j: usize| if i == j { 1.0 } else { 0.0 };
    // U = A [A6 (b13 A6 + b11 A4 + b9 A2) + b7 A6 + b5 A4 + b3 A2 + b1 I]
    let u_inner = Mat::from_fn(n, n, |i, j| a6[(i, j)] * B[13] + a4[(i, j)] * B[11] + a2[(i, j)] * B[9]);
    let mut u_sum = mul(a6.as_ref(), u_inner.as_ref());
    for i in 0..n {
        for j in 0..n {
            u_sum[(i, j)] += a6[(i, j)] * B[7] + a4[(i, j)] * B[5] + a2[(i, j)] * B[3] + c64::new(B[1] * id(i, j), 0.0);
        }
    }
    let u = mul(a1.as_ref(), u_sum.as_ref());
    // V = A6 (b12 A6 + b10 A4 + b8 A2) + b6 A6 + b4 A4 + b2 A2 + b0 I
    let v_inner = Mat::from_fn(n, n, |i, j| a6[(i, j)] * B[12] + a4[(i, j)] * B[10] + a2[(i, j)] * B[8]);
    let mut v = mul(a6.as_ref(), v_inner.as_ref());
    for i in 0..n {
        for j in 0..n {
            v[(i, j)] += a6[(i, j)] * B[6] + a4[(i, j)] * B[4] + a2[(i, j)] * B[2] + c64::new(B[0] * id(i, j), 0.0);
        }
    }
    // (V − U) X = V + U
    let p = Mat::from_fn(n, n, |i, j| v[(i, j)] + u[(i, j)]);
    let q = Mat::from_fn(n, n, |i, j| v[(i, j)] - u[(i, j)]);
    let mut x = lu_solve(q.as_ref(), p.as_ref());
    for _ in 0..s {
        x = mul(x.as_ref(), x.as_ref());
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    fn random(n: usize, seed: u64, scale: f64) -> Mat<c64> {
        let mut state = seed;
        let mut next = || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * scale
        };
        Mat::from_fn(n, n, |_, _| c64::new(next(), next()))
    }

    #[test]
    fn infinite_input_returns_at_once() {
        // The squaring count is capped: an infinite norm must not loop ~2³¹ times.
        let mut a = random(16, 9, 0.1);
        a[(3, 4)] = c64::new(f64::INFINITY, 0.0);
        let start = std::time::Instant::now();
        let e = expm(a.as_ref());
        assert!(start.elapsed().as_secs_f64() < 1.0);
        assert!(e.norm_max().is_nan() || !e.norm_max().is_finite());
        // Entries whose squares overflow still get a finite 1-norm.
        let b = Mat::from_fn(2, 2, |i, j| c64::new(if i == j { 1e160 } else { 0.0 }, 0.0));
        assert_eq!(norm1(b.as_ref()), 1e160);
    }

    #[test]
    fn agrees_with_nalgebra_reference() {
        // Scales chosen so that every Padé order (3, 5, 7, 9, 13 with scaling) is used.
        for (seed, scale) in [(5, 0.0005), (6, 0.005), (7, 0.03), (1, 0.1), (8, 0.2), (2, 1.0), (3, 10.0), (4, 50.0)] {
            let a = random(16, seed, scale);
            let err = crate::linalg::testing::exp_error_against_nalgebra(&a, &expm(a.as_ref()));
            assert!(err < 1e-11, "scale {scale}: relative error {err}");
        }
    }

    #[test]
    fn diagonal_closed_form() {
        let d = [c64::new(-1.0, 300.0), c64::new(0.5, -20.0), c64::new(0.0, 0.0)];
        let a = Mat::from_fn(3, 3, |i, j| if i == j { d[i] } else { c64::new(0.0, 0.0) });
        let e = expm(a.as_ref());
        for i in 0..3 {
            assert!((e[(i, i)] - d[i].exp()).norm() < 1e-12 * d[i].exp().norm().max(1.0));
        }
    }
}
