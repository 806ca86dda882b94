//! Region sensitivities by central differences: two step sizes agree to 1e-3, and the
//! electrical region f1+r1 moves with the branch tuning frequency exactly as the sum of
//! the whirl frequencies ω_f1 + ω_r does (an eigenvalue-only computation).

use crate::common;
use common::load;
use rotorshunt::analysis::floquet::FloquetSystem;
use rotorshunt::analysis::modes::whirl_modes_of;
use rotorshunt::analysis::regions::sensitivity::{region_quantities, sensitivity, Quantities};
use rotorshunt::analysis::regions::{seeds, RegionSettings};
use rotorshunt::analysis::{Interval, Rotor};

const AGREEMENT: f64 = 1e-3;

fn prepared(name: &str, key: &str, value: f64) -> (FloquetSystem, rotorshunt::analysis::modes::ModesResult) {
    let p = load(name, &[&format!("{key}={value}")]);
    let rotor = Rotor::new(&p.model).unwrap();
    let fs = FloquetSystem::new(&rotor, &p.settings, p.model.speed).unwrap();
    let full = whirl_modes_of(&rotor, &p.settings, p.model.speed).unwrap();
    (fs, full)
}

fn quantities(name: &str, key: &str, label: &str, value: f64, level: f64) -> Option<Quantities> {
    let (fs, full) = prepared(name, key, value);
    region_quantities(&fs, &full, &RegionSettings::precise(), label, 1, 1.0, level)
}

#[test]
fn electrical_region_start_follows_the_tuning_frequency() {
    let (name, key) = ("fig11-closed-2000.toml", "circuit.branches[0].tuning_frequency");
    // Level 0.001, below the onset: f1+r1 merges with f1+r2 (1.8 rad/s away) as soon as it
    // widens, and the edges of the union are not smooth in the tuning; start and onset are.
    let s = sensitivity(key, 900.0, 0.01, |v| quantities(name, key, "f1+r1", v, 0.001)).unwrap();
    eprintln!("{s:?}");
    assert!(s.disagreement < AGREEMENT, "steps disagree: {}", s.disagreement);
    // Independent path: the predicted start ω_f1 + ω_r1 from the eigenvalues alone.
    let seed = |v: f64| {
        let (fs, full) = prepared(name, key, v);
        seeds(&fs, Some(&full), Interval::new(1.0, 1e5), 1)
            .unwrap()
            .into_iter()
            .find(|x| x.label == "f1+r1")
            .unwrap()
            .phi
    };
    let d_seed = (seed(900.0 + s.step) - seed(900.0 - s.step)) / (2.0 * s.step);
    assert!(d_seed > 0.5, "ω_r follows the tuning: {d_seed}");
    assert!(
        (s.derivatives.start / d_seed - 1.0).abs() < AGREEMENT,
        "dφ_s/dω_t = {} vs d(ω_f1+ω_r1)/dω_t = {d_seed}",
        s.derivatives.start
    );
    // A mechanical region hardly moves with the electrical tuning.
    let m = sensitivity(key, 900.0, 0.01, |v| quantities(name, key, "f1+b1", v, 0.3)).unwrap();
    assert!(m.derivatives.start.abs() < 0.05 * s.derivatives.start, "f1+b1 moves by {}", m.derivatives.start);
}

#[test]
fn damping_sensitivity_is_consistent_between_steps() {
    // dβ_min/dη of the n1+n2 region at η = 200 N·s/m (Fig. 8b): positive (damping lifts the
    // onset) and the same with h and h/2.
    let (name, key) = ("fig8-eta200.toml", "ring.eta");
    let s = sensitivity(key, 200.0, 0.01, |v| quantities(name, key, "n1+n2", v, 0.3)).unwrap();
    eprintln!("{s:?}");
    assert!(s.derivatives.onset > 0.0);
    assert!(s.disagreement < AGREEMENT, "steps disagree: {}", s.disagreement);
}
