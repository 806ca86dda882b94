//! Robustness is real (issue 27, point 2): the robust variant of the paper's widest-band
//! design (`problems/design-robust.toml`: L ±5 %, R ±20 %) holds the band it guarantees at
//! every corner of its tolerance box and at 200 Monte Carlo builds, each judged here by a
//! band query on a perturbed copy of its tuned.toml; the nominal design of the same
//! problem (`problems/design-widest-band.toml`) does not hold its band at some corner.
//!
//! The perturbed copies are made independently of the tool's own perturbation: the tuned
//! file's text is rewritten with every branch given by its inductance (L from the file's
//! tuning frequency by Eq. 4, times the factor) and its resistance times the factor, and
//! read as a new problem. The test draws its own samples (another seed). Both designs run
//! shortened through `--set` to keep the test short: the robust one with 2 starts, the
//! nominal one with 2 (whose result breaks at corners), 10 iterations each, their
//! catalogues over 900–1600 rad/s around φ_op. What is checked (the robust result holds at
//! every build, the nominal one does not) is checked on whatever designs the runs return;
//! the closing figures come from the full problems.

use crate::common;

use common::{bin, json, problem_path, run_ok, tmp};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use rotorshunt::analysis::floquet::FloquetSystem;
use rotorshunt::analysis::{Interval, Rotor};
use rotorshunt::model::Branch;
use rotorshunt::problem::Problem;
use serde_json::Value;

const PHI_OP: f64 = 1230.0;
const LEVEL: f64 = 0.3;
const WINDOW: Interval = Interval::new(100.0, 8000.0);
/// The problem's tolerances (design-robust.toml).
const TOL_L: f64 = 0.05;
const TOL_R: f64 = 0.2;
/// Builds drawn by the test, as the acceptance asks.
const SAMPLES: usize = 200;
/// Two routes to a lattice-refined edge give the same number up to round-off (rad/s).
const SAME_EDGE: f64 = 1e-9;
/// Monte Carlo builds of the tool's own check on the result: fewer than the file's 200,
/// since the test checks its own [`SAMPLES`] builds independently (the file's count is
/// what the full problem's figures in problems/README.md were made with).
const TOOL_SAMPLES: u64 = 20;
/// The shortened runs' settings (starts are given per design), on a fixed basis of 8
/// modes without the refined check: the test checks the tolerance box, by band queries on
/// the same basis (tuned.toml keeps the basis in its `[analysis]`).
const SETS: [&str; 4] =
    ["design.max_iterations=10", "design.phi_range=[900.0, 1600.0]", common::QUICK_BASIS[0], common::QUICK_BASIS[1]];

fn design(file: &str, name: &str, starts: usize, extra: &[String]) -> (std::path::PathBuf, Value) {
    let dir = tmp(name);
    let mut cmd = bin();
    cmd.arg("design").arg(problem_path(file)).args(["--set", &format!("design.starts={starts}")]);
    for s in extra {
        cmd.args(["--set", s]);
    }
    for s in SETS.iter().chain(&common::COARSE_CHARTS) {
        cmd.args(["--set", s]);
    }
    let text = run_ok(cmd.arg("--out").arg(&dir).arg("--quiet"));
    eprintln!("{file}:\n{text}");
    let report = json(&dir.join("report.json"));
    common::outcome_round_trips(&report["outcome"]);
    (dir, report)
}

/// The tuned file's text with every branch at L·`fl` (by inductance) and R·`fr`.
fn perturbed(tuned: &str, fl: f64, fr: f64) -> String {
    let mut t: toml::Table = tuned.parse().unwrap();
    t.remove("design");
    let cp_t = t["ring"]["cp_t"].as_float().unwrap();
    let circuit = t.get_mut("circuit").unwrap().as_table_mut().unwrap();
    for b in circuit.get_mut("branches").unwrap().as_array_mut().unwrap() {
        let b = b.as_table_mut().unwrap();
        let c_f = b["c_f"].as_float().unwrap();
        let omega = b.remove("tuning_frequency").unwrap().as_float().unwrap();
        let l = Branch::tuned_inductance(cp_t, c_f, omega);
        b.insert("inductance".into(), toml::Value::Float(l * fl));
        let r = b["resistance"].as_float().unwrap();
        b.insert("resistance".into(), toml::Value::Float(r * fr));
    }
    toml::to_string(&t).unwrap()
}

/// The band around φ_op at β_op of a problem text ([`common::unnamed_band`]).
fn band_of(text: &str) -> Option<Interval> {
    let p = Problem::from_bytes(text.as_bytes(), "perturbed tuned.toml", &[]).unwrap();
    let rotor = Rotor::new(&p.model).unwrap();
    let fs = FloquetSystem::new(&rotor, &p.settings, p.model.speed).unwrap();
    common::unnamed_band(&fs, &p.regions, WINDOW, PHI_OP, LEVEL).band
}

fn interval(v: &Value) -> Interval {
    Interval::new(v["lo"].as_f64().unwrap(), v["hi"].as_f64().unwrap())
}

fn holds(band: Option<Interval>, claimed: Interval) -> bool {
    band.is_some_and(|b| b.lo <= claimed.lo + SAME_EDGE && b.hi >= claimed.hi - SAME_EDGE)
}

const CORNERS: [(f64, f64); 4] =
    [(1.0 - TOL_L, 1.0 - TOL_R), (1.0 - TOL_L, 1.0 + TOL_R), (1.0 + TOL_L, 1.0 - TOL_R), (1.0 + TOL_L, 1.0 + TOL_R)];

#[test]
fn the_robust_design_holds_its_band_as_built_and_the_nominal_one_does_not() {
    // The robust design: verified, its guaranteed band holds at every corner and sample.
    let (dir, report) =
        design("design-robust.toml", "robust-design", 2, &[format!("design.tolerances.samples={TOOL_SAMPLES}")]);
    let outcome = &report["outcome"];
    assert!(["improved", "unchanged"].contains(&outcome["status"].as_str().unwrap()), "{}", outcome["status"]);
    let part = outcome["verification"]["parts"].as_array().unwrap().iter().find(|p| p["part"] == "tolerances").cloned();
    let part = part.expect("a tolerances part");
    assert_eq!(part["status"], "passed", "{part}");
    assert_eq!(part["checked"].as_u64(), Some(5 + TOOL_SAMPLES), "centre, 4 corners and the samples: {part}");
    let guaranteed = interval(&outcome["robustness"]["guaranteed"][0]);
    assert!(guaranteed.contains(PHI_OP), "{guaranteed:?}");
    let tuned = std::fs::read_to_string(dir.join("tuned.toml")).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(2027);
    let mut builds: Vec<(f64, f64)> = CORNERS.to_vec();
    builds.extend(
        (0..SAMPLES).map(|_| (1.0 + TOL_L * rng.random_range(-1.0..=1.0), 1.0 + TOL_R * rng.random_range(-1.0..=1.0))),
    );
    let bands: Vec<Option<Interval>> = builds.par_iter().map(|&(fl, fr)| band_of(&perturbed(&tuned, fl, fr))).collect();
    let failing: Vec<String> = builds
        .iter()
        .zip(&bands)
        .filter(|(_, b)| !holds(**b, guaranteed))
        .map(|((fl, fr), b)| format!("L x{fl:.4}, R x{fr:.4}: band {b:?}"))
        .collect();
    let narrowest = bands.iter().flatten().map(|b| b.width()).fold(f64::INFINITY, f64::min);
    eprintln!(
        "robust: guaranteed band [{:.3}, {:.3}] ({:.2} rad/s); {} corners and {SAMPLES} samples by band queries on perturbed tuned.toml copies: {} not holding it; narrowest band {narrowest:.2} rad/s",
        guaranteed.lo,
        guaranteed.hi,
        guaranteed.width(),
        CORNERS.len(),
        failing.len()
    );
    assert!(failing.is_empty(), "{failing:#?}");

    // The nominal design of the same problem: its band does not hold at some corner.
    let (dir, report) = design("design-widest-band.toml", "robust-design-nominal", 2, &[]);
    let claimed = interval(&report["outcome"]["after_bands"][0]["band"]["band"]);
    let tuned = std::fs::read_to_string(dir.join("tuned.toml")).unwrap();
    let at_corners: Vec<Option<Interval>> =
        CORNERS.par_iter().map(|&(fl, fr)| band_of(&perturbed(&tuned, fl, fr))).collect();
    let broken: Vec<String> = CORNERS
        .iter()
        .zip(&at_corners)
        .filter(|(_, b)| !holds(**b, claimed))
        .map(|((fl, fr), b)| format!("L x{fl}, R x{fr}: band {b:?}"))
        .collect();
    eprintln!("nominal: band [{:.3}, {:.3}]; corners where it does not hold: {broken:#?}", claimed.lo, claimed.hi);
    assert!(!broken.is_empty(), "the nominal design holds its band at every corner: {at_corners:?}");
}
