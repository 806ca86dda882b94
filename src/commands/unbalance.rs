//! `unbalance` (steady-state unbalance response, optionally compared with a second
//! configuration) and `damping` (ζ of the whirl modes over a speed range).

use super::bounds::{self};
use super::out::json_pretty;
use super::{title, Compare, OutDir, Progress, Provenance};
use crate::commands::Error;
use rotorshunt::analysis::damping::ModeDamping;
use rotorshunt::analysis::limits::{self, MAX_COUNT};
use rotorshunt::analysis::unbalance::UnbalanceResult;
use rotorshunt::analysis::AnalysisError;
use rotorshunt::problem::Problem;
use rotorshunt::report::unbalance::{damping_text, peaks_csv, peaks_text, unbalance_csv, BodeLayer, BodePlot};
use rotorshunt::run::Budget;
use rotorshunt::run::{Run, RunError, UnbalanceRun};
use serde::Serialize;
use std::borrow::Cow;
use std::path::Path;

/// The files `unbalance` writes (checked against its inputs before it computes).
const UNBALANCE_FILES: [&str; 12] = [
    "unbalance.json",
    "unbalance.csv",
    "peaks.csv",
    "compare.json",
    "compare.csv",
    "compare-peaks.csv",
    "bode.svg",
    "bode.png",
    "bode-x.svg",
    "bode-x.png",
    "bode-y.svg",
    "bode-y.png",
];

/// What `unbalance` is asked.
pub struct UnbalanceArgs<'a> {
    /// `--speeds A:B:STEP` (rad/s).
    pub speeds: &'a str,
    /// `--nodes 3,16`: shaft nodes reported besides the disks and supports.
    pub nodes: &'a str,
    /// The second configuration drawn beside the problem, if any.
    pub compare: Compare<'a>,
    /// `--json`: print the JSON instead of the table of peaks.
    pub json: bool,
}

/// The speed grid of `--speeds`: parsed, each speed by its rule, at least one; and the
/// unit it was given in (rpm echoes in rpm).
fn speed_grid(
    text: &str,
    rule: fn(f64) -> Result<f64, limits::ParamError>,
) -> Result<(Vec<f64>, rotorshunt::numbers::SpeedUnit), Error> {
    let (speeds, unit) = super::args::parse_speeds(text, "--speeds")?;
    for &w in &speeds {
        bounds::flag("--speeds", rule(w))?;
    }
    Ok((speeds, unit))
}

/// `--nodes 3,16` as node indices (empty text: none; an empty entry is refused).
fn node_list(text: &str) -> Result<Vec<usize>, Error> {
    super::args::parse_list(text, "--nodes")?
        .into_iter()
        .map(|t| {
            t.parse::<usize>().map_err(|_| Error::Argument {
                argument: "--nodes".into(),
                message: format!("`{t}` in `{text}` is not a node index (expected e.g. 3,16)"),
            })
        })
        .collect()
}

/// A run's error, a probe node off the shaft named by `--nodes`.
pub fn on_nodes(e: RunError) -> Error {
    match e {
        RunError::Analysis(e) => about("--nodes", e),
        other => other.into(),
    }
}

/// A library error about a flag's value, named by the flag (exit 2).
fn about(argument: &str, e: AnalysisError) -> Error {
    match e {
        AnalysisError::ProbeNodeOffShaft { .. } | AnalysisError::UnknownMode { .. } | AnalysisError::NoSpeeds => {
            Error::Argument { argument: argument.into(), message: e.to_string() }
        }
        other => other.into(),
    }
}

/// JSON of `unbalance` (unbalance.json): borrowed where `unbalance` writes it, owned
/// where the Python bindings' `unbalance` converts it.
#[derive(Serialize)]
pub struct UnbalanceJson<'a> {
    /// Tool, input hash and settings.
    #[serde(flatten)]
    pub provenance: Provenance,
    /// Definitions of the numbers, for a reader of the file.
    conventions: Conventions,
    /// The response.
    pub unbalance: Cow<'a, UnbalanceResult>,
}

#[derive(Serialize)]
struct Conventions {
    amplitude: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    orbit: Option<&'static str>,
    phase: &'static str,
    peaks: &'static str,
    amplification_factor: &'static str,
}

const CONVENTIONS: Conventions = Conventions {
    amplitude: "|U| (m): radius of the synchronous circular whirl u(t) = U e^{j Omega t}, u = v + jw",
    orbit: None,
    phase: "arg U (rad, in (-pi, pi]): angle of the deflection from the v axis towards w at t = 0, the reference of the disks' phase",
    peaks: "interior local maxima of the amplitude on the speed grid, refined by golden-section search on the analytic response",
    amplification_factor: "API 684 half-power: Omega_peak/(Omega_2 - Omega_1), amplitude A_peak/sqrt(2) at Omega_1 and Omega_2",
};

/// The conventions of the real coordinates (an anisotropic model): elliptical orbits.
const REAL_CONVENTIONS: Conventions = Conventions {
    amplitude: "semi-major axis |F| + |B| (m) of the synchronous elliptical orbit",
    orbit: Some("x(t) = |X| cos(Omega t + arg X) (v), y(t) = |Y| cos(Omega t + arg Y) (w); F = (X + jY)/2 and B = conj(X - jY)/2 the forward and backward circular components (u = x + jy = F e^{j Omega t} + B e^{-j Omega t}); major = |F| + |B|, minor = ||F| - |B||; the orbit whirls forward when |F| > |B|"),
    phase: "arg X (rad, in (-pi, pi]): phase of the x (v) motion, the reference of the disks' phase",
    peaks: CONVENTIONS.peaks,
    amplification_factor: CONVENTIONS.amplification_factor,
};

/// The checks of `unbalance` on its speeds (rad/s): at least one, each by its rule.
#[allow(dead_code)] // called by the Python bindings alone
pub fn unbalance_speeds(speeds: &[f64]) -> Result<(), Error> {
    if speeds.is_empty() {
        return Err(about("--speeds", AnalysisError::NoSpeeds));
    }
    for &w in speeds {
        bounds::flag("--speeds", limits::response_speed(w))?;
    }
    Ok(())
}

/// unbalance.json's document of the response `r` of `problem`, with the conventions of
/// its coordinates (complex, or real with orbits).
fn unbalance_json<'a>(problem: &Problem, r: Cow<'a, UnbalanceResult>) -> UnbalanceJson<'a> {
    let conventions = if r.probes.iter().any(|p| p.orbit.is_some()) { REAL_CONVENTIONS } else { CONVENTIONS };
    UnbalanceJson { provenance: Provenance::of(problem), conventions, unbalance: r }
}

/// unbalance.json's document of the response a run computed on `problem` (its
/// [`UnbalanceRun::main`]): the Python bindings' `unbalance`.
#[allow(dead_code)] // called by the Python bindings alone
pub fn unbalance_output(problem: &Problem, r: UnbalanceResult) -> UnbalanceJson<'static> {
    unbalance_json(problem, Cow::Owned(r))
}

fn write_layer(dir: &OutDir, stem: &str, problem: &Problem, r: &UnbalanceResult) -> Result<String, Error> {
    let text = json_pretty(&unbalance_json(problem, Cow::Borrowed(r)), "the JSON output")?;
    dir.write(&format!("{stem}.json"), text.as_bytes())?;
    let csv = unbalance_csv(r).map_err(|e| dir.error(&format!("{stem}.csv"), e))?;
    dir.write(&format!("{stem}.csv"), csv.as_bytes())?;
    let peaks_name = if stem == "unbalance" { "peaks.csv".to_string() } else { format!("{stem}-peaks.csv") };
    let peaks = peaks_csv(r).map_err(|e| dir.error(&peaks_name, e))?;
    dir.write(&peaks_name, peaks.as_bytes())?;
    Ok(text)
}

/// `rotorshunt unbalance FILE --speeds A:B:STEP --out DIR [--nodes 3,16] [--json]
/// [--compare FILE2 | --compare-set key=value]`: the steady-state unbalance response at
/// the disks, the supports and the nodes asked for; `unbalance.{json,csv}`, `peaks.csv`,
/// `bode.{svg,png}` (and `compare.{json,csv}`, `compare-peaks.csv`).
pub fn unbalance_cmd(
    problem: &Problem,
    args: UnbalanceArgs<'_>,
    out: &Path,
    progress: &dyn Progress,
    budget: Budget,
) -> Result<String, Error> {
    let UnbalanceArgs { speeds, nodes, compare, json } = args;
    let (speeds, unit) = speed_grid(speeds, limits::response_speed)?;
    let nodes = node_list(nodes)?;
    // Every check and estimate before any file is touched, for each configuration.
    let other = match &compare {
        Compare::Problem(_, other) => Some(*other),
        Compare::None => None,
    };
    let run = Run::new(progress).with_budget(budget);
    let job = run.unbalance(problem, other, &speeds, &nodes).map_err(on_nodes)?;
    let mut inputs = vec![(Path::new(&problem.file), "the input problem file")];
    if let Compare::Problem(_, other) = &compare {
        inputs.push((Path::new(&other.file), "the --compare file"));
    }
    let dir = OutDir::with_inputs(out, &inputs)?;
    dir.check_outputs(&UNBALANCE_FILES)?;
    let UnbalanceRun { main, other } = job.run().map_err(on_nodes)?;
    // Both layers are named alike: by file and overrides when a second file is compared,
    // by circuit state and overrides when the same file is.
    let by_file = matches!(compare, Compare::Problem(_, other) if other.file != problem.file);
    let compared = match (compare, other) {
        (Compare::Problem(name, other), Some(r)) => Some((name, other, r)),
        _ => None,
    };
    let main_json = write_layer(&dir, "unbalance", problem, &main)?;
    let mut layers = vec![BodeLayer {
        name: match (&compared, by_file) {
            (None, _) => String::new(),
            (Some((_, other, _)), true) => super::compare::file_layer_names(problem, other).0,
            (Some(_), false) => super::layer_name(problem),
        },
        dashed: false,
        result: &main,
    }];
    let mut text = peaks_text(&main, &format!("unbalance response: {}", title(problem)), unit);
    if let Some((name, other, r)) = &compared {
        write_layer(&dir, "compare", other, r)?;
        text += &peaks_text(r, &format!("compare ({name}):"), unit);
        let shown = if by_file { super::compare::file_layer_names(problem, other).1 } else { name.to_string() };
        layers.push(BodeLayer { name: shown, dashed: true, result: r });
    }
    // Real coordinates: a Bode plot per direction too (the main one draws semi-major axes).
    let directions: Vec<(&str, UnbalanceResult)> =
        ["x", "y"].iter().enumerate().filter_map(|(plane, name)| Some((*name, main.direction(plane)?))).collect();
    let plot = BodePlot { title: format!("Unbalance response: {}", super::plot_title(problem)), layers, unit };
    dir.figure("bode", &plot)?;
    for (name, r) in &directions {
        let layers = vec![BodeLayer { name: format!("{name} direction"), dashed: false, result: r }];
        let title = format!("Unbalance response, {name} direction: {}", super::plot_title(problem));
        dir.figure(&format!("bode-{name}"), &BodePlot { title, layers, unit })?;
    }
    dir.commit("unbalance", progress)?;
    let files = match (compared.is_some(), directions.is_empty()) {
        (true, true) => "unbalance.{json,csv}, peaks.csv, compare.{json,csv}, compare-peaks.csv and bode.{svg,png}",
        (true, false) => {
            "unbalance.{json,csv}, peaks.csv, compare.{json,csv}, compare-peaks.csv and bode{,-x,-y}.{svg,png}"
        }
        (false, true) => "unbalance.{json,csv}, peaks.csv and bode.{svg,png}",
        (false, false) => "unbalance.{json,csv}, peaks.csv and bode{,-x,-y}.{svg,png}",
    };
    let head = format!(
        "unbalance: {} speeds ({}), {} probes; wrote {files} to {}\n",
        speeds.len(),
        unit.range(speeds[0], speeds[speeds.len() - 1]),
        main.probes.len(),
        out.display()
    );
    if json {
        return Ok(main_json + "\n");
    }
    Ok(head + &text)
}

/// JSON of `damping`.
#[derive(Serialize)]
struct DampingJson<'a> {
    #[serde(flatten)]
    provenance: Provenance,
    speeds: &'a [f64],
    modes: &'a [ModeDamping],
}

/// `rotorshunt damping FILE --speeds A:B:STEP [--modes f1,fr1] [--count N] [--json]`:
/// ζ of the named whirls (by their tag at the first speed), or of the lowest N forward
/// and backward whirls, tracked over the speeds.
pub fn damping_cmd(
    problem: &Problem,
    speeds: &str,
    modes: &str,
    count: usize,
    json: bool,
    progress: &dyn Progress,
    budget: Budget,
) -> Result<String, Error> {
    bounds::flag("--count", limits::count(count as u64, 1, MAX_COUNT as u64))?;
    let (speeds, unit) = speed_grid(speeds, limits::speed)?;
    let tags: Vec<String> = super::args::parse_list(modes, "--modes")?.into_iter().map(String::from).collect();
    let run = Run::new(progress).with_budget(budget);
    let result = run.damping(problem, &speeds, &tags, count).map_err(|e| match e {
        RunError::Analysis(e) => about("--modes", e),
        other => other.into(),
    })?;
    if json {
        let out = DampingJson { provenance: Provenance::of(problem), speeds: &speeds, modes: &result };
        return Ok(json_pretty(&out, "the JSON output")? + "\n");
    }
    Ok(damping_text(&result, &speeds, unit))
}
