//! Safe `--out` folders (docs/errors.md, "Output-folder errors"): a command interrupted by
//! SIGINT or SIGKILL while it runs leaves the previous results in its folder byte for byte
//! (or no folder, when there was none) and no visible leftover; a staging folder that a
//! SIGKILL leaves is hidden and removed by the next run. Stale files of the same
//! command's previous run are removed, a user's files never; `--out` naming a file is bad
//! input (exit 2) and leaves the file alone.

use crate::common;

use std::collections::BTreeMap;
use std::os::unix::process::ExitStatusExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

const SIGINT: i32 = 2;
const SIGKILL: i32 = 9;
/// Kill points as fractions of an uninterrupted run's wall time: one, in the middle of the
/// run. tests/kill_points.rs kills `chart` and `study merge` deterministically at every
/// write and rename of the file layer; this test adds SIGINT's cleanup and the other
/// commands, where one point per signal shows the handling.
const FRACTIONS: [f64; 1] = [0.5];

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_rotorshunt"));
    c.env("RAYON_NUM_THREADS", "2");
    c
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rotorshunt-out-folder-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// Every file and folder below `dir` (hidden ones included), relative, with the bytes of
/// each file (None for a folder).
fn snapshot(dir: &Path) -> Snapshot {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            let rel = p.strip_prefix(dir).unwrap().to_path_buf();
            if p.is_dir() {
                out.insert(rel, None);
                stack.push(p);
            } else {
                out.insert(rel, Some(std::fs::read(&p).unwrap()));
            }
        }
    }
    out
}

/// Whether a path (relative to the folder or its parent) is a staging folder or inside one.
fn staging(p: &Path) -> bool {
    p.components().any(|c| {
        let c = c.as_os_str().to_string_lossy();
        c.starts_with(".rotorshunt-tmp.")
    })
}

/// One command of the test: its arguments before `--out` for the previous results and
/// for the interrupted run (different inputs, so different outputs).
struct Case {
    name: &'static str,
    previous: Vec<String>,
    next: Vec<String>,
}

fn run(args: &[String], out: &Path) -> Output {
    bin().args(args).arg("--out").arg(out).output().unwrap()
}

fn run_ok(args: &[String], out: &Path) -> Duration {
    let t = Instant::now();
    let o = run(args, out);
    assert!(o.status.success(), "{args:?}: {}", text(&o.stderr));
    t.elapsed()
}

/// Start `args` into `out` and send `signal` after `delay`; whether it died of it.
fn interrupt(args: &[String], out: &Path, signal: i32, delay: Duration) -> bool {
    let mut child = bin().args(args).arg("--out").arg(out).stdout(Stdio::null()).stderr(Stdio::null()).spawn().unwrap();
    std::thread::sleep(delay);
    if child.try_wait().unwrap().is_some() {
        return false;
    }
    if signal == SIGINT {
        assert!(Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap().success());
    } else {
        child.kill().unwrap();
    }
    child.wait().unwrap().signal() == Some(signal)
}

type Snapshot = BTreeMap<PathBuf, Option<Vec<u8>>>;

/// Interrupt `args` into `out` at `fraction` of `duration`, after `prepare` has laid out
/// the folder (its snapshot is returned); a run that ended before the signal proves
/// nothing, so it is repeated from a fresh `prepare` with half the delay (the machine's
/// load varies).
fn interrupt_at(
    args: &[String],
    out: &Path,
    signal: i32,
    (duration, fraction): (Duration, f64),
    prepare: &dyn Fn() -> Snapshot,
) -> Snapshot {
    let mut delay = duration.mul_f64(fraction);
    for _ in 0..4 {
        let before = prepare();
        if interrupt(args, out, signal, delay) {
            return before;
        }
        delay /= 2;
    }
    panic!("{args:?}: the run ended before kill -{signal} four times");
}

fn strings(v: &[&str]) -> Vec<String> {
    v.iter().map(|s| s.to_string()).collect()
}

fn cases() -> Vec<Case> {
    let fig11 = common::problem_path("fig11-closed-2000.toml");
    let design = common::problem_path("design-widest-band.toml");
    let coarse = common::COARSE_MODEL_ARGS;
    let design_args = |iterations: &str| {
        let mut v = strings(&["design", &design]);
        v.extend(strings(&coarse));
        v.extend(strings(&["--set", "design.starts=2", "--set", &format!("design.max_iterations={iterations}")]));
        v.extend(strings(&["--set", "design.phi_range=[1000.0, 1500.0]"]));
        v.extend(strings(&common::COARSE_CHART_ARGS));
        v
    };
    vec![
        Case {
            name: "chart",
            previous: strings(&["chart", &fig11, "--phi", "1000:1500:50", "--beta", "0:0.5:0.1"]),
            next: strings(&["chart", &fig11, "--phi", "1000:1500:1", "--beta", "0:0.5:0.025"]),
        },
        Case {
            name: "regions",
            previous: strings(&["regions", &fig11, "--phi", "1200:1260", "--beta-max", "0.4", "--level", "0.3"]),
            next: strings(&["regions", &fig11, "--phi", "1100:1400", "--beta-max", "0.5", "--level", "0.3"]),
        },
        Case { name: "design", previous: design_args("3"), next: design_args("25") },
    ]
}

#[test]
fn interrupted_runs_leave_previous_results_and_no_folder() {
    let dir = scratch("interrupt");
    for case in cases() {
        // The uninterrupted run's wall time, and its files.
        let reference = dir.join(format!("{}-reference", case.name));
        let duration = run_ok(&case.next, &reference);
        let reference_files = snapshot(&reference);
        eprintln!("{}: uninterrupted run {:.2} s", case.name, duration.as_secs_f64());
        for (k, &fraction) in FRACTIONS.iter().enumerate() {
            for signal in [SIGINT, SIGKILL] {
                // An existing folder: previous results and a user's file.
                let parent = dir.join(format!("{}-{k}-{signal}", case.name));
                let out = parent.join("results");
                let prepare = || {
                    let _ = std::fs::remove_dir_all(&parent);
                    run_ok(&case.previous, &out);
                    std::fs::write(out.join("notes.txt"), "the user's notes\n").unwrap();
                    snapshot(&out)
                };
                let before = interrupt_at(&case.next, &out, signal, (duration, fraction), &prepare);
                let after = snapshot(&out);
                let visible: BTreeMap<_, _> = after.iter().filter(|(p, _)| !staging(p)).collect();
                assert_eq!(
                    visible,
                    before.iter().collect::<BTreeMap<_, _>>(),
                    "{} kill -{signal} at {fraction}: the previous results changed",
                    case.name
                );
                let left: Vec<_> = snapshot(&parent)
                    .into_keys()
                    .filter(|p| staging(p))
                    .filter(|p| p.components().count() <= 2)
                    .collect();
                if signal == SIGINT {
                    assert!(left.is_empty(), "{} SIGINT left staging folders: {left:?}", case.name);
                }
                // The next run removes any leftover and writes the new results.
                run_ok(&case.next, &out);
                let done = snapshot(&parent);
                let stray: Vec<_> = done.keys().filter(|p| staging(p)).collect();
                assert!(stray.is_empty(), "{} kill -{signal}: the next run left {stray:?}", case.name);
                assert_eq!(std::fs::read(out.join("notes.txt")).unwrap(), b"the user's notes\n");
                let csv_or_json = |files: &Snapshot| -> Vec<PathBuf> {
                    files
                        .keys()
                        .filter(|p| p.extension().is_some_and(|e| e == "csv" || e == "toml" || e == "svg"))
                        .cloned()
                        .collect()
                };
                for p in csv_or_json(&reference_files) {
                    assert_eq!(
                        std::fs::read(out.join(&p)).ok(),
                        reference_files[&p].clone(),
                        "{}: {} after the re-run",
                        case.name,
                        p.display()
                    );
                }
                eprintln!("{} kill -{signal} at {fraction}: {} hidden leftover(s) removed", case.name, left.len());

                // No folder before: none after (and SIGINT leaves nothing in the parent).
                let fresh_parent = dir.join(format!("{}-{k}-{signal}-new", case.name));
                let fresh = fresh_parent.join("results");
                let prepare = || {
                    let _ = std::fs::remove_dir_all(&fresh_parent);
                    std::fs::create_dir_all(&fresh_parent).unwrap();
                    Snapshot::new()
                };
                interrupt_at(&case.next, &fresh, signal, (duration, fraction), &prepare);
                assert!(!fresh.exists(), "{} kill -{signal}: an output folder appeared", case.name);
                let left: Vec<_> = snapshot(&fresh_parent).into_keys().collect();
                if signal == SIGINT {
                    assert!(left.is_empty(), "{} SIGINT left {left:?}", case.name);
                } else {
                    assert!(left.iter().all(|p| staging(p)), "{} SIGKILL left visible {left:?}", case.name);
                }
                // The leftover's removal, by a run of the shorter inputs (the full one above
                // has shown that a re-run writes the new results).
                run_ok(&case.previous, &fresh);
                let entries: Vec<_> = std::fs::read_dir(&fresh_parent)
                    .unwrap()
                    .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                    .collect();
                assert_eq!(entries, ["results"], "{}: the next run left {entries:?}", case.name);
            }
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn stale_files_of_the_same_command_go_and_a_users_files_stay() {
    let dir = scratch("stale");
    let fig11 = common::problem_path("fig11-closed-2000.toml");
    let out = dir.join("chart");
    let chart = |extra: &[&str]| {
        let mut args = strings(&["chart", &fig11, "--phi", "1100:1300:50", "--beta", "0:0.4:0.1"]);
        args.extend(strings(extra));
        run_ok(&args, &out);
    };
    chart(&["--compare-set", "circuit.state=open"]);
    assert!(out.join("compare.csv").exists() && out.join("compare.json").exists());
    std::fs::write(out.join("notes.txt"), "mine\n").unwrap();
    // A campbell diagram in the same folder is another command's output: it stays.
    let c = bin().args(["campbell", &fig11, "--speeds", "0:2000:1000", "--out"]).arg(&out).output().unwrap();
    assert!(c.status.success(), "{}", text(&c.stderr));
    chart(&[]);
    for gone in ["compare.csv", "compare.json"] {
        assert!(!out.join(gone).exists(), "the stale {gone} of the earlier chart --compare survived");
    }
    for kept in ["chart.json", "chart.csv", "chart.png", "growth.svg", "campbell.json", "campbell.png", "notes.txt"] {
        assert!(out.join(kept).exists(), "{kept} is gone");
    }
    // A stale file the user edited since is theirs: kept.
    chart(&["--compare-set", "circuit.state=open"]);
    std::fs::write(out.join("compare.csv"), "edited by the user\n").unwrap();
    chart(&[]);
    assert_eq!(std::fs::read(out.join("compare.csv")).unwrap(), b"edited by the user\n");
    assert!(!out.join("compare.json").exists());
    assert_eq!(std::fs::read(out.join("notes.txt")).unwrap(), b"mine\n");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn out_naming_a_file_is_bad_input_and_the_file_is_kept() {
    let dir = scratch("file");
    let fig11 = common::problem_path("fig11-closed-2000.toml");
    let design = common::problem_path("design-widest-band.toml");
    let file = dir.join("results.txt");
    std::fs::write(&file, "not a folder\n").unwrap();
    let link = dir.join("link");
    std::os::unix::fs::symlink(&file, &link).unwrap();
    let commands: [Vec<String>; 5] = [
        strings(&["chart", &fig11, "--phi", "1200:1300:50", "--beta", "0:0.3:0.1"]),
        strings(&["regions", &fig11, "--phi", "1200:1260", "--beta-max", "0.4"]),
        strings(&["design", &design]),
        strings(&["campbell", &fig11, "--speeds", "0:1000:500"]),
        strings(&["response", &fig11, "--phi", "1230", "--beta", "0.1", "--periods", "2"]),
    ];
    for args in &commands {
        for target in [&file, &link] {
            let o = run(args, target);
            assert_eq!(o.status.code(), Some(2), "{args:?} --out {}: {}", target.display(), text(&o.stderr));
            let e = text(&o.stderr);
            assert_eq!(
                e.lines().next().unwrap_or_default(),
                format!(
                    "error: --out {} is a file, not a folder: give a folder for the output files (it is created if missing)",
                    target.display()
                ),
                "{args:?}"
            );
            assert_eq!(std::fs::read(&file).unwrap(), b"not a folder\n");
        }
    }
    let entries: Vec<_> =
        std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    assert_eq!(entries.len(), 2, "nothing else written: {entries:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}
