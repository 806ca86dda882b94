//! Modal reduction of Eq. (22)–(23): the first M undamped modes of (K, M) at Ω = 0
//! without axial load (electrical modes included when the circuit is closed), and the
//! periodic state matrix of Eq. (24)–(25), B(t) = B0 + β·cos(φt)·B1.

use super::{AnalysisError, Rotor};
use crate::linalg::definite_eigen;
use faer::{c64, Mat};
use serde::Serialize;

/// The reduced model: mass-normalised modes, so M̃ = I and K̃ = diag(ω²).
#[derive(Debug, Clone)]
pub struct ReducedModel {
    /// Undamped natural frequencies of the basis modes at Ω = 0, no load (rad/s).
    pub frequencies: Vec<f64>,
    /// Φ (n × M), mass-normalised: ΦᵀMΦ = I.
    pub basis: Mat<f64>,
    /// C̃ = ΦᵀCΦ.
    pub c: Mat<f64>,
    /// G̃ = ΦᵀGΦ (per unit speed).
    pub g: Mat<f64>,
    /// K̃ = ΦᵀKΦ = diag(ω²).
    pub k: Mat<f64>,
    /// S̃ = ΦᵀSΦ.
    pub s: Mat<f64>,
    /// Φᵀ·unbalance (kg·m per mass-normalised coordinate).
    pub unbalance: Vec<c64>,
    /// P_cr (N).
    pub critical_load: f64,
    /// α.
    pub alpha: f64,
}

/// B(t) = B0 + β·cos(φt)·B1 of Eq. (25) for the state y = [q̇; q] (Eq. 24).
#[derive(Debug, Clone)]
pub struct PeriodicSystem {
    /// B0 = [−D̃, −(K̃ − αP_cr·S̃); I, 0] with D̃ = C̃ − jΩG̃.
    pub b0: Mat<c64>,
    /// B1 = [0, P_cr·S̃; 0, 0]; nilpotent (B1² = 0).
    pub b1: Mat<c64>,
}

impl PeriodicSystem {
    /// The diagonal scaling s of the state y = [q̇; q] into [q̇; w·q]: s_i = 1 for the
    /// velocities and w_i = √|K̃eff_ii| (at least 1) for the displacements, from B0's
    /// stiffness block. B0 holds ω² next to the identity block, so ‖hB0‖ ~ hω²_max and an
    /// exponential of hB0 needs many squarings, each of which amplifies its round-off; in
    /// the scaled coordinates every block is ~ω and ‖hB0‖ ~ hω_max. Exponentials are taken
    /// of s·(hB)·s⁻¹ and scaled back, E_ij = E'_ij·s_j/s_i: the same matrix, to round-off.
    pub fn frequency_scaling(&self) -> Vec<f64> {
        let m = self.b0.nrows() / 2;
        (0..2 * m).map(|i| if i < m { 1.0 } else { self.b0[(i - m, i)].norm().sqrt().max(1.0) }).collect()
    }
}

/// Summary of a reduced model for outputs.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ReductionInfo {
    /// M.
    pub modes: usize,
    /// Basis frequencies (rad/s).
    pub frequencies: Vec<f64>,
}

fn project(phi: &Mat<f64>, a: &Mat<f64>) -> Mat<f64> {
    let m = phi.ncols();
    let n = phi.nrows();
    let mut ap = Mat::<f64>::zeros(n, m);
    for i in 0..n {
        for k in 0..n {
            let x = a[(i, k)];
            if x != 0.0 {
                for j in 0..m {
                    ap[(i, j)] += x * phi[(k, j)];
                }
            }
        }
    }
    let mut out = Mat::<f64>::zeros(m, m);
    for i in 0..m {
        for j in 0..m {
            out[(i, j)] = (0..n).map(|k| phi[(k, i)] * ap[(k, j)]).sum();
        }
    }
    // Exact symmetry of the projection of a symmetric matrix.
    Mat::from_fn(m, m, |i, j| 0.5 * (out[(i, j)] + out[(j, i)]))
}

impl ReducedModel {
    /// Reduce a prepared rotor to its first `count` modes.
    pub fn new(rotor: &Rotor, count: usize) -> Result<ReducedModel, AnalysisError> {
        let sys = &rotor.system;
        // M x = θ K x: θ = 1/ω², massless DOFs give θ = 0 (ω = ∞) and are never selected.
        let eig = definite_eigen(sys.k.as_ref(), sys.m.as_ref())?;
        let available = eig.values.iter().filter(|t| **t > 0.0).count();
        if count == 0 || count > available {
            return Err(AnalysisError::ReducedModes { requested: count, available });
        }
        let n = sys.size();
        let theta = &eig.values[..count];
        // x with xᵀKx = 1 → mass-normalise: x/√θ has xᵀMx = 1.
        let basis = Mat::from_fn(n, count, |i, j| eig.vectors[(i, j)] / theta[j].sqrt());
        let frequencies = theta.iter().map(|t| (1.0 / t).sqrt()).collect();
        let unbalance = (0..count).map(|j| (0..n).map(|i| sys.unbalance[i] * basis[(i, j)]).sum()).collect();
        Ok(ReducedModel {
            frequencies,
            c: project(&basis, &sys.c),
            g: project(&basis, &sys.g),
            k: project(&basis, &sys.k),
            s: project(&basis, &sys.s),
            basis,
            unbalance,
            critical_load: rotor.critical_load,
            alpha: rotor.model.load.alpha,
        })
    }

    /// Number of modes M.
    pub fn size(&self) -> usize {
        self.frequencies.len()
    }

    /// B0 and B1 at speed Ω (rad/s).
    pub fn periodic_system(&self, speed: f64) -> PeriodicSystem {
        let m = self.size();
        let p = self.critical_load;
        let z = c64::new(0.0, 0.0);
        let b0 = Mat::from_fn(2 * m, 2 * m, |i, j| match (i < m, j < m) {
            (true, true) => c64::new(-self.c[(i, j)], speed * self.g[(i, j)]),
            (true, false) => c64::new(-(self.k[(i, j - m)] - self.alpha * p * self.s[(i, j - m)]), 0.0),
            (false, true) => c64::new(if i - m == j { 1.0 } else { 0.0 }, 0.0),
            (false, false) => z,
        });
        let b1 =
            Mat::from_fn(2 * m, 2 * m, |i, j| if i < m && j >= m { c64::new(p * self.s[(i, j - m)], 0.0) } else { z });
        PeriodicSystem { b0, b1 }
    }

    /// Summary for outputs.
    pub fn info(&self) -> ReductionInfo {
        ReductionInfo { modes: self.size(), frequencies: self.frequencies.clone() }
    }
}
