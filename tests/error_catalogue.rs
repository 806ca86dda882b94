//! `docs/errors.md` cannot drift: every example command in it is run and must print
//! exactly the quoted message; every error kind has a section (each error's `kind()` is
//! an exhaustive match in the crate, so a new kind has a name before it compiles, and the
//! list below holds one of each); every fixture in `tests/fixtures/bad` has its kind
//! documented.

use crate::common;
use rotorshunt::analysis::AnalysisError;
use rotorshunt::design::DesignError;
use rotorshunt::import::ross::{Format, Refusal, RossError, RossErrorKind};
use rotorshunt::linalg::LinalgError;
use rotorshunt::problem::{Problem, ProblemErrorKind};
use rotorshunt::run::{CostError, CountLimitError, Resource, TimeLimitError};
use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

// The command line's error, compiled here from the binary's own source: its kinds are
// the CLI's, and the command layer is not part of the library's API.
#[path = "../src/commands/error.rs"]
#[allow(dead_code)]
mod cli_error;
use cli_error::Error;

const DOC: &str = "docs/errors.md";

/// Kinds whose examples exit with status 1 (analysis or output failures); the rest exit 2.
const EXIT_1: [&str; 10] = [
    "Output",
    "SlurmFailed",
    "ReducedModes",
    "StaticLoadBuckles",
    "Linalg",
    "ResponseNotFinite",
    "NoWhirlModes",
    "ReducedBasis",
    "StiffResponse",
    "Unreliable",
];

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// One of every kind, so that the list of names follows the enums.
fn every_kind() -> Vec<&'static str> {
    let s = String::new;
    let problem = [
        ProblemErrorKind::Read(s()),
        ProblemErrorKind::NotARegularFile { kind: s() },
        ProblemErrorKind::TooLarge { size: 0, limit: 0 },
        ProblemErrorKind::TooComplex { tokens: 0, tables: 0, arrays: 0, keys: 0, estimate: 0, limit: 0 },
        ProblemErrorKind::NotUtf8(0),
        ProblemErrorKind::Empty,
        ProblemErrorKind::Syntax(s()),
        ProblemErrorKind::Schema(s()),
        ProblemErrorKind::Version { found: 2, supported: 1 },
        ProblemErrorKind::NotFinite(f64::NAN),
        ProblemErrorKind::NotPositive(0.0),
        ProblemErrorKind::Negative(-1.0),
        ProblemErrorKind::OutOfRange { value: 0.0, range: s() },
        ProblemErrorKind::BothGiven(s(), s()),
        ProblemErrorKind::NeitherGiven(s(), s()),
        ProblemErrorKind::DiskOffShaft { position: 0.0, length: 0.0 },
        ProblemErrorKind::DiskNodeOffShaft { node: 0, last: 0 },
        ProblemErrorKind::TooManyEntries { count: 0, limit: 0 },
        ProblemErrorKind::TooManyDofs { dofs: 0, limit: 0 },
        ProblemErrorKind::NoBranches,
        ProblemErrorKind::NodeOffShaft { node: 0, last: 0 },
        ProblemErrorKind::PositionOffShaft { position: 0.0, length: 0.0 },
        ProblemErrorKind::SupportsShareNode { node: 0, first: s() },
        ProblemErrorKind::RigidBody { supports: 0 },
        ProblemErrorKind::NegativeStiffness { value: -1.0, speed: None },
        ProblemErrorKind::DampingNotSemiDefinite { c: [[0.0; 2]; 2], eigenvalue: -1.0, speed: None },
        ProblemErrorKind::OutOfScale { coefficient: "kxx", value: 1.0, scale: 1.0, speed: None },
        ProblemErrorKind::TableSpeedsNotIncreasing { index: 1, speed: 0.0, previous: 0.0 },
        ProblemErrorKind::TableLength { values: 1, speeds: 2 },
        ProblemErrorKind::TableTooLong { points: 2, limit: 1 },
        ProblemErrorKind::Several { first: Box::new(ProblemErrorKind::NoBranches), more: Box::new([]) },
        ProblemErrorKind::InnerNotBelowOuter { inner: 0.0, outer: 0.0 },
        ProblemErrorKind::ShaftLength { total: 0.0 },
        ProblemErrorKind::UnknownName { what: rotorshunt::problem::NameOf::Ring, name: s(), known: Box::new([]) },
        ProblemErrorKind::BadName { name: s(), reason: s() },
        ProblemErrorKind::MixedForms(s(), s()),
        ProblemErrorKind::NoShearModulus { material: s() },
        ProblemErrorKind::TimoshenkoOnly(s()),
        ProblemErrorKind::UnknownMode { mode: s(), speed: 0.0, available: Box::new([]) },
        ProblemErrorKind::Override { text: s(), reason: s() },
        ProblemErrorKind::ClampedCapacitance { cp_s: 0.0, cp_t: 0.0, angle_deg: 0.0, from_k_eq2: None },
        ProblemErrorKind::NoTradeOff(s()),
    ];
    let analysis = [
        AnalysisError::Linalg(LinalgError::NotPositiveDefinite { what: "stiffness" }),
        AnalysisError::ReducedModes { requested: 1, available: 0 },
        AnalysisError::StaticLoadBuckles { alpha: 1.0, critical_load: 1.0 },
        AnalysisError::OutsideWindow { phi: 1.0, window: rotorshunt::analysis::Interval::new(2.0, 3.0) },
        AnalysisError::ResponseNotFinite { phi: 1.0, beta: 1.0, time: 1.0, periods: 1 },
        AnalysisError::NoWhirlModes { speed: 0.0, eigenvalues: 0, tolerance: 0.5 },
        AnalysisError::ReducedBasis { modes: 1, drift: 1.0 },
        AnalysisError::StiffResponse { phi: 1.0, rate: 1.0, steps: 1.0, accuracy_steps: 1.0 },
        AnalysisError::Unreliable {
            phi: 1.0,
            issue: rotorshunt::analysis::floquet::PointIssue::ZeroLoad { deviation: 1.0 },
        },
        AnalysisError::ProbeNodeOffShaft { node: 1, last: 0 },
        AnalysisError::ProbeOffSystem { dof: 1, dofs: 1 },
        AnalysisError::SingularAtSpeed { speed: 1.0 },
        AnalysisError::NoSpeeds,
        AnalysisError::SpeedsNotAscending { index: 1, speed: 1.0, previous: 1.0 },
        AnalysisError::UnknownMode { label: s(), speed: 0.0, available: vec![] },
        AnalysisError::Ltp(rotorshunt::analysis::ltp::LtpError::Load { what: s() }),
    ];
    let errors = [
        Error::Argument { argument: s(), message: s() },
        Error::Cost(CostError {
            what: s(),
            resource: Resource::Work,
            estimate: 1.0,
            limit: 1.0,
            factor: 1.0,
            parameter: s(),
            detail: s(),
        }),
        Error::TimeLimit(TimeLimitError { what: s(), limit: 1.0, elapsed: 1.0, explicit: true }),
        Error::CountLimit(CountLimitError { what: s(), allowed: 1, used: 2 }),
        Error::Cancelled { what: s() },
        Error::Output { path: s(), message: s() },
        Error::Study { file: s(), message: s() },
        Error::OutputIsInput { path: s(), input: s() },
        Error::OutIsNotAFolder { path: s(), what: s() },
        Error::Unsafe { path: s(), what: s() },
        Error::FolderNotEmpty { dir: s(), entries: vec![], count: 0 },
        Error::NotOwned { path: s() },
        Error::OtherStudy { dir: s(), owner: s() },
        Error::StudyLocked { dir: s(), lock: s(), pid: None, host: None },
        Error::StudyTooLarge { file: s(), cases: None, limit: 0 },
        Error::Shard { source_name: s(), value: s(), message: s() },
        Error::PlanMismatch { dir: s(), study: s(), found: s(), advice: s() },
        Error::NotAStudyFolder { dir: s(), manifest: s(), reason: s() },
        Error::SlurmMissing { program: s(), reason: s() },
        Error::SlurmValue { what: s(), value: s(), message: s() },
        Error::SlurmFailed { program: s(), script: s(), status: s(), stderr: s() },
        Error::OutputExists { path: s() },
        Error::from(RossError {
            file: s(),
            kind: RossErrorKind::Syntax { format: Format::Toml, line: None, message: s() },
        }),
        Error::from(RossError { file: s(), kind: RossErrorKind::Schema { key: s(), line: None, message: s() } }),
        Error::from(RossError {
            file: s(),
            kind: RossErrorKind::Refused { element: None, reason: Box::new(Refusal::NoBearing), more: Box::new([]) },
        }),
        Error::Import(Box::new(rotorshunt::import::ross::ImportError::Ross(RossError {
            file: s(),
            kind: RossErrorKind::Schema { key: s(), line: None, message: s() },
        }))),
        Error::Design(DesignError::NoDesign),
        Error::Design(DesignError::Optimiser(s())),
        Error::Design(DesignError::Qp(s())),
        Error::Design(DesignError::NoResponse),
        Error::Design(DesignError::FrontPoints(0)),
        Error::Design(DesignError::Stopped),
        Error::Design(DesignError::Candidate {
            variable: 0,
            name: s(),
            error: rotorshunt::model::BranchError::NoBranch { ring: 0, branch: 0, branches: 0 },
        }),
    ];
    let mut names: Vec<&str> = problem.iter().map(ProblemErrorKind::name).collect();
    names.extend(analysis.iter().map(AnalysisError::kind));
    names.extend(errors.iter().map(Error::kind));
    // The argument parser's own errors (clap).
    names.push("Usage");
    names.extend(warning_kinds());
    names
}

/// Every plausibility warning kind (named in the crate, as the error kinds): their sections'
/// examples print a `warning: ` line and exit 0.
fn warning_kinds() -> Vec<&'static str> {
    use rotorshunt::analysis::warnings::RangeWarning as R;
    use rotorshunt::problem::WarningKind as W;
    let (x, s) = (0.0, String::new);
    let all = [
        W::YoungsModulus { value: x, lo: x, hi: x },
        W::Mass { what: "shaft", mass: x, limit: x },
        W::Slenderness { length: x, diameter: x, ratio: x, limit: x },
        W::AngleInRadians { angle_deg: x },
        W::PeripheralSpeed { speed: x, radius: x, peripheral: x, limit: x, rpm_key: s() },
        W::PeripheralSpeedRpm { rpm: x, radius: x, peripheral: x, limit: x },
        W::Range(R::RangeAboveWhirls { lo: x, hi: x, largest_sum: x, speed: x }),
        W::Range(R::RangeBelowWhirls { lo: x, hi: x, smallest_sum: x, order: 1, speed: x }),
        W::OutsideTable { speed: x, lo: x, hi: x },
    ];
    all.iter().map(W::name).collect::<Vec<_>>()
}

/// Section name (`### \`Name\``) → its text.
fn sections(doc: &str) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    let mut current: Option<(String, String)> = None;
    for line in doc.lines() {
        if let Some(name) = line.strip_prefix("### `").and_then(|l| l.strip_suffix('`')) {
            if let Some((n, t)) = current.take() {
                out.insert(n, t);
            }
            current = Some((name.to_string(), String::new()));
        } else if line.starts_with("## ") {
            if let Some((n, t)) = current.take() {
                out.insert(n, t);
            }
        } else if let Some((_, t)) = current.as_mut() {
            t.push_str(line);
            t.push('\n');
        }
    }
    if let Some((n, t)) = current {
        out.insert(n, t);
    }
    out
}

/// `$ rotorshunt ARGS` lines with the `error: …` (or, for a warning, `warning: …`) line
/// that follows each.
fn examples(section: &str) -> Vec<(Vec<String>, String)> {
    let lines: Vec<&str> = section.lines().collect();
    let mut out = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        if let Some(cmd) = line.trim_start().strip_prefix("$ rotorshunt ") {
            let expected = lines.get(i + 1).map(|l| l.trim()).unwrap_or_default();
            assert!(
                expected.starts_with("error: ") || expected.starts_with("warning: "),
                "`{line}` is not followed by an `error: ` or `warning: ` line"
            );
            out.push((cmd.split_whitespace().map(String::from).collect(), expected.to_string()));
        }
    }
    out
}

/// `text` with the time a stopped run had taken (`(after 0.0 s,` of `TimeLimit`) as
/// `(after X s,`: a measured time, which the host's load moves.
fn measured_as_x(text: &str) -> String {
    match text.split_once("(after ").and_then(|(head, rest)| Some((head, rest.split_once(" s,")?.1))) {
        Some((head, tail)) => format!("{head}(after X s,{tail}"),
        None => text.to_string(),
    }
}

fn doc() -> String {
    std::fs::read_to_string(root().join(DOC)).unwrap_or_else(|e| panic!("{DOC}: {e}"))
}

#[test]
fn every_error_kind_has_a_section_with_a_fix() {
    let sections = sections(&doc());
    let mut failures = Vec::new();
    for kind in every_kind() {
        match sections.get(kind) {
            None => failures.push(format!("{DOC} has no section ### `{kind}`")),
            Some(text) => {
                if !text.contains("\nFix: ") && !text.starts_with("Fix: ") {
                    failures.push(format!("`{kind}` has no `Fix: `"));
                }
                // A kind with no command that raises it: the library's alone, or the
                // command line's for errors no version raises yet.
                let library_only = text.contains("Library only") || text.contains("Raised by no command today");
                if examples(text).is_empty() && !library_only {
                    failures.push(format!("`{kind}` has no `$ rotorshunt …` example"));
                }
            }
        }
    }
    let known = every_kind();
    for name in sections.keys() {
        if !known.contains(&name.as_str()) {
            failures.push(format!("{DOC} documents `{name}`, which is not an error kind"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn documented_messages_are_what_the_binary_prints() {
    let sections = sections(&doc());
    // The examples run in a scratch folder that shows the repository's `problems/` and
    // `tests/` (symbolic links) and the inputs that cannot live in the repository as
    // `out/generated/`: what they write goes to its `out/`, never into the repository.
    let work = common::scratch("error-catalogue");
    common::too_large_file();
    common::too_complex_file();
    common::long_table_file();
    common::generated("ross_2001_elements.json", |p| {
        std::fs::write(p, common::ross_rotor(2001, "json")).expect("write ross_2001_elements.json")
    });
    std::fs::create_dir_all(work.join("out")).expect("create out/");
    for (link, target) in [
        ("problems", root().join("problems")),
        ("tests", root().join("tests")),
        ("out/generated", common::generated_dir()),
    ] {
        std::os::unix::fs::symlink(&target, work.join(link)).unwrap_or_else(|e| panic!("{link}: {e}"));
    }
    let mut failures = Vec::new();
    let mut count = 0;
    for (kind, text) in &sections {
        for (args, expected) in examples(text) {
            count += 1;
            let out = Command::new(env!("CARGO_BIN_EXE_rotorshunt"))
                .args(&args)
                .current_dir(&work)
                .env_remove("RUST_BACKTRACE")
                .output()
                .expect("run rotorshunt");
            let stderr = String::from_utf8_lossy(&out.stderr);
            // Warnings come before an error: compare the first line of the example's sort.
            let sort = if expected.starts_with("warning: ") { "warning: " } else { "error: " };
            let first = stderr.lines().find(|l| l.starts_with(sort)).unwrap_or_default();
            if measured_as_x(first) != measured_as_x(&expected) {
                failures.push(format!(
                    "`{kind}`: rotorshunt {}\n    doc:    {expected}\n    actual: {first}",
                    args.join(" ")
                ));
            }
            let code = if expected.starts_with("warning: ") {
                0
            } else if EXIT_1.contains(&kind.as_str()) {
                1
            } else if kind == "TimeLimit" {
                7
            } else {
                2
            };
            if out.status.code() != Some(code) {
                failures.push(format!("`{kind}`: exit status {:?}, expected {code}", out.status.code()));
            }
        }
    }
    assert!(count >= 20, "only {count} examples");
    let _ = std::fs::remove_dir_all(&work);
    // The one library-only example.
    let mut model = common::load("paper-open.toml", &[]).model;
    model.load.alpha = 1.0;
    let e = rotorshunt::analysis::Rotor::new(&model).unwrap_err();
    let quoted = format!("Example (library): `{e}`.");
    if !sections["StaticLoadBuckles"].contains(&quoted) {
        failures.push(format!("`StaticLoadBuckles`: the doc does not quote {quoted}"));
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn every_bad_fixture_has_its_kind_documented() {
    let sections = sections(&doc());
    let dir = root().join("tests/fixtures/bad");
    let mut fixtures: Vec<_> = std::fs::read_dir(&dir)
        .expect("bad fixtures")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    fixtures.sort();
    assert!(fixtures.len() >= 40);
    let mut failures = Vec::new();
    for path in fixtures {
        // A whirl tag of a damping constraint is refused by the design, not the loader
        // (tests/bad_input.rs): its kind is the design's.
        let (kind, e) = match Problem::from_path(&path, &[]) {
            Err(e) => (e.kind.name(), e.to_string()),
            Ok(p) => {
                let e = common::design_refusal(&p).expect_err("bad fixture accepted");
                (e.kind(), e.to_string())
            }
        };
        if !sections.contains_key(kind) {
            failures.push(format!("{}: kind `{kind}` is not in {DOC} ({e})", path.display()));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn a_measured_time_in_a_message_is_compared_as_x() {
    let stopped = |after: &str| {
        format!("error: the chart was stopped at its time limit of 2 s (after {after} s, measured while it ran); nothing was written")
    };
    assert_eq!(measured_as_x(&stopped("0.0")), measured_as_x(&stopped("12.3")));
    assert_eq!(measured_as_x(&stopped("0.0")), stopped("X"));
    assert_eq!(measured_as_x("error: no time here"), "error: no time here");
}
