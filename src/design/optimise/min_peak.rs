//! The least peak response: multi-start Nelder–Mead (argmin) on the scaled variables,
//! first without constraints (the design that damps best), then with the constraints as
//! an exact penalty, then sequential convex steps (clarabel) on the linearised
//! constraints from the best feasible point (see [`crate::design`]).

use super::convex::linearise;
use super::peak_as_built::{build_peak, largest, CornerPeak};
use super::*;
use crate::design::vibration::{
    check_constraints, classic_tuning, peak_of, rotor_at, Baseline, ClassicTuning, ConstraintCheck, PeakValue,
};
use serde::Deserialize;

/// Nelder–Mead stops when the simplex's costs (ln of the peak in m) differ by less than
/// this: 1e-4 is 0.01 % of the peak, far below what distinguishes two designs.
const COST_TOLERANCE: f64 = 1e-4;
/// Penalty per unit of relative constraint violation, in units of ln(peak): a violation of
/// 0.1 % of a limit costs as much as a factor e in the peak, far above the peak's
/// sensitivity to the constraints near an optimum (their Lagrange multipliers), so a
/// minimiser of the penalised cost is feasible wherever a feasible design lies nearby
/// (an exact penalty).
const VIOLATION_PENALTY: f64 = 1.0e3;
/// Penalty per scaled unit outside [0, 1] (ln units): the nearest point inside is
/// evaluated and the simplex pushed back.
const BOUND_PENALTY: f64 = 100.0;
/// Cost of a candidate whose analysis failed (ln units, far above any design).
const FAILED_LN_COST: f64 = 1.0e3;
/// Central-difference step of the convex steps' gradients (scaled units, 1 % of a range).
const GRADIENT_STEP: f64 = 0.01;
/// First and largest trust region of the convex steps (scaled units); below the least,
/// no further progress is possible.
const TRUST_START: f64 = 0.05;
const TRUST_MAX: f64 = 0.2;
const TRUST_MIN: f64 = 1e-3;
/// Convex steps at most after the penalised Nelder–Mead.
const CONVEX_STEPS: usize = 8;
/// Margin asked of each linearised constraint (relative units): the linearisation is
/// only first order, so a constraint met exactly by it can be missed by a little.
const MARGIN: f64 = 1e-3;

/// One design judged: its scaled point, peak and constraints.
#[derive(Debug, Clone)]
struct Judged {
    /// Scaled point, in [0, 1].
    u: Vec<f64>,
    /// Its values (SI units): `u`'s, or the reference design's own where they lie
    /// outside the bounds.
    values: Vec<f64>,
    peak: PeakValue,
    /// With `[design.tolerances]`: the corner of the tolerance box with the largest peak.
    worst: Option<CornerPeak>,
    checks: Vec<ConstraintCheck>,
}

impl Judged {
    /// What the optimiser minimises (m): the peak, or with `[design.tolerances]` the
    /// largest peak over the tolerance box's centre and corners.
    fn value(&self) -> f64 {
        self.worst.as_ref().map_or(self.peak.amplitude, |w| w.peak.amplitude.max(self.peak.amplitude))
    }
    fn violation(&self) -> f64 {
        self.checks.iter().map(|c| c.violation).sum()
    }
    fn feasible(&self) -> bool {
        self.checks.iter().all(|c| c.met)
    }
}

/// The design with its peak and constraints, for reports.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct JudgedDesign {
    /// Variable values (SI units).
    pub values: Vec<f64>,
    /// Its largest amplitude at the response node (as designed).
    pub peak: PeakValue,
    /// With `[design.tolerances]`: the corner of the tolerance box with the largest peak,
    /// the value the optimiser minimised.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub worst_corner: Option<CornerPeak>,
    /// The constraints on it (empty without constraints).
    pub constraints: Vec<ConstraintCheck>,
    /// Whether every constraint is met.
    pub feasible: bool,
}

/// One sequential convex step of the constrained run.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct PeakStep {
    /// Step number, from 1.
    pub iteration: usize,
    /// Trust region (scaled units).
    pub trust: f64,
    /// Number of linearised constraints (rows) of the step's QP: one per constraint other
    /// than the bands, plus the bands' intruders and neighbours.
    pub constraints: usize,
    /// Peak before (m; with `[design.tolerances]`, the worst corner's).
    pub peak_before: f64,
    /// Peak at the trial point (m; with `[design.tolerances]`, the worst corner's).
    pub peak_after: f64,
    /// Whether the trial point meets every constraint.
    pub feasible: bool,
    /// Whether the step was taken.
    pub accepted: bool,
    /// Trial values (SI units).
    pub values: Vec<f64>,
    /// Clarabel's verdict on the step's QP (`crate::design::qp::QpStatus`).
    pub qp_status: crate::design::qp::QpStatus,
}

/// What the price of the stability constraints is in response.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct Price {
    /// Constrained peak − unconstrained peak (m; with `[design.tolerances]`, of their worst
    /// corners).
    pub metres: f64,
    /// The same relative to the unconstrained peak (%).
    pub percent: f64,
}

/// The min-peak-response findings.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct PeakFindings {
    /// The reference design.
    pub before: JudgedDesign,
    /// The tuned design.
    pub after: JudgedDesign,
    /// The design that damps best with no constraint (the constraints judged on it).
    pub unconstrained: JudgedDesign,
    /// The classic single-mode tuning and its design, when a branch has a tuning or
    /// resistance variable.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub classic: Option<ClassicTuning>,
    /// The classic design's peak (m, with the constraints judged on it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub classic_design: Option<JudgedDesign>,
    /// What the constraints cost in peak response (with constraints only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub price: Option<Price>,
    /// The sequential convex steps after the penalised Nelder–Mead.
    pub convex_steps: Vec<PeakStep>,
    /// With `[design.tolerances]`: the tuned design's peak at every corner of the tolerance
    /// box and at its Monte Carlo samples (the verification's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub as_built: Option<super::peak_as_built::PeakAsBuilt>,
    /// The tuned design beside the open circuit, the reference circuit and the classic
    /// tuning, each by peak and amplification factor (`crate::design::vibration::baselines`).
    pub baselines: Vec<Baseline>,
}

impl Context<'_> {
    /// The peak and (when `constrained`) the constraints of the design at `u` (scaled).
    fn judge(&self, u: &[f64], constrained: bool) -> Result<Judged, DesignError> {
        self.judge_values(u, &self.values(u), constrained)
    }

    /// [`Context::judge`] of the design with `values` (SI units) at the scaled point `u`.
    fn judge_values(&self, u: &[f64], values: &[f64], constrained: bool) -> Result<Judged, DesignError> {
        // None once the caller asks to stop, as for `Context::candidate`.
        super::stopped(self.progress)?;
        self.candidates.fetch_add(1, Ordering::Relaxed);
        self.progress.advance(1);
        let r = self.judge_quietly(u, values, constrained);
        match &r {
            Err(e) => self.note_failure(e),
            // Unconstrained judgements rank only where there are no constraints to miss.
            Ok(j) if constrained || self.spec.constraints.is_empty() => {
                let rank = if j.feasible() { Rank(0, j.value(), 0.0) } else { Rank(1, j.violation(), j.value()) };
                self.best.offer(rank, values, self.progress);
            }
            Ok(_) => {}
        }
        r
    }

    fn judge_quietly(&self, u: &[f64], values: &[f64], constrained: bool) -> Result<Judged, DesignError> {
        let spec = self.spec;
        let response = spec.response().ok_or(DesignError::NoResponse)?;
        let (machine, rotor) = rotor_at(self.base, spec, values)?;
        let peak = peak_of(&rotor, response)?;
        let worst = match &spec.tolerances {
            Some(t) => worst_corner(&machine, &rotor, t, response)?,
            None => None,
        };
        let checks = if constrained && !spec.constraints.is_empty() {
            let c = Candidate::from_parts(machine, rotor, spec, spec.constraints.needs_stability())?;
            check_constraints(&c, &self.eval(), Some(peak))?
        } else {
            Vec::new()
        };
        Ok(Judged { u: u.iter().map(|x| x.clamp(0.0, 1.0)).collect(), values: values.to_vec(), peak, worst, checks })
    }

    fn report(&self, j: &Judged) -> JudgedDesign {
        JudgedDesign {
            values: j.values.clone(),
            peak: j.peak,
            worst_corner: j.worst.clone(),
            constraints: j.checks.clone(),
            feasible: j.feasible(),
        }
    }
}

/// The corner of the tolerance box with the largest peak ([`build_peak`] at each corner); None for a
/// box without corners.
fn worst_corner(
    machine: &Machine,
    rotor: &crate::Rotor,
    t: &crate::design::tolerance::Tolerances,
    response: &crate::design::spec::Response,
) -> Result<Option<CornerPeak>, DesignError> {
    let corners = t.corners()[1..]
        .iter()
        .map(|p| build_peak(&machine.model, rotor.critical_load, p, response))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(largest(&corners).cloned())
}

/// The Nelder–Mead cost of one start: ln(peak) (+ the penalty); keeps the best point
/// (feasible first, then lowest peak) and the history.
struct PeakCost<'a, 'b> {
    ctx: &'a Context<'b>,
    constrained: bool,
    start: usize,
    history: RefCell<Vec<HistoryPoint>>,
    best: RefCell<Option<Judged>>,
}

/// Whether `a` is a better design than `b`: feasible before infeasible, then the smaller
/// violation, then the lower peak.
fn better(a: &Judged, b: &Judged) -> bool {
    match (a.feasible(), b.feasible()) {
        (true, false) => true,
        (false, true) => false,
        (true, true) => a.value() < b.value(),
        (false, false) => (a.violation(), a.value()) < (b.violation(), b.value()),
    }
}

impl CostFunction for PeakCost<'_, '_> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, u: &Self::Param) -> Result<f64, argmin::core::Error> {
        let outside: f64 = u.iter().map(|&x| (x - x.clamp(0.0, 1.0)).abs()).sum();
        let judged = self.ctx.judge(u, self.constrained).ok();
        let cost = match &judged {
            Some(j) => j.value().ln() + VIOLATION_PENALTY * j.violation(),
            None => FAILED_LN_COST,
        };
        if let Some(j) = judged {
            let mut best = self.best.borrow_mut();
            if best.as_ref().is_none_or(|b| better(&j, b)) {
                *best = Some(j);
            }
        }
        let mut h = self.history.borrow_mut();
        let value = cost.exp();
        let best = h.last().map_or(value, |p| p.best.min(value));
        let step = h.len() + 1;
        let point = HistoryPoint { start: self.start, step, value, best };
        h.push(point);
        self.ctx.observe(point, u);
        Ok(cost + BOUND_PENALTY * outside)
    }
}

/// One start's report, history and best design.
type PeakRun = (StartReport, Vec<HistoryPoint>, Option<Judged>);

/// Nelder–Mead from each of `starts` in parallel: their reports, histories and best points.
fn nelder_mead(
    ctx: &Context<'_>,
    starts: &[(String, Vec<f64>)],
    constrained: bool,
    first: usize,
) -> Result<Vec<PeakRun>, DesignError> {
    starts
        .par_iter()
        .enumerate()
        .map(|(i, (origin, u0))| {
            let cost = PeakCost {
                ctx,
                constrained,
                start: first + i,
                history: RefCell::new(Vec::new()),
                best: RefCell::new(None),
            };
            let solver = NelderMead::new(super::nelder_mead::initial_simplex(u0))
                .with_sd_tolerance(COST_TOLERANCE)
                .map_err(|e| DesignError::Optimiser(e.to_string()))?;
            let res = Executor::new(cost, solver)
                .configure(|s| s.max_iters(ctx.spec.max_iterations as u64))
                .run()
                .map_err(|e| DesignError::Optimiser(e.to_string()))?;
            let state = res.state();
            let (history, best) = match res.problem.problem.as_ref() {
                Some(c) => (c.history.borrow().clone(), c.best.borrow().clone()),
                None => (Vec::new(), None),
            };
            let report = StartReport {
                origin: format!("{}{origin}", if constrained { "constrained, " } else { "" }),
                initial: ctx.values(u0),
                best: best.as_ref().map_or_else(|| ctx.values(u0), |b| b.values.clone()),
                objective: best.as_ref().map_or(f64::NAN, Judged::value),
                evaluations: history.len(),
                iterations: state.get_iter(),
                termination: state.get_termination_reason().map_or("none".into(), |r| r.to_string()),
            };
            Ok((report, history, best))
        })
        .collect()
}

/// The starts of a run: `first` points, then the reference, then the map's basins
/// (`basins`, scaled, best first), then Halton points, to `spec.starts` (at least the
/// given ones).
fn starts_of(
    ctx: &Context<'_>,
    first: Vec<(String, Vec<f64>)>,
    reference: &[f64],
    basins: &[Vec<f64>],
) -> Vec<(String, Vec<f64>)> {
    let n = ctx.spec.variables.len();
    let mut starts = first;
    starts.push(("reference".into(), reference.to_vec()));
    for (r, u) in basins.iter().enumerate() {
        if starts.len() >= ctx.spec.starts {
            break;
        }
        starts.push((format!("map basin {}", r + 1), u.clone()));
    }
    let mut k = 0;
    while starts.len() < ctx.spec.starts {
        starts.push((format!("halton {}", k + 1), halton(k, n)));
        k += 1;
    }
    starts
}

/// The map of the peak over the box (`design.map`, as the widest-band objective's): the
/// Halton set's points judged without constraints (with `[design.tolerances]`, at the
/// worst corner), in parallel; the best distinct basins (lowest peaks) as scaled points,
/// best first. The map goes to `out.map`.
fn peak_map(ctx: &Context<'_>, out: &mut DesignOutcome, node: usize) -> Result<Vec<Vec<f64>>, DesignError> {
    let n = ctx.spec.variables.len();
    let scaled = map::points(map::map_points(n), n);
    let peaks: Vec<Option<f64>> = scaled.par_iter().map(|u| ctx.judge(u, false).ok().map(|j| j.value())).collect();
    stopped(ctx.progress)?;
    // Basins of the lowest peaks: ln(peak) negated, to be maximised.
    let score: Vec<Option<f64>> = peaks.iter().map(|p| p.filter(|p| *p > 0.0).map(|p| -p.ln())).collect();
    let chosen = map::basins(&scaled, &score, ctx.spec.starts.max(1) + map::extra_starts(n));
    out.map = Some(ObjectiveMap {
        objective: format!("largest unbalance amplitude at node {node} (without the constraints), m"),
        maximise: false,
        points: scaled.iter().zip(&peaks).map(|(u, &v)| MapPoint { values: ctx.values(u), objective: v }).collect(),
        basins: chosen.clone(),
        slices: Vec::new(),
    });
    Ok(chosen.into_iter().map(|i| scaled[i].clone()).collect())
}

/// Sequential convex steps from `start`, each accepted when it gives a better design
/// ([`better`]: feasible first, then less violation or a lower peak): the gradient step on ln(peak)
/// projected (clarabel, [`crate::design::qp`]) onto the linearised constraints (each
/// constraint's signed margin by central differences; the bands' intruders and neighbours
/// as the clear-bands steps linearise them) inside a trust region.
fn convex_steps(ctx: &Context<'_>, start: Judged) -> Result<(Judged, Vec<PeakStep>), DesignError> {
    let n = start.u.len();
    let mut at = start;
    let mut trust = TRUST_START;
    let mut steps = Vec::new();
    let weights = vec![1.0; n];
    for iteration in 1..=CONVEX_STEPS.min(ctx.spec.max_iterations) {
        let probes: Vec<(usize, f64)> = (0..n).flat_map(|j| [(j, GRADIENT_STEP), (j, -GRADIENT_STEP)]).collect();
        let probed: Vec<Result<Judged, DesignError>> = probes
            .par_iter()
            .map(|&(j, h)| {
                let mut p = at.u.clone();
                p[j] = (p[j] + h).clamp(0.0, 1.0);
                ctx.judge(&p, true)
            })
            .collect();
        let probed = probed.into_iter().collect::<Result<Vec<_>, _>>()?;
        let span = |j: usize| (at.u[j] + GRADIENT_STEP).min(1.0) - (at.u[j] - GRADIENT_STEP).max(0.0);
        let grad_ln: Vec<f64> =
            (0..n).map(|j| (probed[2 * j].value().ln() - probed[2 * j + 1].value().ln()) / span(j)).collect();
        let mut rows: Vec<Linear> = Vec::new();
        for (i, c) in at.checks.iter().enumerate() {
            if c.kind == crate::design::vibration::ConstraintKind::BandsClear {
                continue;
            }
            let margin = |x: &ConstraintCheck| signed_margin(x);
            let g: Vec<f64> = (0..n)
                .map(|j| -(margin(&probed[2 * j].checks[i]) - margin(&probed[2 * j + 1].checks[i])) / span(j))
                .collect();
            rows.push(Linear { g, h: margin(c) - MARGIN });
        }
        if !ctx.spec.constraints.bands.is_empty() {
            let c = ctx.candidate(&at.u)?;
            let ints = intrusions(&c, &ctx.eval())?;
            rows.extend(linearise(ctx, &at.u, &ints)?);
        }
        let norm = grad_ln.iter().fold(0.0f64, |m, g| m.max(g.abs()));
        if norm == 0.0 {
            break;
        }
        let target: Vec<f64> = at.u.iter().zip(&grad_ln).map(|(u, g)| u - trust * g / norm).collect();
        let problem = StepProblem { current: &at.u, reference: &target, weights: &weights, constraints: &rows, trust };
        // A step problem clarabel neither solves nor proves infeasible (a constraint far
        // out of scale: a peak limit of 1e-30 m stalls it with InsufficientProgress) gives
        // no step to trust: the steps from this start end, and the design is judged as it
        // stands, infeasible if it is (issue 50, item 5).
        let Ok(solved) = qp::solve(&problem, None) else { break };
        let qp_status = solved.status;
        let d = match solved.step {
            Step::Solved(d) => d,
            Step::Infeasible => {
                trust /= 2.0;
                if trust < TRUST_MIN {
                    break;
                }
                continue;
            }
        };
        let trial: Vec<f64> = at.u.iter().zip(&d).map(|(a, b)| (a + b).clamp(0.0, 1.0)).collect();
        let judged = ctx.judge(&trial, true)?;
        let accepted = better(&judged, &at);
        steps.push(PeakStep {
            iteration,
            trust,
            constraints: rows.len(),
            peak_before: at.value(),
            peak_after: judged.value(),
            feasible: judged.feasible(),
            accepted,
            values: ctx.values(&trial),
            qp_status,
        });
        if accepted {
            at = judged;
            trust = (2.0 * trust).min(TRUST_MAX);
        } else {
            trust /= 2.0;
            if trust < TRUST_MIN {
                break;
            }
        }
    }
    Ok((at, steps))
}

/// A constraint's signed margin (relative; ≥ 0 when met).
fn signed_margin(c: &ConstraintCheck) -> f64 {
    use crate::design::vibration::ConstraintKind as K;
    let scale = c.limit.abs().max(f64::MIN_POSITIVE);
    match c.kind {
        K::Peak => (c.limit - c.value) / scale,
        K::BandWidth | K::Damping => (c.value - c.limit) / scale,
        K::BandsClear => -c.violation,
        K::Margins => (c.value - c.limit) / c.limit.max(crate::design::vibration::MARGIN_SCALE),
    }
}

/// The min-peak-response run: fills the starts, history, tuned values and
/// [`Findings::MinPeak`].
pub(crate) fn min_peak(ctx: &Context<'_>, out: &mut DesignOutcome) -> Result<(), DesignError> {
    let spec = ctx.spec;
    let reference = to_unit(spec, &out.before);
    let classic = classic_tuning(ctx.base, spec)?;
    let mut first = Vec::new();
    if let Some(c) = &classic {
        first.push(("classic tuning".to_string(), to_unit(spec, &c.values)));
    }
    first.extend(ctx.extra_starts.iter().cloned());
    let constrained = !spec.constraints.is_empty();
    // The map over the box, whose basins take the starts the first ones leave.
    let basins = match spec.response() {
        Some(r) if spec.map => peak_map(ctx, out, r.node)?,
        _ => Vec::new(),
    };
    // The reference at its own values (they may lie outside the bounds).
    let before = ctx.judge_values(&reference, &out.before, true)?;
    let classic_design = match &classic {
        Some(c) => Some(ctx.judge(&to_unit(spec, &c.values), true)?),
        None => None,
    };
    // Without constraints: the design that damps best (the caller's, when given).
    let free = match &ctx.unconstrained {
        Some(u) => ctx.judge(u, false)?,
        None => {
            let free_starts = starts_of(ctx, first.clone(), &reference, &basins);
            let runs = nelder_mead(ctx, &free_starts, false, 0)?;
            let mut free: Option<Judged> = None;
            for (report, history, best) in runs {
                out.starts.push(report);
                out.history.extend(history);
                if let Some(b) = best {
                    if free.as_ref().is_none_or(|f| b.value() < f.value()) {
                        free = Some(b);
                    }
                }
            }
            free.ok_or_else(|| DesignError::Optimiser("no start evaluated a design".into()))?
        }
    };
    // The constraints judged on the unconstrained optimum (a fresh evaluation).
    let free = if constrained { ctx.judge(&free.u, true)? } else { free };
    let mut convex = Vec::new();
    let mut best = free.clone();
    if constrained {
        let mut seeds = vec![("unconstrained optimum".to_string(), free.u.clone())];
        seeds.extend(first);
        let starts = starts_of(ctx, seeds, &reference, &basins);
        let offset = out.starts.len();
        let runs = nelder_mead(ctx, &starts, true, offset)?;
        let mut found: Option<Judged> = None;
        for (report, history, b) in runs {
            out.starts.push(report);
            out.history.extend(history);
            if let Some(b) = b {
                if found.as_ref().is_none_or(|f| better(&b, f)) {
                    found = Some(b);
                }
            }
        }
        best = found.unwrap_or_else(|| before.clone());
        let (polished, steps) = convex_steps(ctx, best)?;
        best = polished;
        convex = steps;
    }
    let improved = |b: &Judged| b.feasible() && (!before.feasible() || b.value() < before.value());
    out.status = if constrained && !best.feasible() {
        Status::Infeasible
    } else if improved(&best) {
        Status::Improved
    } else {
        best = before.clone();
        Status::Unchanged
    };
    out.after = best.values.clone();
    let price = constrained.then(|| {
        let metres = best.value() - free.value();
        Price { metres, percent: 100.0 * metres / free.value() }
    });
    out.findings = Findings::MinPeak(Box::new(PeakFindings {
        // Filled by the run with the responses of its report ([`crate::design::vibration::baselines`]).
        baselines: Vec::new(),
        before: ctx.report(&before),
        after: ctx.report(&best),
        unconstrained: ctx.report(&free),
        classic,
        classic_design: classic_design.as_ref().map(|j| ctx.report(j)),
        price,
        convex_steps: convex,
        as_built: None,
    }));
    fill_slices(ctx, out, &|u| ctx.judge(u, false).ok().map(|j| j.value()))
}
