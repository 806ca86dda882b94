//! Issue 28, "Speed": the lowest whirls of the real coordinates by block shift-invert
//! Krylov ([`whirl_modes_nearest`]) against the dense solver they replace on large models
//! ([`whirl_modes_of`], the reference): the same whirls of the window, with the same
//! tags and directions, on the anisotropic rotors and on every problem of problems/
//! forced to the real path, at rest and at speed; and against the Jeffcott rotor's
//! closed form.

use crate::common;
use rotorshunt::analysis::modes::{
    lowest_whirls_of, whirl_modes_nearest, whirl_modes_nearest_by, whirl_modes_of, ModesResult, NearestSolver, Whirl,
    WHIRL_WINDOW,
};
use rotorshunt::analysis::Rotor;
use rotorshunt::problem::Problem;

/// Relative agreement |λ_fast − λ_dense|/|λ_dense| of the two solvers. Neither is exact:
/// on the 200-element rotor made isotropic, where the complex path is an independent
/// reference, the dense real solver's lowest whirls are 7e-10 from it (its Cholesky
/// forms carry the shortest elements' 12EI/l³ ≈ 2e13 N/m against modal stiffnesses of
/// ~1e7 N/m) and the Krylov ones 1e-10; the two differ by at most 1.4e-9 on the
/// anisotropic 200-element rotor. 1e-8 leaves a factor 7 for other speeds and models,
/// and is still 1e4 times below any physical difference between whirls.
const FAST_DENSE_AGREEMENT: f64 = 1e-8;

/// Whirls asked of each direction, as `modes`' default.
const COUNT: usize = 4;

fn modulus(e: [f64; 2]) -> f64 {
    e[0].hypot(e[1])
}

/// The whirls `lowest(count)` lists from each solver: the same tags, directions and
/// kinds, eigenvalues within [`FAST_DENSE_AGREEMENT`]; and the whole window too.
fn compare(name: &str, count: usize, fast: &ModesResult, dense: &ModesResult) {
    let (a, b) = (fast.lowest(count), dense.lowest(count));
    assert!(!b.is_empty(), "{name}: no whirl");
    assert_eq!(
        a.iter().map(|m| m.tag()).collect::<Vec<_>>(),
        b.iter().map(|m| m.tag()).collect::<Vec<_>>(),
        "{name}: the listed whirls"
    );
    for (x, y) in a.iter().zip(&b) {
        let d = (x.eigenvalue[0] - y.eigenvalue[0]).hypot(x.eigenvalue[1] - y.eigenvalue[1]) / modulus(y.eigenvalue);
        assert!(d < FAST_DENSE_AGREEMENT, "{name} {}: {:?} vs {:?} ({d:e})", x.tag(), x.eigenvalue, y.eigenvalue);
        assert_eq!((x.whirl, x.kind), (y.whirl, y.kind), "{name} {}", x.tag());
    }
    let (wa, wb) = (fast.window(count), dense.window(count));
    assert_eq!(wa.len(), wb.len(), "{name}: window");
    for (&i, &j) in wa.iter().zip(&wb) {
        let (x, y) = (&fast.modes[i], &dense.modes[j]);
        assert_eq!(x.tag(), y.tag(), "{name}: window");
        assert!(common::rel(modulus(x.eigenvalue), modulus(y.eigenvalue)) < FAST_DENSE_AGREEMENT, "{name} {}", x.tag());
    }
}

/// The Krylov solve with a space as large as the whole state allowed (the small models'
/// windows can be a good part of it): `None` would be a fallback, which must not happen
/// on these models.
fn fast(name: &str, count: usize, rotor: &Rotor, p: &Problem, speed: f64) -> ModesResult {
    let state = 2 * rotor.general_size();
    whirl_modes_nearest(rotor, &p.settings, speed, WHIRL_WINDOW * count, state)
        .unwrap()
        .unwrap_or_else(|| panic!("{name} at {speed} rad/s: the Krylov solve fell back"))
}

#[test]
fn krylov_and_dense_whirls_agree_on_the_anisotropic_rotors() {
    let fixtures = ["tests/fixtures/aniso/stepped-aniso.toml", "tests/fixtures/aniso/stepped-aniso-200.toml"];
    for f in fixtures {
        let p = Problem::from_path(common::root().join(f), &[]).unwrap();
        let rotor = Rotor::new(&p.model).unwrap();
        assert!(rotor.real);
        for speed in [0.0, p.model.speed, 3000.0] {
            let name = format!("{f} at {speed} rad/s");
            let dense = whirl_modes_of(&rotor, &p.settings, speed).unwrap();
            compare(&name, COUNT, &fast(&name, COUNT, &rotor, &p, speed), &dense);
        }
    }
    // The anisotropic Jeffcott rotor, with and without a gyroscopic disk: its four
    // whirls, the window of one whirl per direction. (Its next are the nearly massless
    // shaft's, 1.6e7 rad/s and up: 1e5 times the first, which no relative residual of a
    // shift-invert solve at 0 resolves, and `modes` solves such a small model densely.)
    // At speed with a steel shaft: the nearly massless one's gyroscopic terms
    // (1e-3 kg/m³) make its translations ellipses of κ ~ 1e-12, at the orbits'
    // LINE_TOLERANCE, whose direction no solver decides.
    for (polar, speed) in [(0.0, 0.0), (0.2, 0.0), (0.2, 300.0), (0.2, 900.0)] {
        let mut text = common::jeffcott(1.0e6, 2.0e6, polar, 0.1, speed);
        if speed > 0.0 {
            text = text.replace("density = 1.0e-3", "density = 7800.0");
        }
        let p = Problem::from_text(&text, "jeffcott.toml", &[]).unwrap();
        let rotor = Rotor::new(&p.model).unwrap();
        let name = format!("Jeffcott J_p = {polar} at {speed} rad/s");
        let dense = whirl_modes_of(&rotor, &p.settings, speed).unwrap();
        compare(&name, 1, &fast(&name, 1, &rotor, &p, speed), &dense);
    }
}

#[test]
#[ignore = "a sweep over problems/ (every problem forced to the real path): the anisotropic rotors above keep the block solver's agreement in CI; run by hand with -- --ignored krylov_and_dense_whirls_agree_on_every_problem"]
fn krylov_and_dense_whirls_agree_on_every_problem_forced_to_the_real_path() {
    let names = common::problem_names();
    assert!(names.len() >= 20, "{names:?}");
    for name in &names {
        let p = common::load(name, &["analysis.coordinates=\"real\""]);
        let rotor = Rotor::new(&p.model).unwrap();
        // At rest every whirl of an isotropic rotor is double in real coordinates.
        for speed in [0.0, p.model.speed] {
            let label = format!("{name} at {speed} rad/s");
            let dense = whirl_modes_of(&rotor, &p.settings, speed).unwrap();
            compare(&label, COUNT, &fast(&label, COUNT, &rotor, &p, speed), &dense);
        }
    }
}

/// The shaft's mass is 8e-8 of the disk's (as tests/anisotropic.rs).
const JEFFCOTT_TOLERANCE: f64 = 1e-6;

/// |ζ| of an undamped whirl from the Krylov solve: its eigenvalue's real part is the
/// solve's round-off, ~1e-13 of |λ| (the dense solver's Hermitian form makes it exactly
/// 0; the Krylov one has no such form for a general D and K).
const UNDAMPED_ZETA: f64 = 1e-10;

#[test]
fn krylov_whirls_of_the_jeffcott_rotor_are_its_closed_form() {
    // At rest: two planar translations √(k_x/m), √(k_y/m) and two planar tilts
    // √(a_x/J_d), √(a_y/J_d).
    let (kx, ky, jd) = (1.0e6, 2.0e6, 0.1);
    let p = Problem::from_text(&common::jeffcott(kx, ky, 0.2, jd, 0.0), "jeffcott.toml", &[]).unwrap();
    let rotor = Rotor::new(&p.model).unwrap();
    let r = fast("Jeffcott", 1, &rotor, &p, 0.0);
    let mut expected = [
        (common::jeffcott_translation(kx) / 10.0).sqrt(),
        (common::jeffcott_translation(ky) / 10.0).sqrt(),
        (common::jeffcott_tilt(kx) / jd).sqrt(),
        (common::jeffcott_tilt(ky) / jd).sqrt(),
    ];
    expected.sort_by(f64::total_cmp);
    let window = r.window(1);
    assert_eq!(window.len(), 4);
    for (&i, w) in window.iter().zip(expected) {
        let m = &r.modes[i];
        assert!(common::rel(m.frequency, w) < JEFFCOTT_TOLERANCE, "{}: {} vs {w}", m.tag(), m.frequency);
        // Planar: a line orbit in x or in y.
        assert_eq!((m.whirl, m.ellipticity), (Whirl::Mixed, Some(0.0)), "{m:?}");
        assert!(m.damping_ratio.abs() < UNDAMPED_ZETA, "{m:?}");
    }
}

#[test]
fn the_200_element_rotor_takes_the_krylov_path_within_the_modes_limit() {
    let p = Problem::from_path(common::root().join("tests/fixtures/aniso/stepped-aniso-200.toml"), &[]).unwrap();
    let rotor = Rotor::new(&p.model).unwrap();
    let state = 2 * rotor.general_size();
    assert_eq!(state, 1616);
    // The limit `modes` gives the space (a third of the state): no fallback to dense.
    let limit = state / rotorshunt::analysis::modes::KRYLOV_STATE_FRACTION;
    let fast = whirl_modes_nearest(&rotor, &p.settings, p.model.speed, WHIRL_WINDOW * COUNT, limit).unwrap();
    let fast = fast.expect("resolved within a third of the state");
    let routed = lowest_whirls_of(&rotor, &p.settings, p.model.speed, COUNT).unwrap();
    assert_eq!(fast.lowest(COUNT), routed.lowest(COUNT));
    // The solve finds the window and not the whole spectrum.
    assert!(fast.modes.len() < 100, "{} whirls", fast.modes.len());
}

#[test]
fn a_massless_charge_leaves_the_krylov_path_to_the_dense_solver() {
    // L = 0: the charge has no mass, M is singular and has no energy coordinates.
    let p = common::load("paper-closed.toml", &["analysis.coordinates=\"real\""]);
    let mut model = p.model.clone();
    for r in &mut model.rings {
        r.circuit.branches[0].inductance = 0.0;
    }
    let rotor = Rotor::new(&model).unwrap();
    let state = 2 * rotor.general_size();
    assert!(whirl_modes_nearest(&rotor, &p.settings, 2000.0, WHIRL_WINDOW * COUNT, state).unwrap().is_none());
    let dense = whirl_modes_of(&rotor, &p.settings, 2000.0).unwrap();
    let routed = lowest_whirls_of(&rotor, &p.settings, 2000.0, COUNT).unwrap();
    assert_eq!(routed.lowest(COUNT), dense.lowest(COUNT));
    assert!(!dense.lowest(COUNT).is_empty());
}

/// faer's partial eigensolver on the same operator ([`NearestSolver::Faer`], kept as the
/// block solver's comparison in benches/modes.rs and docs/decisions.md) with the whole
/// state allowed; `None` when it falls back.
fn by_faer(rotor: &Rotor, p: &Problem, speed: f64, count: usize) -> Option<ModesResult> {
    let state = 2 * rotor.general_size();
    whirl_modes_nearest_by(rotor, &p.settings, speed, WHIRL_WINDOW * count, state, NearestSolver::Faer).unwrap()
}

/// faer's whirls within [`FAST_DENSE_AGREEMENT`] of the dense ones, as the block
/// solver's: its pairs carry relative residuals up to 4e-11 (the block solver's 1e-13),
/// measured 1.0e-9 from the dense whirls at most where the block solver's are 1.4e-9.
#[test]
#[ignore = "faer's solver is not on the tool's path (docs/decisions.md, \"The lowest whirls stay with the block Krylov solver\"): the bench's correctness check, run by hand with -- --ignored faer_"]
fn faer_and_dense_whirls_agree_on_the_anisotropic_rotors() {
    let fixtures = [
        "tests/fixtures/aniso/stepped-aniso.toml",
        "tests/fixtures/aniso/stepped-aniso-200.toml",
        "problems/ross/compressor_example.toml",
    ];
    for f in fixtures {
        let p = Problem::from_path(common::root().join(f), &[]).unwrap();
        let rotor = Rotor::new(&p.model).unwrap();
        assert!(rotor.real);
        for speed in [p.model.speed, 3000.0] {
            let name = format!("{f} at {speed} rad/s");
            let dense = whirl_modes_of(&rotor, &p.settings, speed).unwrap();
            let faer = by_faer(&rotor, &p, speed, COUNT).unwrap_or_else(|| panic!("{name}: faer fell back"));
            compare(&name, COUNT, &faer, &dense);
        }
    }
}

/// Where faer resolves the window it agrees with the dense solver; it falls back only at
/// rest (9 of the 42 cases), where an isotropic rotor's whirls are double in real
/// coordinates: a single-vector Krylov–Schur holds one vector of a double eigenvalue,
/// and the whirls' QEP residuals (6e-10 to 5e-8 measured) miss the 1e-10 the path asks.
/// The block solver resolves every one of these cases (the test above).
#[test]
#[ignore = "a sweep over problems/ of a solver not on the tool's path: run by hand with -- --ignored faer_"]
fn faer_and_dense_whirls_agree_on_every_problem_forced_to_the_real_path() {
    let mut fallbacks = Vec::new();
    for name in &common::problem_names() {
        let p = common::load(name, &["analysis.coordinates=\"real\""]);
        let rotor = Rotor::new(&p.model).unwrap();
        for speed in [0.0, p.model.speed] {
            let label = format!("{name} at {speed} rad/s");
            let dense = whirl_modes_of(&rotor, &p.settings, speed).unwrap();
            match by_faer(&rotor, &p, speed, COUNT) {
                Some(faer) => compare(&label, COUNT, &faer, &dense),
                None => fallbacks.push((label, speed)),
            }
        }
    }
    assert!(fallbacks.iter().all(|(_, speed)| *speed == 0.0), "{fallbacks:?}");
}
