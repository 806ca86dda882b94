//! The Floquet commands: `floquet` (one point), `chart` (a grid, optionally compared with
//! a second configuration) and `response` (time response at one point).

use super::bounds::{self};
use super::{files_phase, parse_range, OutDir, Provenance};
use crate::commands::out::{json_compact, json_pretty};
use crate::commands::Error;
use rotorshunt::analysis::basis::BasisReport;
use rotorshunt::analysis::chart::ChartResult;
use rotorshunt::analysis::floquet::FloquetPoint;
use rotorshunt::analysis::limits::{self, Quantity, MAX_PERIODS};
use rotorshunt::analysis::response::ResponseResult;
use rotorshunt::analysis::unbalance::Probe;
use rotorshunt::problem::Problem;
use rotorshunt::progress::Progress;
use rotorshunt::report::chart::{chart_csv, GrowthMap, Layer, StabilityPlot};
use rotorshunt::report::plot::{envelope, Curve, CurvePlot};
use rotorshunt::report::style;
use rotorshunt::run::Budget;
use rotorshunt::run::{ResponseRun, Run};
use serde::Serialize;
use std::path::Path;

/// Most points of one chart: ~10 minutes of CPU and ~100 MB of results on this machine
/// class; beyond that a typo in a step (0.001 for 1) should fail at once, not run for days.
pub const MAX_CHART_POINTS: usize = 2_000_000;

/// The files `chart` writes (checked against its inputs before it computes).
const CHART_FILES: [&str; 8] =
    ["chart.json", "chart.csv", "compare.json", "compare.csv", "chart.svg", "chart.png", "growth.svg", "growth.png"];

fn arg_error(argument: &str, message: String) -> Error {
    Error::Argument { argument: argument.into(), message }
}

/// The checks of `floquet` (and `response`) on φ (rad/s) and β.
pub fn check_point(phi: f64, beta: f64) -> Result<(), Error> {
    bounds::flag("--phi", limits::frequency(Quantity::Frequency, phi))?;
    bounds::flag("--beta", limits::load(beta))?;
    Ok(())
}

/// A probe's physical displacement over a response, as written to `response.json`.
#[derive(Serialize)]
struct PhysicalSeries<'a> {
    /// The probe (name, kind, node, global DOF).
    #[serde(flatten)]
    probe: &'a Probe,
    /// u = Φ·q at each sample time (m), as [v, w] = [Re u, Im u].
    displacement_m: Vec<[f64; 2]>,
}

/// A probe name as a CSV column stem: lower case, runs of other characters as `_`.
fn column_stem(name: &str) -> String {
    let mut out = String::new();
    for c in name.chars() {
        if c.is_ascii_alphanumeric() {
            out.push(c.to_ascii_lowercase());
        } else if !out.ends_with('_') {
            out.push('_');
        }
    }
    out.trim_matches('_').to_string()
}

/// Columns of a pixel-wide envelope of the response plot (about the plotting width).
const RESPONSE_COLUMNS: usize = 900;

/// JSON of `floquet`.
#[derive(Debug, Serialize)]
pub struct FloquetOutput {
    /// Tool, input hash and settings.
    #[serde(flatten)]
    pub provenance: Provenance,
    /// Ω (rad/s).
    pub speed: f64,
    /// The reduced basis the point was computed on, and its convergence.
    pub basis: BasisReport,
    /// The Floquet point at (φ, β): its summary (max|μ|, growth rate, verdict) and the
    /// multipliers μ; flattened into the JSON.
    #[serde(flatten)]
    pub point: FloquetPoint,
}

/// `rotorshunt floquet FILE --phi P --beta B [--json]`.
pub fn floquet_cmd(problem: &Problem, phi: f64, beta: f64, json: bool, budget: Budget) -> Result<String, Error> {
    check_point(phi, beta)?;
    // On a basis sized by convergence, or fixed by the settings (basis::point_sized).
    let sized = Run::new(&rotorshunt::progress::Silent).with_budget(budget).point(problem, phi, beta)?;
    let (fs, point, basis) = (sized.system, sized.answer, sized.basis);
    if json {
        let out = FloquetOutput { provenance: Provenance::of(problem), speed: fs.speed, basis, point };
        return Ok(json_pretty(&out, "the JSON output")? + "\n");
    }
    let mut s = format!(
        "phi = {phi} rad/s, beta = {beta}, speed = {} rad/s, {}\nmax|mu| = {:.8} (ln = {:.6e}), growth rate = {:.6e} 1/s: {} (unstable when {}), status {:?}\n",
        fs.speed,
        basis.text(),
        point.summary.max_multiplier,
        point.summary.ln_max_multiplier,
        point.summary.growth_rate,
        if point.summary.stable { "stable" } else { "UNSTABLE" },
        problem.settings.threshold().describe(),
        point.summary.status
    );
    if let Some(reason) = point.summary.reason {
        s += &format!("reason: {reason}\n");
    }
    s += "multipliers:\n";
    for m in &point.multipliers {
        s += &format!(
            "  {:+.8e} {:+.8e}i  |mu| = {:.8}\n",
            m[0],
            m[1],
            m[0].hypot(m[1]) * point.multiplier_log_scale.exp()
        );
    }
    Ok(s)
}

/// The checks `chart` makes on its grid (φ in rad/s, β): every value by its rule, and at
/// most [`MAX_CHART_POINTS`] points.
pub fn check_grid(phis: &[f64], betas: &[f64]) -> Result<(), Error> {
    for &p in phis {
        bounds::flag("--phi", limits::frequency(Quantity::Frequency, p))?;
    }
    for &b in betas {
        bounds::flag("--beta", limits::load(b))?;
    }
    let points = phis.len() * betas.len();
    if points > MAX_CHART_POINTS {
        return Err(arg_error(
            "--phi/--beta",
            format!("the grid has {points} points, more than the {MAX_CHART_POINTS} a chart may have (about 10 minutes here); use coarser steps"),
        ));
    }
    Ok(())
}

#[derive(Serialize)]
struct ChartJson<'a> {
    #[serde(flatten)]
    provenance: Provenance,
    chart: &'a ChartResult,
}

/// Legend name of a problem's chart: its circuit state and the overrides that set it
/// apart (the state override is already in the name).
pub fn layer_name(problem: &Problem) -> String {
    let extra: Vec<&str> =
        problem.overrides.iter().map(String::as_str).filter(|o| !o.starts_with("circuit.state")).collect();
    let mut name = format!("{} circuit", problem.model.state_text());
    if !extra.is_empty() {
        name += &format!(", {}", extra.join(", "));
    }
    name
}

/// What `chart` compares the main problem with.
pub enum Compare<'a> {
    /// Nothing.
    None,
    /// Another problem (label, problem).
    Problem(&'a str, &'a Problem),
}

impl<'a> Compare<'a> {
    /// The comparison with `other` if there is one, else [`Compare::None`].
    pub fn of(other: Option<&'a super::Compared>) -> Compare<'a> {
        match other {
            Some(o) => Compare::Problem(&o.label, &o.problem),
            None => Compare::None,
        }
    }
}

fn write_chart(
    dir: &OutDir,
    stem: &str,
    problem: &Problem,
    warnings: &[rotorshunt::problem::Warning],
    c: &ChartResult,
) -> Result<(), Error> {
    let json = ChartJson { provenance: Provenance::of(problem).with(warnings), chart: c };
    dir.write(&format!("{stem}.json"), json_compact(&json, "the JSON output")?.as_bytes())?;
    let csv = chart_csv(c).map_err(|e| dir.error(&format!("{stem}.csv"), e))?;
    dir.write(&format!("{stem}.csv"), csv.as_bytes())
}

/// What a chart is asked: the grids as given on the command line and what to compare.
pub struct ChartArgs<'a> {
    /// `--phi A:B:STEP` (rad/s).
    pub phi: &'a str,
    /// `--beta A:B:STEP` (−).
    pub beta: &'a str,
    /// The second configuration drawn beside the problem, if any.
    pub compare: Compare<'a>,
    /// `--timing`: also print the chart's wall time per point.
    pub timing: bool,
}

/// `rotorshunt chart FILE --phi A:B:STEP --beta A:B:STEP --out DIR [--compare …]`.
/// Progress: `chart` (a step per φ), `compare` (with a second configuration), `files`.
pub fn chart_cmd(
    problem: &Problem,
    args: ChartArgs<'_>,
    out: &Path,
    progress: &dyn Progress,
    budget: Budget,
) -> Result<String, Error> {
    let ChartArgs { phi, beta, compare, timing } = args;
    let phis = parse_range(phi, "--phi")?;
    let betas = parse_range(beta, "--beta")?;
    check_grid(&phis, &betas)?;
    // Both systems built and the charts' work admitted before any file is touched.
    let run = Run::new(progress).with_budget(budget);
    let other = match &compare {
        Compare::Problem(_, other) => Some(*other),
        Compare::None => None,
    };
    let job = run.chart(problem, other, &phis, &betas)?;
    let (main_warnings, other_warnings) = job.warnings.clone();
    let mut inputs = vec![(Path::new(&problem.file), "the input problem file")];
    if let Compare::Problem(_, other) = &compare {
        inputs.push((Path::new(&other.file), "the --compare file"));
    }
    let dir = OutDir::with_inputs(out, &inputs)?;
    dir.check_outputs(&CHART_FILES)?;
    let charts = job.run()?;
    let (main, elapsed) = (charts.main, charts.seconds);
    // Both layers are named alike: by their file and overrides when a second file is
    // compared, by circuit state and overrides when the same file is.
    let by_file = matches!(compare, Compare::Problem(_, other) if other.file != problem.file);
    let compared = match (compare, charts.other) {
        (Compare::Problem(name, other), Some(c)) => Some((name, other, c)),
        _ => None,
    };
    let written = files_phase(progress, if compared.is_some() { 8 } else { 6 });
    write_chart(&dir, "chart", problem, &main_warnings, &main)?;
    let label = super::plot_title(problem);
    let files = compared.as_ref().map(|(_, other, _)| super::compare::file_layer_names(problem, other));
    let name = match (&files, by_file) {
        (Some((main_name, _)), true) => main_name.clone(),
        _ => layer_name(problem),
    };
    let mut layers = vec![Layer { name, color: (31, 119, 180), chart: main.clone() }];
    let mut text = String::new();
    if let Some((name, other, c)) = compared {
        write_chart(&dir, "compare", other, &other_warnings, &c)?;
        written();
        written();
        text += &format!("compare ({name}): {} of {} points unstable\n", c.unstable(), c.points.len());
        let shown = match files {
            Some((_, other_name)) if by_file => other_name,
            _ => name.to_string(),
        };
        layers.push(Layer { name: shown, color: (214, 39, 40), chart: c });
    }
    written();
    written();
    let plot = StabilityPlot::new(&format!("Stability chart: {label}"), layers);
    dir.figure("chart", &plot)?;
    written();
    written();
    let growth = GrowthMap::new(&format!("Growth rate: {label}"), main.clone());
    dir.figure("growth", &growth)?;
    written();
    written();
    dir.commit("chart", progress)?;
    let mut head = format!(
        "chart: {} points ({} phi x {} beta), {} unstable, {} failed, {} inaccurate; wrote chart.{{json,csv,svg,png}} and growth.{{svg,png}} to {}\n",
        main.points.len(),
        phis.len(),
        betas.len(),
        main.unstable(),
        main.failed,
        main.inaccurate,
        out.display()
    );
    head += &format!("basis: {}\n", main.basis.text());
    if timing {
        head += &format!(
            "timing: {} points in {:.3} s wall ({:.1} us/point/thread, {} threads, method {:?}, {} steps/period)\n",
            main.points.len(),
            elapsed,
            elapsed * 1e6 * rayon::current_num_threads() as f64 / main.points.len() as f64,
            rayon::current_num_threads(),
            problem.settings.method,
            problem.settings.steps_per_period
        );
    }
    Ok(head + &text)
}

/// `rotorshunt response FILE --phi P --beta B --periods N --out DIR`. Progress: `floquet
/// point` (time only), `response` (up to a hundred steps per load period), then `files`.
pub fn response_cmd(
    problem: &Problem,
    phi: f64,
    beta: f64,
    periods: usize,
    out: &Path,
    progress: &dyn Progress,
    budget: Budget,
) -> Result<String, Error> {
    check_point(phi, beta)?;
    bounds::flag("--periods", limits::count(periods as u64, 1, MAX_PERIODS as u64))?;
    let run = Run::new(progress).with_budget(budget);
    let job = run.response(problem, phi, beta, periods)?;
    super::check_folder(out)?;
    let ResponseRun { point, response: r, physical } = job.run()?;
    let written = files_phase(progress, 4);
    let dir = OutDir::create(out, &problem.file)?;
    #[derive(Serialize)]
    struct Json<'a> {
        #[serde(flatten)]
        provenance: Provenance,
        floquet: &'a FloquetPoint,
        response: &'a ResponseResult,
        /// The disks' and supports' physical displacements (m).
        physical: &'a [PhysicalSeries<'a>],
    }
    let physical: Vec<PhysicalSeries<'_>> =
        physical.iter().map(|(p, u)| PhysicalSeries { probe: p, displacement_m: u.clone() }).collect();
    let json = Json { provenance: Provenance::of(problem), floquet: &point, response: &r, physical: &physical };
    dir.write("response.json", json_compact(&json, "the JSON output")?.as_bytes())?;
    written();
    let mut csv = String::from("time_s,q1_re,q1_im");
    for p in &physical {
        let stem = column_stem(&p.probe.name);
        csv += &format!(",{stem}_v_m,{stem}_w_m");
    }
    csv.push('\n');
    for (i, (t, q)) in r.time.iter().zip(&r.q1).enumerate() {
        csv += &format!("{t},{},{}", q[0], q[1]);
        for p in &physical {
            let u = p.displacement_m.get(i).copied().unwrap_or([f64::NAN, f64::NAN]);
            csv += &format!(",{},{}", u[0], u[1]);
        }
        csv.push('\n');
    }
    dir.write("response.csv", csv.as_bytes())?;
    written();
    let ymax =
        physical.iter().flat_map(|p| p.displacement_m.iter().map(|u| u[0].abs())).fold(0.0, f64::max).max(1e-300);
    let curves: Vec<Curve> = physical
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let points: Vec<(f64, f64)> = r.time.iter().zip(&p.displacement_m).map(|(t, u)| (*t, u[0])).collect();
            // Solid lines: a dash pattern over thousands of oscillations costs more to
            // draw than the response to compute, and colour tells the probes apart.
            Curve {
                width: if k == 0 { style::LINE_WIDTH } else { style::THIN },
                ..Curve::new(format!("{}: v", p.probe.name), style::color(k), envelope(&points, RESPONSE_COLUMNS))
            }
        })
        .collect();
    let plot = CurvePlot {
        title: format!(
            "Response at φ = {phi} rad/s, β = {beta}: {} (max|μ| = {:.5}), {}",
            if point.summary.stable { "stable" } else { "unstable" },
            point.summary.max_multiplier,
            super::plot_title(problem)
        ),
        x_label: style::axis_label("time", "t", "s"),
        y_label: style::axis_label("vertical displacement", "v = Re u", "m"),
        x_range: (0.0, *r.time.last().unwrap_or(&1.0)),
        y_range: (-ymax * 1.05, ymax * 1.05),
        log_y: false,
        curves,
    };
    dir.figure("response", &plot)?;
    written();
    written();
    dir.commit("response", progress)?;
    Ok(format!(
        "response: {} periods, RK4 step {:.3e} s; peak |q| first period {:.4e}, last period {:.4e} (ratio {:.3e}); Floquet: max|mu| = {:.6} ({}); wrote response.{{json,csv,svg,png}} to {}\n",
        periods,
        r.step,
        r.first_period_peak,
        r.last_period_peak,
        r.growth_ratio(),
        point.summary.max_multiplier,
        if point.summary.stable { "stable" } else { "unstable" },
        out.display()
    ))
}
