//! Design candidates set their values on the model ([`machine_at`]); the tuned file is
//! written by the file layer ([`tuned_file`]). The two must agree bit for bit: the tuned
//! file, read back by the normal loader, gives the candidate's model, for every bundled
//! design and for the cases where the file's meaning matters (a tuning frequency held
//! while C_f changes, an inductance replacing a tuning frequency, the shorthand's one
//! circuit tuned with the left ring's C_p^T whichever ring is named).

use crate::common;

use common::load;
use rotorshunt::design::evaluate::machine_at;
use rotorshunt::design::DesignError;
use rotorshunt::model::{BranchError, Given, Model};
use rotorshunt::problem::tuned::{tuned_file, Setting};
use rotorshunt::problem::Problem;

/// Every branch's given form (the model's equality compares C_f, L and R only).
fn given(m: &Model) -> Vec<Vec<Given>> {
    m.rings.iter().map(|r| r.circuit.branches.iter().map(|b| b.given).collect()).collect()
}

/// The candidate at the scaled point `u` of every variable, and the tuned file read back.
fn both(base: &Problem, u: f64) -> (rotorshunt::design::Machine, Problem) {
    let spec = base.design.as_ref().expect("a [design] table");
    let values: Vec<f64> = spec.variables.iter().map(|v| v.from_unit(u)).collect();
    let candidate = machine_at(&base.machine(), spec, &values).unwrap_or_else(|e| panic!("{e}"));
    let settings: Vec<Setting> = spec
        .variables
        .iter()
        .zip(&values)
        .map(|(v, &value)| Setting { ring: v.ring, branch: v.branch, parameter: v.parameter, value })
        .collect();
    let text = tuned_file(&base.data, &settings, &base.rpm).unwrap_or_else(|e| panic!("{e}"));
    let reread = Problem::from_text(&text, "tuned.toml", &[]).unwrap_or_else(|e| panic!("{e}\n{text}"));
    (candidate, reread)
}

fn assert_agree(name: &str, overrides: &[&str]) {
    let base = load(name, overrides);
    for u in [0.0, 0.3, 0.7, 1.0] {
        let (c, r) = both(&base, u);
        assert!(c.model == r.model, "{name} {overrides:?} at u = {u}: the candidate's model is not the tuned file's");
        assert_eq!(given(&c.model), given(&r.model), "{name} {overrides:?} at u = {u}");
        assert!(c.model != base.model, "{name} {overrides:?} at u = {u}: nothing was set");
    }
}

#[test]
fn every_bundled_design_candidate_is_its_tuned_file() {
    for name in [
        "design-widest-band.toml",
        "design-clear-bands.toml",
        "design-min-peak-at-speed.toml",
        "design-min-peak-stepped.toml",
    ] {
        assert_agree(name, &[]);
    }
}

#[test]
fn a_held_tuning_frequency_follows_c_f_and_an_inductance_replaces_it() {
    // Variable 1 becomes branch 1's C_f: L is recomputed from the file's ω = 900 rad/s.
    let c_f = ["design.variables[1].parameter=\"c_f\"", "design.variables[1].min=1e-6", "design.variables[1].max=1e-5"];
    assert_agree("design-widest-band.toml", &c_f);
    let base = load("design-widest-band.toml", &c_f);
    let spec = base.design.as_ref().expect("[design]");
    let c = machine_at(&base.machine(), spec, &[900.0, 2e-6]).unwrap_or_else(|e| panic!("{e}"));
    let b = &c.model.rings[1].circuit.branches[0];
    assert_eq!(b.given, Given::TuningFrequency(900.0));
    assert!((b.tuning_frequency(c.model.rings[0].ring.cp_t) / 900.0 - 1.0).abs() < 1e-12);
    // Variable 0 an inductance on a branch the file tunes: it replaces the tuning.
    let l =
        ["design.variables[0].parameter=\"inductance\"", "design.variables[0].min=0.5", "design.variables[0].max=2"];
    assert_agree("design-widest-band.toml", &l);
    let base = load("design-widest-band.toml", &l);
    let c = machine_at(&base.machine(), base.design.as_ref().expect("[design]"), &[1.25, 3.0])
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(c.model.rings.iter().all(|r| r.circuit.branches[0].given == Given::Inductance));
    assert!(c.model.rings.iter().all(|r| r.circuit.branches[0].inductance == 1.25));
}

#[test]
fn the_shorthand_circuit_is_tuned_with_the_left_ring_whichever_ring_is_named() {
    let right = ["ring.right.cp_t=2.5e-6", "design.variables[0].ring=\"right\""];
    assert_agree("design-widest-band.toml", &right);
    let base = load("design-widest-band.toml", &right);
    let c = machine_at(&base.machine(), base.design.as_ref().expect("[design]"), &[1000.0, 5.0])
        .unwrap_or_else(|e| panic!("{e}"));
    let cp_t_left = c.model.rings[0].ring.cp_t;
    assert!(c.model.rings[1].ring.cp_t != cp_t_left);
    for r in &c.model.rings {
        assert_eq!(r.circuit.branches[0].given, Given::TuningFrequency(1000.0), "{}", r.name);
        assert!((r.circuit.branches[0].tuning_frequency(cp_t_left) / 1000.0 - 1.0).abs() < 1e-12, "{}", r.name);
    }
    // The reference values are the file's: ω = 900 rad/s read with the left ring's C_p^T.
    let before = rotorshunt::design::evaluate::values_of(&base.machine(), base.design.as_ref().expect("[design]"));
    assert!((before[0] / 900.0 - 1.0).abs() < 1e-12, "{before:?}");
}

#[test]
fn a_value_no_branch_could_take_is_a_typed_error() {
    let base = load("design-widest-band.toml", &[]);
    let spec = base.design.as_ref().expect("[design]");
    let err = |values: &[f64]| match machine_at(&base.machine(), spec, values) {
        Err(DesignError::Candidate { variable, error, .. }) => (variable, error),
        other => panic!("{values:?}: {:?}", other.map(|_| ())),
    };
    assert!(matches!(err(&[f64::NAN, 0.0]), (0, BranchError::NotFinite { .. })));
    assert!(matches!(err(&[0.0, 0.0]), (0, BranchError::NotPositive { .. })));
    assert!(matches!(err(&[900.0, -1.0]), (1, BranchError::Negative { .. })));
    // R = 1e308 Ω is a valid number but γR overflows (γ ≈ 33 on the paper's ring).
    let e = err(&[900.0, 1e308]);
    assert!(matches!(e, (1, BranchError::Overflow { .. })), "{e:?}");
    // ω = 1e-160 rad/s gives L = inf by Eq. (4).
    assert!(matches!(err(&[1e-160, 0.0]), (0, BranchError::Overflow { .. })));
}
