//! The command line's error: the layers' errors, and those of its arguments, out folders,
//! studies and Slurm. The library's own errors are the layers' (`ProblemError`,
//! `AnalysisError`, `DesignError`, `ImportError`).

use thiserror::Error;

/// Any failure of a command.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum Error {
    /// A problem file is unreadable or invalid.
    #[error(transparent)]
    Problem(#[from] rotorshunt::problem::ProblemError),
    /// A ROSS rotor file that cannot be imported (`import-ross`); boxed, as it is large
    /// and rare.
    #[error(transparent)]
    Ross(Box<rotorshunt::import::ross::RossError>),
    /// An import failure of a kind this command line does not know (the library's
    /// `ImportError` is non-exhaustive); boxed like [`Error::Ross`].
    #[error(transparent)]
    Import(Box<rotorshunt::import::ross::ImportError>),
    /// An analysis failed on valid input (e.g. a load at buckling).
    #[error("analysis failed: {0}")]
    Analysis(#[from] rotorshunt::analysis::AnalysisError),
    /// A design run failed.
    #[error("design failed: {0}")]
    Design(#[from] rotorshunt::design::DesignError),
    /// A study file is unreadable or invalid.
    #[error("study file {file}: {message}")]
    Study {
        /// The study file.
        file: String,
        /// What is wrong (with the key path).
        message: String,
    },
    /// Bad command-line argument: its form (range syntax), or a grid of too many points.
    #[error("argument `{argument}`: {message}")]
    Argument {
        /// The argument's name.
        argument: String,
        /// What is wrong.
        message: String,
    },
    /// A command-line value that breaks its parameter's rule
    /// ([`rotorshunt::analysis::limits`]): the same rule, and the same kind, as a problem or
    /// study file's key gives for that value.
    #[error("argument `{argument}`: {kind}")]
    Parameter {
        /// The argument's name, e.g. `--beta-max`.
        argument: String,
        /// The rule broken, as the file layer's kind (`NotFinite`, `NotPositive`,
        /// `Negative`, `OutOfRange`).
        kind: rotorshunt::problem::ProblemErrorKind,
    },
    /// A run refused before it started: its estimated time or memory is beyond the limit
    /// ([`rotorshunt::analysis::cost`]).
    #[error(transparent)]
    Cost(#[from] rotorshunt::run::CostError),
    /// A run stopped at its time limit while it ran ([`rotorshunt::progress::Deadline`]); nothing
    /// was written.
    #[error(transparent)]
    TimeLimit(#[from] rotorshunt::run::TimeLimitError),
    /// A run stopped at its allowance of monodromy evaluations while it ran, counted as
    /// the searches made them ([`rotorshunt::run::Budget::allowance`]); nothing
    /// was written.
    #[error(transparent)]
    CountLimit(#[from] rotorshunt::run::CountLimitError),
    /// A run its caller cancelled while it ran (the Python bindings' Ctrl-C,
    /// [`rotorshunt::run::CancelToken`]); nothing was kept.
    #[error("{what} was cancelled by its caller; nothing was kept")]
    Cancelled {
        /// What was cancelled.
        what: String,
    },
    /// Writing an output failed (including a read-only file, which is not replaced).
    #[error("cannot write {path}: {message}")]
    Output {
        /// The file or directory.
        path: String,
        /// Why.
        message: String,
    },
    /// A symbolic link, a FIFO, a device or a socket stands where the tool reads a
    /// record or writes a file or folder ([`rotorshunt::files::Refused`]): it is never
    /// followed and never replaced.
    #[error("refusing {path}: {what} stands there, and rotorshunt neither follows nor replaces it: remove it, or choose another output")]
    Unsafe {
        /// The path.
        path: String,
        /// What stands there ("a symbolic link", "a FIFO", "a device", …).
        what: String,
    },
    /// An output would replace an input of the same run (the same path, or a symbolic
    /// link to it).
    #[error("refusing to write {path}: it is {input} of this run; choose another --out folder")]
    OutputIsInput {
        /// The output file.
        path: String,
        /// Which input, e.g. "the --compare file".
        input: String,
    },
    /// A command's `--out` names an existing file (or a link to one), not a folder.
    #[error("--out {path} is {what}, not a folder: give a folder for the output files (it is created if missing)")]
    OutIsNotAFolder {
        /// The path given.
        path: String,
        /// What it is, e.g. "a file".
        what: String,
    },
    /// `import-ross --out FILE` names an existing file and `--force` was not given.
    #[error("{path} exists and is not replaced: give --force to replace it, or choose another --out file")]
    OutputExists {
        /// The file.
        path: String,
    },
    /// A study's `--out` folder holds entries that the study did not create.
    #[error(
        "--out folder {dir} holds {} this study did not create ({}): use a new or empty folder, or give --allow-non-empty to write the study beside them (they are never changed)",
        entries_count(*count),
        entries_list(entries, *count)
    )]
    FolderNotEmpty {
        /// The folder.
        dir: String,
        /// The first few of those entries, sorted.
        entries: Vec<String>,
        /// How many there are.
        count: usize,
    },
    /// An entry a study has to write exists and was not written by that study.
    #[error("{path} exists and was not written by this study, so it is not replaced: move it away or choose another --out folder")]
    NotOwned {
        /// The entry.
        path: String,
    },
    /// A study's `--out` folder belongs to another study (its manifest names another study
    /// file and another plan), or holds a manifest that cannot be read.
    #[error("--out folder {dir} belongs to {owner}: choose another --out folder")]
    OtherStudy {
        /// The folder.
        dir: String,
        /// The other study, e.g. "the study /data/other.toml", or what is wrong with the manifest.
        owner: String,
    },
    /// Another run holds the lock of a study's `--out` folder.
    #[error(
        "--out folder {dir} is in use by another study run ({}): wait for it to end, or remove {lock} if that run is gone",
        holder_text(*pid, host)
    )]
    StudyLocked {
        /// The folder.
        dir: String,
        /// The lock file.
        lock: String,
        /// Process id of the holder, if its lock records one.
        pid: Option<u32>,
        /// Host of the holder, if its lock records one.
        host: Option<String>,
    },
    /// A shard of a study is not valid: `--shard K/N` out of range or malformed, a
    /// `SLURM_ARRAY_TASK_ID` that is not a shard number, more shards than cases, or a
    /// shard count other than the one the `--out` folder's study was split into.
    #[error("{source_name} {value}: {message}")]
    Shard {
        /// Where the shard came from: `--shard`, `--shards`, `--tasks` or
        /// `SLURM_ARRAY_TASK_ID`.
        source_name: String,
        /// The value given.
        value: String,
        /// What is wrong, and the valid range.
        message: String,
    },
    /// A sharded run, `study slurm`, `merge` or `status` met an `--out` folder whose
    /// manifest records another plan than the study file's: shards of two plans would
    /// split the cases differently.
    #[error(
        "--out folder {dir} holds results of another plan (plan {} of the study {study}): {advice}",
        short_hash(found)
    )]
    PlanMismatch {
        /// The folder.
        dir: String,
        /// The study file its manifest names.
        study: String,
        /// The plan hash its manifest records (SHA-256, hex).
        found: String,
        /// What to do.
        advice: String,
    },
    /// `study status` or `study merge` on a folder that is not a study's `--out` folder.
    #[error("{dir} is not a study folder: it has no readable {manifest} ({reason}); give the --out folder of a study")]
    NotAStudyFolder {
        /// The folder.
        dir: String,
        /// The manifest file name.
        manifest: String,
        /// Why it cannot be read.
        reason: String,
    },
    /// `study slurm --submit` cannot find the `sbatch` program; nothing was written.
    #[error("cannot submit: the program `{program}` {reason}; nothing was written (without --submit the scripts are written for submitting by hand)")]
    SlurmMissing {
        /// The program (`--sbatch`, default `sbatch`).
        program: String,
        /// Why it cannot be run.
        reason: String,
    },
    /// A value `study slurm` would write into a job script that the script cannot carry: a
    /// control character in a path or value (a line break would end an `#SBATCH` line), a
    /// `--time` not in Slurm's forms, a `--partition` outside its characters, a path that is
    /// not UTF-8 or that Slurm's `--output` cannot name. Checked before anything is written.
    #[error("{what} {value}: {message}; nothing was written")]
    SlurmValue {
        /// The flag or path, e.g. `--time`, `--out`, `the study file`.
        what: String,
        /// The value, quoted and escaped (a newline as `\n`), so the message is one line.
        value: String,
        /// What is wrong, and what to give.
        message: String,
    },
    /// `sbatch` refused a job script of `study slurm --submit`.
    #[error("{program} {script} failed ({status}): {stderr}")]
    SlurmFailed {
        /// The program.
        program: String,
        /// The script it was given.
        script: String,
        /// Its exit status.
        status: String,
        /// The first line of its standard error.
        stderr: String,
    },
    /// A study's plan has more cases than a study may run.
    #[error(
        "study file {file}: the plan has {} cases, more than the limit of {limit}: split the study or sweep fewer values",
        cases.map_or_else(|| format!("more than {}", u64::MAX), |n| n.to_string())
    )]
    StudyTooLarge {
        /// The study file.
        file: String,
        /// Listed cases plus the product of the sweep's value counts (`None`: beyond u64).
        cases: Option<u64>,
        /// The limit.
        limit: u64,
    },
}

impl From<rotorshunt::import::ross::ImportError> for Error {
    fn from(e: rotorshunt::import::ross::ImportError) -> Error {
        match e {
            rotorshunt::import::ross::ImportError::Read(e) => Error::Problem(e),
            rotorshunt::import::ross::ImportError::Ross(e) => Error::Ross(Box::new(e)),
            other => Error::Import(Box::new(other)),
        }
    }
}

impl From<rotorshunt::run::Stopped> for Error {
    fn from(e: rotorshunt::run::Stopped) -> Error {
        match e {
            rotorshunt::run::Stopped::Time(e) => Error::TimeLimit(e),
            rotorshunt::run::Stopped::Count(e) => Error::CountLimit(e),
        }
    }
}

impl From<rotorshunt::run::RunError> for Error {
    fn from(e: rotorshunt::run::RunError) -> Error {
        use rotorshunt::run::RunError as R;
        match e {
            R::Problem(e) => Error::Problem(e),
            R::Analysis(e) => Error::Analysis(e),
            R::Design(e) => Error::Design(e),
            R::Refused(e) => Error::Cost(e),
            R::Stopped(e) => e.into(),
            R::Cancelled { what } => Error::Cancelled { what },
        }
    }
}

impl From<rotorshunt::import::ross::RossError> for Error {
    fn from(e: rotorshunt::import::ross::RossError) -> Error {
        Error::Ross(Box::new(e))
    }
}

impl Error {
    /// The error of an input/output failure at `path`: [`Error::Unsafe`] when the file
    /// layer refused what stands there, else [`Error::Output`].
    pub fn io(path: &std::path::Path, e: &std::io::Error) -> Error {
        match e.get_ref().and_then(|r| r.downcast_ref::<rotorshunt::files::Refused>()) {
            Some(r) => Error::Unsafe { path: path.display().to_string(), what: r.what.clone() },
            None => Error::Output { path: path.display().to_string(), message: e.to_string() },
        }
    }

    /// The error's kind, named as docs/errors.md heads its section: a layer's error keeps
    /// its layer's kind, and a flag's broken rule is the file layer's kind of that value.
    #[allow(dead_code)] // called by the Python bindings alone
    pub fn kind(&self) -> &'static str {
        match self {
            Error::Problem(p) => p.kind.name(),
            Error::Analysis(a) => a.kind(),
            Error::Design(d) => d.kind(),
            Error::Ross(r) => r.kind.name(),
            Error::Import(_) => "Import",
            Error::Parameter { kind, .. } => kind.name(),
            Error::Study { .. } => "Study",
            Error::Argument { .. } => "Argument",
            Error::Cost(_) => "Cost",
            Error::TimeLimit(_) => "TimeLimit",
            Error::CountLimit(_) => "CountLimit",
            Error::Cancelled { .. } => "Cancelled",
            Error::Output { .. } => "Output",
            Error::OutputIsInput { .. } => "OutputIsInput",
            Error::OutIsNotAFolder { .. } => "OutIsNotAFolder",
            Error::Unsafe { .. } => "Unsafe",
            Error::FolderNotEmpty { .. } => "FolderNotEmpty",
            Error::NotOwned { .. } => "NotOwned",
            Error::OtherStudy { .. } => "OtherStudy",
            Error::StudyLocked { .. } => "StudyLocked",
            Error::StudyTooLarge { .. } => "StudyTooLarge",
            Error::Shard { .. } => "Shard",
            Error::PlanMismatch { .. } => "PlanMismatch",
            Error::NotAStudyFolder { .. } => "NotAStudyFolder",
            Error::SlurmMissing { .. } => "SlurmMissing",
            Error::SlurmValue { .. } => "SlurmValue",
            Error::SlurmFailed { .. } => "SlurmFailed",
            Error::OutputExists { .. } => "OutputExists",
        }
    }

    /// The exit code of a run that failed with this error (docs/errors.md): 2 for bad
    /// input (the problem or study file, arguments, a refused cost or output folder, a
    /// request or design that breaks a rule), 1 for a failure on valid input, 7 for a run
    /// stopped while it ran (its time limit or its allowance of evaluations).
    pub fn exit_code(&self) -> u8 {
        const BAD_INPUT: u8 = 2;
        const FAILED: u8 = 1;
        const STOPPED: u8 = 7;
        match self {
            Error::TimeLimit(_) | Error::CountLimit(_) | Error::Cancelled { .. } => STOPPED,
            Error::Problem(_)
            | Error::Ross(_)
            | Error::OutputExists { .. }
            | Error::Argument { .. }
            | Error::Parameter { .. }
            | Error::Cost(_)
            | Error::Study { .. }
            | Error::StudyTooLarge { .. }
            | Error::FolderNotEmpty { .. }
            | Error::NotOwned { .. }
            | Error::OtherStudy { .. }
            | Error::StudyLocked { .. }
            | Error::Shard { .. }
            | Error::PlanMismatch { .. }
            | Error::NotAStudyFolder { .. }
            | Error::SlurmMissing { .. }
            | Error::SlurmValue { .. }
            | Error::OutputIsInput { .. }
            | Error::OutIsNotAFolder { .. }
            | Error::Unsafe { .. } => BAD_INPUT,
            Error::Output { .. } | Error::SlurmFailed { .. } | Error::Import(_) => FAILED,
            // Sorted by the library, whose match lists every kind.
            Error::Analysis(a) if a.is_bad_input() => BAD_INPUT,
            Error::Design(d) if d.is_bad_input() => BAD_INPUT,
            Error::Analysis(_) | Error::Design(_) => FAILED,
        }
    }

    /// The error of command-line argument `argument` whose value breaks a parameter rule.
    pub fn parameter(argument: &str, e: &rotorshunt::analysis::limits::ParamError) -> Error {
        Error::Parameter { argument: argument.to_string(), kind: e.into() }
    }
}

fn entries_count(count: usize) -> String {
    if count == 1 {
        "1 entry".into()
    } else {
        format!("{count} entries")
    }
}

fn entries_list(entries: &[String], count: usize) -> String {
    let mut s = entries.join(", ");
    if count > entries.len() {
        s += &format!(" and {} more", count - entries.len());
    }
    s
}

fn holder_text(pid: Option<u32>, host: &Option<String>) -> String {
    match (pid, host) {
        (Some(pid), Some(host)) => format!("pid {pid} on host {host}"),
        (None, Some(host)) => format!("a lock of host {host} whose record is not the tool's"),
        (Some(pid), None) => format!("pid {pid}"),
        (None, None) => "a run that is starting, or a lock whose record is not the tool's".into(),
    }
}

/// The first 12 hex digits of a hash, for messages.
fn short_hash(h: &str) -> &str {
    h.get(..12).unwrap_or(h)
}
