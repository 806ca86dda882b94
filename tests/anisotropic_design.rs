//! Issue 28, point 3: design and studies flow through the real path. A widest-band design
//! and a small study on an anisotropic rotor (tests/fixtures/aniso/design-aniso.toml: a
//! tabulated, cross-coupled fluid-film bearing and a cross-coupled seal), each checked by
//! other commands run on the files they wrote, not by the numbers they report.

use crate::common;

use common::{bin, json, run_ok, scratch};
use rotorshunt::problem::Problem;
use serde_json::Value;
use std::path::{Path, PathBuf};

/// β_op and φ_op (rad/s) of the fixture's `[design]`, and its φ window (rad/s).
const LEVEL: f64 = 0.3;
const PHI_OP: f64 = 950.0;
const WINDOW: &str = "850:1100";

fn fixture() -> PathBuf {
    common::root().join("tests/fixtures/aniso/design-aniso.toml")
}

/// `rotorshunt band FILE --phi-op 950 --level 0.3 --phi 850:1100 --json` with `--set`s:
/// the band [lo, hi] (rad/s).
fn band_of(file: &Path, set: &[&str]) -> (f64, f64) {
    let mut cmd = bin();
    cmd.arg("band").arg(file);
    for s in set {
        cmd.args(["--set", s]);
    }
    let text =
        run_ok(cmd.args(["--phi-op", &PHI_OP.to_string(), "--level", &LEVEL.to_string(), "--phi", WINDOW, "--json"]));
    let v: Value = serde_json::from_str(&text).unwrap();
    (v["band"]["lo"].as_f64().unwrap(), v["band"]["hi"].as_f64().unwrap())
}

fn lo_hi(v: &Value) -> (f64, f64) {
    (v["lo"].as_f64().unwrap(), v["hi"].as_f64().unwrap())
}

#[test]
fn a_design_on_an_anisotropic_rotor_ends_verified_with_the_band_of_its_tuned_file() {
    let input = fixture();
    let p = Problem::from_path(&input, &[]).unwrap();
    assert!(p.model.real_coordinates(), "the fixture must take the real path");
    let dir = scratch("aniso-design");
    let out = dir.join("design");
    let o = bin()
        .arg("design")
        .arg(&input)
        .args(common::COARSE_CHART_ARGS)
        .arg("--out")
        .arg(&out)
        .arg("--quiet")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(0), "{stdout}{}", String::from_utf8_lossy(&o.stderr));
    assert!(stdout.contains("design: improved") && stdout.contains("verification: passed"), "{stdout}");
    for f in ["report.md", "report.html", "report.json", "tuned.toml", "charts.png", "campbell.png"] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let report = json(&out.join("report.json"));
    let outcome = &report["outcome"];
    assert_eq!(outcome["status"], "improved");
    assert_eq!(outcome["verified"], true);
    let before = lo_hi(&outcome["before_bands"][0]["band"]["band"]);
    let after = lo_hi(&outcome["after_bands"][0]["band"]["band"]);

    // The tuned file is a complete anisotropic problem: still on the real path, with the
    // bearing's speed tables and the seal, and a circuit inside the variables' bounds.
    let tuned = out.join("tuned.toml");
    let t = Problem::from_path(&tuned, &[]).unwrap();
    assert!(t.model.real_coordinates());
    assert_eq!((t.model.bearings.len(), t.model.speed), (p.model.bearings.len(), p.model.speed));
    let text = std::fs::read_to_string(&tuned).unwrap();
    assert!(text.contains("kxy") && text.contains("speeds"), "tuned.toml lost the bearing's tables");
    let value = |key: &str| -> f64 {
        let line = text.lines().find(|l| l.trim_start().starts_with(key)).unwrap_or_else(|| panic!("no {key}"));
        line.split('=').nth(1).unwrap().trim().parse().unwrap()
    };
    let (tuning, resistance) = (value("tuning_frequency"), value("resistance"));
    assert!((700.0..=1100.0).contains(&tuning), "tuning {tuning} rad/s outside its bounds");
    assert!((0.0..=20.0).contains(&resistance), "R {resistance} Ω outside its bounds");
    assert!(tuning != 900.0 || resistance != 0.0, "the circuit did not change");

    // 1. The design's bands are `rotorshunt band` run on the input and on tuned.toml.
    assert_eq!(band_of(&input, &[]), before, "before");
    assert_eq!(band_of(&tuned, &[]), after, "after");
    assert!(after.1 - after.0 > before.1 - before.0, "{after:?} not wider than {before:?}");
    assert!(after.0 <= PHI_OP && PHI_OP <= after.1, "{after:?} does not hold φ_op");

    // 2. The verification checked something: every part applicable and passed, its grid
    // the interior points of the band at 0.05 rad/s (docs/design.md), lo + 0.05 i for
    // i = 1 .. width/0.05 - 1 (one either way for rounding).
    let v = &outcome["verification"];
    let parts = v["parts"].as_array().unwrap();
    let part = |name: &str| parts.iter().find(|q| q["part"] == name).unwrap_or_else(|| panic!("no part {name}"));
    for name in ["catalogue", "centres", "grid"] {
        assert_eq!(part(name)["status"], "passed", "{}", part(name));
        assert_eq!(part(name)["failed"], 0);
    }
    let grid = part("grid")["checked"].as_u64().unwrap();
    let expected = ((after.1 - after.0) / 0.05).floor() as u64 - 1;
    assert!(grid + 1 >= expected && grid <= expected + 1, "grid checked {grid} points over {after:?}");
    assert!(part("catalogue")["checked"].as_u64().unwrap() > 0);

    // 3. An independent chart of tuned.toml at β_op (0.125 rad/s, not the verifier's
    // grid): no unstable point inside the band.
    let chart = dir.join("chart");
    run_ok(
        bin()
            .arg("chart")
            .arg(&tuned)
            .args(["--phi", &format!("{}:{}:0.125", after.0, after.1), "--beta", &format!("{LEVEL}:{LEVEL}:1")])
            .arg("--out")
            .arg(&chart),
    );
    let points = json(&chart.join("chart.json"))["chart"]["points"].as_array().unwrap().clone();
    assert_eq!(points.len() as f64, ((after.1 - after.0) / 0.125).floor() + 1.0);
    let unstable: Vec<f64> = points
        .iter()
        .filter(|q| q["stable"] == false)
        .map(|q| q["phi"].as_f64().unwrap())
        .filter(|phi| *phi > after.0 && *phi < after.1)
        .collect();
    assert!(unstable.is_empty(), "unstable points inside the tuned band {after:?}: {unstable:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_study_over_the_anisotropic_rotor_reports_the_bands_of_its_speeds() {
    // Two regions cases at two speeds: the bearing's coefficients come from its table at
    // each speed (4.5e7 and 4.9e7 N/m for kxx), so each case is its own rotor.
    let dir = scratch("aniso-study");
    let study = dir.join("study.toml");
    std::fs::write(
        &study,
        format!(
            "base = {:?}\nkind = \"regions\"\nphi = [850.0, 1100.0]\nbeta_max = {LEVEL}\nlevel = {LEVEL}\n\
             phi_op = {PHI_OP}\n\n[sweep]\nspeed = [1000.0, 1500.0]\n",
            fixture().display().to_string()
        ),
    )
    .unwrap();
    let out = dir.join("out");
    let text = run_ok(bin().arg("study").arg(&study).arg("--out").arg(&out));
    assert!(text.contains("study: 2 cases (2 run, 0 skipped as finished, 0 failed)"), "{text}");
    let summary = json(&out.join("summary/summary.json"));
    let cases = summary["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 2);
    for (case, speed) in cases.iter().zip(["1000.0", "1500.0"]) {
        assert_eq!(case["status"], "ok", "{case}");
        assert_eq!(case["overrides"][0], format!("speed={speed}"));
        let m = &case["metrics"];
        let band = (m["band_lo"].as_f64().unwrap(), m["band_hi"].as_f64().unwrap());
        // The case's band is `rotorshunt band` on the base file at that speed.
        assert_eq!(band_of(&fixture(), &[&format!("speed={speed}")]), band, "{speed}");
        // Its region count is that of its own regions.json.
        let slug = case["slug"].as_str().unwrap();
        let regions = json(&out.join("cases").join(slug).join("regions.json"));
        assert_eq!(m["regions"].as_u64().unwrap() as usize, regions["regions"].as_array().unwrap().len(), "{speed}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
