//! # rotorshunt
//!
//! Parametric stability of a rotor (Rayleigh-beam shaft, rigid disks, gyroscopic
//! effects) on bearings mounted in piezoelectric vibration rings whose stacks are
//! shunted by multi-branch current-flowing circuits, after the paper
//! "Stability analysis of a rotor system with electromechanically coupled boundary
//! conditions under periodic axial load" (equation numbers below refer to it; the
//! modelling choices it leaves implicit are in docs/model.md).
//!
//! In the complex coordinates of Eq. (13) the system is (Eq. 14)
//!
//! ```text
//! M ü + (C − jΩG) u̇ + (K − P(t)·S) u = Q(t),   P(t) = P_cr·(α + β·cos φt)
//! ```
//!
//! with real symmetric M, C, K, S, G assembled from Rayleigh beam elements, disks
//! (Eq. 6), rings (Eq. 7–11) and N-branch shunts (Eq. A8). Whirl frequencies come from
//! the quadratic eigenproblem of Eq. (16), solved in a structure-keeping first-order
//! form (shift-invert, Eq. 18–21, where that form does not apply).
//!
//! Data flows one way: [`problem`] (file) → [`model`] (physics) → [`assembly`]
//! (matrices) → [`analysis`] → [`design`] → [`run`] → [`report`]; [`import`] turns other
//! programs' rotor files (ROSS's) into problem files. [`run`] is the application layer:
//! a [`run::Run`] holds a use's limits (cost, time, evaluations), observer and
//! cancellation, and its methods are the tool's jobs, admitted, run and stopped as the
//! command line and the Python bindings run them. The code's dependencies follow the types: the
//! file layer builds the model, the settings and the design spec, so it names those
//! layers and none of them names it; it reads and checks, and never runs an analysis
//! (tests/layers.rs checks every layer). SI units and rad/s throughout.
//!
//! ## The library's face
//!
//! The types re-exported here are the supported surface: load a [`Problem`], take its
//! rotor at a speed as an [`OperatingPoint`] (whirls and the reduced periodic system),
//! and ask it for a chart ([`ChartRequest`]), a catalogue of regions
//! ([`CatalogueRequest`]) or a stable band ([`BandRequest`]); every request is checked
//! when it is built. A file with a `[design]` table is designed by [`run_design`], given
//! its machine ([`Problem::machine`]) and its spec, or through [`run::Run::design`], which
//! admits it by its estimate and returns the best design so far when a limit or a
//! [`run::CancelToken`] stops it. The modules stay public for the rest
//! (assembled matrices, solvers); `commands` is the command line's layer and not part of
//! the library.
//!
//! Each layer returns its own error: [`ProblemError`] (with a [`problem::ProblemErrorKind`]),
//! [`AnalysisError`], [`DesignError`] and the ROSS importer's [`ImportError`]. The enums
//! are `#[non_exhaustive]`, and each names its kind as docs/errors.md heads it
//! (`ProblemErrorKind::name`, `AnalysisError::kind`, `DesignError::kind`).
//!
//! ```
//! use rotorshunt::{CatalogueRequest, Interval, Problem};
//!
//! let problem = Problem::from_path("problems/paper-open.toml", &[]).unwrap();
//! let op = problem.operating_point_at(2000.0).unwrap();
//! let f1 = op.modes.forward().next().unwrap().frequency;
//! assert!((f1 / 399.0 - 1.0).abs() < 1e-3); // Table 2: ω_f1 = 399.0 rad/s
//! let request = CatalogueRequest::builder().range(Interval::new(600.0, 800.0)).beta_max(0.1).level(0.05);
//! let cat = op.catalogue(&request.build().unwrap()).unwrap();
//! assert!(cat.regions.iter().any(|r| r.label == "f1+b1")); // Fig. 9: ω_f1 + ω_b1 ≈ 700
//! ```

#![warn(missing_docs)]
// No panics on data (docs/invariants.md): clippy refuses `unwrap`, `expect`, `panic!`,
// `unreachable!`, `todo!`, `unimplemented!`, the `assert` family and `unwrap_unchecked`
// (the last two listed in clippy.toml) outside tests; the few calls that hold by
// construction carry `#[expect(…, reason = "…")]` at the call.
#![cfg_attr(
    not(test),
    deny(
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::panic,
        clippy::unreachable,
        clippy::todo,
        clippy::unimplemented,
        clippy::disallowed_macros,
        clippy::disallowed_methods
    )
)]

pub mod analysis;
pub mod assembly;
pub mod design;
pub mod files;
pub mod import;
pub mod linalg;
pub mod model;
pub mod numbers;
pub mod problem;
pub mod progress;
// The Python bindings (`--features python`, built by maturin; docs/python.md): they only
// convert, to and from the command layer and the library.
#[cfg(feature = "python")]
mod python;
// The command layer (src/commands/): the subcommands, their argument types and the study
// folder's records, shared by the two front ends and public in neither. The binary
// compiles it as its own module; the Python bindings compile the same files here, as a
// private module. Its files name the library as `rotorshunt::…`, which resolves in both
// crates (`extern crate self` below). The binary's build checks the layer for dead code;
// here, what the binary alone calls is unused, and the arms for error kinds added to the
// library later (its enums are non-exhaustive to the binary) cannot be reached.
#[cfg(feature = "python")]
#[allow(dead_code, unused_imports, unreachable_patterns)]
mod commands;
#[cfg(feature = "python")]
extern crate self as rotorshunt;
pub mod report;
pub mod run;

pub use analysis::regions::{Band, Catalogue, CatalogueRequest};
pub use analysis::{AnalysisError, BandRequest, ChartRequest, Criterion, Interval, OperatingPoint, Rotor, Settings};
pub use design::{run as run_design, DesignError, DesignOutcome, DesignSpec, Machine};
pub use import::ross::ImportError;
pub use problem::{Problem, ProblemError};
