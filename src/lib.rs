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
//! (matrices) → [`analysis`] → [`design`] → [`report`]; [`import`] turns other programs'
//! rotor files (ROSS's) into problem files. SI units and rad/s throughout.
//!
//! ```
//! let problem = rotorshunt::problem::Problem::from_path("problems/paper-open.toml", &[]).unwrap();
//! let result = rotorshunt::analysis::modes::whirl_modes(&problem.model, &problem.settings, 2000.0).unwrap();
//! let f1 = result.forward().next().unwrap().frequency;
//! assert!((f1 / 399.0 - 1.0).abs() < 1e-3); // Table 2
//! ```

#![warn(missing_docs)]

pub mod analysis;
pub mod assembly;
pub mod commands;
pub mod design;
pub mod error;
pub mod import;
pub mod linalg;
pub mod model;
pub mod problem;
pub mod report;

pub use error::Error;
