//! Fault points: every write, rename and removal of [`crate::files`] passes one, so a
//! test can end the process at any of them and check what a reader finds afterwards.
//!
//! Unarmed (always, unless a caller arms it) a point only counts. The binary arms it
//! from the test-only environment variable `ROTORSHUNT_TEST_KILL_AT=N`: the process
//! then kills itself with SIGKILL, which nothing can catch or clean up after, at the
//! N-th point (1-based) — as a power cut or an out-of-memory kill would.

use std::sync::atomic::{AtomicU64, Ordering};

/// The point at which to die (0: never).
static KILL_AT: AtomicU64 = AtomicU64::new(0);
/// Points passed so far by this process.
static PASSED: AtomicU64 = AtomicU64::new(0);

/// Kill the process at the `n`-th fault point from now on counting from the first
/// (`n` = 0 disarms).
pub fn arm(n: u64) {
    KILL_AT.store(n, Ordering::SeqCst);
}

/// The number of fault points this process has passed.
pub fn passed() -> u64 {
    PASSED.load(Ordering::SeqCst)
}

/// A fault point, just before the step it guards.
pub(crate) fn point() {
    let n = PASSED.fetch_add(1, Ordering::SeqCst) + 1;
    if KILL_AT.load(Ordering::SeqCst) == n {
        kill();
    }
}

#[cfg(unix)]
fn kill() {
    // SAFETY: raise only sends a signal to this process; SIGKILL ends it here.
    unsafe {
        libc::raise(libc::SIGKILL);
    }
}

#[cfg(not(unix))]
fn kill() {
    std::process::abort();
}
