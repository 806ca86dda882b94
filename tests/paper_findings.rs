//! The paper's findings (section 5) asserted on charts at the resolution needed to see
//! them: where instability regions start (sums of whirl frequencies of the reduced model)
//! and how damping and resistance lift their onset.

use crate::common;
use common::load;
use rotorshunt::analysis::floquet::FloquetSystem;
use rotorshunt::analysis::Rotor;

fn system(name: &str, overrides: &[&str]) -> FloquetSystem {
    let p = load(name, overrides);
    let rotor = Rotor::new(&p.model).unwrap();
    FloquetSystem::new(&rotor, &p.settings, p.model.speed).unwrap()
}

/// Relative half-width of the φ window scanned around a predicted region start, and the
/// number of points: regions open at β = 0 from a point, with a width ∝ β, so a ±1.5 %
/// window at 601 points (step 0.005 %) resolves the tips seen at β ≥ 0.05.
const WINDOW: f64 = 0.015;
const SCAN_POINTS: usize = 601;

/// Unstable points in the window around `centre` at load β, and the φ of the most unstable.
fn scan(fs: &FloquetSystem, centre: f64, beta: f64) -> (usize, f64) {
    let phis: Vec<f64> = (0..SCAN_POINTS)
        .map(|i| centre * (1.0 - WINDOW + 2.0 * WINDOW * i as f64 / (SCAN_POINTS - 1) as f64))
        .collect();
    let mut count = 0;
    let (mut best, mut at) = (f64::MIN, 0.0);
    for &phi in &phis {
        let p = fs.point_fast(&fs.table(phi, beta), beta);
        if !p.summary.stable {
            count += 1;
        }
        if p.summary.ln_max_multiplier > best {
            best = p.summary.ln_max_multiplier;
            at = phi;
        }
    }
    (count, at)
}

#[test]
fn at_rest_simple_and_sum_regions_but_no_difference_regions() {
    // Ω = 0, open, η = 0, M = 4 (Fig. 8a): regions start at 2ω_p and ω_p + ω_q.
    let fs = system("fig8-eta0.toml", &[]);
    let (w, _) = fs.whirls().unwrap();
    for (label, centre) in [("2ω1", 2.0 * w[0]), ("2ω2", 2.0 * w[1]), ("ω1+ω2", w[0] + w[1]), ("ω1+ω3", w[0] + w[2])]
    {
        let (n, at) = scan(&fs, centre, 0.1);
        assert!(n > 0, "no region near {label} = {centre:.1} rad/s at β = 0.1");
        assert!((at / centre - 1.0).abs() < 0.01, "{label}: most unstable at {at}, predicted {centre}");
    }
    for (label, centre) in [("ω2−ω1", w[1] - w[0]), ("ω3−ω1", w[2] - w[0]), ("ω3−ω2", w[2] - w[1])] {
        let (n, _) = scan(&fs, centre, 0.5);
        assert_eq!(n, 0, "difference-type region near {label} = {centre:.1} rad/s");
    }
}

#[test]
fn rotating_open_circuit_has_only_combination_regions() {
    // Ω = 2000, open (Fig. 9): no region at 2ω_f1 or 2ω_b1, one at ω_f1 + ω_b1. At β ≥ 0.3
    // the (very wide) ω_f1 + ω_b1 region itself spreads over 2ω_b1 and 2ω_f1, so the absence
    // of simple regions is checked at β = 0.1, where it is 20 rad/s wide.
    let fs = system("fig9-open-2000.toml", &[]);
    let (f, b) = fs.whirls().unwrap();
    for (label, centre) in [("2ωf1", 2.0 * f[0]), ("2ωb1", 2.0 * b[0]), ("2ωf2", 2.0 * f[1])] {
        let (n, _) = scan(&fs, centre, 0.1);
        assert_eq!(n, 0, "simple region near {label} = {centre:.1} rad/s while rotating");
    }
    for (label, centre) in [("ωf1+ωb1", f[0] + b[0]), ("ωf2+ωb2", f[1] + b[1])] {
        let (n, at) = scan(&fs, centre, 0.1);
        assert!(n > 0, "no combination region near {label} = {centre:.1}");
        assert!((at / centre - 1.0).abs() < 0.01, "{label}: most unstable at {at}, predicted {centre}");
    }
}

#[test]
fn closing_the_circuit_adds_electrical_combination_regions() {
    // Ω = 2000, closed, R = 0 (Fig. 11): new regions at ω_f1 + ω_r and ω_b1 + ω_r that the
    // open circuit does not have.
    let closed = system("fig11-closed-2000.toml", &[]);
    let open = system("fig11-closed-2000.toml", &["circuit.state=open"]);
    let (f, b) = closed.whirls().unwrap();
    // Reduced closed model, ascending: f1 ≈ 399, then the r modes ≈ 879–881.
    let r = f.iter().copied().find(|w| (850.0..910.0).contains(w)).expect("an r mode");
    for (label, centre) in [("ωf1+ωr", f[0] + r), ("ωb1+ωr", b[0] + r)] {
        let (n, _) = scan(&closed, centre, 0.2);
        assert!(n > 0, "closed: no region near {label} = {centre:.1}");
        let (n_open, _) = scan(&open, centre, 0.2);
        assert_eq!(n_open, 0, "open circuit already unstable near {label} = {centre:.1}");
    }
}

#[test]
fn damping_lifts_the_onset_of_combination_regions() {
    // Fig. 8: damping moves the start of the ω1 + ω2 region up from β = 0. Undamped it is
    // unstable near the start point already at β = 0.001; η = 200 keeps β = 0.005 stable,
    // η = 4000 keeps β = 0.02 stable; at β = 0.3 all three are unstable (the region exists).
    let (w, _) = system("fig8-eta0.toml", &[]).whirls().unwrap();
    let centre = w[0] + w[1];
    let cases =
        [("fig8-eta0.toml", 0.001, true), ("fig8-eta200.toml", 0.005, false), ("fig8-eta4000.toml", 0.02, false)];
    for (name, beta, unstable) in cases {
        let fs = system(name, &[]);
        assert_eq!(scan(&fs, centre, beta).0 > 0, unstable, "{name} at β = {beta} near ω1+ω2 = {centre:.1}");
        assert!(scan(&fs, centre, 0.3).0 > 0, "{name}: the region should exist at β = 0.3");
    }
}

#[test]
fn resistance_lifts_the_onset_of_electrical_regions() {
    // R = 50 Ω (Fig. 13b) acts like damping on the new regions ω_f1 + ω_r.
    let r0 = system("fig11-closed-2000.toml", &[]);
    let r50 = system("fig13-r50.toml", &[]);
    let (f, _) = r0.whirls().unwrap();
    let r = f.iter().copied().find(|w| (850.0..910.0).contains(w)).unwrap();
    let centre = f[0] + r;
    assert!(scan(&r0, centre, 0.02).0 > 0, "R = 0: region should reach β = 0.02");
    assert_eq!(scan(&r50, centre, 0.02).0, 0, "R = 50 Ω should keep β = 0.02 stable near ωf1+ωr");
}
