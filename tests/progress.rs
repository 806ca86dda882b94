//! Progress on standard error when it is not a terminal (src/reporter.rs): a long design
//! with standard output and standard error redirected to files writes a progress line at
//! least every 5 s, naming each of its phases (optimise, verification, report), and
//! nothing on standard output; `--quiet` writes no line at all.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The reporter's interval between lines.
const INTERVAL: Duration = Duration::from_secs(5);
/// What a line may come late by on this shared 2-core machine: the printer thread's
/// wake-up and the polling of the file below (every 50 ms).
const SLACK: Duration = Duration::from_millis(1500);
/// The design is long enough to be worth reporting on any machine: one thread makes the
/// widest-band design of the README take about 15 s on an idle 2-core machine.
const THREADS: &str = "1";

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rotorshunt-progress-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Run the design into `dir` with stdout and stderr redirected to files; the arrival time
/// (since the start) of each line of stderr, read by polling the file while it runs, the
/// lines, the wall time and stdout.
fn design(dir: &Path, extra: &[&str]) -> (Vec<(Duration, String)>, Duration, String) {
    let (out, err) = (dir.join("stdout"), dir.join("stderr"));
    let started = Instant::now();
    let mut child = Command::new(env!("CARGO_BIN_EXE_rotorshunt"))
        .env("RAYON_NUM_THREADS", THREADS)
        .args(["design", &common::problem_path("design-widest-band.toml"), "--out"])
        .arg(dir.join("design"))
        .args(extra)
        .stdout(Stdio::from(std::fs::File::create(&out).unwrap()))
        .stderr(Stdio::from(std::fs::File::create(&err).unwrap()))
        .spawn()
        .unwrap();
    let mut lines: Vec<(Duration, String)> = Vec::new();
    let mut seen = 0;
    let mut read = |lines: &mut Vec<(Duration, String)>| {
        let text = std::fs::read_to_string(&err).unwrap_or_default();
        let complete: Vec<&str> = text.split_inclusive('\n').filter(|l| l.ends_with('\n')).collect();
        for l in &complete[seen..] {
            lines.push((started.elapsed(), l.trim_end().to_string()));
        }
        seen = complete.len();
    };
    let status = loop {
        read(&mut lines);
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let wall = started.elapsed();
    read(&mut lines);
    assert!(status.success(), "{lines:?}");
    (lines, wall, std::fs::read_to_string(&out).unwrap())
}

#[test]
fn a_long_design_reports_every_five_seconds_and_quiet_reports_nothing() {
    let dir = scratch("design");
    let (loud, quiet) = (dir.join("loud"), dir.join("quiet"));
    std::fs::create_dir_all(&loud).unwrap();
    std::fs::create_dir_all(&quiet).unwrap();
    // The two runs side by side, one thread each.
    let (a, b) = std::thread::scope(|s| {
        let a = s.spawn(|| design(&loud, &[]));
        let b = s.spawn(|| design(&quiet, &["--quiet"]));
        (a.join().unwrap(), b.join().unwrap())
    });
    let (lines, wall, stdout) = a;
    eprintln!("design: {:.1} s, {} lines", wall.as_secs_f64(), lines.len());
    for (t, l) in &lines {
        eprintln!("  {:6.2} s  {l}", t.as_secs_f64());
    }
    // Periodic lines (besides the last, `done in`): the design is long enough to show them.
    assert!(lines.len() >= 3, "the design took {wall:?}, {} lines: too short to show periodic progress", lines.len());
    assert!(lines.iter().all(|(_, l)| l.starts_with("progress: design: ")), "{lines:?}");
    assert!(stdout.starts_with("design: "), "the summary alone on stdout: {stdout}");
    assert!(!stdout.contains("progress:"), "{stdout}");
    // At least every 5 s: from the start to the first line, between lines, from the last
    // line to the end.
    let mut times: Vec<Duration> = vec![Duration::ZERO];
    times.extend(lines.iter().map(|(t, _)| *t));
    times.push(wall);
    for w in times.windows(2) {
        assert!(w[1] - w[0] <= INTERVAL + SLACK, "a gap of {:?} between progress lines: {lines:?}", w[1] - w[0]);
    }
    for phase in ["optimise (phase 1 of 3)", "verification (phase 2 of 3)", "report (phase 3 of 3)"] {
        assert!(lines.iter().any(|(_, l)| l.contains(phase)), "no line of the {phase} phase: {lines:?}");
    }
    let counted = lines.iter().filter(|(_, l)| l.contains(" steps, ") && l.contains(" elapsed")).count();
    assert!(counted + 1 >= lines.len(), "lines carry done/total and elapsed: {lines:?}");
    assert!(lines.last().is_some_and(|(_, l)| l.starts_with("progress: design: done in ")), "{lines:?}");

    // The same design as the loud one, which showed periodic lines above.
    let (lines, _, stdout) = b;
    assert!(lines.is_empty(), "--quiet wrote to stderr: {lines:?}");
    assert!(stdout.starts_with("design: "), "{stdout}");
    std::fs::remove_dir_all(&dir).unwrap();
}
