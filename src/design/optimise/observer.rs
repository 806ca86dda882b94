//! Watching a design run while it goes, as argmin's `Executor` takes observers: every
//! evaluation of the objective is handed to the caller's [`Observer`] when it is made,
//! with the entry the run's history keeps for it. A notebook can plot the history live, a
//! service can log it; the run's result does not depend on the observer.

use super::outcome::HistoryPoint;

/// One evaluation of a design run's objective, as it is made.
#[derive(Debug, Clone, Copy)]
pub struct Observation<'a> {
    /// The entry [`super::DesignOutcome::history`] keeps for it (start, step, value and the
    /// start's best so far, in the objective's unit).
    pub point: HistoryPoint,
    /// The candidate's variable values (SI units, in the order of `[design]`'s variables).
    /// Empty for a clear-bands run, whose entries are its convex steps, reported when a
    /// convex run ends.
    pub values: &'a [f64],
}

/// A watcher of a design run ([`super::RunOptions::observer`]). The Nelder–Mead starts
/// run in parallel, so observations of different starts interleave in any order; within a
/// start they come in step order. A closure `Fn(&Observation)` is an observer.
pub trait Observer: Send + Sync {
    /// One evaluation was made.
    fn observe(&self, observation: &Observation<'_>);
}

impl<F: Fn(&Observation<'_>) + Send + Sync> Observer for F {
    fn observe(&self, observation: &Observation<'_>) {
        self(observation)
    }
}
