//! Time response (Eq. 29, Fig. 10): a point inside a region diverges at the Floquet growth
//! rate, a point outside stays bounded. The RK4 time integration is independent of the
//! monodromy paths, so the agreement of growth rates checks both.

use crate::common;
use common::load;
use rotorshunt::analysis::floquet::FloquetSystem;
use rotorshunt::analysis::response::response;
use rotorshunt::analysis::Rotor;

fn system(name: &str) -> FloquetSystem {
    let p = load(name, &[]);
    FloquetSystem::new(&Rotor::new(&p.model).unwrap(), &p.settings, p.model.speed).unwrap()
}

#[test]
fn inside_diverges_at_the_floquet_rate_outside_stays_bounded() {
    let fs = system("fig9-open-2000.toml");
    let periods = 40;
    // Inside the ω_f1 + ω_b1 region (≈ 704 rad/s) at β = 0.25, as Γ2/Γ3 of Fig. 10.
    let inside = fs.point(704.0, 0.25);
    assert!(!inside.summary.stable);
    let r = response(&fs, 704.0, 0.25, periods);
    assert!(r.growth_ratio() > 1e4, "ratio {}", r.growth_ratio());
    // Per-period growth of the response vs ln max|μ|: the forced (unbalance) part and the
    // transient of the other multipliers blur it by a few per cent over 40 periods.
    let per_period = r.growth_ratio().ln() / (periods - 1) as f64;
    assert!(
        (per_period / inside.summary.ln_max_multiplier - 1.0).abs() < 0.05,
        "{per_period} vs {}",
        inside.summary.ln_max_multiplier
    );
    // Outside (1000 rad/s, Γ1/Γ4): stable and bounded.
    let outside = fs.point(1000.0, 0.25);
    assert!(outside.summary.stable);
    let r = response(&fs, 1000.0, 0.25, periods);
    assert!(r.growth_ratio() < 5.0, "ratio {}", r.growth_ratio());
    assert!(r.q1.iter().all(|q| q[0].is_finite() && q[1].is_finite()));
}
