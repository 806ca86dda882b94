//! Margins (issue 27, point 1): a design with `[design.margins]` holds them by routes the
//! optimiser does not take (`rotorshunt regions` on the written tuned.toml), the paper
//! design's report states its load margin and its strict-criterion band, the strict band
//! of `band` is the catalogue's under the strict tolerance declared, and a negative
//! margin is refused naming its key and line.

use crate::common;

use common::{bin, json, problem_path, run_ok, tmp};
use serde_json::Value;
use std::path::Path;

/// Coarse settings that keep a design run short (as tests/hostile_folder.rs takes them),
/// without the refined-basis check (the margins are checked here on the same basis).
const COARSE: [&str; 4] =
    ["shaft.elements=8", "disks[0].node=2", "analysis.reduced_modes=4", "design.refined_check=false"];
/// β_op of the design problems and the margin asked by problems/design-margins.toml.
const LEVEL: f64 = 0.3;
const BETA_MARGIN: f64 = 0.2;
const PHI_MARGIN: f64 = 50.0;
/// φ_op of problems/design-margins.toml: on the coarse model it lies 35 rad/s above the tongue bounding the
/// reference's band at the margin level: the margin binds, and tuning can meet it.
const PHI_OP: f64 = 1330.0;
/// Two edges computed by different routes agree to the band edges' lattice cell
/// (0.125 rad/s, the largest power of two below `regions.phi_tolerance` = 0.2).
const CELL: f64 = 0.125;

fn with_sets(cmd: &mut std::process::Command, sets: &[&str]) {
    for s in sets {
        cmd.args(["--set", s]);
    }
}

/// `rotorshunt regions FILE --json` over 100..8000 rad/s.
fn regions(file: &Path, beta_max: f64, level: f64, sets: &[&str]) -> Value {
    let mut cmd = bin();
    cmd.arg("regions").arg(file).args([
        "--phi",
        "100:8000",
        "--beta-max",
        &beta_max.to_string(),
        "--level",
        &level.to_string(),
        "--json",
    ]);
    with_sets(&mut cmd, sets);
    serde_json::from_str(&run_ok(&mut cmd)).unwrap()
}

/// The stable band of a catalogue containing φ.
fn band_containing(cat: &Value, phi: f64) -> Option<(f64, f64)> {
    cat["stable_bands"].as_array().unwrap().iter().find_map(|b| {
        let (lo, hi) = (b["lo"].as_f64().unwrap(), b["hi"].as_f64().unwrap());
        (lo <= phi && phi <= hi).then_some((lo, hi))
    })
}

#[test]
fn design_with_margins_holds_them_by_the_catalogue_of_tuned_toml() {
    let margin_level = (1.0 + BETA_MARGIN) * LEVEL;
    let input = problem_path("design-margins.toml");
    // The reference misses the frequency margin at the margin level (the constraint binds).
    let sets: Vec<&str> = COARSE.to_vec();
    let reference = regions(Path::new(&input), margin_level, margin_level, &sets);
    let (lo, hi) = band_containing(&reference, PHI_OP).expect("phi_op stable at the margin level");
    assert!(
        PHI_OP - lo < PHI_MARGIN || hi - PHI_OP < PHI_MARGIN,
        "the reference already meets the margin: [{lo}, {hi}]"
    );

    let dir = tmp("margins-design");
    let mut cmd = bin();
    cmd.arg("design").arg(&input).arg("--quiet");
    with_sets(&mut cmd, &sets);
    with_sets(&mut cmd, &["design.starts=2", "design.max_iterations=12"]);
    with_sets(&mut cmd, &common::COARSE_CHARTS);
    run_ok(cmd.arg("--out").arg(&dir));
    let report = json(&dir.join("report.json"))["outcome"].clone();
    assert_eq!(report["verified"], Value::Bool(true), "{}", report["after_speeds"][0]["failures"]);
    assert!(common::outcome_round_trips(&report).after_speeds.iter().all(|s| s.margin_check.is_some()));
    let tuned = dir.join("tuned.toml");

    // At the margin level: φ_op at least 50 rad/s from each edge of its band, and no
    // counted tongue (their onsets are below that level) within 50 rad/s of φ_op.
    let high = regions(&tuned, margin_level, margin_level, &[]);
    let (lo, hi) = band_containing(&high, PHI_OP).expect("phi_op stable at the margin level");
    assert!(PHI_OP - lo >= PHI_MARGIN && hi - PHI_OP >= PHI_MARGIN, "band [{lo}, {hi}] at beta = {margin_level}");
    let guarded = (PHI_OP - PHI_MARGIN, PHI_OP + PHI_MARGIN);
    let mut reaching = Vec::new();
    for r in high["regions"].as_array().unwrap() {
        if let (Some(l), Some(rr)) = (r["left"].as_f64(), r["right"].as_f64()) {
            if r["counted"].as_bool().unwrap() && rr > guarded.0 && l < guarded.1 {
                reaching.push(r["label"].as_str().unwrap().to_string());
            }
        }
    }
    for u in high["unexplained"].as_array().unwrap() {
        if u["hi"].as_f64().unwrap() > guarded.0 && u["lo"].as_f64().unwrap() < guarded.1 {
            reaching.push("unexplained".into());
        }
    }
    assert!(reaching.is_empty(), "tongues within {PHI_MARGIN} rad/s of phi_op at beta = {margin_level}: {reaching:?}");
    // The design's own margin check names the same band as the catalogue.
    let mc = &report["after_speeds"][0]["margin_check"]["band"];
    assert!((mc["lo"].as_f64().unwrap() - lo).abs() <= CELL && (mc["hi"].as_f64().unwrap() - hi).abs() <= CELL, "{mc}");

    // At β_op, onsets up to the margin level: no region with an onset below 1.2·β_op is
    // born inside, or reaches into, the guarded window around φ_op.
    let low = regions(&tuned, margin_level, LEVEL, &[]);
    let mut born = Vec::new();
    for r in low["regions"].as_array().unwrap() {
        let onset = r["onset_beta"].as_f64().unwrap();
        let start = r["start"].as_f64().unwrap();
        let edges = (r["left"].as_f64(), r["right"].as_f64());
        // A tongue at the level counts by its flag; one born above it by its start.
        let inside = match edges {
            (Some(l), Some(rr)) => r["counted"].as_bool().unwrap() && rr > guarded.0 && l < guarded.1,
            _ => guarded.0 < start && start < guarded.1,
        };
        if onset < margin_level && inside {
            born.push((r["label"].as_str().unwrap().to_string(), onset, start));
        }
    }
    assert!(
        born.is_empty(),
        "regions with onset below {margin_level} reaching within {PHI_MARGIN} rad/s of phi_op: {born:?}"
    );
}

#[test]
fn paper_design_report_states_its_load_margin_and_strict_band() {
    let dir = tmp("margins-paper-report");
    let mut cmd = bin();
    cmd.arg("design").arg(problem_path("design-widest-band.toml")).arg("--quiet");
    with_sets(&mut cmd, &["design.starts=1", "design.max_iterations=3"]);
    with_sets(&mut cmd, &common::COARSE_CHARTS);
    with_sets(&mut cmd, &common::QUICK_BASIS);
    // The paper's criterion, max|μ| ≤ 1.0001: the strict band is reported beside it.
    with_sets(&mut cmd, &["analysis.instability_tolerance=1.0001"]);
    run_ok(cmd.arg("--out").arg(&dir));
    let report = json(&dir.join("report.json"))["outcome"].clone();
    let d = &report["after_speeds"][0];
    let m = &d["margins"];
    let band = &d["band"]["band"];
    let (lo, hi) = (band["lo"].as_f64().unwrap(), band["hi"].as_f64().unwrap());
    let phi_op = 1230.0;
    assert!((m["phi_below"].as_f64().unwrap() - (phi_op - lo)).abs() < 1e-9, "{m}");
    assert!((m["phi_above"].as_f64().unwrap() - (hi - phi_op)).abs() < 1e-9, "{m}");
    // The load margin: the lowest onset above β_op among the report catalogue's regions
    // born inside the band, or none up to its β_max (1 by default).
    let regions = d["catalogue"]["regions"].as_array().unwrap();
    let expected = regions
        .iter()
        .filter(|r| {
            let (onset, start) = (r["onset_beta"].as_f64().unwrap(), r["start"].as_f64().unwrap());
            onset > LEVEL && lo < start && start < hi
        })
        .map(|r| r["onset_beta"].as_f64().unwrap())
        .fold(f64::INFINITY, f64::min);
    match m["load"].as_object() {
        Some(l) => {
            let margin = l["margin"].as_f64().unwrap();
            assert!(margin.is_finite() && margin > 0.0, "{m}");
            assert!((l["onset"].as_f64().unwrap() - expected).abs() < 1e-12, "{m} vs {expected}");
        }
        None => assert!(expected.is_infinite(), "{m}: a region born inside at onset {expected}"),
    }
    // Inside the band every sampled point is stable by the declared tolerance.
    let largest = m["max_multiplier"].as_f64().unwrap();
    assert!(largest.is_finite() && largest <= 1.0001 && m["sampled"].as_u64().unwrap() > 0, "{m}");
    // The strict band lies inside the declared one.
    let strict = &m["strict_band"];
    let (slo, shi) = (strict["lo"].as_f64().unwrap(), strict["hi"].as_f64().unwrap());
    assert!(slo.is_finite() && shi.is_finite() && slo >= lo && shi <= hi && slo < phi_op && phi_op < shi, "{m}");
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(md.contains("load margin") && md.contains("strict band"), "report.md states no margins");
    assert!(md.contains(&format!("[{slo:.2}, {shi:.2}]")), "report.md lacks the strict band [{slo:.2}, {shi:.2}]");
}

#[test]
fn the_strict_band_of_band_is_the_catalogue_band_at_the_strict_tolerance() {
    // The Fig. 11 file declares the paper's max|mu| > 1.0001; its strict rule is the growth
    // floor, ln max|mu| > 1e-6.
    let file = problem_path("fig11-closed-2000.toml");
    let text = run_ok(
        bin().arg("band").arg(&file).args(["--phi-op", "1230", "--level", "0.3", "--phi", "100:8000", "--json"]),
    );
    let v: Value = serde_json::from_str(&text).unwrap();
    let m = &v["margins"];
    assert_eq!(m["strict"]["rule"], "growth", "{m}");
    let floor = m["strict"]["floor"].as_f64().unwrap();
    assert!(floor <= 1e-6, "{m}");
    let strict = &m["strict_band"];
    let (slo, shi) = (strict["lo"].as_f64().unwrap(), strict["hi"].as_f64().unwrap());
    // The catalogue with that rule declared as a tolerance on max|mu| (e^floor: the same
    // threshold to 5e-13): an independent route to the same band.
    let set = format!("analysis.instability_tolerance={}", floor.exp());
    let cat = regions(Path::new(&file), 0.3, 0.3, &[&set]);
    let (lo, hi) = band_containing(&cat, 1230.0).expect("1230 rad/s stable by the strict criterion");
    assert!(
        (lo - slo).abs() <= CELL && (hi - shi).abs() <= CELL,
        "band's strict [{slo}, {shi}] vs catalogue [{lo}, {hi}]"
    );
    // Frequency margins are the distances to the declared band's edges.
    let b = &v["band"];
    assert!((m["phi_below"].as_f64().unwrap() - (1230.0 - b["lo"].as_f64().unwrap())).abs() < 1e-9);
    assert!((m["phi_above"].as_f64().unwrap() - (b["hi"].as_f64().unwrap() - 1230.0)).abs() < 1e-9);
}

#[test]
fn a_margin_no_band_in_the_window_can_give_is_refused_at_its_key_before_any_solve() {
    // Issue 50, item 7. problems/design-margins.toml: β_op = 0.3, φ_op = 1330 rad/s in
    // [100, 8000] rad/s. A band found in the window ends inside it, so φ_op's room is
    // min(1330 − 100, 8000 − 1330) = 1230 rad/s; the margin level (1 + m)·0.3 stays at most
    // MAX_BETA = 100 for m ≤ 100/0.3 − 1 = 332.33. Both messages quote the value typed.
    let file = problem_path("design-margins.toml");
    for (set, expected) in [
        (
            "design.margins.phi=1e300",
            "error: problems/design-margins.toml, --set: key `design.margins.phi`: must be at most 1230 rad/s, the room phi_op = 1330 rad/s has inside the design's phi range [100, 8000] rad/s (no stable band found there reaches farther), found 1e300",
        ),
        (
            "design.margins.beta=1000",
            "error: problems/design-margins.toml, --set: key `design.margins.beta`: must be at most 332.333 (with beta_op = 0.3 a larger margin puts the margin level (1 + beta) beta_op above 100, the largest beta a search covers), found 1000",
        ),
    ] {
        // `design` itself refuses it before it makes its folder.
        let dir = tmp("margins-refused");
        let out = bin()
            .current_dir(common::root())
            .args(["design", "problems/design-margins.toml", "--set", set, "--out"])
            .arg(&dir)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{set}");
        assert_eq!(String::from_utf8_lossy(&out.stderr).lines().next(), Some(expected), "{set}");
        assert!(!dir.exists(), "{set}: refused before the folder is made");
    }
    // 1230 rad/s itself and m = 332 are admitted.
    let p = rotorshunt::problem::Problem::from_path(
        &file,
        &["design.margins.phi=1230".into(), "design.margins.beta=332".into()],
    )
    .unwrap();
    // The library's route, DesignSpec::check, by the same rule and value.
    let mut spec = p.design.unwrap();
    let margins = spec.constraints.margins.as_mut().unwrap();
    margins.phi = 1e300;
    let (key, e) = spec.check(&[2, 2]).unwrap_err();
    assert_eq!((key.as_str(), e.value), ("margins.phi", 1e300));
}
