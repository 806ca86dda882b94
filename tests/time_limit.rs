//! `--time-limit SECONDS`: a bound measured while a run runs, on whatever machine runs
//! it (issue 30: "a limit is a count, or a time measured while running with a clean
//! stop"). A run still computing at its limit stops at its next step (a chart row, a
//! search, a speed, a design candidate), writes nothing, leaves an earlier output folder
//! as it was and exits 7 with the `TimeLimit` error; a design keeps its best design so far
//! as `best-effort.toml`, with the stop on its report's page one, and exits 7. A limit of one nanosecond has passed
//! by the first step on any machine, so these tests assert what a stop does, never how
//! long anything took.

use crate::common::{self, bin, problem_path, scratch};
use std::path::Path;
use std::process::Output;

/// The exit code of a run stopped at its time limit (docs/errors.md).
const STOPPED: i32 = 7;
/// A limit that has passed before any step asks.
const PASSED: &str = "1e-9";

fn run(args: &[&str], out: Option<&Path>) -> Output {
    let mut cmd = bin();
    cmd.arg("--quiet").args(args);
    if let Some(out) = out {
        cmd.arg("--out").arg(out);
    }
    cmd.output().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// `o` is the stop of `what` at the limit 1e-9 s, with nothing written into `dir`: no
/// output folder, and no staging folder left beside it.
fn stopped(o: &Output, what: &str, dir: &Path) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(STOPPED), "{what}: {err}");
    assert!(
        err.starts_with(&format!("error: {what} was stopped at its time limit of 1e-9 s (after ")),
        "{what}: {err}"
    );
    assert!(err.contains("nothing was written; allow more time with --time-limit SECONDS"), "{err}");
    assert_eq!(err.lines().count(), 1, "one paragraph: {err}");
    let left: Vec<_> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert!(left.is_empty(), "{what} left {left:?} in {}", dir.display());
}

#[test]
fn every_long_command_stops_at_its_limit_and_writes_nothing() {
    let fig11 = problem_path("fig11-closed-2000.toml");
    let min_peak = problem_path("design-min-peak-at-speed.toml");
    let cases: [(&str, Vec<&str>, bool); 10] = [
        (
            "the chart",
            vec![
                "chart",
                &fig11,
                "--phi",
                "1100:1300:10",
                "--beta",
                "0:0.4:0.2",
                "--compare-set",
                "circuit.state=open",
            ],
            true,
        ),
        (
            "the unbalance response",
            vec!["unbalance", &fig11, "--speeds", "100:3000:10", "--compare-set", "circuit.state=open"],
            true,
        ),
        ("the Pareto front", vec!["design", &min_peak, "--pareto", "2"], true),
        ("the response", vec!["response", &fig11, "--phi", "1230", "--beta", "0.3", "--periods", "50"], true),
        ("the chart", vec!["chart", &fig11, "--phi", "1100:1300:10", "--beta", "0:0.4:0.1"], true),
        ("the region catalogue", vec!["regions", &fig11, "--phi", "1150:1250", "--beta-max", "0.4"], true),
        ("the band search", vec!["band", &fig11, "--phi-op", "1230", "--level", "0.3"], false),
        ("the Campbell diagram", vec!["campbell", &fig11, "--speeds", "0:2000:100"], true),
        ("the unbalance response", vec!["unbalance", &fig11, "--speeds", "100:3000:10"], true),
        ("the damping-ratio tracking", vec!["damping", &fig11, "--speeds", "0:2000:100"], false),
    ];
    for (what, args, with_out) in cases {
        let dir = scratch(&format!("time-limit-{}", what.replace(' ', "-")));
        let mut all = vec!["--time-limit", PASSED];
        all.extend(&args);
        let o = run(&all, with_out.then(|| dir.join("out")).as_deref());
        stopped(&o, what, &dir);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

#[test]
fn a_design_at_its_limit_writes_its_best_design_so_far_and_exits_7() {
    let dir = scratch("time-limit-design");
    let out = dir.join("out");
    let o = run(&["--time-limit", PASSED, "design", &problem_path("design-widest-band.toml")], Some(&out));
    let text = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(STOPPED), "{}{text}", stderr(&o));
    assert!(text.starts_with("design: stopped at its time limit of 1e-9 s, after "), "{text}");
    assert!(text.contains("best-effort.toml (the best design judged so far: NOT A RESULT"), "{text}");
    let mut files: Vec<String> =
        std::fs::read_dir(&out).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    files.sort();
    assert_eq!(files, [".rotorshunt-out.json", "best-effort.toml", "report.html", "report.json", "report.md"]);
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    let page_one = md.lines().take(20).collect::<Vec<_>>().join("\n");
    assert!(
        page_one.contains(
            "**Answer.** **Stopped, NOT A RESULT**: the run was stopped before it ended (at its time limit of 1e-9 s"
        ),
        "{page_one}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    assert_eq!(json["outcome"]["status"], "stopped", "{}", json["outcome"]["stop"]);
    // Nothing was judged before a limit that had passed at the first question: the
    // best design so far is the file's own, and best-effort.toml reads back as it.
    let o = run(&["check", out.join("best-effort.toml").to_str().unwrap()], None);
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_stopped_rerun_leaves_the_earlier_folder_as_it_was() {
    let dir = scratch("time-limit-rerun");
    let out = dir.join("out");
    let fig11 = problem_path("fig11-closed-2000.toml");
    let args = ["chart", &fig11, "--phi", "1200:1260:20", "--beta", "0:0.2:0.1"];
    // A generous limit changes nothing: the chart is written.
    let mut first = vec!["--time-limit", "36000"];
    first.extend(args);
    let o = run(&first, Some(&out));
    assert!(o.status.success(), "{}", stderr(&o));
    let before = common::tree(&dir, Path::new("/nonexistent"));
    assert!(before.keys().any(|p| p.ends_with("chart.json")), "{:?}", before.keys());
    let mut again = vec!["--time-limit", PASSED];
    again.extend(args);
    let o = run(&again, Some(&out));
    assert_eq!(o.status.code(), Some(STOPPED), "{}", stderr(&o));
    assert_eq!(common::tree(&dir, Path::new("/nonexistent")), before, "the earlier chart stands, nothing beside it");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_computation_that_never_asks_is_bounded_by_its_estimate_alone() {
    // One Floquet point is one step (its monodromy): there is nothing to stop between,
    // and its estimate admitted it (docs/errors.md, `TimeLimit`).
    let fig11 = problem_path("fig11-closed-2000.toml");
    let o = run(&["--time-limit", PASSED, "floquet", &fig11, "--phi", "1230", "--beta", "0.3"], None);
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn a_time_limit_that_is_not_a_positive_duration_is_refused() {
    let fig11 = problem_path("fig11-closed-2000.toml");
    for bad in ["0", "-1", "nan", "inf", "-0"] {
        let o = run(&[&format!("--time-limit={bad}"), "check", &fig11], None);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{bad}: {err}");
        assert!(err.starts_with("error: argument `--time-limit`: must be "), "{bad}: {err}");
    }
    // The extremes that are valid: below a nanosecond stops at the first step; beyond
    // any duration never stops.
    let dir = scratch("time-limit-extremes");
    let chart = ["chart", &fig11, "--phi", "1200:1260:20", "--beta", "0:0.2:0.1"];
    for (limit, code) in [("5e-324", STOPPED), ("1e300", 0)] {
        let mut args = vec!["--time-limit", limit];
        args.extend(chart);
        let o = run(&args, Some(&dir.join(limit)));
        assert_eq!(o.status.code(), Some(code), "{limit}: {}", stderr(&o));
        assert_eq!(dir.join(limit).exists(), code == 0, "{limit}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn each_study_case_stops_at_its_own_limit_and_records_only_its_failure() {
    let dir = scratch("time-limit-study");
    let study = common::coarse_study(&dir, "study.toml", "[[cases]]\nname = \"a\"\n[[cases]]\nname = \"b\"\n");
    let out = dir.join("out");
    let o = bin()
        .args(["--quiet", "--time-limit", PASSED, "study", study.to_str().unwrap(), "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(5), "cases failed: {}", stderr(&o));
    let summary = std::fs::read_to_string(out.join("summary/summary.csv")).unwrap();
    for name in ["a", "b"] {
        let case = out.join("cases").join(name);
        let result = common::json(&case.join("result.json"));
        assert_eq!(result["status"], "failed", "{result}");
        let message = result["error"].as_str().unwrap_or_default();
        assert!(message.starts_with("the case's region catalogue was stopped at its time limit"), "{result}");
        assert!(!case.join("regions.json").exists(), "a stopped case writes no regions.json");
    }
    assert!(summary.lines().count() >= 3, "{summary}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_slurm_array_task_runs_under_the_limits_it_was_written_with() {
    let dir = scratch("time-limit-slurm");
    let study = common::coarse_study(&dir, "study.toml", "[[cases]]\nname = \"a\"\n");
    let exec_line = |flags: &[&str], out: &str| {
        let o = bin()
            .args(flags)
            .args(["study", "slurm", study.to_str().unwrap(), "--tasks", "1", "--out"])
            .arg(dir.join(out))
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", stderr(&o));
        let script = std::fs::read_to_string(dir.join(out).join("slurm/study.sbatch")).unwrap();
        let line = script.lines().find(|l| l.starts_with("exec ")).unwrap().to_string();
        line.split(" study ").next().unwrap().to_string()
    };
    // The default budget passes nothing; a given one passes both flags, read back exactly.
    let plain = exec_line(&[], "plain");
    assert!(!plain.contains("--"), "{plain}");
    let limited = exec_line(&["--max-cost", "2", "--time-limit", "90.5"], "limited");
    assert!(limited.ends_with(" --max-cost 2.0 --time-limit 90.5"), "{limited}");
    std::fs::remove_dir_all(&dir).unwrap();
}
