//! Time response of the reduced model with the unbalance force (Eq. 29):
//! ẏ = B(t)·y + R(t), R = [Q̃(t); 0] with Q̃(t) = Ω²·Φᵀ·(m e e^{jγ})·e^{jΩt} (M̃ = I).
//! Classical RK4 with a step resolving the fastest mode, from rest.

use super::floquet::FloquetSystem;
use super::AnalysisError;
use faer::c64;
use serde::Serialize;

/// RK4 steps per period of the fastest basis mode: h·ω_max ≤ 2π/64 ≈ 0.1 keeps the
/// RK4 phase error per step ~1e-7.
const STEPS_PER_FASTEST_PERIOD: f64 = 64.0;
/// At most this many samples are stored, whatever the step count.
const MAX_SAMPLES: usize = 4000;

/// A sampled response.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ResponseResult {
    /// φ (rad/s).
    pub phi: f64,
    /// β.
    pub beta: f64,
    /// Periods of the load simulated.
    pub periods: usize,
    /// Times (s).
    pub time: Vec<f64>,
    /// First modal coordinate q₁: real part = vertical, imaginary = horizontal (Eq. 29).
    pub q1: Vec<[f64; 2]>,
    /// Largest |q| over the first and over the last period (growth indicator).
    pub first_period_peak: f64,
    /// See `first_period_peak`.
    pub last_period_peak: f64,
    /// RK4 step (s).
    pub step: f64,
    /// Time (s) of the first step whose state is not finite (the response outgrew f64):
    /// the integration stopped there and the samples end before it. Absent when the
    /// whole interval was integrated.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stopped_at: Option<f64>,
}

impl ResponseResult {
    /// last/first period peak ratio: ≫ 1 for a point inside an instability region.
    pub fn growth_ratio(&self) -> f64 {
        self.last_period_peak / self.first_period_peak.max(f64::MIN_POSITIVE)
    }

    /// The response, or the analysis error of one whose state stopped being finite.
    pub fn finite(self) -> Result<ResponseResult, AnalysisError> {
        match self.stopped_at {
            None => Ok(self),
            Some(time) => {
                Err(AnalysisError::ResponseNotFinite { phi: self.phi, beta: self.beta, time, periods: self.periods })
            }
        }
    }
}

/// Integrate `periods` load periods at (φ, β) from rest, stopping at the first step whose
/// state is not finite (`stopped_at`; [`ResponseResult::finite`] makes that an error).
pub fn response(fs: &FloquetSystem, phi: f64, beta: f64, periods: usize) -> ResponseResult {
    let sys = &fs.system;
    let n = sys.b0.nrows();
    let m = n / 2;
    let omega_max = fs.reduced.frequencies.iter().fold(phi, |a, b| a.max(*b)).max(fs.speed);
    let period = 2.0 * std::f64::consts::PI / phi;
    let steps_per_period =
        ((period * omega_max / (2.0 * std::f64::consts::PI) * STEPS_PER_FASTEST_PERIOD).ceil() as usize).max(64);
    let h = period / steps_per_period as f64;
    let total = steps_per_period * periods;
    let stride = total.div_ceil(MAX_SAMPLES).max(1);
    let force: Vec<c64> = fs.reduced.unbalance.iter().map(|u| u * (fs.speed * fs.speed)).collect();
    let rhs = |t: f64, y: &[c64], out: &mut [c64]| {
        let load = beta * (phi * t).cos();
        let spin = c64::from_polar(1.0, fs.speed * t);
        for (i, o) in out.iter_mut().enumerate() {
            let mut acc = c64::new(0.0, 0.0);
            for (j, yj) in y.iter().enumerate() {
                acc += (sys.b0[(i, j)] + sys.b1[(i, j)] * load) * yj;
            }
            if i < m {
                acc += force[i] * spin;
            }
            *o = acc;
        }
    };
    let mut y = vec![c64::new(0.0, 0.0); n];
    let (mut k1, mut k2, mut k3, mut k4, mut tmp) = (y.clone(), y.clone(), y.clone(), y.clone(), y.clone());
    let mut time = vec![0.0];
    let mut q1 = vec![[0.0, 0.0]];
    let (mut first, mut last) = (0.0f64, 0.0f64);
    let mut stopped_at = None;
    for s in 0..total {
        let t = s as f64 * h;
        rhs(t, &y, &mut k1);
        for i in 0..n {
            tmp[i] = y[i] + k1[i] * (h / 2.0);
        }
        rhs(t + h / 2.0, &tmp, &mut k2);
        for i in 0..n {
            tmp[i] = y[i] + k2[i] * (h / 2.0);
        }
        rhs(t + h / 2.0, &tmp, &mut k3);
        for i in 0..n {
            tmp[i] = y[i] + k3[i] * h;
        }
        rhs(t + h, &tmp, &mut k4);
        for i in 0..n {
            y[i] += (k1[i] + (k2[i] + k3[i]) * 2.0 + k4[i]) * (h / 6.0);
        }
        let amp = y[m..].iter().map(|z| z.norm_sqr()).sum::<f64>().sqrt();
        if !y.iter().all(|z| z.re.is_finite() && z.im.is_finite()) || !amp.is_finite() {
            stopped_at = Some(t + h);
            break;
        }
        if s < steps_per_period {
            first = first.max(amp);
        }
        if s >= total - steps_per_period {
            last = last.max(amp);
        }
        if (s + 1) % stride == 0 {
            time.push(t + h);
            q1.push([y[m].re, y[m].im]);
        }
    }
    ResponseResult {
        phi,
        beta,
        periods,
        time,
        q1,
        first_period_peak: first,
        last_period_peak: last,
        step: h,
        stopped_at,
    }
}
