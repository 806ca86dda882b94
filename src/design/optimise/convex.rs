//! Clear bands: a global pass, then sequential convex programming (clarabel) on the
//! linearised edges and onsets of the intruding tongues.

use super::*;

/// Central-difference step of the constraint gradients in scaled units (1 % of a range).
const GRADIENT_STEP: f64 = 0.01;
/// Initial and largest trust region of the convex steps (scaled units).
const TRUST_START: f64 = 0.25;
const TRUST_MAX: f64 = 0.5;
/// A trust region below this means no further progress is possible.
const TRUST_MIN: f64 = 1e-3;
/// Extra margin asked of each linearised constraint (rad/s, β for onsets): the edges are
/// resolved to 0.2 rad/s, so a constraint met exactly could be violated by that much.
const MARGIN_PHI: f64 = 0.5;
const MARGIN_BETA: f64 = 2e-3;
/// How far (rad/s) beyond its own half-width an unlabelled sliver is looked for after a
/// gradient step: a 1 % step moves a region by a few rad/s.
const UNLABELLED_SEARCH: f64 = 10.0;
/// Slack price of the elastic step (per unit of violation): far above any change cost.
const ELASTIC_WEIGHT: f64 = 1.0e3;
/// A convex step smaller than this (scaled units) ends the run.
const STEP_MIN: f64 = 1e-4;
/// The termination of a clear-bands global pass point in the starts' table: a point of
/// the map, judged once, not the start of a local search.
pub const GLOBAL_PASS: &str = "global pass";
/// Points of the clear-bands global pass per configured start.
const GLOBAL_POINTS_PER_START: usize = 4;

/// (onset bound, left, right) of an intrusion's tongue in a nearby candidate.
fn intrusion_quantities(ctx: &Context<'_>, c: &Candidate, it: &Intrusion) -> Result<Option<OnsetEdges>, DesignError> {
    follow(c, &ctx.eval(), it, UNLABELLED_SEARCH)
}

fn total(ints: &[Intrusion]) -> f64 {
    ints.iter().map(Intrusion::violation).sum()
}

/// The intrusions of the candidate at `u` (scaled) as built: the nominal and, with
/// `[design.tolerances]`, every corner.
fn as_built_intrusions(ctx: &Context<'_>, u: &[f64]) -> Result<Vec<Intrusion>, DesignError> {
    intrusions_as_built(&ctx.candidate(u)?, &ctx.eval())
}

/// [`as_built_intrusions`], offered to the best design so far.
fn evaluate_bands(ctx: &Context<'_>, u: &[f64]) -> Result<Vec<Intrusion>, DesignError> {
    let ints = as_built_intrusions(ctx, u)?;
    ctx.best.offer(Rank(0, total(&ints), 0.0), &ctx.values(u), ctx.progress);
    Ok(ints)
}

/// Squared distance in scaled units (the QP's weights are all 1).
fn change(u: &[f64], r: &[f64]) -> f64 {
    u.iter().zip(r).map(|(a, b)| (a - b) * (a - b)).sum()
}

/// One sequential-convex run from `u0` toward the least change from `reference`.
struct ConvexRun {
    u: Vec<f64>,
    intrusions: Vec<Intrusion>,
    steps: Vec<ConvexStep>,
    /// The linearised constraints had no solution anywhere inside the bounds.
    linear_infeasible: bool,
}

/// The linearised constraints of the current intrusions and neighbours (module docs).
pub(super) fn linearise(ctx: &Context<'_>, u: &[f64], ints: &[Intrusion]) -> Result<Vec<Linear>, DesignError> {
    let spec = ctx.spec;
    let n = u.len();
    // Central differences (one-sided at a bound); the perturbed candidates in parallel.
    let probes: Vec<(usize, f64)> = (0..n).flat_map(|j| [(j, GRADIENT_STEP), (j, -GRADIENT_STEP)]).collect();
    let probed: Vec<Result<Vec<Option<OnsetEdges>>, DesignError>> = probes
        .par_iter()
        .map(|&(j, h)| {
            let mut p = u.to_vec();
            p[j] = (p[j] + h).clamp(0.0, 1.0);
            let c = ctx.candidate(&p)?;
            // Each build the intrusions were found on (`[design.tolerances]`), built once.
            let mut builds: Vec<(Option<&str>, Candidate)> = Vec::new();
            for name in ints.iter().map(|it| it.build.as_deref()) {
                if name.is_some() && !builds.iter().any(|(n, _)| *n == name) {
                    if let Some(b) = as_build(&c, spec, name)? {
                        builds.push((name, b));
                    }
                }
            }
            ints.iter()
                .map(|it| {
                    let on = builds.iter().find(|(n, _)| *n == it.build.as_deref()).map_or(&c, |(_, b)| b);
                    intrusion_quantities(ctx, on, it)
                })
                .collect()
        })
        .collect();
    let probed = probed.into_iter().collect::<Result<Vec<_>, _>>()?;
    let mut constraints = Vec::new();
    for (i, it) in ints.iter().enumerate() {
        let mut grad = [vec![0.0; n], vec![0.0; n], vec![0.0; n]]; // onset, left, right
        for j in 0..n {
            let (up, dn) = (&probed[2 * j][i], &probed[2 * j + 1][i]);
            let span = (u[j] + GRADIENT_STEP).min(1.0) - (u[j] - GRADIENT_STEP).max(0.0);
            if let (Some(a), Some(b)) = (up, dn) {
                grad[0][j] = (a.0 - b.0) / span;
                grad[1][j] = (a.1 - b.1) / span;
                grad[2][j] = (a.2 - b.2) / span;
            }
        }
        let g = spec.kept_clear()[it.band].guarded();
        let below = Linear { g: grad[2].clone(), h: g.lo - MARGIN_PHI - it.right };
        let above = Linear { g: grad[1].iter().map(|x| -x).collect(), h: it.left - g.hi - MARGIN_PHI };
        let lifted = Linear { g: grad[0].iter().map(|x| -x).collect(), h: it.onset - spec.level - MARGIN_BETA };
        if !it.inside {
            // A neighbour keeps its side.
            constraints.push(if it.right <= g.lo { below } else { above });
            continue;
        }
        // Three ways out: below the band, above it, or onset above β_op; take the one the
        // linearisation says is the shortest move.
        let cost = |c: &Linear| {
            let norm = c.g.iter().map(|x| x * x).sum::<f64>().sqrt();
            if norm > 0.0 {
                (-c.h).max(0.0) / norm
            } else {
                f64::INFINITY
            }
        };
        let options = [below, above, lifted];
        if let Some(best) = options.into_iter().min_by(|a, b| cost(a).total_cmp(&cost(b))) {
            if cost(&best).is_finite() {
                constraints.push(best);
            }
        }
    }
    Ok(constraints)
}

fn convex_run(ctx: &Context<'_>, u0: &[f64], reference: &[f64]) -> Result<ConvexRun, DesignError> {
    let spec = ctx.spec;
    let n = u0.len();
    let mut u = u0.to_vec();
    let mut ints = evaluate_bands(ctx, &u)?;
    let mut merit = total(&ints);
    let mut trust = TRUST_START;
    let mut steps = Vec::new();
    let mut linear_infeasible = false;
    let weights = vec![1.0; n];
    for iteration in 1..=spec.max_iterations {
        let constraints = linearise(ctx, &u, &ints)?;
        let problem =
            |trust: f64| StepProblem { current: &u, reference, weights: &weights, constraints: &constraints, trust };
        // A step problem clarabel neither solves nor proves infeasible gives no step to
        // trust ([`qp::solve`]'s error): the steps end, and the design is judged as it
        // stands, by the true model (issue 50, item 5).
        let Ok(solved) = qp::solve(&problem(trust), None) else { break };
        let (step, qp_status) = match solved.step {
            Step::Solved(d) => (d, solved.status),
            Step::Infeasible => {
                let linear = qp::solve(&problem(1.0), None);
                linear_infeasible = linear.is_ok_and(|s| s.step == Step::Infeasible);
                match qp::solve(&problem(trust), Some(ELASTIC_WEIGHT)) {
                    Ok(Solved { step: Step::Solved(d), status }) => (d, status),
                    _ => break,
                }
            }
        };
        let size = step.iter().fold(0.0f64, |m, d| m.max(d.abs()));
        if size < STEP_MIN {
            break;
        }
        let trial: Vec<f64> = u.iter().zip(&step).map(|(a, d)| (a + d).clamp(0.0, 1.0)).collect();
        let trial_ints = evaluate_bands(ctx, &trial)?;
        let trial_merit = total(&trial_ints);
        // Accept a smaller intrusion, or, once clear, a smaller change that stays clear.
        let accepted = trial_merit < merit
            || (trial_merit == 0.0 && merit == 0.0 && change(&trial, reference) < change(&u, reference));
        steps.push(ConvexStep {
            iteration,
            trust,
            constraints: constraints.len(),
            intrusion_before: merit,
            intrusion_after: Some(trial_merit),
            accepted,
            values: ctx.values(&trial),
            qp_status,
        });
        if accepted {
            u = trial;
            ints = trial_ints;
            merit = trial_merit;
            trust = (2.0 * trust).min(TRUST_MAX);
        } else {
            trust /= 2.0;
            if trust < TRUST_MIN {
                break;
            }
        }
    }
    Ok(ConvexRun { u, intrusions: ints, steps, linear_infeasible })
}

pub(crate) fn clear_bands(ctx: &Context<'_>, out: &mut DesignOutcome) -> Result<(), DesignError> {
    let spec = ctx.spec;
    let n = spec.variables.len();
    let reference = to_unit(spec, &out.before);
    // A coarse global pass: the landscape is disjunctive (a region can leave a band on
    // either side, or pass through a neighbouring band), so the local convex steps from
    // the reference alone can stall. Halton points, in parallel.
    // Its points are the map of the box (`map::points`, the Halton set), drawn in the report.
    let mut points: Vec<(String, Vec<f64>)> = vec![("reference".into(), reference.clone())];
    let scaled = map::points(GLOBAL_POINTS_PER_START * spec.starts, n);
    points.extend(scaled.iter().enumerate().map(|(k, u)| (format!("halton {}", k + 1), u.clone())));
    let merits: Vec<Result<(f64, Vec<Intrusion>), DesignError>> = points
        .par_iter()
        .map(|(_, u)| {
            let ints = evaluate_bands(ctx, u)?;
            Ok((total(&ints), ints))
        })
        .collect();
    let mut scored = Vec::new();
    let mut before = Vec::new();
    for ((origin, u), m) in points.iter().zip(merits) {
        let (merit, ints) = m?;
        if origin == "reference" {
            before = ints.into_iter().filter(|i| i.inside).collect();
        }
        out.starts.push(StartReport {
            origin: origin.clone(),
            initial: ctx.values(u),
            best: ctx.values(u),
            objective: -merit,
            evaluations: 1,
            iterations: 0,
            termination: GLOBAL_PASS.into(),
        });
        scored.push((merit, change(u, &reference), u.clone()));
    }
    // Convex runs from the reference and from the best global point (least intrusion,
    // then least change).
    let mut seeds = vec![reference.clone()];
    let best = (1..scored.len())
        .min_by(|&a, &b| scored[a].0.total_cmp(&scored[b].0).then(scored[a].1.total_cmp(&scored[b].1)));
    if let Some(i) = best {
        seeds.push(scored[i].2.clone());
    }
    out.map = Some(ObjectiveMap {
        objective: match &spec.tolerances {
            Some(t) => format!("total intrusion into the widened bands at β_op, over the design and the corners of its tolerance box ({}), rad/s", t.text()),
            None => "total intrusion into the widened bands at β_op, rad/s".into(),
        },
        maximise: false,
        points: scored[1..].iter().map(|(merit, _, u)| MapPoint { values: ctx.values(u), objective: Some(*merit) }).collect(),
        basins: best.map(|i| vec![i - 1]).unwrap_or_default(),
        slices: Vec::new(),
    });
    // The run from the reference always exists; a later run replaces it when better.
    let (first, rest) = seeds.split_first().ok_or(DesignError::Qp("no convex start".into()))?;
    let mut best_run = convex_run(ctx, first, &reference)?;
    record(ctx, out, 0, &best_run);
    for (k, u0) in rest.iter().enumerate() {
        let run = convex_run(ctx, u0, &reference)?;
        record(ctx, out, k + 1, &run);
        let (m0, m1) = (total(&best_run.intrusions), total(&run.intrusions));
        if m1 < m0 || (m1 == m0 && change(&run.u, &reference) < change(&best_run.u, &reference)) {
            best_run = run;
        }
    }
    out.after = ctx.values(&best_run.u);
    let after: Vec<Intrusion> = best_run.intrusions.into_iter().filter(|i| i.inside).collect();
    out.status = if after.is_empty() { Status::Feasible } else { Status::Infeasible };
    out.findings = Findings::ClearBands { before, after, linear_infeasible: best_run.linear_infeasible };
    fill_slices(ctx, out, &|u| as_built_intrusions(ctx, u).ok().map(|i| total(&i)))
}

/// A convex run's history and steps, as start `k`.
/// Each entry goes to the caller's observer as it is recorded.
fn record(ctx: &Context<'_>, out: &mut DesignOutcome, k: usize, run: &ConvexRun) {
    let merit = total(&run.intrusions);
    let mut push = |point: HistoryPoint| {
        out.history.push(point);
        ctx.observe(point, &[]);
    };
    push(HistoryPoint { start: k, step: 0, value: merit, best: merit });
    for (i, s) in run.steps.iter().enumerate() {
        let value = s.intrusion_after.unwrap_or(s.intrusion_before);
        push(HistoryPoint { start: k, step: i + 1, value, best: value.min(s.intrusion_before) });
    }
    out.convex_steps.extend(run.steps.iter().cloned());
}
