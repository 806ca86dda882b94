//! Batch studies: 12+ cases end to end, one deliberately broken case, and a re-run that
//! skips finished cases without recomputing them.

use crate::common;

use std::path::PathBuf;
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rotorshunt"))
}

#[test]
fn a_study_survives_a_broken_case_and_resumes_without_recomputing() {
    let dir = std::env::temp_dir().join(format!("rotorshunt-study-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // 12 swept regions cases plus one that cannot load (alpha >= 1 buckles the shaft), on
    // the coarse model of common::coarse_study: what is checked is the study's survival of
    // the broken case and its resumption, not the cases' physics.
    let study = common::coarse_study(
        &dir,
        "study.toml",
        r#"[[cases]]
name = "broken: static load above buckling"
set = ["load.alpha=1.5"]

[sweep]
speed = [1000.0, 2000.0, 3000.0]
"circuit.branches[0].resistance" = [0.0, 10.0, 50.0, 100.0]
"#,
    );
    let out_dir = dir.join("out");
    let run = |extra: &[&str]| {
        let out = bin().arg("study").arg(&study).arg("--out").arg(&out_dir).args(extra).output().unwrap();
        // A study with a failed case exits 5 (docs/errors.md), the others being finished.
        assert_eq!(out.status.code(), Some(5), "{}", String::from_utf8_lossy(&out.stderr));
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    let first = run(&[]);
    assert!(first.contains("study: 13 cases (13 run, 0 skipped as finished, 1 failed)"), "{first}");
    assert!(first.contains("failed: broken: static load above buckling"), "{first}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("summary/summary.json")).unwrap()).unwrap();
    let cases = summary["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 13);
    assert_eq!(cases.iter().filter(|c| c["status"] == "ok").count(), 12);
    let broken = cases.iter().find(|c| c["status"] == "failed").unwrap();
    assert!(broken["error"].as_str().unwrap().contains("load.alpha"), "{broken}");
    for f in ["summary/summary.csv", "summary/summary.md"] {
        assert!(out_dir.join(f).exists());
    }
    // summary.md: the flagged count, the failed case flagged, each case linked to its output.
    let md = std::fs::read_to_string(out_dir.join("summary/summary.md")).unwrap();
    // Flagged: the failed case, and every case without a stable band around phi_op.
    let flagged = cases.iter().filter(|c| c["status"] == "failed" || c["metrics"]["band_width"].is_null()).count();
    assert!(md.contains(&format!("13 case(s), {flagged} flagged")), "{md}");
    let row = md.lines().find(|l| l.starts_with("| broken")).expect("row of the failed case");
    assert!(row.contains("| failed | failed |") && row.ends_with("|  |"), "no output linked: {row}");
    for c in cases.iter().filter(|c| c["status"] == "ok") {
        let slug = c["slug"].as_str().unwrap();
        let row = md.lines().find(|l| l.contains(&format!("(../cases/{slug}/regions.json)"))).expect("linked");
        assert_eq!(row.contains("phi_op unstable"), c["metrics"]["band_width"].is_null(), "{row}");
    }
    // Every finished case's result.json, with its modification time.
    let results: Vec<PathBuf> =
        std::fs::read_dir(out_dir.join("cases")).unwrap().map(|e| e.unwrap().path().join("result.json")).collect();
    assert_eq!(results.len(), 13);
    let stamp = |p: &PathBuf| std::fs::metadata(p).unwrap().modified().unwrap();
    let before: Vec<_> = results.iter().map(stamp).collect();
    std::thread::sleep(std::time::Duration::from_millis(50));
    let second = run(&[]);
    assert!(second.contains("study: 13 cases (1 run, 12 skipped as finished, 1 failed)"), "{second}");
    let after: Vec<_> = results.iter().map(stamp).collect();
    let rewritten = before.iter().zip(&after).filter(|(a, b)| a != b).count();
    assert_eq!(rewritten, 1, "only the failed case is run again");
    let summary2 = std::fs::read_to_string(out_dir.join("summary/summary.json")).unwrap();
    let strip = |s: &str| -> serde_json::Value {
        let mut v: serde_json::Value = serde_json::from_str(s).unwrap();
        for c in v["cases"].as_array_mut().unwrap() {
            c["seconds"] = serde_json::Value::Null;
            // The task that ran the case (its pid) differs between runs, like wall times.
            c["task"] = serde_json::Value::Null;
        }
        v
    };
    assert_eq!(strip(&summary2), strip(&serde_json::to_string(&summary).unwrap()), "same results after resuming");
    let forced = run(&["--force"]);
    assert!(forced.contains("(13 run, 0 skipped"), "{forced}");
    std::fs::remove_dir_all(&dir).unwrap();
}
