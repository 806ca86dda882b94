//! Cost of Floquet evaluations on a reduced model: per-φ tables, CFM4 and DSTM
//! monodromies, RK4 responses and charts.

use super::*;

/// Chebyshev point counts the fast path's per-φ table tries (`floquet::fast`).
const CHEBYSHEV_DEGREES: [usize; 15] = [4, 5, 6, 7, 8, 9, 10, 12, 14, 16, 20, 24, 32, 48, 64];
/// The table's step doubling: while the coupling per exponential exceeds this, up to
/// [`TABLE_STEPS`] steps (`floquet::fast`).
const TABLE_COUPLING: f64 = 2.0;
const TABLE_STEPS: f64 = 4096.0;
/// Largest |x| = β·|ξ| per unit β of the CFM4 exponentials: 2(|w₁| + |w₂|) = 2/√3.
const XI_MAX: f64 = 1.154_700_538_379_251_5;

/// The cost of Floquet evaluations on one reduced model: the floating-point operations of
/// a per-φ table, a CFM4 or DSTM monodromy and an RK4 step, from its size, frequencies
/// and coupling.
#[derive(Debug, Clone, PartialEq)]
pub struct PointCost {
    /// State dimension n = 2M.
    n: f64,
    w_min: f64,
    w_max: f64,
    /// ‖τ⁻¹·B1‖₁ in the fast path's frequency-scaled coordinates (1/s).
    coupling: f64,
    steps_per_period: f64,
    max_step_phase: f64,
    method: MonodromyMethod,
    reference_steps: f64,
    speed: f64,
}

impl PointCost {
    /// The costs of `fs`.
    pub fn of(fs: &FloquetSystem) -> PointCost {
        let f = &fs.reduced.frequencies;
        let n = fs.system.b0.nrows();
        let m = n / 2;
        // The fast path exponentiates τ(B0 + xB1) in the coordinates [q̇; w·q], w_i the
        // modal frequency: B1's block P_cr·S̃ is divided by w of its column there.
        let scale = |j: usize| fs.system.b0[(j - m, j)].norm().sqrt().max(1.0);
        let coupling =
            (m..n).map(|j| (0..m).map(|i| fs.system.b1[(i, j)].norm()).sum::<f64>() / scale(j)).fold(0.0, f64::max);
        PointCost {
            n: n as f64,
            w_min: f.iter().copied().fold(f64::INFINITY, f64::min),
            w_max: f.iter().copied().fold(0.0, f64::max),
            coupling,
            steps_per_period: fs.settings.steps_per_period as f64,
            max_step_phase: fs.settings.max_step_phase,
            method: fs.settings.method,
            reference_steps: fs.settings.reference_steps as f64,
            speed: fs.speed,
        }
    }

    fn step(&self) -> f64 {
        step_ops(self.n)
    }

    fn eig(&self) -> f64 {
        eig_ops(self.n)
    }

    fn exp(&self) -> f64 {
        exp_ops(self.n)
    }

    /// CFM4 steps per period the step rule asks for at φ (rad/s): at least the settings'
    /// minimum, h·ω_min ≤ `max_step_phase`, and clear of the aliased resonance
    /// ([`FloquetSystem::steps_for`], without its cap of 10⁶: a period that needs more is
    /// not resolved by fewer).
    pub fn steps(&self, phi: f64) -> f64 {
        let period = 2.0 * std::f64::consts::PI / phi;
        let by_phase = (period * self.w_min / self.max_step_phase).ceil();
        let by_alias = (ALIAS_MARGIN * 2.0 * self.w_max / phi).ceil() + ALIAS_ORDERS as f64;
        let needed = by_phase.max(by_alias);
        if needed.is_nan() {
            f64::INFINITY
        } else {
            self.steps_per_period.max(needed)
        }
    }

    /// A per-φ table for loads up to β: (operations, steps per period of its monodromies).
    /// Each attempt costs its Chebyshev exponentials; the steps double while the coupling
    /// per exponential exceeds 2 (up to 4096 steps).
    pub fn table(&self, phi: f64, beta: f64) -> (f64, f64) {
        let mut steps = self.steps(phi);
        if !steps.is_finite() {
            return (f64::INFINITY, f64::INFINITY);
        }
        steps = (2.0 * (steps / 2.0).ceil()).max(2.0);
        let per_step = XI_MAX * beta * std::f64::consts::PI / phi * self.coupling;
        let mut operations = 0.0;
        loop {
            let a = per_step / steps;
            operations += chebyshev_points(a) * self.exp();
            if a <= TABLE_COUPLING || steps >= TABLE_STEPS || !a.is_finite() {
                return (operations, steps);
            }
            steps *= 2.0;
        }
    }

    /// One monodromy at load β on a table built for `beta_table` ≥ β (operations): its
    /// steps and the eigenvalues; by the DSTM if that is the method.
    pub fn monodromy(&self, phi: f64, beta_table: f64) -> f64 {
        match self.method {
            MonodromyMethod::Fast => self.table(phi, beta_table).1 * self.step() + self.eig(),
            MonodromyMethod::Dstm => self.dstm(),
        }
    }

    /// One monodromy on a table of its own (operations): what a search's point costs.
    pub fn point(&self, phi: f64, beta: f64) -> f64 {
        let (table, steps) = self.table(phi, beta);
        table + steps * self.step() + self.eig()
    }

    /// One point by the configured method (operations), as `floquet` computes it.
    pub fn point_by_method(&self, phi: f64, beta: f64) -> f64 {
        match self.method {
            MonodromyMethod::Fast => self.point(phi, beta),
            MonodromyMethod::Dstm => self.dstm(),
        }
    }

    /// One DSTM monodromy with the settings' reference steps (operations).
    pub fn dstm(&self) -> f64 {
        self.dstm_with(self.reference_steps)
    }

    /// One DSTM monodromy with `steps` steps (operations).
    pub fn dstm_with(&self, steps: f64) -> f64 {
        steps * dstm_step_ops(self.n) + self.eig()
    }

    /// Driver and detail of a point at φ: the low frequency when its steps exceed the
    /// settings' minimum many times, the reduced model when its size makes a step dear.
    pub(super) fn point_driver(&self, phi: f64) -> (Driver, String) {
        if self.method == MonodromyMethod::Dstm {
            return (Driver::Settings, format!("{} DSTM steps per point", compact(self.reference_steps)));
        }
        let steps = self.steps(phi);
        if steps.is_nan() || steps > 16.0 * self.steps_per_period {
            let why = format!("at phi = {} rad/s a period needs {} CFM4 steps", compact(phi), compact_count(steps));
            return (Driver::LowFrequency, why);
        }
        (Driver::ReducedModel, format!("M = {} modes, {} CFM4 steps per period", self.n / 2.0, compact_count(steps)))
    }
}

/// Chebyshev points of a converged interpolant at coupling `a` per exponential (the first
/// count whose coefficient bound 2(a/2)^k/k! is below a tenth of 1e-11); where the
/// coupling is too large for that, every count up to 64 is tried.
fn chebyshev_points(a: f64) -> f64 {
    let bound = |p: usize| 2.0 * (1..=p - 2).fold(1.0, |acc, i| acc * (a / 2.0) / i as f64);
    match CHEBYSHEV_DEGREES.iter().position(|&p| bound(p) <= 1e-12) {
        Some(i) if a <= TABLE_COUPLING => CHEBYSHEV_DEGREES[i] as f64,
        Some(i) => CHEBYSHEV_DEGREES[i..].iter().sum::<usize>() as f64,
        None => CHEBYSHEV_DEGREES[6..].iter().sum::<usize>() as f64,
    }
}

/// One Floquet point by the configured method (`floquet`).
pub fn floquet_point(pc: &PointCost, phi: f64, beta: f64) -> Estimate {
    let (driver, detail) = pc.point_driver(phi);
    Estimate::work(pc.point_by_method(phi, beta), driver, detail)
}

/// A chart: one table per φ (to the grid's largest β) and a monodromy per point.
pub fn chart(pc: &PointCost, phis: &[f64], betas: &[f64]) -> Estimate {
    let beta_max = betas.iter().fold(0.0f64, |m, b| m.max(b.abs()));
    let nb = betas.len() as f64;
    let operations: f64 = phis
        .iter()
        .map(|&phi| match pc.method {
            MonodromyMethod::Fast => pc.table(phi, beta_max).0 + nb * pc.monodromy(phi, beta_max),
            MonodromyMethod::Dstm => nb * pc.dstm(),
        })
        .sum();
    let lowest = phis.iter().copied().fold(f64::INFINITY, f64::min);
    let (driver, why) = pc.point_driver(lowest);
    let detail = format!("{} points ({} phi × {} beta)", phis.len() * betas.len(), phis.len(), betas.len());
    let driver =
        if driver == Driver::ReducedModel && phis.len() * betas.len() > 10_000 { Driver::Grid } else { driver };
    Estimate::work(operations, driver, if why.is_empty() { detail } else { format!("{detail}; {why}") })
}

/// RK4 steps per load period of a response at φ (`response`): 64 per period of the
/// fastest of the basis modes, φ and Ω, and at least 64.
pub fn response_steps(pc: &PointCost, phi: f64) -> f64 {
    let omega_max = pc.w_max.max(phi).max(pc.speed);
    let period = 2.0 * std::f64::consts::PI / phi;
    let s = (period * omega_max / (2.0 * std::f64::consts::PI) * 64.0).ceil();
    if s.is_nan() {
        f64::INFINITY
    } else {
        s.max(64.0)
    }
}

/// The cost of the time response `response` runs at (φ, β) over `periods` load periods:
/// the response's own steps per period ([`crate::analysis::response::rk4_steps_per_period`]),
/// except that a stiff one (beyond `STIFFNESS_LIMIT` times the phase rule's steps) is
/// refused before any step, so only the phase rule's steps are counted for it.
pub fn response_of(fs: &crate::analysis::floquet::FloquetSystem, phi: f64, beta: f64, periods: usize) -> Estimate {
    use crate::analysis::response::{rk4_steps_per_period, STIFFNESS_LIMIT};
    let pc = PointCost::of(fs);
    let phase = response_steps(&pc, phi);
    let steps = rk4_steps_per_period(fs, phi) as f64;
    let steps = if steps > STIFFNESS_LIMIT * phase { phase } else { steps };
    response(&pc, phi, beta, periods, steps)
}

/// A time response of `periods` periods of `per_period` RK4 steps each (the response's
/// own step rule, [`crate::analysis::response::rk4_steps_per_period`]) and its Floquet point.
pub fn response(pc: &PointCost, phi: f64, beta: f64, periods: usize, per_period: f64) -> Estimate {
    let steps = per_period * periods as f64;
    let operations = steps * rk4_ops(pc.n) + pc.point_by_method(phi, beta);
    // Many steps per period come from a fast rotor (Ω above every mode and φ) or a low φ;
    // otherwise the periods asked for drive the work.
    let driver = if per_period > 64.0 * 16.0 {
        if pc.speed > pc.w_max.max(phi) {
            Driver::Speed
        } else {
            Driver::LowFrequency
        }
    } else {
        Driver::Periods
    };
    let detail = format!(
        "{periods} periods × {} RK4 steps per period at phi = {} rad/s",
        compact_count(per_period),
        compact(phi)
    );
    Estimate::work(operations, driver, detail)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chebyshev_points_follow_the_coefficient_bound() {
        // a = 0.1: 2·0.05⁶/6! = 4.3e-11 at 8 points, 2·0.05⁷/7! = 3.1e-13 at 9.
        assert_eq!(chebyshev_points(0.1), 9.0);
        // a = 2: 2/14! = 2.3e-11 at 16 points, 2/18! = 3.1e-16 at 20.
        assert_eq!(chebyshev_points(2.0), 20.0);
        // Beyond the doubling threshold the table tries more counts.
        assert!(chebyshev_points(30.0) >= 64.0);
        assert!(chebyshev_points(f64::INFINITY) >= 64.0);
    }
}
