//! The application layer ([`rotorshunt::run::Run`]): a design run with a time limit,
//! with an allowance of evaluations and cancelled from another thread returns the best
//! design judged so far with its status as data, and the work after the stop was asked
//! stays under one band search's evaluations per thread.

use crate::cancel::{assert_stopped, short_design};
use rotorshunt::analysis::cost::DESIGN_BAND_EVALUATIONS;
use rotorshunt::progress::{Progress, Silent};
use rotorshunt::run::{Budget, Stopped};
use rotorshunt::run::{CancelToken, Run, RunStatus};
use std::sync::mpsc;
use std::sync::Mutex;

#[test]
fn a_design_at_its_time_limit_returns_its_best_design_with_the_status() {
    let problem = short_design();
    let budget = Budget::default().with_time_limit(1e-9).unwrap();
    let run = Run::new(&Silent).with_budget(budget);
    let o = run.design(&problem, "the design").unwrap().run(true).unwrap();
    assert_eq!(o.status, RunStatus::TimeLimit);
    assert!(matches!(o.stop, Some(Stopped::Time(_))), "{:?}", o.stop);
    assert_stopped(&o.value.outcome);
    // Stopped: no charts, the best design's model kept for its file.
    assert!(o.value.content.is_none());
    assert!(o.value.outcome.stop.as_deref().is_some_and(|s| s.contains("time limit")));
}

#[test]
fn a_design_at_its_allowance_of_evaluations_returns_its_best_design_with_the_status() {
    let problem = short_design();
    let allowance = 300;
    let run = Run::new(&Silent).with_evaluations(allowance).unwrap();
    let o = run.design(&problem, "the design").unwrap().run(false).unwrap();
    assert_eq!(o.status, RunStatus::EvaluationLimit);
    assert!(matches!(&o.stop, Some(Stopped::Count(c)) if c.allowed == allowance), "{:?}", o.stop);
    assert_stopped(&o.value.outcome);
    let after = o.evaluations - allowance;
    let threads = rayon::current_num_threads() as f64;
    println!("stopped at {} evaluations, {after} after the allowance of {allowance}", o.evaluations);
    assert!((after as f64) < threads * DESIGN_BAND_EVALUATIONS, "{after} evaluations after the stop");
    // An allowance of none is refused by its rule.
    assert!(Run::new(&Silent).with_evaluations(0).is_err());
}

/// Tells another thread once the first candidate of the optimiser is built.
struct FirstCandidate(Mutex<Option<mpsc::Sender<()>>>);

impl Progress for FirstCandidate {
    fn advance(&self, _steps: u64) {
        if let Some(tx) = self.0.lock().unwrap().take() {
            tx.send(()).unwrap();
        }
    }
}

#[test]
fn a_design_cancelled_from_another_thread_returns_its_best_design_with_the_status() {
    let problem = short_design();
    let (tx, rx) = mpsc::channel();
    let observer = FirstCandidate(Mutex::new(Some(tx)));
    let token = CancelToken::new();
    let remote = token.clone();
    let canceller = std::thread::spawn(move || {
        rx.recv().unwrap();
        remote.cancel();
    });
    let run = Run::new(&observer).with_cancel(token.clone());
    let o = run.design(&problem, "the design").unwrap().run(true).unwrap();
    canceller.join().unwrap();
    assert!(token.is_cancelled());
    assert_eq!(o.status, RunStatus::Cancelled);
    // No limit stopped it: the outcome says its caller did.
    assert!(o.stop.is_none());
    let outcome = &o.value.outcome;
    assert_eq!(outcome.status, rotorshunt::design::Status::Stopped);
    assert!(outcome.stop.is_none() && !outcome.verified());
    // A job with nothing to keep is an error that names the cancellation.
    let chart = Run::new(&Silent).with_cancel(token);
    let fs = chart.reduced_system(&problem, 1500.0).unwrap();
    let e = chart.chart_of(&fs, &[1000.0, 1100.0], &[0.1]).unwrap_err();
    assert!(matches!(e, rotorshunt::run::RunError::Cancelled { .. }), "{e}");
}
