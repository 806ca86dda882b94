//! Exit codes scripts can trust (docs/errors.md, "Exit status"): 0 a result, 1 an analysis
//! failure, 2 bad input, 5 a study with failed cases. Codes 3 (infeasible design) and 4
//! (design not verified) are tested with the design runs in tests/design.rs.

use crate::common;

use common::problem_path;
use std::process::{Command, Output};

fn rotorshunt(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rotorshunt")).args(args).output().unwrap()
}

#[test]
fn a_result_exits_0() {
    let f = problem_path("fig11-closed-2000.toml");
    let o = rotorshunt(&["band", &f, "--phi-op", "1230", "--level", "0.3"]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stdout).contains("stable band at beta = 0.3"));
}

#[test]
fn an_analysis_failure_exits_1() {
    // Valid input, but more reduced modes than the model has finite ones.
    let f = problem_path("fig9-open-2000.toml");
    let o = rotorshunt(&["floquet", &f, "--phi", "1000", "--beta", "0.3", "--set", "analysis.reduced_modes=200"]);
    assert_eq!(o.status.code(), Some(1), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).starts_with("error: analysis failed"));
}

#[test]
fn bad_input_exits_2_and_level_0_is_refused_by_band_and_regions_alike() {
    let f = problem_path("fig11-closed-2000.toml");
    for args in [
        vec!["band", f.as_str(), "--phi-op", "1230", "--level", "0"],
        vec!["regions", f.as_str(), "--phi", "1000:1500", "--level", "0"],
        vec!["band", f.as_str(), "--phi-op", "1230", "--level", "0.3", "--phi", "2000:3000"],
        vec!["check", f.as_str(), "--set", "shaft.length=-1"],
    ] {
        let o = rotorshunt(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", String::from_utf8_lossy(&o.stderr));
    }
    let level = |cmd: &[&str]| String::from_utf8_lossy(&rotorshunt(cmd).stderr).into_owned();
    let (b, r) = (
        level(&["band", &f, "--phi-op", "1230", "--level", "0"]),
        level(&["regions", &f, "--phi", "1000:1500", "--level", "0"]),
    );
    assert!(b.contains("argument `--level`") && r.contains("argument `--level`"), "{b}{r}");
}

#[test]
fn a_study_with_a_failed_case_exits_5() {
    let dir = std::env::temp_dir().join(format!("rotorshunt-exit5-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let study = dir.join("study.toml");
    std::fs::write(
        &study,
        format!(
            "base = \"{}\"\nphi = [1150.0, 1300.0]\nbeta_max = 0.3\nset = [\"shaft.elements=8\", \"disks[0].node=2\", \"analysis.reduced_modes=4\"]\n\n[[cases]]\nname = \"fine\"\n\n[[cases]]\nname = \"broken\"\nset = [\"load.alpha=1.5\"]\n",
            problem_path("fig11-closed-2000.toml")
        ),
    )
    .unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_rotorshunt"))
        .arg("study")
        .arg(&study)
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(5), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("1 failed") && text.contains("failed: broken"), "{text}");
    std::fs::remove_dir_all(&dir).unwrap();
}
