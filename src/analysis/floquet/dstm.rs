//! The paper's discrete state transition matrix (Eq. 26–27), kept as the reference path:
//! N equal steps over one period T = 2π/φ, on each the mean of B(t),
//! C_k = B0 + β·c̄_k·B1 with c̄_k = (sin φt_k − sin φt_{k−1})/(φΔ), and
//! Ξ = ∏ exp(Δ·C_k) (later steps on the left). Second order in Δ.
//!
//! Each exp(Δ·C_k) is taken in the frequency-scaled coordinates [q̇; w·q]
//! ([`PeriodicSystem::frequency_scaling`]) and scaled back. In the plain coordinates
//! ‖Δ·B0‖ ~ Δ·ω²_max, and the Padé exponential's squarings leave each step an error
//! ~ε·Δ·ω²_max that is the same in every step, so over the period it adds up to
//! ~ε·T·ω²_max whatever N: with a 3·10⁶ rad/s basis mode (M = 120 on the Fig. 11 rotor)
//! an undamped system gave max|μ(β = 0)| = 1 + 5·10⁻⁶ at 256, 4096 and 16 384 steps.
//! Scaled, the steps are unitary in the energy norm to ~1e-15 and the same system gives
//! 1 + 3·10⁻¹² (docs/decisions.md).

use super::product::ScaledProduct;
use crate::analysis::reduction::PeriodicSystem;
use crate::linalg::expm;
use crate::linalg::seq::product;
use faer::{c64, Mat};

/// exp(h·(B0 + x·B1)), computed in the coordinates scaled by `scale` and scaled back.
fn step_exponential(sys: &PeriodicSystem, scale: &[f64], x: f64, h: f64) -> Mat<c64> {
    let n = sys.b0.nrows();
    let c = Mat::from_fn(n, n, |i, j| (sys.b0[(i, j)] + sys.b1[(i, j)] * x) * (h * scale[i] / scale[j]));
    let e = expm(c.as_ref());
    Mat::from_fn(n, n, |i, j| e[(i, j)] * (scale[j] / scale[i]))
}

/// Monodromy by the DSTM with `steps` steps.
pub fn monodromy_dstm(sys: &PeriodicSystem, phi: f64, beta: f64, steps: usize) -> ScaledProduct {
    let n = sys.b0.nrows();
    let period = 2.0 * std::f64::consts::PI / phi;
    let h = period / steps as f64;
    let scale = sys.frequency_scaling();
    let mut prod = ScaledProduct::identity(n);
    for k in 1..=steps {
        let (t0, t1) = ((k - 1) as f64 * h, k as f64 * h);
        let mean = ((phi * t1).sin() - (phi * t0).sin()) / (phi * h);
        let x = beta * mean;
        prod.left_multiply(step_exponential(sys, &scale, x, h).as_ref());
    }
    prod
}

/// The DSTM monodromy at β = 0 with `steps` steps: every step is the same exp(Δ·B0), so
/// the product is its N-th power, formed by repeated squaring (log₂N products instead of
/// N exponentials). It carries the same per-step error as [`monodromy_dstm`] at β = 0.
pub fn monodromy_dstm_unloaded(sys: &PeriodicSystem, phi: f64, steps: usize) -> ScaledProduct {
    let h = 2.0 * std::f64::consts::PI / phi / steps as f64;
    let step = step_exponential(sys, &sys.frequency_scaling(), 0.0, h);
    ScaledProduct::power(step.as_ref(), steps)
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
        let k2 = product(b2.as_ref(), (&id + &k1 * faer::Scale(c64::new(h / 2.0, 0.0))).as_ref());
        let k3 = product(b2.as_ref(), (&id + &k2 * faer::Scale(c64::new(h / 2.0, 0.0))).as_ref());
        let k4 = product(b3.as_ref(), (&id + &k3 * faer::Scale(c64::new(h, 0.0))).as_ref());
        let step = &id
            + (&k1 + &k2 * faer::Scale(c64::new(2.0, 0.0)) + &k3 * faer::Scale(c64::new(2.0, 0.0)) + &k4)
                * faer::Scale(c64::new(h / 6.0, 0.0));
        prod.left_multiply(step.as_ref());
    }
    prod
}
