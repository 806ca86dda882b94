//! The general model (issue 16) against references that do not use the code under test:
//! a hollow pinned-pinned tube's Rayleigh-beam closed form, a transfer-matrix solution of
//! a stepped shaft's free vibration and buckling written here, and a dense Cholesky of
//! the assembled stiffness for the rigid-body check. Also `modes` on a 200-element stepped
//! rotor with two rings: its electrical whirls.

use crate::common;
use common::rel;
use rotorshunt::analysis::modes::whirl_modes;
use rotorshunt::analysis::Rotor;
use rotorshunt::assembly::SystemMatrices;
use rotorshunt::linalg::seq::cholesky;
use rotorshunt::model::{Bearing, CircuitState, Model};
use rotorshunt::problem::Problem;
use std::f64::consts::PI;

/// Steel of the test rotors: E (Pa), ρ (kg/m³).
const E: f64 = 2.1e11;
const RHO: f64 = 7800.0;

/// A general-form problem with `sections` (length, D, d, elements), plain bearings
/// (position, stiffness) and no ring, at rest and without static load.
fn bearing_rotor(sections: &[(f64, f64, f64, usize)], bearings: &[(f64, f64)]) -> Problem {
    let mut text = String::from("version = 1\nspeed = 0.0\n\n");
    for (l, d_o, d_i, n) in sections {
        text += &format!(
            "[[sections]]\nlength = {l:e}\nouter_diameter = {d_o:e}\ninner_diameter = {d_i:e}\nyoungs_modulus = {E:e}\ndensity = {RHO:e}\nelements = {n}\n\n"
        );
    }
    for (x, k) in bearings {
        text += &format!("[[bearings]]\nposition = {x:e}\nstiffness = {k:e}\n\n");
    }
    text += "[load]\nalpha = 0.0\n\n[analysis]\nreduced_modes = 4\n";
    Problem::from_text(&text, "bearing-rotor.toml", &[]).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// The lowest `count` natural frequencies (rad/s) of the problem at rest: its forward
/// whirls at Ω = 0 (equal to the backward ones).
fn natural(p: &Problem, count: usize) -> Vec<f64> {
    let m = whirl_modes(&p.model, &p.settings, 0.0).unwrap_or_else(|e| panic!("{e}"));
    m.forward().take(count).map(|w| w.frequency).collect()
}

fn section_props(d_o: f64, d_i: f64) -> (f64, f64) {
    let area = PI * (d_o * d_o - d_i * d_i) / 4.0;
    let inertia = PI * (d_o.powi(4) - d_i.powi(4)) / 64.0;
    (area, inertia)
}

/// Bearings so stiff that the ends are pinned to within the discretisation error (N/m):
/// the tube's modal stiffness EIπ⁴/L³ is ~5e6 N/m, so the ends move by ~5e-9 of the mode.
const PINNED: f64 = 1e15;

#[test]
fn hollow_pinned_tube_converges_to_the_rayleigh_closed_form() {
    let (length, d_o, d_i) = (1.0, 0.05, 0.03);
    let (area, inertia) = section_props(d_o, d_i);
    // Rayleigh beam, pinned-pinned: ω² = EI k⁴ / (ρA (1 + (I/A) k²)), k = nπ/L.
    let exact: Vec<f64> = (1..=3)
        .map(|n| {
            let k = n as f64 * PI / length;
            (E * inertia * k.powi(4) / (RHO * area * (1.0 + inertia / area * k * k))).sqrt()
        })
        .collect();
    let mut errors = Vec::new();
    for elements in [8, 16, 32] {
        let p = bearing_rotor(&[(length, d_o, d_i, elements)], &[(0.0, PINNED), (length, PINNED)]);
        let w = natural(&p, 3);
        let e: Vec<f64> = w.iter().zip(&exact).map(|(a, b)| rel(*a, *b)).collect();
        println!(
            "{elements:>2} elements: ω = {:.4?} rad/s, closed form {:.4?}, relative errors {:?}",
            w,
            exact,
            e.iter().map(|x| format!("{x:.3e}")).collect::<Vec<_>>()
        );
        errors.push(e);
    }
    for mode in 0..3 {
        // Hermite elements converge like h⁴ in frequency: halving h divides the error by
        // ~16; at least 8 is asked, i.e. order ≥ 3.
        for pair in errors.windows(2) {
            assert!(pair[1][mode] < pair[0][mode] / 8.0, "mode {}: {:?}", mode + 1, errors);
        }
    }
    // 32 elements: well inside 1e-5 on the first three modes.
    assert!(errors[2].iter().all(|&e| e < 1e-5), "{errors:?}");
}

/// A 4×4 matrix, row-major.
type M4 = [[f64; 4]; 4];

fn mul(a: &M4, b: &M4) -> M4 {
    let mut c = [[0.0; 4]; 4];
    for i in 0..4 {
        for j in 0..4 {
            c[i][j] = (0..4).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    c
}

/// Inverse by Gauss–Jordan elimination with partial pivoting.
fn inverse(a: &M4) -> M4 {
    let mut m = *a;
    let mut inv = [[0.0; 4]; 4];
    for (i, row) in inv.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    for col in 0..4 {
        let p = (col..4).max_by(|&x, &y| m[x][col].abs().total_cmp(&m[y][col].abs())).expect("rows");
        m.swap(col, p);
        inv.swap(col, p);
        let d = m[col][col];
        for j in 0..4 {
            m[col][j] /= d;
            inv[col][j] /= d;
        }
        for r in 0..4 {
            if r != col {
                let f = m[r][col];
                for j in 0..4 {
                    m[r][j] -= f * m[col][j];
                    inv[r][j] -= f * inv[col][j];
                }
            }
        }
    }
    inv
}

/// The state y = [w, w′, EI w″, EI w‴ + q w′] carried across a section, continuous at
/// steps, for the functional ½∫(EI w″² − q w′² − ρAω² w²) dx: q = ρIω² and the
/// ρAω² term for free vibration of a Rayleigh beam (EI w⁗ + ρIω² w″ − ρAω² w = 0),
/// q = P and no mass term for buckling (EI w⁗ + P w″ = 0). Its field matrix over a
/// section of length l is Φ(l)·Φ(0)⁻¹, Φ's columns the state of each basis solution.
fn field_matrix(ei: f64, q: f64, mass: f64, l: f64) -> M4 {
    // Basis: e^{sx} with EI s⁴ + q s² − mass = 0: s² = α² > 0 (cosh, sinh) when mass > 0,
    // else 1 and x; and s² = −β² (cos, sin).
    let (a, b) = (q / ei, mass / ei);
    let root = (a * a + 4.0 * b).sqrt();
    let beta = ((a + root) / 2.0).sqrt();
    let state = |x: f64| -> M4 {
        // Columns: [f, f', EI f'', EI f''' + q f'] of each basis function.
        let mut cols: Vec<[f64; 4]> = Vec::new();
        if mass > 0.0 {
            let alpha = ((-a + root) / 2.0).sqrt();
            let (ch, sh) = ((alpha * x).cosh(), (alpha * x).sinh());
            cols.push([ch, alpha * sh, ei * alpha * alpha * ch, ei * alpha.powi(3) * sh + q * alpha * sh]);
            cols.push([sh, alpha * ch, ei * alpha * alpha * sh, ei * alpha.powi(3) * ch + q * alpha * ch]);
        } else {
            cols.push([1.0, 0.0, 0.0, 0.0]);
            cols.push([x, 1.0, 0.0, q]);
        }
        let (c, s) = ((beta * x).cos(), (beta * x).sin());
        cols.push([c, -beta * s, -ei * beta * beta * c, ei * beta.powi(3) * s - q * beta * s]);
        cols.push([s, beta * c, -ei * beta * beta * s, -ei * beta.powi(3) * c + q * beta * c]);
        let mut m = [[0.0; 4]; 4];
        for (j, col) in cols.iter().enumerate() {
            for i in 0..4 {
                m[i][j] = col[i];
            }
        }
        m
    };
    mul(&state(l), &inverse(&state(0.0)))
}

/// The frequency (or load) determinant of a shaft of sections (EI, q, mass per length
/// times ω², length) on springs k0 at x = 0 and kL at x = L, free slopes: y(0) =
/// [w, θ, 0, −k0 w], and at L the moment M = 0 and S = kL w.
fn determinant(sections: &[(f64, f64, f64, f64)], k0: f64, kl: f64) -> f64 {
    let mut t = [[0.0; 4]; 4];
    for (i, row) in t.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    for &(ei, q, mass, l) in sections {
        t = mul(&field_matrix(ei, q, mass, l), &t);
    }
    let b0 = [[1.0, 0.0], [0.0, 1.0], [0.0, 0.0], [-k0, 0.0]];
    let row = |r: [f64; 4]| -> [f64; 2] { [0, 1].map(|c| (0..4).map(|k| r[k] * b0[k][c]).sum()) };
    let moment = row(t[2]);
    let shear = row([0, 1, 2, 3].map(|k| t[3][k] - kl * t[0][k]));
    moment[0] * shear[1] - moment[1] * shear[0]
}

/// The first `count` roots of `f` above `start`, by a scan with `step` and bisection.
fn roots(f: &dyn Fn(f64) -> f64, start: f64, step: f64, count: usize) -> Vec<f64> {
    let mut out = Vec::new();
    let (mut x, mut fx) = (start, f(start));
    while out.len() < count {
        let (y, fy) = (x + step, f(x + step));
        if fx.signum() != fy.signum() {
            let (mut lo, mut hi, mut flo) = (x, y, fx);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                let fm = f(mid);
                if fm.signum() == flo.signum() {
                    lo = mid;
                    flo = fm;
                } else {
                    hi = mid;
                }
            }
            out.push(0.5 * (lo + hi));
        }
        (x, fx) = (y, fy);
    }
    out
}

/// The stepped shaft of the transfer-matrix tests: (length, D, d, elements).
const STEPPED: [(f64, f64, f64, usize); 2] = [(0.3, 0.06, 0.0, 30), (0.5, 0.04, 0.02, 50)];

#[test]
fn stepped_shaft_matches_a_transfer_matrix_solution() {
    // Spring ends of 1e8 N/m: the supports' stiffness enters both solutions.
    let k = 1e8;
    let length: f64 = STEPPED.iter().map(|s| s.0).sum();
    let p = bearing_rotor(&STEPPED, &[(0.0, k), (length, k)]);
    let fe = natural(&p, 4);
    let det = |w: f64| {
        let sections: Vec<_> = STEPPED
            .iter()
            .map(|&(l, d_o, d_i, _)| {
                let (a, i) = section_props(d_o, d_i);
                (E * i, RHO * i * w * w, RHO * a * w * w, l)
            })
            .collect();
        determinant(&sections, k, k)
    };
    let tm = roots(&det, 1.0, 0.5, 4);
    for (n, (a, b)) in fe.iter().zip(&tm).enumerate() {
        println!(
            "stepped shaft mode {}: FE {a:.4} rad/s, transfer matrix {b:.4} rad/s, error {:.2e}",
            n + 1,
            rel(*a, *b)
        );
        assert!(rel(*a, *b) < 1e-3, "mode {}: FE {a}, transfer matrix {b}", n + 1);
    }
}

#[test]
fn critical_load_of_a_stepped_shaft_on_stiff_supports() {
    // Uniform limit: π²EI/L² of the pinned-pinned shaft.
    let (length, d_o) = (0.8, 0.04);
    let p = bearing_rotor(&[(length, d_o, 0.0, 40)], &[(0.0, PINNED), (length, PINNED)]);
    let (_, i) = section_props(d_o, 0.0);
    let euler = PI * PI * E * i / (length * length);
    let fe = Rotor::new(&p.model).expect("rotor").critical_load;
    println!("uniform: P_cr = {fe:.6e} N, pi^2 EI/L^2 = {euler:.6e} N, error {:.2e}", rel(fe, euler));
    assert!(rel(fe, euler) < 1e-6);
    // Stepped: the transfer-matrix buckling load of the same sections and supports.
    let length: f64 = STEPPED.iter().map(|s| s.0).sum();
    let p = bearing_rotor(&STEPPED, &[(0.0, PINNED), (length, PINNED)]);
    let fe = Rotor::new(&p.model).expect("rotor").critical_load;
    let det = |load: f64| {
        let sections: Vec<_> =
            STEPPED.iter().map(|&(l, d_o, d_i, _)| (E * section_props(d_o, d_i).1, load, 0.0, l)).collect();
        determinant(&sections, PINNED, PINNED)
    };
    let weakest = PI * PI * E * section_props(0.04, 0.02).1 / (length * length);
    let tm = roots(&det, 0.5 * weakest, weakest / 2000.0, 1)[0];
    println!("stepped: P_cr = {fe:.6e} N, transfer matrix {tm:.6e} N, error {:.2e}", rel(fe, tm));
    assert!(rel(fe, tm) < 1e-4, "FE {fe}, transfer matrix {tm}");
    // The weakest section's Euler load is a lower bound (the stiffer section only helps).
    assert!(tm > weakest);
}

/// The rigid-body check of the file layer (two supports with stiffness at distinct nodes)
/// against a dense Cholesky of the assembled open-circuit stiffness at zero load.
#[test]
fn rigid_body_check_agrees_with_a_cholesky_of_k() {
    let base = common::load("stepped-bearing-ring.toml", &[]).model;
    let defined = |m: &Model| cholesky(SystemMatrices::assemble(&m.with_state(CircuitState::Open)).k.as_ref()).is_ok();
    assert!(defined(&base), "the bearing and the ring hold the rotor");
    let mut free = base.clone();
    free.bearings.clear();
    free.rings.clear();
    let mut one_ring = base.clone();
    one_ring.bearings.clear();
    let mut one_bearing = base.clone();
    one_bearing.rings.clear();
    let mut two_bearings = one_bearing.clone();
    two_bearings.bearings.push(Bearing::isotropic(base.shaft.last_node(), 1e7, 0.0, 0.0));
    let mut soft = two_bearings.clone();
    soft.bearings[1] = Bearing::isotropic(soft.bearings[1].node, 0.0, 0.0, 0.0);
    for (name, m, supported) in [
        ("free-free", &free, false),
        ("one ring", &one_ring, false),
        ("one bearing", &one_bearing, false),
        ("two bearings", &two_bearings, true),
        ("a bearing and a zero-stiffness bearing", &soft, false),
    ] {
        assert_eq!(defined(m), supported, "{name}: Cholesky of K");
        let p = Problem::from_data(to_file(m, &common::load("stepped-bearing-ring.toml", &[]).data), name, &[]);
        match p {
            Ok(_) => assert!(supported, "{name}: loaded although K is singular"),
            Err(e) => {
                assert!(!supported, "{name}: {e}");
                assert!(e.to_string().contains("unsupported: rigid-body mode(s)"), "{name}: {e}");
            }
        }
    }
}

/// `data` with its supports replaced by the model's (positions kept out: by node).
fn to_file(m: &Model, data: &rotorshunt::problem::ProblemFile) -> rotorshunt::problem::ProblemFile {
    use rotorshunt::problem::file::BearingFile;
    let mut d = data.clone();
    d.design = None;
    d.bearings = m
        .bearings
        .iter()
        .map(|b| BearingFile {
            node: Some(b.node as i64),
            position: None,
            stiffness: Some(b.stiffness()),
            damping: Some(b.damping()),
            mass: b.mass,
            ..Default::default()
        })
        .collect();
    d.rings.truncate(m.rings.len());
    d
}

#[test]
fn modes_of_a_200_element_stepped_rotor_with_two_rings() {
    let base = std::fs::read_to_string(common::problem_path("two-rings-1-3.toml")).expect("two-rings-1-3.toml");
    // The paper's shaft in four sections of 50 elements: 0.7 m, stepped 30/36/30/26 mm.
    let (head, rest) = base.split_once("[[sections]]").expect("sections");
    let tail = &rest[rest.find("[[disks]]").expect("disks")..];
    let mut text = String::from(head);
    for (l, d) in [(0.175, 0.030), (0.2, 0.036), (0.2, 0.030), (0.125, 0.026)] {
        text += &format!("[[sections]]\nlength = {l}\nouter_diameter = {d}\ninner_diameter = 0.01\nmaterial = \"paper-steel\"\nelements = 50\n\n");
    }
    text += tail;
    let p = Problem::from_text(&text, "two-rings-200.toml", &[]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(p.model.shaft.elements(), 200);
    assert_eq!(p.model.shaft.sections.len(), 4);
    // What it finds is asserted, never how long it takes.
    let m = whirl_modes(&p.model, &p.settings, p.model.speed).expect("modes");
    let electrical = m.modes.iter().filter(|w| w.label.contains('@')).count();
    assert_eq!(electrical, 8, "4 charges, each a forward and a backward electrical whirl");
}
