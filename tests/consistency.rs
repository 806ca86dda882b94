//! One truth at β_op (issue acceptance): the catalogue reports the same regions and stable
//! bands at the level with and without `--out` (tracking only adds boundaries) and for any
//! β_max ≥ β_op; the stable bands of `band`, of the catalogue, of the design report and of
//! the study summary are the same numbers for the same input.

use crate::common;

use common::problem_path;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rotorshunt"))
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("rotorshunt-consistency-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn run_json(cmd: &mut Command) -> Value {
    let out = cmd.output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

fn read_json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// What a catalogue says at its level: every region's (label, order, left, right,
/// counted) that reaches the level, the unexplained tongues, the ignored ones and the
/// stable bands, as JSON text (exact numbers).
fn at_level(v: &Value) -> String {
    let regions: Vec<Value> = v["regions"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|r| !r["left"].is_null())
        .map(|r| serde_json::json!([r["label"], r["order"], r["left"], r["right"], r["counted"]]))
        .collect();
    serde_json::json!({
        "regions": regions,
        "unexplained": v["unexplained"],
        "ignored": v["ignored"],
        "stable_bands": v["stable_bands"],
    })
    .to_string()
}

fn regions(file: &str, beta_max: &str, out: Option<&Path>) -> Value {
    let mut c = bin();
    c.args(["regions", file, "--phi", "100:8000", "--beta-max", beta_max, "--level", "0.3", "--json"]);
    if let Some(dir) = out {
        c.arg("--out").arg(dir);
    }
    run_json(&mut c)
}

#[test]
fn the_catalogue_at_the_level_is_the_same_with_out_and_for_any_beta_max() {
    let file = problem_path("fig11-closed-2000.toml");
    let reference = regions(&file, "1", None);
    let dir = tmp("out");
    let tracked = regions(&file, "1", Some(&dir));
    let written = read_json(&dir.join("regions.json"));
    let base = at_level(&reference);
    assert_eq!(at_level(&tracked), base, "--out changes the catalogue at the level");
    assert_eq!(at_level(&written), base, "regions.json differs from the printed catalogue");
    // Tracking adds boundaries and nothing else: same regions, one by one.
    let strip = |v: &Value| -> Vec<Value> {
        v["regions"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| {
                let mut r = r.clone();
                r.as_object_mut().unwrap().remove("boundary");
                r
            })
            .collect()
    };
    assert_eq!(strip(&tracked), strip(&reference), "--out changes a region");
    assert!(tracked["regions"].as_array().unwrap().iter().any(|r| !r["boundary"].as_array().unwrap().is_empty()));
    for beta_max in ["2", "100"] {
        let other = regions(&file, beta_max, None);
        assert_eq!(at_level(&other), base, "--beta-max {beta_max} changes the catalogue at the level");
        // Every onset at or below the level is the same number; above it, only regions
        // with onsets below the larger β_max are added.
        let onsets = |v: &Value, below: f64| -> Vec<(String, u64, f64)> {
            v["regions"]
                .as_array()
                .unwrap()
                .iter()
                .filter(|r| r["onset_beta"].as_f64().unwrap() <= below)
                .map(|r| {
                    (
                        r["label"].as_str().unwrap().into(),
                        r["order"].as_u64().unwrap(),
                        r["onset_beta"].as_f64().unwrap(),
                    )
                })
                .collect()
        };
        assert_eq!(onsets(&other, 0.3), onsets(&reference, 0.3), "--beta-max {beta_max}: onsets below the level");
    }
    eprintln!(
        "{} regions, {} stable bands at beta = 0.3, the same with --out and --beta-max 1, 2, 100",
        reference["regions"].as_array().unwrap().len(),
        reference["stable_bands"].as_array().unwrap().len()
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn band_catalogue_design_and_study_give_the_same_band() {
    let file = problem_path("design-widest-band.toml");
    let band = run_json(
        bin()
            .args(["band", &file, "--phi-op", "1230", "--level", "0.3", "--phi", "100:8000", "--json"])
            .args(common::FIXED_BASIS_ARGS),
    );
    let b = (band["band"]["lo"].as_f64().unwrap(), band["band"]["hi"].as_f64().unwrap());
    // The catalogue of the same range at the same level.
    let cat = run_json(
        bin()
            .args(["regions", &file, "--phi", "100:8000", "--beta-max", "0.3", "--level", "0.3", "--json"])
            .args(common::FIXED_BASIS_ARGS),
    );
    let containing: Vec<(f64, f64)> = cat["stable_bands"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| (x["lo"].as_f64().unwrap(), x["hi"].as_f64().unwrap()))
        .filter(|x| x.0 <= 1230.0 && 1230.0 <= x.1)
        .collect();
    assert_eq!(containing, vec![b], "catalogue band");
    // The design report's band before the design (the same file, the same φ range).
    let dir = tmp("design");
    let out = bin()
        .args(["design", &file, "--set", "design.starts=1", "--set", "design.max_iterations=2"])
        .args(common::COARSE_CHART_ARGS)
        .args(common::QUICK_BASIS_ARGS)
        .arg("--out")
        .arg(&dir)
        .output()
        .unwrap();
    assert!(out.status.code().is_some_and(|c| c == 0 || c == 4), "{}", String::from_utf8_lossy(&out.stderr));
    let report = read_json(&dir.join("report.json"));
    let before = &report["outcome"]["before_bands"][0]["band"]["band"];
    assert_eq!((before["lo"].as_f64().unwrap(), before["hi"].as_f64().unwrap()), b, "design report");
    let cb = &report["outcome"]["before_speeds"][0]["catalogue_band"];
    assert_eq!((cb["lo"].as_f64().unwrap(), cb["hi"].as_f64().unwrap()), b, "design report's catalogue");
    // A study regions case of the same file, range and level.
    let study = dir.join("study.toml");
    std::fs::write(
        &study,
        format!(
            "base = \"{file}\"\nkind = \"regions\"\nphi = [100.0, 8000.0]\nbeta_max = 0.3\nlevel = 0.3\nphi_op = 1230.0\nset = [\"analysis.reduced_modes=8\"]\n[[cases]]\nname = \"paper\"\n"
        ),
    )
    .unwrap();
    let sdir = dir.join("study");
    let out = bin().arg("study").arg(&study).arg("--out").arg(&sdir).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let summary = read_json(&sdir.join("summary/summary.json"));
    let m = &summary["cases"][0]["metrics"];
    assert_eq!((m["band_lo"].as_f64().unwrap(), m["band_hi"].as_f64().unwrap()), b, "study summary");
    eprintln!("band around 1230 rad/s at beta = 0.3: {b:?} by band, regions, design and study");
    std::fs::remove_dir_all(&dir).unwrap();
}
