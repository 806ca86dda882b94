//! `Progress::cancelled`: a chart, a region catalogue and an unbalance response asked to
//! stop skip the steps not begun (an incomplete result, for the caller to discard), a
//! design ends `Status::Stopped` with the best design judged before the stop (asked by
//! its caller, from another thread, at its time limit or when its allowance of
//! evaluations is spent, `Progress::evaluated`), and a progress that never asks changes
//! nothing (the Python bindings' Ctrl-C, docs/python.md).

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
pub(crate) fn short_design() -> Problem {
    let short = ["design.starts=1", "design.max_iterations=2", "design.phi_range=[1000.0, 1500.0]"];
    let o: Vec<String> = short.iter().chain(&crate::common::QUICK_BASIS).map(|s| s.to_string()).collect();
    Problem::from_path("problems/design-widest-band.toml", &o).unwrap()
}

/// What a stopped design must be: `Status::Stopped`, not verified, not a result, its
/// values inside the bounds (the reference's own where no candidate was judged).
pub(crate) fn assert_stopped(o: &rotorshunt::design::DesignOutcome) {
    use rotorshunt::design::Status;
    assert_eq!(o.status, Status::Stopped);
    assert!(!o.status.is_result() && !o.verified() && o.verification.parts.is_empty());
    assert!(o.stop.is_some());
    if o.after != o.before {
        for (v, x) in o.spec.variables.iter().zip(&o.after) {
            assert!((v.min..=v.max).contains(x), "{x} outside [{}, {}]", v.min, v.max);
        }
    }
}

#[test]
fn a_design_asked_to_stop_builds_no_more_candidates_and_keeps_its_best() {
    use rotorshunt::design;
    let problem = short_design();
    let spec = problem.design.as_ref().unwrap();
    let machine = problem.machine();
    // Never asked: the same outcome as without a progress.
    let full = design::run(&machine, spec, &Silent).unwrap();
    let never = design::run(&machine, spec, &stop_after(u64::MAX)).unwrap();
    assert_eq!((never.after.clone(), never.candidates), (full.after.clone(), full.candidates));
    assert!(full.candidates > 4, "{} candidates", full.candidates);
    // Asked after 2 candidates (a step of the optimise phase is a candidate built): the
    // run ends stopped, having built at most a candidate per thread more.
    let progress = stop_after(2);
    let o = design::run(&machine, spec, &progress).unwrap();
    assert_stopped(&o);
    let built = progress.done.load(Ordering::Relaxed);
    assert!(built <= 2 + rayon::current_num_threads() as u64, "{built} candidates built");
}

#[test]
fn a_design_reports_its_evaluations_and_stops_at_its_allowance() {
    use rotorshunt::analysis::cost::DESIGN_BAND_EVALUATIONS;
    use rotorshunt::design;
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
    // An allowance of half the optimiser's count stops the run on its own count, and the
    // work after the stop was asked stays under one band search's evaluations per thread
    // (each thread ends the search it is in).
    let allowance = optimiser / 2;
    let half = Deadline::new(&Silent, f64::INFINITY).with_allowance(Some(allowance));
    let o = design::run(&machine, spec, &half).unwrap();
    assert_stopped(&o);
    let after = half.evaluations() - allowance;
    let threads = rayon::current_num_threads() as f64;
    println!("stopped at {} evaluations, {after} after the allowance of {allowance}", half.evaluations());
    assert!(half.counted_out() && (after as f64) < threads * DESIGN_BAND_EVALUATIONS, "{half:?}");
}

#[test]
fn a_design_at_its_time_limit_keeps_the_best_design_judged() {
    use rotorshunt::design;
    use rotorshunt::progress::Deadline;
    let problem = short_design();
    let spec = problem.design.as_ref().unwrap();
    let machine = problem.machine();
    // A limit that has passed at the first question: nothing judged, the reference kept.
    let at_once = Deadline::new(&Silent, 1e-12);
    let o = design::run(&machine, spec, &at_once).unwrap();
    assert_stopped(&o);
    assert!(at_once.tripped() && !at_once.counted_out());
    assert_eq!(o.after, o.before);
}

/// A caller's stop, set from another thread once the run has judged `after` candidates,
/// and what the caller's observer saw: each evaluation's values and band objective, and
/// whether the stop had been asked when it was seen.
struct Caller {
    stop: std::sync::atomic::AtomicBool,
    seen: std::sync::Mutex<Vec<(Vec<f64>, f64, bool)>>,
}

impl Progress for Caller {
    fn cancelled(&self) -> bool {
        self.stop.load(Ordering::SeqCst)
    }
}

struct Watch(std::sync::Arc<Caller>);

impl rotorshunt::design::optimise::Observer for Watch {
    fn observe(&self, o: &rotorshunt::design::optimise::Observation<'_>) {
        let asked = self.0.cancelled();
        self.0.seen.lock().unwrap().push((o.values.to_vec(), o.point.value, asked));
    }
}

#[test]
fn a_design_stopped_from_another_thread_keeps_the_best_design_judged_before() {
    use rotorshunt::design::optimise::{run_with, RunOptions};
    use std::sync::Arc;
    let problem = short_design();
    let spec = problem.design.as_ref().unwrap();
    let machine = problem.machine();
    let caller = Arc::new(Caller { stop: false.into(), seen: Default::default() });
    let options = RunOptions { observer: Some(Arc::new(Watch(caller.clone()))), ..RunOptions::default() };
    let o = std::thread::scope(|scope| {
        let c = caller.clone();
        scope.spawn(move || {
            while c.seen.lock().unwrap().len() < 4 {
                std::thread::sleep(std::time::Duration::from_millis(5));
            }
            c.stop.store(true, Ordering::SeqCst);
        });
        run_with(&machine, spec, &options, caller.as_ref()).unwrap()
    });
    assert_stopped(&o);
    let seen = caller.seen.lock().unwrap();
    // The kept design was judged, and is at least as good as every judgement seen
    // complete before the stop (the run keeps no judgement that ended after it).
    let complete = seen.iter().filter(|s| !s.2).map(|s| s.1).fold(f64::NEG_INFINITY, f64::max);
    let kept = seen.iter().filter(|s| s.0 == o.after).map(|s| s.1).fold(f64::NEG_INFINITY, f64::max);
    println!("{} judgements seen, kept {kept} rad/s, best complete {complete} rad/s", seen.len());
    assert!(complete.is_finite() && kept >= complete, "kept {kept} < {complete}");
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
    use rotorshunt::design;
    let problem = Problem::from_path("problems/design-min-peak-at-speed.toml", &[]).unwrap();
    let spec = problem.design.as_ref().unwrap();
    // Asked from the start: not even the reference design is judged (a step of the
    // optimise phase is a candidate judged), and the reference is what it keeps.
    let progress = stop_after(0);
    let o = design::run(&problem.machine(), spec, &progress).unwrap();
    assert_stopped(&o);
    assert_eq!(o.after, o.before);
    assert_eq!(progress.done.load(Ordering::Relaxed), 0);
}
