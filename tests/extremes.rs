//! Numerical extremes, one test per case, each with the right answer it must give (from a
//! closed form, a limit argument or an independent computation) or the typed error / flag
//! it must raise. Run with `--nocapture` to see the values.

use crate::common;
use common::{load, problem_path, rel};
use rotorshunt::analysis::buckling::buckling_load;
use rotorshunt::analysis::floquet::{dstm, FloquetPoint, FloquetSystem, PointStatus};
use rotorshunt::analysis::modes::{whirl_modes, ModeKind, Whirl};
use rotorshunt::analysis::{AnalysisError, Rotor};
use rotorshunt::assembly::SystemMatrices;
use rotorshunt::model::Model;
use rotorshunt::problem::{Location, Problem, ProblemErrorKind};
use std::time::Instant;

fn floquet_system(p: &Problem) -> FloquetSystem {
    let rotor = Rotor::new(&p.model).unwrap_or_else(|e| panic!("{e}"));
    FloquetSystem::new(&rotor, &p.settings, p.model.speed).unwrap_or_else(|e| panic!("{e}"))
}

/// Every number of a point is finite and the point was computed normally.
fn assert_sound(point: &FloquetPoint, what: &str) {
    let s = &point.summary;
    assert_eq!(s.status, PointStatus::Ok, "{what}: status {:?}", s.status);
    assert!(s.ln_max_multiplier.is_finite() && s.growth_rate.is_finite(), "{what}: {s:?}");
    assert!(!s.max_multiplier.is_nan(), "{what}: {s:?}");
    assert!(point.multipliers.iter().flatten().all(|x| x.is_finite()), "{what}: {:?}", point.multipliers);
}

/// The lowest forward whirl frequencies (rad/s) of the full model's mechanical modes.
fn forward(model: &Model, p: &Problem, speed: f64, count: usize) -> Vec<f64> {
    let r = whirl_modes(model, &p.settings, speed).unwrap_or_else(|e| panic!("{e}"));
    let mechanical = r.modes.iter().filter(|m| m.whirl == Whirl::Forward && m.kind == ModeKind::Mechanical);
    mechanical.map(|m| m.frequency).take(count).collect()
}

/// |μ_1·…·μ_n| = |det Φ(T)| = exp(∫ Re tr B dt) (Liouville): 1 for an undamped system.
fn ln_abs_det(point: &FloquetPoint) -> f64 {
    point.multipliers.iter().map(|m| m[0].hypot(m[1]).ln() + point.multiplier_log_scale).sum()
}

/// The closed circuit of Fig. 11 with branch 1's inductance written as `inductance = L`.
fn fig11_with_inductance(l: &str) -> Problem {
    let text = std::fs::read_to_string(problem_path("fig11-closed-2000.toml")).unwrap();
    let text = text.replacen("tuning_frequency = 900.0", &format!("inductance = {l}"), 1);
    assert!(text.contains(&format!("inductance = {l}")));
    Problem::from_text(&text, "l.toml", &[]).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn zero_inductance_goes_through_floquet_as_its_limit() {
    // L = 0 (a purely capacitive branch, singular M) is valid input. Its charges are
    // massless, so the reduced basis (modes of finite frequency) has no r mode, and the
    // Floquet result is the L → 0 limit: L = 1e-9 H puts the r mode at ~4e7 rad/s, far
    // outside the 8-mode basis (< 7000 rad/s), shifting the basis by O((7e3/4e7)²) ≈ 3e-8.
    let zero = fig11_with_inductance("0.0");
    let tiny = fig11_with_inductance("1e-9");
    assert_eq!(zero.model.rings[0].circuit.branches[0].inductance, 0.0);
    let (fz, ft) = (floquet_system(&zero), floquet_system(&tiny));
    println!("L = 0 basis: {:?}", fz.reduced.frequencies);
    assert!(
        fz.reduced.frequencies.iter().all(|w| w.is_finite() && !(850.0..910.0).contains(w)),
        "an r mode in the basis"
    );
    for (a, b) in fz.reduced.frequencies.iter().zip(&ft.reduced.frequencies) {
        assert!(rel(*a, *b) < 1e-6, "basis {a} vs {b}");
    }
    for (phi, beta) in [(704.0, 0.25), (1500.0, 0.1), (3300.0, 0.5)] {
        let (pz, pt) = (fz.point(phi, beta), ft.point(phi, beta));
        assert_sound(&pz, "L = 0");
        println!(
            "L = 0 at ({phi}, {beta}): ln max|mu| = {:.9} (L = 1e-9: {:.9})",
            pz.summary.ln_max_multiplier, pt.summary.ln_max_multiplier
        );
        assert!((pz.summary.ln_max_multiplier - pt.summary.ln_max_multiplier).abs() < 1e-6);
        assert_eq!(pz.summary.stable, pt.summary.stable);
    }
}

#[test]
fn zero_resistance_keeps_the_monodromy_volume_preserving() {
    // R = 0 and η = 0: no dissipation, D̃ = −jΩG̃ has a purely imaginary trace, so by
    // Liouville |det Φ(T)| = ∏|μ| = 1 at every (φ, β); at β = 0 all |μ| = 1 (stable).
    let p = load("fig11-closed-2000.toml", &["circuit.branches[0].resistance=0", "circuit.branches[1].resistance=0"]);
    let fs = floquet_system(&p);
    let flat = fs.point(1234.5, 0.0);
    assert_sound(&flat, "beta = 0");
    assert!((flat.summary.max_multiplier - 1.0).abs() < 1e-9, "{:?}", flat.summary);
    assert!(flat.summary.stable);
    for (phi, beta) in [(704.0, 0.25), (1290.0, 0.3), (3000.0, 0.8)] {
        let pt = fs.point(phi, beta);
        assert_sound(&pt, "R = 0");
        println!(
            "R = 0 at ({phi}, {beta}): ln|det| = {:.3e}, ln max|mu| = {:.6}",
            ln_abs_det(&pt),
            pt.summary.ln_max_multiplier
        );
        assert!(ln_abs_det(&pt).abs() < 1e-8, "ln|det Φ| = {}", ln_abs_det(&pt));
    }
}

#[test]
fn huge_resistance_acts_as_an_open_circuit() {
    // R = 1e9 Ω: the branch time constant R·C ≥ 1e9·1e-7 = 100 s is ≫ 1/ω, the charges
    // cannot move, and the stacks behave as on open circuit: whirls shift by O(1/(ωRC))
    // ≤ 1/(300·100) ≈ 3e-5.
    let huge =
        load("fig11-closed-2000.toml", &["circuit.branches[0].resistance=1e9", "circuit.branches[1].resistance=1e9"]);
    let open = load("fig11-closed-2000.toml", &["circuit.state=open"]);
    let (h, o) = (forward(&huge.model, &huge, 2000.0, 4), forward(&open.model, &open, 2000.0, 4));
    println!("R = 1e9: {h:?}\nopen:    {o:?}");
    assert_eq!(h.len(), 4);
    for (a, b) in h.iter().zip(&o) {
        assert!(rel(*a, *b) < 1e-4, "{a} vs {b}");
    }
    // Table 2 (open circuit, Ω = 2000): 399.0, 1903.5, 4899.6, 6854.3 rad/s, to 0.1 %.
    for (a, b) in h.iter().zip([399.0, 1903.5, 4899.6, 6854.3]) {
        assert!(rel(*a, b) < 1e-3, "{a} vs Table 2 {b}");
    }
}

#[test]
fn speed_zero_has_equal_forward_and_backward_whirls() {
    // Ω = 0: no gyroscopic coupling, the isotropic rotor's forward and backward whirls
    // coincide, at Table 2's ω_n; the Floquet system is sound.
    let p = load("paper-open.toml", &["speed=0"]);
    let r = whirl_modes(&p.model, &p.settings, 0.0).unwrap();
    let f: Vec<f64> = r.forward().map(|m| m.frequency).take(4).collect();
    let b: Vec<f64> = r.backward().map(|m| m.frequency).take(4).collect();
    println!("speed 0: forward {f:?} backward {b:?}");
    for ((wf, wb), table) in f.iter().zip(&b).zip([350.5, 1817.1, 3723.4, 6277.1]) {
        assert!(rel(*wf, *wb) < 1e-9, "{wf} vs {wb}");
        assert!(rel(*wf, table) < 1e-3, "{wf} vs Table 2 {table}");
    }
    let fs = floquet_system(&load("fig8-eta0.toml", &[]));
    assert_eq!(fs.speed, 0.0);
    let (wf, wb) = fs.whirls().unwrap();
    for (a, b) in wf.iter().zip(&wb) {
        assert!(rel(*a, *b) < 1e-9, "reduced whirls {a} vs {b}");
    }
    assert_sound(&fs.point(701.0, 0.1), "speed 0");
}

#[test]
fn very_high_speed_is_finite_or_flagged() {
    // Ω = 1e5 rad/s (50× the paper's): the gyroscopic stiffening is large but the model is
    // linear, so every result is finite; a point may be flagged inaccurate but never NaN.
    let p = load("fig9-open-2000.toml", &["speed=1e5"]);
    let r = whirl_modes(&p.model, &p.settings, 1e5).unwrap();
    assert!(r.modes.iter().all(|m| m.frequency.is_finite() && m.damping_ratio.is_finite()));
    let f1 = r.forward().next().unwrap().frequency;
    let b1 = r.backward().next().unwrap().frequency;
    println!("speed 1e5: f1 = {f1}, b1 = {b1}");
    // Gyroscopic splitting: forward above, backward below the Ω = 2000 values (399.0, 300.2).
    assert!(f1 > 399.0 && b1 < 300.2, "f1 {f1} b1 {b1}");
    let fs = floquet_system(&p);
    for (phi, beta) in [(f1 + b1, 0.1), (1000.0, 0.5)] {
        let pt = fs.point(phi, beta);
        println!("speed 1e5 at ({phi}, {beta}): {:?}", pt.summary);
        assert!(pt.summary.status != PointStatus::Failed, "{:?}", pt.summary);
        assert!(pt.summary.ln_max_multiplier.is_finite(), "{:?}", pt.summary);
        // Undamped: |det Φ| = 1 (Liouville) whatever the speed.
        assert!(ln_abs_det(&pt).abs() < 1e-6, "ln|det Φ| = {}", ln_abs_det(&pt));
    }
}

#[test]
fn alpha_near_one_sends_the_lowest_frequency_to_zero() {
    // Ω = 0, open circuit, P_cr of the same supports: ω_1²(α) is the smallest eigenvalue of
    // K − αP_cr·S against M, concave in α and zero at α = 1. Hence the closed-form bounds
    // ω_1(α) ≥ √(1 − α)·ω_1(0), and near α = 1 ω_1² ∝ (1 − α): ω(0.999)/ω(0.99) → √0.1.
    let w = |alpha: f64| {
        let p = load("paper-open.toml", &["speed=0", &format!("load.alpha={alpha}")]);
        forward(&p.model, &p, 0.0, 1)[0]
    };
    let (w0, w99, w999) = (w(0.0), w(0.99), w(0.999));
    println!("alpha 0: {w0}, 0.99: {w99}, 0.999: {w999}, ratio {}", w999 / w99);
    assert!(w999 > 0.0 && w999 >= (0.001f64).sqrt() * w0 * (1.0 - 1e-9), "{w999}");
    assert!(w999 < 0.05 * w0, "{w999} vs {w0}");
    assert!(rel(w999 / w99, 0.1f64.sqrt()) < 0.01, "ratio {}", w999 / w99);
    // Floquet at α = 0.999 (undamped, Ω = 0): the reduced whirls are Ritz values of the same
    // pencil on nested subspaces, so the lowest is ≥ the full model's and falls
    // monotonically with M towards it. The paper's M = 4 is far off this close to
    // buckling (83 rad/s against 16 rad/s); M = 100 is within 1e-3.
    let reduced = |m: usize| {
        let p = load("fig8-eta0.toml", &["load.alpha=0.999", &format!("analysis.reduced_modes={m}")]);
        floquet_system(&p).whirls().unwrap().0[0]
    };
    let mut last = f64::INFINITY;
    for m in [4, 8, 16, 32, 64, 100] {
        let w = reduced(m);
        println!("alpha 0.999, M = {m}: lowest reduced whirl {w}");
        assert!(w >= w999 * (1.0 - 1e-9) && w <= last * (1.0 + 1e-9), "M = {m}: {w} (full {w999}, M before {last})");
        last = w;
    }
    assert!(rel(last, w999) < 1e-3, "M = 100: {last} vs full {w999}");
    let fs = floquet_system(&load("fig8-eta0.toml", &["load.alpha=0.999"]));
    let pt = fs.point(700.0, 0.0005);
    assert_sound(&pt, "alpha 0.999");
}

#[test]
fn alpha_at_or_above_one_is_a_typed_error() {
    // α ≥ 1: the static load alone buckles the shaft. The file layer refuses it at
    // `load.alpha`; the analysis layer refuses a model built without the file layer.
    for alpha in ["1", "1.0", "1.5", "1e300"] {
        let e = Problem::from_path(problem_path("paper-open.toml"), &[format!("load.alpha={alpha}")]).unwrap_err();
        assert_eq!(e.key, "load.alpha", "{e}");
        assert_eq!(e.location, Location::Override, "{e}");
        assert!(matches!(e.kind, ProblemErrorKind::OutOfRange { value, .. } if value == alpha.parse::<f64>().unwrap()));
        assert!(e.to_string().contains("alpha >= 1 means the static load alone buckles the shaft"), "{e}");
    }
    let mut model = load("paper-open.toml", &[]).model;
    model.load.alpha = 1.0;
    match Rotor::new(&model) {
        Err(AnalysisError::StaticLoadBuckles { alpha, critical_load }) => {
            assert_eq!(alpha, 1.0);
            assert!(rel(critical_load, model.shaft.euler_load()) < 1e-4);
        }
        other => panic!("expected StaticLoadBuckles, got {other:?}"),
    }
}

#[test]
fn huge_beta_gives_an_exact_logarithm_beyond_1e300() {
    // β = 400 at φ = 100 rad/s: the load swings to 400·P_cr and the shaft grows by far more
    // than 1e300 in one period. ln max|μ| must be finite and exact (checked against an
    // independent RK4 integration with the same log scaling), max|μ| saturated at f64::MAX
    // beyond e^709, nothing NaN.
    let p = load("fig9-open-2000.toml", &[]);
    let fs = floquet_system(&p);
    let (phi, beta) = (100.0, 400.0);
    let start = Instant::now();
    let pt = fs.point(phi, beta);
    println!("beta {beta}: {:?} in {:?}", pt.summary, start.elapsed());
    let s = pt.summary;
    assert!(s.ln_max_multiplier > (1e300f64).ln(), "ln max|mu| = {}", s.ln_max_multiplier);
    assert!(!s.stable && s.ln_max_multiplier.is_finite() && s.growth_rate.is_finite());
    if s.ln_max_multiplier > 709.0 {
        assert_eq!(s.max_multiplier, f64::MAX);
    }
    assert!(pt.multipliers.iter().flatten().all(|x| x.is_finite()));
    let rk = dstm::monodromy_rk4(&fs.system, phi, beta, 200_000);
    let rk_point = FloquetPoint::from_monodromy(
        phi,
        beta,
        &rk,
        rotorshunt::analysis::criterion::Threshold::Multiplier { tolerance: 1.0001 },
        PointStatus::Ok,
    );
    println!("rk4: {:?}", rk_point.summary);
    assert!(rel(s.ln_max_multiplier, rk_point.summary.ln_max_multiplier) < 1e-6);
}

#[test]
fn reduced_modes_above_the_dof_count_is_a_typed_error() {
    // 8 elements, closed with 2 branches: 2·9 shaft + 2 ring + 2·2 charge DOFs = 24, all
    // with mass (L > 0), so 24 finite modes: M = 24 works and M = 25 is refused.
    let base = ["shaft.elements=8", "disks[0].node=2"];
    let with = |m: usize| load("fig11-closed-2000.toml", &[base[0], base[1], &format!("analysis.reduced_modes={m}")]);
    let p = with(24);
    assert_eq!(SystemMatrices::assemble(&p.model).size(), 24);
    let rotor = Rotor::new(&p.model).unwrap();
    assert_eq!(FloquetSystem::new(&rotor, &p.settings, 2000.0).unwrap().reduced.size(), 24);
    let p = with(25);
    let e = FloquetSystem::new(&rotor, &p.settings, 2000.0).unwrap_err();
    assert_eq!(e, AnalysisError::ReducedModes { requested: 25, available: 24 });
    assert!(e.to_string().contains("analysis.reduced_modes must be between 1 and 24"), "{e}");
    // Above the file layer's own bound: refused with the key and the override.
    let e =
        Problem::from_path(problem_path("fig11-closed-2000.toml"), &["analysis.reduced_modes=201".into()]).unwrap_err();
    assert_eq!(e.key, "analysis.reduced_modes", "{e}");
    // Through the CLI: exit status 1 (analysis failure), the key named.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_rotorshunt"))
        .args(["floquet", &problem_path("fig11-closed-2000.toml"), "--phi", "700", "--beta", "0.1"])
        .args(["--set", base[0], "--set", base[1], "--set", "analysis.reduced_modes=25"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("analysis.reduced_modes") && !stderr.contains("panicked"), "{stderr}");
}

/// Buckling load of the problem's shaft with `n` elements (disk at node 0).
fn buckling_with(n: usize) -> (f64, Model) {
    let p = load("paper-open.toml", &[&format!("shaft.elements={n}"), "disks[0].node=0"]);
    let rotor = Rotor::new(&p.model).unwrap();
    (buckling_load(&rotor.system).unwrap(), p.model)
}

#[test]
fn one_element_buckles_at_12_ei_over_l_squared() {
    // One Hermite element: the symmetric mode (end slopes θ, −θ) is decoupled from the end
    // deflections (K and S coupling terms 6L(θ1+θ2), 3L(θ1+θ2) vanish), so the springs do
    // not enter and the Rayleigh quotient is (4EI/L)/(L/3) = 12EI/L² exactly.
    let (p, model) = buckling_with(1);
    let ei = model.shaft.sections[0].bending_stiffness();
    let l = model.shaft.length();
    println!("1 element: P = {p}, 12EI/L² = {}", 12.0 * ei / (l * l));
    assert!(rel(p, 12.0 * ei / (l * l)) < 1e-9);
    // The modes and Floquet still work (4 DOFs of shaft + 2 ring = 6 finite modes, M = 4).
    let p = load("fig9-open-2000.toml", &["shaft.elements=1", "disks[0].node=1"]);
    let fs = floquet_system(&p);
    assert_sound(&fs.point(700.0, 0.1), "1 element");
}

#[test]
fn two_elements_buckle_at_the_two_element_closed_form() {
    // Two Hermite elements of length a = L/2, pinned ends: the symmetric mode has DOFs
    // (θ0, w1); with EI = a = 1, K = [[4, −6], [−6, 12]], S = [[4, −3], [−3, 36]]/30 and
    // det(K − pS) = 0 gives 135q² − 156q + 12 = 0, q = p/30: P = 4p·EI/L² ≈ 9.944 EI/L².
    // The end springs (k_eq ≈ 2.6e7 N/m ≈ 1e3·EI/L³) move it by far less than 1e-4.
    let q = (156.0 - (156.0f64 * 156.0 - 4.0 * 135.0 * 12.0).sqrt()) / 270.0;
    let closed = 4.0 * 30.0 * q;
    let (p, model) = buckling_with(2);
    let ei = model.shaft.sections[0].bending_stiffness();
    let l = model.shaft.length();
    println!("2 elements: P = {p}, closed form {} ({}·EI/L²)", closed * ei / (l * l), closed);
    assert!(rel(p, closed * ei / (l * l)) < 1e-4);
}

#[test]
fn four_hundred_elements_buckle_at_the_euler_load() {
    // The sine is an exact buckling mode of the spring-supported beam (zero end deflection,
    // moment and shear at P = π²EI/L²), and Hermite cubics converge as h⁴: at 400 elements
    // the FE error is ~1e-10; what remains is round-off of the eigenproblem, whose K spans
    // 12EI/h³ ≈ 2e12 N/m down to the springs: ε·(L/h)⁴ ≈ 6e-6 bounds it (measured 4e-8).
    // Timed: assembly and buckling, then Floquet setup and one point.
    let start = Instant::now();
    let (p, model) = buckling_with(400);
    let t_buckling = start.elapsed();
    let euler = model.shaft.euler_load();
    println!("400 elements: P = {p}, pi²EI/L² = {euler}, rel {:e}, buckling {t_buckling:?}", rel(p, euler));
    assert!(rel(p, euler) < 1e-6);
    let start = Instant::now();
    let q = load("fig9-open-2000.toml", &["shaft.elements=400", "disks[0].node=100"]);
    let fs = floquet_system(&q);
    let pt = fs.point(704.0, 0.25);
    println!("400 elements: Floquet setup and one point in {:?}: {:?}", start.elapsed(), pt.summary);
    assert_sound(&pt, "400 elements");
    // Fig. 9/10: (704, 0.25) is unstable (the ω_f1 + ω_b1 region).
    assert!(!pt.summary.stable);
}

#[test]
fn disk_at_a_bearing_node_is_mirror_symmetric() {
    // The rings are identical at both ends, so a disk at node 0 and at the last node are
    // mirror images (x → L − x flips every slope, and M, K, S, G are quadratic in them):
    // identical whirls and multipliers. The disk's mass adds to the bearing mass; the
    // buckling load does not depend on masses: π²EI/L².
    let left = load("fig9-open-2000.toml", &["disks[0].node=0"]);
    let right = load("fig9-open-2000.toml", &["disks[0].node=64"]);
    let (l, r) = (forward(&left.model, &left, 2000.0, 6), forward(&right.model, &right, 2000.0, 6));
    println!("disk at node 0: {l:?}\ndisk at node 64: {r:?}");
    // Two separate eigen-solutions: agreement to the solver's accuracy (~1e-10 measured).
    for (a, b) in l.iter().zip(&r) {
        assert!(rel(*a, *b) < 1e-8, "{a} vs {b}");
    }
    let rotor = Rotor::new(&left.model).unwrap();
    assert!(rel(rotor.critical_load, left.model.shaft.euler_load()) < 1e-6);
    let (fl, fr) = (floquet_system(&left), floquet_system(&right));
    for (phi, beta) in [(500.0, 0.3), (2000.0, 0.6)] {
        let (a, b) = (fl.point(phi, beta), fr.point(phi, beta));
        assert_sound(&a, "disk at node 0");
        assert!((a.summary.ln_max_multiplier - b.summary.ln_max_multiplier).abs() < 1e-9, "{a:?} vs {b:?}");
    }
}
