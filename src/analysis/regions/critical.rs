//! The critical load curve β_c(φ): the smallest β in [0, β_max] with max|μ| above the
//! instability tolerance, by bracketing from below and bisection.

use crate::analysis::floquet::fast::PhiTable;
use crate::analysis::floquet::FloquetSystem;
use serde::Serialize;

/// Settings of the region analysis.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RegionSettings {
    /// Bracketing step in β (−): β is sampled upward from 0 at this step until the first
    /// unstable sample; an unstable band thinner than this in β can be stepped over.
    pub beta_bracket: f64,
    /// Bisection tolerance on β (−).
    pub beta_tolerance: f64,
    /// Bisection tolerance on φ for region edges (rad/s).
    pub phi_tolerance: f64,
    /// Highest order k of the predicted region starts (ω_i + ω_j)/k.
    pub max_order: usize,
    /// Number of β levels of the boundary tracking between the onset and β_max.
    pub tracking_levels: usize,
    /// Most refinement steps of the tip search once its maximum is bracketed (parabolic,
    /// or golden section where the parabola does not help).
    pub tip_iterations: usize,
    /// The tip search stops when its bracket is narrower than this, relative to φ.
    pub tip_tolerance: f64,
    /// The tip is searched at β = β_c(seed)·(1 + relative) + absolute: the region is a short
    /// interval there whose growth maximum is the start, biased by at most its half-width.
    pub tip_margin: (f64, f64),
    /// Relative spacing g of the guard lattice (1 + g)^n at the level (0 turns it off):
    /// an unstable lattice point outside every seeded tongue is a tongue no seed found,
    /// reported as unexplained. The band's march from φ_op visits the same points.
    pub guard_step: f64,
    /// Secant iterations of the centre search.
    pub centre_iterations: usize,
    /// Largest φ step when marching to a region's edge, (absolute rad/s, relative to φ):
    /// the larger of the two. A stable gap between two tongues at least this wide is never
    /// stepped over.
    pub edge_step: (f64, f64),
}

impl RegionSettings {
    /// The largest edge-march step at φ (rad/s).
    pub fn max_edge_step(&self, phi: f64) -> f64 {
        self.edge_step.0.max(self.edge_step.1 * phi.abs())
    }

    /// Tight tolerances for finite-difference sensitivities: quantities must be resolved
    /// far below their change over the step (start to ~1e-8·φ, β to 1e-8).
    pub fn precise() -> RegionSettings {
        RegionSettings {
            beta_tolerance: 1e-10,
            phi_tolerance: 1e-5,
            tip_iterations: 60,
            tip_tolerance: 1e-9,
            tip_margin: (1e-4, 1e-8),
            ..RegionSettings::default()
        }
    }
}

impl Default for RegionSettings {
    fn default() -> Self {
        RegionSettings {
            // 1/32: regions are wedges opening upward, so only a stable hole thinner than
            // 0.031 in β inside a region can be stepped over — finer than the 0.025 β step
            // of the paper's charts.
            beta_bracket: 1.0 / 32.0,
            // 1e-4: below the resolution any chart of the paper shows (0.025 in β).
            beta_tolerance: 1e-4,
            // 0.2 rad/s: five times finer than the 1 rad/s grid the edges are checked on.
            phi_tolerance: 0.2,
            max_order: 2,
            tracking_levels: 12,
            // 8: parabolic steps converge in 3–5 on a smooth dome; golden steps take over
            // where the region is narrower than the climb's first step.
            tip_iterations: 8,
            // 1e-5: a hundredth of the 0.1 % the starts are checked to.
            tip_tolerance: 1e-5,
            // 5 % + 0.002: a region wide enough for the climb's first steps to see its dome,
            // while the bias (at most its half-width there) stays far below the 0.1 % the
            // start is checked to.
            tip_margin: (0.05, 2e-3),
            // 0.5 %: a tongue the seeds missed that is wider than 0.5 % of φ at the level
            // cannot hide between two lattice points (~880 points over 100..8000 rad/s,
            // of which only those in stable bands are evaluated).
            guard_step: 0.005,
            // 3: from the seed the first secant step lands inside a drifted tongue in the
            // cases examined; two more absorb a misidentified first step.
            centre_iterations: 3,
            // 2 rad/s or 0.2 %: below 1000 rad/s twice the 1 rad/s grid the edges are
            // checked on (0.5 % let a gap at 4768 rad/s on Fig. 11 be stepped over).
            edge_step: (2.0, 2e-3),
        }
    }
}

/// Result of one β_c(φ) evaluation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CriticalLoad {
    /// φ (rad/s).
    pub phi: f64,
    /// β_c, or None if stable up to β_max.
    pub beta: Option<f64>,
    /// Monodromy evaluations used.
    pub evaluations: usize,
}

/// Whether (φ, β) is unstable, from a table valid up to at least β.
pub fn unstable(fs: &FloquetSystem, table: &PhiTable, beta: f64) -> bool {
    !fs.point_fast(table, beta).summary.stable
}

/// β_c(φ) in [0, β_max]: bracket from below at `beta_bracket`, then bisect.
pub fn critical_load(fs: &FloquetSystem, settings: &RegionSettings, phi: f64, beta_max: f64) -> CriticalLoad {
    let table = fs.table(phi, beta_max);
    let crossing = Crossing::below(fs, settings, &table, (0.0, beta_max), settings.beta_tolerance);
    CriticalLoad { phi, beta: crossing.bracket.map(|b| b.1), evaluations: crossing.evaluations }
}

/// The first stable → unstable crossing in β on one per-φ table, bracketed from below.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crossing {
    /// (stable, unstable) loads at most the tolerance apart; (0, 0) if unstable at β = 0;
    /// None if stable up to β_max.
    pub bracket: Option<(f64, f64)>,
    /// Monodromy evaluations used.
    pub evaluations: usize,
}

impl Crossing {
    /// The first crossing in (from, to] on one table: bracket upward from `from` (known
    /// stable, or 0, which is evaluated) at the multiples of `beta_bracket` and `to`
    /// itself, then bisect to `tolerance`.
    pub fn below(
        fs: &FloquetSystem,
        settings: &RegionSettings,
        table: &PhiTable,
        (from, to): (f64, f64),
        tolerance: f64,
    ) -> Crossing {
        let mut evaluations = 0;
        let mut eval = |b: f64| {
            evaluations += 1;
            unstable(fs, table, b)
        };
        if from == 0.0 && eval(0.0) {
            return Crossing { bracket: Some((0.0, 0.0)), evaluations };
        }
        let first = (from / settings.beta_bracket).floor() as usize + 1;
        let last = (to / settings.beta_bracket).ceil().max(1.0) as usize;
        let mut lo = from;
        for k in first..=last {
            let hi = (k as f64 * settings.beta_bracket).min(to);
            if hi <= lo {
                continue;
            }
            if eval(hi) {
                let bracket = bisect(lo, hi, tolerance, &mut eval);
                return Crossing { bracket: Some(bracket), evaluations };
            }
            lo = hi;
        }
        Crossing { bracket: None, evaluations }
    }

    /// A (stable, unstable) bracket bisected to `tolerance` on its table; `evaluations`
    /// counts this bisection's.
    pub fn bisected(fs: &FloquetSystem, table: &PhiTable, (lo, hi): (f64, f64), tolerance: f64) -> Crossing {
        let mut evaluations = 0;
        let mut eval = |b: f64| {
            evaluations += 1;
            unstable(fs, table, b)
        };
        let bracket = bisect(lo, hi, tolerance, &mut eval);
        Crossing { bracket: Some(bracket), evaluations }
    }
}

/// β_c(φ) below a load `beta_hi` known to be near the region's onset (the β_c of a point
/// within 0.3 % of φ): None if φ is stable at `beta_hi`, otherwise step down from
/// `beta_hi` at `beta_bracket` to the first stable sample (or 0) and bisect. Next to a
/// tip the region is a wedge, so the crossing found is the first from below.
pub fn critical_load_below(fs: &FloquetSystem, settings: &RegionSettings, phi: f64, beta_hi: f64) -> CriticalLoad {
    let table = fs.table(phi, beta_hi);
    let mut evaluations = 0;
    let mut eval = |b: f64| {
        evaluations += 1;
        unstable(fs, &table, b)
    };
    if !eval(beta_hi) {
        return CriticalLoad { phi, beta: None, evaluations };
    }
    let mut hi = beta_hi;
    loop {
        let lo = (hi - settings.beta_bracket).max(0.0);
        if !eval(lo) {
            let beta = bisect(lo, hi, settings.beta_tolerance, &mut eval).1;
            return CriticalLoad { phi, beta: Some(beta), evaluations };
        }
        if lo == 0.0 {
            return CriticalLoad { phi, beta: Some(0.0), evaluations };
        }
        hi = lo;
    }
}

/// Bisect between a stable `lo` and an unstable `hi` until they are at most `tolerance`
/// apart; the final (stable, unstable) pair.
fn bisect(mut lo: f64, mut hi: f64, tolerance: f64, eval: &mut impl FnMut(f64) -> bool) -> (f64, f64) {
    while hi - lo > tolerance {
        let mid = 0.5 * (lo + hi);
        if eval(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    (lo, hi)
}
