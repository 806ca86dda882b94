//! Regression: the miss found by a design run's independent verification, `missed-f2b2-k3`
//! (tests/fixtures/regressions/missed-f2b2-k3.toml, a tuned design on the paper's rotor,
//! run at Ω = 1900 rad/s). At β = 0.3 the f2+b2 tongue of order 3 is about 0.16 rad/s
//! wide at φ ≈ 1196.4 rad/s with max|μ| ≈ 1.00026, barely above the 1.0001 tolerance; `band`
//! around φ_op = 1230 rad/s reported [1188.75, 1464.25] rad/s across it, and `regions` over
//! 1150–1250 rad/s listed nothing there: the seed's centre search had taken a foreign
//! multiplier for the pair's backward one beside the collision (docs/decisions.md,
//! "A seed's pair: every eigenvector is one whirl's").
//!
//! The reference is independent of the region search: Floquet points by the DSTM path
//! (`point_dstm`, the file's 4096 reference steps) on a 0.02 rad/s grid around the tongue,
//! plain fast-path points on a 0.05 rad/s grid inside the whole band, and the tongue's
//! pair from the full model's whirls and the unstable exponent's frequency.

use crate::common;

use rayon::prelude::*;
use rotorshunt::analysis::floquet::FloquetSystem;
use rotorshunt::analysis::modes::{whirl_modes_of, Whirl};
use rotorshunt::analysis::regions::{band, catalogue, Bound, CatalogueRequest, RegionSettings};
use rotorshunt::analysis::{Criterion, Interval, Rotor};
use rotorshunt::problem::Problem;

/// The design run's verification was at this speed (the file's own is 2000 rad/s).
const SPEED: &str = "speed=1900";
const LEVEL: f64 = 0.3;
const PHI_OP: f64 = 1230.0;
/// The band's window and the catalogue's range of the reported commands (rad/s).
const WINDOW: Interval = Interval::new(100.0, 8000.0);
const NEAR: Interval = Interval::new(1150.0, 1250.0);
/// The reference grid around the tongue (rad/s): its φ range and step.
const REFERENCE: (f64, f64, f64) = (1195.8, 1197.0, 0.02);
/// The fast grid inside the band and the reach beyond an edge (rad/s), as tests/band_truth.rs.
const GRID: f64 = 0.05;
const BEYOND: f64 = 0.5;

fn problem() -> Problem {
    let path = common::root().join("tests/fixtures/regressions/missed-f2b2-k3.toml");
    Problem::from_path(path, &[SPEED.to_string()]).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn missed_f2b2_k3_is_outside_the_band_and_catalogued() {
    let p = problem();
    let rotor = Rotor::new(&p.model).unwrap();
    let fs = FloquetSystem::new(&rotor, &p.settings, p.model.speed).unwrap();
    let full = whirl_modes_of(&rotor, &p.settings, p.model.speed).unwrap();
    let criterion = Criterion::of(&p.settings);
    let s = RegionSettings::default();

    // The reference: DSTM points around 1196.4 rad/s; the tongue is where they count.
    let (lo, hi, step) = REFERENCE;
    let phis: Vec<f64> = (0..=((hi - lo) / step).round() as usize).map(|i| lo + i as f64 * step).collect();
    let points: Vec<_> = phis.par_iter().map(|&phi| fs.point_dstm(phi, LEVEL, p.settings.reference_steps)).collect();
    let unstable: Vec<f64> =
        points.iter().filter(|pt| criterion.counts(&pt.summary)).map(|pt| pt.summary.phi).collect();
    let peak = points.iter().max_by(|a, b| a.summary.max_multiplier.total_cmp(&b.summary.max_multiplier)).unwrap();
    println!(
        "DSTM: {} of {} points count in [{lo}, {hi}] rad/s: {}; peak max|mu| {:.7} at {:.2} rad/s",
        unstable.len(),
        points.len(),
        unstable.iter().map(|x| format!("{x:.2}")).collect::<Vec<_>>().join(" "),
        peak.summary.max_multiplier,
        peak.summary.phi
    );
    assert!(!unstable.is_empty(), "the reference finds no tongue near 1196.4 rad/s: the case is not reproduced");
    let (first, last) = (unstable[0], unstable[unstable.len() - 1]);
    assert!(last - first < 0.5, "one thin tongue expected, unstable from {first} to {last} rad/s");

    // Its pair, from the physics: the unstable exponent's frequency |arg μ|·φ/2π is that of
    // f2 folded by 2φ, and the order-3 sum of the full model's f2 and b2 lies beside it.
    let whirl =
        |w: Whirl, tag: &str| full.modes.iter().find(|m| m.whirl == w && m.tag() == tag).map(|m| m.frequency).unwrap();
    let (f2, b2) = (whirl(Whirl::Forward, "f2"), whirl(Whirl::Backward, "b2"));
    let mu = peak.multipliers.iter().max_by(|a, b| a[0].hypot(a[1]).total_cmp(&b[0].hypot(b[1]))).unwrap();
    let phi = peak.summary.phi;
    let nu = mu[1].atan2(mu[0]).abs() * phi / std::f64::consts::TAU;
    println!(
        "exponent frequency {nu:.2} rad/s, |2 phi - f2| = {:.2}; (f2 + b2)/3 = {:.3}",
        (2.0 * phi - f2).abs(),
        (f2 + b2) / 3.0
    );
    assert!(common::rel(nu, (2.0 * phi - f2).abs()) < 0.01, "exponent {nu} rad/s is not f2 folded by 2φ");
    assert!(common::rel(phi, (f2 + b2) / 3.0) < 0.005, "the tongue at {phi} rad/s is not f2+b2 of order 3");

    // 1. The band around φ_op does not reach across the tongue, and its lower edge is the
    //    tongue's.
    let b = band(&fs, &full, &s, WINDOW, PHI_OP, LEVEL).unwrap();
    let found = b.band.expect("φ_op = 1230 rad/s is stable");
    println!("band [{}, {}] rad/s, {} evaluations, below: {:?}", found.lo, found.hi, b.evaluations, b.left);
    for &x in &unstable {
        assert!(
            !(x > found.lo && x < found.hi),
            "DSTM-unstable {x} rad/s inside the band [{}, {}]",
            found.lo,
            found.hi
        );
    }
    assert!(
        found.lo >= last && found.lo - last <= BEYOND,
        "lower edge {} rad/s is not the tongue's (unstable up to {last} rad/s)",
        found.lo
    );
    match &b.left {
        Some(Bound::Tongue { label, .. }) => assert_eq!(label, "f2+b2 (k = 3)", "lower bound"),
        other => panic!("lower bound {other:?}"),
    }

    // 2. No point of a 0.05 rad/s grid inside the band counts (fast path, plain points).
    let first_k = (found.lo / GRID).floor() as i64 + 1;
    let last_k = (found.hi / GRID).ceil() as i64 - 1;
    let inside: Vec<f64> =
        (first_k..=last_k).map(|k| k as f64 * GRID).filter(|&x| x > found.lo && x < found.hi).collect();
    let counted: Vec<f64> = inside
        .par_iter()
        .copied()
        .filter(|&x| criterion.counts(&fs.point_fast(&fs.table(x, LEVEL), LEVEL).summary))
        .collect();
    println!("{} grid points inside the band, {} count", inside.len(), counted.len());
    assert!(counted.is_empty(), "grid points inside the band count: {counted:?}");

    // 3. The catalogue of 1150–1250 rad/s lists the tongue as f2+b2 of order 3, counted.
    let req = CatalogueRequest::builder().range(NEAR).beta_max(1.0).level(LEVEL).build().unwrap();
    let cat = catalogue(&fs, &full, &s, &req).unwrap();
    let holding: Vec<_> = cat
        .regions
        .iter()
        .filter(|r| r.counted && r.left.is_some_and(|l| l <= first) && r.right.is_some_and(|r| r >= last))
        .collect();
    for r in &holding {
        println!("region {} (k = {}): [{:?}, {:?}]", r.label, r.order, r.left, r.right);
    }
    assert!(
        holding.iter().any(|r| r.label == "f2+b2" && r.order == 3),
        "no counted f2+b2 (k = 3) region holds the tongue [{first}, {last}] rad/s"
    );
    assert!(
        cat.stable_bands.iter().all(|band| unstable.iter().all(|&x| !(x > band.lo && x < band.hi))),
        "a stable band of the catalogue contains the tongue"
    );
}
