//! The application layer behind the CLI: each command loads a problem, runs analyses,
//! renders reports and writes files. Commands return the text for standard output.

mod args;
pub(crate) mod bounds;
mod compare;
pub(crate) mod design;
mod error;
#[cfg(test)]
mod flag_fuzz;
mod floquet;
mod import;
mod out;
mod regions;
mod study;
mod tuned;
pub(crate) mod unbalance;

// What the binary calls, and the layer's own modules use.
pub(crate) use args::parse_range;
pub use compare::{compared, Compared};
pub use design::{design_cmd, pareto_cmd};
pub use error::Error;
pub(crate) use floquet::layer_name;
pub use floquet::{chart_cmd, floquet_cmd, response_cmd, ChartArgs, Compare};
pub use import::import_ross_cmd;
pub use out::remove_unfinished;
pub(crate) use out::{check_folder, OutDir};
pub use regions::{band_cmd, regions_cmd, RegionsArgs};
pub use study::{
    merge_cmd, plan_cmd, slurm_cmd, status_cmd, study_cmd, Shard, ShardRequest, SlurmOptions, StatusReport,
    StudyOptions, MAX_SHARDS,
};
pub use unbalance::{damping_cmd, unbalance_cmd, UnbalanceArgs};
// What the Python bindings alone call (unused in the binary, whose build checks the rest
// of this layer for dead code).
#[allow(unused_imports)]
pub use design::{design_file_name, design_into, pareto_into, status_word};
#[allow(unused_imports)]
pub use floquet::{check_grid, check_point};
#[allow(unused_imports)]
pub use regions::{band_output, band_request, regions_output, regions_request, BandOutput, BandRequest, RegionsJson};
#[allow(unused_imports)]
pub use tuned::tuned_toml;
#[allow(unused_imports)]
pub use unbalance::{on_nodes, unbalance_output, unbalance_speeds, UnbalanceJson};

use crate::commands::out::json_pretty;
use rotorshunt::analysis::limits::{self, MAX_COUNT};
use rotorshunt::analysis::modes::WhirlMode;
use rotorshunt::analysis::Rotor;
use rotorshunt::numbers::SpeedUnit;
use rotorshunt::problem::Problem;
use rotorshunt::progress::Progress;
use rotorshunt::report::{campbell as campbell_report, summary};
use rotorshunt::run::{Budget, CampbellRun, ModesRun, Run};
use serde::Serialize;
use std::path::Path;

/// Forward and backward whirls listed or tracked when no `--count` is given (`modes`,
/// `campbell`, `damping`, and the Python bindings' `modes` and `campbell`).
pub const DEFAULT_WHIRL_COUNT: usize = 4;

pub use rotorshunt::problem::provenance::{Provenance, TOOL};

/// Begin the `files` phase that ends a command, of `count` files; the step to call after
/// each file is written.
pub(crate) fn files_phase(progress: &dyn Progress, count: u64) -> impl Fn() + '_ {
    progress.phase("files", count);
    move || progress.advance(1)
}

pub(crate) fn title(p: &Problem) -> String {
    p.data.title.clone().unwrap_or_else(|| p.file.clone())
}

/// The configuration a plot shows: the file's title and, in brackets, the `--set`
/// overrides applied to it, e.g. `Fig. 9 … [circuit.state=closed]`.
pub fn plot_title(p: &Problem) -> String {
    match p.overrides.as_slice() {
        [] => title(p),
        o => format!("{} [{}]", title(p), o.join(", ")),
    }
}

/// `rotorshunt check FILE`: the model summary. Refused before assembly when the model's
/// dense matrices are beyond `budget`. A design's damping constraints are checked against
/// the model's whirls here too, as the design will ([`rotorshunt::design::checks::modes_exist`]).
pub fn check(problem: &Problem, budget: Budget) -> Result<String, Error> {
    let rotor = Run::new(&rotorshunt::progress::Silent).with_budget(budget).check(problem)?;
    Ok(check_text(problem, &rotor))
}

/// The text of `check`: the model summary of the rotor [`Run::check`] built from
/// `problem`.
pub fn check_text(problem: &Problem, rotor: &Rotor) -> String {
    format!("{}: valid\n{}", problem.file, summary::check_text(rotor, &title(problem)))
}

/// JSON of `modes`.
#[derive(Debug, Serialize)]
pub struct ModesOutput {
    /// Tool, input hash and settings.
    #[serde(flatten)]
    pub provenance: Provenance,
    /// Ω (rad/s).
    pub speed: f64,
    /// P_cr (N).
    pub critical_load: f64,
    /// αP_cr (N).
    pub static_load: f64,
    /// Lowest `count` forward and backward whirls, by frequency.
    pub modes: Vec<WhirlMode>,
}

/// `rotorshunt modes FILE [--speed W] [--count N] [--json]`.
pub fn modes(problem: &Problem, speed: Option<f64>, count: usize, json: bool, budget: Budget) -> Result<String, Error> {
    let speed = modes_speed(problem, speed, count)?;
    let r = Run::new(&rotorshunt::progress::Silent).with_budget(budget).modes(problem, speed, count)?;
    let out = modes_output(problem, speed, count, &r);
    if json {
        Ok(json_pretty(&out, "the JSON output")? + "\n")
    } else {
        Ok(summary::modes_text(&out.modes, speed, out.critical_load))
    }
}

/// The checks of `modes` (`--count`, `--speed`): the speed (rad/s) asked, the problem's
/// when none is.
pub fn modes_speed(problem: &Problem, speed: Option<f64>, count: usize) -> Result<f64, Error> {
    bounds::flag("--count", limits::count(count as u64, 1, MAX_COUNT as u64))?;
    match speed {
        Some(w) => bounds::flag("--speed", limits::speed(w)),
        None => Ok(problem.model.speed),
    }
}

/// The JSON document of `modes` from the whirls [`Run::modes`] computed at `speed`: the
/// lowest `count` of each direction. Rendered by `modes`, converted by the Python
/// bindings' `modes`.
pub fn modes_output(problem: &Problem, speed: f64, count: usize, r: &ModesRun) -> ModesOutput {
    ModesOutput {
        provenance: Provenance::of(problem),
        speed,
        critical_load: r.critical_load,
        static_load: r.static_load,
        modes: r.lowest(count),
    }
}

/// The operating speeds of a problem (rad/s): its `speed` and a design's speeds, each once.
fn operating_speeds(problem: &Problem) -> Vec<f64> {
    let mut out = vec![problem.model.speed];
    for &w in problem.design.iter().flat_map(|d| d.speeds.iter()) {
        if !out.contains(&w) {
            out.push(w);
        }
    }
    out
}

/// JSON of `campbell` (campbell.json).
#[derive(Serialize)]
pub struct CampbellJson {
    /// Tool, input hash and settings.
    #[serde(flatten)]
    pub provenance: Provenance,
    /// The diagram.
    pub campbell: CampbellRun,
    /// The problem's operating speeds (rad/s): its `speed` and a design's speeds.
    pub operating_speeds: Vec<f64>,
    /// The crossings of the tracks with the 1× line, by speed.
    pub critical_speeds: Vec<campbell_report::CriticalSpeed>,
}

/// The check of `campbell` on each of its speeds (rad/s).
pub fn campbell_speeds(speeds: &[f64]) -> Result<(), Error> {
    for &w in speeds {
        bounds::flag("--speeds", limits::speed(w))?;
    }
    Ok(())
}

/// campbell.json's document from the diagram [`Run::campbell`] computed: with the
/// problem's provenance, its operating speeds (rad/s) and the critical speeds. Written by
/// `campbell`, converted by the Python bindings' `campbell`.
pub fn campbell_output(problem: &Problem, result: CampbellRun) -> CampbellJson {
    CampbellJson {
        provenance: Provenance::of(problem),
        operating_speeds: operating_speeds(problem),
        critical_speeds: campbell_report::critical_speeds(&result),
        campbell: result,
    }
}

/// `rotorshunt campbell FILE --speeds A:B:STEP --out DIR`: CSV, JSON, SVG and PNG.
/// Progress: `whirls` (a step per speed), then `files` (a step per file).
pub fn campbell_cmd(
    problem: &Problem,
    speeds: &str,
    count: usize,
    out: &Path,
    progress: &dyn Progress,
    budget: Budget,
) -> Result<String, Error> {
    bounds::flag("--count", limits::count(count as u64, 1, MAX_COUNT as u64))?;
    let (speeds, given) = args::parse_speeds(speeds, "--speeds")?;
    campbell_speeds(&speeds)?;
    // rpm on the axis when the user gave rpm, on the command line or in the file.
    let unit = if given == SpeedUnit::Rpm { given } else { problem.speed_unit() };
    let run = Run::new(progress).with_budget(budget);
    let job = run.campbell(problem, &speeds, count)?;
    let dir = OutDir::create(out, &problem.file)?;
    let doc = campbell_output(problem, job.run()?);
    progress.phase("files", 4);
    dir.write("campbell.json", json_pretty(&doc, "the JSON output")?.as_bytes())?;
    let (result, operating, critical) = (&doc.campbell, &doc.operating_speeds, &doc.critical_speeds);
    progress.advance(1);
    let csv = campbell_report::campbell_csv(result).map_err(|e| dir.error("campbell.csv", e))?;
    dir.write("campbell.csv", csv.as_bytes())?;
    progress.advance(1);
    let plot =
        campbell_report::campbell_plot(result, &format!("Campbell diagram: {}", plot_title(problem)), unit, operating);
    dir.figure("campbell", &plot)?;
    progress.advance(2);
    dir.commit("campbell", progress)?;
    let mut text = format!(
        "campbell: {} speeds ({}), {} tracks, {} low-MAC steps flagged (threshold {}); wrote campbell.{{csv,json,svg,png}} to {}\n",
        speeds.len(),
        unit.range(speeds[0], speeds[speeds.len() - 1]),
        result.tracks.len(),
        result.flagged,
        result.mac_threshold,
        out.display()
    );
    for w in operating {
        text += &format!("operating speed: {}\n", unit.text(*w));
    }
    text += "critical speeds (crossings with 1x):";
    if critical.is_empty() {
        text += " none in the range";
    }
    text += "\n";
    for c in critical {
        let whirl = format!("{:?}", c.whirl).to_lowercase();
        text += &format!("  {} ({whirl} whirl): {}\n", c.track, unit.text(c.speed));
    }
    Ok(text)
}
