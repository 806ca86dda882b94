//! `rotorshunt design FILE --out DIR`: run the `[design]` of a problem file and write the
//! tuned-parameter report (report.md, report.json), the tuned problem (tuned.toml) and
//! plots (charts before/after with the operating bands, Campbell diagram, history).

use super::bounds::{self, Names};
use super::{title, OutDir};
use crate::analysis::campbell::campbell;
use crate::analysis::chart::chart;
use crate::analysis::cost::{self, Budget, CatalogueWork, Dense, Driver, Estimate, PointCost, DESIGN_BAND_EVALUATIONS};
use crate::analysis::Interval;
use crate::commands::out::json_pretty;
use crate::design::evaluate::Candidate;
use crate::design::evaluate::{neighbourhood, values_of};
use crate::design::spec::{DesignSpec, Objective};
use crate::design::verify::{GRID_STEP, MAX_GRID_POINTS, NEAR};
use crate::design::{self, DesignError, DesignOutcome, Status};
use crate::problem::Problem;
use crate::progress::Progress;
use crate::report::campbell::campbell_plot;
use crate::report::chart::{Layer, StabilityPlot};
use crate::report::design::{markdown, BranchRow, DesignReport};
use crate::report::plot::{LinePlot, Series};
use crate::report::unbalance::{BodeLayer, BodePlot};
use crate::Error;
use std::path::Path;

/// Whirls tracked in the tuned design's Campbell diagram.
const CAMPBELL_WHIRLS: usize = 6;
/// Grid of the before/after charts: φ points and β points.
const CHART_GRID: (usize, usize) = (400, 31);
/// Speeds of the tuned design's Campbell diagram (0 to 1.5 × the largest operating speed).
const CAMPBELL_SPEEDS: usize = 31;

/// Every ring's circuit, branch by branch: one table of the shared circuit when two or
/// more rings carry an identical one (tuning by the first ring's C_p^T, as `check` prints
/// it), else each ring's branches under its name.
fn branches(p: &Problem) -> Vec<BranchRow> {
    let shared = !p.model.labels_by_ring();
    let rings = if shared { &p.model.rings[..1.min(p.model.rings.len())] } else { &p.model.rings[..] };
    rings
        .iter()
        .flat_map(|r| {
            r.circuit.branches.iter().enumerate().map(move |(i, b)| BranchRow {
                ring: (!shared).then(|| r.name.clone()),
                branch: i + 1,
                c_f: b.c_f,
                inductance: b.inductance,
                resistance: b.resistance,
                tuning_frequency: b.tuning_frequency(r.ring.cp_t),
            })
        })
        .collect()
}

/// The φ window of the charts: around φ_op or the bands, inside the design's range.
fn chart_window(spec: &DesignSpec) -> (f64, f64) {
    let (lo, hi) = match spec.objective {
        Objective::WidestStableBand { .. } => {
            let p = spec.objective.phi_op().unwrap_or(spec.phi_range.0);
            (p * 0.5, p * 1.5)
        }
        Objective::ClearBands { .. } => band_window(spec.kept_clear()),
        // The bands kept clear, else φ_op's, else the whole range.
        Objective::MinPeakResponse { .. } => match spec.phi_op() {
            _ if !spec.kept_clear().is_empty() => band_window(spec.kept_clear()),
            Some(p) => (p * 0.5, p * 1.5),
            None => spec.phi_range,
        },
    };
    (lo.max(spec.phi_range.0), hi.min(spec.phi_range.1))
}

/// The window around operating bands: their widened span and a quarter of it each side.
fn band_window(bands: &[crate::design::spec::Band]) -> (f64, f64) {
    let lo = bands.iter().map(|b| b.guarded().lo).fold(f64::INFINITY, f64::min);
    let hi = bands.iter().map(|b| b.guarded().hi).fold(0.0, f64::max);
    (lo - 0.25 * (hi - lo), hi + 0.25 * (hi - lo))
}

/// The before/after charts at each speed; a step of `progress` per φ row and per file.
fn charts(
    dir: &OutDir,
    before: &Candidate,
    after: &Candidate,
    spec: &DesignSpec,
    progress: &dyn Progress,
) -> Result<(), Error> {
    let (lo, hi) = chart_window(spec);
    let phis: Vec<f64> = (0..CHART_GRID.0).map(|i| lo + (hi - lo) * i as f64 / (CHART_GRID.0 - 1) as f64).collect();
    let top = spec.beta_max.min(2.0 * spec.level).max(spec.level);
    let betas: Vec<f64> = (0..CHART_GRID.1).map(|i| top * i as f64 / (CHART_GRID.1 - 1) as f64).collect();
    let mut markers = Vec::new();
    if let Some(p) = spec.phi_op() {
        markers.push((p, "φ_op".to_string()));
    }
    for (i, b) in spec.kept_clear().iter().enumerate() {
        markers.push((b.lo, format!("band {} lo", i + 1)));
        markers.push((b.hi, format!("band {} hi", i + 1)));
    }
    for (k, &w) in spec.speeds.iter().enumerate() {
        let mut layers = Vec::new();
        for (name, c, color) in [("reference circuit", before, (31, 119, 180)), ("tuned circuit", after, (214, 39, 40))]
        {
            let fs = &c.systems[k].1;
            layers.push(Layer { name: name.into(), color, chart: chart(fs, &phis, &betas, progress) });
        }
        // The operating level as a horizontal line.
        let level = Series {
            name: format!("β_op = {}", spec.level),
            color: (0, 0, 0),
            dashed: true,
            points: vec![(lo, spec.level), (hi, spec.level)],
        };
        let plot = StabilityPlot::new(&format!("Stability before and after the design, Ω = {w} rad/s"), layers)
            .with_markers(markers.clone())
            .with_lines(vec![level]);
        let name = if spec.speeds.len() == 1 { "charts".to_string() } else { format!("charts-{}", k + 1) };
        dir.write(&format!("{name}.svg"), plot.svg().map_err(|e| dir.error("charts.svg", e))?.as_bytes())?;
        progress.advance(1);
        dir.write(&format!("{name}.png"), &plot.png().map_err(|e| dir.error("charts.png", e))?)?;
        progress.advance(1);
    }
    Ok(())
}

fn history_plot(o: &DesignOutcome) -> LinePlot {
    let colors = [(31, 119, 180), (214, 39, 40), (44, 160, 44), (148, 103, 189), (255, 127, 14), (23, 190, 207)];
    let starts = o.history.iter().map(|h| h.start).max().map_or(0, |m| m + 1);
    let series: Vec<Series> = (0..starts)
        .map(|k| Series {
            name: match o.spec.objective {
                Objective::WidestStableBand { .. } => {
                    o.starts.get(k).map_or(format!("start {k}"), |s| s.origin.clone())
                }
                Objective::ClearBands { .. } => {
                    if k == 0 {
                        "from the reference".into()
                    } else {
                        "from the best global point".into()
                    }
                }
                Objective::MinPeakResponse { .. } => o.starts.get(k).map_or(format!("start {k}"), |s| s.origin.clone()),
            },
            color: colors[k % colors.len()],
            dashed: false,
            points: o.history.iter().filter(|h| h.start == k).map(|h| (h.step as f64, h.best)).collect(),
        })
        .collect();
    let ys: Vec<f64> = series.iter().flat_map(|s| s.points.iter().map(|p| p.1)).filter(|y| y.abs() < 1e8).collect();
    let (y0, y1) = ys.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &y| (a.min(y), b.max(y)));
    let (y0, y1) = if y0.is_finite() && y1 > y0 { (y0, y1) } else { (y0.min(0.0) - 1.0, y1.max(0.0) + 1.0) };
    let x1 = series.iter().flat_map(|s| s.points.iter().map(|p| p.0)).fold(1.0, f64::max);
    LinePlot {
        title: "Optimiser history (best so far)".into(),
        x_label: match o.spec.objective {
            Objective::WidestStableBand { .. } => "candidate evaluations of the start".into(),
            Objective::ClearBands { .. } => "convex step".into(),
            Objective::MinPeakResponse { .. } => "candidate evaluations of the start".into(),
        },
        y_label: match o.spec.objective {
            Objective::WidestStableBand { .. } => "smallest band width over the speeds (rad/s)".into(),
            Objective::ClearBands { .. } => "total intrusion into the bands (rad/s)".into(),
            Objective::MinPeakResponse { .. } => "peak response, with the constraints' penalty (m)".into(),
        },
        x_range: (0.0, x1),
        y_range: (y0 - 0.05 * (y1 - y0), y1 + 0.05 * (y1 - y0)),
        series: series.into_iter().filter(|s| !s.points.is_empty()).collect(),
    }
}

/// The name of the design file written: `tuned.toml` for a result that can be handed on,
/// `best-effort.toml` for an infeasible or unverified one.
pub fn design_file_name(status: Status) -> &'static str {
    if status.is_result() {
        "tuned.toml"
    } else {
        "best-effort.toml"
    }
}

/// The status as a word (kebab-case, as in report.json).
pub fn status_word(status: Status) -> String {
    serde_json::to_value(status).ok().and_then(|v| v.as_str().map(str::to_string)).unwrap_or_default()
}

/// The names of a design's inputs in a refusal.
pub(crate) const DESIGN: Names<'static> = Names {
    phi: "`design.phi_range`",
    grid: "`design.phi_range` or `design.bands`",
    load: "`design.level` or `design.beta_max`",
    periods: "the design",
};

/// The estimated cost of `problem`'s design, from its reference candidate (its rotor and
/// reduced systems are built: bounded by the dense estimate, checked first): every
/// candidate's dense stages and band (or operating-band) search at every speed, and the
/// verification with the report (two catalogues per speed, the grids, the DSTM points at
/// tongue centres, the before/after charts and the Campbell diagram).
pub(crate) fn design_estimate(problem: &Problem, spec: &DesignSpec, budget: &Budget) -> Result<Estimate, Error> {
    let threads = rayon::current_num_threads();
    let speeds = spec.speeds.len() as f64;
    let model = &problem.model;
    let dense = cost::dense(model, Dense::Reduced, 1);
    let verify_dense = cost::dense(model, Dense::ReducedAndWhirls, 1);
    let mut memory = dense.memory.clone();
    memory.amount = (memory.amount * threads as f64).max(verify_dense.memory.amount);
    let admitted = Estimate { time: dense.time.clone(), memory: memory.clone() };
    bounds::admit(budget, "the design", &admitted, &DESIGN)?;
    let reference = Candidate::new(problem, spec, &values_of(problem, spec))?;
    let s = problem.regions.clone();
    let criterion = reference.criterion();
    let mut per_candidate = Estimate::time(dense.time.amount * speeds, Driver::Dofs, dense.time.detail.clone());
    let mut verification = Estimate::zero();
    for (k, (_, fs)) in reference.systems.iter().enumerate() {
        let pc = PointCost::of(fs);
        let seeds = reference.seeds(k, spec)?;
        let range = spec.range();
        let work = match spec.objective {
            Objective::WidestStableBand { .. } => {
                let phi_op = spec.objective.phi_op().unwrap_or(range.lo);
                cost::points(&pc, DESIGN_BAND_EVALUATIONS, (0.5 * phi_op).max(range.lo), spec.level)
            }
            Objective::ClearBands { .. } | Objective::MinPeakResponse { .. } => {
                let windows: Vec<Interval> =
                    spec.kept_clear().iter().map(|b| neighbourhood(b).clipped(&range)).collect();
                let mut work = cost::scan(&pc, &s, &criterion, &seeds, &windows, spec.level);
                if let Some(b) = spec.constraints.min_band_width {
                    let band = cost::points(&pc, DESIGN_BAND_EVALUATIONS, (0.5 * b.phi_op).max(range.lo), spec.level);
                    work = work.then(band);
                }
                work
            }
        };
        per_candidate = per_candidate.then(work);
        let catalogue = CatalogueWork { range, beta_max: spec.beta_max, level: spec.level, track: false };
        let cat = cost::catalogue(&pc, &s, &criterion, &seeds, &catalogue);
        // The windows checked: the band, taken as the charts' window around φ_op (half to
        // 1.5 times it), or each widened operating band.
        let windows: Vec<Interval> = match spec.objective {
            Objective::WidestStableBand { .. } => {
                let (lo, hi) = chart_window(spec);
                vec![Interval::new(lo, hi)]
            }
            Objective::ClearBands { .. } | Objective::MinPeakResponse { .. } => {
                let mut w: Vec<Interval> = spec.kept_clear().iter().map(|b| b.guarded().clipped(&range)).collect();
                if spec.constraints.min_band_width.is_some() {
                    let (lo, hi) = chart_window(spec);
                    w.push(Interval::new(lo, hi));
                }
                w
            }
        };
        let mut grids = Estimate::zero();
        for w in &windows {
            let n = (w.width() / GRID_STEP).min(MAX_GRID_POINTS as f64);
            grids = grids.then(cost::points(&pc, n, w.lo, spec.level));
            let near = Interval::new(w.lo * (1.0 - NEAR), w.hi * (1.0 + NEAR));
            let centres = seeds.iter().filter(|x| near.contains(x.phi)).count() as f64;
            grids = grids.then(Estimate::time(
                centres * pc.dstm(),
                Driver::Settings,
                "DSTM points at tongue centres".into(),
            ));
        }
        let (lo, hi) = chart_window(spec);
        let phis: Vec<f64> = (0..CHART_GRID.0).map(|i| lo + (hi - lo) * i as f64 / (CHART_GRID.0 - 1) as f64).collect();
        let top = spec.beta_max.min(2.0 * spec.level).max(spec.level);
        let betas: Vec<f64> = (0..CHART_GRID.1).map(|i| top * i as f64 / (CHART_GRID.1 - 1) as f64).collect();
        let charts = cost::chart(&pc, &phis, &betas).times(2.0, Driver::Grid, "charts");
        verification = verification.then(cat.times(2.0, Driver::Grid, "catalogues")).then(grids).then(charts);
    }
    // The whirls: the physics seed's and the catalogues' at each speed, and the Campbell
    // diagram's speeds.
    let whirls = cost::dense(model, Dense::Whirls(CAMPBELL_SPEEDS + 3 * spec.speeds.len()), threads);
    let total = per_candidate
        .times(design::optimise::most_candidates(spec) as f64, Driver::Candidates, "candidates")
        .then(verification)
        .then(whirls);
    Ok(Estimate { memory: if memory.amount > total.memory.amount { memory } else { total.memory.clone() }, ..total })
}

/// `rotorshunt design FILE --out DIR`: the summary text and the outcome (whose status
/// decides the exit code). Refused before any folder is made when its estimate is beyond
/// `budget`. Progress: the design's `optimise` and `verification` ([`design::run`]),
/// then `report` (a step per chart row, Campbell speed and file).
pub fn design_cmd(
    problem: &Problem,
    out: &Path,
    progress: &dyn Progress,
    budget: Budget,
) -> Result<(String, DesignOutcome), Error> {
    // No folder is created for a file without a [design] table.
    let spec = problem.design.as_ref().ok_or(Error::Design(DesignError::NoDesign))?;
    bounds::admit(&budget, "the design", &design_estimate(problem, spec, &budget)?, &DESIGN)?;
    let dir = OutDir::create(out, &problem.file)?;
    let outcome = design_report(problem, &dir, progress)?;
    dir.commit("design")?;
    Ok((summary_text(&outcome, out), outcome))
}

/// Run the design and write the report files to `dir`; the outcome.
pub fn design_report(problem: &Problem, dir: &OutDir, progress: &dyn Progress) -> Result<DesignOutcome, Error> {
    let spec = problem.design.as_ref().ok_or(Error::Design(DesignError::NoDesign))?;
    let outcome = design::run(problem, progress)?;
    // Each design's rotor and reduced systems, built once for the charts and Campbell.
    let before = Candidate::new(problem, spec, &outcome.before)?;
    let after = Candidate::new(problem, spec, &outcome.after)?;
    let tuned = &after.problem;
    let chart_files: Vec<String> = if spec.speeds.len() == 1 {
        vec!["charts.svg".into(), "charts.png".into()]
    } else {
        (1..=spec.speeds.len()).flat_map(|k| [format!("charts-{k}.svg"), format!("charts-{k}.png")]).collect()
    };
    let mut files: Vec<String> =
        vec!["report.md".into(), "report.html".into(), "report.json".into(), design_file_name(outcome.status).into()];
    files.extend(chart_files);
    files.extend(["campbell.svg", "campbell.png", "history.svg", "history.png"].iter().map(|s| s.to_string()));
    if outcome.vibration.is_some() {
        files.extend(["bode.svg", "bode.png"].iter().map(|s| s.to_string()));
    }
    let chart_rows = 2 * spec.speeds.len() * CHART_GRID.0;
    progress.phase("report", (chart_rows + CAMPBELL_SPEEDS + files.len()) as u64);
    let report = DesignReport {
        provenance: super::Provenance::of(problem),
        title: title(problem),
        branches_before: branches(problem),
        branches_after: branches(tuned),
        outcome: outcome.clone(),
        files,
    };
    dir.write(design_file_name(outcome.status), super::tuned_toml(problem, &outcome)?.as_bytes())?;
    dir.write("report.json", (json_pretty(&report, "the JSON output")? + "\n").as_bytes())?;
    dir.write("report.md", markdown(&report).as_bytes())?;
    progress.advance(3);
    charts(dir, &before, &after, spec, progress)?;
    let top = spec.speeds.iter().fold(0.0f64, |m, &w| m.max(w)).max(100.0) * 1.5;
    let speeds: Vec<f64> = (0..CAMPBELL_SPEEDS).map(|i| top * i as f64 / (CAMPBELL_SPEEDS - 1) as f64).collect();
    let c = campbell(&after.rotor, &tuned.settings, &speeds, CAMPBELL_WHIRLS, progress)?;
    let plot = campbell_plot(&c, &format!("Campbell diagram, tuned circuit: {}", title(problem)));
    dir.write("campbell.svg", plot.svg().map_err(|e| dir.error("campbell.svg", e))?.as_bytes())?;
    progress.advance(1);
    dir.write("campbell.png", &plot.png().map_err(|e| dir.error("campbell.png", e))?)?;
    progress.advance(1);
    let h = history_plot(&outcome);
    dir.write("history.svg", h.svg().map_err(|e| dir.error("history.svg", e))?.as_bytes())?;
    progress.advance(1);
    dir.write("history.png", &h.png().map_err(|e| dir.error("history.png", e))?)?;
    progress.advance(1);
    if let Some(v) = &outcome.vibration {
        let layers = vec![
            BodeLayer { name: "reference circuit".into(), dashed: false, result: &v.before },
            BodeLayer { name: "tuned circuit".into(), dashed: true, result: &v.after },
        ];
        let plot =
            BodePlot { title: format!("Unbalance response before and after the design: {}", title(problem)), layers };
        dir.write("bode.svg", plot.svg().map_err(|e| dir.error("bode.svg", e))?.as_bytes())?;
        progress.advance(1);
        dir.write("bode.png", &plot.png().map_err(|e| dir.error("bode.png", e))?)?;
        progress.advance(1);
    }
    let page = crate::report::html::page(&report.title, &markdown(&report), dir);
    dir.write("report.html", page.as_bytes())?;
    progress.advance(1);
    Ok(outcome)
}

/// The one-paragraph result on standard output.
pub fn summary_text(o: &DesignOutcome, out: &Path) -> String {
    let spec = &o.spec;
    let values = |v: &[f64]| {
        spec.variables
            .iter()
            .zip(v)
            .map(|(var, x)| format!("{} = {x:.6e} {}", var.name(), var.parameter.unit()))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut s = format!("design: {}", status_word(o.status));
    match spec.objective {
        Objective::WidestStableBand { .. } => {
            let w = |v: &[crate::design::evaluate::OperatingBand]| {
                v.iter()
                    .map(|b| match b.band.band {
                        Some(x) => format!("[{:.2}, {:.2}] ({:.2} rad/s) at Ω = {}", x.lo, x.hi, x.width(), b.speed),
                        None => format!("none (φ_op unstable) at Ω = {}", b.speed),
                    })
                    .collect::<Vec<_>>()
                    .join("; ")
            };
            s += &format!(
                "\nstable band at beta = {} around phi_op = {} rad/s: before {}; after {}",
                spec.level,
                spec.objective.phi_op().map_or_else(|| "?".into(), |p| p.to_string()),
                w(o.before_bands()),
                w(o.after_bands())
            );
            if let Some(b) = o.after_bands().first() {
                s += &format!("\nguarantee: {}", b.band.guarantee);
            }
        }
        Objective::ClearBands { .. } => {
            s += &format!(
                "\nbands: {} tongue(s) inside before, {} after",
                o.before_intrusions().len(),
                o.after_intrusions().len()
            );
            if o.status == Status::Infeasible {
                for it in o.after_intrusions() {
                    let b = &spec.objective.bands()[it.band];
                    s += &format!(
                        "\nviolated: band [{}, {}] (clearance {}) at Ω = {}: {} at [{:.2}, {:.2}] rad/s",
                        b.lo, b.hi, b.clearance, it.speed, it.label, it.left, it.right
                    );
                }
            }
        }
        Objective::MinPeakResponse { .. } => {}
    }
    if let Some(f) = o.peak_findings() {
        let p = |d: &crate::design::optimise::JudgedDesign| {
            format!("{:.4e} m at {:.2} rad/s", d.peak.amplitude, d.peak.speed)
        };
        s += &format!(
            "\npeak response: before {}; after {}; unconstrained optimum {}",
            p(&f.before),
            p(&f.after),
            p(&f.unconstrained)
        );
        if let Some(c) = &f.classic_design {
            s += &format!("; classic tuning {}", p(c));
        }
        if let Some(price) = f.price {
            s += &format!("\nprice of the constraints: {:+.4e} m ({:+.2} %)", price.metres, price.percent);
        }
    }
    for c in &o.constraints_after {
        s += &format!("\nconstraint {}: {:.6e} ({})", c.name, c.value, if c.met { "met" } else { "NOT met" });
    }
    s += &format!("\nverification: {}", if o.verified { "passed" } else { "FAILED" });
    for d in &o.after_speeds {
        for f in &d.failures {
            s += &format!("\n  at Ω = {}: {f}", d.speed);
        }
    }
    s += &format!(
        "\nbefore: {}\nafter: {}\n{} candidates, {} Floquet evaluations, {:.1} s optimising; verification {} evaluations, {:.1} s; wrote report.md, report.html, report.json, {} and plots to {}\n",
        values(&o.before),
        values(&o.after),
        o.candidates,
        o.floquet_evaluations,
        o.seconds,
        o.verification_cost.evaluations,
        o.verification_cost.seconds,
        design_file_name(o.status),
        out.display()
    );
    s
}
