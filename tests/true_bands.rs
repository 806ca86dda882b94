//! True bands (issue 47): answers that hold when the model is refined, and verdicts no
//! larger than the check.
//!
//! - A design on a basis that does not hold (fixed too small) fails its refined-basis part
//!   and is not verified: the check repeats the band on twice the basis.
//! - A design whose φ_op stays inside a tongue is neither improved nor verified, in its
//!   report and in a study's summary alike.
//! - A band that reaches the end of its window is flagged clipped, its width "at least".
//! - The min-peak design is never verified on a band that twice its basis refutes.
//! - By hand (`cargo test --release --test suite -- --ignored true_bands`): every design of
//!   problems/ run with its defaults, and `band` on its tuned.toml at the default basis and
//!   at twice it agree within the convergence tolerance.
//!
//! tests/design.rs runs the widest-band design on its default basis (sized by convergence,
//! checked on twice it) and compares `band` on its tuned.toml at the default and at twice
//! the basis shown converged.

use crate::common;

use common::{bin, json, problem_path, tmp};
use serde_json::Value;
use std::path::Path;

/// `rotorshunt band FILE --phi-op P --level L --phi W --json` with `extra`: its JSON.
fn band_json(file: &Path, phi_op: f64, level: f64, window: &str, extra: &[&str]) -> Value {
    let out = bin()
        .arg("band")
        .arg(file)
        .args(extra)
        .args(["--phi-op", &phi_op.to_string(), "--level", &level.to_string(), "--phi", window, "--json"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

fn lo_hi(v: &Value) -> Option<(f64, f64)> {
    Some((v["lo"].as_f64()?, v["hi"].as_f64()?))
}

/// The edge tolerance of the convergence (the defaults: the larger of 0.25 % of the band's
/// width and 0.5 rad/s).
fn tolerance(width: f64) -> f64 {
    (0.0025 * width).max(0.5)
}

#[test]
fn a_design_on_a_basis_that_does_not_hold_is_not_verified() {
    // A coarse shaft and a fixed basis of 4 modes: the tuned design's band moves by tens of
    // rad/s on 8 modes, which the refined check sees.
    let dir = tmp("true-bands-small-basis");
    let out = bin()
        .arg("design")
        .arg(problem_path("design-widest-band.toml"))
        .args(["--set", "shaft.elements=8", "--set", "disks[0].node=2", "--set", "analysis.reduced_modes=4"])
        .args(["--set", "design.starts=2", "--set", "design.max_iterations=25"])
        .args(["--set", "design.phi_range=[1000.0, 1500.0]"])
        .args(common::COARSE_CHART_ARGS)
        .arg("--out")
        .arg(&dir)
        .arg("--quiet")
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(4), "{text}{}", String::from_utf8_lossy(&out.stderr));
    assert!(text.contains("design: not-verified") && text.contains("refined-basis FAILED"), "{text}");
    let o = &json(&dir.join("report.json"))["outcome"];
    let refined = &o["refined"][0];
    assert_eq!((refined["modes"].as_u64(), refined["refined_modes"].as_u64()), (Some(4), Some(8)));
    assert_eq!(refined["held"], false);
    let moved = refined["movements"][0]["value"].as_f64().unwrap();
    println!("fixed M = 4: the band moved {moved} rad/s on 8 modes");
    assert!(moved > refined["movements"][0]["tolerance"].as_f64().unwrap());
    // The same design sized by convergence holds (its basis grew until it did).
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_design_whose_phi_op_stays_unstable_is_neither_improved_nor_verified() {
    // φ_op = 699 rad/s lies in the mechanical f1+b1 tongue (ω_f1 + ω_b1 ≈ 698.6 rad/s at
    // Ω = 2000 rad/s), which the shunt cannot move out of.
    let dir = tmp("true-bands-unstable");
    let case = [
        "design.phi_op=699",
        "design.phi_range=[500.0, 900.0]",
        "design.starts=1",
        "design.max_iterations=3",
        common::QUICK_BASIS[0],
        common::QUICK_BASIS[1],
    ];
    let mut cmd = bin();
    cmd.arg("design").arg(problem_path("design-widest-band.toml"));
    for s in case {
        cmd.args(["--set", s]);
    }
    let out = cmd.args(common::COARSE_CHART_ARGS).arg("--out").arg(dir.join("design")).arg("--quiet").output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(3), "{text}{}", String::from_utf8_lossy(&out.stderr));
    assert!(text.contains("design: infeasible") && !text.contains("improved"), "{text}");
    assert!(text.contains("operating-point FAILED"), "{text}");
    let o = &json(&dir.join("design/report.json"))["outcome"];
    assert_eq!((o["status"].as_str(), o["verified"].as_bool()), (Some("infeasible"), Some(false)));
    let md = std::fs::read_to_string(dir.join("design/report.md")).unwrap();
    let page_one = md.split("\n---\n").next().unwrap();
    assert!(page_one.contains("**Infeasible**") && page_one.contains("is **unstable** at β_op"), "{page_one}");
    assert!(!page_one.contains("window end"), "no band, so nothing ends at the window: {page_one}");
    assert!(!dir.join("design/tuned.toml").exists());
    // A study of the same case says the same in its summary.
    let sets: Vec<String> = case.iter().chain(&common::COARSE_CHARTS).map(|s| format!("\"{s}\"")).collect();
    let study = dir.join("study.toml");
    std::fs::write(
        &study,
        format!(
            "base = \"{}\"\nkind = \"design\"\nset = [{}]\n[[cases]]\nname = \"unstable\"\n",
            problem_path("design-widest-band.toml"),
            sets.join(", ")
        ),
    )
    .unwrap();
    let out = bin().arg("study").arg(&study).arg("--out").arg(dir.join("study")).arg("--quiet").output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let summary = json(&dir.join("study/summary/summary.json"));
    let m = &summary["cases"][0]["metrics"];
    assert_eq!((m["design_status"].as_str(), m["verified"].as_bool()), (Some("infeasible"), Some(false)), "{m}");
    let md = std::fs::read_to_string(dir.join("study/summary/summary.md")).unwrap();
    assert!(md.contains("infeasible") && md.contains("phi_op unstable") && !md.contains("improved"), "{md}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_band_that_reaches_the_window_is_clipped() {
    // The paper's band around 1230 rad/s on the Fig. 11 rotor is [1191.62, 1233.75]: a
    // window from 1200 rad/s cuts it below.
    let file = Path::new(&problem_path("fig11-closed-2000.toml")).to_path_buf();
    let cut = band_json(&file, 1230.0, 0.3, "1200:1300", &[]);
    assert_eq!(cut["clipped"], true, "{cut}");
    assert_eq!(cut["left"]["kind"], "window");
    let whole = band_json(&file, 1230.0, 0.3, "100:8000", &[]);
    assert_eq!(whole["clipped"], false, "{whole}");
    let text = String::from_utf8_lossy(
        &bin()
            .arg("band")
            .arg(&file)
            .args(["--phi-op", "1230", "--level", "0.3", "--phi", "1200:1300"])
            .output()
            .unwrap()
            .stdout,
    )
    .into_owned();
    assert!(text.contains("width at least") && text.contains("widen --phi"), "{text}");
}

#[test]
#[ignore = "a refined-model check (a design, then its band on twice its basis: about 40 s on 2 cores); tests/design.rs checks a design's band at twice its basis in CI; run by hand: cargo test --release --test suite -- --ignored the_min_peak_design_is_never_verified"]
fn the_min_peak_design_is_never_verified_on_a_band_a_refined_basis_refutes() {
    // The min-peak design with the band of 225 rad/s around 370 rad/s it was once
    // "verified" with (a band 18 rad/s wide on 12 modes): on its default basis, sized by
    // convergence and checked on twice it. Shortened (1 start of 4 iterations, the
    // design's catalogues over 200-1000 rad/s): what is checked holds for whatever the run
    // returns.
    let dir = tmp("true-bands-min-peak");
    let mut cmd = bin();
    cmd.arg("design").arg(problem_path("design-min-peak-at-speed.toml"));
    let sets = [
        "design.constraints.min_band_width=225",
        "design.starts=1",
        "design.max_iterations=4",
        "design.phi_range=[200.0, 1000.0]",
    ];
    for s in sets.iter().chain(&common::COARSE_CHARTS) {
        cmd.args(["--set", s]);
    }
    let out = cmd.arg("--out").arg(&dir).arg("--quiet").output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    println!("{text}");
    let o = &json(&dir.join("report.json"))["outcome"];
    let status = o["status"].as_str().unwrap();
    let modes = o["basis"]["modes"].as_u64().unwrap();
    if o["verified"] == true {
        // Verified: its band holds on twice its basis, by `band` on tuned.toml.
        assert!(["improved", "unchanged"].contains(&status), "{status}");
        let twice = format!("analysis.reduced_modes={}", 2 * modes);
        let b = band_json(&dir.join("tuned.toml"), 370.0, 0.3, "100:8000", &["--set", twice.as_str()]);
        let (lo, hi) = lo_hi(&b["band"]).expect("a band on twice the basis");
        println!("verified on M = {modes}: band [{lo}, {hi}] on M = {}", 2 * modes);
        assert!(hi - lo >= 225.0, "[{lo}, {hi}] on twice the basis");
    } else {
        // Not verified: it ends infeasible (exit 3) and says which constraint it missed.
        assert_eq!((status, out.status.code()), ("infeasible", Some(3)), "{text}");
        assert!(text.contains("stable band around 370 rad/s >= 225 rad/s") && text.contains("NOT met"), "{text}");
        assert!(!dir.join("tuned.toml").exists());
        let constraint = &o["constraints_after"][0];
        println!("infeasible on M = {modes}: the widest band kept is {} rad/s", constraint["value"]);
        assert!(constraint["value"].as_f64().unwrap() < 225.0);
    }
    // Either way the refined check ran and its band is the design's within the tolerance.
    let refined = &o["refined"][0];
    assert_eq!(refined["refined_modes"].as_u64(), Some(2 * modes));
    assert_eq!(refined["held"], true, "{refined}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The designs of problems/ with the `band` questions their tuned.toml answers: (file,
/// φ_op of each band, β_op, window). A widest-band design's φ_op; the min-peak design's
/// constraint's; a clear-bands design's kept-clear bands' centres. The stepped min-peak
/// design asks no band: its refined check (`refined-basis`, report.json) is printed.
const DESIGNS: [(&str, &[f64], f64, &str); 9] = [
    ("design-widest-band.toml", &[1230.0], 0.3, "100:8000"),
    ("design-margins.toml", &[1330.0], 0.3, "100:8000"),
    ("design-robust.toml", &[1230.0], 0.3, "100:8000"),
    ("design-speed-range.toml", &[1230.0], 0.3, "100:8000"),
    ("design-robust-speed-range.toml", &[1230.0], 0.3, "100:8000"),
    ("design-min-peak-at-speed.toml", &[370.0], 0.3, "100:8000"),
    ("design-min-peak-stepped.toml", &[], 0.3, "1000:4000"),
    ("design-clear-bands.toml", &[1180.0, 1850.0], 0.3, "1000:2100"),
    ("design-compressor.toml", &[2000.0], 0.1, "500:6000"),
];

#[test]
#[ignore = "every design of problems/ and its band at twice its basis: an hour and more; run by hand"]
fn every_design_holds_its_band_at_twice_its_basis() {
    // One design by name (ROTORSHUNT_SWEEP=design-robust.toml), or all of them.
    let only = std::env::var("ROTORSHUNT_SWEEP").ok();
    for (name, phis, level, window) in DESIGNS.iter().filter(|d| only.as_deref().is_none_or(|o| o == d.0)) {
        let dir = tmp(&format!("true-bands-{name}"));
        let started = std::time::Instant::now();
        let out = bin().arg("design").arg(problem_path(name)).arg("--out").arg(&dir).arg("--quiet").output().unwrap();
        let text = String::from_utf8_lossy(&out.stdout);
        println!("{name}: exit {:?} after {:.0} s\n{text}", out.status.code(), started.elapsed().as_secs_f64());
        let tuned = if dir.join("tuned.toml").exists() { dir.join("tuned.toml") } else { dir.join("best-effort.toml") };
        let report: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
        for r in report["outcome"]["refined"].as_array().into_iter().flatten() {
            println!(
                "{name}: refined check at {} rad/s: M = {} -> {}, held {}",
                r["speed"], r["modes"], r["refined_modes"], r["held"]
            );
        }
        for phi_op in phis.iter() {
            let auto = band_json(&tuned, *phi_op, *level, window, &[]);
            let m = auto["basis"]["modes"].as_u64().unwrap();
            let twice = format!("analysis.reduced_modes={}", 2 * m);
            // Twice the basis over the whole window costs more than the default allowance
            // (the clear-bands design's band around 1850 rad/s on M = 44: 3.5e14 operations).
            let double = band_json(&tuned, *phi_op, *level, window, &["--set", twice.as_str(), "--max-cost", "20"]);
            match (lo_hi(&auto["band"]), lo_hi(&double["band"])) {
                (Some(a), Some(d)) => {
                    let moved = (a.0 - d.0).abs().max((a.1 - d.1).abs());
                    println!(
                        "{name}: band around {phi_op} rad/s {a:?} on M = {m}, {d:?} on M = {}: moved {moved:.3} rad/s (tolerance {:.3})",
                        2 * m,
                        tolerance(a.1 - a.0)
                    );
                    assert!(moved <= tolerance(a.1 - a.0), "{name}: moved {moved}");
                }
                (None, None) => println!("{name}: {phi_op} rad/s unstable on both bases"),
                (a, d) => panic!("{name}: {a:?} on M = {m} against {d:?} on twice it"),
            }
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
