//! Two-path agreement of the Floquet multipliers (issue acceptance):
//! β = 0 against exp(λT); fast CFM4 against the reference DSTM at a fine step count and
//! against an independent RK4 integration; parallel chart = sequential chart; a
//! closed-form Mathieu boundary through the same monodromy code.

use crate::common;
use common::load;
use faer::{c64, Mat};
use rotorshunt::analysis::chart::chart;
use rotorshunt::analysis::floquet::fast::{PhiTable, Symmetry};
use rotorshunt::analysis::floquet::{dstm, FloquetPoint, FloquetSystem, PointStatus, ScaledProduct};
use rotorshunt::analysis::reduction::PeriodicSystem;
use rotorshunt::analysis::Rotor;

/// Problems of the catalogue with Floquet settings (Figs. 8, 9, 11, 13).
const PROBLEMS: [&str; 7] = [
    "fig8-eta0.toml",
    "fig8-eta200.toml",
    "fig8-eta4000.toml",
    "fig9-open-2000.toml",
    "fig11-closed-2000.toml",
    "fig13-r10.toml",
    "fig13-r50.toml",
];

fn system(name: &str) -> FloquetSystem {
    let p = load(name, &[]);
    let rotor = Rotor::new(&p.model).unwrap();
    FloquetSystem::new(&rotor, &p.settings, p.model.speed).unwrap()
}

fn ln_max(p: &ScaledProduct) -> f64 {
    p.matrix.eigenvalues().unwrap().iter().map(|z| z.norm()).fold(0.0, f64::max).ln() + p.log_scale
}

/// |Δ max|μ|| / max(1, max|μ|): absolute near the stability limit, relative when large.
fn mu_diff(a: f64, b: f64) -> f64 {
    (a.exp() - b.exp()).abs() / a.exp().max(b.exp()).max(1.0)
}

#[test]
fn unloaded_multipliers_are_exponentials_of_the_eigenvalues() {
    // β = 0: B is constant, Φ(T) = exp(B0·T) exactly, so μ_i = exp(λ_i T) to round-off.
    for name in ["fig8-eta200.toml", "fig11-closed-2000.toml"] {
        let fs = system(name);
        let lambdas = fs.eigenvalues().unwrap();
        for phi in [350.0, 1234.5, 7000.0] {
            let t = 2.0 * std::f64::consts::PI / phi;
            let expected: Vec<c64> = lambdas.iter().map(|l| (l * t).exp()).collect();
            for (path, point) in
                [("fast", fs.point_fast(&fs.table(phi, 0.0), 0.0)), ("dstm", fs.point_dstm(phi, 0.0, 64))]
            {
                assert_eq!(point.multipliers.len(), expected.len());
                for m in &point.multipliers {
                    let m = c64::new(m[0], m[1]);
                    let best = expected.iter().map(|e| (e - m).norm()).fold(f64::MAX, f64::min);
                    assert!(best < 1e-10, "{name} {path} φ={phi}: multiplier {m} is {best:e} from every exp(λT)");
                }
            }
        }
    }
}

#[test]
fn fast_agrees_with_reference_dstm_and_rk4() {
    // The fast path (32 CFM4 steps) against the DSTM at 4096 steps (second order: ~1e-8)
    // and RK4 with h·ω_max ≤ 0.02 (~1e-9): all three within 1e-6 in max|μ|.
    const AGREEMENT: f64 = 1e-6;
    let points = [(700.0, 0.3), (1180.0, 0.6), (2700.0, 0.9), (5200.0, 0.5), (9000.0, 1.0)];
    let mut worst: f64 = 0.0;
    for name in PROBLEMS {
        let fs = system(name);
        let w_max = fs.reduced.frequencies.iter().fold(0.0f64, |a, b| a.max(*b)) + fs.speed;
        for (phi, beta) in points {
            let fast = fs.point_fast(&fs.table(phi, beta), beta);
            assert_eq!(fast.summary.status, PointStatus::Ok);
            let reference = ln_max(&dstm::monodromy_dstm(&fs.system, phi, beta, 4096));
            let period = 2.0 * std::f64::consts::PI / phi;
            let rk_steps = ((w_max * period / 0.02).ceil() as usize).max(2000);
            let rk = ln_max(&dstm::monodromy_rk4(&fs.system, phi, beta, rk_steps));
            let (d1, d2, d3) = (
                mu_diff(fast.summary.ln_max_multiplier, reference),
                mu_diff(fast.summary.ln_max_multiplier, rk),
                mu_diff(reference, rk),
            );
            worst = worst.max(d1).max(d2);
            assert!(
                d1 < AGREEMENT && d2 < AGREEMENT && d3 < AGREEMENT,
                "{name} φ={phi} β={beta}: fast {} dstm {} rk4 {}",
                fast.summary.max_multiplier,
                reference.exp(),
                rk.exp()
            );
        }
    }
    eprintln!("worst fast-path disagreement: {worst:.2e}");
}

#[test]
fn chebyshev_and_half_period_tricks_equal_the_straightforward_cfm4() {
    // The fast path changes how CFM4's exponentials are computed (one Chebyshev
    // interpolant per φ) and how the period is closed (X⁻¹·Lᵀ·X·L); the straightforward
    // CFM4 (one expm per exponential, full period stepped) must give the same max|μ| to
    // round-off: both are the same integrator with the same steps.
    let fs = system("fig11-closed-2000.toml");
    for (phi, beta) in [(700.0, 0.3), (1180.0, 0.6), (5200.0, 1.0)] {
        let table = fs.table(phi, beta);
        let fast = ln_max(&table.monodromy(&fs.symmetry, beta));
        let direct =
            ln_max(&rotorshunt::analysis::floquet::fast::monodromy_cfm4_direct(&fs.system, phi, beta, table.steps));
        assert!(mu_diff(fast, direct) < 1e-9, "φ={phi} β={beta}: {} vs {}", fast.exp(), direct.exp());
    }
}

#[test]
fn parallel_chart_equals_sequential_chart() {
    let fs = system("fig11-closed-2000.toml");
    let phis: Vec<f64> = (0..40).map(|i| 600.0 + 37.5 * i as f64).collect();
    let betas: Vec<f64> = (0..6).map(|i| 0.2 * i as f64).collect();
    let par = chart(&fs, &phis, &betas, &|| {});
    let seq =
        rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap().install(|| chart(&fs, &phis, &betas, &|| {}));
    assert_eq!(par, seq);
    assert!(par.unstable() > 0 && par.unstable() < par.points.len());
}

#[test]
fn no_chart_point_is_nan_even_far_beyond_the_paper_loads() {
    let fs = system("fig11-closed-2000.toml");
    let c = chart(&fs, &[150.0, 700.0, 1800.0, 4000.0], &[0.0, 1.0, 3.0, 10.0], &|| {});
    for p in &c.points {
        assert!(p.max_multiplier.is_finite() && p.ln_max_multiplier.is_finite() && p.growth_rate.is_finite(), "{p:?}");
        assert_ne!(p.status, PointStatus::Failed, "{p:?}");
    }
}

/// x″ + (δ + ε cos t)·x = 0 as y = [ẋ; x]: B0 = [0, −δ; 1, 0], B1 = [0, −1; 0, 0], β = ε.
fn mathieu_unstable(delta: f64, eps: f64) -> bool {
    let z = c64::new(0.0, 0.0);
    let b0 = Mat::from_fn(2, 2, |i, j| match (i, j) {
        (0, 1) => c64::new(-delta, 0.0),
        (1, 0) => c64::new(1.0, 0.0),
        _ => z,
    });
    let b1 = Mat::from_fn(2, 2, |i, j| if (i, j) == (0, 1) { c64::new(-1.0, 0.0) } else { z });
    let sys = PeriodicSystem { b0, b1 };
    let table = PhiTable::new(&sys, 1.0, eps, 32, false);
    let mono = table.monodromy(&Symmetry::new(&sys), eps);
    // Undamped: stable multipliers lie on the unit circle to round-off (~1e-13).
    let p = FloquetPoint::from_monodromy(
        1.0,
        eps,
        &mono,
        rotorshunt::analysis::criterion::Threshold::Multiplier { tolerance: 1.0 + 1e-9 },
        PointStatus::Ok,
    );
    !p.summary.stable
}

fn bisect(mut stable: f64, mut unstable: f64, eps: f64) -> f64 {
    while (stable - unstable).abs() > 1e-10 {
        let mid = 0.5 * (stable + unstable);
        if mathieu_unstable(mid, eps) {
            unstable = mid;
        } else {
            stable = mid;
        }
    }
    0.5 * (stable + unstable)
}

#[test]
fn mathieu_first_tongue_boundaries() {
    // Closed form (Mathieu characteristic values a₁, b₁ at q = ε/2 … in this scaling the
    // tongue from δ = 1/4 at ε = 0.5 spans δ ∈ (−0.0275622042, 0.4647770181)).
    let lower = bisect(-0.08, 0.1, 0.5);
    let upper = bisect(0.6, 0.3, 0.5);
    eprintln!("Mathieu ε = 0.5: δ boundaries {lower:.10} and {upper:.10}");
    assert!((lower - -0.0275622042).abs() < 1e-6, "lower {lower}");
    assert!((upper - 0.4647770181).abs() < 1e-6, "upper {upper}");
}
