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

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

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
    /// `count` more monodromy evaluations were made (the region search's unit of work,
    /// counted where it is made: the search's probe, the design's counters). A
    /// [`Deadline`] with an allowance stops the work once the count passes it; a wrapper
    /// that passes reports on must pass this one too.
    fn evaluated(&self, _count: u64) {}
    /// Whether the caller asks the computation to stop (the Python bindings: Ctrl-C, a
    /// progress callback that raised; a command's time limit, [`Deadline`]). The loops that take long ask it before each step
    /// (a chart before each φ row, the region catalogue and the band search before each
    /// seed's search and each boundary's tracking, a time response ten times a load
    /// period) and, once it is true, skip the steps
    /// not yet begun and return early: the result is then incomplete, and the caller that
    /// asked to stop discards it. Asking never changes a result that is not stopped.
    /// Default: never.
    fn cancelled(&self) -> bool {
        false
    }
}

/// A progress that also asks the work to stop once a time limit has passed since it was
/// made: the running bound of a command, measured while it runs on whatever machine it
/// runs (`--time-limit`, docs/errors.md `TimeLimit`). Every report goes on to `inner`, and
/// the work stops as `inner` asks too (Ctrl-C in the Python bindings).
///
/// A deadline may also carry an allowance of monodromy evaluations
/// ([`Deadline::with_allowance`]): the work's own count, reported as it is made
/// ([`Progress::evaluated`]), stops it once it passes the allowance, whatever the machine.
///
/// [`Deadline::tripped`] tells whether a limit stopped a step ([`Deadline::counted_out`]:
/// the allowance): the work skipped what it had not begun, and its result is incomplete.
/// A computation that never asks [`Progress::cancelled`] is never stopped, and never
/// tripped.
pub struct Deadline<'a> {
    inner: &'a dyn Progress,
    started: Instant,
    /// The limit (`None`: no limit, e.g. an infinite one).
    limit: Option<Duration>,
    tripped: AtomicBool,
    /// Most monodromy evaluations allowed ([`Deadline::with_allowance`]; `None`: no
    /// count limit).
    allowance: Option<u64>,
    /// Monodromy evaluations reported so far ([`Progress::evaluated`]).
    evaluations: AtomicU64,
    /// Whether the allowance (not the time) stopped a step.
    counted_out: AtomicBool,
}

impl<'a> Deadline<'a> {
    /// Progress reported to `inner`, and a stop asked once `seconds` (s of wall time) have
    /// passed from now. A limit that is not positive, or too large for a duration
    /// (infinite, NaN), never stops; one below a nanosecond stops at the first question.
    pub fn new(inner: &'a dyn Progress, seconds: f64) -> Deadline<'a> {
        let limit = if seconds > 0.0 { Duration::try_from_secs_f64(seconds).ok() } else { None };
        Deadline {
            inner,
            started: Instant::now(),
            limit,
            tripped: AtomicBool::new(false),
            allowance: None,
            evaluations: AtomicU64::new(0),
            counted_out: AtomicBool::new(false),
        }
    }

    /// This deadline with at most `most` monodromy evaluations (`None`: no count limit):
    /// the first question after the reported count has passed it stops the work.
    pub fn with_allowance(self, most: Option<u64>) -> Deadline<'a> {
        Deadline { allowance: most, ..self }
    }

    /// The allowance of monodromy evaluations, if any.
    pub fn allowance(&self) -> Option<u64> {
        self.allowance
    }

    /// Monodromy evaluations reported so far.
    pub fn evaluations(&self) -> u64 {
        self.evaluations.load(Ordering::Relaxed)
    }

    /// Whether the allowance of evaluations (rather than the time) stopped a step.
    pub fn counted_out(&self) -> bool {
        self.counted_out.load(Ordering::Relaxed)
    }

    /// Whether the limit has stopped a step (the work asked and was told to stop).
    pub fn tripped(&self) -> bool {
        self.tripped.load(Ordering::Relaxed)
    }

    /// Seconds since the deadline was made.
    pub fn elapsed(&self) -> f64 {
        self.started.elapsed().as_secs_f64()
    }
}

impl std::fmt::Debug for Deadline<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Deadline")
            .field("limit", &self.limit)
            .field("allowance", &self.allowance)
            .field("evaluations", &self.evaluations())
            .field("tripped", &self.tripped())
            .finish_non_exhaustive()
    }
}

impl Progress for Deadline<'_> {
    fn phase(&self, name: &str, steps: u64) {
        self.inner.phase(name, steps)
    }
    fn extend(&self, steps: u64) {
        self.inner.extend(steps)
    }
    fn advance(&self, steps: u64) {
        self.inner.advance(steps)
    }
    fn warning(&self, warning: &dyn std::fmt::Display) {
        self.inner.warning(warning)
    }
    fn notice(&self, line: &str) {
        self.inner.notice(line)
    }
    fn evaluated(&self, count: u64) {
        self.evaluations.fetch_add(count, Ordering::Relaxed);
        self.inner.evaluated(count)
    }
    fn cancelled(&self) -> bool {
        if self.inner.cancelled() {
            return true;
        }
        if self.tripped() {
            return true;
        }
        if self.allowance.is_some_and(|most| self.evaluations() > most) {
            self.counted_out.store(true, Ordering::Relaxed);
            self.tripped.store(true, Ordering::Relaxed);
            return true;
        }
        let over = self.limit.is_some_and(|limit| self.started.elapsed() > limit);
        if over {
            self.tripped.store(true, Ordering::Relaxed);
        }
        over
    }
}

/// Progress that nobody watches: every report is dropped.
#[derive(Debug, Clone, Copy, Default)]
pub struct Silent;

impl Progress for Silent {}

/// A progress that passes on only the question whether to stop ([`Progress::cancelled`]):
/// for a search whose caller counts its steps and evaluations itself, and that must still
/// stop when the caller's progress asks (a design's band searches, one per candidate).
#[derive(Clone, Copy)]
pub struct AskOnly<'a>(pub &'a dyn Progress);

impl std::fmt::Debug for AskOnly<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_tuple("AskOnly").finish_non_exhaustive()
    }
}

impl Progress for AskOnly<'_> {
    fn cancelled(&self) -> bool {
        self.0.cancelled()
    }
}

/// A progress that passes every report on to `inner` and counts the monodromy evaluations
/// reported through it ([`Progress::evaluated`]): the work of searches that keep no count
/// of their own for the caller (a basis sized by convergence).
pub struct Tally<'a> {
    inner: &'a dyn Progress,
    evaluations: std::sync::atomic::AtomicU64,
}

impl<'a> Tally<'a> {
    /// A tally at 0 that reports to `inner`.
    pub fn new(inner: &'a dyn Progress) -> Tally<'a> {
        Tally { inner, evaluations: std::sync::atomic::AtomicU64::new(0) }
    }

    /// The evaluations reported so far.
    pub fn evaluations(&self) -> u64 {
        self.evaluations.load(Ordering::Relaxed)
    }
}

impl Progress for Tally<'_> {
    fn phase(&self, name: &str, steps: u64) {
        self.inner.phase(name, steps);
    }
    fn extend(&self, steps: u64) {
        self.inner.extend(steps);
    }
    fn advance(&self, steps: u64) {
        self.inner.advance(steps);
    }
    fn warning(&self, warning: &dyn std::fmt::Display) {
        self.inner.warning(warning);
    }
    fn notice(&self, line: &str) {
        self.inner.notice(line);
    }
    fn evaluated(&self, count: u64) {
        self.evaluations.fetch_add(count, Ordering::Relaxed);
        self.inner.evaluated(count);
    }
    fn cancelled(&self) -> bool {
        self.inner.cancelled()
    }
}

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

    /// A stop asked by the caller.
    struct Stop;
    impl Progress for Stop {
        fn cancelled(&self) -> bool {
            true
        }
    }

    #[test]
    fn a_deadline_stops_once_its_limit_has_passed_and_says_so() {
        // A limit of one nanosecond, or of less, has passed by the first question.
        for seconds in [1e-9, 5e-324] {
            let d = Deadline::new(&Silent, seconds);
            std::thread::sleep(Duration::from_millis(1));
            assert!(!d.tripped(), "not tripped before the work asks");
            assert!(d.cancelled());
            assert!(d.tripped());
        }
        // No limit, or one that is not a positive duration: never stops.
        for seconds in [f64::INFINITY, f64::NAN, 0.0, -1.0, 1e300] {
            let d = Deadline::new(&Silent, seconds);
            assert!(!d.cancelled() && !d.tripped(), "{seconds}");
        }
        // The caller's own stop passes through and is not the limit's.
        let d = Deadline::new(&Stop, 1e300);
        assert!(d.cancelled() && !d.tripped());
        // Reports go on to the inner progress.
        let calls = AtomicU64::new(0);
        let tick = || {
            calls.fetch_add(1, Ordering::Relaxed);
        };
        Deadline::new(&tick, 1.0).advance(3);
        assert_eq!(calls.load(Ordering::Relaxed), 3);
    }

    #[test]
    fn an_allowance_stops_the_first_question_after_the_count_passes_it() {
        let d = Deadline::new(&Silent, f64::INFINITY).with_allowance(Some(5));
        d.evaluated(3);
        d.evaluated(2);
        assert!(!d.cancelled() && !d.tripped(), "5 of 5 is within the allowance");
        d.evaluated(1);
        assert!(!d.tripped(), "not tripped before the work asks");
        assert!(d.cancelled() && d.tripped() && d.counted_out());
        assert_eq!(d.evaluations(), 6);
        // Without an allowance the count never stops the work; a time stop is not a count's.
        let d = Deadline::new(&Silent, f64::INFINITY);
        d.evaluated(u64::MAX / 2);
        assert!(!d.cancelled() && !d.counted_out());
        let d = Deadline::new(&Silent, 1e-9).with_allowance(Some(5));
        std::thread::sleep(Duration::from_millis(1));
        assert!(d.cancelled() && d.tripped() && !d.counted_out());
        // Counts go on to the inner progress (a deadline inside another).
        let outer = Deadline::new(&Silent, f64::INFINITY).with_allowance(Some(1));
        let inner = Deadline::new(&outer, f64::INFINITY);
        inner.evaluated(2);
        assert_eq!(outer.evaluations(), 2);
        assert!(inner.cancelled() && !inner.tripped() && outer.counted_out());
    }
}
