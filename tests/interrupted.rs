//! Interrupted studies: a running `rotorshunt study` is killed (SIGINT and SIGKILL) at five
//! points spread over its run, then re-run without `--force`. The interrupted tree must hold
//! no partial JSON file, the re-run must skip exactly the cases that had finished, leave no
//! `write_atomic` temporaries and give the same results as an uninterrupted run.

use crate::common;

use serde_json::Value;
use std::collections::BTreeMap;
use std::os::unix::process::ExitStatusExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Kill points as fractions of the uninterrupted run's wall time.
const FRACTIONS: [f64; 5] = [0.1, 0.25, 0.45, 0.65, 0.85];
const SIGINT: i32 = 2;
const SIGKILL: i32 = 9;

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_rotorshunt"));
    c.env("RAYON_NUM_THREADS", "2");
    c
}

/// 15 swept regions cases and one design case (nine output files, written one after the
/// other, then result.json) on a coarse model, so the whole study takes a few seconds.
fn write_study(dir: &Path) -> PathBuf {
    common::coarse_study(
        dir,
        "study.toml",
        &format!(
            r#"[[cases]]
name = "design"
kind = "design"
set = ["design.starts=1", "design.max_iterations=3", "design.phi_range=[1000.0, 1500.0]", "{}", "{}"]

[sweep]
speed = [1000.0, 2000.0, 3000.0]
"circuit.branches[0].resistance" = [0.0, 10.0, 50.0, 100.0, 200.0]
"#,
            common::COARSE_CHARTS[0],
            common::COARSE_CHARTS[1]
        ),
    )
}

/// Run the study to completion; its standard output.
fn run_to_end(study: &Path, out: &Path) -> String {
    let o = bin().arg("study").arg(study).arg("--out").arg(out).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// (N, R, S, F) of the line `study: N cases (R run, S skipped as finished, F failed)`.
fn counts(stdout: &str) -> (usize, usize, usize, usize) {
    let line = stdout.lines().find(|l| l.starts_with("study: ")).unwrap_or_else(|| panic!("no summary: {stdout}"));
    let numbers: Vec<usize> =
        line.split(|c: char| !c.is_ascii_digit()).filter_map(|w| w.parse().ok()).take(4).collect();
    assert_eq!(numbers.len(), 4, "{line}");
    assert!(line.contains(" cases (") && line.contains(" skipped as finished, "), "{line}");
    (numbers[0], numbers[1], numbers[2], numbers[3])
}

/// Every file below `dir`, relative to it.
fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                files.push(p.strip_prefix(dir).unwrap().to_path_buf());
            }
        }
    }
    files.sort();
    files
}

/// A `write_atomic` temporary: `.rotorshunt-tmp.NAME.<pid>.<n>`.
fn is_temporary(p: &Path) -> bool {
    let name = p.file_name().unwrap().to_string_lossy();
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    name.strip_prefix(".rotorshunt-tmp.")
        .and_then(|rest| rest.rsplit_once('.'))
        .and_then(|(rest, n)| rest.rsplit_once('.').map(|(target, pid)| (target, pid, n)))
        .is_some_and(|(target, pid, n)| !target.is_empty() && digits(pid) && digits(n))
}

/// The value without what differs between runs: wall times (`seconds`, at any depth) and
/// the task that ran a case (`task`: host, pid, shard, Slurm ids).
fn without_seconds(mut v: Value) -> Value {
    fn strip(v: &mut Value) {
        match v {
            Value::Object(m) => {
                m.remove("seconds");
                m.remove("task");
                m.values_mut().for_each(strip);
            }
            Value::Array(a) => a.iter_mut().for_each(strip),
            _ => {}
        }
    }
    strip(&mut v);
    v
}

fn parse(path: &Path) -> Value {
    let text = std::fs::read_to_string(path).unwrap();
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}: {text}", path.display()))
}

/// The comparable content of a finished tree: JSON without wall times, Markdown without
/// the design report's wall time, other files as bytes; the summary's CSV and Markdown
/// hold wall times and are left out (summary.json has the same rows), and so is the
/// summary folder's record (it holds the token of the run that wrote it).
fn content(out: &Path) -> BTreeMap<PathBuf, Result<Value, Vec<u8>>> {
    walk(out)
        .into_iter()
        .filter(|p| {
            !matches!(p.to_str(), Some("summary/summary.csv" | "summary/summary.md" | "summary/.rotorshunt-out.json"))
        })
        .map(|p| {
            let full = out.join(&p);
            let c = if p.extension().is_some_and(|e| e == "json") {
                Ok(without_seconds(parse(&full)))
            } else if p.extension().is_some_and(|e| e == "md" || e == "html") {
                // The design report's `- cost: …, N.N s` line (`<li>cost: …, N.N s</li>` in
                // report.html) ends with the wall time.
                Err(common::without_report_wall_time(&std::fs::read_to_string(&full).unwrap()).into_bytes())
            } else {
                Err(std::fs::read(&full).unwrap())
            };
            (p, c)
        })
        .collect()
}

/// What an interrupted tree holds.
struct Interrupted {
    /// Cases with a result.json (all status ok).
    finished: usize,
    /// Case directories with files but no result.json: cut off mid-way.
    partial: usize,
    /// `write_atomic` temporaries.
    temporaries: usize,
}

/// Check an interrupted tree: every JSON parses, and a case with a result.json has all
/// the files it has in the reference.
fn inspect(out: &Path, reference: &BTreeMap<PathBuf, Result<Value, Vec<u8>>>) -> Interrupted {
    let files = walk(out);
    for p in files.iter().filter(|p| p.extension().is_some_and(|e| e == "json")) {
        parse(&out.join(p));
    }
    let mut cases: BTreeMap<&Path, bool> = BTreeMap::new();
    for p in files.iter().filter(|p| p.starts_with("cases") && !is_temporary(p)) {
        let case = p.parent().unwrap();
        let done = p.file_name().is_some_and(|n| n == "result.json");
        *cases.entry(case).or_default() |= done;
        if done {
            let r = parse(&out.join(p));
            assert_eq!(r["status"], "ok", "{}: {r}", p.display());
            for f in reference.keys().filter(|f| f.starts_with(case)) {
                assert!(out.join(f).exists(), "{} finished without {}", case.display(), f.display());
            }
        }
    }
    Interrupted {
        finished: cases.values().filter(|&&d| d).count(),
        partial: cases.values().filter(|&&d| !d).count(),
        temporaries: files.iter().filter(|p| is_temporary(p)).count(),
    }
}

/// Start the study into `out`, send `signal` after `delay`; whether it died of the signal
/// (not if it had ended before).
fn interrupt(study: &Path, out: &Path, signal: i32, delay: Duration) -> bool {
    let mut child = bin()
        .arg("study")
        .arg(study)
        .arg("--out")
        .arg(out)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(delay);
    if child.try_wait().unwrap().is_some() {
        return false;
    }
    if signal == SIGINT {
        let pid = child.id().to_string();
        assert!(Command::new("kill").args(["-INT", &pid]).status().unwrap().success());
    } else {
        child.kill().unwrap();
    }
    // It may still have ended on its own between the check and the signal.
    child.wait().unwrap().signal() == Some(signal)
}

#[test]
fn an_interrupted_study_resumes_to_identical_results() {
    let started = Instant::now();
    let dir = std::env::temp_dir().join(format!("rotorshunt-interrupted-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let study = write_study(&dir);

    // The uninterrupted reference and its wall time.
    let reference_dir = dir.join("reference");
    let t = Instant::now();
    let first = run_to_end(&study, &reference_dir);
    let duration = t.elapsed();
    assert_eq!(counts(&first), (16, 16, 0, 0), "{first}");
    let reference = content(&reference_dir);
    assert!(reference.keys().any(|p| p.ends_with("cases/design/tuned.toml")), "{:?}", reference.keys());
    assert!(!walk(&reference_dir).iter().any(|p| is_temporary(p)));
    eprintln!("uninterrupted study: {:.2} s", duration.as_secs_f64());

    let (mut resumed_with_skips, mut cut_mid_case, mut temporaries) = (0, 0, 0);
    for (k, &fraction) in FRACTIONS.iter().enumerate() {
        for signal in [SIGINT, SIGKILL] {
            let out = dir.join(format!("out-{k}-{signal}"));
            // The machine's load varies: a run that ended before the signal proves
            // nothing, so it is repeated with half the delay.
            let mut delay = duration.mul_f64(fraction);
            let mut attempts = 1;
            while !interrupt(&study, &out, signal, delay) {
                assert!(
                    attempts < 4,
                    "kill -{signal} at {fraction}: the study ended before the signal {attempts} times"
                );
                std::fs::remove_dir_all(&out).unwrap();
                delay /= 2;
                attempts += 1;
            }
            let state = inspect(&out, &reference);

            let stdout = run_to_end(&study, &out);
            let (n, run, skipped, failed) = counts(&stdout);
            eprintln!(
                "kill -{signal} after {:.2} s (attempt {attempts}): {} cases finished, {} cut off, {} temporaries; \
                 re-run: {run} run, {skipped} skipped",
                delay.as_secs_f64(),
                state.finished,
                state.partial,
                state.temporaries
            );
            assert_eq!((n, failed), (16, 0), "{stdout}");
            assert_eq!(run + skipped, n, "{stdout}");
            assert_eq!(skipped, state.finished, "the re-run skips exactly the finished cases: {stdout}");
            resumed_with_skips += usize::from(skipped > 0);
            cut_mid_case += usize::from(state.partial > 0);
            temporaries += state.temporaries;
            let left: Vec<_> = walk(&out).into_iter().filter(|p| is_temporary(p)).collect();
            assert!(left.is_empty(), "kill -{signal} at {fraction}: temporaries left: {left:?}");
            let resumed = content(&out);
            assert_eq!(
                resumed.keys().collect::<Vec<_>>(),
                reference.keys().collect::<Vec<_>>(),
                "kill -{signal} at {fraction}: other files"
            );
            for (p, c) in &resumed {
                assert!(c == &reference[p], "kill -{signal} at {fraction}: {} differs from the reference", p.display());
            }
            std::fs::remove_dir_all(&out).unwrap();
        }
    }
    assert!(resumed_with_skips > 0, "no re-run skipped a finished case");
    assert!(cut_mid_case > 0, "no interruption cut a case off mid-way");
    std::fs::remove_dir_all(&dir).unwrap();
    eprintln!(
        "interrupted-study test: {:.1} s ({temporaries} temporaries removed on resuming)",
        started.elapsed().as_secs_f64()
    );
}
