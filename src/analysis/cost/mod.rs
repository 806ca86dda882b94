//! What a run costs, counted from its plan before it starts: the counts the run will
//! make (grid points, seeds and lattice points of a search, candidates × speeds) times
//! what one of each costs (floating-point operations of a kernel from its matrix sizes;
//! bytes of the dense matrices held at once). The count only refuses what is plainly too
//! big ([`Budget::admit`](crate::run::Budget::admit), at the limits of [`crate::run`]): a
//! slip of units or digits. A run
//! admitted is bounded while it runs by the counts it keeps itself (its time measured
//! there, its monodromy evaluations against the allowance the count gives,
//! [`crate::run::Budget`]).
//!
//! - **work**: floating-point operations: the leading terms
//!   of each kernel (Golub and Van Loan, *Matrix Computations*) at the sizes it runs at
//!   (the model's DOFs; the reduced model's state dimension n = 2M), times its calls
//!   (CFM4 steps per period, which grow like 1/φ and ω_max/φ and double with β; RK4
//!   steps; β samples up to β_max);
//! - **memory**: bytes of the dense matrices a run holds at once.

mod dense;
mod floquet;
mod regions;

pub use dense::{dense, unbalance, Dense};
pub use floquet::{chart, floquet_point, response_of, PointCost};
pub use regions::{
    band, band_and_margins, catalogue, points, scan, CROSSING_EVALUATIONS, DESIGN_BAND_EVALUATIONS, LEVEL_EVALUATIONS,
    SEED_EVALUATIONS, START_EVALUATIONS,
};

use super::floquet::FloquetSystem;
use super::limits::compact;
use super::regions::{seeds::Seed, RegionSettings};
use super::{Criterion, Interval, MonodromyMethod};
use serde::Serialize;

// Operation counts of the kernels: real floating-point operations (a complex multiply-add
// is 8), n the state dimension 2M of the reduced model or the DOFs of the full one.
// Matrices smaller than 8 × 8 count as 8 × 8 (`cubed`): below that a call's fixed work
// (dispatch, bookkeeping, the result's allocation) is no longer small beside its
// arithmetic.

/// n³ at the size a kernel's count is taken at: at least [`SMALLEST_COUNTED`].
fn cubed(n: f64) -> f64 {
    n.max(SMALLEST_COUNTED).powi(3)
}
/// The smallest matrix size counted (module comment above).
const SMALLEST_COUNTED: f64 = 8.0;
/// One CFM4 step of the fast path: the step's exponential summed from the per-φ table's
/// Chebyshev coefficients (a real 2n² × p by p product, 4pn², p ≤ 20 for a converged
/// table) and its complex product into the monodromy (8n³).
fn step_ops(n: f64) -> f64 {
    8.0 * cubed(n) + 80.0 * n * n
}
/// Eigenvalues of the complex n × n monodromy (Hessenberg reduction and shifted QR, about
/// 10n³ complex operations), per n³.
const EIG_OPS_N3: f64 = 40.0;
/// One exponential at a Chebyshev point: a Taylor polynomial by Paterson–Stockmeyer, about
/// eight complex products, per n³.
const EXP_OPS_N3: f64 = 64.0;
/// One DSTM step: a Padé-13 exponential with scaling and squaring (six products, a solve
/// and about three squarings: some twelve complex products' work) and its product into
/// the monodromy, per n³.
const DSTM_STEP_OPS_N3: f64 = 104.0;
/// One RK4 step of the response: four right-hand sides, each two complex n × n
/// matrix-vector products (B0·y and B1·y), and the vector updates.
fn rk4_ops(n: f64) -> f64 {
    64.0 * n.max(SMALLEST_COUNTED).powi(2) + 64.0 * n
}
/// The symmetric-definite eigensolution of the full model with its vectors (buckling load
/// or modal basis): Cholesky, reduction to standard form, tridiagonalisation and the
/// implicit QR with vectors, about 14n³.
const DENSE_EIGEN_OPS_N3: f64 = 14.0;
/// The quadratic eigenproblem of the full model: the complex nonsymmetric eigenproblem of
/// its 2n × 2n linearisation with vectors, about 25(2n)³ complex operations, per (2n)³.
const QEP_OPS_2N3: f64 = 100.0;
/// One sparse LU factorisation and solve of the dynamic stiffness, per DOF
/// (`analysis::unbalance`): the shaft's band keeps the factors' fill fixed per DOF, about
/// 8b² complex operations per row for a half-bandwidth b ≤ 11.
const UNBALANCE_SOLVE_OPS_N: f64 = 1000.0;

/// Peak bytes per DOF² of a rotor and its symmetric eigensolutions (`check`: 90 MB at 808
/// DOFs, 334 MB at 1 608).
const ROTOR_BYTES_N2: f64 = 130.0;
/// Bytes per DOF² of the assembled M, C, K, S, G (real, dense) and their copies.
const ASSEMBLED_BYTES_N2: f64 = 48.0;
/// Peak bytes per DOF² of the quadratic eigenproblem (`modes`: 346 MB at 808 DOFs, 1.27
/// GB at 1 608).
const QEP_BYTES_N2: f64 = 530.0;
/// Bytes per DOF² of the mode shapes kept per speed by a Campbell diagram (237 MB for 301
/// speeds at 132 DOFs).
const SHAPES_BYTES_N2: f64 = 40.0;

/// Peak bytes per probe and speed of an unbalance response: the values, and the JSON, CSV
/// and SVG text written from them (118 MB above the process's own for 5 probes × 100 001
/// speeds: 236 bytes).
const UNBALANCE_BYTES_PER_VALUE: f64 = 250.0;

/// What an estimate is driven by: the input a refusal names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Driver {
    /// The model's size: its DOFs (shaft elements, closed branches).
    Dofs,
    /// The lowest excitation frequency: steps per period grow like 1/φ.
    LowFrequency,
    /// How many points, speeds or values a grid or range holds.
    Grid,
    /// The load: β bracket samples grow like β_max, table steps double with β.
    Load,
    /// The reduced model's size M (`analysis.reduced_modes`) or frequencies.
    ReducedModel,
    /// The rotating speed Ω (a response's step resolves it).
    Speed,
    /// The periods of a time response.
    Periods,
    /// The candidates of a design (starts × iterations).
    Candidates,
    /// The builds a robust design judges (the corners of its tolerance box, its Monte
    /// Carlo samples) and the speeds of its speed range.
    Builds,
    /// The numerical settings (steps per period, DSTM steps).
    Settings,
}

/// One resource of an estimate: the amount, and what drives it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Part {
    /// Floating-point operations (work) or bytes (memory).
    pub amount: f64,
    /// The input that drives it.
    pub driver: Driver,
    /// How it comes about, e.g. `91 points × 2.4e304 CFM4 steps per period`.
    pub detail: String,
}

/// The counted cost of a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Estimate {
    /// Floating-point operations.
    pub work: Part,
    /// Bytes of dense matrices held at once.
    pub memory: Part,
    /// Monodromy evaluations of the region searches counted in `work` (0 for work that
    /// is not a region search): with `work`, the cost per evaluation that the run's
    /// allowance of evaluations ([`crate::run::Budget::allowance`]) is counted at.
    pub evaluations: f64,
}

impl Estimate {
    /// Nothing.
    pub fn zero() -> Estimate {
        let part = |driver| Part { amount: 0.0, driver, detail: String::new() };
        Estimate { work: part(Driver::Grid), memory: part(Driver::Dofs), evaluations: 0.0 }
    }

    /// A work-only estimate of `operations` floating-point operations.
    pub fn work(operations: f64, driver: Driver, detail: String) -> Estimate {
        Estimate { work: Part { amount: operations, driver, detail }, ..Estimate::zero() }
    }

    /// This run followed by `other`: the work adds (the larger part's driver kept), memory
    /// is the larger peak.
    pub fn then(self, other: Estimate) -> Estimate {
        let amount = self.work.amount + other.work.amount;
        let work = if other.work.amount > self.work.amount || self.work.amount.is_nan() {
            Part { amount, ..other.work }
        } else {
            Part { amount, ..self.work }
        };
        let memory = if other.memory.amount > self.memory.amount { other.memory } else { self.memory };
        Estimate { work, memory, evaluations: self.evaluations + other.evaluations }
    }

    /// `count` runs of this one in sequence (`what` names them). The count becomes the
    /// driver unless one run's own driver is an extreme input (a low frequency, a load) or
    /// a robust design's builds.
    pub fn times(mut self, count: f64, driver: Driver, what: &str) -> Estimate {
        self.work.amount *= count;
        self.evaluations *= count;
        if count > 1.0 {
            let each =
                if self.work.detail.is_empty() { String::new() } else { format!(", each: {}", self.work.detail) };
            self.work.detail = format!("{} {what}{each}", compact_count(count));
            if !matches!(self.work.driver, Driver::LowFrequency | Driver::Load | Driver::Speed | Driver::Builds) {
                self.work.driver = driver;
            }
        }
        self
    }
}

fn compact_count(x: f64) -> String {
    match x {
        x if !x.is_finite() => "unboundedly many".into(),
        x if x < 1e6 => format!("{}", x.round()),
        x => format!("{x:.2e}"),
    }
}
