//! Invariants of the assembled model and the eigen-solutions, and closed forms.

use crate::common;
use common::{load, rel};
use faer::{c64, Mat};
use rotorshunt::analysis::buckling::buckling_load;
use rotorshunt::analysis::modes::{whirl_modes, whirl_modes_of, Whirl};
use rotorshunt::analysis::Rotor;
use rotorshunt::assembly::SystemMatrices;
use rotorshunt::linalg::definite_eigen;

fn assert_symmetric(a: &Mat<f64>, what: &str) {
    for i in 0..a.nrows() {
        for j in 0..i {
            assert_eq!(a[(i, j)], a[(j, i)], "{what} not symmetric at ({i},{j})");
        }
    }
}

#[test]
fn matrices_are_symmetric_in_every_circuit_state() {
    for state in ["open", "short", "closed"] {
        let p = load(
            "paper-closed.toml",
            &[&format!("circuit.state={state}"), "ring.eta=200", "circuit.branches[0].resistance=10"],
        );
        let s = SystemMatrices::assemble(&p.model);
        for (m, w) in [(&s.m, "M"), (&s.c, "C"), (&s.k, "K"), (&s.s, "S"), (&s.g, "G")] {
            assert_symmetric(m, &format!("{w} ({state})"));
        }
        let expected = 130 + 2 + if state == "closed" { 4 } else { 0 };
        assert_eq!(s.size(), expected, "DOFs ({state})");
    }
}

#[test]
fn rigid_translation_carries_the_total_mass() {
    // tᵀMt for t = unit deflection at every node equals ρAL + Σ m_disk (mass conservation).
    let p = load("paper-closed.toml", &[]);
    let s = SystemMatrices::assemble(&p.model);
    let n = s.size();
    let t: Vec<f64> = (0..n).map(|i| if i < s.dofs.shaft_dofs() && i % 2 == 0 { 1.0 } else { 0.0 }).collect();
    let mut mass = 0.0;
    for i in 0..n {
        for j in 0..n {
            mass += t[i] * s.m[(i, j)] * t[j];
        }
    }
    let parts = p.model.shaft.sections[0].density * p.model.shaft.sections[0].area() * p.model.shaft.length() + 4.85;
    assert!(rel(mass, parts) < 1e-12, "{mass} vs {parts}");
    assert!(rel(p.model.rotor_mass(), parts) < 1e-12);
    // A rigid translation also has no geometric or bending energy.
    let mut e = 0.0;
    for i in 0..s.dofs.shaft_dofs() {
        for j in 0..s.dofs.shaft_dofs() {
            e += t[i] * s.s[(i, j)] * t[j];
        }
    }
    assert!(e.abs() < 1e-9, "S rigid energy {e}");
}

#[test]
fn qep_residuals_are_small() {
    // Backward-stable eigensolvers give residuals of a few ε·n relative to the terms for
    // the eigenvalues near the shift (the whirls of interest); shift-invert resolves the
    // far ones (≥ 1e4 rad/s) with relative accuracy ~ ε·|λ/λ_min|, hence the looser bound.
    const RESIDUAL_LIMIT: f64 = 1e-9;
    const FAR_RESIDUAL_LIMIT: f64 = 1e-5;
    for (name, speed) in [("paper-open.toml", 0.0), ("paper-open.toml", 2000.0), ("paper-closed.toml", 2000.0)] {
        let p = load(name, &["ring.eta=200", "circuit.branches[1].resistance=50"]);
        let r = whirl_modes(&p.model, &p.settings, speed).unwrap();
        assert!(r.modes.len() > 100);
        for m in &r.modes {
            let limit = if m.frequency < 1e4 { RESIDUAL_LIMIT } else { FAR_RESIDUAL_LIMIT };
            assert!(m.residual < limit, "{name} {}: residual {}", m.tag(), m.residual);
        }
    }
}

#[test]
fn forward_and_backward_coincide_at_rest() {
    for name in ["paper-open.toml", "paper-closed.toml"] {
        let p = load(name, &["ring.eta=200"]);
        let r = whirl_modes(&p.model, &p.settings, 0.0).unwrap();
        let f: Vec<f64> = r.forward().map(|m| m.frequency).collect();
        let b: Vec<f64> = r.backward().map(|m| m.frequency).collect();
        assert_eq!(f.len(), b.len());
        for (x, y) in f.iter().zip(&b).take(12) {
            assert!(rel(*x, *y) < 1e-9, "{name}: {x} vs {y}");
        }
    }
}

#[test]
fn undamped_rest_frequencies_agree_with_a_symmetric_eigensolver() {
    // Second computation path: at Ω = 0 without damping the QEP reduces to the
    // symmetric-definite (K − αP_cr·S) x = ω² M x, solved by Cholesky + symmetric EVD.
    let p = load("paper-closed.toml", &[]);
    let rotor = Rotor::new(&p.model).unwrap();
    let k = rotor.system.stiffness_at(rotor.static_load());
    let eig = definite_eigen(k.as_ref(), rotor.system.m.as_ref()).unwrap();
    let sym: Vec<f64> = eig.values.iter().take(12).map(|t| (1.0 / t).sqrt()).collect();
    let qep = whirl_modes_of(&rotor, &p.settings, 0.0).unwrap();
    let f: Vec<f64> = qep.forward().map(|m| m.frequency).take(12).collect();
    // 1e-9 below 1e4 rad/s; far from the shift, shift-invert loses digits (see residuals).
    for (a, b) in f.iter().zip(&sym) {
        let tol = if *b < 1e4 { 1e-9 } else { 1e-7 };
        assert!(rel(*a, *b) < tol, "{a} vs {b}");
    }
}

#[test]
fn buckling_load_closed_forms() {
    // Stiff supports: the Euler mode sin(πx/L) leaves the end springs unloaded
    // (EI·w‴ + P·w′ = 0 at the ends when P = π²EI/L²), so P_cr = π²EI/L² exactly for
    // any support stiffer than the sway mode; FE converges at O(h⁴): < 1e-6 at 64 elements.
    for overrides in [vec![], vec!["ring.k_b=1e13", "ring.k_1=1e13", "ring.k_2=1e13"]] {
        let p = load("paper-open.toml", &overrides);
        let euler = p.model.shaft.euler_load();
        let pcr = buckling_load(&SystemMatrices::assemble(&p.model)).unwrap();
        assert!(rel(pcr, euler) < 1e-6, "{pcr} vs {euler}");
    }
    // Very soft bearings: the shaft tilts rigidly on its two end springs, w = x − L/2, with
    // P_cr = k_s·L/2 (k_s = k_eq in series with k_eq1 + k_eq2); the shaft's bending
    // flexibility lowers it by O(k_s·L³/EI) ≈ 4e-9 here, below the solver's accuracy for a
    // pencil this ill-conditioned (k_s = 100 N/m against EI/l³ ≈ 6e9 N/m): 1e-5.
    let p = load("paper-open.toml", &["ring.k_b=100"]);
    let r = &p.model.rings[0].ring;
    let ground = r.k_eq1() + r.k_eq2();
    let k_s = r.k_eq() * ground / (r.k_eq() + ground);
    let sway = k_s * p.model.shaft.length() / 2.0;
    let pcr = buckling_load(&SystemMatrices::assemble(&p.model)).unwrap();
    assert!(rel(pcr, sway) < 1e-5, "{pcr} vs {sway}");
    // The paper's problem: ≈ 1.650e5 N (docs/model.md).
    let paper = Rotor::new(&load("paper-open.toml", &[]).model).unwrap();
    assert!(rel(paper.critical_load, 1.650e5) < 1e-3, "{}", paper.critical_load);
}

#[test]
fn gyroscopic_effect_splits_whirls_the_right_way() {
    // Forward whirls stiffen and backward whirls soften with speed (Figs. 6–7).
    let p = load("paper-open.toml", &[]);
    let rotor = Rotor::new(&p.model).unwrap();
    let rest = whirl_modes_of(&rotor, &p.settings, 0.0).unwrap();
    let spin = whirl_modes_of(&rotor, &p.settings, 2000.0).unwrap();
    for k in 0..4 {
        let f0 = rest.forward().nth(k).unwrap().frequency;
        assert!(spin.forward().nth(k).unwrap().frequency > f0);
        assert!(spin.backward().nth(k).unwrap().frequency < f0);
    }
}

#[test]
fn damping_gives_positive_damping_ratios() {
    let p = load(
        "paper-closed.toml",
        &["ring.eta=4000", "circuit.branches[0].resistance=50", "circuit.branches[1].resistance=50"],
    );
    let r = whirl_modes(&p.model, &p.settings, 2000.0).unwrap();
    for m in r.lowest(8) {
        assert!(m.damping_ratio > 0.0, "{}: ζ = {}", m.tag(), m.damping_ratio);
    }
    // Resistance damps the electrical modes.
    let fr1 = r.modes.iter().find(|m| m.tag() == "fr1").unwrap();
    assert!(fr1.damping_ratio > 1e-3, "{}", fr1.damping_ratio);
    let _ = (Whirl::Forward, c64::new(0.0, 0.0));
}
