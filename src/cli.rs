//! The command line's arguments (clap): the commands, their flags and their help texts.

// clap prints these doc comments as the help, unformatted: a TOML table's name in brackets
// (`[design]`) is text there, not a link to check.
#![allow(rustdoc::broken_intra_doc_links)]

use clap::{Args, Parser, Subcommand};
use std::path::PathBuf;

/// Parametric stability and shunt design of rotors on piezoelectric vibration rings.
/// All inputs and outputs are SI, frequencies and speeds in rad/s.
#[derive(Parser)]
#[command(name = "rotorshunt", version, about)]
pub(crate) struct Cli {
    #[command(subcommand)]
    pub(crate) command: Command,
    /// Allow FACTOR times the documented limits of work (5e13 floating-point operations)
    /// and memory (400 MiB of dense matrices) that every command checks its counted cost
    /// against before it starts (docs/errors.md, `Cost`), FACTOR times the default time
    /// limit, and the Floquet evaluations the region searches may make while they run
    /// (`CountLimit`), which scale with it.
    #[arg(long = "max-cost", value_name = "FACTOR", global = true, default_value_t = 1.0)]
    pub(crate) max_cost: f64,
    /// Stop a run still computing after SECONDS of wall time, at its next step (a chart
    /// row, a search, a speed, a design candidate), writing nothing: exit 7
    /// (docs/errors.md, `TimeLimit`). Measured on the machine that runs it; each case of a
    /// study has its own. Default: the time limit of --max-cost (FACTOR × 3600 s); none
    /// for a study's cases.
    #[arg(long = "time-limit", value_name = "SECONDS", global = true)]
    pub(crate) time_limit: Option<f64>,
    /// Report no progress on standard error (by default: a bar on a terminal; otherwise,
    /// from a run's fifth second on, a line every 5 s and at each phase).
    #[arg(long, global = true)]
    pub(crate) quiet: bool,
}

/// The problem file and its overrides, shared by every command.
#[derive(Args)]
pub(crate) struct Input {
    /// Problem file (TOML, format version 1; see problems/README.md).
    pub(crate) file: PathBuf,
    /// Override a value of the file, e.g. `--set circuit.state=open --set speed=1500
    /// --set circuit.branches[0].resistance=50`. Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub(crate) set: Vec<String>,
}

/// One point (φ, β) of the load P(t) = P_cr(α + β cos φt).
#[derive(Args)]
pub(crate) struct Point {
    /// Excitation frequency φ (rad/s).
    #[arg(long)]
    pub(crate) phi: f64,
    /// Dynamic load coefficient β.
    #[arg(long)]
    pub(crate) beta: f64,
}

#[derive(Subcommand)]
pub(crate) enum Command {
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
        #[arg(long, default_value_t = crate::commands::DEFAULT_WHIRL_COUNT)]
        count: usize,
        /// Print JSON instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// Campbell diagram over a speed range: CSV, JSON, SVG and PNG in DIR.
    Campbell {
        #[command(flatten)]
        input: Input,
        /// Speeds A:B:STEP in rad/s, or in rpm with the suffix `rpm` (0:30000:500rpm).
        #[arg(long)]
        speeds: String,
        /// Number of forward and of backward whirls to track.
        #[arg(long, default_value_t = crate::commands::DEFAULT_WHIRL_COUNT)]
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
        /// Trace the trade-off between the peak unbalance response and the stable band
        /// around phi_op with K verified designs, from the best damping to the widest band
        /// (tuned-1.toml … tuned-K.toml, the front's table and plot; docs/design.md).
        #[arg(long, value_name = "K", value_parser = clap::value_parser!(u64).range(rotorshunt::design::pareto::MIN_POINTS as u64..=rotorshunt::design::pareto::MAX_POINTS as u64))]
        pareto: Option<u64>,
    },
    /// Run a batch study (STUDY.toml: a base problem and a list or sweep of cases), in
    /// parallel, with per-case reports and a summary; finished cases are skipped on re-runs.
    /// `study plan|status|merge|slurm` list, inspect, summarise and submit a study split
    /// into shards (docs/cluster.md).
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
        /// Speeds A:B:STEP in rad/s, or in rpm with the suffix `rpm` (0:30000:500rpm).
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
        /// Speeds A:B:STEP in rad/s, or in rpm with the suffix `rpm` (0:30000:500rpm).
        #[arg(long)]
        speeds: String,
        /// Mode tags at the first speed, e.g. `f1,b1,fr1` (as `modes` and `campbell` name them).
        #[arg(long, default_value = "")]
        modes: String,
        /// Without --modes: the number of forward and of backward whirls.
        #[arg(long, default_value_t = crate::commands::DEFAULT_WHIRL_COUNT)]
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
pub(crate) struct StudyArgs {
    #[command(subcommand)]
    pub(crate) action: Option<StudyAction>,
    /// The study file.
    #[arg(required = true)]
    pub(crate) file: Option<PathBuf>,
    /// Output directory (created if missing).
    #[arg(long, required = true)]
    pub(crate) out: Option<PathBuf>,
    /// Recompute cases that are already finished.
    #[arg(long)]
    pub(crate) force: bool,
    /// Use an --out folder that holds other files: the study writes beside them and
    /// never changes, replaces or deletes any of them.
    #[arg(long = "allow-non-empty")]
    pub(crate) allow_non_empty: bool,
    /// Run only shard K of N, 0-based (0/N to N-1/N; `study plan --shards N` lists them),
    /// and write no summary (`study merge DIR` does). Shards of one plan may run at once
    /// into one --out folder, on any machines that share it.
    #[arg(long, value_name = "K/N", conflicts_with = "shards")]
    pub(crate) shard: Option<String>,
    /// Run shard SLURM_ARRAY_TASK_ID of N (what `study slurm`'s job script passes). Inside
    /// a Slurm array task without --shard or --shards, N is the count the --out folder
    /// records.
    #[arg(long, value_name = "N")]
    pub(crate) shards: Option<String>,
    /// Print the cases this run would do (with a shard: that shard's) and write nothing.
    #[arg(long = "dry-run")]
    pub(crate) dry_run: bool,
}

#[derive(Subcommand)]
pub(crate) enum StudyAction {
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
