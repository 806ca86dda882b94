//! Time response of the reduced model with the unbalance force (Eq. 29):
//! ẏ = B(t)·y + R(t), R = [Q̃(t); 0] with Q̃(t) = Ω²·Φᵀ·(m e e^{jγ})·e^{jΩt} (M̃ = I).
//! Classical RK4 with a step resolving the fastest mode, from rest.

use super::floquet::FloquetSystem;
use super::AnalysisError;
use crate::progress::{Progress, Silent};
use faer::c64;
use serde::{Deserialize, Serialize};

/// RK4 steps per period of the fastest basis mode: h·ω_max ≤ 2π/64 ≈ 0.1 keeps the
/// RK4 phase error per step ~1e-7.
const STEPS_PER_FASTEST_PERIOD: f64 = 64.0;
/// Largest |h·λ| over B0's eigenvalues λ: classical RK4 is stable (|R(hλ)| ≤ 0.873) on
/// the whole left half-disc |hλ| ≤ 2.5, and no longer at 2.7. The phase rule above keeps
/// every oscillatory λ far inside; this bounds the decay rates of stiff damping (a branch
/// with R = 1e9 Ω has Re λ ≈ −R/L ≈ −1e9 1/s), which RK4 with the phase step turned into
/// an overflow within 2e-4 s instead of a decaying response.
const RK4_STABLE_STEP: f64 = 2.5;
/// At most this many samples are stored, whatever the step count.
const MAX_SAMPLES: usize = 4000;
/// Progress steps per load period at most: a long period (a slow load, φ = 0.01 rad/s is
/// a period of 628 s) still reports an advancing count, never "0/1" for minutes.
const PROGRESS_PER_PERIOD: usize = 100;
/// Questions whether to stop ([`Progress::cancelled`]) per load period at most: often
/// enough that a long period stops within a tenth of it, rarely enough that asking costs
/// nothing beside the steps.
const STOP_CHECKS_PER_PERIOD: usize = 10;

/// The progress steps [`checked_response`] reports for `periods` periods at φ: each
/// period's RK4 steps in up to `PROGRESS_PER_PERIOD` (100) equal parts.
pub fn response_steps(fs: &FloquetSystem, phi: f64, periods: usize) -> u64 {
    (rk4_steps_per_period(fs, phi).min(PROGRESS_PER_PERIOD) as u64).saturating_mul(periods as u64)
}

/// A sampled response.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ResponseResult {
    /// φ (rad/s).
    pub phi: f64,
    /// Dynamic load coefficient β (−).
    pub beta: f64,
    /// Periods of the load simulated.
    pub periods: usize,
    /// Times (s).
    pub time: Vec<f64>,
    /// First modal coordinate q₁: real part = vertical, imaginary = horizontal (Eq. 29).
    pub q1: Vec<[f64; 2]>,
    /// Largest ‖q‖, the Euclidean norm of the mass-normalised modal coordinates, over the
    /// first load period (kg^½·m).
    pub first_period_peak: f64,
    /// Largest ‖q‖ over the last load period (kg^½·m; 0 if the integration stopped before
    /// it); `growth_ratio` divides it by `first_period_peak`.
    pub last_period_peak: f64,
    /// RK4 step (s).
    pub step: f64,
    /// Time (s) of the first step whose state is not finite (the response outgrew f64):
    /// the integration stopped there and the samples end before it. Absent when the
    /// whole interval was integrated.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stopped_at: Option<f64>,
    /// Every modal coordinate q (M values) at each sample time, for the physical
    /// displacements ([`ResponseResult::displacement`]); not serialised.
    #[serde(skip)]
    pub modal: Vec<Vec<c64>>,
}

impl ResponseResult {
    /// The physical displacement u = Φ·q (m) of the global DOF `dof` at each sample time,
    /// as [v, w] = [Re u, Im u] (vertical, horizontal), from the reduced basis Φ
    /// (`basis`, n × M, of the same model); zeros for a DOF beyond the basis.
    pub fn displacement(&self, basis: faer::MatRef<'_, f64>, dof: usize) -> Vec<[f64; 2]> {
        self.modal
            .iter()
            .map(|q| {
                if dof >= basis.nrows() {
                    return [0.0, 0.0];
                }
                let u: c64 = q.iter().enumerate().map(|(j, qj)| qj * basis[(dof, j)]).sum();
                [u.re, u.im]
            })
            .collect()
    }

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

/// Most times the steps of the phase rule that RK4's stability may ask for: beyond it
/// the response is stiff (a decay rate 100× the fastest oscillation: nearly all steps
/// would be spent on a component that has long vanished) and is refused
/// ([`AnalysisError::StiffResponse`]) rather than integrated for hours: R = 1e9 Ω on
/// the Fig. 13 rotor needs 6 600× (4.7 s a period here), η = 1e12 N·s/m on Fig. 8
/// 2.6·10⁶×.
pub const STIFFNESS_LIMIT: f64 = 100.0;

/// RK4 steps per load period at φ (rad/s) of [`response`]: 64 per period of the fastest
/// of the basis frequencies, φ and Ω (at least 64), and more where B0 has a decay rate
/// beyond RK4's stability region at that step (`RK4_STABLE_STEP`). The work of a
/// response is this times the periods, each step four products of the 2M-state.
pub fn rk4_steps_per_period(fs: &FloquetSystem, phi: f64) -> usize {
    let (by_phase, by_stability, _) = step_rules(fs, phi);
    // `as` saturates: a non-finite or huge count becomes usize::MAX, never wraps.
    (by_phase.max(by_stability) as usize).max(64)
}

/// RK4 steps per period at φ by the phase rule alone (what the response is counted at
/// when it is stiff: it is refused before any step).
pub(crate) fn phase_steps(fs: &FloquetSystem, phi: f64) -> f64 {
    step_rules(fs, phi).0
}

/// Steps per period by the phase rule, by RK4's stability, and B0's spectral radius.
fn step_rules(fs: &FloquetSystem, phi: f64) -> (f64, f64, f64) {
    let omega_max = fs.reduced.frequencies.iter().fold(phi, |a, b| a.max(*b)).max(fs.speed);
    let period = 2.0 * std::f64::consts::PI / phi;
    let by_phase = (period * omega_max / (2.0 * std::f64::consts::PI) * STEPS_PER_FASTEST_PERIOD).ceil();
    // The spectral radius of B0 (0 if its eigenvalues fail: the phase rule alone).
    let radius = fs.eigenvalues().map(|ev| ev.iter().map(|z| z.norm()).fold(0.0, f64::max)).unwrap_or(0.0);
    (by_phase, (period * radius / RK4_STABLE_STEP).ceil(), radius)
}

/// [`response`] for callers that report it: refused before work when it is stiff
/// (beyond [`STIFFNESS_LIMIT`]), and an error when its state stops being finite;
/// `progress` advances [`response_steps`] steps over the integration.
pub fn checked_response(
    fs: &FloquetSystem,
    phi: f64,
    beta: f64,
    periods: usize,
    progress: &dyn Progress,
) -> Result<ResponseResult, AnalysisError> {
    let (by_phase, by_stability, radius) = step_rules(fs, phi);
    let by_phase = by_phase.max(64.0);
    if by_stability.is_nan() || by_stability > STIFFNESS_LIMIT * by_phase {
        return Err(AnalysisError::StiffResponse { phi, rate: radius, steps: by_stability, accuracy_steps: by_phase });
    }
    response_reporting(fs, phi, beta, periods, progress).finite()
}

/// Integrate `periods` load periods at (φ, β) from rest, stopping at the first step whose
/// state is not finite (`stopped_at`; [`ResponseResult::finite`] makes that an error).
pub fn response(fs: &FloquetSystem, phi: f64, beta: f64, periods: usize) -> ResponseResult {
    response_reporting(fs, phi, beta, periods, &Silent)
}

/// [`response`], advancing `progress` by [`response_steps`] steps over the integration
/// (up to `PROGRESS_PER_PERIOD` (100) per load period). Once
/// [`Progress::cancelled`] is true (asked up to ten times a period) the integration ends
/// early: the result is then incomplete, for the caller that asked to drop.
pub fn response_reporting(
    fs: &FloquetSystem,
    phi: f64,
    beta: f64,
    periods: usize,
    progress: &dyn Progress,
) -> ResponseResult {
    let sys = &fs.system;
    let n = sys.b0.nrows();
    let m = n / 2;
    let period = 2.0 * std::f64::consts::PI / phi;
    let steps_per_period = rk4_steps_per_period(fs, phi);
    let h = period / steps_per_period as f64;
    let total = steps_per_period.saturating_mul(periods);
    let stride = total.div_ceil(MAX_SAMPLES).max(1);
    let parts = steps_per_period.min(PROGRESS_PER_PERIOD);
    // Asked whether to stop at most `STOP_CHECKS_PER_PERIOD` times a period: a period may
    // be 10⁸ steps (a low φ), and a step at M = 4 a fraction of a microsecond.
    let check_every = (steps_per_period / STOP_CHECKS_PER_PERIOD).max(1);
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
                // Real coordinates: the force is the real part of Ω²·q·e^{jΩt} in each
                // plane, and the state stays real.
                acc += if fs.reduced.real { c64::new((force[i] * spin).re, 0.0) } else { force[i] * spin };
            }
            *o = acc;
        }
    };
    let mut y = vec![c64::new(0.0, 0.0); n];
    let (mut k1, mut k2, mut k3, mut k4, mut tmp) = (y.clone(), y.clone(), y.clone(), y.clone(), y.clone());
    let mut time = vec![0.0];
    let mut q1 = vec![[0.0, 0.0]];
    let mut modal = vec![vec![c64::new(0.0, 0.0); m]];
    let (mut first, mut last) = (0.0f64, 0.0f64);
    let mut stopped_at = None;
    for s in 0..total {
        if s % check_every == 0 && progress.cancelled() {
            break;
        }
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
            modal.push(y[m..].to_vec());
        }
        // The period's progress parts: part j ends at step ⌈j·steps/parts⌉ of the period.
        let within = s % steps_per_period.max(1) + 1;
        if within * parts / steps_per_period.max(1) > (within - 1) * parts / steps_per_period.max(1) {
            progress.advance(1);
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
        modal,
    }
}
