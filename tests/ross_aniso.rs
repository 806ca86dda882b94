//! Against ROSS itself on the general path (issue 28): the rotor_example geometry on
//! anisotropic, cross-coupled, damped bearings tabulated against speed. ROSS's results
//! are the committed fixtures `tests/fixtures/ross/aniso_tables.*` made by
//! `scripts/ross/make_aniso_fixtures.py` (no Python here), which also writes the rotor as
//! a rotorshunt problem from the numbers it gives ROSS. Rayleigh elements on both sides.

use crate::common;
use rotorshunt::analysis::modes::{whirl_modes, Whirl};
use rotorshunt::analysis::unbalance::{node_probe, unbalance_response};
use rotorshunt::analysis::Rotor;
use rotorshunt::problem::Problem;
use serde_json::Value;

/// Issue 28's acceptance for the whirl frequencies: 0.05 % of ROSS's.
const MODAL_RTOL: f64 = 5e-4;
/// Issue 28's acceptance for the unbalance amplitudes: 0.5 % of ROSS's (relative to the
/// probe's largest amplitude over the speeds, so that a near-zero crossing of one
/// direction does not count as a large relative error).
const UNBALANCE_RTOL: f64 = 5e-3;
/// The bearing coefficients rotorshunt interpolates against ROSS's, relative to the
/// largest value of the same kind (stiffness or damping) in the bearing's table: ROSS
/// fits scipy's `UnivariateSpline` with its default smoothing s = number of points
/// (Σ residual² ≤ 6 here: up to √6 ≈ 2.4 N/m or N·s/m per point), rotorshunt the
/// interpolating not-a-knot spline. Against the tables' largest dampings (~900 N·s/m)
/// that allows 2.7e-3.
const COEFFICIENT_RTOL: f64 = 2.7e-3;
/// The lowest lateral whirls compared at each speed.
const WHIRLS: usize = 8;

fn fixture(name: &str) -> std::path::PathBuf {
    common::root().join("tests/fixtures/ross").join(name)
}

fn json(name: &str) -> Value {
    serde_json::from_str(&std::fs::read_to_string(fixture(name)).unwrap()).unwrap()
}

fn numbers(v: &Value) -> Vec<f64> {
    v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()
}

fn problem() -> Problem {
    Problem::from_path(fixture("aniso_tables.problem.toml"), &[]).unwrap()
}

#[test]
fn lowest_whirls_and_their_directions_match_ross_run_modal() {
    let p = problem();
    assert!(p.model.real_coordinates());
    let modal = json("aniso_tables.modal.json");
    let (mut worst, mut worst_coefficient) = (0.0f64, 0.0f64);
    for s in modal["speeds"].as_array().unwrap() {
        let speed = s["speed"].as_f64().unwrap();
        // The coefficients rotorshunt interpolates are ROSS's (its spline through the
        // table, between table points), to its smoothing.
        for b in &p.model.bearings {
            let ross = &s["coefficients"][b.node.to_string()];
            for (i, name) in rotorshunt::model::COEFFICIENT_NAMES.iter().enumerate() {
                let want = ross[*name].as_f64().unwrap();
                let got = b.coefficient_at(i, speed);
                let kind = if i < 4 { 0..4 } else { 4..8 };
                let scale = kind.flat_map(|j| b.coefficients[j].iter().map(|x| x.abs())).fold(0.0, f64::max);
                let d = (got - want).abs() / scale;
                worst_coefficient = worst_coefficient.max(d);
                assert!(d <= COEFFICIENT_RTOL, "{name} at node {} {speed}: {got} vs {want}", b.node);
            }
        }
        let r = whirl_modes(&p.model, &p.settings, speed).unwrap();
        let wd = numbers(&s["wd"]);
        let whirls: Vec<&str> = s["whirl"].as_array().unwrap().iter().map(|w| w.as_str().unwrap()).collect();
        for k in 0..WHIRLS {
            let m = &r.modes[k];
            let d = common::rel(m.frequency, wd[k]);
            worst = worst.max(d);
            assert!(d < MODAL_RTOL, "speed {speed}, whirl {k}: {} vs ROSS {}", m.frequency, wd[k]);
            let ours = match m.whirl {
                Whirl::Forward => "Forward",
                Whirl::Backward => "Backward",
                Whirl::Mixed => "Mixed",
            };
            assert_eq!(ours, whirls[k], "speed {speed}, whirl {k} at {} rad/s", m.frequency);
        }
    }
    eprintln!("worst whirl frequency gap to ROSS: {worst:.2e}; worst coefficient gap {worst_coefficient:.2e}");
}

#[test]
fn unbalance_orbits_match_ross_run_unbalance_response() {
    let p = problem();
    let rotor = Rotor::new(&p.model).unwrap();
    let u = json("aniso_tables.unbalance.json");
    let speeds = numbers(&u["speeds"]);
    let nodes: Vec<usize> = [0, 2, 4].to_vec();
    let probes: Vec<_> = nodes.iter().map(|&n| node_probe(&rotor.system.dofs, n).unwrap()).collect();
    let r = unbalance_response(&rotor, &speeds, &probes, &rotorshunt::progress::Silent).unwrap();
    let mut worst = 0.0f64;
    for (k, n) in nodes.iter().enumerate() {
        let ross = &u["probes"][n.to_string()];
        let o = r.probes[k].orbit.as_ref().unwrap();
        for (ours, theirs) in
            [(&o.x_amplitude, numbers(&ross["x_amplitude"])), (&o.y_amplitude, numbers(&ross["y_amplitude"]))]
        {
            let top = theirs.iter().copied().fold(0.0, f64::max);
            for i in 0..speeds.len() {
                let d = (ours[i] - theirs[i]).abs() / top;
                worst = worst.max(d);
                assert!(d < UNBALANCE_RTOL, "node {n} at {}: {} vs ROSS {}", speeds[i], ours[i], theirs[i]);
            }
        }
    }
    eprintln!("worst unbalance amplitude gap to ROSS: {worst:.2e}");
}
