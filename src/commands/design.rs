//! `rotorshunt design FILE --out DIR`: run the `[design]` of a problem file and write the
//! tuned-parameter report (report.md, report.json), the tuned problem (tuned.toml) and
//! plots (charts before/after with the operating bands, Campbell diagram, history).

use super::bounds::{self, Names};
use super::{title, OutDir};
use crate::commands::out::json_pretty;
use crate::commands::Error;
use rotorshunt::analysis::cost::{self, Budget, CatalogueWork, Dense, Driver, Estimate, PointCost};
use rotorshunt::analysis::{Interval, Rotor};
use rotorshunt::design::content::{chart_grid, content, content_steps, CAMPBELL_SPEEDS};
use rotorshunt::design::evaluate::values_of;
use rotorshunt::design::evaluate::Candidate;
use rotorshunt::design::objective::CostAt;
use rotorshunt::design::spec::DesignSpec;
use rotorshunt::design::verify::{GRID_STEP, MAX_GRID_POINTS, NEAR};
use rotorshunt::design::{self, DesignError, DesignOutcome, Status};
use rotorshunt::problem::Problem;
use rotorshunt::progress::Progress;
use rotorshunt::report::design::{self as report_design, branch_rows, markdown, DesignReport};
use std::path::Path;

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
    let admitted = Estimate { memory: memory.clone(), ..dense.clone() };
    bounds::admit(budget, "the design", &admitted, &DESIGN)?;
    let machine = problem.machine();
    let reference = Candidate::new(&machine, spec, &values_of(&machine, spec))?;
    let s = problem.regions.clone();
    let criterion = reference.criterion();
    let mut per_candidate = Estimate::work(dense.work.amount * speeds, Driver::Dofs, dense.work.detail.clone());
    let mut verification = Estimate::zero();
    for (k, (_, fs)) in reference.systems.iter().enumerate() {
        let pc = PointCost::of(fs);
        let seeds = reference.seeds(k, spec)?;
        let range = spec.range();
        let at = CostAt { point: &pc, regions: &s, criterion: &criterion, seeds: &seeds };
        let work = spec.objective.candidate_cost(spec, &at);
        per_candidate = per_candidate.then(work);
        let catalogue = CatalogueWork { range, beta_max: spec.beta_max, level: spec.level, track: false };
        let cat = cost::catalogue(&pc, &s, &criterion, &seeds, &catalogue);
        // The windows checked: the band, taken as the charts' window around φ_op (half to
        // 1.5 times it), or each widened operating band.
        let windows: Vec<Interval> = spec.objective.checked_windows(spec);
        let mut grids = Estimate::zero();
        for w in &windows {
            let n = (w.width() / GRID_STEP).min(MAX_GRID_POINTS as f64);
            grids = grids.then(cost::points(&pc, n, w.lo, spec.level));
            let near = Interval::new(w.lo * (1.0 - NEAR), w.hi * (1.0 + NEAR));
            let centres = seeds.iter().filter(|x| near.contains(x.phi)).count() as f64;
            grids = grids.then(Estimate::work(
                centres * pc.dstm(),
                Driver::Settings,
                "DSTM points at tongue centres".into(),
            ));
        }
        let (phis, betas) = chart_grid(spec);
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
    let estimate = design_estimate(problem, spec, &budget)?;
    bounds::admit(&budget, "the design", &estimate, &DESIGN)?;
    modes_exist(problem, None, spec)?;
    let dir = OutDir::create(out, &problem.file)?;
    let (outcome, _) = design_report(problem, &dir, progress, &budget, &estimate)?;
    dir.commit("design", progress)?;
    Ok((summary_text(&outcome, out), outcome))
}

/// The design of `problem` as `design` runs it (the same checks and admission), without
/// its report: the outcome, for the Python bindings' `design` (its tuned file is
/// [`super::tuned_toml`]). Progress: the design's `optimise` and `verification`.
#[allow(dead_code)] // called by the Python bindings alone
pub fn design_run(problem: &Problem, progress: &dyn Progress, budget: Budget) -> Result<DesignOutcome, Error> {
    let spec = problem.design.as_ref().ok_or(Error::Design(DesignError::NoDesign))?;
    let estimate = design_estimate(problem, spec, &budget)?;
    bounds::admit(&budget, "the design", &estimate, &DESIGN)?;
    modes_exist(problem, None, spec)?;
    let deadline = budget.running(progress, &estimate);
    let outcome = design::run(&problem.machine(), spec, &deadline);
    budget.stopped(&deadline, "the design")?;
    Ok(outcome?)
}

/// The damping constraints' whirl tags against the model ([`design::checks::modes_exist`]),
/// checked once the run is admitted and before its folder is made; a tag the model lacks
/// is refused as the file's error at the tag's line.
pub(crate) fn modes_exist(problem: &Problem, rotor: Option<&Rotor>, spec: &DesignSpec) -> Result<(), Error> {
    if spec.constraints.damping.is_empty() {
        return Ok(());
    }
    let built;
    let rotor = match rotor {
        Some(r) => r,
        None => {
            built = Rotor::new(&problem.model)?;
            &built
        }
    };
    match design::checks::modes_exist(rotor, &problem.settings, spec) {
        Err(DesignError::UnknownMode { index, mode, speed, available }) => Err(problem
            .refuse(
                &format!("design.constraints.damping[{index}].mode"),
                rotorshunt::problem::ProblemErrorKind::UnknownMode { mode, speed, available: available.into() },
            )
            .into()),
        other => Ok(other?),
    }
}

/// Run the design admitted at `estimate` and write the report files to `dir`; the
/// outcome, and the limit that stopped it. A design stopped by `budget`'s time limit, the
/// estimate's allowance of evaluations or `progress` ([`Status::Stopped`]) keeps the best
/// design judged so far: `best-effort.toml` and the report's text, with the stop on page
/// one, and no figures. Its report's charts stopped so are an error, its files left
/// uncommitted.
pub fn design_report(
    problem: &Problem,
    dir: &OutDir,
    progress: &dyn Progress,
    budget: &Budget,
    estimate: &Estimate,
) -> Result<(DesignOutcome, Option<cost::Stopped>), Error> {
    let spec = problem.design.as_ref().ok_or(Error::Design(DesignError::NoDesign))?;
    let machine = problem.machine();
    let deadline = budget.running(progress, estimate);
    let mut outcome = design::run(&machine, spec, &deadline)?;
    if outcome.status == Status::Stopped {
        let stop = budget.stopped(&deadline, "the design").err();
        if let Some(s) = &stop {
            outcome.stop = Some(s.reason());
        }
        let after = rotorshunt::design::evaluate::machine_at(&machine, spec, &outcome.after)?;
        let files = text_files(outcome.status);
        let report = report_of(problem, &after.model, outcome, Vec::new(), files);
        write_texts(problem, dir, &report)?;
        return Ok((report.outcome, stop));
    }
    // Each design's rotor and reduced systems, built once for the charts and Campbell.
    let before = Candidate::new(&machine, spec, &outcome.before)?;
    let after = Candidate::new(&machine, spec, &outcome.after)?;
    // The charts' rows and Campbell speeds, the three text files and report.html; a step
    // per figure once the figures are known.
    progress.phase("report", (content_steps(spec) + 4) as u64);
    // Every band the charts draw: the stable bands found before and after, the operating
    // bands with their clearances.
    let bands: Vec<Interval> = outcome
        .before_bands()
        .iter()
        .chain(outcome.after_bands())
        .filter_map(|b| b.band.band)
        .chain(spec.kept_clear().iter().map(|b| b.guarded()))
        .collect();
    let content = content(spec, &before, &after, &bands, &deadline);
    budget.stopped(&deadline, "the design's report")?;
    let mut content = content?;
    let whirls = std::mem::take(&mut content.whirls);
    let figures = report_design::figures(&outcome, content, &title(problem));
    progress.extend(figures.len() as u64);
    let mut files = text_files(outcome.status);
    files.extend(figures.iter().flat_map(|(stem, _)| [format!("{stem}.svg"), format!("{stem}.png")]));
    let report = report_of(problem, &after.machine.model, outcome.clone(), whirls, files);
    progress.advance(3);
    for (stem, figure) in &figures {
        dir.figure(stem, figure.as_ref())?;
        progress.advance(1);
    }
    write_texts(problem, dir, &report)?;
    progress.advance(1);
    Ok((report.outcome, None))
}

/// The report of `outcome` on `problem`, the tuned circuit that of `after`.
fn report_of(
    problem: &Problem,
    after: &rotorshunt::model::Model,
    outcome: DesignOutcome,
    whirls: Vec<rotorshunt::design::content::SpeedWhirls>,
    files: Vec<String>,
) -> DesignReport {
    DesignReport {
        provenance: super::Provenance::of(problem),
        title: title(problem),
        branches_before: branch_rows(&problem.model),
        branches_after: branch_rows(after),
        outcome,
        whirls,
        files,
    }
}

/// The text files a design writes ([`write_texts`]), the figures aside.
fn text_files(status: Status) -> Vec<String> {
    ["report.md", "report.html", "report.json", design_file_name(status)].map(str::to_string).to_vec()
}

/// The design file (`tuned.toml` or `best-effort.toml`), report.json, report.md and
/// report.html (after the figures it shows).
fn write_texts(problem: &Problem, dir: &OutDir, report: &DesignReport) -> Result<(), Error> {
    let design_file = design_file_name(report.outcome.status);
    dir.write(design_file, super::tuned_toml(problem, &report.outcome)?.as_bytes())?;
    dir.write("report.json", (json_pretty(report, "the JSON output")? + "\n").as_bytes())?;
    let text = markdown(report);
    dir.write("report.md", text.as_bytes())?;
    dir.write("report.html", rotorshunt::report::html::page(&report.title, &text, dir).as_bytes())?;
    Ok(())
}

/// The one-paragraph result on standard output.
pub fn summary_text(o: &DesignOutcome, out: &Path) -> String {
    let spec = &o.spec;
    let values = |v: &[f64]| {
        spec.variables
            .iter()
            .zip(v)
            .map(|(var, x)| format!("{} = {} {}", var.name(), rotorshunt::numbers::sig(*x, 5), var.parameter.unit()))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let at = |w: f64| rotorshunt::report::design::speed_text(spec.speed_unit, w);
    if o.status == Status::Stopped {
        return format!(
            "design: stopped {}\nbefore: {}\nbest so far: {}\nwrote report.md, report.html, report.json and best-effort.toml (the best design judged so far: NOT A RESULT, not verified) to {}\n",
            o.stop.as_deref().unwrap_or("by its caller"),
            values(&o.before),
            values(&o.after),
            out.display()
        );
    }
    let mut s = format!("design: {}", status_word(o.status));
    s += &spec.objective.summary(o);
    if let Some(f) = o.peak_findings() {
        let p = |d: &rotorshunt::design::optimise::JudgedDesign| {
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
        for b in f.baselines.iter().filter(|b| b.design != "tuned") {
            s += &match (b.peak.unbounded, b.amplification_factor) {
                (true, _) => format!(
                    "\nbaseline {}: unbounded at {:.2} rad/s (an undamped critical speed in the range)",
                    b.design, b.peak.speed
                ),
                (false, af) => format!(
                    "\nbaseline {}: {:.4e} m at {:.2} rad/s ({}); tuned {:+.1} %",
                    b.design,
                    b.peak.amplitude,
                    b.peak.speed,
                    af.map_or("no half-power band in the range".to_string(), |a| format!("AF {a:.1}")),
                    100.0 * (f.after.peak.amplitude / b.peak.amplitude - 1.0)
                ),
            };
        }
        if let Some(price) = f.price {
            s += &format!("\nprice of the constraints: {:+.4e} m ({:+.2} %)", price.metres, price.percent);
        }
    }
    for c in &o.constraints_after {
        s += &format!("\nconstraint {}: {:.6e} ({})", c.name, c.value, if c.met { "met" } else { "NOT met" });
    }
    s += &format!("\nverification: {}", o.verification.verdict);
    for p in &o.verification.parts {
        let status = match p.status {
            rotorshunt::design::verify::PartStatus::Passed => continue,
            rotorshunt::design::verify::PartStatus::Failed => "FAILED",
            rotorshunt::design::verify::PartStatus::NotApplicable => "not applicable",
        };
        s += &format!("\n  {} {status}: {}", p.part, p.summary);
    }
    for d in &o.after_speeds {
        for f in &d.failures {
            s += &format!("\n  at {}: {f}", at(d.speed));
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

/// `rotorshunt design FILE --pareto K --out DIR`: the front of the file's trade-off
/// ([`design::pareto::front`]) with its report (report.md, report.html, report.json),
/// the plot of the front (pareto.svg, pareto.png) and every point's design file
/// (`tuned-k.toml`, or `best-effort-k.toml` for a point that is not a verified result).
/// A design without a trade-off is refused at its key and line, before any folder is
/// made. Progress: `front` (the runs' candidates and verification points), `report`.
pub fn pareto_cmd(
    problem: &Problem,
    points: usize,
    out: &Path,
    progress: &dyn Progress,
    budget: Budget,
) -> Result<(String, design::pareto::Front), Error> {
    use rotorshunt::problem::ProblemErrorKind;
    use rotorshunt::report::design::pareto::{front_plot, markdown, point_file, point_line, FrontReport};
    let spec = problem.design.as_ref().ok_or(Error::Design(DesignError::NoDesign))?;
    design::pareto::trade_off(spec).map_err(|e| problem.refuse(&e.key, ProblemErrorKind::NoTradeOff(e.reason)))?;
    // A front is its points' runs, and a point run again when it is dominated.
    let one = design_estimate(problem, spec, &budget)?;
    let runs = (2 * points) as f64;
    let estimate = one.times(runs, Driver::Candidates, "design runs");
    bounds::admit(&budget, "the Pareto front", &estimate, &DESIGN)?;
    modes_exist(problem, None, spec)?;
    let dir = OutDir::create(out, &problem.file)?;
    let deadline = budget.running(progress, &estimate);
    let front = design::pareto::front(&problem.machine(), spec, points, &deadline);
    budget.stopped(&deadline, "the Pareto front")?;
    let front = front?;
    progress.phase("report", (front.points.len() + 4) as u64);
    let design_files: Vec<String> = front.points.iter().map(point_file).collect();
    let mut files: Vec<String> =
        ["report.md", "report.html", "report.json", "pareto.svg", "pareto.png"].iter().map(|s| s.to_string()).collect();
    files.extend(design_files.iter().cloned());
    let report = FrontReport {
        provenance: super::Provenance::of(problem),
        title: title(problem),
        branches_before: branch_rows(&problem.model),
        variables: spec.variables.iter().map(|v| format!("{} ({})", v.name(), v.parameter.unit())).collect(),
        front,
        design_files,
        files,
    };
    for (p, file) in report.front.points.iter().zip(&report.design_files) {
        dir.write(file, super::tuned_toml(problem, &p.outcome)?.as_bytes())?;
        progress.advance(1);
    }
    dir.write("report.json", (json_pretty(&report, "the JSON output")? + "\n").as_bytes())?;
    let text = markdown(&report);
    dir.write("report.md", text.as_bytes())?;
    dir.figure("pareto", &front_plot(&report))?;
    dir.write("report.html", rotorshunt::report::html::page(&report.title, &text, &dir).as_bytes())?;
    progress.advance(4);
    dir.commit("design", progress)?;
    let f = &report.front;
    let mut s = format!(
        "design --pareto {points}: {} points from the best damping to the widest band around phi_op = {} rad/s at beta = {}; front {}{}\n",
        f.points.len(),
        f.phi_op,
        f.level,
        if f.monotone { "monotone" } else { "NOT monotone" },
        if f.collapsed { " (no trade-off: the best-damped design has the widest band)" } else { "" }
    );
    for p in &f.points {
        s += &point_line(p, &report.variables);
        s.push('\n');
    }
    s += &format!(
        "{} design runs, {} candidates, {} Floquet evaluations, {:.1} s; wrote report.md, report.html, report.json, pareto.svg, pareto.png and {} to {}\n",
        f.runs,
        f.candidates,
        f.evaluations,
        f.seconds,
        report.design_files.join(", "),
        out.display()
    );
    Ok((s, report.front))
}
