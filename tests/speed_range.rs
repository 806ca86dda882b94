//! Speed ranges (issue 27, point 3): `problems/design-speed-range.toml` asks the widest
//! band around φ_op = 1230 rad/s for every Ω in [2500, 3000] rad/s. The reference circuit
//! is stable at φ_op at both ends of the range but not inside it (a tongue crosses φ_op):
//! shown here by band queries on the test's own 51-speed grid. The design must find that
//! (its report's check of the reference names a failing interior speed) and fix it: the
//! tuned design is verified on its 33-speed grid and stable at φ_op at every speed of the
//! test's grid. The design runs shortened (1 start of 6 iterations, its catalogues over
//! 900–1700 rad/s around φ_op, through `--set`): what is checked is the design's own
//! check of the reference and the tuned file at the test's speeds, which hold for whatever
//! design the run returns.

use crate::common;

use common::{bin, json, problem_path, run_ok, tmp};
use rayon::prelude::*;
use rotorshunt::analysis::floquet::FloquetSystem;
use rotorshunt::analysis::{Interval, Rotor};
use rotorshunt::problem::Problem;

const PHI_OP: f64 = 1230.0;
const LEVEL: f64 = 0.3;
const WINDOW: Interval = Interval::new(100.0, 8000.0);
const RANGE: Interval = Interval::new(2500.0, 3000.0);
/// The test's speed grid: 10 rad/s apart, ends included.
const TEST_SPEEDS: usize = 51;

/// The band around φ_op at β_op of `p` at speed `w` ([`common::unnamed_band`]).
fn band_at(p: &Problem, w: f64) -> Option<Interval> {
    let rotor = Rotor::new(&p.model).unwrap();
    let fs = FloquetSystem::new(&rotor, &p.settings, w).unwrap();
    common::unnamed_band(&fs, &p.regions, WINDOW, PHI_OP, LEVEL).band
}

/// The speeds of the test's grid (ends included) where φ_op is unstable.
fn unstable_speeds(p: &Problem) -> Vec<f64> {
    let grid: Vec<f64> =
        (0..TEST_SPEEDS).map(|i| RANGE.lo + RANGE.width() * i as f64 / (TEST_SPEEDS - 1) as f64).collect();
    let bands: Vec<Option<Interval>> = grid.par_iter().map(|&w| band_at(p, w)).collect();
    grid.iter().zip(&bands).filter(|(_, b)| b.is_none()).map(|(w, _)| *w).collect()
}

#[test]
fn a_violation_inside_the_speed_range_only_is_found_and_fixed() {
    // On a fixed basis of 8 modes, the design's and the test's band queries alike (the
    // test checks the speed range's handling; tests/true_bands.rs the basis).
    let input = problem_path("design-speed-range.toml");
    let reference = Problem::from_path(&input, &[common::QUICK_BASIS[0].to_string()]).unwrap();
    let bad = unstable_speeds(&reference);
    eprintln!("reference: phi_op unstable at {bad:?} rad/s of the test's {TEST_SPEEDS} speeds");
    assert!(!bad.is_empty(), "the reference is unstable somewhere inside the range");
    assert!(bad.iter().all(|&w| w > RANGE.lo && w < RANGE.hi), "ends stable: {bad:?}");

    let dir = tmp("speed-range");
    let text = run_ok(
        bin()
            .arg("design")
            .arg(&input)
            .args(["--set", "design.starts=1", "--set", "design.max_iterations=6"])
            .args(["--set", "design.phi_range=[900.0, 1700.0]"])
            .args(common::COARSE_CHART_ARGS)
            .args(common::QUICK_BASIS_ARGS)
            .arg("--out")
            .arg(&dir)
            .arg("--quiet"),
    );
    eprintln!("{text}");
    let outcome = json(&dir.join("report.json"))["outcome"].clone();
    assert_eq!(outcome["status"], "improved");
    assert!(common::outcome_round_trips(&outcome).speed_check.is_some());
    // Found: the report's check of the reference names failing interior speeds.
    let before = outcome["speed_check_before"]["failing"].as_array().unwrap();
    assert!(!before.is_empty(), "the design's check of the reference finds the interior violation");
    for f in before {
        let w = f[0].as_f64().unwrap();
        assert!(w > RANGE.lo && w < RANGE.hi, "{f}");
    }
    // Fixed: verified on its grid, and stable at every speed of the test's.
    let part = outcome["verification"]["parts"].as_array().unwrap().iter().find(|p| p["part"] == "speeds").cloned();
    let part = part.expect("a speeds part");
    assert_eq!(part["status"], "passed", "{part}");
    assert_eq!(part["checked"].as_u64(), Some(33));
    let tuned = Problem::from_path(dir.join("tuned.toml"), &[]).unwrap();
    let still = unstable_speeds(&tuned);
    eprintln!(
        "design: the reference failed at {} of 33 speeds, first {}; tuned: unstable at {still:?} of the test's {TEST_SPEEDS}",
        before.len(),
        before[0]
    );
    assert!(still.is_empty(), "{still:?}");
}
