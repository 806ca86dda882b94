//! `rotorshunt design FILE --out DIR`: run the `[design]` of a problem file and write the
//! tuned-parameter report (report.md, report.json), the tuned problem (tuned.toml) and
//! plots (charts before/after with the operating bands, Campbell diagram, history).

use super::{title, OutDir};
use crate::commands::out::json_pretty;
use crate::commands::Error;
use rotorshunt::design::{DesignError, DesignOutcome, Status};
use rotorshunt::problem::Problem;
use rotorshunt::progress::Progress;
use rotorshunt::report::design::map::{map_csv, map_file};
use rotorshunt::report::design::pareto::FrontReport;
use rotorshunt::report::design::{self as report_design, branch_rows, markdown, DesignReport};
use rotorshunt::run::{Budget, DesignJob, DesignRun, FrontJob, Outcome, Run};
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

/// `rotorshunt design FILE --out DIR`: the summary text and the outcome (whose status
/// decides the exit code). Refused before any folder is made when its estimate is beyond
/// `budget`. Progress: the design's `optimise` and `verification`
/// ([`rotorshunt::design::run`]), then `report` (a step per chart row, Campbell speed and
/// file).
pub fn design_cmd(
    problem: &Problem,
    out: &Path,
    progress: &dyn Progress,
    budget: Budget,
) -> Result<(String, DesignOutcome), Error> {
    let run = Run::new(progress).with_budget(budget);
    // No folder is created for a file without a [design] table, nor for one refused.
    let job = run.design(problem, "the design")?;
    design_into(problem, out, job, progress)
}

/// Run the admitted design `job` of `problem` into the folder `out`, as `design --out`
/// writes it (made before the design runs, committed after the report): the summary text
/// and the outcome. `design`'s, and the Python bindings' `design` with `out`.
pub fn design_into(
    problem: &Problem,
    out: &Path,
    job: DesignJob<'_, '_>,
    progress: &dyn Progress,
) -> Result<(String, DesignOutcome), Error> {
    let dir = OutDir::create(out, &problem.file)?;
    let outcome = design_report(problem, &dir, job, progress)?.value;
    dir.commit("design", progress)?;
    Ok((summary_text(&outcome, out), outcome))
}

/// Run the admitted design `job` and write the report files to `dir`: the outcome, with
/// the limit that stopped it. A design stopped by its time limit, its allowance of
/// evaluations or its caller keeps the best design judged so far: `best-effort.toml`
/// and the report's text, with the stop on page one, and no figures. Its report's
/// charts stopped so are an error, its files left uncommitted. Progress: the design's
/// `optimise` and `verification`, then `report` (a step per chart row, Campbell speed
/// and file).
pub fn design_report(
    problem: &Problem,
    dir: &OutDir,
    job: DesignJob<'_, '_>,
    progress: &dyn Progress,
) -> Result<Outcome<DesignOutcome>, Error> {
    let Outcome { status, value, stop, evaluations } = job.run(true)?;
    let DesignRun { outcome, tuned, content } = value;
    let Some(mut content) = content else {
        let files = text_files(&outcome);
        let report = report_of(problem, &tuned, outcome, Vec::new(), files);
        write_texts(problem, dir, &report)?;
        return Ok(Outcome { status, value: report.outcome, stop, evaluations });
    };
    let whirls = std::mem::take(&mut content.whirls);
    let figures = report_design::figures(&outcome, content, &title(problem));
    progress.extend(figures.len() as u64);
    let mut files = text_files(&outcome);
    files.extend(figures.iter().flat_map(|(stem, _)| [format!("{stem}.svg"), format!("{stem}.png")]));
    let report = report_of(problem, &tuned, outcome.clone(), whirls, files);
    progress.advance(3);
    for (stem, figure) in &figures {
        dir.figure(stem, figure.as_ref())?;
        progress.advance(1);
    }
    write_texts(problem, dir, &report)?;
    progress.advance(1);
    Ok(Outcome { status, value: report.outcome, stop, evaluations })
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
fn text_files(o: &DesignOutcome) -> Vec<String> {
    let mut files: Vec<String> =
        ["report.md", "report.html", "report.json", design_file_name(o.status)].map(str::to_string).to_vec();
    if o.map.is_some() {
        files.extend(["map.csv", "map.json"].map(str::to_string));
    }
    files
}

/// The design file (`tuned.toml` or `best-effort.toml`), report.json, report.md and
/// report.html (after the figures it shows).
fn write_texts(problem: &Problem, dir: &OutDir, report: &DesignReport) -> Result<(), Error> {
    let design_file = design_file_name(report.outcome.status);
    dir.write(design_file, super::tuned_toml(problem, &report.outcome)?.as_bytes())?;
    dir.write("report.json", (json_pretty(report, "the JSON output")? + "\n").as_bytes())?;
    if let (Some(csv), Some(map)) = (map_csv(&report.outcome), map_file(&report.outcome)) {
        dir.write("map.csv", csv.as_bytes())?;
        dir.write("map.json", (json_pretty(&map, "the map")? + "\n").as_bytes())?;
    }
    let text = markdown(report);
    dir.write("report.md", text.as_bytes())?;
    dir.write("report.html", rotorshunt::report::html::page(&report.title, &text, dir).as_bytes())?;
    Ok(())
}

/// The one-paragraph result on standard output.
pub fn summary_text(o: &DesignOutcome, out: &Path) -> String {
    let spec = &o.spec;
    let values = |v: &[f64]| spec.values_text(v);
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
                    af.map_or("no half-power band in the range".to_string(), |a| format!(
                        "AF {a:.1}{}",
                        rotorshunt::analysis::unbalance::split_note(b.split_pair)
                    )),
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
/// ([`rotorshunt::design::pareto::front`]) with its report (report.md, report.html,
/// report.json), the plot of the front (pareto.svg, pareto.png) and every point's design
/// file (`tuned-k.toml`, or `best-effort-k.toml` for a point that is not a verified
/// result). A design without a trade-off is refused at its key and line, before any
/// folder is made. Progress: `front` (the runs' candidates and verification points),
/// `report`. Returns the summary text and the report (report.json's document).
pub fn pareto_cmd(
    problem: &Problem,
    points: usize,
    out: &Path,
    progress: &dyn Progress,
    budget: Budget,
) -> Result<(String, FrontReport), Error> {
    let run = Run::new(progress).with_budget(budget);
    let job = run.pareto(problem, points)?;
    pareto_into(problem, points, out, job, progress)
}

/// Run the admitted front `job` of `problem` (`points` points) into the folder `out`, as
/// `design --pareto` writes it (made before the front runs, committed after the report):
/// the summary text and the report. `design --pareto`'s, and the Python bindings'
/// `pareto`.
pub fn pareto_into(
    problem: &Problem,
    points: usize,
    out: &Path,
    job: FrontJob<'_, '_>,
    progress: &dyn Progress,
) -> Result<(String, FrontReport), Error> {
    use rotorshunt::report::design::pareto::{front_plot, markdown, point_file, point_line};
    let spec = problem.design.as_ref().ok_or(Error::Design(DesignError::NoDesign))?;
    let dir = OutDir::create(out, &problem.file)?;
    let front = job.run()?;
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
        "design --pareto {points}: {} points from the best damping to the widest band around phi_op = {} rad/s at beta = {}; front {}{}{}\n",
        f.points.len(),
        f.phi_op,
        f.level,
        if f.monotone { "monotone" } else { "NOT monotone" },
        if f.ends_consistent { "" } else { ", ends NOT consistent" },
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
    Ok((s, report))
}
