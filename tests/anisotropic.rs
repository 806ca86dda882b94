//! Issue 28 (points 2–3): supports with full coefficient matrices and the general path in
//! real coordinates. The anisotropic Jeffcott rotor against its closed form, continuity
//! of the real coordinates with the complex ones on every problem of problems/, and the
//! coefficient checks reported all at once.

mod common;
use rotorshunt::analysis::modes::{whirl_modes, ModesResult, Whirl};
use rotorshunt::problem::{Problem, ProblemErrorKind};

/// A Jeffcott rotor: a 10 kg disk without inertia at the middle of a 0.4 m shaft of
/// diameter 0.05 m whose density is 1e-3 kg/m³ (7.9e-7 kg: 8e-8 of the disk), on two
/// identical bearings kxx = `kx`, kyy = `ky` (N/m) at its ends, no damping unless `c`.
fn jeffcott(kx: f64, ky: f64, c: f64, speed: f64) -> String {
    format!(
        r#"version = 1
title = "anisotropic Jeffcott rotor"
speed = {speed:?}
[[sections]]
length = 0.4
outer_diameter = 0.05
youngs_modulus = 2.0e11
density = 1.0e-3
elements = 4
[[disks]]
node = 2
mass = 10.0
polar_inertia = 0.0
diametral_inertia = 0.0
eccentricity = 1.0e-4
[[bearings]]
node = 0
kxx = {kx:?}
kyy = {ky:?}
cxx = {c:?}
[[bearings]]
node = 4
kxx = {kx:?}
kyy = {ky:?}
cxx = {c:?}
[load]
alpha = 0.0
"#
    )
}

/// The Jeffcott rotor's stiffness in one plane: the shaft's mid-span stiffness 48EI/L³
/// (cubic beam elements reproduce a nodal point load's static deflection exactly) in
/// series with its two bearings (N/m).
fn jeffcott_stiffness(k: f64) -> f64 {
    let i = std::f64::consts::PI * 0.05f64.powi(4) / 64.0;
    let shaft = 48.0 * 2.0e11 * i / 0.4f64.powi(3);
    1.0 / (1.0 / shaft + 1.0 / (2.0 * k))
}

/// The shaft's mass is 8e-8 of the disk's: the whirls move by about half that from the
/// massless closed form (and the shaft's rotary inertia by less).
const JEFFCOTT_TOLERANCE: f64 = 1e-6;

#[test]
fn anisotropic_jeffcott_whirls_at_the_two_closed_form_critical_speeds() {
    let (kx, ky) = (1.0e6, 2.0e6);
    let p = Problem::from_text(&jeffcott(kx, ky, 0.0, 0.0), "jeffcott.toml", &[]).unwrap();
    assert!(p.model.real_coordinates());
    let r = whirl_modes(&p.model, &p.settings, 0.0).unwrap();
    let wx = (jeffcott_stiffness(kx) / 10.0).sqrt();
    let wy = (jeffcott_stiffness(ky) / 10.0).sqrt();
    let lowest: Vec<f64> = r.modes.iter().take(2).map(|m| m.frequency).collect();
    assert!(common::rel(lowest[0], wx) < JEFFCOTT_TOLERANCE, "{} vs {wx}", lowest[0]);
    assert!(common::rel(lowest[1], wy) < JEFFCOTT_TOLERANCE, "{} vs {wy}", lowest[1]);
    // Each is a straight line in its own plane: neither forward nor backward, undamped.
    for m in &r.modes[..2] {
        assert_eq!(m.whirl, Whirl::Mixed, "{m:?}");
        assert_eq!(m.ellipticity, Some(0.0));
        assert_eq!(m.damping_ratio, 0.0);
    }
    // The same rotor isotropic (kx = ky) runs in complex coordinates: one whirl pair.
    let iso = Problem::from_text(&jeffcott(kx, kx, 0.0, 0.0), "jeffcott.toml", &[]).unwrap();
    assert!(!iso.model.real_coordinates());
    let r = whirl_modes(&iso.model, &iso.settings, 0.0).unwrap();
    assert!(common::rel(r.modes[0].frequency, wx) < JEFFCOTT_TOLERANCE);
}

/// The lowest whirls compared between the two paths: per direction.
const CONTINUITY_MODES: usize = 8;
/// Relative agreement of the whirl frequencies of the complex and the real coordinates
/// (issue 28's acceptance): both solve the same physics in the same first-order form,
/// the real one of twice the size; measured ≤ 5.1e-11 (fig13-r50, b1) on problems/.
const CONTINUITY_TOLERANCE: f64 = 1e-9;

fn compare(name: &str, complex: &ModesResult, real: &ModesResult) {
    for whirl in [Whirl::Forward, Whirl::Backward] {
        let c: Vec<_> = complex.modes.iter().filter(|m| m.whirl == whirl).take(CONTINUITY_MODES).collect();
        let r: Vec<_> = real.modes.iter().filter(|m| m.whirl == whirl).take(CONTINUITY_MODES).collect();
        assert_eq!(c.len(), r.len(), "{name}: {whirl:?} whirls");
        for (a, b) in c.iter().zip(&r) {
            assert_eq!(a.tag(), b.tag(), "{name}");
            let d = common::rel(b.frequency, a.frequency);
            assert!(d < CONTINUITY_TOLERANCE, "{name} {}: {} vs {} ({d:e})", a.tag(), b.frequency, a.frequency);
            assert!(
                (a.damping_ratio - b.damping_ratio).abs() < CONTINUITY_TOLERANCE,
                "{name} {}: zeta {} vs {}",
                a.tag(),
                a.damping_ratio,
                b.damping_ratio
            );
            assert_eq!(a.kind, b.kind, "{name} {}", a.tag());
        }
    }
    assert_eq!(
        real.modes.iter().filter(|m| m.whirl == Whirl::Mixed).count(),
        0,
        "{name}: isotropic whirls are circles"
    );
}

#[test]
fn real_coordinates_reproduce_the_complex_whirls_on_every_problem() {
    let mut names: Vec<String> = std::fs::read_dir(common::root().join("problems"))
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".toml"))
        .collect();
    names.sort();
    assert!(names.len() >= 20, "{names:?}");
    for name in &names {
        let complex = common::load(name, &[]);
        assert!(!complex.model.real_coordinates(), "{name} is isotropic");
        let real = common::load(name, &["analysis.coordinates=\"real\""]);
        assert!(real.model.real_coordinates());
        let speed = complex.model.speed;
        let a = whirl_modes(&complex.model, &complex.settings, speed).unwrap();
        let b = whirl_modes(&real.model, &real.settings, speed).unwrap();
        assert_eq!(a.critical_load, b.critical_load, "{name}: P_cr");
        compare(name, &a, &b);
    }
}

#[test]
fn every_coefficient_error_of_a_file_is_reported_at_once() {
    let path = common::root().join("tests/fixtures/bad/support_all_at_once.toml");
    let e = Problem::from_path(&path, &[]).expect_err("four defects");
    let all = e.all();
    let found: Vec<(String, Option<usize>, &'static str)> = all
        .iter()
        .map(|e| {
            let kind = match e.kind {
                ProblemErrorKind::TableSpeedsNotIncreasing { .. } => "speeds",
                ProblemErrorKind::TableLength { values: 5, speeds: 6 } => "length",
                ProblemErrorKind::NegativeStiffness { value, speed: None } if value == -2.0e6 => "negative",
                ProblemErrorKind::DampingNotSemiDefinite { .. } => "damping",
                _ => "other",
            };
            (e.key.clone(), e.line(), kind)
        })
        .collect();
    let expected = [
        ("bearings[0].speeds", 45, "speeds"),
        ("bearings[0].cyy", 51, "length"),
        ("seals[0].kxx", 58, "negative"),
        ("seals[0].cxy", 62, "damping"),
    ];
    assert_eq!(found.len(), expected.len(), "{found:?}");
    for ((key, line, kind), (k, l, d)) in found.iter().zip(expected) {
        assert_eq!((key.as_str(), *line, *kind), (k, Some(l), d));
    }
    // The command line prints each on its own `error:` line, and exits 2.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_rotorshunt"))
        .args(["check", path.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    let lines: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error: ")).collect();
    assert_eq!(lines.len(), 4, "{stderr}");
    for ((k, l, _), line) in expected.iter().zip(&lines) {
        assert!(line.contains(&format!("line {l}: key `{k}`")), "{line}");
    }
}

#[test]
fn isotropic_keys_and_their_matrix_form_are_one_bearing() {
    // `stiffness`/`damping` and kxx = kyy, cxx = cyy with no cross-coupling: the same
    // model, on the complex path, to the bit.
    let a = jeffcott(1.5e6, 1.5e6, 30.0, 100.0);
    let b = a.replacen("kxx = 1500000.0\nkyy = 1500000.0\ncxx = 30.0", "stiffness = 1500000.0\ndamping = 30.0", 1);
    assert_ne!(a, b);
    let (pa, pb) = (Problem::from_text(&a, "a", &[]).unwrap(), Problem::from_text(&b, "b", &[]).unwrap());
    assert_eq!(pa.model, pb.model);
    // Giving both forms is refused, naming both keys.
    let both = a.replacen("kxx = 1500000.0", "stiffness = 1.0\nkxx = 1500000.0", 1);
    let e = Problem::from_text(&both, "both", &[]).unwrap_err();
    assert!(matches!(e.kind, ProblemErrorKind::BothGiven(..)) && e.key == "bearings[0].kxx", "{e}");
}
