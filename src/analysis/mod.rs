//! Analyses of an assembled model; each returns a serialisable result object.

pub mod buckling;
pub mod campbell;
pub mod chart;
pub mod criterion;
pub mod floquet;
pub mod interval;
pub mod modes;
pub mod reduction;
pub mod regions;
pub mod response;
mod rotor;
mod settings;

pub use criterion::Criterion;
pub use interval::Interval;
pub use rotor::Rotor;
pub use settings::{MonodromyMethod, Settings};

use crate::linalg::LinalgError;
use thiserror::Error;

/// Failures of an analysis.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum AnalysisError {
    /// Dense linear algebra failed.
    #[error(transparent)]
    Linalg(#[from] LinalgError),
    /// M (reduced modes) is zero or larger than the number of finite modes.
    #[error("the reduced model asks for {requested} modes but the model has {available} finite modes (analysis.reduced_modes must be between 1 and {available})")]
    ReducedModes {
        /// Requested M.
        requested: usize,
        /// Finite undamped modes of the model.
        available: usize,
    },
    /// A stable band was asked around a φ outside the window searched.
    #[error("phi_op = {phi} rad/s lies outside the phi window {window:.2} rad/s searched for its band")]
    OutsideWindow {
        /// φ_op (rad/s).
        phi: f64,
        /// The window (rad/s).
        window: Interval,
    },
    /// α ≥ 1: the static part of the load alone buckles the shaft.
    #[error("the static load αP_cr = {alpha} × {critical_load:.6e} N is at or above the buckling load (alpha must be below 1)")]
    StaticLoadBuckles {
        /// α.
        alpha: f64,
        /// P_cr (N).
        critical_load: f64,
    },
}
