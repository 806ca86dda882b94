//! Issue 49, point 2: a damping design holds through its run-up. The shunt of
//! `problems/design-min-peak.toml` is tuned to the first critical speed (~360
//! rad/s), which the machine crosses on its way to 2000 rad/s; the band constraint around
//! φ_op is asked over that whole range (`design.speed_range = [300, 2000]`). The design's
//! own check (part `speeds`, 33 speeds) is judged again by `rotorshunt band` on the
//! written tuned.toml at speeds the design did not choose.
//!
//! Ignored in CI (the full model at 5 speeds per candidate and 33 in the verification:
//! about 8 CPU-minutes); run with `cargo test --release --test suite run_up:: -- --ignored
//! --nocapture`.

use crate::common;
use common::{bin, json, problem_path, run_ok, tmp};

/// The file's band constraint: around φ_op = 370 rad/s at β_op = 0.3, at least 200 rad/s.
const PHI_OP: f64 = 370.0;
const LEVEL: f64 = 0.3;
const MIN_WIDTH: f64 = 200.0;
/// The run-up (rad/s).
const RUN_UP: (f64, f64) = (300.0, 2000.0);
/// Speeds of the independent check over the run-up, ends included: none of them on the
/// design's 5-speed grid but the ends, and between the verification's 33.
const CHECK_SPEEDS: usize = 12;

#[test]
#[ignore = "the full model over the run-up (several minutes on 2 cores); run with `cargo test --release --test suite run_up:: -- --ignored`"]
fn the_min_peak_design_holds_at_every_speed_of_its_run_up() {
    let dir = tmp("run-up");
    let text = run_ok(bin().args(["design", &problem_path("design-min-peak.toml"), "--quiet", "--out"]).arg(&dir));
    println!("{text}");
    assert!(text.starts_with("design: improved"), "{text}");
    let report = json(&dir.join("report.json"));
    let parts = report["outcome"]["verification"]["parts"].as_array().unwrap().clone();
    let speeds = parts.iter().find(|p| p["part"] == "speeds").expect("a speeds part");
    assert_eq!(speeds["status"], "passed", "{speeds}");
    assert_eq!(speeds["checked"], 33);
    assert_eq!(speeds["failed"], 0);
    let tuned = dir.join("tuned.toml");
    for i in 0..CHECK_SPEEDS {
        let w = RUN_UP.0 + (RUN_UP.1 - RUN_UP.0) * i as f64 / (CHECK_SPEEDS - 1) as f64;
        let speed = format!("speed={w}");
        let v: serde_json::Value = serde_json::from_str(&run_ok(bin().arg("band").arg(&tuned).args([
            "--set",
            &speed,
            "--phi-op",
            &PHI_OP.to_string(),
            "--level",
            &LEVEL.to_string(),
            "--phi",
            "100:8000",
            "--json",
            "--quiet",
        ])))
        .unwrap();
        let (lo, hi) = (v["band"]["lo"].as_f64(), v["band"]["hi"].as_f64());
        let (Some(lo), Some(hi)) = (lo, hi) else { panic!("φ_op unstable at Ω = {w} rad/s: {v}") };
        println!("Ω = {w:.1} rad/s: band [{lo:.2}, {hi:.2}] ({:.2} rad/s)", hi - lo);
        assert!(hi - lo >= MIN_WIDTH, "Ω = {w}: band [{lo}, {hi}] narrower than {MIN_WIDTH} rad/s");
    }
}
