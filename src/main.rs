//! `rotorshunt` command line: parse arguments, load the problem, run, print, exit code.

use clap::{Args, Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
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

fn run(cli: Cli) -> Result<String, rotorshunt::Error> {
    match cli.command {
        Command::Check { input } => commands::check(&load(&input)?),
        Command::Modes {
            input,
            speed,
            count,
            json,
        } => commands::modes(&load(&input)?, speed, count, json),
        Command::Campbell {
            input,
            speeds,
            count,
            out,
        } => commands::campbell_cmd(&load(&input)?, &speeds, count, &out, &bar()),
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(text) => {
            print!("{text}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(match e {
                rotorshunt::Error::Problem(_) | rotorshunt::Error::Argument { .. } => 2,
                _ => 1,
            })
        }
    }
}
