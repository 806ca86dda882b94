//! The widest stable band: multi-start Nelder–Mead (argmin) on the scaled variables,
//! the band of `rotorshunt band` as the objective.

use super::*;

/// Edge of the initial Nelder–Mead simplex in scaled units: 10 % of each variable's range
/// (of its logarithm for C_f, L, ω), large enough to step across a narrow region.
const SIMPLEX_STEP: f64 = 0.1;
/// The initial simplex around `u0` (scaled units): `u0` and one vertex per variable,
/// [`SIMPLEX_STEP`] along its axis (backwards where that would leave [0, 1]).
pub(super) fn initial_simplex(u0: &[f64]) -> Vec<Vec<f64>> {
    let mut simplex = vec![u0.to_vec()];
    for j in 0..u0.len() {
        let mut p = u0.to_vec();
        p[j] = if p[j] + SIMPLEX_STEP <= 1.0 { p[j] + SIMPLEX_STEP } else { p[j] - SIMPLEX_STEP };
        simplex.push(p);
    }
    simplex
}

/// Nelder–Mead stops when the simplex's objective values differ by less than this (rad/s):
/// the band edges themselves are bisected to 0.2 rad/s.
const OBJECTIVE_TOLERANCE: f64 = 0.1;
/// Penalty per scaled unit outside [0, 1] (rad/s): the optimiser evaluates the nearest
/// point inside the bounds and is pushed back in.
const BOUND_PENALTY: f64 = 1.0e4;

/// The Nelder–Mead cost of one start: −(band objective) + bound penalty; records history.
struct BandCost<'a, 'b> {
    ctx: &'a Context<'b>,
    phi_op: f64,
    start: usize,
    history: RefCell<Vec<HistoryPoint>>,
}

impl CostFunction for BandCost<'_, '_> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, u: &Self::Param) -> Result<f64, argmin::core::Error> {
        let outside: f64 = u.iter().map(|&x| (x - x.clamp(0.0, 1.0)).abs()).sum();
        let value = self.ctx.band_objective(u, self.phi_op);
        let mut h = self.history.borrow_mut();
        let best = h.last().map_or(value, |p| p.best.max(value));
        let step = h.len() + 1;
        let point = HistoryPoint { start: self.start, step, value, best };
        h.push(point);
        self.ctx.observe(point, u);
        Ok(-value + BOUND_PENALTY * outside)
    }
}

/// The physics seed: every tuning variable (ω of Eq. 4, or L through it) set so that the
/// predicted electrical region starts ω_w + ω_e (w = the lowest forward and backward
/// mechanical whirls of the reference, at each speed) lie as far from φ_op as the bounds
/// allow; other variables keep their reference values. None without a tuning variable.
fn physics_seed(ctx: &Context<'_>, reference: &[f64], phi_op: f64) -> Result<Option<Vec<f64>>, DesignError> {
    let tuning: Vec<usize> = (0..ctx.spec.variables.len())
        .filter(|&j| matches!(ctx.spec.variables[j].parameter, Parameter::TuningFrequency | Parameter::Inductance))
        .collect();
    if tuning.is_empty() {
        return Ok(None);
    }
    let rotor = crate::analysis::Rotor::new(&ctx.base.model)?;
    let mut whirls = Vec::new();
    for &w in &ctx.spec.speeds {
        let m = crate::analysis::modes::whirl_modes_of(&rotor, &ctx.base.settings, w)?;
        for tag in ["f1", "b1"] {
            if let Some(x) = m.modes.iter().find(|x| x.tag() == tag) {
                whirls.push(x.frequency);
            }
        }
    }
    let mut u = to_unit(ctx.spec, reference);
    for &j in &tuning {
        let v: &Variable = &ctx.spec.variables[j];
        // ω_e as a function of the scaled variable (L through Eq. 4 with the branch's C_f).
        let support = &ctx.base.model.rings[v.ring.unwrap_or(0)];
        let (c_f, cp_t) = (support.circuit.branches[v.branch].c_f, support.ring.cp_t);
        let omega = |x: f64| match v.parameter {
            Parameter::TuningFrequency => v.from_unit(x),
            _ => crate::model::Branch::frequency_of(cp_t, c_f, v.from_unit(x)),
        };
        let distance = |x: f64| whirls.iter().map(|w| (w + omega(x) - phi_op).abs()).fold(f64::INFINITY, f64::min);
        let best = (0..=200).map(|k| k as f64 / 200.0).max_by(|a, b| distance(*a).total_cmp(&distance(*b)));
        u[j] = best.unwrap_or(u[j]);
    }
    Ok(Some(u))
}

/// The widest-band run around φ_op (rad/s): fills the starts, the history, the tuned
/// values and [`Findings::WidestBand`].
pub(crate) fn widest_band(ctx: &Context<'_>, out: &mut DesignOutcome, phi_op: f64) -> Result<(), DesignError> {
    let spec = ctx.spec;
    let n = spec.variables.len();
    let reference = to_unit(spec, &out.before);
    let mut starts: Vec<(String, Vec<f64>)> = vec![("reference".into(), reference.clone())];
    if let Some(seed) = physics_seed(ctx, &out.before, phi_op)? {
        starts.push(("physics seed".into(), seed));
    }
    // The map over the whole box, when the starts leave room for its basins: the starts
    // not taken by the reference and the physics seed (with more than three variables,
    // one more per variable beyond three) begin from its best distinct basins.
    starts.truncate(spec.starts.max(1));
    let room = spec.starts.max(1) - starts.len();
    if room > 0 && !spec.map {
        starts.extend((0..room).map(|k| (format!("halton {}", k + 1), halton(k, n))));
    } else if room > 0 {
        let want = room + map::extra_starts(n);
        let scaled = map::points(map::map_points(n), n);
        let values: Vec<f64> = scaled.par_iter().map(|u| ctx.band_objective(u, phi_op)).collect();
        stopped(ctx.progress)?;
        let objective: Vec<Option<f64>> = values.iter().map(|&v| (v > -FAILED_COST).then_some(v)).collect();
        let chosen = map::basins(&scaled, &objective, want);
        for (r, &i) in chosen.iter().enumerate() {
            starts.push((format!("map basin {}", r + 1), scaled[i].clone()));
        }
        out.map = Some(ObjectiveMap {
            objective: "band width around φ_op as the widest-band objective judges it, rad/s".into(),
            maximise: true,
            points: scaled
                .iter()
                .zip(&objective)
                .map(|(u, &v)| MapPoint { values: ctx.values(u), objective: v })
                .collect(),
            basins: chosen,
            slices: Vec::new(),
        });
    }
    // The caller's starts, and the tuned design of a round on a smaller basis.
    starts.extend(ctx.extra_starts.iter().cloned());
    // Starts in parallel (the outermost loop); each Nelder–Mead run is sequential.
    let runs: Vec<Result<StartRun, DesignError>> = starts
        .par_iter()
        .enumerate()
        .map(|(i, (origin, u0))| {
            let cost = BandCost { ctx, phi_op, start: i, history: RefCell::new(Vec::new()) };
            let solver = NelderMead::new(initial_simplex(u0))
                .with_sd_tolerance(OBJECTIVE_TOLERANCE)
                .map_err(|e| DesignError::Optimiser(e.to_string()))?;
            let res = Executor::new(cost, solver)
                .configure(|s| s.max_iters(spec.max_iterations as u64))
                .run()
                .map_err(|e| DesignError::Optimiser(e.to_string()))?;
            let state = res.state();
            let best_u: Vec<f64> = state
                .get_best_param()
                .cloned()
                .unwrap_or_else(|| u0.clone())
                .iter()
                .map(|x| x.clamp(0.0, 1.0))
                .collect();
            let history = res.problem.problem.as_ref().map(|c| c.history.borrow().clone()).unwrap_or_default();
            let report = StartReport {
                origin: origin.clone(),
                initial: ctx.values(u0),
                best: ctx.values(&best_u),
                objective: -state.get_best_cost(),
                evaluations: history.len(),
                iterations: state.get_iter(),
                termination: state.get_termination_reason().map_or("none".into(), |r| r.to_string()),
            };
            Ok((report, history, best_u))
        })
        .collect();
    let mut finals = Vec::new();
    for r in runs {
        let (report, history, u) = r?;
        finals.push(u);
        out.history.extend(history);
        out.starts.push(report);
    }
    let (before_value, before) = ctx.judged(&ctx.reference, phi_op)?;
    // The widest band over the starts' best points, by the same band function, margin
    // penalty and tolerance corners as the objective (ties: the earlier start).
    let banded: Vec<Result<(f64, Vec<OperatingBand>), DesignError>> =
        finals.par_iter().map(|u| ctx.judged(&Candidate::new(ctx.base, spec, &ctx.values(u))?, phi_op)).collect();
    let mut best: Option<(f64, usize, Vec<OperatingBand>)> = None;
    ctx.best.offer(Rank(0, -before_value, 0.0), &out.before, ctx.progress);
    for (k, b) in banded.into_iter().enumerate() {
        let (w, b) = b?;
        ctx.best.offer(Rank(0, -w, 0.0), &ctx.values(&finals[k]), ctx.progress);
        if best.as_ref().is_none_or(|x| w > x.0) {
            best = Some((w, k, b));
        }
    }
    let after = match best {
        Some((w, k, bands)) if w > before_value => {
            out.status = Status::Improved;
            out.after = ctx.values(&finals[k]);
            bands
        }
        _ => {
            out.status = Status::Unchanged;
            out.after = out.before.clone();
            before.clone()
        }
    };
    // A design that leaves φ_op inside a tongue at some speed has no band to widen: no
    // design in the box was found that makes φ_op stable there.
    if after.iter().any(|b| b.band.band.is_none()) {
        out.status = Status::Infeasible;
    }
    out.findings = Findings::WidestBand { before, after };
    let objective = |u: &[f64]| ctx.candidate(u).and_then(|c| Ok(ctx.judged(&c, phi_op)?.0)).ok();
    fill_slices(ctx, out, &|u| objective(u).filter(|v| *v > -FAILED_COST))
}
