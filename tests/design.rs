//! The shunt design (issue: design optimiser): results checked independently of the
//! optimiser, by a 1 rad/s chart and by the regions command run on the written tuned.toml.

mod common;

use common::problem_path;
use rotorshunt::design::{self, Status};
use rotorshunt::problem::Problem;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rotorshunt"))
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("rotorshunt-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn run_ok(cmd: &mut Command) -> String {
    let out = cmd.output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Verdicts of `rotorshunt chart FILE` on a 1 rad/s grid over [lo, hi] at one β, by φ.
fn fine_chart(file: &Path, lo: f64, hi: f64, beta: f64, dir: &Path) -> Vec<(f64, bool)> {
    run_ok(
        bin()
            .arg("chart")
            .arg(file)
            .args(["--phi", &format!("{}:{}:1", lo.ceil(), hi.floor()), "--beta", &format!("{beta}:{beta}:1"), "--out"])
            .arg(dir),
    );
    let v = json(&dir.join("chart.json"));
    v["chart"]["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| (p["phi"].as_f64().unwrap(), p["stable"].as_bool().unwrap()))
        .collect()
}

/// The run of stable 1 rad/s grid points containing φ_op, as [first, last] stable point.
fn stable_run(points: &[(f64, bool)], phi_op: f64) -> Option<(f64, f64)> {
    let i = points.iter().position(|p| p.0 >= phi_op)?;
    if !points[i].1 {
        return None;
    }
    let mut a = i;
    while a > 0 && points[a - 1].1 {
        a -= 1;
    }
    let mut b = i;
    while b + 1 < points.len() && points[b + 1].1 {
        b += 1;
    }
    Some((points[a].0, points[b].0))
}

/// Regions of `rotorshunt regions FILE --json` whose edges at the level reach into (lo, hi),
/// and the guard scan's unexplained intervals there.
fn regions_inside(file: &Path, range: (f64, f64), lo: f64, hi: f64, level: f64) -> Vec<(String, f64, f64)> {
    let text = run_ok(bin().arg("regions").arg(file).args([
        "--phi",
        &format!("{}:{}", range.0, range.1),
        "--beta-max",
        "1",
        "--level",
        &level.to_string(),
        "--json",
    ]));
    let v: Value = serde_json::from_str(&text).unwrap();
    let mut inside = Vec::new();
    for r in v["regions"].as_array().unwrap() {
        if let (Some(l), Some(rr)) = (r["left"].as_f64(), r["right"].as_f64()) {
            if rr > lo && l < hi {
                inside.push((r["label"].as_str().unwrap().to_string(), l, rr));
            }
        }
    }
    for u in v["unexplained"].as_array().unwrap() {
        let (l, rr) = (u["left"].as_f64().unwrap(), u["right"].as_f64().unwrap());
        if rr > lo && l < hi {
            inside.push(("unexplained".to_string(), l, rr));
        }
    }
    inside
}

#[test]
fn widest_band_design_is_wider_on_an_independent_fine_chart_of_tuned_toml() {
    let dir = tmp("design-widest");
    let input = PathBuf::from(problem_path("design-widest-band.toml"));
    let text = run_ok(bin().arg("design").arg(&input).arg("--out").arg(&dir));
    assert!(text.contains("design: improved"), "{text}");
    for f in ["report.md", "report.json", "tuned.toml", "charts.png", "charts.svg", "campbell.png", "history.png"] {
        assert!(dir.join(f).exists(), "{f} missing");
    }
    let report = json(&dir.join("report.json"));
    let band = report["outcome"]["after_verified"][0][1].as_array().unwrap();
    let (lo, hi) = (band[0].as_f64().unwrap(), band[1].as_f64().unwrap());
    let (phi_op, level) = (1230.0, 0.3);
    assert!(lo < phi_op && phi_op < hi);
    let tuned = dir.join("tuned.toml");
    // 1. No unstable point of a 1 rad/s grid inside the reported band (tuned.toml, chart).
    let inside = fine_chart(&tuned, lo, hi, level, &dir.join("check"));
    let bad: Vec<f64> = inside.iter().filter(|p| !p.1 && p.0 > lo && p.0 < hi).map(|p| p.0).collect();
    assert!(bad.is_empty(), "unstable grid points inside the reported band [{lo}, {hi}]: {bad:?}");
    // 2. The same chart window for the paper's circuit and the tuned one: the stable run of
    //    grid points around φ_op is strictly wider with the tuned circuit.
    let window = (phi_op - 700.0, phi_op + 700.0);
    let reference = stable_run(&fine_chart(&input, window.0, window.1, level, &dir.join("ref")), phi_op);
    let tuned_run = stable_run(&fine_chart(&tuned, window.0, window.1, level, &dir.join("tun")), phi_op).unwrap();
    let ref_width = reference.map_or(0.0, |r| r.1 - r.0);
    assert!(tuned_run.1 - tuned_run.0 > ref_width, "tuned {tuned_run:?} vs reference {reference:?}");
    eprintln!("grid-stable run around 1230 rad/s at beta 0.3: reference {reference:?} ({ref_width}), tuned {tuned_run:?} ({})", tuned_run.1 - tuned_run.0);
    // 3. The regions command on tuned.toml finds no region inside the band as wide as the
    //    1 rad/s grid it is verified on; thinner tongues it does find are named in the report.
    let hits = regions_inside(&tuned, (100.0, 8000.0), lo + 0.5, hi - 0.5, level);
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    for (label, l, r) in &hits {
        assert!(r - l < 1.0, "region {label} [{l}, {r}] inside the tuned band [{lo}, {hi}]");
        assert!(
            md.contains(&format!("{label} (k = ")) && md.contains(&format!("[{l:.2}, {r:.2}]")),
            "{label} not named"
        );
    }
    eprintln!("thin tongues inside the tuned band: {hits:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn clear_bands_design_clears_both_bands_on_an_independent_fine_chart() {
    let dir = tmp("design-clear");
    let input = PathBuf::from(problem_path("design-clear-bands.toml"));
    let text = run_ok(bin().arg("design").arg(&input).arg("--out").arg(&dir));
    assert!(text.contains("design: feasible"), "{text}");
    let tuned = dir.join("tuned.toml");
    let p = Problem::from_path(&tuned, &[]).unwrap();
    let spec = p.design.clone().unwrap();
    let level = spec.level;
    for (i, b) in spec.bands.iter().enumerate() {
        let (lo, hi) = b.guarded();
        let pts = fine_chart(&tuned, lo, hi, level, &dir.join(format!("band{i}")));
        let bad: Vec<f64> = pts.iter().filter(|p| !p.1).map(|p| p.0).collect();
        assert!(bad.is_empty(), "band {i} [{lo}, {hi}] has unstable grid points {bad:?}");
        let hits = regions_inside(&tuned, (lo - 100.0, hi + 100.0), lo, hi, level);
        assert!(hits.is_empty(), "band {i}: {hits:?}");
    }
    // The reference circuit does not clear them (the design changed something that mattered).
    let pts = fine_chart(&input, 1135.0, 1225.0, level, &dir.join("ref"));
    assert!(pts.iter().any(|p| !p.1), "the paper's circuit already clears band 1");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn impossible_bounds_are_reported_infeasible_with_the_violated_bands() {
    let dir = tmp("design-infeasible");
    let out = bin()
        .arg("design")
        .arg(problem_path("design-clear-bands.toml"))
        .args(["--set", "design.variables[0].min=850", "--set", "design.variables[0].max=920"])
        .args(["--set", "design.variables[1].max=1", "--set", "design.max_iterations=4", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(text.contains("design: infeasible"), "{text}");
    assert!(text.contains("violated: band [1150, 1210]"), "{text}");
    let report = json(&dir.join("report.json"));
    assert_eq!(report["outcome"]["status"], "infeasible");
    assert!(!report["outcome"]["after_intrusions"].as_array().unwrap().is_empty());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_design_run_is_reproducible_bit_for_bit_and_under_two_minutes() {
    let p = common::load("design-widest-band.toml", &["design.starts=3", "design.max_iterations=15"]);
    let a = design::run(&p, &|_| {}).unwrap();
    let b = design::run(&p, &|_| {}).unwrap();
    assert_eq!(a.status, Status::Improved);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a.after), bits(&b.after));
    assert_eq!(a.floquet_evaluations, b.floquet_evaluations);
    assert_eq!(format!("{:?}", a.after_verified), format!("{:?}", b.after_verified));
    // The full default run (4 starts × 25 iterations) is timed by the CLI test above; this
    // smaller one must also finish far inside the budget.
    assert!(a.seconds < 120.0, "{} s", a.seconds);
    eprintln!(
        "design run: {:.1} s, {} candidates, {} Floquet evaluations",
        a.seconds, a.candidates, a.floquet_evaluations
    );
}

#[test]
fn design_problems_are_validated_with_key_paths() {
    let base = problem_path("design-widest-band.toml");
    for (set, key) in [
        ("design.level=-0.1", "design.level"),
        ("design.variables[0].branch=3", "design.variables[0].branch"),
        ("design.variables[0].max=500", "design.variables[0].max"),
        ("design.variables[0].parameter=\"resistance\"", "design.variables[1].parameter"),
        ("design.phi_op=9000", "design.phi_op"),
    ] {
        let e = Problem::from_path(&base, &[set.to_string()]).unwrap_err();
        assert_eq!(e.key, key, "{set}: {e}");
    }
    let e = Problem::from_path(problem_path("design-clear-bands.toml"), &["circuit.state=open".into()]).unwrap_err();
    assert_eq!(e.key, "circuit.state", "{e}");
    // No [design] table: the design command says so and exits 2.
    let out =
        bin().args(["design", &problem_path("fig11-closed-2000.toml"), "--out"]).arg(tmp("nodesign")).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no [design] table"));
}
