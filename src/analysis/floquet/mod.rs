//! Floquet stability of y′ = B(t)·y, B(t) = B0 + β·cos(φt)·B1 (Eq. 24–28).
//!
//! The monodromy Φ(T), T = 2π/φ, comes from one of two paths: the paper's DSTM
//! ([`dstm`], reference) or the fast CFM4 path ([`fast`]); both return a scaled product
//! e^{s}·Φ̂ so that strongly unstable points never overflow. Multipliers μ are the
//! eigenvalues of Φ(T); the point is unstable by the settings' threshold
//! ([`crate::analysis::criterion::Threshold`]: growth above the path's floor by default,
//! max|μ| above 1.0001 in the paper).
//!
//! β = 0 sanity check: at β = 0 the system is constant and its multipliers are exactly
//! exp(λ_k T), λ_k the eigenvalues of B0 (on the unit circle when undamped). Every
//! reported point is checked against that at its φ, with the path and steps that
//! computed it; a path that misses it by more than [`ZERO_LOAD_TOLERANCE`] is not as
//! accurate as it claims there, and its points are `inaccurate` with the deviation as
//! reason ([`PointIssue::ZeroLoad`]).

pub mod dstm;
pub mod fast;
mod point;
pub(crate) mod product;

pub use point::{FloquetPoint, PointIssue, PointStatus, PointSummary};
pub use product::{ScaledProduct, ScaledSplit};

use super::basis::BasisReport;
use super::reduction::{ModeSet, PeriodicSystem, ReducedModel, ReductionInfo};
use super::{AnalysisError, MonodromyMethod, Rotor, Settings};
use fast::{PhiTable, Symmetry};

/// Aliased orders kept clear of the step rate: with N ≥ ALIAS_MARGIN·2ω_max/φ +
/// ALIAS_ORDERS steps a combination of two whirls lies below (N − ALIAS_ORDERS)·φ, so the
/// aliased tongues nearest to it are of order above 4, as thin as the physical tongues the
/// criterion's search reaches at β ≤ 1.
pub const ALIAS_ORDERS: usize = 4;
/// Relative margin of 2ω_max/φ below the step rate: the whirls drift under the static and
/// parametric load, and the margin keeps them away from the aliased resonance.
pub const ALIAS_MARGIN: f64 = 1.1;

/// Largest deviation of the β = 0 multipliers from exp(λ_k T) (moduli, relative to the
/// largest) before the points of that φ are flagged `inaccurate`. Both paths meet it by
/// orders of magnitude where they are sound: at every φ = 100:14000:25 rad/s of the nine
/// paper problems the fast path deviates by ≤ 4.4e-13 (from tables built for β ≤ 1) and
/// the DSTM(4096) by ≤ 2.0e-12 (measured), ≤ 1.2e-10 with a 3·10⁶ rad/s basis mode.
/// 1e-8 is 1e-4 of the paper's instability margin (max|μ| − 1 = 1e-4), so a point that
/// passes has its verdict decided by the physics, not by the path's error floor.
pub const ZERO_LOAD_TOLERANCE: f64 = 1e-8;

/// The β = 0 reference of a system: the exact multiplier moduli are exp(Re λ_k·T).
#[derive(Debug, Clone)]
struct ZeroLoadReference {
    /// Re λ_k of B0's eigenvalues (1/s), descending; None if they could not be computed.
    rates: Option<Vec<f64>>,
}

impl ZeroLoadReference {
    /// `deviation` of the β = 0 point of some path at its φ from exp(λ_k T): the largest
    /// difference of the moduli, both sorted (sorting moves no modulus further than the
    /// pairing does, so this is a lower bound of the pairwise error), relative to the
    /// largest exact modulus; infinite if the point has no finite multipliers.
    fn deviation(rates: &[f64], point: &FloquetPoint) -> f64 {
        let s = &point.summary;
        if s.status == PointStatus::Failed || point.multipliers.len() != rates.len() || rates.is_empty() {
            return f64::INFINITY;
        }
        let period = 2.0 * std::f64::consts::PI / s.phi;
        let mut got: Vec<f64> =
            point.multipliers.iter().map(|m| m[0].hypot(m[1]).ln() + point.multiplier_log_scale).collect();
        if got.iter().any(|x| x.is_nan()) {
            return f64::INFINITY;
        }
        got.sort_by(|a, b| b.total_cmp(a));
        // Exact moduli relative to the largest, in logarithms: no overflow for any rate.
        let top = rates[0] * period;
        got.iter().zip(rates).map(|(g, r)| ((g - top).exp() - (r * period - top).exp()).abs()).fold(0.0, f64::max)
    }

    /// The issue of the points computed with the path whose β = 0 point is `zero`.
    fn issue(&self, zero: &FloquetPoint) -> Option<PointIssue> {
        match &self.rates {
            None => Some(PointIssue::NoZeroLoadReference),
            Some(rates) => {
                let deviation = ZeroLoadReference::deviation(rates, zero);
                (deviation.is_nan() || deviation > ZERO_LOAD_TOLERANCE).then_some(PointIssue::ZeroLoad { deviation })
            }
        }
    }
}

/// A rotor prepared for Floquet analysis at one speed: reduced model, B0, B1, X.
#[derive(Debug, Clone)]
pub struct FloquetSystem {
    /// The reduced model (Eq. 22–24) the monodromy is computed on.
    pub reduced: ReducedModel,
    /// B0, B1 at the speed.
    pub system: PeriodicSystem,
    /// The transpose symmetry used by the fast path.
    pub symmetry: Symmetry,
    /// Speed Ω (rad/s).
    pub speed: f64,
    /// Numerical settings in force (the reduced model's size fixed at its modes).
    pub settings: Settings,
    /// How its basis was chosen: fixed, or the first size of a schedule (unchecked); a
    /// search that sizes its basis by convergence reports its own.
    pub basis: BasisReport,
    /// The β = 0 check's reference.
    zero_load: ZeroLoadReference,
}

impl FloquetSystem {
    /// Reduce the rotor at `speed` (rad/s) to `settings.reduced_modes` modes, or, when
    /// they are sized by convergence, to the first size of the schedule for the default φ
    /// window ([`crate::analysis::basis::Schedule`], [`crate::analysis::DEFAULT_BAND_RANGE`]);
    /// the settings are checked first ([`Settings::validate`]).
    pub fn new(rotor: &Rotor, settings: &Settings, speed: f64) -> Result<FloquetSystem, AnalysisError> {
        FloquetSystem::for_window(rotor, settings, speed, crate::analysis::DEFAULT_BAND_RANGE.hi)
    }

    /// [`FloquetSystem::new`] for answers about a φ window whose top is `top` (rad/s): with
    /// the basis sized by convergence, the first size of its schedule for that window,
    /// reported as unchecked ([`crate::analysis::basis::Sizing::Unchecked`]).
    pub fn for_window(
        rotor: &Rotor,
        settings: &Settings,
        speed: f64,
        top: f64,
    ) -> Result<FloquetSystem, AnalysisError> {
        settings.validate()?;
        match settings.reduced_modes.fixed() {
            Some(m) => FloquetSystem::with_modes(rotor, settings, speed, m),
            None => {
                let m = crate::analysis::basis::Schedule::new(rotor, settings, speed, top)?.first();
                let mut fs = FloquetSystem::with_modes(rotor, settings, speed, m)?;
                fs.basis = BasisReport::unchecked(settings.basis, m);
                Ok(fs)
            }
        }
    }

    /// Reduce the rotor at `speed` (rad/s) to exactly `modes` modes of the settings' basis;
    /// the system's settings record that count.
    pub fn with_modes(
        rotor: &Rotor,
        settings: &Settings,
        speed: f64,
        modes: usize,
    ) -> Result<FloquetSystem, AnalysisError> {
        FloquetSystem::from_mode_set(&ModeSet::new(rotor, speed, settings.basis)?, settings, speed, modes)
    }

    /// [`FloquetSystem::with_modes`] from the basis modes `set` already solved (of the
    /// settings' basis kind, at `speed` in rad/s): a schedule of sizes solves them once.
    pub fn from_mode_set(
        set: &ModeSet,
        settings: &Settings,
        speed: f64,
        modes: usize,
    ) -> Result<FloquetSystem, AnalysisError> {
        let settings = settings.with_modes(modes);
        settings.validate()?;
        FloquetSystem::from_reduced(set.reduced(modes)?, &settings, speed)
    }

    /// The Floquet system of a reduced model at `speed` (rad/s) under `settings` (checked
    /// first; its `reduced_modes` should be fixed at the model's modes): B0, B1, the
    /// transpose symmetry and the β = 0 check's reference.
    pub fn from_reduced(
        reduced: ReducedModel,
        settings: &Settings,
        speed: f64,
    ) -> Result<FloquetSystem, AnalysisError> {
        settings.validate()?;
        let settings = settings.clone();
        let modes = settings.reduced_modes.fixed().unwrap_or(reduced.size());
        let system = reduced.periodic_system(speed);
        let symmetry = Symmetry::new(&system);
        let rates = eigenvalues_of(&system).ok().map(|ev| {
            let mut rates: Vec<f64> = ev.iter().map(|z| z.re).collect();
            rates.sort_by(|a, b| b.total_cmp(a));
            rates
        });
        let zero_load = ZeroLoadReference { rates: rates.filter(|r| r.iter().all(|x| x.is_finite())) };
        let basis = BasisReport::fixed(settings.basis, modes);
        Ok(FloquetSystem { reduced, system, symmetry, speed, settings, basis, zero_load })
    }

    /// The modes M of its reduced model (−): per plane on the general path, whose basis
    /// holds 2M real modes.
    pub fn modes(&self) -> usize {
        self.settings.reduced_modes.fixed().unwrap_or(self.reduced.size())
    }

    /// Eigenvalues λ of B0 (the reduced model at the static load), sorted by |Im λ|:
    /// the whirls whose sums (ω_i + ω_j)/k are where instability regions start.
    pub fn eigenvalues(&self) -> Result<Vec<faer::c64>, AnalysisError> {
        eigenvalues_of(&self.system)
    }

    /// Forward (Im λ > 0) and backward whirl frequencies of the reduced model (rad/s),
    /// each ascending.
    pub fn whirls(&self) -> Result<(Vec<f64>, Vec<f64>), AnalysisError> {
        self.system.whirls()
    }

    /// Whether the forward and the backward whirls of B0 are the same frequencies, so
    /// that a pair (i, j) and (j, i) are one combination: at rest, and always in real
    /// coordinates, where every whirl is a conjugate pair ±jω of the real B0 (a
    /// combination resonance ω_i + ω_j pairs +jω_i with −jω_j, a simple one 2ω_i).
    pub fn paired(&self) -> bool {
        self.speed == 0.0 || self.reduced.real
    }

    /// Reduction summary.
    pub fn info(&self) -> ReductionInfo {
        self.reduced.info()
    }

    /// The per-φ table of the fast path for loads up to `beta_max`.
    pub fn table(&self, phi: f64, beta_max: f64) -> PhiTable {
        PhiTable::new(&self.system, phi, beta_max, self.steps_for(phi), self.reduced.real)
    }

    /// CFM4 steps per period at φ: the configured minimum, or more so that each step
    /// spans at most `max_step_phase` of the lowest basis mode, and so that no
    /// combination of two basis whirls resonates with the step rate.
    ///
    /// The step rule sees the excitation cos φt only at N points per period, so the
    /// discrete system is also excited at (mN ± l)·φ: a combination ω_i + ω_j near
    /// (N − l)·φ gives a tongue of order-l strength that the continuous system does not
    /// have (seen at φ = 1125 rad/s on the open rotor with M = 8: the 17 443 rad/s whirl at
    /// 2ω₇ = 31φ with N = 32 steps gave max|μ| = 1.0012 at β = 0.1, where the DSTM gives
    /// 1). So N − [`ALIAS_ORDERS`] must exceed 2ω_max/φ with [`ALIAS_MARGIN`] to spare.
    pub fn steps_for(&self, phi: f64) -> usize {
        let needed = self.steps_needed(phi);
        self.settings.steps_per_period.max(if needed.is_finite() { needed.min(1e6) as usize } else { 0 })
    }

    /// The steps per period the rule of [`FloquetSystem::steps_for`] asks for at φ
    /// (rad/s), before the settings' minimum and the cap of 10⁶; infinite when φ resolves
    /// nothing (0, NaN). What a run's count before it starts takes ([`crate::analysis::cost`]).
    pub fn steps_needed(&self, phi: f64) -> f64 {
        let freqs = &self.reduced.frequencies;
        let w_min = freqs.iter().copied().fold(f64::INFINITY, f64::min);
        let w_max = freqs.iter().copied().fold(0.0, f64::max);
        let period = 2.0 * std::f64::consts::PI / phi;
        let by_phase = (period * w_min / self.settings.max_step_phase).ceil();
        let by_alias = (ALIAS_MARGIN * 2.0 * w_max / phi).ceil() + ALIAS_ORDERS as f64;
        let needed = by_phase.max(by_alias);
        if needed.is_nan() {
            f64::INFINITY
        } else {
            needed
        }
    }

    /// The β = 0 check alone at φ (one fast-path table and its unloaded monodromy):
    /// `Some` when the unloaded monodromy misses exp(λT) or has no reference. The region
    /// search runs it at the ends of its range before any work.
    pub fn zero_load_issue(&self, phi: f64) -> Option<PointIssue> {
        let table = self.table(phi, 0.0);
        self.zero_load.issue(&self.point_fast(&table, 0.0))
    }

    /// One point with the configured method, with the β = 0 check.
    pub fn point(&self, phi: f64, beta: f64) -> FloquetPoint {
        match self.settings.method {
            MonodromyMethod::Fast => {
                let table = self.table(phi, beta);
                let mut point = self.point_fast(&table, beta);
                let issue = if beta == 0.0 {
                    self.zero_load.issue(&point)
                } else {
                    self.zero_load.issue(&self.point_fast(&table, 0.0))
                };
                point.summary.flag(issue);
                point
            }
            MonodromyMethod::Dstm => self.point_dstm(phi, beta, self.settings.reference_steps),
        }
    }

    /// One point from a prepared per-φ table (β ≤ the table's β_max). Flagged when the
    /// table is (see [`PhiTable::issue`]), but without the β = 0 check, which costs about
    /// one more point per table: searches that need only verdicts (regions) call this;
    /// [`FloquetSystem::point`] and [`FloquetSystem::row`] add the check.
    pub fn point_fast(&self, table: &PhiTable, beta: f64) -> FloquetPoint {
        self.point_of(table, &table.monodromy(&self.symmetry, beta), beta)
    }

    /// The point of a monodromy computed from `table` at β (for callers that also need
    /// the monodromy itself); as [`FloquetSystem::point_fast`].
    pub fn point_of(&self, table: &PhiTable, mono: &ScaledProduct, beta: f64) -> FloquetPoint {
        FloquetPoint::from_monodromy_with(table.phi, beta, mono, self.settings.threshold(), table.issue())
    }

    /// One point by the reference DSTM with `steps` steps, with the β = 0 check (the
    /// unloaded monodromy of the same steps, [`dstm::monodromy_dstm_unloaded`]: one
    /// exponential and log₂N products, against the N exponentials of the point).
    pub fn point_dstm(&self, phi: f64, beta: f64, steps: usize) -> FloquetPoint {
        let mut point = self.point_dstm_unchecked(phi, beta, steps);
        point.summary.flag(self.dstm_zero_load_issue(phi, steps));
        point
    }

    fn point_dstm_unchecked(&self, phi: f64, beta: f64, steps: usize) -> FloquetPoint {
        let mono = dstm::monodromy_dstm(&self.system, phi, beta, steps);
        FloquetPoint::from_monodromy_with(phi, beta, &mono, self.settings.threshold(), None)
    }

    fn dstm_zero_load_issue(&self, phi: f64, steps: usize) -> Option<PointIssue> {
        let mono = dstm::monodromy_dstm_unloaded(&self.system, phi, steps);
        let zero = FloquetPoint::from_monodromy_with(phi, 0.0, &mono, self.settings.threshold(), None);
        self.zero_load.issue(&zero)
    }

    /// A row of points at one φ for several β, sharing the per-φ work, with the β = 0
    /// check (free when the row has β = 0: its point is the check).
    pub fn row(&self, phi: f64, betas: &[f64]) -> Vec<FloquetPoint> {
        let (mut points, issue) = match self.settings.method {
            MonodromyMethod::Fast => {
                let beta_max = betas.iter().fold(0.0f64, |m, b| m.max(b.abs()));
                let table = self.table(phi, beta_max);
                let points: Vec<FloquetPoint> = betas.iter().map(|&b| self.point_fast(&table, b)).collect();
                let issue = match betas.iter().position(|&b| b == 0.0) {
                    Some(i) => self.zero_load.issue(&points[i]),
                    None => self.zero_load.issue(&self.point_fast(&table, 0.0)),
                };
                (points, issue)
            }
            MonodromyMethod::Dstm => {
                let steps = self.settings.reference_steps;
                let points = betas.iter().map(|&b| self.point_dstm_unchecked(phi, b, steps)).collect();
                (points, self.dstm_zero_load_issue(phi, steps))
            }
        };
        for p in &mut points {
            p.summary.flag(issue);
        }
        points
    }
}

/// Balanced eigenvalues of B0, sorted by |Im λ| ([`PeriodicSystem::eigenvalues`]).
fn eigenvalues_of(system: &PeriodicSystem) -> Result<Vec<faer::c64>, AnalysisError> {
    system.eigenvalues()
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::{c64, Mat};

    /// A β = 0 point whose monodromy is diag(μ) at φ = 1 rad/s.
    fn point(mu: &[c64]) -> FloquetPoint {
        let n = mu.len();
        let m = Mat::from_fn(n, n, |i, j| if i == j { mu[i] } else { c64::new(0.0, 0.0) });
        FloquetPoint::from_monodromy_with(
            1.0,
            0.0,
            &ScaledProduct::from_matrix(m, 0.0),
            crate::analysis::criterion::Threshold::Multiplier { tolerance: 1.0001 },
            None,
        )
    }

    #[test]
    fn zero_load_check_compares_sorted_moduli_with_exp_lambda_t() {
        let t = 2.0 * std::f64::consts::PI;
        // Undamped pair, a lightly damped one and one damped to e^{-60}: exact multipliers.
        let lambdas = [c64::new(0.0, 3.0), c64::new(0.0, -2.0), c64::new(-0.01, 5.0), c64::new(-60.0 / t, 1.0)];
        let mut rates: Vec<f64> = lambdas.iter().map(|l| l.re).collect();
        rates.sort_by(|a, b| b.total_cmp(a));
        let reference = ZeroLoadReference { rates: Some(rates) };
        let exact: Vec<c64> = lambdas.iter().map(|l| (l * t).exp()).collect();
        assert_eq!(reference.issue(&point(&exact)), None);
        // One modulus 2e-8 off: flagged, with that deviation (order of the list irrelevant).
        let mut off = exact.clone();
        off.reverse();
        off[2] *= 1.0 + 2e-8;
        match reference.issue(&point(&off)) {
            Some(PointIssue::ZeroLoad { deviation }) => assert!((deviation - 2e-8).abs() < 1e-12, "{deviation}"),
            other => panic!("{other:?}"),
        }
        // 5e-9 off: inside the tolerance.
        let mut close = exact.clone();
        close[0] *= 1.0 - 5e-9;
        assert_eq!(reference.issue(&point(&close)), None);
        // A failed β = 0 point, or no reference: flagged too.
        let nan = vec![c64::new(f64::NAN, 0.0); 4];
        assert!(
            matches!(reference.issue(&point(&nan)), Some(PointIssue::ZeroLoad { deviation }) if deviation.is_infinite())
        );
        assert_eq!(ZeroLoadReference { rates: None }.issue(&point(&exact)), Some(PointIssue::NoZeroLoadReference));
    }

    #[test]
    fn a_flag_keeps_the_first_reason_and_never_touches_failed_points() {
        let mut p = point(&[c64::new(1.0, 0.0)]).summary;
        p.flag(None);
        assert_eq!((p.status, p.reason), (PointStatus::Ok, None));
        p.flag(Some(PointIssue::ZeroLoad { deviation: 1.0 }));
        p.flag(Some(PointIssue::Interpolant { terms: 64 }));
        assert_eq!((p.status, p.reason), (PointStatus::Inaccurate, Some(PointIssue::ZeroLoad { deviation: 1.0 })));
        // A NaN monodromy: the eigenvalue iteration refuses it (or its values are not
        // finite); either way a failed point with its reason, which a flag leaves alone.
        let mut f = point(&[c64::new(f64::NAN, 0.0)]).summary;
        let reason = f.reason;
        assert_eq!(f.status, PointStatus::Failed);
        assert!(matches!(reason, Some(PointIssue::Eigenvalues | PointIssue::NotFinite)), "{reason:?}");
        f.flag(Some(PointIssue::ZeroLoad { deviation: 1.0 }));
        assert_eq!((f.status, f.reason), (PointStatus::Failed, reason));
    }
}
