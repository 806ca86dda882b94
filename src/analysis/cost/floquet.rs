//! Cost of Floquet evaluations on a reduced model: per-φ tables, CFM4 and DSTM
//! monodromies, RK4 responses and charts, at the step counts the evaluations themselves
//! choose ([`FloquetSystem::steps_needed`], the table's Chebyshev counts).

use super::*;
use crate::analysis::floquet::fast::{chebyshev_points_after, first_chebyshev_points, MAX_COUPLING, MAX_STEPS};

/// Largest |x| = β·|ξ| per unit β of the CFM4 exponentials: 2(|w₁| + |w₂|) = 2/√3.
const XI_MAX: f64 = 1.154_700_538_379_251_5;

/// The cost of Floquet evaluations on one reduced model: the floating-point operations of
/// a per-φ table, a CFM4 or DSTM monodromy and an RK4 step, from its size, frequencies
/// and coupling.
#[derive(Debug, Clone)]
pub struct PointCost<'a> {
    fs: &'a FloquetSystem,
    /// State dimension n = 2M.
    n: f64,
    /// ‖τ⁻¹·B1‖₁ in the fast path's frequency-scaled coordinates (1/s).
    coupling: f64,
}

impl<'a> PointCost<'a> {
    /// The costs of `fs`.
    pub fn of(fs: &'a FloquetSystem) -> PointCost<'a> {
        let n = fs.system.b0.nrows();
        let m = n / 2;
        // The fast path exponentiates τ(B0 + xB1) in the coordinates [q̇; w·q], w_i the
        // modal frequency: B1's block P_cr·S̃ is divided by w of its column there.
        let scale = |j: usize| fs.system.b0[(j - m, j)].norm().sqrt().max(1.0);
        let coupling =
            (m..n).map(|j| (0..m).map(|i| fs.system.b1[(i, j)].norm()).sum::<f64>() / scale(j)).fold(0.0, f64::max);
        PointCost { fs, n: n as f64, coupling }
    }

    /// CFM4 steps per period at φ (rad/s): the system's own rule without its cap of 10⁶
    /// (a period that needs more is not resolved by fewer).
    pub fn steps(&self, phi: f64) -> f64 {
        (self.fs.settings.steps_per_period as f64).max(self.fs.steps_needed(phi))
    }

    /// A per-φ table for loads up to β: (operations, steps per period of its monodromies).
    /// Each attempt costs its Chebyshev exponentials; the steps double while the coupling
    /// per exponential exceeds [`MAX_COUPLING`], up to [`MAX_STEPS`].
    pub fn table(&self, phi: f64, beta: f64) -> (f64, f64) {
        let mut steps = self.steps(phi);
        if !steps.is_finite() {
            return (f64::INFINITY, f64::INFINITY);
        }
        steps = (2.0 * (steps / 2.0).ceil()).max(2.0);
        let per_period = XI_MAX * beta * std::f64::consts::PI / phi * self.coupling;
        let mut operations = 0.0;
        loop {
            let a = per_period / steps;
            let first = first_chebyshev_points(a);
            // Beyond the doubling threshold the interpolant does not converge at its
            // first count: every larger count is tried too.
            let tried = if a <= MAX_COUPLING { first } else { first + chebyshev_points_after(first).sum::<usize>() };
            operations += tried as f64 * (EXP_OPS_N3 * cubed(self.n));
            if a <= MAX_COUPLING || steps >= MAX_STEPS as f64 || !a.is_finite() {
                return (operations, steps);
            }
            steps *= 2.0;
        }
    }

    /// A per-φ table for loads up to `beta_table`, one monodromy on it by the configured
    /// method and one point on a table of its own (operations of each), from one count of
    /// the table: (table, monodromy, point). A DSTM point builds no table; the region
    /// searches' β crossings do, whatever the method.
    pub(super) fn costs(&self, phi: f64, beta_table: f64) -> (f64, f64, f64) {
        let (table, steps) = self.table(phi, beta_table);
        match self.fs.settings.method {
            MonodromyMethod::Fast => {
                let monodromy = steps * step_ops(self.n) + EIG_OPS_N3 * cubed(self.n);
                (table, monodromy, table + monodromy)
            }
            MonodromyMethod::Dstm => (table, self.dstm(), self.dstm()),
        }
    }

    /// One point on a table of its own (operations), by the configured method: what a
    /// search's point costs.
    pub fn point(&self, phi: f64, beta: f64) -> f64 {
        self.costs(phi, beta).2
    }

    /// One DSTM monodromy with the settings' reference steps (operations).
    pub fn dstm(&self) -> f64 {
        self.fs.settings.reference_steps as f64 * (DSTM_STEP_OPS_N3 * cubed(self.n)) + EIG_OPS_N3 * cubed(self.n)
    }

    /// Driver and detail of a point at φ: the low frequency when its steps exceed the
    /// settings' minimum many times, the reduced model when its size makes a step dear.
    pub(super) fn point_driver(&self, phi: f64) -> (Driver, String) {
        let settings = &self.fs.settings;
        if settings.method == MonodromyMethod::Dstm {
            return (Driver::Settings, format!("{} DSTM steps per point", settings.reference_steps));
        }
        let steps = self.steps(phi);
        if steps.is_nan() || steps > 16.0 * settings.steps_per_period as f64 {
            let why = format!("at phi = {} rad/s a period needs {} CFM4 steps", compact(phi), compact_count(steps));
            return (Driver::LowFrequency, why);
        }
        (Driver::ReducedModel, format!("M = {} modes, {} CFM4 steps per period", self.n / 2.0, compact_count(steps)))
    }
}

/// One Floquet point by the configured method (`floquet`).
pub fn floquet_point(pc: &PointCost, phi: f64, beta: f64) -> Estimate {
    let (driver, detail) = pc.point_driver(phi);
    Estimate::work(pc.point(phi, beta), driver, detail)
}

/// A chart: one table per φ (to the grid's largest β) and a monodromy per point.
pub fn chart(pc: &PointCost, phis: &[f64], betas: &[f64]) -> Estimate {
    let beta_max = betas.iter().fold(0.0f64, |m, b| m.max(b.abs()));
    let nb = betas.len() as f64;
    let operations: f64 = phis
        .iter()
        .map(|&phi| {
            let (table, monodromy, _) = pc.costs(phi, beta_max);
            let table = if pc.fs.settings.method == MonodromyMethod::Fast { table } else { 0.0 };
            table + nb * monodromy
        })
        .sum();
    let lowest = phis.iter().copied().fold(f64::INFINITY, f64::min);
    let (driver, why) = pc.point_driver(lowest);
    let detail = format!("{} points ({} phi × {} beta); {why}", phis.len() * betas.len(), phis.len(), betas.len());
    let driver =
        if driver == Driver::ReducedModel && phis.len() * betas.len() > 10_000 { Driver::Grid } else { driver };
    Estimate::work(operations, driver, detail)
}

/// The time response `response` runs at (φ, β) over `periods` load periods and its
/// Floquet point: the response's own RK4 steps per period
/// ([`crate::analysis::response::rk4_steps_per_period`]), except that a stiff one (beyond
/// `STIFFNESS_LIMIT` times the phase rule's steps) is refused before any step, so only
/// the phase rule's steps are counted for it.
pub fn response_of(fs: &FloquetSystem, phi: f64, beta: f64, periods: usize) -> Estimate {
    use crate::analysis::response::{phase_steps, rk4_steps_per_period, STIFFNESS_LIMIT};
    let pc = PointCost::of(fs);
    let phase = phase_steps(fs, phi).max(64.0);
    let per_period = rk4_steps_per_period(fs, phi) as f64;
    let per_period = if per_period > STIFFNESS_LIMIT * phase { phase } else { per_period };
    let operations = per_period * periods as f64 * rk4_ops(pc.n) + pc.point(phi, beta);
    // Many steps per period come from a fast rotor (Ω above every mode and φ) or a low φ;
    // otherwise the periods asked for drive the work.
    let w_max = fs.reduced.frequencies.iter().copied().fold(phi, f64::max);
    let driver = match per_period > 64.0 * 16.0 {
        true if fs.speed > w_max => Driver::Speed,
        true => Driver::LowFrequency,
        false => Driver::Periods,
    };
    let detail = format!(
        "{periods} periods × {} RK4 steps per period at phi = {} rad/s",
        compact_count(per_period),
        compact(phi)
    );
    Estimate::work(operations, driver, detail)
}
