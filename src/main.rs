//! `rotorshunt` command line: parse arguments, load the problem, run, print, exit code.

use clap::{Args, Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use rotorshunt::analysis::cost::Budget;
use rotorshunt::commands::{self, Progress};
use rotorshunt::problem::Problem;
use std::path::PathBuf;
use std::process::ExitCode;

/// Parametric stability and shunt design of rotors on piezoelectric vibration rings.
/// All inputs and outputs are SI, frequencies and speeds in rad/s.
#[derive(Parser)]
#[command(name = "rotorshunt", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Allow FACTOR times the documented limits of computing time (3600 s of one core)
    /// and memory (400 MiB of dense matrices) that every command checks its estimated
    /// cost against before it starts (docs/errors.md, `Cost`).
    #[arg(long = "max-cost", value_name = "FACTOR", global = true, default_value_t = 1.0)]
    max_cost: f64,
}

/// The problem file and its overrides, shared by every command.
#[derive(Args)]
struct Input {
    /// Problem file (TOML, format version 1; see problems/README.md).
    file: PathBuf,
    /// Override a value of the file, e.g. `--set circuit.state=open --set speed=1500
    /// --set circuit.branches[0].resistance=50`. Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
}

/// One point (φ, β) of the load P(t) = P_cr(α + β cos φt).
#[derive(Args)]
struct Point {
    /// Excitation frequency φ (rad/s).
    #[arg(long)]
    phi: f64,
    /// Dynamic load coefficient β.
    #[arg(long)]
    beta: f64,
}

#[derive(Subcommand)]
enum Command {
    /// Validate a problem file and print the model summary (DOFs, k_eq, k_eq1, k_eq2,
    /// C_p^S, branch inductances, P_cr).
    Check {
        #[command(flatten)]
        input: Input,
    },
    /// Whirl frequencies at one speed: the lowest N forward and N backward whirls.
    Modes {
        #[command(flatten)]
        input: Input,
        /// Speed Ω (rad/s); default: the file's `speed`.
        #[arg(long)]
        speed: Option<f64>,
        /// Number of forward and of backward whirls.
        #[arg(long, default_value_t = 4)]
        count: usize,
        /// Print JSON instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// Campbell diagram over a speed range: CSV, JSON, SVG and PNG in DIR.
    Campbell {
        #[command(flatten)]
        input: Input,
        /// Speeds A:B:STEP (rad/s).
        #[arg(long)]
        speeds: String,
        /// Number of forward and of backward whirls to track.
        #[arg(long, default_value_t = 4)]
        count: usize,
        /// Output directory (created if missing).
        #[arg(long)]
        out: PathBuf,
    },
    /// Floquet multipliers at one point (φ, β) of P(t) = P_cr(α + β cos φt).
    Floquet {
        #[command(flatten)]
        input: Input,
        #[command(flatten)]
        point: Point,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Stability chart over a (φ, β) grid: JSON, CSV, SVG and PNG (chart and growth map).
    Chart {
        #[command(flatten)]
        input: Input,
        /// φ grid A:B:STEP (rad/s).
        #[arg(long)]
        phi: String,
        /// β grid A:B:STEP.
        #[arg(long)]
        beta: String,
        /// Output directory (created if missing).
        #[arg(long)]
        out: PathBuf,
        /// Overlay the chart of a second problem file (drawn in red).
        #[arg(long, conflicts_with = "compare_set")]
        compare: Option<PathBuf>,
        /// Overlay the chart of the same file with these further overrides, e.g.
        /// `--compare-set circuit.state=closed`. Repeatable.
        #[arg(long = "compare-set", value_name = "KEY=VALUE")]
        compare_set: Vec<String>,
        /// Print a timing line (wall time, time per point, threads).
        #[arg(long)]
        timing: bool,
    },
    /// Catalogue of instability regions in a φ range: start, onset, edges and width at a
    /// load level, stable bands; with --out also the tracked boundaries (regions.json).
    Regions {
        #[command(flatten)]
        input: Input,
        /// φ range A:B (rad/s).
        #[arg(long)]
        phi: String,
        /// Highest load coefficient searched.
        #[arg(long = "beta-max", default_value_t = 1.0)]
        beta_max: f64,
        /// Level β_op of the edges and stable bands (default: beta-max).
        #[arg(long)]
        level: Option<f64>,
        /// Print JSON instead of a table.
        #[arg(long)]
        json: bool,
        /// Also track boundaries and write regions.json (and plots) to this directory.
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// The stable band at load level β_op that contains the operating frequency φ_op.
    Band {
        #[command(flatten)]
        input: Input,
        /// Operating excitation frequency φ_op (rad/s).
        #[arg(long = "phi-op")]
        phi_op: f64,
        /// Load level β_op (> 0).
        #[arg(long)]
        level: f64,
        /// φ window A:B searched (rad/s); default φ_op/20 to 20·φ_op.
        #[arg(long)]
        phi: Option<String>,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Optimise the shunt circuit for the file's [design] table and write the tuned-parameter
    /// report (report.md, report.json), tuned.toml and plots.
    Design {
        #[command(flatten)]
        input: Input,
        /// Output directory (created if missing).
        #[arg(long)]
        out: PathBuf,
    },
    /// Run a batch study (STUDY.toml: a base problem and a list or sweep of cases), in
    /// parallel, with per-case reports and a summary; finished cases are skipped on re-runs.
    Study {
        /// The study file.
        file: PathBuf,
        /// Output directory (created if missing).
        #[arg(long)]
        out: PathBuf,
        /// Recompute cases that are already finished.
        #[arg(long)]
        force: bool,
        /// Use an --out folder that holds other files: the study writes beside them and
        /// never changes, replaces or deletes any of them.
        #[arg(long = "allow-non-empty")]
        allow_non_empty: bool,
    },
    /// Time response (Eq. 29) of the reduced model with unbalance at one (φ, β).
    Response {
        #[command(flatten)]
        input: Input,
        #[command(flatten)]
        point: Point,
        /// Number of load periods to simulate.
        #[arg(long, default_value_t = 50)]
        periods: usize,
        /// Output directory (created if missing).
        #[arg(long)]
        out: PathBuf,
    },
}

/// An indicatif bar on standard error (hidden when it is not a terminal).
struct Bar(ProgressBar);

impl Progress for Bar {
    fn start(&self, len: u64, what: &str) {
        self.0.set_length(len);
        self.0.set_message(what.to_string());
        self.0.reset_eta();
    }
    fn tick(&self) {
        self.0.inc(1);
    }
    fn finish(&self) {
        self.0.finish_and_clear();
    }
}

fn bar() -> Bar {
    let pb = ProgressBar::new(0);
    if let Ok(style) = ProgressStyle::with_template("{msg:>10} [{bar:40}] {pos}/{len} ({eta})") {
        pb.set_style(style.progress_chars("=> "));
    }
    Bar(pb)
}

fn load(input: &Input) -> Result<Problem, rotorshunt::Error> {
    Ok(Problem::from_path(&input.file, &input.set)?)
}

/// Exit codes (docs/errors.md): 0 a result, 1 an analysis failure, 2 bad input, 3 an
/// infeasible design, 4 a design that failed its verification, 5 a study with failed
/// cases.
mod exit {
    pub const INFEASIBLE: u8 = 3;
    pub const NOT_VERIFIED: u8 = 4;
    pub const STUDY_FAILED_CASES: u8 = 5;
}

/// The text for standard output and the exit code of a run that produced output.
fn run(cli: Cli) -> Result<(String, u8), rotorshunt::Error> {
    let plain = |r: Result<String, rotorshunt::Error>| r.map(|t| (t, 0));
    let budget = Budget::new(cli.max_cost).map_err(|e| rotorshunt::Error::parameter("--max-cost", &e))?;
    match cli.command {
        Command::Check { input } => plain(commands::check(&load(&input)?, budget)),
        Command::Modes { input, speed, count, json } => {
            plain(commands::modes(&load(&input)?, speed, count, json, budget))
        }
        Command::Campbell { input, speeds, count, out } => {
            plain(commands::campbell_cmd(&load(&input)?, &speeds, count, &out, &bar(), budget))
        }
        Command::Floquet { input, point, json } => {
            plain(commands::floquet_cmd(&load(&input)?, point.phi, point.beta, json, budget))
        }
        Command::Chart { input, phi, beta, out, compare, compare_set, timing } => {
            let problem = load(&input)?;
            let other = match (&compare, compare_set.is_empty()) {
                (Some(path), _) => Some(Problem::from_path(path, &input.set)?),
                (None, false) => {
                    let all: Vec<String> = input.set.iter().chain(&compare_set).cloned().collect();
                    Some(Problem::from_path(&input.file, &all)?)
                }
                (None, true) => None,
            };
            let label = match (&compare, &other) {
                (Some(_), Some(o)) => o.data.title.clone().unwrap_or_else(|| o.file.clone()),
                (_, Some(o)) => {
                    // The compare problem carries the main --set overrides too: name it by
                    // its state and the --compare-set overrides only.
                    let only = Problem { overrides: compare_set.clone(), ..o.clone() };
                    commands::layer_name(&only)
                }
                _ => String::new(),
            };
            let cmp = match &other {
                Some(o) => commands::Compare::Problem(&label, o),
                None => commands::Compare::None,
            };
            plain(commands::chart_cmd(&problem, &phi, &beta, &out, cmp, timing, &bar(), budget))
        }
        Command::Regions { input, phi, beta_max, level, json, out } => {
            plain(commands::regions_cmd(&load(&input)?, &phi, beta_max, level, json, out.as_deref(), budget))
        }
        Command::Band { input, phi_op, level, phi, json } => {
            plain(commands::band_cmd(&load(&input)?, phi_op, level, phi.as_deref(), json, budget))
        }
        Command::Design { input, out } => {
            let (text, outcome) = commands::design_cmd(&load(&input)?, &out, &bar(), budget)?;
            let code = match outcome.status {
                rotorshunt::design::Status::Infeasible => exit::INFEASIBLE,
                rotorshunt::design::Status::NotVerified => exit::NOT_VERIFIED,
                _ => 0,
            };
            Ok((text, code))
        }
        Command::Study { file, out, force, allow_non_empty } => {
            let options = commands::StudyOptions { force, allow_non_empty, budget };
            let (text, failed) = commands::study_cmd(&file, &out, options, &bar())?;
            if failed > 0 {
                // Scripts read the status; a person reads why on stderr, after the summary.
                eprintln!(
                    "error: {failed} case(s) of the study failed: their errors are in {}",
                    out.join("summary.md").display()
                );
            }
            Ok((text, if failed > 0 { exit::STUDY_FAILED_CASES } else { 0 }))
        }
        Command::Response { input, point, periods, out } => {
            plain(commands::response_cmd(&load(&input)?, point.phi, point.beta, periods, &out, budget))
        }
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok((text, code)) => {
            print!("{text}");
            ExitCode::from(code)
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(match e {
                rotorshunt::Error::Problem(_)
                | rotorshunt::Error::Argument { .. }
                | rotorshunt::Error::Parameter { .. }
                | rotorshunt::Error::Cost(_)
                | rotorshunt::Error::Analysis(rotorshunt::analysis::AnalysisError::Request(_))
                | rotorshunt::Error::Study { .. }
                | rotorshunt::Error::StudyTooLarge { .. }
                | rotorshunt::Error::FolderNotEmpty { .. }
                | rotorshunt::Error::NotOwned { .. }
                | rotorshunt::Error::OtherStudy { .. }
                | rotorshunt::Error::StudyLocked { .. }
                | rotorshunt::Error::OutputIsInput { .. }
                | rotorshunt::Error::Design(
                    rotorshunt::design::DesignError::NoDesign
                    | rotorshunt::design::DesignError::Candidate(_)
                    | rotorshunt::design::DesignError::Spec { .. },
                ) => 2,
                _ => 1,
            })
        }
    }
}
