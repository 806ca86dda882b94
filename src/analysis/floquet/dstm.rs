//! The paper's discrete state transition matrix (Eq. 26–27), kept as the reference path:
//! N equal steps over one period T = 2π/φ, on each the mean of B(t),
//! C_k = B0 + β·c̄_k·B1 with c̄_k = (sin φt_k − sin φt_{k−1})/(φΔ), and
//! Ξ = ∏ exp(Δ·C_k) (later steps on the left). Second order in Δ.

use super::product::ScaledProduct;
use crate::analysis::reduction::PeriodicSystem;
use crate::linalg::expm;
use faer::{c64, Mat};

/// Monodromy by the DSTM with `steps` steps.
pub fn monodromy_dstm(sys: &PeriodicSystem, phi: f64, beta: f64, steps: usize) -> ScaledProduct {
    let n = sys.b0.nrows();
    let period = 2.0 * std::f64::consts::PI / phi;
    let h = period / steps as f64;
    let mut prod = ScaledProduct::identity(n);
    for k in 1..=steps {
        let (t0, t1) = ((k - 1) as f64 * h, k as f64 * h);
        let mean = ((phi * t1).sin() - (phi * t0).sin()) / (phi * h);
        let x = beta * mean;
        let c = Mat::from_fn(n, n, |i, j| (sys.b0[(i, j)] + sys.b1[(i, j)] * x) * h);
        prod.left_multiply(expm(c.as_ref()).as_ref());
    }
    prod
}

/// Monodromy by classical fourth-order Runge–Kutta on Φ′ = B(t)Φ: an independent path
/// (no matrix exponential) used to check the others.
pub fn monodromy_rk4(sys: &PeriodicSystem, phi: f64, beta: f64, steps: usize) -> ScaledProduct {
    let n = sys.b0.nrows();
    let period = 2.0 * std::f64::consts::PI / phi;
    let h = period / steps as f64;
    let b = |t: f64| -> Mat<c64> {
        let x = beta * (phi * t).cos();
        Mat::from_fn(n, n, |i, j| sys.b0[(i, j)] + sys.b1[(i, j)] * x)
    };
    // One RK4 step of the linear ODE is a matrix polynomial S; Φ ← S·Φ.
    let mut prod = ScaledProduct::identity(n);
    for k in 0..steps {
        let t = k as f64 * h;
        let (b1, b2, b3) = (b(t), b(t + h / 2.0), b(t + h));
        let id: Mat<c64> = Mat::identity(n, n);
        let k1 = b1.clone();
        let k2 = &b2 * (&id + &k1 * faer::Scale(c64::new(h / 2.0, 0.0)));
        let k3 = &b2 * (&id + &k2 * faer::Scale(c64::new(h / 2.0, 0.0)));
        let k4 = &b3 * (&id + &k3 * faer::Scale(c64::new(h, 0.0)));
        let step = &id
            + (&k1 + &k2 * faer::Scale(c64::new(2.0, 0.0)) + &k3 * faer::Scale(c64::new(2.0, 0.0)) + &k4)
                * faer::Scale(c64::new(h / 6.0, 0.0));
        prod.left_multiply(step.as_ref());
    }
    prod
}
