//! Modal reduction of Eq. (22)–(23): the first M undamped modes of (K, M) at Ω = 0
//! without axial load (electrical modes included when the circuit is closed), and the
//! periodic state matrix of Eq. (24)–(25), B(t) = B0 + β·cos(φt)·B1.

use super::settings::Basis;
use super::{AnalysisError, Rotor};
use crate::linalg::definite_eigen;
use faer::{c64, Mat};
use serde::{Deserialize, Serialize};

/// Largest deviation of ΦᵀMΦ from I (any entry) accepted from the (K, M) eigenvectors
/// as they come. The Cholesky-of-K solve keeps the low modes M-orthonormal to ~1e-15 but
/// not the high FE modes: 2e-4 at M = 60 and 9e-3 at M = 136 on the Fig. 11 rotor, with
/// basis frequencies 4.5e-3 off the full model's. A basis beyond 1e-10 (far above
/// round-off, n·ε ≈ 1e-12 at 2000 elements) is re-orthonormalised; one within it is kept
/// bit for bit.
const MASS_ORTHONORMALITY_TOLERANCE: f64 = 1e-10;

/// Deviation of ΦᵀMΦ from I beyond which the (K, M) solve has not resolved the basis at
/// all (M-normalised vectors overlapping by 10 %): the masses and stiffnesses span more
/// orders of magnitude than it can hold. On the Fig. 11 rotor the deviation grows with
/// branch 1's inductance as 1e-10, 1e-8, 2e-6, 1e-4 and 1 for tuning frequencies of 1,
/// 0.1, 0.01, 1e-3 and 1e-5 rad/s (L up to 7.6e7 H); at 1e-10 rad/s the basis has lost
/// the rotor modes and (704 rad/s, 0.25), unstable with max|μ| ≈ 1.42 for a frozen
/// branch, read "stable".
const UNRESOLVED_BASIS: f64 = 0.1;

/// The reduced model: mass-normalised modes, so M̃ = I and K̃ = diag(ω²) (to round-off;
/// re-orthonormalised bases have K̃ nearly diagonal, see `MASS_ORTHONORMALITY_TOLERANCE`).
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
    /// K̃ = ΦᵀKΦ ≈ diag(ω²).
    pub k: Mat<f64>,
    /// S̃ = ΦᵀSΦ.
    pub s: Mat<f64>,
    /// Φᵀ·unbalance (kg·m per mass-normalised coordinate).
    pub unbalance: Vec<c64>,
    /// P_cr (N).
    pub critical_load: f64,
    /// Static load coefficient α (−).
    pub alpha: f64,
    /// Real coordinates (the general path): the basis spans both planes (2M real modes),
    /// `k` and `c` carry the supports at the speed and are not symmetric in general, and
    /// `g` is the skew G_r entering B0 as −Ω·G̃ (real) instead of jΩ·G̃.
    pub real: bool,
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

impl PeriodicSystem {
    /// Balanced eigenvalues λ of B0 (the reduced model at the static load), sorted by
    /// |Im λ|.
    pub fn eigenvalues(&self) -> Result<Vec<c64>, AnalysisError> {
        // B0 holds ω² next to 1: balance first, or λ is accurate only to ~ε·ω².
        let mut b0 = self.b0.clone();
        crate::linalg::balance(&mut b0);
        let mut ev = crate::linalg::seq::eigenvalues(b0.as_ref()).map_err(|_| {
            AnalysisError::Linalg(crate::linalg::LinalgError::NoConvergence { what: "reduced state matrix" })
        })?;
        ev.sort_by(|a, b| a.im.abs().total_cmp(&b.im.abs()).then(a.im.total_cmp(&b.im)));
        Ok(ev)
    }

    /// Forward (Im λ > 0) and backward whirl frequencies of B0 (rad/s), each ascending.
    pub fn whirls(&self) -> Result<(Vec<f64>, Vec<f64>), AnalysisError> {
        let ev = self.eigenvalues()?;
        let f = ev.iter().filter(|z| z.im > 0.0).map(|z| z.im).collect();
        let b = ev.iter().filter(|z| z.im < 0.0).map(|z| -z.im).collect();
        Ok((f, b))
    }
}

/// Summary of a reduced model for outputs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReductionInfo {
    /// Number of retained modes M.
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

/// Φᵀ·A·Φ of a matrix that need not be symmetric (no symmetrisation).
fn project_general(phi: &Mat<f64>, a: &Mat<f64>) -> Mat<f64> {
    let ap = crate::linalg::seq::product(a.as_ref(), phi.as_ref());
    crate::linalg::seq::product(phi.transpose(), ap.as_ref())
}

/// The undamped modes of a rotor's basis stiffness and mass at one speed, solved once:
/// any number of them makes a reduced model ([`ModeSet::reduced`]) without another
/// eigensolution, so that bases of several sizes (a schedule sized by convergence) cost
/// one solve.
#[derive(Debug, Clone)]
pub struct ModeSet {
    /// θ = 1/ω² descending and the K_b-orthonormal vectors of M x = θ K_b x.
    eig: crate::linalg::DefiniteEigen,
    /// The basis stiffness K_b.
    k_b: Mat<f64>,
    /// M, C, K, S, G of the coordinates the basis spans (complex, or real on the general
    /// path with the supports at the speed), and the unbalance.
    m: Mat<f64>,
    c: Mat<f64>,
    k: Mat<f64>,
    s: Mat<f64>,
    g: Mat<f64>,
    unbalance: Vec<c64>,
    /// 1, or 2 on the general path (two real modes per complex one).
    planes: usize,
    critical_load: f64,
    alpha: f64,
}

impl ModeSet {
    /// The modes of the kind `basis` of `rotor` at speed Ω (rad/s); on the general path
    /// those of the symmetric part of the real-coordinate stiffness at Ω, the supports'
    /// coefficients taken there.
    pub fn new(rotor: &Rotor, speed: f64, basis: Basis) -> Result<ModeSet, AnalysisError> {
        let (m, c, k, s, g, unbalance, k_sym, planes) = if rotor.real {
            let sys = rotor.general_at(speed);
            let k_sym = sys.symmetric_stiffness();
            (sys.m, sys.c, sys.k, sys.s, sys.g, sys.unbalance, k_sym, 2)
        } else {
            let sys = &rotor.system;
            let k_sym = sys.k.clone();
            (sys.m.clone(), sys.c.clone(), sys.k.clone(), sys.s.clone(), sys.g.clone(), sys.unbalance.clone(), k_sym, 1)
        };
        let k_b = basis_stiffness(&k_sym, &s, rotor, basis)?;
        // M x = θ K x: θ = 1/ω², massless DOFs give θ = 0 (ω = ∞) and are never selected.
        let eig = definite_eigen(k_b.as_ref(), m.as_ref())?;
        Ok(ModeSet {
            eig,
            k_b,
            m,
            c,
            k,
            s,
            g,
            unbalance,
            planes,
            critical_load: rotor.critical_load,
            alpha: rotor.model.load.alpha,
        })
    }

    /// The modes M a reduced model can have: the finite modes, per plane.
    pub fn available(&self) -> usize {
        self.eig.values.iter().filter(|t| **t > 0.0).count() / self.planes
    }

    /// The finite modes' frequencies √(1/θ) (rad/s), ascending: per real mode (both
    /// planes on the general path).
    pub fn frequencies(&self) -> Vec<f64> {
        self.eig.values.iter().filter(|t| **t > 0.0).map(|t| (1.0 / t).sqrt()).collect()
    }

    /// Whether the modes are of the real coordinates (the general path).
    pub fn real(&self) -> bool {
        self.planes == 2
    }

    /// The reduced model of the lowest `modes` modes (per plane; 2·`modes` real ones on the
    /// general path), mass-normalised, re-orthonormalised when the solve leaves them beyond
    /// `MASS_ORTHONORMALITY_TOLERANCE`.
    pub fn reduced(&self, modes: usize) -> Result<ReducedModel, AnalysisError> {
        let count = self.planes * modes;
        let available = self.eig.values.iter().filter(|t| **t > 0.0).count();
        if count == 0 || count > available {
            return Err(AnalysisError::ReducedModes { requested: modes, available: available / self.planes });
        }
        let n = self.m.nrows();
        let theta = &self.eig.values[..count];
        // x with xᵀKx = 1 → mass-normalise: x/√θ has xᵀMx = 1.
        let mut basis = Mat::from_fn(n, count, |i, j| self.eig.vectors[(i, j)] / theta[j].sqrt());
        let mut frequencies: Vec<f64> = theta.iter().map(|t| (1.0 / t).sqrt()).collect();
        let mass = project(&basis, &self.m);
        let drift = (0..count)
            .flat_map(|j| (0..count).map(move |i| (i, j)))
            .map(|(i, j)| (mass[(i, j)] - if i == j { 1.0 } else { 0.0 }).abs())
            .fold(0.0, f64::max);
        if drift.is_nan() || drift > UNRESOLVED_BASIS {
            return Err(AnalysisError::ReducedBasis { modes: count, drift });
        }
        if drift > MASS_ORTHONORMALITY_TOLERANCE {
            // Φ ← Φ·R⁻ᵀ with ΦᵀMΦ = R·Rᵀ (Cholesky; ≈ I, so well conditioned): exactly
            // M-orthonormal, the same span. K̃ is then no longer exactly diagonal; B0 takes
            // it whole, and the basis frequencies become its Rayleigh quotients √K̃_jj.
            let l = crate::linalg::seq::cholesky(mass.as_ref())
                .map_err(|_| AnalysisError::ReducedBasis { modes: count, drift })?;
            let mut rt = basis.transpose().to_owned();
            faer::linalg::triangular_solve::solve_lower_triangular_in_place(l.as_ref(), rt.as_mut(), faer::Par::Seq);
            basis = rt.transpose().to_owned();
            let k = project(&basis, &self.k_b);
            frequencies = (0..count).map(|j| k[(j, j)].sqrt()).collect();
        }
        let unbalance = (0..count).map(|j| (0..n).map(|i| self.unbalance[i] * basis[(i, j)]).sum()).collect();
        let real = self.real();
        // The complex path's matrices are symmetric: projected symmetric exactly; the general
        // path's supports need not be.
        let proj = |a: &Mat<f64>| if real { project_general(&basis, a) } else { project(&basis, a) };
        Ok(ReducedModel {
            frequencies,
            c: proj(&self.c),
            g: proj(&self.g),
            k: proj(&self.k),
            s: project(&basis, &self.s),
            basis,
            unbalance,
            critical_load: self.critical_load,
            alpha: self.alpha,
            real,
        })
    }
}

/// The stiffness whose modes make the basis: K itself ([`Basis::Unloaded`]), or
/// K − αP_cr·S ([`Basis::Loaded`]), which must then be positive definite (the static
/// load below the buckling load of the model as assembled).
fn basis_stiffness(k: &Mat<f64>, s: &Mat<f64>, rotor: &Rotor, basis: Basis) -> Result<Mat<f64>, AnalysisError> {
    match basis {
        Basis::Unloaded => Ok(k.clone()),
        Basis::Loaded => {
            let p = rotor.static_load();
            let k_b = Mat::from_fn(k.nrows(), k.ncols(), |i, j| k[(i, j)] - p * s[(i, j)]);
            match crate::linalg::seq::cholesky(k_b.as_ref()) {
                Ok(_) => Ok(k_b),
                Err(_) => Err(AnalysisError::StaticLoadBuckles {
                    alpha: rotor.model.load.alpha,
                    critical_load: rotor.critical_load,
                }),
            }
        }
    }
}

impl ReducedModel {
    /// Reduce a prepared rotor to its first `count` modes of the kind `basis`; on the
    /// general path ([`Rotor::real`]) to the first 2·`count` undamped modes of the
    /// symmetric part of the real-coordinate stiffness at speed Ω (rad/s), the supports'
    /// coefficients taken there: both planes of the complex basis, the electrical modes
    /// included ([`ModeSet`]).
    pub fn new(rotor: &Rotor, count: usize, speed: f64, basis: Basis) -> Result<ReducedModel, AnalysisError> {
        ModeSet::new(rotor, speed, basis)?.reduced(count)
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
        // −D̃ = −(C̃ − jΩG̃) in complex coordinates, −(C̃ + ΩG̃_r) in real ones.
        let minus_d = |i: usize, j: usize| {
            if self.real {
                c64::new(-self.c[(i, j)] - speed * self.g[(i, j)], 0.0)
            } else {
                c64::new(-self.c[(i, j)], speed * self.g[(i, j)])
            }
        };
        let b0 = Mat::from_fn(2 * m, 2 * m, |i, j| match (i < m, j < m) {
            (true, true) => minus_d(i, j),
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
