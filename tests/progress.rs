//! Progress on standard error when it is not a terminal (src/reporter.rs): a design with
//! standard output and standard error redirected writes progress lines naming each of its
//! phases (optimise, verification, report) with the phase's done and total steps, the
//! done count of a phase rises, nothing goes to standard output,
//! and `--quiet` writes no line at all.
//!
//! Counts, not seconds: the lines every 5 s need a run longer than 5 s, which depends on
//! the machine, so the run sets `ROTORSHUNT_TEST_PROGRESS_EVERY` (test-only), which adds a
//! line each time a phase's done count passes a multiple of [`EVERY`]. The 5 s lines are
//! still printed beside them on a slow machine and must have the same form.

use crate::common;

use std::process::Output;

/// A line each time a phase's done count passes a multiple of this (the optimise phase of
/// the design below has some ten steps, the verification and report hundreds to thousands).
const EVERY: &str = "10";
/// A short design: one start of a few iterations and a narrow report range (as in
/// tests/reproducibility.rs) on the coarse model ([`common::COARSE_MODEL_ARGS`]), with
/// every phase of a full one.
const SETS: [&str; 6] =
    ["--set", "design.starts=1", "--set", "design.max_iterations=3", "--set", "design.phi_range=[900.0, 1600.0]"];

fn design(dir: &std::path::Path, extra: &[&str]) -> Output {
    let out = common::bin()
        .env("ROTORSHUNT_TEST_PROGRESS_EVERY", EVERY)
        .args(["design", &common::problem_path("design-widest-band.toml"), "--out"])
        .arg(dir)
        .args(SETS)
        .args(common::COARSE_MODEL_ARGS)
        .args(extra)
        .output()
        .expect("run rotorshunt");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    out
}

/// `progress: design: NAME (phase k of 4): DONE/TOTAL steps, …`: (name, done, total); a
/// phase that knows none of its steps yet reports its time only (`…: 2 s elapsed`, done
/// and total 0) or its done count only (`…: DONE steps, …`, total 0), never a total of 0.
fn counts(line: &str) -> Option<(&str, u64, u64)> {
    let rest = line.strip_prefix("progress: design: ")?;
    let (name, rest) = rest.split_once(" (phase ")?;
    let (_, rest) = rest.split_once("): ")?;
    let Some((fraction, rest)) = rest.split_once(" steps, ") else {
        return rest.contains(" elapsed").then_some((name, 0, 0));
    };
    rest.contains(" elapsed").then_some(())?;
    match fraction.split_once('/') {
        Some((done, total)) => Some((name, done.parse().ok()?, total.parse().ok()?)),
        None => Some((name, fraction.parse().ok()?, 0)),
    }
}

#[test]
fn a_design_reports_its_phases_and_rising_counts_and_quiet_reports_nothing() {
    let dir = common::scratch("progress");
    let (loud, quiet) = std::thread::scope(|s| {
        let loud = s.spawn(|| design(&dir.join("loud"), &[]));
        let quiet = s.spawn(|| design(&dir.join("quiet"), &["--quiet"]));
        (loud.join().expect("loud run"), quiet.join().expect("quiet run"))
    });
    let stderr = String::from_utf8_lossy(&loud.stderr);
    let stdout = String::from_utf8_lossy(&loud.stdout);
    let lines: Vec<&str> = stderr.lines().collect();
    assert!(stdout.starts_with("design: "), "the summary alone on stdout: {stdout}");
    assert!(!stdout.contains("progress:"), "{stdout}");
    // Every line but the closing one carries its phase and counts (or its time only while
    // the phase knows none of its steps): never a total of 0.
    assert!(!stderr.contains("/0 steps"), "{stderr}");
    let (last, periodic) = lines.split_last().expect("progress lines");
    assert!(last.starts_with("progress: design: done in "), "{last}");
    let parsed: Vec<(&str, u64, u64)> =
        periodic.iter().map(|l| counts(l).unwrap_or_else(|| panic!("not a progress line: {l}"))).collect();
    for phase in ["optimise", "verification", "report"] {
        assert!(parsed.iter().any(|(name, ..)| *name == phase), "no line of the {phase} phase: {stderr}");
    }
    // A phase's done count rises from line to line: some phase shows at least three
    // different counts. (Lines of threads that pass a multiple at once may print in
    // either order, so the order of the lines is not asserted.)
    let mut seen = std::collections::BTreeMap::<&str, std::collections::BTreeSet<u64>>::new();
    for (name, done, _) in &parsed {
        seen.entry(name).or_default().insert(*done);
    }
    let summary: Vec<String> =
        seen.iter().map(|(p, d)| format!("{p}: {} counts up to {:?}", d.len(), d.last())).collect();
    assert!(seen.values().any(|d| d.len() >= 3), "no phase's done count rose twice: {summary:?}");
    eprintln!("{} progress lines: {summary:?}", lines.len());

    // The same design with --quiet: nothing on stderr, the summary on stdout.
    assert!(quiet.stderr.is_empty(), "--quiet wrote to stderr: {}", String::from_utf8_lossy(&quiet.stderr));
    assert!(String::from_utf8_lossy(&quiet.stdout).starts_with("design: "));
    std::fs::remove_dir_all(&dir).expect("remove the scratch folder");
}
