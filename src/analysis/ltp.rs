//! A small linear time-periodic system given by its matrices, for research and checks:
//!
//! ```text
//! M q̈ + (C − jΩG) q̇ + (K − P(t)·S) q = 0,   P(t) = P_ref·(α + β cos φt),
//! ```
//!
//! the form of Eq. (14) with M, C, K, S and G real symmetric (G may be absent), q complex
//! (at Ω = 0 and with G absent, the same multipliers as the real system q ∈ ℝⁿ). It becomes
//! a [`FloquetSystem`] ([`LtpSystem::floquet`]) on which every Floquet and region question
//! of the tool runs as on a rotor: points, charts, onsets and starts, the catalogue and
//! the band, by the settings' criterion. The basis is every mode of (K − αP_ref·S, M): no
//! truncation.
//!
//! ```
//! use rotorshunt::analysis::ltp::LtpSystem;
//! use rotorshunt::analysis::regions::{Probe, RegionSettings};
//! use rotorshunt::analysis::Settings;
//! use faer::Mat;
//!
//! // The damped Mathieu equation x″ + 2ζωx′ + ω²(1 − h cos 2ωt)x = 0, ω = 100 rad/s.
//! let (w, zeta) = (100.0, 0.01);
//! let one = |x: f64| Mat::from_fn(1, 1, |_, _| x);
//! let sys = LtpSystem::new(one(1.0), one(2.0 * zeta * w), one(w * w), one(w * w), None, 1.0, 0.0).unwrap();
//! let fs = sys.floquet(&Settings::default(), 0.0).unwrap();
//! // Its principal region starts at φ = 2ω; its onset is h_c = 4ζ to first order.
//! let s = RegionSettings::default();
//! let start = Probe::new(&fs, &s).locate_start(2.0 * w, 0.01 * w, 0.1, 0.2).unwrap();
//! assert!((start.onset / (4.0 * zeta) - 1.0).abs() < 5e-3);
//! ```

use super::floquet::FloquetSystem;
use super::reduction::ReducedModel;
use super::{AnalysisError, Settings};
use crate::linalg::definite_eigen;
use faer::Mat;

/// Why matrices do not make an [`LtpSystem`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum LtpError {
    /// A matrix is not n × n with n the size of M (or M is empty).
    #[error("matrix {matrix} is {rows} x {cols}; it must be {n} x {n}, as M is")]
    Shape {
        /// Its name (`M`, `C`, `K`, `S`, `G`).
        matrix: &'static str,
        /// Its rows.
        rows: usize,
        /// Its columns.
        cols: usize,
        /// The size of M.
        n: usize,
    },
    /// A matrix has a NaN or infinite entry.
    #[error("matrix {matrix} has a non-finite entry at ({row}, {col})")]
    NotFinite {
        /// Its name.
        matrix: &'static str,
        /// Row of the entry.
        row: usize,
        /// Column of the entry.
        col: usize,
    },
    /// A matrix is not symmetric to round-off.
    #[error("matrix {matrix} is not symmetric: entries ({row}, {col}) and ({col}, {row}) differ by {difference:e}")]
    NotSymmetric {
        /// Its name.
        matrix: &'static str,
        /// Row of the worst entry.
        row: usize,
        /// Column of the worst entry.
        col: usize,
        /// |A_ij − A_ji|.
        difference: f64,
    },
    /// P_ref or α is not a finite number, or α·P_ref makes K − αP_ref·S or M indefinite.
    #[error("{what}")]
    Load {
        /// What is wrong, in words.
        what: String,
    },
}

/// A linear time-periodic system by its matrices (module docs).
#[derive(Debug, Clone)]
pub struct LtpSystem {
    m: Mat<f64>,
    c: Mat<f64>,
    k: Mat<f64>,
    s: Mat<f64>,
    g: Mat<f64>,
    load: f64,
    alpha: f64,
}

/// Relative asymmetry accepted in a matrix said to be symmetric: round-off of an assembly.
const SYMMETRY_TOLERANCE: f64 = 1e-12;

impl LtpSystem {
    /// The system from M, C, K, S (and G, or none) (SI units of the caller's choice, one
    /// consistent set), the reference load P_ref and the static coefficient α; every matrix
    /// checked: n × n, finite, symmetric to 1e-12 of its largest entry.
    pub fn new(
        m: Mat<f64>,
        c: Mat<f64>,
        k: Mat<f64>,
        s: Mat<f64>,
        g: Option<Mat<f64>>,
        load: f64,
        alpha: f64,
    ) -> Result<LtpSystem, LtpError> {
        let n = m.nrows();
        let g = g.unwrap_or_else(|| Mat::zeros(n, n));
        for (name, a) in [("M", &m), ("C", &c), ("K", &k), ("S", &s), ("G", &g)] {
            check(name, a, n)?;
        }
        if !load.is_finite() || !alpha.is_finite() {
            return Err(LtpError::Load { what: format!("P_ref = {load} and alpha = {alpha} must be finite numbers") });
        }
        Ok(LtpSystem { m, c, k, s, g, load, alpha })
    }

    /// The number of coordinates n.
    pub fn size(&self) -> usize {
        self.m.nrows()
    }

    /// The system as a [`FloquetSystem`] at speed Ω (rad/s) under `settings` (its
    /// criterion, steps and paths), on the basis of all n modes of (K − αP_ref·S, M)
    /// mass-normalised: the reduced matrices are the system's own in modal coordinates.
    pub fn floquet(&self, settings: &Settings, speed: f64) -> Result<FloquetSystem, AnalysisError> {
        let n = self.size();
        let p = self.alpha * self.load;
        let k_b = Mat::from_fn(n, n, |i, j| self.k[(i, j)] - p * self.s[(i, j)]);
        let eig = definite_eigen(k_b.as_ref(), self.m.as_ref()).map_err(|_| {
            AnalysisError::Ltp(LtpError::Load {
                what: format!(
                    "K - alpha P_ref S (alpha P_ref = {p}) must be positive definite, and M positive semi-definite"
                ),
            })
        })?;
        let count = eig.values.iter().filter(|t| **t > 0.0).count();
        if count == 0 {
            return Err(AnalysisError::ReducedModes { requested: n, available: 0 });
        }
        let theta = &eig.values[..count];
        let basis = Mat::from_fn(n, count, |i, j| eig.vectors[(i, j)] / theta[j].sqrt());
        let project = |a: &Mat<f64>| {
            let ap = crate::linalg::seq::product(a.as_ref(), basis.as_ref());
            crate::linalg::seq::product(basis.transpose(), ap.as_ref())
        };
        let reduced = ReducedModel {
            frequencies: theta.iter().map(|t| (1.0 / t).sqrt()).collect(),
            c: project(&self.c),
            g: project(&self.g),
            k: project(&self.k),
            s: project(&self.s),
            unbalance: vec![faer::c64::new(0.0, 0.0); count],
            critical_load: self.load,
            alpha: self.alpha,
            real: false,
            basis,
        };
        FloquetSystem::from_reduced(reduced, &settings.with_modes(count), speed)
    }
}

fn check(name: &'static str, a: &Mat<f64>, n: usize) -> Result<(), LtpError> {
    if n == 0 || a.nrows() != n || a.ncols() != n {
        return Err(LtpError::Shape { matrix: name, rows: a.nrows(), cols: a.ncols(), n });
    }
    let mut largest = 0.0f64;
    for i in 0..n {
        for j in 0..n {
            let x = a[(i, j)];
            if !x.is_finite() {
                return Err(LtpError::NotFinite { matrix: name, row: i, col: j });
            }
            largest = largest.max(x.abs());
        }
    }
    for i in 0..n {
        for j in 0..i {
            let difference = (a[(i, j)] - a[(j, i)]).abs();
            if difference > SYMMETRY_TOLERANCE * largest {
                return Err(LtpError::NotSymmetric { matrix: name, row: i, col: j, difference });
            }
        }
    }
    Ok(())
}
