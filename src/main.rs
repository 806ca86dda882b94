//! `rotorshunt` command line: parse arguments, load the problem, run, print, exit code.

mod reporter;

use clap::{Args, Parser, Subcommand};
use reporter::Reporter;
use rotorshunt::analysis::cost::Budget;
use rotorshunt::commands;
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
    /// Report no progress on standard error (by default: a bar on a terminal; otherwise,
    /// from a run's fifth second on, a line every 5 s and at each phase).
    #[arg(long, global = true)]
    quiet: bool,
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
    /// `study plan|status|merge|slurm` list, inspect, summarise and submit a study split
    /// into shards (README, "Running a study on a cluster").
    Study(StudyArgs),
    /// Convert a rotor saved by ROSS (`Rotor.save`, TOML or JSON) into a problem file: shaft
    /// elements to sections, disks, isotropic bearings to plain bearings (docs/ross-format.md).
    /// Elements rotorshunt cannot represent are refused, naming the element (exit 2).
    #[command(name = "import-ross")]
    ImportRoss {
        /// The ROSS file (`.toml` or `.json`).
        file: PathBuf,
        /// The problem file to write; an existing file is refused unless --force.
        #[arg(long)]
        out: PathBuf,
        /// Speed Ω (rad/s): the problem's `speed`, and where speed-dependent bearing
        /// coefficients are evaluated (frequency = speed, as ROSS's run_modal); default 0,
        /// and tabulated bearings refused.
        #[arg(long)]
        speed: Option<f64>,
        /// Replace an existing --out file.
        #[arg(long)]
        force: bool,
    },
    /// Steady-state unbalance response (one complex solve per speed, static load αP_cr
    /// included) at the disks, the supports and chosen nodes: amplitude (m), phase (rad),
    /// peaks and their API 684 amplification factors; JSON, CSV and a Bode plot in DIR.
    Unbalance {
        #[command(flatten)]
        input: Input,
        /// Speeds A:B:STEP (rad/s).
        #[arg(long)]
        speeds: String,
        /// Shaft nodes reported besides the disks and supports, e.g. `3,16` (0 = left end).
        #[arg(long, default_value = "")]
        nodes: String,
        /// Output directory (created if missing).
        #[arg(long)]
        out: PathBuf,
        /// Print the JSON instead of the table of peaks.
        #[arg(long)]
        json: bool,
        /// Overlay the response of a second problem file (drawn dashed).
        #[arg(long, conflicts_with = "compare_set")]
        compare: Option<PathBuf>,
        /// Overlay the response of the same file with these further overrides, e.g.
        /// `--compare-set circuit.state=open`. Repeatable.
        #[arg(long = "compare-set", value_name = "KEY=VALUE")]
        compare_set: Vec<String>,
    },
    /// Damping ratios ζ of whirl modes over a speed range, tracked by MAC: the modes named
    /// by their tag at the first speed (`--modes f1,fr1`), or the lowest N of each whirl.
    Damping {
        #[command(flatten)]
        input: Input,
        /// Speeds A:B:STEP (rad/s).
        #[arg(long)]
        speeds: String,
        /// Mode tags at the first speed, e.g. `f1,b1,fr1` (as `modes` and `campbell` name them).
        #[arg(long, default_value = "")]
        modes: String,
        /// Without --modes: the number of forward and of backward whirls.
        #[arg(long, default_value_t = 4)]
        count: usize,
        /// Print JSON instead of a table.
        #[arg(long)]
        json: bool,
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

/// `rotorshunt study STUDY.toml --out DIR …`, or one of its subcommands.
#[derive(Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
struct StudyArgs {
    #[command(subcommand)]
    action: Option<StudyAction>,
    /// The study file.
    #[arg(required = true)]
    file: Option<PathBuf>,
    /// Output directory (created if missing).
    #[arg(long, required = true)]
    out: Option<PathBuf>,
    /// Recompute cases that are already finished.
    #[arg(long)]
    force: bool,
    /// Use an --out folder that holds other files: the study writes beside them and
    /// never changes, replaces or deletes any of them.
    #[arg(long = "allow-non-empty")]
    allow_non_empty: bool,
    /// Run only shard K of N, 0-based (0/N to N-1/N; `study plan --shards N` lists them),
    /// and write no summary (`study merge DIR` does). Shards of one plan may run at once
    /// into one --out folder, on any machines that share it.
    #[arg(long, value_name = "K/N", conflicts_with = "shards")]
    shard: Option<String>,
    /// Run shard SLURM_ARRAY_TASK_ID of N (what `study slurm`'s job script passes). Inside
    /// a Slurm array task without --shard or --shards, N is the count the --out folder
    /// records.
    #[arg(long, value_name = "N")]
    shards: Option<String>,
    /// Print the cases this run would do (with a shard: that shard's) and write nothing.
    #[arg(long = "dry-run")]
    dry_run: bool,
}

#[derive(Subcommand)]
enum StudyAction {
    /// List the plan: every case's index, id (folder name and a hash of its overrides),
    /// kind and, with --shards, its shard.
    Plan {
        /// The study file.
        file: PathBuf,
        /// Also assign the cases to N shards.
        #[arg(long, value_name = "N")]
        shards: Option<String>,
        /// Print JSON instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// Count the cases of a study folder that are done, failed, missing and running, and
    /// print the shards to rerun as a Slurm --array list and as --shard values. Writes
    /// nothing. Exit 0 when every case is done, 5 otherwise.
    Status {
        /// The study's --out folder.
        dir: PathBuf,
        /// Count shards of N (default: the count the folder records, else 1).
        #[arg(long, value_name = "N")]
        shards: Option<String>,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Write summary.{csv,json,md} from every finished case of a study folder; can run at
    /// any time, even while shards run. Exit 0 when every case is done, 5 otherwise.
    Merge {
        /// The study's --out folder.
        dir: PathBuf,
    },
    /// Write a Slurm array job of N tasks (one shard each) and a merge job that runs after
    /// it (--dependency=afterany) into DIR/slurm/, and with --submit submit them.
    Slurm {
        /// The study file.
        file: PathBuf,
        /// The study's output directory (created if missing), on a filesystem every node sees.
        #[arg(long)]
        out: PathBuf,
        /// Array tasks, one shard each (at most the number of cases).
        #[arg(long, value_name = "N")]
        tasks: String,
        /// Slurm partition of both jobs (#SBATCH --partition).
        #[arg(long)]
        partition: Option<String>,
        /// Time limit of each job in Slurm's forms, e.g. 2:00:00 (#SBATCH --time).
        #[arg(long)]
        time: Option<String>,
        /// CPUs of each array task, and so its threads (#SBATCH --cpus-per-task).
        #[arg(long = "cpus-per-task", default_value_t = 2)]
        cpus_per_task: u32,
        /// Submit the two jobs with sbatch.
        #[arg(long)]
        submit: bool,
        /// The sbatch program.
        #[arg(long, default_value = "sbatch")]
        sbatch: String,
        /// Use an --out folder that holds other files (never changed).
        #[arg(long = "allow-non-empty")]
        allow_non_empty: bool,
    },
}

/// The shard count of `--shards`/`--tasks`.
fn count(source: &str, text: Option<&str>) -> Result<Option<u32>, rotorshunt::Error> {
    text.map(|t| match t.trim().parse::<u32>() {
        Ok(n) if (1..=commands::MAX_SHARDS).contains(&n) => Ok(n),
        _ => Err(rotorshunt::Error::Shard {
            source_name: source.into(),
            value: t.into(),
            message: format!("the number of shards must be a whole number from 1 to {}", commands::MAX_SHARDS),
        }),
    })
    .transpose()
}

fn study(args: StudyArgs, budget: Budget, progress: &Reporter) -> Result<(String, u8), rotorshunt::Error> {
    let done = |r: &commands::StatusReport| if r.done == r.cases { 0 } else { exit::STUDY_FAILED_CASES };
    match args.action {
        Some(StudyAction::Plan { file, shards, json }) => {
            Ok((commands::plan_cmd(&file, count("--shards", shards.as_deref())?, json)?, 0))
        }
        Some(StudyAction::Status { dir, shards, json }) => {
            let (text, r) = commands::status_cmd(&dir, count("--shards", shards.as_deref())?, json)?;
            Ok((text, done(&r)))
        }
        Some(StudyAction::Merge { dir }) => {
            let (text, r) = commands::merge_cmd(&dir)?;
            Ok((text, done(&r)))
        }
        Some(StudyAction::Slurm {
            file,
            out,
            tasks,
            partition,
            time,
            cpus_per_task,
            submit,
            sbatch,
            allow_non_empty,
        }) => {
            let tasks = count("--tasks", Some(&tasks))?.unwrap_or(1);
            let binary = std::env::current_exe().map_err(|e| rotorshunt::Error::Argument {
                argument: "study slurm".into(),
                message: format!("cannot find this program's own path for the job scripts: {e}"),
            })?;
            let options = commands::SlurmOptions {
                tasks,
                partition,
                time,
                cpus_per_task,
                submit,
                sbatch,
                allow_non_empty,
                binary,
            };
            Ok((commands::slurm_cmd(&file, &out, &options)?, 0))
        }
        None => {
            // clap requires both without a subcommand.
            let (Some(file), Some(out)) = (args.file, args.out) else {
                return Err(rotorshunt::Error::Argument {
                    argument: "study".into(),
                    message: "give a study file and --out DIR".into(),
                });
            };
            let shard = match (args.shard, count("--shards", args.shards.as_deref())?) {
                (Some(s), _) => commands::ShardRequest::Shard(commands::Shard::parse(&s)?),
                (None, Some(n)) => commands::ShardRequest::Count(n),
                (None, None) => commands::ShardRequest::Auto,
            };
            let options = commands::StudyOptions {
                force: args.force,
                allow_non_empty: args.allow_non_empty,
                shard,
                array_task_id: std::env::var_os("SLURM_ARRAY_TASK_ID").map(|v| v.to_string_lossy().into_owned()),
                dry_run: args.dry_run,
                budget,
            };
            let (text, failed) = commands::study_cmd(&file, &out, options, progress)?;
            if failed > 0 {
                // Scripts read the status; a person reads why on stderr, after the summary.
                let place = if text.starts_with("study: shard ") {
                    format!("{} (and in `rotorshunt study status {}`)", out.join("cases").display(), out.display())
                } else {
                    out.join("summary.md").display().to_string()
                };
                eprintln!("error: {failed} case(s) of the study failed: their errors are in {place}");
            }
            Ok((text, if failed > 0 { exit::STUDY_FAILED_CASES } else { 0 }))
        }
    }
}

/// Inside a Slurm job that asked for `--cpus-per-task`, rayon's threads follow
/// `SLURM_CPUS_PER_TASK` (Slurm sets it; rayon alone would use every CPU of the node).
/// `RAYON_NUM_THREADS`, if set, wins; a value that is not a positive count is ignored.
fn threads_from_slurm() {
    if std::env::var_os("RAYON_NUM_THREADS").is_some_and(|v| !v.is_empty()) {
        return;
    }
    if let Some(n) = std::env::var("SLURM_CPUS_PER_TASK").ok().and_then(|v| v.trim().parse::<usize>().ok()) {
        if n >= 1 {
            let _ = rayon::ThreadPoolBuilder::new().num_threads(n).build_global();
        }
    }
}

/// The progress reporter of a command: its name and phases, or none for the quick ones.
fn reporter(cli: &Cli) -> Reporter {
    let (name, plan): (&'static str, &[&'static str]) = match &cli.command {
        Command::Campbell { .. } => ("campbell", &["whirls", "files"]),
        Command::Chart { compare, compare_set, .. } if compare.is_some() || !compare_set.is_empty() => {
            ("chart", &["chart", "compare", "files"])
        }
        Command::Chart { .. } => ("chart", &["chart", "files"]),
        Command::Regions { out: Some(_), .. } => ("regions", &["catalogue", "chart", "files"]),
        Command::Regions { .. } => ("regions", &["catalogue"]),
        Command::Band { .. } => ("band", &["band"]),
        Command::Design { .. } => ("design", &["optimise", "verification", "report"]),
        Command::Study(StudyArgs { action: None, .. }) => ("study", &["cases"]),
        Command::Response { .. } => ("response", &["response", "files"]),
        _ => return Reporter::Quiet,
    };
    Reporter::new(cli.quiet, name, plan)
}

/// On SIGINT or SIGTERM, remove the unfinished output folders of this run, then end as
/// the signal would have ended it (the same exit status).
#[cfg(unix)]
fn remove_outputs_on_signals() {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM]) else { return };
    let _ = std::thread::Builder::new().name("signals".into()).spawn(move || {
        if let Some(signal) = signals.forever().next() {
            commands::remove_unfinished();
            let _ = signal_hook::low_level::emulate_default_handler(signal);
            std::process::exit(128 + signal);
        }
    });
}

#[cfg(not(unix))]
fn remove_outputs_on_signals() {}

/// Load the problem and print its plausibility warnings on standard error.
fn load(input: &Input) -> Result<Problem, rotorshunt::Error> {
    let problem = Problem::from_path(&input.file, &input.set)?;
    warn(&problem);
    Ok(problem)
}

/// Print a problem's plausibility warnings on standard error, one line each.
fn warn(problem: &Problem) {
    for w in &problem.warnings {
        eprintln!("warning: {w}");
    }
}

/// The configuration of `--compare FILE2` (with the main `--set` overrides) or
/// `--compare-set` (the main file with both sets of overrides), and its legend name: the
/// compared file's title, or its circuit state and the `--compare-set` overrides.
fn compared(
    input: &Input,
    compare: Option<&std::path::Path>,
    compare_set: &[String],
    main: &Problem,
) -> Result<(String, Option<Problem>), rotorshunt::Error> {
    let other = match (compare, compare_set.is_empty()) {
        (Some(path), _) => Some(Problem::from_path(path, &input.set)?),
        (None, false) => {
            let all: Vec<String> = input.set.iter().chain(compare_set).cloned().collect();
            Some(Problem::from_path(&input.file, &all)?)
        }
        (None, true) => None,
    };
    // The compared configuration's warnings that the main one has not printed.
    if let Some(o) = &other {
        for w in o.warnings.iter().filter(|w| !main.warnings.iter().any(|m| m.key == w.key && m.kind == w.kind)) {
            eprintln!("warning: {w}");
        }
    }
    let label = match (compare, &other) {
        (Some(_), Some(o)) => o.data.title.clone().unwrap_or_else(|| o.file.clone()),
        (_, Some(o)) => {
            // The compare problem carries the main --set overrides too: name it by
            // its state and the --compare-set overrides only.
            let only = Problem { overrides: compare_set.to_vec(), ..o.clone() };
            commands::layer_name(&only)
        }
        _ => String::new(),
    };
    Ok((label, other))
}

/// Exit codes (docs/errors.md): 0 a result, 1 an analysis failure, 2 bad input, 3 an
/// infeasible design, 4 a design that failed its verification, 5 a study with failed
/// cases (`study status` and `study merge`: a case not done).
mod exit {
    pub const INFEASIBLE: u8 = 3;
    pub const NOT_VERIFIED: u8 = 4;
    pub const STUDY_FAILED_CASES: u8 = 5;
}

/// The text for standard output and the exit code of a run that produced output.
fn run(cli: Cli, progress: &Reporter) -> Result<(String, u8), rotorshunt::Error> {
    let plain = |r: Result<String, rotorshunt::Error>| r.map(|t| (t, 0));
    let budget = Budget::new(cli.max_cost).map_err(|e| rotorshunt::Error::parameter("--max-cost", &e))?;
    match cli.command {
        Command::Check { input } => plain(commands::check(&load(&input)?, budget)),
        Command::Modes { input, speed, count, json } => {
            plain(commands::modes(&load(&input)?, speed, count, json, budget))
        }
        Command::Campbell { input, speeds, count, out } => {
            plain(commands::campbell_cmd(&load(&input)?, &speeds, count, &out, progress, budget))
        }
        Command::Floquet { input, point, json } => {
            plain(commands::floquet_cmd(&load(&input)?, point.phi, point.beta, json, budget))
        }
        Command::Chart { input, phi, beta, out, compare, compare_set, timing } => {
            let problem = load(&input)?;
            let (label, other) = compared(&input, compare.as_deref(), &compare_set, &problem)?;
            let cmp = match &other {
                Some(o) => commands::Compare::Problem(&label, o),
                None => commands::Compare::None,
            };
            let args = commands::ChartArgs { phi: &phi, beta: &beta, compare: cmp, timing };
            plain(commands::chart_cmd(&problem, args, &out, progress, budget))
        }
        Command::Unbalance { input, speeds, nodes, out, json, compare, compare_set } => {
            let problem = load(&input)?;
            let (label, other) = compared(&input, compare.as_deref(), &compare_set, &problem)?;
            let cmp = match &other {
                Some(o) => commands::Compare::Problem(&label, o),
                None => commands::Compare::None,
            };
            let args = commands::UnbalanceArgs { speeds: &speeds, nodes: &nodes, compare: cmp, json };
            plain(commands::unbalance_cmd(&problem, args, &out, progress, budget))
        }
        Command::Damping { input, speeds, modes, count, json } => {
            plain(commands::damping_cmd(&load(&input)?, &speeds, &modes, count, json, progress, budget))
        }
        Command::Regions { input, phi, beta_max, level, json, out } => {
            let args = commands::RegionsArgs { phi: &phi, beta_max, level, json, out: out.as_deref() };
            plain(commands::regions_cmd(&load(&input)?, args, progress, budget))
        }
        Command::Band { input, phi_op, level, phi, json } => {
            plain(commands::band_cmd(&load(&input)?, phi_op, level, phi.as_deref(), json, progress, budget))
        }
        Command::Design { input, out } => {
            let (text, outcome) = commands::design_cmd(&load(&input)?, &out, progress, budget)?;
            let code = match outcome.status {
                rotorshunt::design::Status::Infeasible => exit::INFEASIBLE,
                rotorshunt::design::Status::NotVerified => exit::NOT_VERIFIED,
                _ => 0,
            };
            Ok((text, code))
        }
        Command::Study(args) => study(args, budget, progress),
        Command::ImportRoss { file, out, speed, force } => plain(commands::import_ross_cmd(&file, &out, speed, force)),
        Command::Response { input, point, periods, out } => {
            plain(commands::response_cmd(&load(&input)?, point.phi, point.beta, periods, &out, progress, budget))
        }
    }
}

fn main() -> ExitCode {
    threads_from_slurm();
    remove_outputs_on_signals();
    let cli = Cli::parse();
    let progress = reporter(&cli);
    let result = run(cli, &progress);
    progress.finish();
    match result {
        Ok((text, code)) => {
            print!("{text}");
            ExitCode::from(code)
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(match e {
                rotorshunt::Error::Problem(_)
                | rotorshunt::Error::Ross(_)
                | rotorshunt::Error::OutputExists { .. }
                | rotorshunt::Error::Argument { .. }
                | rotorshunt::Error::Parameter { .. }
                | rotorshunt::Error::Cost(_)
                | rotorshunt::Error::Analysis(
                    rotorshunt::analysis::AnalysisError::Request(_)
                    | rotorshunt::analysis::AnalysisError::ProbeNodeOffShaft { .. }
                    | rotorshunt::analysis::AnalysisError::NoSpeeds
                    | rotorshunt::analysis::AnalysisError::SpeedsNotAscending { .. }
                    | rotorshunt::analysis::AnalysisError::UnknownMode { .. },
                )
                | rotorshunt::Error::Study { .. }
                | rotorshunt::Error::StudyTooLarge { .. }
                | rotorshunt::Error::FolderNotEmpty { .. }
                | rotorshunt::Error::NotOwned { .. }
                | rotorshunt::Error::OtherStudy { .. }
                | rotorshunt::Error::StudyLocked { .. }
                | rotorshunt::Error::Shard { .. }
                | rotorshunt::Error::PlanMismatch { .. }
                | rotorshunt::Error::NotAStudyFolder { .. }
                | rotorshunt::Error::SlurmMissing { .. }
                | rotorshunt::Error::OutputIsInput { .. }
                | rotorshunt::Error::OutIsNotAFolder { .. }
                | rotorshunt::Error::Design(
                    rotorshunt::design::DesignError::NoDesign
                    | rotorshunt::design::DesignError::Candidate { .. }
                    | rotorshunt::design::DesignError::Spec { .. },
                ) => 2,
                _ => 1,
            })
        }
    }
}
