//! `Progress::cancelled`: a chart, a region catalogue and an unbalance response asked to
//! stop skip the steps not begun (an incomplete result, for the caller to discard), a
//! design ends with `DesignError::Stopped` (also when its allowance of evaluations is
//! spent, `Progress::evaluated`), and a progress that never asks changes nothing (the
//! Python bindings' Ctrl-C, docs/python.md).

use rotorshunt::analysis::chart::chart;
use rotorshunt::analysis::regions::catalogue_with;
use rotorshunt::progress::{Progress, Silent};
use rotorshunt::{CatalogueRequest, Interval, Problem};
use std::sync::atomic::{AtomicU64, Ordering};

/// Asks to stop once `after` steps are done.
struct StopAfter {
    done: AtomicU64,
    after: u64,
}

impl Progress for StopAfter {
    fn advance(&self, steps: u64) {
        self.done.fetch_add(steps, Ordering::Relaxed);
    }
    fn cancelled(&self) -> bool {
        self.done.load(Ordering::Relaxed) >= self.after
    }
}

fn stop_after(after: u64) -> StopAfter {
    StopAfter { done: AtomicU64::new(0), after }
}

#[test]
fn a_chart_asked_to_stop_skips_the_rows_not_begun() {
    let problem = Problem::from_path("problems/fig11-closed-2000.toml", &[]).unwrap();
    let op = problem.operating_point().unwrap();
    let phis: Vec<f64> = (0..200).map(|k| 1000.0 + 2.0 * f64::from(k)).collect();
    let betas = [0.1, 0.2, 0.3];
    let full = chart(&op.floquet, &phis, &betas, &Silent);
    assert_eq!(full.points.len(), 600);
    // Never asked to stop: the same chart.
    assert_eq!(chart(&op.floquet, &phis, &betas, &stop_after(u64::MAX)), full);
    // Stopped from the start: no row computed; after 10 rows: at most a row per thread more.
    assert!(chart(&op.floquet, &phis, &betas, &stop_after(0)).points.is_empty());
    let part = chart(&op.floquet, &phis, &betas, &stop_after(10)).points.len();
    let threads = rayon::current_num_threads();
    assert!((30..=3 * (10 + threads)).contains(&part), "{part} points");
}

#[test]
fn a_catalogue_asked_to_stop_returns_early() {
    let problem = Problem::from_path("problems/fig11-closed-2000.toml", &[]).unwrap();
    let op = problem.operating_point().unwrap();
    let req =
        CatalogueRequest::builder().range(Interval::new(1000.0, 1400.0)).beta_max(1.0).level(0.3).build().unwrap();
    let full = catalogue_with(&op.floquet, &op.modes, &op.regions, &req, &Silent).unwrap();
    let never = catalogue_with(&op.floquet, &op.modes, &op.regions, &req, &stop_after(u64::MAX)).unwrap();
    assert_eq!(never.regions, full.regions);
    assert!(!full.regions.is_empty());
    let stopped = catalogue_with(&op.floquet, &op.modes, &op.regions, &req, &stop_after(0)).unwrap();
    assert!(stopped.regions.is_empty(), "{} regions", stopped.regions.len());
}

#[test]
fn an_unbalance_response_asked_to_stop_solves_no_more_speeds_and_comes_back_empty() {
    use rotorshunt::analysis::unbalance::{node_probe, unbalance_response};
    let problem = Problem::from_path("problems/fig11-closed-2000.toml", &[]).unwrap();
    let rotor = problem.rotor().unwrap();
    let probe = [node_probe(&rotor.system.dofs, 16).unwrap()];
    let speeds: Vec<f64> = (0..400).map(|k| 200.0 + f64::from(k)).collect();
    let full = unbalance_response(&rotor, &speeds, &probe, &Silent).unwrap();
    assert_eq!((full.speeds.len(), full.probes.len()), (400, 1));
    // No probes asked is not a stop: the speeds are kept.
    assert_eq!(unbalance_response(&rotor, &speeds, &[], &Silent).unwrap().speeds.len(), 400);
    // Never asked: the same response; a step is a speed solved.
    let never = stop_after(u64::MAX);
    assert_eq!(unbalance_response(&rotor, &speeds, &probe, &never).unwrap(), full);
    assert_eq!(never.done.load(Ordering::Relaxed), 400);
    // Asked after 10 speeds: at most a speed per thread more is solved, and the result
    // has no speeds and no probes.
    let progress = stop_after(10);
    let stopped = unbalance_response(&rotor, &speeds, &probe, &progress).unwrap();
    assert!(stopped.speeds.is_empty() && stopped.probes.is_empty());
    let solved = progress.done.load(Ordering::Relaxed);
    assert!((10..=10 + rayon::current_num_threads() as u64).contains(&solved), "{solved} speeds solved");
}

/// The widest-band design cut short: one start of two iterations over 1000–1500 rad/s.
fn short_design() -> Problem {
    let short = ["design.starts=1", "design.max_iterations=2", "design.phi_range=[1000.0, 1500.0]"];
    let o: Vec<String> = short.iter().chain(&crate::common::QUICK_BASIS).map(|s| s.to_string()).collect();
    Problem::from_path("problems/design-widest-band.toml", &o).unwrap()
}

#[test]
fn a_design_asked_to_stop_builds_no_more_candidates_and_says_it_stopped() {
    use rotorshunt::design::{self, DesignError};
    let problem = short_design();
    let spec = problem.design.as_ref().unwrap();
    let machine = problem.machine();
    // Never asked: the same outcome as without a progress.
    let full = design::run(&machine, spec, &Silent).unwrap();
    let never = design::run(&machine, spec, &stop_after(u64::MAX)).unwrap();
    assert_eq!((never.after.clone(), never.candidates), (full.after.clone(), full.candidates));
    assert!(full.candidates > 4, "{} candidates", full.candidates);
    // Asked after 2 candidates (a step of the optimise phase is a candidate built): the
    // run ends with the error, having built at most a candidate per thread more.
    let progress = stop_after(2);
    let e = design::run(&machine, spec, &progress).expect_err("stopped");
    assert!(matches!(e, DesignError::Stopped), "{e}");
    assert_eq!(e.kind(), "Stopped");
    let built = progress.done.load(Ordering::Relaxed);
    assert!(built <= 2 + rayon::current_num_threads() as u64, "{built} candidates built");
}

#[test]
fn a_design_reports_its_evaluations_and_stops_at_its_allowance() {
    use rotorshunt::design::{self, DesignError};
    use rotorshunt::progress::Deadline;
    let problem = short_design();
    let spec = problem.design.as_ref().unwrap();
    let machine = problem.machine();
    // Every candidate's evaluations are reported (the optimiser's count), and the
    // verification's catalogues beside them (its grid points are not region searches).
    let watch = Deadline::new(&Silent, f64::INFINITY);
    let full = design::run(&machine, spec, &watch).unwrap();
    let (optimiser, verification) = (full.floquet_evaluations as u64, full.verification_cost.evaluations as u64);
    let reported = watch.evaluations();
    let catalogues: u64 =
        full.before_speeds.iter().chain(&full.after_speeds).map(|d| d.catalogue.evaluations as u64).sum();
    println!("reported {reported}: optimiser {optimiser}, verification {verification} (catalogues {catalogues})");
    assert!(optimiser > 100 && catalogues > 100, "{optimiser} and {catalogues} evaluations");
    // At least the candidates' and the catalogues' (none missing), at most what the run
    // counted in all (none twice, short of the grid points it never reports).
    assert!(
        (optimiser + catalogues..=optimiser + verification).contains(&reported),
        "{reported} of {optimiser} + {verification}"
    );
    // An allowance of half the optimiser's count stops the run on its own count.
    let half = Deadline::new(&Silent, f64::INFINITY).with_allowance(Some(optimiser / 2));
    let e = design::run(&machine, spec, &half).expect_err("stopped");
    assert!(matches!(e, DesignError::Stopped), "{e}");
    assert!(half.counted_out() && half.evaluations() < optimiser, "{half:?}");
}

#[test]
fn a_time_response_asked_to_stop_ends_its_integration_early() {
    use rotorshunt::analysis::response::{response, response_reporting, response_steps};
    let problem = Problem::from_path("problems/fig11-closed-2000.toml", &[]).unwrap();
    let fs = problem.operating_point().unwrap().floquet;
    let (phi, beta, periods) = (1230.0, 0.3, 20);
    let full = response(&fs, phi, beta, periods);
    // Never asked: the same response, every progress step reported.
    let never = stop_after(u64::MAX);
    assert_eq!(response_reporting(&fs, phi, beta, periods, &never), full);
    assert_eq!(never.done.load(Ordering::Relaxed), response_steps(&fs, phi, periods));
    // Asked after 5 of its progress steps (a twentieth of a period each at most, as the
    // step rule gives ≥ 64 steps a period): the integration ends within a tenth of a
    // period after, with its samples so far.
    let progress = stop_after(5);
    let stopped = response_reporting(&fs, phi, beta, periods, &progress);
    let done = progress.done.load(Ordering::Relaxed);
    let per_period = response_steps(&fs, phi, periods) / periods as u64;
    assert!((5..5 + per_period / 10 + 2).contains(&done), "{done} progress steps of {per_period} a period");
    assert!(stopped.time.len() < full.time.len() / 10, "{} samples of {}", stopped.time.len(), full.time.len());
    assert!(stopped.stopped_at.is_none(), "a stop is not a state that ceased to be finite");
}

#[test]
fn a_min_peak_design_asked_to_stop_judges_no_candidate() {
    use rotorshunt::design::{self, DesignError};
    let problem = Problem::from_path("problems/design-min-peak.toml", &[]).unwrap();
    let spec = problem.design.as_ref().unwrap();
    // Asked from the start: not even the reference design is judged (a step of the
    // optimise phase is a candidate judged).
    let progress = stop_after(0);
    let e = design::run(&problem.machine(), spec, &progress).expect_err("stopped");
    assert!(matches!(e, DesignError::Stopped), "{e}");
    assert_eq!(progress.done.load(Ordering::Relaxed), 0);
}
