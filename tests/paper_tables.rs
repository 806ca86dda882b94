//! Reference: the whirl frequencies of the paper's Tables 2 and 3 (rad/s, printed to
//! 0.1 rad/s). The issue asks for 0.1 %; an independent implementation reached
//! 0.03 %, so 0.1 % leaves room only for the paper's own rounding and modelling choices.

use crate::common;
use common::{load, rel};
use rotorshunt::analysis::modes::{whirl_modes, ModeKind};

/// The acceptance tolerance of the issue: 0.1 %.
const TABLE_TOLERANCE: f64 = 1e-3;

fn check(table: &[(&str, f64)], name: &str, overrides: &[&str], speed: f64) {
    let p = load(name, overrides);
    let r = whirl_modes(&p.model, &p.settings, speed).unwrap();
    for (tag, expected) in table {
        let m = r.modes.iter().find(|m| m.tag() == *tag).unwrap_or_else(|| panic!("no mode {tag} at {speed}"));
        let e = rel(m.frequency, *expected);
        assert!(
            e < TABLE_TOLERANCE,
            "{name} Ω={speed} {tag}: {} vs paper {expected} ({:.3} %)",
            m.frequency,
            100.0 * e
        );
    }
}

#[test]
fn table2_open_circuit_at_rest() {
    // ω_n at Ω = 0: forward and backward coincide.
    let t = [
        ("f1", 350.5),
        ("f2", 1817.1),
        ("f3", 3723.4),
        ("f4", 6277.1),
        ("b1", 350.5),
        ("b2", 1817.1),
        ("b3", 3723.4),
        ("b4", 6277.1),
    ];
    check(&t, "paper-open.toml", &[], 0.0);
}

#[test]
fn table2_open_circuit_at_2000() {
    let t = [
        ("f1", 399.0),
        ("f2", 1903.5),
        ("f3", 4899.6),
        ("f4", 6854.3),
        ("b1", 300.2),
        ("b2", 1653.1),
        ("b3", 2808.5),
        ("b4", 6092.3),
    ];
    check(&t, "paper-open.toml", &[], 2000.0);
}

#[test]
fn table3_closed_circuit_at_2000() {
    let t = [
        ("f1", 398.5),
        ("b1", 300.1),
        ("fr1", 879.1),
        ("br1", 877.9),
        ("fr2", 880.9),
        ("br2", 879.8),
        ("f2", 1903.8),
        ("b2", 1654.5),
        ("fs1", 2605.9),
        ("bs1", 2601.1),
        ("fs2", 2607.4),
        ("bs2", 2607.3),
        ("f3", 4901.8),
        ("b3", 2815.3),
        ("f4", 6856.4),
        ("b4", 6094.7),
    ];
    check(&t, "paper-closed.toml", &[], 2000.0);
}

#[test]
fn closed_circuit_labels_electrical_modes() {
    let p = load("paper-closed.toml", &[]);
    let r = whirl_modes(&p.model, &p.settings, 2000.0).unwrap();
    let electrical: Vec<String> = r.modes.iter().filter(|m| m.kind == ModeKind::Electrical).map(|m| m.tag()).collect();
    for tag in ["fr1", "br1", "fr2", "br2", "fs1", "bs1", "fs2", "bs2"] {
        assert!(electrical.contains(&tag.to_string()), "{tag} missing from {electrical:?}");
    }
}

#[test]
fn the_modes_command_prints_the_tables_as_json() {
    // The same values through the CLI path: `rotorshunt modes FILE --count 8 --json`.
    let text = common::run_ok(
        common::bin()
            .args(["modes", &common::problem_path("paper-closed.toml")])
            .args(["--speed", "2000", "--count", "8", "--json"]),
    );
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(v["speed"], 2000.0);
    assert!(rel(v["critical_load"].as_f64().unwrap(), 1.650e5) < 1e-3);
    let modes = v["modes"].as_array().unwrap();
    assert_eq!(modes.len(), 16);
    let f: Vec<(f64, &str)> =
        modes.iter().map(|m| (m["frequency"].as_f64().unwrap(), m["whirl"].as_str().unwrap())).collect();
    assert!(f.windows(2).all(|w| w[0].0 <= w[1].0), "sorted by frequency");
    assert!(rel(f[0].0, 300.1) < TABLE_TOLERANCE && f[0].1 == "backward");
    assert!(rel(f[15].0, 6856.4) < TABLE_TOLERANCE && f[15].1 == "forward");
    assert!(modes.iter().all(|m| m["damping_ratio"].is_number()));
}
