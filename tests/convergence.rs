//! Convergence of the default step count: on every point of the Fig. 11 grid
//! (φ = 100:14000:25, β = 0:1:0.025, 22 837 points) max|μ| at the default step rule
//! (32 CFM4 steps per period, more where h·ω_min would exceed 0.1 rad) is within 1e-5 of a
//! 4× finer computation (both limits divided by 4). The difference is
//! measured as |Δ max|μ|| / max(1, max|μ|): absolute at the stability limit, relative for
//! strongly unstable points whose max|μ| is large.

use crate::common;
use common::load;
use rotorshunt::analysis::chart::chart;
use rotorshunt::analysis::floquet::FloquetSystem;
use rotorshunt::analysis::Interval;
use rotorshunt::analysis::Rotor;

const CONVERGENCE: f64 = 1e-5;

#[test]
fn default_steps_are_converged_on_the_fig11_grid() {
    let p = load("fig11-closed-2000.toml", &[]);
    let rotor = Rotor::new(&p.model).unwrap();
    let coarse = FloquetSystem::new(&rotor, &p.settings, p.model.speed).unwrap();
    let mut fine_settings = p.settings.clone();
    fine_settings.steps_per_period *= 4;
    fine_settings.max_step_phase /= 4.0;
    let fine = FloquetSystem::new(&rotor, &fine_settings, p.model.speed).unwrap();
    let phis = Interval::new(100.0, 14000.0).stepped(25.0, 1000).unwrap();
    let betas = Interval::new(0.0, 1.0).stepped(0.025, 1000).unwrap();
    let a = chart(&coarse, &phis, &betas, &|| {});
    let b = chart(&fine, &phis, &betas, &|| {});
    assert_eq!(a.points.len(), 22_837);
    let mut worst = (0.0f64, 0.0, 0.0);
    let mut verdicts = 0;
    for (x, y) in a.points.iter().zip(&b.points) {
        let d = (x.max_multiplier - y.max_multiplier).abs() / x.max_multiplier.max(y.max_multiplier).max(1.0);
        if d > worst.0 {
            worst = (d, x.phi, x.beta);
        }
        verdicts += usize::from(x.stable != y.stable);
    }
    eprintln!("worst difference {:.2e} at φ = {}, β = {}; {verdicts} verdicts differ", worst.0, worst.1, worst.2);
    assert!(worst.0 < CONVERGENCE, "worst difference {:.2e} at φ = {}, β = {}", worst.0, worst.1, worst.2);
    assert_eq!(a.failed + b.failed, 0);
}
