//! Long calls from Python: the work runs on a worker thread with the GIL released, while
//! the calling thread wakes every [`TICK`] to check Python's signals and report progress.
//! A pending signal (Ctrl-C: `KeyboardInterrupt`) or a progress callback that raises asks
//! the work to stop ([`Progress::cancelled`]); the call then waits for the work to reach
//! its next step, drops its (incomplete) result and raises that exception.

use crate::progress::Progress;
use pyo3::prelude::*;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc;
use std::sync::Mutex;
use std::time::Duration;

/// How often the calling thread checks signals and reports progress.
const TICK: Duration = Duration::from_millis(50);

/// The progress of a watched call, shared by its worker threads and the calling thread.
#[derive(Default)]
struct Watch {
    stop: AtomicBool,
    done: AtomicU64,
    total: AtomicU64,
    phase: Mutex<String>,
}

impl Progress for Watch {
    fn phase(&self, name: &str, steps: u64) {
        if let Ok(mut p) = self.phase.lock() {
            name.clone_into(&mut p);
        }
        self.total.store(steps, Ordering::Relaxed);
        self.done.store(0, Ordering::Relaxed);
    }
    fn extend(&self, steps: u64) {
        self.total.fetch_add(steps, Ordering::Relaxed);
    }
    fn advance(&self, steps: u64) {
        self.done.fetch_add(steps, Ordering::Relaxed);
    }
    fn cancelled(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }
}

/// A Rust panic caught at the boundary: an error of the package, never a crash.
pub(crate) fn panicked(payload: &(dyn std::any::Any + Send)) -> PyErr {
    super::Error::new_err(format!("internal error (please report it): {}", panic_text(payload)))
}

/// A panic's message.
pub(crate) fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown".into())
}

/// Run `work` with the GIL released, honouring Ctrl-C between its steps and calling
/// `callback(phase, done, total)` as it advances.
pub(crate) fn watched<T: Send>(
    py: Python<'_>,
    callback: Option<&Bound<'_, PyAny>>,
    work: impl FnOnce(&dyn Progress) -> Result<T, crate::commands::Error> + Send,
) -> PyResult<T> {
    let watch = Watch::default();
    let (tx, rx) = mpsc::channel::<()>();
    // Waited on with the GIL released, which needs what it borrows to be Sync.
    let rx = Mutex::new(rx);
    let mut raised: Option<PyErr> = None;
    let mut last = (String::new(), u64::MAX, u64::MAX);
    let outcome = std::thread::scope(|s| {
        let worker = s.spawn(|| {
            let r = catch_unwind(AssertUnwindSafe(|| work(&watch)));
            let _ = tx.send(());
            r
        });
        loop {
            let finished = py.detach(|| match rx.lock() {
                Ok(rx) => !matches!(rx.recv_timeout(TICK), Err(mpsc::RecvTimeoutError::Timeout)),
                Err(_) => true,
            });
            if raised.is_none() {
                if let Err(e) = py.check_signals() {
                    watch.stop.store(true, Ordering::Relaxed);
                    raised = Some(e);
                }
            }
            if let (Some(cb), None) = (callback, &raised) {
                let phase = watch.phase.lock().map(|p| p.clone()).unwrap_or_default();
                let now = (phase, watch.done.load(Ordering::Relaxed), watch.total.load(Ordering::Relaxed));
                if now != last {
                    if let Err(e) = cb.call1((now.0.as_str(), now.1, now.2)) {
                        watch.stop.store(true, Ordering::Relaxed);
                        raised = Some(e);
                    }
                    last = now;
                }
            }
            if finished {
                break;
            }
        }
        worker.join()
    });
    if let Some(e) = raised {
        return Err(e);
    }
    match outcome {
        Ok(Ok(r)) => r.map_err(super::to_py),
        Ok(Err(payload)) | Err(payload) => Err(panicked(payload.as_ref())),
    }
}

/// Run a short `work` with the GIL released (no progress, no cancelling), a panic caught.
/// A signal that came while it ran (Ctrl-C) raises when it ends (`KeyboardInterrupt`), its
/// result dropped, before any of it is converted.
pub(crate) fn released<T: Send>(
    py: Python<'_>,
    work: impl FnOnce() -> Result<T, crate::commands::Error> + Send,
) -> PyResult<T> {
    let outcome = py.detach(|| catch_unwind(AssertUnwindSafe(work)));
    py.check_signals()?;
    match outcome {
        Ok(r) => r.map_err(super::to_py),
        Err(payload) => Err(panicked(payload.as_ref())),
    }
}
