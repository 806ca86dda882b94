//! Timoshenko and tapered shaft sections (issue 28, point 1) against references that do
//! not use the code under test: Timoshenko's frequency equation of a simply supported
//! beam, Engesser's buckling load of a shear-flexible column, and a tapered shaft against
//! a fine staircase of uniform sections (the paper's closed-form Rayleigh elements, or
//! uniform Timoshenko elements checked against Nelson's closed forms in
//! `src/model/element.rs`).

use crate::common;
use common::rel;
use rotorshunt::analysis::modes::whirl_modes;
use rotorshunt::analysis::Rotor;
use rotorshunt::problem::Problem;
use std::f64::consts::PI;

/// Steel (ROSS's `steel`): E (Pa), G (Pa), ρ (kg/m³).
const E: f64 = 2.11e11;
const G: f64 = 8.12e10;
const RHO: f64 = 7810.0;

/// Bearings so stiff that the ends are pinned to within the tolerances below (N/m): the
/// thick shaft's first modal stiffness EIπ⁴/L³ is ~4e9 N/m, so its ends move by ~1e-8 of
/// the mode, the fourth mode's (×4⁴ in bending, less with shear) by ~1e-6, and its
/// frequency by less (the spring's share of the modal energy).
const PINNED: f64 = 1e17;

/// One `[[sections]]` entry: length, D left, d left, D right, d right (m), elements, beam.
struct Sec {
    length: f64,
    outer: (f64, f64),
    inner: (f64, f64),
    elements: usize,
    beam: &'static str,
}

fn sec(length: f64, outer: (f64, f64), inner: (f64, f64), elements: usize, beam: &'static str) -> Sec {
    Sec { length, outer, inner, elements, beam }
}

/// A general-form problem of `sections` on pinned ends, at rest and without static load.
fn pinned_shaft(sections: &[Sec]) -> Problem {
    let mut text = format!(
        "version = 1\nspeed = 0.0\n\n[[materials]]\nname = \"steel\"\nyoungs_modulus = {E:e}\ndensity = {RHO:e}\nshear_modulus = {G:e}\n\n"
    );
    for s in sections {
        text += &format!(
            "[[sections]]\nlength = {:e}\nouter_diameter = {:e}\ninner_diameter = {:e}\nouter_diameter_right = {:e}\ninner_diameter_right = {:e}\nmaterial = \"steel\"\nbeam = \"{}\"\nelements = {}\n\n",
            s.length, s.outer.0, s.inner.0, s.outer.1, s.inner.1, s.beam, s.elements
        );
    }
    let length: f64 = sections.iter().map(|s| s.length).sum();
    text += &format!("[[bearings]]\nnode = 0\nstiffness = {PINNED:e}\n\n[[bearings]]\nposition = {length:e}\nstiffness = {PINNED:e}\n\n");
    text += "[load]\nalpha = 0.0\n\n[analysis]\nreduced_modes = 4\n";
    Problem::from_text(&text, "pinned-shaft.toml", &[]).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// The lowest `count` natural frequencies (rad/s) at rest.
fn natural(p: &Problem, count: usize) -> Vec<f64> {
    let m = whirl_modes(&p.model, &p.settings, 0.0).unwrap_or_else(|e| panic!("{e}"));
    m.forward().take(count).map(|w| w.frequency).collect()
}

/// Cowper's (1966) shear coefficient of a solid circle, 6(1 + ν)/(7 + 6ν).
fn cowper_solid(nu: f64) -> f64 {
    6.0 * (1.0 + nu) / (7.0 + 6.0 * nu)
}

/// Order of convergence of the frequencies and the buckling load with the element
/// length h: Nelson's Timoshenko element converges like h² (its shape functions are
/// exact statically, not dynamically), so halving h divides the error by ~4. The tests
/// ask for a ratio above 3.5 and extrapolate (Richardson) from the two finest meshes.
const CONVERGENCE_RATIO: f64 = 3.5;

/// Richardson's extrapolation of an h² error from meshes of h and h/2.
fn richardson(coarse: f64, fine: f64) -> f64 {
    (4.0 * fine - coarse) / 3.0
}

/// The extrapolated values against a closed form: the h⁴ remainder of the extrapolation
/// at 64 and 128 elements per span, and the pinning springs ([`PINNED`]), leave ~1e-7.
const CLOSED_FORM_RTOL: f64 = 1e-6;

/// The Rayleigh elements at 64 per span against their closed form, unextrapolated:
/// Hermite cubics converge like h⁴, which leaves the fourth mode of the thick shaft ~1e-6
/// off (found: 9.9e-7).
const RAYLEIGH_RTOL: f64 = 1e-5;

/// Values on meshes of 32, 64 and 128 elements: their errors against `exact` must fall
/// like h², and their extrapolation must meet it. Returns (errors per mesh, extrapolated).
fn converges(what: &str, meshes: [Vec<f64>; 3], exact: &[f64]) -> Vec<f64> {
    let errors: Vec<Vec<f64>> =
        meshes.iter().map(|m| m.iter().zip(exact).map(|(a, b)| rel(*a, *b)).collect()).collect();
    let mut extrapolated = Vec::new();
    for n in 0..exact.len() {
        let w = richardson(meshes[1][n], meshes[2][n]);
        let err = rel(w, exact[n]);
        println!(
            "{what} {}: closed form {:.6}; 32/64/128 elements {:.6} / {:.6} / {:.6} (errors {:.2e} / {:.2e} / {:.2e}); extrapolated {w:.6}, error {err:.2e}",
            n + 1,
            exact[n],
            meshes[0][n],
            meshes[1][n],
            meshes[2][n],
            errors[0][n],
            errors[1][n],
            errors[2][n]
        );
        for pair in errors.windows(2) {
            assert!(pair[0][n] / pair[1][n] > CONVERGENCE_RATIO, "{what} {}: errors {:?}", n + 1, errors);
        }
        assert!(err < CLOSED_FORM_RTOL, "{what} {}: extrapolated error {err:.3e}", n + 1);
        extrapolated.push(w);
    }
    extrapolated
}

#[test]
fn timoshenko_1921_simply_supported_frequencies() {
    // Timoshenko (1921), "On the correction for shear of the differential equation for
    // transverse vibrations of prismatic bars": a simply supported beam vibrates in
    // u = U sin kx, ψ = Ψ cos kx, k = nπ/L, and the equations
    //   κGA(u'' − ψ') + ρAω²u = 0,  EIψ'' + κGA(u' − ψ) + ρIω²ψ = 0
    // give (ρAω² − κGAk²)(ρIω² − EIk² − κGA) = (κGAk)², whose lower root in ω² is the
    // bending frequency (the simply supported case of Han, Benaroya & Wei 1999,
    // "Dynamics of transversely vibrating beams using four engineering theories",
    // J. Sound Vib. 225). A short thick shaft: L/D = 10/3.
    let (length, d) = (0.5, 0.15);
    let (a, i) = (PI * d * d / 4.0, PI * d.powi(4) / 64.0);
    let kappa = cowper_solid(E / (2.0 * G) - 1.0);
    let (ra, ri, s, ei) = (RHO * a, RHO * i, kappa * G * a, E * i);
    let exact: Vec<f64> = (1..=4)
        .map(|n| {
            let k = n as f64 * PI / length;
            // ρAρI x² − (ρA(EIk² + κGA) + ρIκGAk²) x + κGA·EI k⁴ = 0, lower root.
            let b = ra * (ei * k * k + s) + ri * s * k * k;
            let c = s * ei * k.powi(4);
            let x = 2.0 * c / (b + (b * b - 4.0 * ra * ri * c).sqrt());
            x.sqrt()
        })
        .collect();
    // Rayleigh (rotary inertia, no shear): ω² = EIk⁴/(ρA(1 + (I/A)k²)).
    let rayleigh_exact: Vec<f64> = (1..=4)
        .map(|n| {
            let k = n as f64 * PI / length;
            (ei * k.powi(4) / (ra * (1.0 + i / a * k * k))).sqrt()
        })
        .collect();
    let mesh = |beam, n| natural(&pinned_shaft(&[sec(length, (d, d), (0.0, 0.0), n, beam)]), 4);
    let timoshenko = converges("Timoshenko mode", [32, 64, 128].map(|n| mesh("timoshenko", n)), &exact);
    // The Rayleigh elements converge (like h⁴) to their own closed form, not Timoshenko's.
    let rayleigh = mesh("rayleigh", 64);
    for n in 0..4 {
        let off = rayleigh[n] / timoshenko[n] - 1.0;
        println!(
            "Rayleigh mode {}: FE {:.6} rad/s, its closed form {:.6} rad/s; {:+.2} % from Timoshenko's",
            n + 1,
            rayleigh[n],
            rayleigh_exact[n],
            100.0 * off
        );
        assert!(rel(rayleigh[n], rayleigh_exact[n]) < RAYLEIGH_RTOL, "Rayleigh mode {}", n + 1);
        assert!(off > 0.05, "mode {}: Rayleigh only {off:.3e} from Timoshenko: not a thick shaft", n + 1);
    }
}

#[test]
fn engesser_buckling_load_of_a_pinned_timoshenko_column() {
    // The axial load works on the slope of the deflection (S = ∫N′ᵀN′): a pinned-pinned
    // shear-flexible column buckles at Engesser's load P_E/(1 + P_E/(κGA)),
    // P_E = π²EI/L² (Timoshenko & Gere 1961, "Theory of Elastic Stability", §2.16).
    let (length, d) = (0.4, 0.12);
    let (a, i) = (PI * d * d / 4.0, PI * d.powi(4) / 64.0);
    let kappa = cowper_solid(E / (2.0 * G) - 1.0);
    let euler = PI * PI * E * i / (length * length);
    let engesser = euler / (1.0 + euler / (kappa * G * a));
    let load = |n| {
        let p = pinned_shaft(&[sec(length, (d, d), (0.0, 0.0), n, "timoshenko")]);
        vec![Rotor::new(&p.model).expect("rotor").critical_load]
    };
    let fe = converges("P_cr (N)", [32, 64, 128].map(load), &[engesser])[0];
    println!(
        "Engesser {engesser:.6e} N, extrapolated FE {fe:.6e} N; Euler {euler:.6e} N ({:+.2} %)",
        100.0 * (euler / engesser - 1.0)
    );
    assert!(euler / engesser - 1.0 > 0.02, "shear must matter here");
}

/// A staircase of `steps` uniform sections of one element each, following the taper of
/// `s` (each step's diameters those at its middle).
fn staircase(s: &Sec, steps: usize) -> Vec<Sec> {
    let at = |(l, r): (f64, f64), t: f64| (1.0 - t) * l + t * r;
    (0..steps)
        .map(|k| {
            let t = (k as f64 + 0.5) / steps as f64;
            let (o, i) = (at(s.outer, t), at(s.inner, t));
            sec(s.length / steps as f64, (o, o), (i, i), 1, s.beam)
        })
        .collect()
}

#[test]
fn a_vanishing_taper_converges_to_the_uniform_section() {
    // D from 0.06 to 0.06(1 + ε): the frequencies approach the uniform shaft's linearly
    // in ε, and at ε = 0 the tapered path gives the uniform one.
    for beam in ["rayleigh", "timoshenko"] {
        let uniform = natural(&pinned_shaft(&[sec(0.8, (0.06, 0.06), (0.02, 0.02), 16, beam)]), 3);
        let mut last = f64::INFINITY;
        for eps in [1e-2, 1e-3, 1e-4] {
            let d = 0.06 * (1.0 + eps);
            let w = natural(&pinned_shaft(&[sec(0.8, (0.06, d), (0.02, 0.02), 16, beam)]), 3);
            let gap = w.iter().zip(&uniform).map(|(a, b)| rel(*a, *b)).fold(0.0, f64::max);
            println!("{beam}: taper ε = {eps:.0e}: largest relative gap to the uniform shaft {gap:.3e}");
            // Linear in ε: the gap shrinks tenfold with ε, and is of order ε.
            assert!(gap < eps && gap < last / 5.0, "{beam} ε = {eps}: {gap}");
            last = gap;
        }
    }
}

#[test]
fn tapered_shafts_match_a_fine_staircase_of_uniform_sections() {
    // A hollow cone on pinned ends, D 0.10 → 0.04 m, d 0.02 → 0.01 m, over 0.9 m: its
    // tapered elements against a staircase of uniform sections, one element each at the
    // mid-step diameters. Both converge like h² (the staircase's midpoint rule of A(x)
    // and I(x), and the Timoshenko elements), so both are extrapolated from 64 and 128
    // elements (tapered) and 128 and 256 steps (staircase). The two extrapolations keep
    // remainders of higher order, found up to 8.5e-7 apart on the Timoshenko cone.
    const STAIRCASE_RTOL: f64 = 2e-6;
    for beam in ["rayleigh", "timoshenko"] {
        let cone = |n| sec(0.9, (0.10, 0.04), (0.02, 0.01), n, beam);
        let tapered: Vec<Vec<f64>> = [64, 128].iter().map(|&n| natural(&pinned_shaft(&[cone(n)]), 4)).collect();
        let steps: Vec<Vec<f64>> =
            [128, 256].iter().map(|&n| natural(&pinned_shaft(&staircase(&cone(1), n)), 4)).collect();
        // The frustum's mass, πρL/12·((D₁² + D₁D₂ + D₂²) − (d₁² + d₁d₂ + d₂²)).
        let frustum = PI * RHO * 0.9 / 12.0 * ((0.01 + 0.004 + 0.0016) - (0.0004 + 0.0002 + 0.0001));
        assert!(rel(pinned_shaft(&[cone(8)]).model.shaft.mass(), frustum) < 1e-14);
        for n in 0..4 {
            let t = richardson(tapered[0][n], tapered[1][n]);
            let s = richardson(steps[0][n], steps[1][n]);
            let err = rel(t, s);
            println!(
                "{beam} cone mode {}: tapered 64/128 elements {:.6} / {:.6} → {t:.6} rad/s; staircase 128/256 steps {:.6} / {:.6} → {s:.6} rad/s; gap {err:.2e} (unextrapolated 128 vs 256: {:.2e})",
                n + 1,
                tapered[0][n],
                tapered[1][n],
                steps[0][n],
                steps[1][n],
                rel(tapered[1][n], steps[1][n])
            );
            assert!(err < STAIRCASE_RTOL, "{beam} mode {}: {err:.3e}", n + 1);
        }
    }
}

#[test]
fn a_set_shear_modulus_replaces_the_files_poisson_ratio() {
    // The good fixture gives ν = 0.3 (G = E/2.6); --set of G replaces it, as the other
    // pairs of alternative keys do (problems/README.md, "Overrides").
    let path = common::root().join("tests/fixtures/good/timoshenko_tapered.toml");
    let g_of = |p: &Problem| match p.model.shaft.sections[1].beam {
        rotorshunt::model::Beam::Timoshenko { shear_modulus, .. } => shear_modulus,
        rotorshunt::model::Beam::Rayleigh => panic!("section 2 is Timoshenko"),
    };
    let file = Problem::from_path(&path, &[]).unwrap();
    assert!(rel(g_of(&file), 2.11e11 / 2.6) < 1e-15);
    let set = Problem::from_path(&path, &["materials[0].shear_modulus=8e10".to_string()]).unwrap();
    assert_eq!(g_of(&set), 8e10);
}

#[test]
fn a_layer_adds_its_tube_to_its_section() {
    // Rayleigh tubes add: A and I of a solid core of D = 0.05 m and a sleeve 0.05/0.08 m
    // are those of a solid D = 0.08 m shaft, so the layered shaft and the solid one have
    // the same matrices up to round-off, and the same frequencies.
    const ROUND_OFF: f64 = 1e-10;
    let text = |sections: &str| {
        format!(
            "version = 1\nspeed = 300.0\n\n{sections}\n[[bearings]]\nnode = 0\nstiffness = 1e7\n\n[[bearings]]\nnode = 20\nstiffness = 1e7\n\n[load]\nalpha = 0.0\n"
        )
    };
    let solid = "[[sections]]\nlength = 1.0\nouter_diameter = 0.08\nyoungs_modulus = 2.11e11\ndensity = 7810.0\nelements = 20\n";
    let layered = "[[sections]]\nlength = 1.0\nouter_diameter = 0.05\nyoungs_modulus = 2.11e11\ndensity = 7810.0\nelements = 20\n\n[[sections.layers]]\nouter_diameter = 0.08\ninner_diameter = 0.05\nyoungs_modulus = 2.11e11\ndensity = 7810.0\n";
    let whirls = |t: &str| {
        let p = Problem::from_text(&text(t), "layer.toml", &[]).unwrap_or_else(|e| panic!("{e}"));
        let m = whirl_modes(&p.model, &p.settings, p.model.speed).unwrap();
        (
            p.model.shaft.mass(),
            m.forward()
                .take(4)
                .map(|w| w.frequency)
                .chain(m.backward().take(4).map(|w| w.frequency))
                .collect::<Vec<_>>(),
        )
    };
    let (m_solid, w_solid) = whirls(solid);
    let (m_layered, w_layered) = whirls(layered);
    assert!(rel(m_layered, m_solid) < ROUND_OFF);
    for (a, b) in w_layered.iter().zip(&w_solid) {
        assert!(rel(*a, *b) < ROUND_OFF, "{a} vs {b}");
    }
}

#[test]
fn every_section_error_of_a_file_is_reported_at_once() {
    use rotorshunt::problem::ProblemErrorKind as K;
    // A Poisson's ratio of 0.5 on a material and of −1 on a section, a taper to a zero
    // outer diameter and a zero shear coefficient on one section; the section made of the
    // failed material adds nothing of its own.
    let path = common::root().join("tests/fixtures/bad/section_all_at_once.toml");
    let e = Problem::from_path(&path, &[]).expect_err("four defects");
    let found: Vec<(String, Option<usize>, &'static str)> = e
        .all()
        .iter()
        .map(|e| {
            let kind = match &e.kind {
                K::OutOfRange { value, .. } if *value == 0.5 || *value == -1.0 => "poisson",
                K::NotPositive(v) if *v == 0.0 => "not positive",
                _ => "other",
            };
            (e.key.clone(), e.line(), kind)
        })
        .collect();
    let expected = [
        ("materials[0].poisson_ratio", 11, "poisson"),
        ("sections[1].poisson_ratio", 28, "poisson"),
        ("sections[2].outer_diameter_right", 34, "not positive"),
        ("sections[2].shear_coefficient", 39, "not positive"),
    ];
    assert_eq!(found.len(), expected.len(), "{found:?}");
    for ((key, line, kind), (k, l, d)) in found.iter().zip(expected) {
        assert_eq!((key.as_str(), *line, *kind), (k, Some(l), d));
    }
    // The command line prints each on its own `error:` line, and exits 2.
    common::check_lists_errors(&path, &expected.map(|(k, l, _)| (k, l)));
}
