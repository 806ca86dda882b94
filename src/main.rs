//! `rotorshunt` command line: parse arguments, load the problem, run, print, exit code.

// No panics on data (docs/invariants.md): clippy refuses `unwrap`, `expect`, `panic!`,
// `unreachable!`, `todo!`, `unimplemented!`, the `assert` family and `unwrap_unchecked`
// (the last two listed in clippy.toml) outside tests; the few calls that hold by
// construction carry `#[expect(…, reason = "…")]` at the call.
#![cfg_attr(
    not(test),
    deny(
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::panic,
        clippy::unreachable,
        clippy::todo,
        clippy::unimplemented,
        clippy::disallowed_macros,
        clippy::disallowed_methods
    )
)]

mod cli;
// The command layer, shared with the Python bindings (see src/lib.rs).
mod commands;
mod reporter;

use clap::Parser;
use cli::{Cli, Command, Input, StudyAction, StudyArgs};
use reporter::{printable, Reporter};
use rotorshunt::problem::Problem;
use rotorshunt::run::Budget;
use std::process::ExitCode;

/// The shard count of `--shards`/`--tasks`.
fn count(source: &str, text: Option<&str>) -> Result<Option<u32>, crate::commands::Error> {
    text.map(|t| match t.trim().parse::<u32>() {
        Ok(n) if (1..=commands::MAX_SHARDS).contains(&n) => Ok(n),
        _ => Err(crate::commands::Error::Shard {
            source_name: source.into(),
            value: t.into(),
            message: format!("the number of shards must be a whole number from 1 to {}", commands::MAX_SHARDS),
        }),
    })
    .transpose()
}

fn study(args: StudyArgs, budget: Budget, progress: &Reporter) -> Result<(String, u8), crate::commands::Error> {
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
            let (text, r) = commands::merge_cmd(&dir, progress)?;
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
            let binary = std::env::current_exe().map_err(|e| crate::commands::Error::Argument {
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
                budget,
            };
            Ok((commands::slurm_cmd(&file, &out, &options)?, 0))
        }
        None => {
            // clap requires both without a subcommand.
            let (Some(file), Some(out)) = (args.file, args.out) else {
                return Err(crate::commands::Error::Argument {
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
                    out.join("summary").join("summary.md").display().to_string()
                };
                eprintln!("error: {failed} case(s) of the study failed: their errors are in {}", printable(&place));
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
        Command::Band { .. } => ("band", &["band", "margins"]),
        Command::Design { pareto: Some(_), .. } => ("design", &["front", "report"]),
        Command::Design { .. } => ("design", &["basis", "optimise", "verification", "report"]),
        Command::Study(StudyArgs { action: None, .. }) => ("study", &["cases"]),
        Command::Response { .. } => ("response", &["floquet point", "response", "files"]),
        _ => return Reporter::Quiet,
    };
    Reporter::new(cli.quiet, name, plan, progress_every())
}

/// Test-only: `ROTORSHUNT_TEST_PROGRESS_EVERY=N` makes the progress lines of a run whose
/// standard error is not a terminal also print each time a phase's done count passes a
/// multiple of N (tests/progress.rs: the count is seen to rise on any machine, however
/// fast, where the lines every 5 s would need a run longer than 5 s).
fn progress_every() -> Option<u64> {
    std::env::var("ROTORSHUNT_TEST_PROGRESS_EVERY").ok().and_then(|v| v.trim().parse::<u64>().ok()).filter(|&n| n > 0)
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
fn load(input: &Input) -> Result<Problem, crate::commands::Error> {
    let problem = Problem::from_path(&input.file, &input.set)?;
    warn(&problem);
    Ok(problem)
}

/// Print a problem's plausibility warnings on standard error, one line each.
fn warn(problem: &Problem) {
    for w in &problem.warnings {
        eprintln!("warning: {}", printable(&w.to_string()));
    }
}

/// The `--compare`/`--compare-set` configuration, its warnings that the main problem has
/// not printed printed on standard error.
fn compared(
    input: &Input,
    compare: Option<&std::path::Path>,
    compare_set: &[String],
    main: &Problem,
) -> Result<Option<commands::Compared>, crate::commands::Error> {
    let other = commands::compared(&input.file, &input.set, compare, compare_set)?;
    for w in other.iter().flat_map(|o| o.new_warnings(main)) {
        eprintln!("warning: {}", printable(&w.to_string()));
    }
    Ok(other)
}

/// Exit codes (docs/errors.md): 0 a result, 1 an analysis failure, 2 bad input, 3 an
/// infeasible design, 4 a design that failed its verification, 5 a study with failed
/// cases (`study status` and `study merge`: a case not done), 6 a design that is not
/// robust; 7 a design stopped while it ran (its best design so far written); 7 for any
/// other run stopped at its limits is its error's (`commands::Error::exit_code`).
mod exit {
    pub const INFEASIBLE: u8 = 3;
    pub const NOT_VERIFIED: u8 = 4;
    pub const STUDY_FAILED_CASES: u8 = 5;
    pub const NOT_ROBUST: u8 = 6;
    /// A design stopped while it ran, its best design so far written.
    pub const STOPPED: u8 = 7;
}

/// The text for standard output and the exit code of a run that produced output.
fn run(cli: Cli, progress: &Reporter) -> Result<(String, u8), crate::commands::Error> {
    let plain = |r: Result<String, crate::commands::Error>| r.map(|t| (t, 0));
    let budget = Budget::new(cli.max_cost).map_err(|e| crate::commands::Error::parameter("--max-cost", &e))?;
    // A study's cases share the threads: a case's wall time includes the other cases'
    // work its threads take on while they wait, so only a limit asked for applies to
    // them (docs/errors.md, `TimeLimit`); every other command has the estimate's.
    let budget = match (cli.time_limit, &cli.command) {
        (Some(seconds), _) => {
            budget.with_time_limit(seconds).map_err(|e| crate::commands::Error::parameter("--time-limit", &e))?
        }
        (None, Command::Study(_)) => budget,
        (None, _) => budget.with_estimate_time_limit(),
    };
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
            let other = compared(&input, compare.as_deref(), &compare_set, &problem)?;
            let cmp = commands::Compare::of(other.as_ref());
            let args = commands::ChartArgs { phi: &phi, beta: &beta, compare: cmp, timing };
            plain(commands::chart_cmd(&problem, args, &out, progress, budget))
        }
        Command::Unbalance { input, speeds, nodes, out, json, compare, compare_set } => {
            let problem = load(&input)?;
            let other = compared(&input, compare.as_deref(), &compare_set, &problem)?;
            let cmp = commands::Compare::of(other.as_ref());
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
        Command::Design { input, out, pareto: Some(k) } => {
            let (text, report) = commands::pareto_cmd(&load(&input)?, k as usize, &out, progress, budget)?;
            Ok((text, if report.front.verified() { 0 } else { exit::NOT_VERIFIED }))
        }
        Command::Design { input, out, pareto: None } => {
            let (text, outcome) = commands::design_cmd(&load(&input)?, &out, progress, budget)?;
            let code = match outcome.status {
                rotorshunt::design::Status::Infeasible => exit::INFEASIBLE,
                rotorshunt::design::Status::NotVerified => exit::NOT_VERIFIED,
                rotorshunt::design::Status::NotRobust => exit::NOT_ROBUST,
                rotorshunt::design::Status::Stopped => exit::STOPPED,
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

/// Test-only: `ROTORSHUNT_TEST_KILL_AT=N` makes the process kill itself with SIGKILL at
/// the N-th write, rename or removal of the file layer (tests/kill_points.rs), to show
/// that an interruption anywhere leaves every output folder old or new, never mixed;
/// `ROTORSHUNT_TEST_FULL_DISK=NAME` makes every write of a file named NAME fail as on a
/// full disk (tests/records.rs).
fn arm_fault_injection() {
    if let Some(n) = std::env::var("ROTORSHUNT_TEST_KILL_AT").ok().and_then(|v| v.trim().parse::<u64>().ok()) {
        rotorshunt::files::fault::arm(n);
    }
    if let Some(name) = std::env::var("ROTORSHUNT_TEST_FULL_DISK").ok().filter(|n| !n.is_empty()) {
        rotorshunt::files::fault::arm_full_disk(&name);
    }
}

fn main() -> ExitCode {
    threads_from_slurm();
    remove_outputs_on_signals();
    arm_fault_injection();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => parse_failed(e),
    };
    let progress = reporter(&cli);
    let result = run(cli, &progress);
    progress.finish();
    match result {
        Ok((text, code)) => {
            print!("{}", printable(&text));
            ExitCode::from(code)
        }
        Err(e) => {
            eprintln!("error: {}", printable(&e.to_string()));
            ExitCode::from(e.exit_code())
        }
    }
}

/// A command line clap refused (or `--help`, `--version`): clap's message and exit code,
/// the message plain and through [`printable`] when it quotes an argument with control
/// characters (clap would print them raw), else as clap styles it.
fn parse_failed(e: clap::Error) -> ! {
    let plain = e.to_string();
    if printable(&plain) == plain {
        e.exit()
    }
    if e.use_stderr() {
        eprint!("{}", printable(&plain));
    } else {
        print!("{}", printable(&plain));
    }
    std::process::exit(e.exit_code())
}
