//! A shunt branch with L = 0 makes M singular (section 4, Eq. 18–21): the shift-invert
//! solver must give finite frequencies equal to those of a tiny L.

use crate::common;
use common::{load, rel};
use rotorshunt::analysis::modes::whirl_modes;

/// With L = 1e-9 H the branch's own mode sits near √(k/γL) ≈ 4e7 rad/s, so it shifts the
/// modes below 7000 rad/s by O((7e3/4e7)²) ≈ 3e-8 relative: 1e-6 is a safe bound.
const TINY_L_AGREEMENT: f64 = 1e-6;

#[test]
fn zero_inductance_equals_tiny_inductance() {
    let p = load("paper-closed.toml", &[]);
    let mut zero = p.model.clone();
    for r in &mut zero.rings {
        r.circuit.branches[0].inductance = 0.0;
    }
    let mut tiny = p.model.clone();
    for r in &mut tiny.rings {
        r.circuit.branches[0].inductance = 1e-9;
    }
    let z = whirl_modes(&zero, &p.settings, 2000.0).unwrap();
    let t = whirl_modes(&tiny, &p.settings, 2000.0).unwrap();
    // Branch 1's charges are massless: its r modes vanish, the s and rotor modes remain.
    assert!(z.modes.iter().all(|m| m.frequency.is_finite() && m.damping_ratio.is_finite()));
    assert!(!z.modes.iter().any(|m| m.label.starts_with('r')), "L = 0 leaves no r mode");
    let zl = z.lowest(6);
    let tl = t.lowest(6);
    for (a, b) in zl.iter().zip(&tl) {
        assert_eq!(a.tag(), b.tag());
        assert!(rel(a.frequency, b.frequency) < TINY_L_AGREEMENT, "{}: {} vs {}", a.tag(), a.frequency, b.frequency);
    }
    // The s modes remain, lowered from 2601–2607 to ≈ 2549 rad/s because the massless branch
    // 1 now acts as a capacitor C_f1 across the stacks.
    assert!(z.modes.iter().any(|m| m.tag() == "fs1" && (2400.0..2700.0).contains(&m.frequency)));
}

#[test]
fn inductance_zero_is_accepted_from_the_file() {
    // `inductance = 0` is valid input (a purely capacitive branch); the problem loads and
    // the modes command works.
    let text = std::fs::read_to_string(common::problem_path("paper-closed.toml")).unwrap().replacen(
        "tuning_frequency = 900.0",
        "inductance = 0.0",
        1,
    );
    let p = rotorshunt::problem::Problem::from_text(&text, "zero-l.toml", &[]).unwrap();
    assert_eq!(p.model.rings[0].circuit.branches[0].inductance, 0.0);
    let dir = common::scratch("zero-l");
    let file = dir.join("zero-l.toml");
    std::fs::write(&file, &text).unwrap();
    let out = common::run_ok(common::bin().args(["modes", file.to_str().unwrap(), "--count", "4", "--json"]));
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(!out.contains("NaN") && !out.contains("inf"));
}
