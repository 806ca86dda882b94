//! Issue 49, point 2: the min-peak design survives its parts. With the inductances ±2 %
//! (`[design.tolerances]`), the design minimises the worst corner's peak; the nominal
//! optimum, tuned sharply to one inductance, loses much of its damping at either corner.
//! The judge is independent of the optimiser's tolerance path: `rotorshunt unbalance` on
//! each written tuned.toml with the branch's inductance set in the file (`--set
//! circuit.branches[0].inductance=…`), the largest refined peak at the disk.

use crate::common;
use common::{bin, json, problem_path, run_ok, tmp};
use rayon::prelude::*;

/// The inductance tolerance (−): the ±2 % of the issue.
const TOLERANCE: f64 = 0.02;

/// The largest refined peak (m) at node 16 over 250–500 rad/s of `file` with branch 1's
/// inductance at `inductance` (H), by `rotorshunt unbalance`.
fn peak(file: &std::path::Path, inductance: f64, name: &str) -> f64 {
    let dir = tmp(name);
    let l = format!("circuit.branches[0].inductance={inductance}");
    let text = run_ok(
        bin()
            .arg("unbalance")
            .arg(file)
            .args(["--set", &l, "--speeds", "250:500:0.5", "--nodes", "16", "--json", "--quiet", "--out"])
            .arg(&dir),
    );
    let _ = std::fs::remove_dir_all(&dir);
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let probe = v["unbalance"]["probes"].as_array().unwrap().iter().find(|p| p["node"] == 16).unwrap().clone();
    probe["peaks"].as_array().unwrap().iter().map(|p| p["amplitude"].as_f64().unwrap()).fold(0.0, f64::max)
}

/// The paper's min-peak file without its band constraint (and the constraint's φ_op): the
/// peak alone is what this test judges, and it needs no Floquet analysis.
fn unconstrained_file(dir: &std::path::Path) -> std::path::PathBuf {
    let text = std::fs::read_to_string(problem_path("design-min-peak-at-speed.toml")).unwrap();
    let mut kept = Vec::new();
    let mut skipping = false;
    for line in text.lines() {
        if line.starts_with('[') {
            skipping = line.starts_with("[design.constraints]");
        }
        if !skipping && !line.starts_with("phi_op") {
            kept.push(line);
        }
    }
    std::fs::create_dir_all(dir).unwrap();
    let file = dir.join("min-peak-free.toml");
    std::fs::write(&file, kept.join("\n")).unwrap();
    file
}

/// A min-peak design of the paper's file without its constraint (`extra` sets): its
/// tuned.toml, branch 1's inductance (H) and report.json.
fn design(extra: &[&str], name: &str) -> (std::path::PathBuf, f64, serde_json::Value) {
    let dir = tmp(name);
    let file = unconstrained_file(&tmp(&format!("{name}-file")));
    let mut cmd = bin();
    cmd.arg("design").arg(&file);
    // 10 iterations per start; the verification's catalogues over 200–1000 rad/s on a
    // fixed basis of 8 modes.
    let quick = ["design.max_iterations=10", "design.phi_range=[200.0, 1000.0]"];
    for s in quick.iter().chain(&common::QUICK_BASIS).chain(&common::COARSE_CHARTS).chain(extra) {
        cmd.args(["--set", s]);
    }
    let text = run_ok(cmd.arg("--out").arg(&dir).arg("--quiet"));
    assert!(text.starts_with("design: improved"), "{text}");
    let report = json(&dir.join("report.json"));
    let inductance = report["branches_after"][0]["inductance"].as_f64().unwrap();
    (dir.join("tuned.toml"), inductance, report)
}

#[test]
fn the_robust_min_peak_design_has_a_lower_worst_corner_than_the_nominal_optimum() {
    let tol = format!("design.tolerances.inductance={TOLERANCE}");
    let runs: Vec<_> = [(vec![], "peak-nominal"), (vec![tol.as_str(), "design.tolerances.samples=8"], "peak-robust")]
        .par_iter()
        .map(|(extra, name)| design(extra, name))
        .collect();
    let worst = |(file, l, _): &(std::path::PathBuf, f64, serde_json::Value), name: &str| {
        let at = |f: f64, tag: &str| peak(file, l * f, &format!("{name}-{tag}"));
        let (nominal, low, high) = (at(1.0, "0"), at(1.0 - TOLERANCE, "lo"), at(1.0 + TOLERANCE, "hi"));
        // The inductance set in the file moves the peak (the set took effect).
        assert!(low.max(high) > 1.05 * nominal, "{name}: {low} {nominal} {high}");
        (nominal, low.max(high))
    };
    let (nominal_at_nominal, nominal_worst) = worst(&runs[0], "nominal");
    let (robust_at_nominal, robust_worst) = worst(&runs[1], "robust");
    println!(
        "L ±2 %: nominal optimum L = {:.4} H, peak {nominal_at_nominal:.4e} m, worst corner {nominal_worst:.4e} m; robust design L = {:.4} H, peak {robust_at_nominal:.4e} m, worst corner {robust_worst:.4e} m ({:+.2} %)",
        runs[0].1,
        runs[1].1,
        100.0 * (robust_worst / nominal_worst - 1.0)
    );
    // The robust design gives up some nominal peak for a lower worst corner.
    assert!(robust_worst < nominal_worst, "robust worst corner {robust_worst} not below the nominal's {nominal_worst}");
    assert!(robust_at_nominal >= nominal_at_nominal * (1.0 - 1e-3), "{robust_at_nominal} {nominal_at_nominal}");
    // The report's as-built part: the optimiser's worst corner found again, by the CLI too.
    let f = &runs[1].2["outcome"]["min_peak"];
    let reported = f["after"]["worst_corner"]["peak"]["amplitude"].as_f64().unwrap();
    assert!((reported / robust_worst - 1.0).abs() < 5e-3, "reported {reported}, unbalance {robust_worst}");
    assert_eq!(f["as_built"]["samples"], 8);
    let parts = runs[1].2["outcome"]["verification"]["parts"].as_array().unwrap().clone();
    let part = parts.iter().find(|p| p["part"] == "tolerance-peaks").expect("a tolerance-peaks part");
    assert_eq!(part["status"], "passed", "{part}");
    assert_eq!(part["checked"], 11, "centre, 2 corners and 8 samples");
    // Page one says it in one line and stays within its 60 lines.
    let md = std::fs::read_to_string(runs[1].0.with_file_name("report.md")).unwrap();
    let end = md.lines().position(|l| l == "---").expect("the end of page one");
    assert!(end <= 60, "page one is {end} lines long");
    let page_one: Vec<&str> = md.lines().take(end).collect();
    assert_eq!(page_one.iter().filter(|l| l.starts_with("As built (L ±2 %)")).count(), 1, "{md}");
}
