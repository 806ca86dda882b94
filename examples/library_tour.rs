//! The library from end to end, as docs/library.md ("Using the library") shows it:
//! load a problem → whirls → a stability chart → the catalogue of regions → the stable
//! band around an operating frequency → a shunt design.
//!
//!     cargo run --release --example library_tour
//!
//! Units: SI, frequencies in rad/s.

use rotorshunt::analysis::unbalance;
use rotorshunt::design::{run_with, Observation, RunOptions};
use rotorshunt::{BandRequest, CatalogueRequest, ChartRequest, Interval, Problem};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // 1. Load: the paper's rotor with the closed two-branch shunt at Ω = 2000 rad/s.
    let problem = Problem::from_path("problems/fig11-closed-2000.toml", &[])?;
    let op = problem.operating_point()?;
    let rotor = &op.modes;
    println!("P_cr = {:.4e} N; whirls at Ω = {} rad/s:", rotor.critical_load, op.speed);
    for m in rotor.modes.iter().take(8) {
        println!("  {:>4}  {:8.1} rad/s  ζ = {:.2e}", m.tag(), m.frequency, m.damping_ratio);
    }

    // 2. A stability chart around ω_b1 + ω_r (Fig. 11): 1 rad/s × 0.05.
    let grid =
        ChartRequest::grid().phi(Interval::new(1150.0, 1250.0)).phi_step(1.0).beta_max(0.5).beta_step(0.05).build()?;
    let chart = op.chart(&grid);
    println!("chart: {} of {} points unstable", chart.unstable(), chart.points.len());

    // 3. The catalogue of regions in 1000–1400 rad/s up to β = 1, edges at β = 0.3.
    let request = CatalogueRequest::builder().range(Interval::new(1000.0, 1400.0)).beta_max(1.0).level(0.3);
    let cat = op.catalogue(&request.build()?)?;
    for r in cat.regions.iter().filter(|r| r.order == 1) {
        println!("  region {:>8}: starts at {:7.1} rad/s, onset β = {:.4}", r.label, r.start, r.onset_beta);
    }

    // 4. The stable band around φ_op = 1230 rad/s at β_op = 0.3.
    let band =
        op.band(&BandRequest::builder().range(Interval::new(100.0, 8000.0)).phi_op(1230.0).level(0.3).build()?)?;
    match band.band {
        Some(b) => println!("stable band around 1230 rad/s: [{:.2}, {:.2}] rad/s", b.lo, b.hi),
        None => println!("1230 rad/s is unstable at β = 0.3"),
    }

    // 5. The unbalance response at the disk (node 16) over 200–600 rad/s, 1 rad/s apart:
    //    its peak, at the first forward critical speed (unbounded: this rotor is undamped).
    let rotor = problem.rotor()?;
    let disk = unbalance::node_probe(&rotor.system.dofs, 16)?;
    let speeds: Vec<f64> = (200..=600).map(f64::from).collect();
    let response = unbalance::unbalance_response(&rotor, &speeds, &[disk], &rotorshunt::progress::Silent)?;
    match response.probes[0].largest(&speeds) {
        (speed, _, true) => println!("unbalance at node 16: unbounded at {speed:.1} rad/s"),
        (speed, amplitude, false) => println!("unbalance at node 16: largest {amplitude:.3e} m at {speed:.1} rad/s"),
    }

    // 6. A design: widen that band by tuning branch 1 (two starts of ten iterations, set
    //    as typed values on the file's spec, to keep the tour short; the run checks them),
    //    with an observer that counts the evaluations as they are made.
    let design = Problem::from_path("problems/design-widest-band.toml", &[])?;
    let mut spec = design.design.clone().ok_or("the file has a [design] table")?;
    spec.starts = 2;
    spec.max_iterations = 10;
    spec.refined_check = false; // a full run re-judges its answer on twice the basis
    let evaluations = Arc::new(AtomicUsize::new(0));
    let counter = Arc::clone(&evaluations);
    let observer = move |_: &Observation<'_>| {
        counter.fetch_add(1, Ordering::Relaxed);
    };
    let options = RunOptions { observer: Some(Arc::new(observer)), ..RunOptions::default() };
    let outcome = run_with(&design.machine(), &spec, &options, &rotorshunt::progress::Silent)?;
    let (before, after) = (&outcome.before_bands()[0].band, &outcome.after_bands()[0].band);
    println!(
        "design {:?} (verified: {}): band width {:.1} → {:.1} rad/s with {:?}, {} evaluations watched",
        outcome.status,
        outcome.verified(),
        before.signed_width(),
        after.signed_width(),
        outcome.after,
        evaluations.load(Ordering::Relaxed)
    );
    Ok(())
}
