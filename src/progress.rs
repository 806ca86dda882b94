//! Progress of long computations, the one way the library reports it: a [`Progress`]
//! receives phases and steps, and the caller decides what to show (the CLI draws a bar on
//! a terminal and writes periodic lines otherwise). The library never prints.
//!
//! A run is a sequence of phases (a design: optimise, verification; the command adds the
//! report). Each phase has a number of steps, known when it begins ([`Progress::phase`])
//! or learned as its searches find work ([`Progress::extend`]), and its steps are counted
//! as they are done ([`Progress::advance`]). What a step is depends on the phase and is
//! documented where it is reported: a φ row of a chart, a speed of a Campbell diagram, a
//! load period of a time response, a candidate of the optimiser, a search or a grid point
//! of the region search. Steps may be reported from any thread, in any order; reporting
//! never changes a result.

/// Receives the progress of a computation. Every method has an empty default, so an
/// observer implements only what it shows.
pub trait Progress: Sync {
    /// A phase `name` begins with `steps` steps known so far (0: none known yet); the
    /// previous phase, if any, is over.
    fn phase(&self, _name: &str, _steps: u64) {}
    /// `steps` more steps of the current phase became known (a search that finds more work).
    fn extend(&self, _steps: u64) {}
    /// `steps` steps of the current phase are done.
    fn advance(&self, _steps: u64) {}
    /// A command found an implausible input while it ran (e.g. a φ range no region can
    /// reach): the warning's text, without the `warning: ` prefix; the warning is also in
    /// its JSON output. The problem file's own warnings are in the problem, not reported
    /// here.
    fn warning(&self, _warning: &dyn std::fmt::Display) {}
    /// A command found something on disk it ignored or left alone (a tampered record, a
    /// leftover it could not prove its own): one line, starting `warning: `.
    fn notice(&self, _line: &str) {}
    /// Whether the caller asks the computation to stop (the Python bindings: Ctrl-C, a
    /// progress callback that raised). The loops that take long ask it before each step
    /// (a chart before each φ row, the region catalogue and the band search before each
    /// seed's search and each boundary's tracking) and, once it is true, skip the steps
    /// not yet begun and return early: the result is then incomplete, and the caller that
    /// asked to stop discards it. Asking never changes a result that is not stopped.
    /// Default: never.
    fn cancelled(&self) -> bool {
        false
    }
}

/// Progress that nobody watches: every report is dropped.
#[derive(Debug, Clone, Copy, Default)]
pub struct Silent;

impl Progress for Silent {}

/// A closure counts steps: it is called once per step done (phases and totals are
/// dropped). `&|| {}` is the same as [`Silent`].
impl<F: Fn() + Sync> Progress for F {
    fn advance(&self, steps: u64) {
        for _ in 0..steps {
            self();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicU64, Ordering};

    #[test]
    fn a_closure_is_called_once_per_step() {
        let calls = AtomicU64::new(0);
        let tick = || {
            calls.fetch_add(1, Ordering::Relaxed);
        };
        let p: &dyn Progress = &tick;
        p.phase("ignored", 10);
        p.extend(5);
        p.advance(3);
        p.advance(0);
        p.advance(2);
        assert_eq!(calls.load(Ordering::Relaxed), 5);
        Silent.advance(7);
    }
}
