//! Fault points: every write, rename and removal of [`crate::files`] passes one, so a
//! test can end the process at any of them and check what a reader finds afterwards.
//!
//! Unarmed (always, unless a caller arms it) a point only counts. The binary arms it
//! from the test-only environment variable `ROTORSHUNT_TEST_KILL_AT=N`: the process
//! then kills itself with SIGKILL, which nothing can catch or clean up after, at the
//! N-th point (1-based) — as a power cut or an out-of-memory kill would.
//!
//! The binary also arms, from `ROTORSHUNT_TEST_FULL_DISK=NAME`, a full disk for the files
//! named NAME: their writes fail with `ENOSPC`, as on a file system with no space left.

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

/// The file name whose writes fail as on a full disk (empty: none).
static FULL: std::sync::OnceLock<String> = std::sync::OnceLock::new();

/// Make every write of a file named `name` fail with "no space left on device" (once per
/// process; a second call is ignored).
pub fn arm_full_disk(name: &str) {
    let _ = FULL.set(name.to_string());
}

/// The error a full disk gives for a write of the file `name`, if armed for it.
pub(crate) fn full_disk(name: &str) -> std::io::Result<()> {
    match FULL.get() {
        Some(n) if n == name => Err(no_space()),
        _ => Ok(()),
    }
}

#[cfg(unix)]
fn no_space() -> std::io::Error {
    std::io::Error::from_raw_os_error(libc::ENOSPC)
}

#[cfg(not(unix))]
fn no_space() -> std::io::Error {
    std::io::Error::new(std::io::ErrorKind::StorageFull, "no space left on device")
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
