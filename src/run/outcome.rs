//! What a job of a run returns when it may stop early ([`Outcome`]), why it ended
//! ([`RunStatus`]), and the caller's way to stop it ([`CancelToken`]).

use super::Stopped;
use crate::progress::Progress;
use serde::Serialize;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// Why a job ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum RunStatus {
    /// It ran to its end.
    Completed,
    /// At the run's time limit.
    TimeLimit,
    /// At its allowance of monodromy evaluations.
    EvaluationLimit,
    /// Its caller cancelled it ([`CancelToken`], or the observer asked).
    Cancelled,
}

/// What a job that keeps its best value returned: the value (the best found so far when
/// it was stopped), why it ended, the limit's error when a limit stopped it, and the
/// monodromy evaluations it made.
#[derive(Debug, Clone, Serialize)]
pub struct Outcome<T> {
    /// Why it ended.
    pub status: RunStatus,
    /// The value (complete only for [`RunStatus::Completed`]).
    pub value: T,
    /// The limit that stopped it, with the figures (limit, elapsed or allowance, used).
    pub stop: Option<Stopped>,
    /// Monodromy evaluations counted while it ran.
    pub evaluations: u64,
}

/// A switch another thread (or a signal handler's flag) turns to stop a run: every
/// search the run calls asks it between its steps. Clones share the switch.
#[derive(Debug, Clone, Default)]
pub struct CancelToken(Arc<AtomicBool>);

impl CancelToken {
    /// A switch not yet turned.
    pub fn new() -> CancelToken {
        CancelToken::default()
    }

    /// Ask the run to stop.
    pub fn cancel(&self) {
        self.0.store(true, Ordering::Relaxed);
    }

    /// Whether the run was asked to stop.
    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

/// The caller's observer, and the run's cancellation with it.
pub(super) struct Observer<'a> {
    inner: &'a dyn Progress,
    token: Option<CancelToken>,
}

impl<'a> Observer<'a> {
    pub(super) fn new(inner: &'a dyn Progress) -> Observer<'a> {
        Observer { inner, token: None }
    }

    pub(super) fn with_token(self, token: CancelToken) -> Observer<'a> {
        Observer { token: Some(token), ..self }
    }
}

impl Progress for Observer<'_> {
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
        self.inner.evaluated(count)
    }
    fn cancelled(&self) -> bool {
        self.token.as_ref().is_some_and(CancelToken::is_cancelled) || self.inner.cancelled()
    }
}
