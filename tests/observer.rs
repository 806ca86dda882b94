//! A design run's observer (argmin's `Executor` manner, issue 30 point 3): it is handed
//! every evaluation the run's history records, no more and no fewer, with the candidate's
//! variable values inside their bounds, and the run's result does not depend on it.

use rotorshunt::design::{run_with, Observation, RunOptions};
use rotorshunt::progress::Silent;
use rotorshunt::Problem;
use std::sync::{Arc, Mutex};

/// What the observer keeps of one evaluation: start, step, value, best and the variables.
type Seen = (usize, usize, f64, f64, Vec<f64>);

#[test]
fn the_observer_sees_the_history_and_changes_nothing() {
    // The coarse model (8 shaft elements, 4 modes, no refined check): what is checked is
    // the bookkeeping.
    let quick: Vec<String> = crate::common::coarse_model().map(String::from).collect();
    let problem = Problem::from_path("problems/design-widest-band.toml", &quick).unwrap();
    let mut spec = problem.design.clone().unwrap();
    // A short run, its catalogues over 900–1600 rad/s around φ_op: what is checked is the
    // bookkeeping, not the optimum.
    spec.starts = 2;
    spec.max_iterations = 4;
    spec.phi_range = (900.0, 1600.0);
    let machine = problem.machine();
    let seen: Arc<Mutex<Vec<Seen>>> = Arc::default();
    let log = Arc::clone(&seen);
    let observer = move |o: &Observation<'_>| {
        let p = o.point;
        log.lock().unwrap().push((p.start, p.step, p.value, p.best, o.values.to_vec()));
    };
    let options = RunOptions { observer: Some(Arc::new(observer)), ..RunOptions::default() };
    let watched = run_with(&machine, &spec, &options, &Silent).unwrap();
    let plain = run_with(&machine, &spec, &RunOptions::default(), &Silent).unwrap();

    let mut seen = seen.lock().unwrap().clone();
    seen.sort_by_key(|a| (a.0, a.1));
    let mut history: Vec<_> = watched.history.iter().map(|p| (p.start, p.step, p.value, p.best)).collect();
    history.sort_by_key(|a| (a.0, a.1));
    println!("{} evaluations observed, {} in the history", seen.len(), history.len());
    assert!(!history.is_empty(), "the run recorded no history");
    let observed: Vec<_> = seen.iter().map(|s| (s.0, s.1, s.2, s.3)).collect();
    assert_eq!(
        observed.iter().map(|s| (s.0, s.1, s.2.to_bits(), s.3.to_bits())).collect::<Vec<_>>(),
        history.iter().map(|s| (s.0, s.1, s.2.to_bits(), s.3.to_bits())).collect::<Vec<_>>(),
        "the observer saw other evaluations than the history holds"
    );
    // Every Nelder–Mead evaluation carries its candidate, one value per variable, inside
    // the variable's bounds (the simplex may step outside [0, 1]; the run clamps).
    for (_, _, _, _, values) in &seen {
        assert_eq!(values.len(), spec.variables.len());
        for (x, v) in values.iter().zip(&spec.variables) {
            let (lo, hi) = (v.min, v.max);
            assert!(*x >= lo * (1.0 - 1e-12) && *x <= hi * (1.0 + 1e-12), "{x} outside [{lo}, {hi}]");
        }
    }
    // The result is the same with and without the observer, bit for bit.
    assert_eq!(
        watched.after.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
        plain.after.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
    );
    assert_eq!(watched.history.len(), plain.history.len());
    assert_eq!(watched.status, plain.status);
}
