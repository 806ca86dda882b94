//! Evaluating a bearing coefficient tabulated against frequency at one speed, as ROSS
//! does (`BearingElement._process_coefficient`, `bearing_seal_element.py`).
//!
//! ROSS interpolates 2 points linearly and 3 quadratically (scipy's `interp1d`, kind 1
//! and 2), so both are reproduced exactly here. From 4 points on it uses scipy's
//! `UnivariateSpline` (cubic, default smoothing s = number of points); this module uses
//! the cubic interpolating spline with not-a-knot ends, which is what FITPACK returns at
//! s = 0. The two agree exactly at the tabulated frequencies and wherever the table is a
//! cubic polynomial of the frequency (a linear table included). Elsewhere they differ:
//! ROSS's smoothing lets its spline miss the points by residuals with Σr² ≤ s (about one
//! unit of the coefficient each, 1 N/m on a table of 10⁶ N/m) and may give it fewer
//! knots, so between the points of a coarse, strongly curved table the two can part by
//! more (docs/ross-format.md).
//! Speeds outside the table are refused by the caller: ROSS extrapolates its spline.

use nalgebra::{DMatrix, DVector};

/// The value at `x` of the table (`xs` strictly increasing, `ys` of the same length ≥ 1,
/// `xs[0] ≤ x ≤ xs[last]`). `None` only if the spline's linear system is singular, which
/// strictly increasing `xs` exclude.
pub fn evaluate(xs: &[f64], ys: &[f64], x: f64) -> Option<f64> {
    if let Some(i) = xs.iter().position(|&xi| xi == x) {
        return Some(ys[i]);
    }
    match xs.len() {
        0 => None,
        1 => Some(ys[0]),
        2 | 3 => Some(lagrange(xs, ys, x)),
        _ => not_a_knot(xs, ys, x),
    }
}

/// The polynomial through all points (degree len − 1), at `x`.
fn lagrange(xs: &[f64], ys: &[f64], x: f64) -> f64 {
    (0..xs.len())
        .map(|i| {
            let w: f64 = (0..xs.len()).filter(|&j| j != i).map(|j| (x - xs[j]) / (xs[i] - xs[j])).product();
            w * ys[i]
        })
        .sum()
}

/// The not-a-knot cubic interpolating spline (≥ 4 points), at `x`: solve for the second
/// derivatives m_i, with continuity of the first derivative at interior points and of
/// the third derivative at the second and the second-to-last points.
fn not_a_knot(xs: &[f64], ys: &[f64], x: f64) -> Option<f64> {
    let n = xs.len();
    let h: Vec<f64> = xs.windows(2).map(|w| w[1] - w[0]).collect();
    let slope: Vec<f64> = (0..n - 1).map(|i| (ys[i + 1] - ys[i]) / h[i]).collect();
    let mut a = DMatrix::<f64>::zeros(n, n);
    let mut b = DVector::<f64>::zeros(n);
    // Third derivative continuous at x_1: (m1 − m0)/h0 = (m2 − m1)/h1.
    a[(0, 0)] = h[1];
    a[(0, 1)] = -(h[0] + h[1]);
    a[(0, 2)] = h[0];
    for i in 1..n - 1 {
        a[(i, i - 1)] = h[i - 1];
        a[(i, i)] = 2.0 * (h[i - 1] + h[i]);
        a[(i, i + 1)] = h[i];
        b[i] = 6.0 * (slope[i] - slope[i - 1]);
    }
    // And at x_{n−2}.
    a[(n - 1, n - 3)] = h[n - 2];
    a[(n - 1, n - 2)] = -(h[n - 3] + h[n - 2]);
    a[(n - 1, n - 1)] = h[n - 3];
    let m = a.lu().solve(&b)?;
    let i = xs.windows(2).position(|w| x <= w[1]).unwrap_or(n - 2);
    let (t0, t1) = (x - xs[i], xs[i + 1] - x);
    let hi = h[i];
    Some(
        m[i] * t1.powi(3) / (6.0 * hi)
            + m[i + 1] * t0.powi(3) / (6.0 * hi)
            + (ys[i] / hi - m[i] * hi / 6.0) * t1
            + (ys[i + 1] / hi - m[i + 1] * hi / 6.0) * t0,
    )
}

#[cfg(test)]
mod tests {
    use super::evaluate;

    #[test]
    fn tabulated_points_are_returned_exactly() {
        let xs = [0.0, 500.0, 1000.0, 1500.0, 2100.0];
        let ys = [1.0e6, 1.3e6, 1.1e6, 1.7e6, 0.9e6];
        for (x, y) in xs.iter().zip(ys) {
            assert_eq!(evaluate(&xs, &ys, *x), Some(y));
        }
    }

    #[test]
    fn cubic_tables_are_reproduced() {
        // Any cubic polynomial is its own not-a-knot spline.
        let p = |x: f64| 3.0e5 + 120.0 * x - 0.05 * x * x + 2.0e-5 * x * x * x;
        let xs = [0.0, 300.0, 700.0, 1000.0, 1600.0, 2000.0];
        let ys: Vec<f64> = xs.iter().map(|&x| p(x)).collect();
        for x in [10.0, 450.0, 999.0, 1800.0, 1999.0] {
            let v = evaluate(&xs, &ys, x).unwrap();
            assert!((v - p(x)).abs() < 1e-9 * p(x).abs(), "{x}: {v} vs {}", p(x));
        }
    }

    #[test]
    fn two_and_three_points_are_linear_and_quadratic() {
        assert_eq!(evaluate(&[0.0, 100.0], &[1.0, 3.0], 25.0), Some(1.5));
        let q = |x: f64| 2.0 - x + 0.5 * x * x;
        let v = evaluate(&[0.0, 1.0, 3.0], &[q(0.0), q(1.0), q(3.0)], 2.0).unwrap();
        assert!((v - q(2.0)).abs() < 1e-12);
    }
}
