//! The margin-constrained tuning step as a convex quadratic programme (clarabel):
//!
//! ```text
//! minimise    ½ Σ w_j (u_j + d_j − r_j)²           (least weighted change from the reference r)
//! subject to  g_i · d ≤ h_i                        (linearised clearance constraints)
//!             −Δ ≤ d_j ≤ Δ                         (trust region)
//!             0 ≤ u_j + d_j ≤ 1                    (bounds, variables scaled to [0, 1])
//! ```
//!
//! over the step d from the current point u.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};
use serde::{Deserialize, Serialize};

/// One linear constraint g · d ≤ h.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Linear {
    /// Gradient g of the constraint in scaled variables (its unit per scaled unit).
    pub g: Vec<f64>,
    /// Right-hand side h: the constraint reads g·d ≤ h (rad/s, or β for onsets).
    pub h: f64,
}

/// The step problem.
#[derive(Debug, Clone, PartialEq)]
pub struct StepProblem<'a> {
    /// Current point u (scaled, in [0, 1]).
    pub current: &'a [f64],
    /// Reference point r in scaled variables (−), from which the change is weighed.
    pub reference: &'a [f64],
    /// Weights w_j > 0.
    pub weights: &'a [f64],
    /// Linearised constraints g·d ≤ h, one per intrusion.
    pub constraints: &'a [Linear],
    /// Trust-region half-width Δ (scaled units).
    pub trust: f64,
}

/// Outcome of the step problem.
#[derive(Debug, Clone, PartialEq)]
pub enum Step {
    /// The optimal step d.
    Solved(Vec<f64>),
    /// No step inside the trust region and bounds satisfies the linearised constraints.
    Infeasible,
}

/// Clarabel's verdict on a step problem, kept as data (recorded with every convex step of
/// a design). The "almost" verdicts, reached at clarabel's reduced accuracy tolerances,
/// are taken as their full verdicts: a step is only a trial that the true model then
/// judges (it is kept only when it improves the design), so a step of reduced accuracy
/// costs at most a rejected trial.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum QpStatus {
    /// Solved to full accuracy.
    Solved,
    /// Solved to clarabel's reduced accuracy.
    AlmostSolved,
    /// Proved infeasible.
    PrimalInfeasible,
    /// Proved infeasible to reduced accuracy.
    AlmostPrimalInfeasible,
}

/// A solved step problem: the step and clarabel's verdict.
#[derive(Debug, Clone, PartialEq)]
pub struct Solved {
    /// The step, or infeasibility.
    pub step: Step,
    /// Clarabel's status.
    pub status: QpStatus,
}

/// Solve the step problem; Err with clarabel's status when it neither solves nor proves
/// infeasibility. With `elastic = Some(ρ)` every constraint gets a slack s_i ≥ 0 costing
/// ρ·s_i (g_i·d − s_i ≤ h_i): the problem is then always feasible and the step reduces the
/// constraint violation as far as the trust region allows.
pub fn solve(p: &StepProblem<'_>, elastic: Option<f64>) -> Result<Solved, String> {
    let n = p.current.len();
    let m = if elastic.is_some() { p.constraints.len() } else { 0 };
    let dim = n + m;
    let mut pm = vec![vec![0.0; dim]; dim];
    for (j, w) in p.weights.iter().enumerate() {
        pm[j][j] = *w;
    }
    let mut q: Vec<f64> = (0..n).map(|j| p.weights[j] * (p.current[j] - p.reference[j])).collect();
    q.extend(std::iter::repeat_n(elastic.unwrap_or(0.0), m));
    // Rows: constraints, slacks ≥ 0, then d ≤ min(Δ, 1 − u), then −d ≤ min(Δ, u).
    let mut rows: Vec<Vec<f64>> = Vec::new();
    let mut b: Vec<f64> = Vec::new();
    for (i, c) in p.constraints.iter().enumerate() {
        let mut row = c.g.clone();
        row.resize(dim, 0.0);
        if m > 0 {
            row[n + i] = -1.0;
        }
        rows.push(row);
        b.push(c.h);
    }
    for i in 0..m {
        let mut row = vec![0.0; dim];
        row[n + i] = -1.0;
        rows.push(row);
        b.push(0.0);
    }
    for j in 0..n {
        let mut e = vec![0.0; dim];
        e[j] = 1.0;
        rows.push(e.clone());
        b.push(p.trust.min(1.0 - p.current[j]));
        e[j] = -1.0;
        rows.push(e);
        b.push(p.trust.min(p.current[j]));
    }
    let pcsc = CscMatrix::from(&pm).to_triu();
    let acsc = CscMatrix::from(&rows);
    let cones = [SupportedConeT::NonnegativeConeT(rows.len())];
    let settings = DefaultSettingsBuilder::default().verbose(false).build().map_err(|e| e.to_string())?;
    let mut solver = DefaultSolver::new(&pcsc, &q, &acsc, &b, &cones, settings).map_err(|e| e.to_string())?;
    solver.solve();
    let status = match solver.solution.status {
        SolverStatus::Solved => QpStatus::Solved,
        SolverStatus::AlmostSolved => QpStatus::AlmostSolved,
        SolverStatus::PrimalInfeasible => QpStatus::PrimalInfeasible,
        SolverStatus::AlmostPrimalInfeasible => QpStatus::AlmostPrimalInfeasible,
        other => return Err(format!("clarabel stopped with status {other:?}")),
    };
    let step = match status {
        QpStatus::Solved | QpStatus::AlmostSolved => Step::Solved(solver.solution.x[..n].to_vec()),
        QpStatus::PrimalInfeasible | QpStatus::AlmostPrimalInfeasible => Step::Infeasible,
    };
    Ok(Solved { step, status })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_constraint_gives_the_minimum_norm_correction() {
        // From u = r, one constraint g·d ≤ h with h < 0: the least-norm step is
        // d = h·g/|g|² (the projection onto the half-space), by hand.
        let u = [0.5, 0.5, 0.5];
        let g = vec![0.3, -0.4, 0.0];
        let h = -0.05;
        let c = [Linear { g: g.clone(), h }];
        let p = StepProblem { current: &u, reference: &u, weights: &[1.0; 3], constraints: &c, trust: 1.0 };
        let Step::Solved(d) = solve(&p, None).unwrap().step else { panic!("infeasible") };
        let norm2 = 0.3f64 * 0.3 + 0.4 * 0.4;
        for j in 0..3 {
            assert!((d[j] - h * g[j] / norm2).abs() < 1e-7, "{d:?}");
        }
    }
}

#[cfg(test)]
mod more_tests {
    use super::*;

    #[test]
    fn two_constraints_and_a_trust_region() {
        // Two active constraints d1 ≥ 0.1, d2 ≥ 0.2 (as −d ≤ −c) from u = r: the minimum-norm
        // step is (0.1, 0.2). With Δ = 0.15 it is infeasible; the elastic form then goes as
        // far as the trust region allows: (0.1, 0.15).
        let u = [0.5, 0.5];
        let c = [Linear { g: vec![-1.0, 0.0], h: -0.1 }, Linear { g: vec![0.0, -1.0], h: -0.2 }];
        let p = StepProblem { current: &u, reference: &u, weights: &[1.0, 1.0], constraints: &c, trust: 1.0 };
        let Step::Solved(d) = solve(&p, None).unwrap().step else { panic!() };
        assert!((d[0] - 0.1).abs() < 1e-7 && (d[1] - 0.2).abs() < 1e-7, "{d:?}");
        let tight = StepProblem { trust: 0.15, ..p.clone() };
        assert_eq!(solve(&tight, None).unwrap().step, Step::Infeasible);
        let Step::Solved(d) = solve(&tight, Some(1e3)).unwrap().step else { panic!() };
        assert!((d[0] - 0.1).abs() < 1e-6 && (d[1] - 0.15).abs() < 1e-6, "{d:?}");
    }

    #[test]
    fn weighted_change_from_a_reference() {
        // From u ≠ r with no active constraint the step goes straight back to r (inside Δ).
        let u = [0.6, 0.3];
        let r = [0.5, 0.5];
        let p = StepProblem { current: &u, reference: &r, weights: &[2.0, 1.0], constraints: &[], trust: 1.0 };
        let Step::Solved(d) = solve(&p, None).unwrap().step else { panic!() };
        assert!((d[0] + 0.1).abs() < 1e-7 && (d[1] - 0.2).abs() < 1e-7, "{d:?}");
    }
}
