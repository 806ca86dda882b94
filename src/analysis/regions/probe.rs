//! The probe of the region search: one Floquet system, the search settings and the count
//! of monodromy evaluations, with the questions every search asks as its methods.
//!
//! Every monodromy evaluation of the region search goes through a [`Probe`] method, which
//! counts it; the count is shared by the threads a search runs on. The questions live
//! with their idea: the point questions here (is (φ, β) unstable, its growth), β_c and the
//! first crossing in β in [`super::critical`], starts and onsets in [`super::start`], edges
//! at any load and boundary tracking in [`super::track`], a pair's detuning and its centre
//! search in [`super::centre`]. The questions at one level β_op under the declared
//! criterion (counted points, lattice-refined edges, tongues) are those of a
//! [`super::Level`], which borrows a probe: a catalogue asks at one level under two
//! criteria (the declared one, and the tolerance alone for the slow tongues), and at many
//! other loads (onsets, tracking), and all of it is one count.
//!
//! A probe also carries the search's [`Progress`]: the searches report their steps (a
//! seed's start or hits, a tongue's extent, a guard-lattice point, a tracked boundary)
//! to it as they learn of them and finish them, and the probe reports each evaluation
//! ([`Progress::evaluated`]): a run's allowance of evaluations stops the search on its
//! own count ([`crate::progress::Deadline::with_allowance`]).

use super::RegionSettings;
use crate::analysis::floquet::fast::PhiTable;
use crate::analysis::floquet::{FloquetSystem, PointSummary};
use crate::progress::{Progress, Silent};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Counts monodromy evaluations (shared across threads), and reports each addition to a
/// [`Progress`] ([`Progress::evaluated`]: the unit of a run's allowance,
/// [`crate::progress::Deadline::with_allowance`]).
pub struct Counter<'a> {
    count: AtomicUsize,
    progress: &'a dyn Progress,
}

impl Default for Counter<'_> {
    /// A counter whose count nobody watches.
    fn default() -> Self {
        Counter::reporting(&Silent)
    }
}

impl std::fmt::Debug for Counter<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_tuple("Counter").field(&self.get()).finish()
    }
}

impl<'a> Counter<'a> {
    /// A counter at 0 that reports its additions to `progress`.
    pub fn reporting(progress: &'a dyn Progress) -> Counter<'a> {
        Counter { count: AtomicUsize::new(0), progress }
    }
    /// Add `n` evaluations.
    pub fn add(&self, n: usize) {
        self.count.fetch_add(n, Ordering::Relaxed);
        self.progress.evaluated(n as u64);
    }
    /// Evaluations so far.
    pub fn get(&self) -> usize {
        self.count.load(Ordering::Relaxed)
    }
    /// The progress the additions are reported to.
    pub fn progress(&self) -> &'a dyn Progress {
        self.progress
    }
}

/// The region search's access to one Floquet system: settings, and the evaluation count
/// with the progress the searches report to.
pub struct Probe<'a> {
    fs: &'a FloquetSystem,
    settings: &'a RegionSettings,
    evaluations: Counter<'a>,
}

impl std::fmt::Debug for Probe<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Probe")
            .field("fs", &self.fs)
            .field("settings", &self.settings)
            .field("evaluations", &self.evaluations)
            .finish_non_exhaustive()
    }
}

impl<'a> Probe<'a> {
    /// A probe of `fs` with the search settings `settings`, no evaluations yet, whose
    /// progress nobody watches.
    pub fn new(fs: &'a FloquetSystem, settings: &'a RegionSettings) -> Probe<'a> {
        Probe::reporting(fs, settings, &Silent)
    }

    /// A probe whose searches report their steps, and its count of evaluations, to
    /// `progress` (module docs).
    pub fn reporting(fs: &'a FloquetSystem, settings: &'a RegionSettings, progress: &'a dyn Progress) -> Probe<'a> {
        Probe { fs, settings, evaluations: Counter::reporting(progress) }
    }

    /// The progress the searches report to.
    pub fn progress(&self) -> &'a dyn Progress {
        self.evaluations.progress()
    }

    /// The Floquet system.
    pub fn system(&self) -> &'a FloquetSystem {
        self.fs
    }

    /// The region-search settings.
    pub fn settings(&self) -> &'a RegionSettings {
        self.settings
    }

    /// Monodromy evaluations so far.
    pub fn evaluations(&self) -> usize {
        self.evaluations.get()
    }

    /// Count one evaluation (for the methods that make one outside this module).
    pub(super) fn count(&self) {
        self.evaluations.add(1);
    }

    /// The Floquet point at (φ (rad/s), β) from a fresh per-φ table; one evaluation.
    pub fn point(&self, phi: f64, beta: f64) -> PointSummary {
        self.point_on(&self.fs.table(phi, beta), beta)
    }

    /// The Floquet point at β on a per-φ table valid up to at least β; one evaluation.
    pub fn point_on(&self, table: &PhiTable, beta: f64) -> PointSummary {
        self.count();
        self.fs.point_fast(table, beta).summary
    }

    /// Whether (φ, β) is unstable (max|μ| above the instability tolerance); one evaluation.
    pub fn unstable(&self, phi: f64, beta: f64) -> bool {
        !self.point(phi, beta).stable
    }

    /// Whether β is unstable on a per-φ table valid up to at least β; one evaluation.
    pub fn unstable_on(&self, table: &PhiTable, beta: f64) -> bool {
        !self.point_on(table, beta).stable
    }

    /// ln max|μ| at (φ, β) (per period); one evaluation.
    pub fn growth(&self, phi: f64, beta: f64) -> f64 {
        self.point(phi, beta).ln_max_multiplier
    }
}
