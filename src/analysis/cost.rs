//! What a run costs, estimated from its inputs before it starts, and the limits beyond
//! which a command refuses it (written once, here).
//!
//! Two resources are bounded:
//! - **time**: seconds of one core of the reference machine (the shared 2-core host the
//!   rates below were measured on; a faster host finishes sooner), at most
//!   [`MAX_SECONDS`];
//! - **memory**: bytes of the dense matrices a run holds at once, at most [`MAX_BYTES`].
//!
//! A [`Budget`] multiplies both limits (`--max-cost FACTOR`). Estimates are sums of counted
//! operations times measured rates: the dense eigensolvers from the model's DOFs (before
//! anything is assembled), and the Floquet work from the reduced model a command builds
//! anyway (its size M, its lowest and highest frequency and the parametric coupling of
//! B1), summed over the φ values a run visits: per-φ tables, CFM4 steps (whose number per
//! period grows like 1/φ and like ω_max/φ, and doubles with β), β bracket samples (β_max
//! over the bracket step), seeds and the guard lattice of a range. They are cheap
//! (closed forms and sums over at most a few thousand φ values) and mostly upper bounds:
//! a search counts every evaluation its bounds allow.

use super::floquet::{FloquetSystem, ALIAS_MARGIN, ALIAS_ORDERS};
use super::limits::{self, compact, ParamError};
use super::regions::start::SCREENING_TOLERANCE;
use super::regions::{seeds::Seed, RegionSettings, CENTRE_WINDOW};
use super::{Criterion, Interval, MonodromyMethod};
use crate::assembly::DofMap;
use crate::model::Model;
use serde::Serialize;
use thiserror::Error;

/// Most seconds of computing (one core of the reference machine) a run may be estimated
/// at: one hour. The estimates are upper bounds (every evaluation a search's bounds allow,
/// at the largest measured rates), 2 to 200 times the measured time: the Fig. 11
/// catalogue is estimated at 9 s and takes 1.6 s, with `--beta-max 100` at 385 s and
/// takes 2.1 s. The bundled problems' largest estimate, the clear-bands design (284 s),
/// is 12 times below the limit. The runs the limit is for are estimated at 10⁴ s and
/// far beyond (φ = 1e-3 for 1e3 in a response: 4·10⁴ s; φ near 1e-300: 10³⁰⁰ s): a slip of
/// units or digits more often than an intent, and `--max-cost` admits them deliberately.
pub const MAX_SECONDS: f64 = 3600.0;

/// Most bytes of dense matrices a run may hold at once: 400 MiB. With the process's own
/// ~20 MB the peak stays under 500 MB; `check` reaches it near 880 shaft elements, the
/// whirl solvers (`modes`, `campbell`, `regions`, `band`) near 440.
pub const MAX_BYTES: f64 = 400.0 * 1024.0 * 1024.0;

// Rates of the kernels on the reference machine (one thread, release build), n the state
// dimension 2M of the reduced model or the DOFs of the full one. Measured with the
// problems' models at M = 4, 8, 16 and 64–800 shaft elements; each rate is the largest
// seen, so the estimates lean high.

/// One CFM4 exponential applied (split-form product and its share of the batched
/// Chebyshev sums): 3.0e-7, 1.2e-6 and 6e-6 s at n = 8, 16, 32.
const STEP_N3: f64 = 3.0e-10;
const STEP_FIXED: f64 = 2.0e-7;
/// Eigenvalues of the n×n monodromy (balanced): 7e-6, 6e-5, 2.9e-4 s at n = 8, 16, 32.
const EIG_N3: f64 = 1.5e-8;
/// One exponential at a Chebyshev point (Taylor, split form): 2e-6, 6e-6, 3.6e-5 s.
const EXP_N3: f64 = 1.5e-9;
const EXP_FIXED: f64 = 1.5e-6;
/// One DSTM step (Padé exponential and product): ~22 µs at n = 16.
const DSTM_N3: f64 = 1.0e-8;
/// One RK4 step of the response (four dense right-hand sides): 4.6e-7 s at n = 8,
/// 1.5e-6 s at n = 16.
const RK4_N2: f64 = 8.0e-9;
/// The symmetric-definite eigensolution of the full model (buckling load or modal basis):
/// 0.24 s at 808 DOFs, 1.8 s at 1 608.
const DENSE_EIGEN_N3: f64 = 4.5e-10;
/// The quadratic eigenproblem of the full model by shift-invert (complex 2n × 2n): 0.35 s
/// at 208 DOFs, 24 s at 808, 261 s at 1 608: per (2n)³.
const QEP_2N3: f64 = 8.0e-9;
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

/// One numeric sparse LU factorisation and solve of the dynamic stiffness per DOF
/// (`analysis::unbalance`; the shaft's band keeps the factors' fill fixed per DOF):
/// 44–51 µs at 136 DOFs (0.35 µs per DOF, `cargo bench --bench unbalance`, host shared);
/// 1e-6 s per DOF leans high, as the other rates do.
const UNBALANCE_SOLVE_N: f64 = 1.0e-6;

/// Peak bytes per probe and speed of an unbalance response: the values, and the JSON, CSV
/// and SVG text written from them (118 MB above the process's own for 5 probes × 100 001
/// speeds: 236 bytes).
const UNBALANCE_BYTES_PER_VALUE: f64 = 250.0;

/// Chebyshev point counts the fast path's per-φ table tries (`floquet::fast`).
const CHEBYSHEV_DEGREES: [usize; 15] = [4, 5, 6, 7, 8, 9, 10, 12, 14, 16, 20, 24, 32, 48, 64];
/// The table's step doubling: while the coupling per exponential exceeds this, up to
/// [`TABLE_STEPS`] steps (`floquet::fast`).
const TABLE_COUPLING: f64 = 2.0;
const TABLE_STEPS: f64 = 4096.0;
/// Largest |x| = β·|ξ| per unit β of the CFM4 exponentials: 2(|w₁| + |w₂|) = 2/√3.
const XI_MAX: f64 = 1.154_700_538_379_251_5;

/// Evaluations of a tip climb: three to bracket, doubling steps across the start window
/// (2e-5 to 3e-3 of φ: 8) and the refinement (`tip_iterations`).
const CLIMB_BRACKET: f64 = 3.0 + 8.0;
/// Evaluations of one seed's search at the level: the centre search (1 + its iterations,
/// each with eigenvectors: counted twice), the lock test (2), the crest climb and its
/// check; and of its tongue's two edges (the first growing march steps and the lattice
/// refinement: 13 each).
const HIT_FIXED: f64 = 2.0 + CLIMB_BRACKET + 1.0;
const EDGE_EVALUATIONS: f64 = 26.0;
/// Evaluations of one tracked level of a boundary: the inside point (up to 10 tries) and
/// both edges.
const TRACK_EVALUATIONS: f64 = 40.0;
/// Evaluations a widest-band design spends per candidate and speed on its band: the
/// bundled problem takes 105 on average (21 711 over 207 candidates); five times that.
pub const DESIGN_BAND_EVALUATIONS: f64 = 500.0;

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
    /// The numerical settings (steps per period, DSTM steps).
    Settings,
}

/// One resource of an estimate: the amount, and what drives it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Part {
    /// Seconds (time) or bytes (memory).
    pub amount: f64,
    /// The input that drives it.
    pub driver: Driver,
    /// How it comes about, e.g. `91 points × 2.4e304 CFM4 steps per period`.
    pub detail: String,
}

/// The estimated cost of a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Estimate {
    /// Seconds of computing on one core of the reference machine.
    pub time: Part,
    /// Bytes of dense matrices held at once.
    pub memory: Part,
}

impl Estimate {
    /// Nothing.
    pub fn zero() -> Estimate {
        let part = |driver| Part { amount: 0.0, driver, detail: String::new() };
        Estimate { time: part(Driver::Grid), memory: part(Driver::Dofs) }
    }

    /// A time-only estimate.
    pub fn time(seconds: f64, driver: Driver, detail: String) -> Estimate {
        Estimate { time: Part { amount: seconds, driver, detail }, ..Estimate::zero() }
    }

    /// This run followed by `other`: times add (the larger part's driver kept), memory is
    /// the larger peak.
    pub fn then(self, other: Estimate) -> Estimate {
        let amount = self.time.amount + other.time.amount;
        let time = if other.time.amount > self.time.amount || self.time.amount.is_nan() {
            Part { amount, ..other.time }
        } else {
            Part { amount, ..self.time }
        };
        let memory = if other.memory.amount > self.memory.amount { other.memory } else { self.memory };
        Estimate { time, memory }
    }

    /// `count` runs of this one in sequence (`what` names them). The count becomes the
    /// driver unless one run's own driver is an extreme input (a low frequency, a load).
    pub fn times(mut self, count: f64, driver: Driver, what: &str) -> Estimate {
        self.time.amount *= count;
        if count > 1.0 {
            self.time.detail = if self.time.detail.is_empty() {
                format!("{} {what}", compact_count(count))
            } else {
                format!("{} {what}, each: {}", compact_count(count), self.time.detail)
            };
            if !matches!(self.time.driver, Driver::LowFrequency | Driver::Load | Driver::Speed) {
                self.time.driver = driver;
            }
        }
        self
    }
}

fn compact_count(x: f64) -> String {
    if !x.is_finite() {
        "unboundedly many".into()
    } else if x < 1e6 {
        format!("{}", x.round())
    } else {
        format!("{x:.2e}")
    }
}

/// Seconds as a person reads them.
fn seconds_text(s: f64) -> String {
    if !s.is_finite() {
        "an unbounded time".into()
    } else if s >= 1e7 {
        format!("{s:.1e} s")
    } else if s >= 7200.0 {
        format!("{:.1} h", s / 3600.0)
    } else {
        format!("{s:.0} s")
    }
}

/// Bytes as a person reads them (MiB, GiB).
fn bytes_text(b: f64) -> String {
    const MIB: f64 = 1024.0 * 1024.0;
    if !b.is_finite() {
        "unbounded memory".into()
    } else if b >= 1e6 * MIB {
        format!("{b:.1e} bytes")
    } else if b >= 1024.0 * MIB {
        format!("{:.1} GiB", b / (1024.0 * MIB))
    } else {
        format!("{:.0} MiB", b / MIB)
    }
}

/// Which limit an estimate broke.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Resource {
    /// Computing time.
    Time,
    /// Memory of dense matrices.
    Memory,
}

/// A run refused before it started: its estimated cost is beyond the limit.
#[derive(Debug, Clone, PartialEq, Error, Serialize)]
#[error(
    "{what} would {} {}, more than the {}{} allowed: {detail}; change {parameter}, or allow FACTOR times more with --max-cost FACTOR",
    if *resource == Resource::Time { "take" } else { "need" },
    amount_text(*resource, *estimate),
    limit_text(*resource, *limit),
    if *factor == 1.0 { String::new() } else { format!(" (--max-cost {})", compact(*factor)) },
)]
pub struct CostError {
    /// What would run, e.g. `the chart`, `check`.
    pub what: String,
    /// Time or memory.
    pub resource: Resource,
    /// The estimate (s or bytes).
    pub estimate: f64,
    /// The limit (s or bytes), with the factor applied.
    pub limit: f64,
    /// The `--max-cost` factor in force.
    pub factor: f64,
    /// The key or flag that drives the estimate, e.g. `--phi`, `shaft.elements`.
    pub parameter: String,
    /// How the estimate comes about.
    pub detail: String,
}

fn amount_text(resource: Resource, x: f64) -> String {
    match (resource, x.is_finite()) {
        (Resource::Time, true) => format!("about {} of computing", seconds_text(x)),
        (Resource::Memory, true) => format!("about {} of memory", bytes_text(x)),
        (_, false) => limit_text(resource, x),
    }
}

fn limit_text(resource: Resource, x: f64) -> String {
    match resource {
        Resource::Time => seconds_text(x),
        Resource::Memory => bytes_text(x),
    }
}

/// The limits of a run: [`MAX_SECONDS`] and [`MAX_BYTES`] times a factor (`--max-cost`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Budget {
    factor: f64,
    /// Runs sharing the memory limit.
    memory_share: f64,
}

impl Default for Budget {
    fn default() -> Budget {
        Budget { factor: 1.0, memory_share: 1.0 }
    }
}

impl Budget {
    /// The limits times `factor` (finite, > 0).
    pub fn new(factor: f64) -> Result<Budget, ParamError> {
        Ok(Budget { factor: limits::cost_factor(factor)?, memory_share: 1.0 })
    }

    /// This budget with its memory limit divided among `parts` runs held at once (the
    /// cases of a study run in parallel); the time limit stays each run's own.
    pub fn share(self, parts: f64) -> Budget {
        Budget { memory_share: self.memory_share * parts.max(1.0), ..self }
    }

    /// The factor.
    pub fn factor(&self) -> f64 {
        self.factor
    }

    /// The time limit (s).
    pub fn seconds(&self) -> f64 {
        MAX_SECONDS * self.factor
    }

    /// The memory limit (bytes) of one run.
    pub fn bytes(&self) -> f64 {
        MAX_BYTES * self.factor / self.memory_share
    }

    /// Refuse `estimate` of `what` when either part is beyond its limit (or not finite),
    /// naming the input `name` gives for the driver.
    pub fn admit(&self, what: &str, estimate: &Estimate, name: &dyn Fn(Driver) -> String) -> Result<(), CostError> {
        let refuse = |resource, part: &Part, limit: f64| CostError {
            what: what.to_string(),
            resource,
            estimate: part.amount,
            limit,
            factor: self.factor,
            parameter: name(part.driver),
            detail: part.detail.clone(),
        };
        // A NaN estimate cannot be bounded: refused like an infinite one.
        if estimate.memory.amount.is_nan() || estimate.memory.amount > self.bytes() {
            return Err(refuse(Resource::Memory, &estimate.memory, self.bytes()));
        }
        if estimate.time.amount.is_nan() || estimate.time.amount > self.seconds() {
            return Err(refuse(Resource::Time, &estimate.time, self.seconds()));
        }
        Ok(())
    }
}

/// Complex DOFs of a model: 2 per shaft node, 1 per ring, 1 per closed branch of each
/// ring ([`DofMap::len`]).
pub fn model_dofs(model: &Model) -> usize {
    DofMap::of(model).len()
}

/// The dense stages a command runs on the full model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dense {
    /// Assembly and the buckling load (`check`, and every command first).
    Rotor,
    /// Rotor, and the modal basis of the reduced model (Floquet commands).
    Reduced,
    /// Rotor, and the quadratic eigenproblem at `n` speeds (whirls: `modes`, `campbell`),
    /// keeping the mode shapes of every speed when `n` > 1.
    Whirls(usize),
    /// Rotor, modal basis and whirls at one speed (`regions`, `band`).
    ReducedAndWhirls,
}

/// The dense work of `stage` on `model`, from its DOFs alone (nothing is assembled).
/// `threads` stages may run at once (a Campbell diagram's speeds).
pub fn dense(model: &Model, stage: Dense, threads: usize) -> Estimate {
    let n = model_dofs(model) as f64;
    // P_cr is computed on the open-circuit model unless the file gives it.
    let open = DofMap { nodes: model.shaft.nodes(), branches: vec![0; model.rings.len()] }.len() as f64;
    let buckling = if model.load.critical_load.is_some() { 0.0 } else { DENSE_EIGEN_N3 * open.powi(3) };
    let eigen = DENSE_EIGEN_N3 * n.powi(3);
    let qep = QEP_2N3 * (2.0 * n).powi(3);
    let dofs = format!("{} complex DOFs", n);
    // Without the buckling eigenproblem a rotor is its five assembled matrices.
    let rotor_bytes = if buckling > 0.0 { ROTOR_BYTES_N2 } else { ASSEMBLED_BYTES_N2 } * n * n;
    let (seconds, bytes, memory_driver, memory_detail) = match stage {
        Dense::Rotor => (buckling, rotor_bytes, Driver::Dofs, dofs.clone()),
        Dense::Reduced => (buckling + eigen, ROTOR_BYTES_N2 * n * n, Driver::Dofs, dofs.clone()),
        Dense::ReducedAndWhirls => (buckling + eigen + qep, QEP_BYTES_N2 * n * n, Driver::Dofs, dofs.clone()),
        Dense::Whirls(speeds) => {
            let s = speeds.max(1) as f64;
            let shapes = if speeds > 1 { SHAPES_BYTES_N2 * n * n * s } else { 0.0 };
            let working = QEP_BYTES_N2 * n * n * (threads.max(1).min(speeds.max(1)) as f64);
            let driver = if shapes > working { Driver::Grid } else { Driver::Dofs };
            let detail =
                if speeds > 1 { format!("{speeds} speeds × the mode shapes of {dofs}") } else { dofs.clone() };
            (buckling + qep * s, working + shapes, driver, detail)
        }
    };
    let time_detail = match stage {
        Dense::Whirls(s) if s > 1 => format!("{s} whirl eigenproblems of {dofs}"),
        _ => format!("the dense eigenproblems of {dofs}"),
    };
    let time_driver = match stage {
        Dense::Whirls(s) if s > 1 && qep * s as f64 > (buckling + qep) * 4.0 => Driver::Grid,
        _ => Driver::Dofs,
    };
    Estimate {
        time: Part { amount: seconds, driver: time_driver, detail: time_detail },
        memory: Part { amount: bytes, driver: memory_driver, detail: memory_detail },
    }
}

/// The unbalance response of `model` at `speeds` speeds with `nodes` extra probes: the
/// rotor (assembly and P_cr), one sparse solve per speed, and at most
/// [`super::unbalance::SOLVES_PER_PEAK`] solves for each possible peak of each probe (an
/// upper bound: every other grid speed, and at most 4 per DOF, of every disk node,
/// support and node).
pub fn unbalance(model: &Model, speeds: usize, nodes: usize) -> Estimate {
    let n = model_dofs(model) as f64;
    let probes =
        (super::unbalance::disk_nodes(model).len() + model.bearings.len() + 2 * model.rings.len() + nodes) as f64;
    // |U_dof(Ω)|² is a ratio of polynomials in Ω of degree at most 4n (A(Ω) is quadratic
    // in Ω: det A and the cofactors have degree ≤ 2n), so it has at most 8n stationary
    // points and 4n local maxima, and a grid at most one peak per two speeds.
    let peaks = probes * ((speeds / 2) as f64).min(4.0 * n);
    let solves = speeds as f64 + peaks * super::unbalance::SOLVES_PER_PEAK as f64;
    let detail = format!(
        "{} sparse solves of {n} complex DOFs ({speeds} speeds, {} peaks at most)",
        compact_count(solves),
        compact_count(peaks)
    );
    let mut response = Estimate::time(solves * UNBALANCE_SOLVE_N * n, Driver::Grid, detail);
    response.memory = Part {
        amount: UNBALANCE_BYTES_PER_VALUE * probes * speeds as f64,
        driver: Driver::Grid,
        detail: format!("{} probes × {speeds} speeds of results and their JSON, CSV and SVG text", probes),
    };
    dense(model, Dense::Rotor, 1).then(response)
}

/// The cost of Floquet evaluations on one reduced model: what a per-φ table, a CFM4 or
/// DSTM monodromy and an RK4 step cost, from its size, frequencies and coupling.
#[derive(Debug, Clone, PartialEq)]
pub struct PointCost {
    /// State dimension n = 2M.
    n: f64,
    w_min: f64,
    w_max: f64,
    /// ‖τ⁻¹·B1‖₁ in the fast path's frequency-scaled coordinates (1/s).
    coupling: f64,
    steps_per_period: f64,
    max_step_phase: f64,
    method: MonodromyMethod,
    reference_steps: f64,
    speed: f64,
}

impl PointCost {
    /// The costs of `fs`.
    pub fn of(fs: &FloquetSystem) -> PointCost {
        let f = &fs.reduced.frequencies;
        let n = fs.system.b0.nrows();
        let m = n / 2;
        // The fast path exponentiates τ(B0 + xB1) in the coordinates [q̇; w·q], w_i the
        // modal frequency: B1's block P_cr·S̃ is divided by w of its column there.
        let scale = |j: usize| fs.system.b0[(j - m, j)].norm().sqrt().max(1.0);
        let coupling =
            (m..n).map(|j| (0..m).map(|i| fs.system.b1[(i, j)].norm()).sum::<f64>() / scale(j)).fold(0.0, f64::max);
        PointCost {
            n: n as f64,
            w_min: f.iter().copied().fold(f64::INFINITY, f64::min),
            w_max: f.iter().copied().fold(0.0, f64::max),
            coupling,
            steps_per_period: fs.settings.steps_per_period as f64,
            max_step_phase: fs.settings.max_step_phase,
            method: fs.settings.method,
            reference_steps: fs.settings.reference_steps as f64,
            speed: fs.speed,
        }
    }

    fn step(&self) -> f64 {
        STEP_N3 * self.n.powi(3) + STEP_FIXED
    }

    fn eig(&self) -> f64 {
        EIG_N3 * self.n.powi(3)
    }

    fn exp(&self) -> f64 {
        EXP_N3 * self.n.powi(3) + EXP_FIXED
    }

    /// CFM4 steps per period the step rule asks for at φ (rad/s): at least the settings'
    /// minimum, h·ω_min ≤ `max_step_phase`, and clear of the aliased resonance
    /// ([`FloquetSystem::steps_for`], without its cap of 10⁶: a period that needs more is
    /// not resolved by fewer).
    pub fn steps(&self, phi: f64) -> f64 {
        let period = 2.0 * std::f64::consts::PI / phi;
        let by_phase = (period * self.w_min / self.max_step_phase).ceil();
        let by_alias = (ALIAS_MARGIN * 2.0 * self.w_max / phi).ceil() + ALIAS_ORDERS as f64;
        let needed = by_phase.max(by_alias);
        if needed.is_nan() {
            f64::INFINITY
        } else {
            self.steps_per_period.max(needed)
        }
    }

    /// A per-φ table for loads up to β: (seconds, steps per period of its monodromies).
    /// Each attempt costs its Chebyshev exponentials; the steps double while the coupling
    /// per exponential exceeds 2 (up to 4096 steps).
    pub fn table(&self, phi: f64, beta: f64) -> (f64, f64) {
        let mut steps = self.steps(phi);
        if !steps.is_finite() {
            return (f64::INFINITY, f64::INFINITY);
        }
        steps = (2.0 * (steps / 2.0).ceil()).max(2.0);
        let per_step = XI_MAX * beta * std::f64::consts::PI / phi * self.coupling;
        let mut seconds = 0.0;
        loop {
            let a = per_step / steps;
            seconds += chebyshev_points(a) * self.exp();
            if a <= TABLE_COUPLING || steps >= TABLE_STEPS || !a.is_finite() {
                return (seconds, steps);
            }
            steps *= 2.0;
        }
    }

    /// One monodromy at load β on a table built for `beta_table` ≥ β (s): its steps and
    /// the eigenvalues; by the DSTM if that is the method.
    pub fn monodromy(&self, phi: f64, beta_table: f64) -> f64 {
        match self.method {
            MonodromyMethod::Fast => self.table(phi, beta_table).1 * self.step() + self.eig(),
            MonodromyMethod::Dstm => self.dstm(),
        }
    }

    /// One monodromy on a table of its own (s): what a search's point costs.
    pub fn point(&self, phi: f64, beta: f64) -> f64 {
        let (table, steps) = self.table(phi, beta);
        table + steps * self.step() + self.eig()
    }

    /// One point by the configured method (s), as `floquet` computes it.
    pub fn point_by_method(&self, phi: f64, beta: f64) -> f64 {
        match self.method {
            MonodromyMethod::Fast => self.point(phi, beta),
            MonodromyMethod::Dstm => self.dstm(),
        }
    }

    /// One DSTM monodromy with the settings' reference steps (s).
    pub fn dstm(&self) -> f64 {
        self.dstm_with(self.reference_steps)
    }

    /// One DSTM monodromy with `steps` steps (s).
    pub fn dstm_with(&self, steps: f64) -> f64 {
        steps * (DSTM_N3 * self.n.powi(3) + 2e-6) + self.eig()
    }

    /// Driver and detail of a point at φ: the low frequency when its steps exceed the
    /// settings' minimum many times, the reduced model when its size makes a step dear.
    fn point_driver(&self, phi: f64) -> (Driver, String) {
        if self.method == MonodromyMethod::Dstm {
            return (Driver::Settings, format!("{} DSTM steps per point", compact(self.reference_steps)));
        }
        let steps = self.steps(phi);
        if steps.is_nan() || steps > 16.0 * self.steps_per_period {
            let why = format!("at phi = {} rad/s a period needs {} CFM4 steps", compact(phi), compact_count(steps));
            return (Driver::LowFrequency, why);
        }
        (Driver::ReducedModel, format!("M = {} modes, {} CFM4 steps per period", self.n / 2.0, compact_count(steps)))
    }
}

/// Chebyshev points of a converged interpolant at coupling `a` per exponential (the first
/// count whose coefficient bound 2(a/2)^k/k! is below a tenth of 1e-11); where the
/// coupling is too large for that, every count up to 64 is tried.
fn chebyshev_points(a: f64) -> f64 {
    let bound = |p: usize| 2.0 * (1..=p - 2).fold(1.0, |acc, i| acc * (a / 2.0) / i as f64);
    match CHEBYSHEV_DEGREES.iter().position(|&p| bound(p) <= 1e-12) {
        Some(i) if a <= TABLE_COUPLING => CHEBYSHEV_DEGREES[i] as f64,
        Some(i) => CHEBYSHEV_DEGREES[i..].iter().sum::<usize>() as f64,
        None => CHEBYSHEV_DEGREES[6..].iter().sum::<usize>() as f64,
    }
}

/// One Floquet point by the configured method (`floquet`).
pub fn floquet_point(pc: &PointCost, phi: f64, beta: f64) -> Estimate {
    let (driver, detail) = pc.point_driver(phi);
    Estimate::time(pc.point_by_method(phi, beta), driver, detail)
}

/// A chart: one table per φ (to the grid's largest β) and a monodromy per point.
pub fn chart(pc: &PointCost, phis: &[f64], betas: &[f64]) -> Estimate {
    let beta_max = betas.iter().fold(0.0f64, |m, b| m.max(b.abs()));
    let nb = betas.len() as f64;
    let seconds: f64 = phis
        .iter()
        .map(|&phi| match pc.method {
            MonodromyMethod::Fast => pc.table(phi, beta_max).0 + nb * pc.monodromy(phi, beta_max),
            MonodromyMethod::Dstm => nb * pc.dstm(),
        })
        .sum();
    let lowest = phis.iter().copied().fold(f64::INFINITY, f64::min);
    let (driver, why) = pc.point_driver(lowest);
    let detail = format!("{} points ({} phi × {} beta)", phis.len() * betas.len(), phis.len(), betas.len());
    let driver =
        if driver == Driver::ReducedModel && phis.len() * betas.len() > 10_000 { Driver::Grid } else { driver };
    Estimate::time(seconds, driver, if why.is_empty() { detail } else { format!("{detail}; {why}") })
}

/// RK4 steps per load period of a response at φ (`response`): 64 per period of the
/// fastest of the basis modes, φ and Ω, and at least 64.
pub fn response_steps(pc: &PointCost, phi: f64) -> f64 {
    let omega_max = pc.w_max.max(phi).max(pc.speed);
    let period = 2.0 * std::f64::consts::PI / phi;
    let s = (period * omega_max / (2.0 * std::f64::consts::PI) * 64.0).ceil();
    if s.is_nan() {
        f64::INFINITY
    } else {
        s.max(64.0)
    }
}

/// A time response of `periods` periods of `per_period` RK4 steps each (the response's
/// own step rule, [`super::response::rk4_steps_per_period`]) and its Floquet point.
pub fn response(pc: &PointCost, phi: f64, beta: f64, periods: usize, per_period: f64) -> Estimate {
    let steps = per_period * periods as f64;
    let seconds = steps * (RK4_N2 * pc.n * pc.n + 1e-7) + pc.point_by_method(phi, beta);
    // Many steps per period come from a fast rotor (Ω above every mode and φ) or a low φ;
    // otherwise the periods asked for drive the work.
    let driver = if per_period > 64.0 * 16.0 {
        if pc.speed > pc.w_max.max(phi) {
            Driver::Speed
        } else {
            Driver::LowFrequency
        }
    } else {
        Driver::Periods
    };
    let detail = format!(
        "{periods} periods × {} RK4 steps per period at phi = {} rad/s",
        compact_count(per_period),
        compact(phi)
    );
    Estimate::time(seconds, driver, detail)
}

/// The points (1 + g)^k of the guard lattice inside `window` ([`super::regions::Level::lattice`]).
fn lattice(g: f64, window: Interval) -> impl Iterator<Item = f64> {
    let base = g.ln_1p();
    let (first, last) = if g > 0.0 && window.lo > 0.0 {
        ((window.lo.ln() / base).ceil() as i64, (window.hi.ln() / base).floor() as i64)
    } else {
        (1, 0)
    };
    (first..=last).map(move |k| (k as f64 * base).exp())
}

/// The φ values an edge march may step through across `window` (steps of the largest
/// edge-march step, [`RegionSettings::max_edge_step`]): where a tongue as wide as the
/// window is marched over.
fn march(s: &RegionSettings, window: Interval) -> impl Iterator<Item = f64> + '_ {
    std::iter::successors(Some(window.lo), move |&p| {
        let next = p + s.edge_step.at(p);
        (next < window.hi && next > p).then_some(next)
    })
}

/// Evaluations of a β bracket from `from` to `to` at the bracket step, and its bisection
/// to `tolerance`.
fn bracket(s: &RegionSettings, from: f64, to: f64, tolerance: f64) -> f64 {
    ((to - from).max(0.0) / s.beta_bracket).ceil() + 1.0 + (s.beta_bracket / tolerance).log2().ceil().max(0.0)
}

/// What a search of the unstable set at `level` over `window` costs (the band, and the
/// level part of a catalogue): each seed of order up to the criterion's whose window
/// reaches it (centre search, crest, both edges), every guard lattice point, and a march
/// across the whole window on both sides (a tongue as wide as the window).
fn level_search(
    pc: &PointCost,
    s: &RegionSettings,
    criterion: &Criterion,
    seeds: &[Seed],
    window: Interval,
    level: f64,
) -> (f64, usize) {
    let reach = |x: &Seed| Interval::new(x.phi * (1.0 - CENTRE_WINDOW), x.phi * (1.0 + CENTRE_WINDOW));
    let per_seed = HIT_FIXED + s.centre_iterations as f64 * 2.0 + 2.0 + s.tip_iterations as f64 + EDGE_EVALUATIONS;
    let mut seconds = 0.0;
    let mut count = 0;
    for x in seeds.iter().filter(|x| x.order <= criterion.max_order && reach(x).overlaps(&window)) {
        let phi = x.phi.clamp(window.lo, window.hi);
        seconds += per_seed * pc.point(phi, level);
        count += 1;
    }
    seconds += lattice(s.guard_step, window).map(|p| pc.point(p, level)).sum::<f64>();
    seconds += 2.0 * march(s, window).map(|p| pc.point(p, level)).sum::<f64>();
    (seconds, count)
}

/// What a catalogue request asks of the search.
#[derive(Debug, Clone, Copy)]
pub struct CatalogueWork {
    /// The φ range (rad/s).
    pub range: Interval,
    /// β_max.
    pub beta_max: f64,
    /// β_op.
    pub level: f64,
    /// Boundaries tracked (`--out`).
    pub track: bool,
}

/// A region catalogue (`regions`, a study's regions case, a design's verification): the
/// starts of the seeds of order ≤ `s.max_order` in the range (β_c bracketed up to β_max at
/// the bracket step, the tip climb, the onset below it), the unstable set at the level
/// (`level_search`), the onsets of regions found only at the level, and the tracking.
/// `seeds` are the range's ([`super::regions::seeds_for`]).
pub fn catalogue(
    pc: &PointCost,
    s: &RegionSettings,
    criterion: &Criterion,
    seeds: &[Seed],
    work: &CatalogueWork,
) -> Estimate {
    let (range, beta_max, level) = (work.range, work.beta_max, work.level);
    let screen = SCREENING_TOLERANCE.min(s.tip_margin.absolute).max(s.beta_tolerance);
    let climb = CLIMB_BRACKET + s.tip_iterations as f64;
    let mut starts = 0.0;
    let mut brackets = 0.0;
    let mut located = 0usize;
    for x in seeds.iter().filter(|x| x.order <= s.max_order && range.contains(x.phi)) {
        let phi = x.phi;
        located += 1;
        // β_c(seed): to the level on a table built to it, then to β_max on another.
        brackets += pc.table(phi, level).0 + bracket(s, 0.0, level, screen) * pc.monodromy(phi, level);
        brackets += pc.table(phi, beta_max).0 + bracket(s, level, beta_max, screen) * pc.monodromy(phi, beta_max);
        // The onset at the tip, stepping down from up to β_max, and β_c(seed) refined.
        brackets +=
            pc.table(phi, beta_max).0 + bracket(s, 0.0, beta_max, s.beta_tolerance) * pc.monodromy(phi, beta_max);
        starts +=
            climb * pc.point(phi, beta_max) + bracket(s, 0.0, 0.0, s.beta_tolerance) * pc.monodromy(phi, beta_max);
        if work.track {
            starts += s.tracking_levels as f64 * TRACK_EVALUATIONS * pc.point(phi, beta_max);
        }
    }
    let (at_level, searched) = level_search(pc, s, criterion, seeds, range, level);
    // Regions found only at the level: β_c stepped down from the level.
    let onsets: f64 = seeds
        .iter()
        .filter(|x| x.order <= criterion.max_order && range.contains(x.phi))
        .map(|x| pc.table(x.phi, level).0 + bracket(s, 0.0, level, s.beta_tolerance) * pc.monodromy(x.phi, level))
        .sum();
    let seconds = starts + brackets + at_level + onsets;
    let samples = bracket(s, 0.0, beta_max, screen);
    let (driver, detail) = if brackets > 0.5 * seconds {
        (
            Driver::Load,
            format!(
                "{located} region starts × {} beta samples up to beta_max = {} (step {})",
                compact_count(samples),
                compact(beta_max),
                compact(s.beta_bracket)
            ),
        )
    } else {
        let (d, why) = pc.point_driver(range.lo);
        let what = format!(
            "{located} region starts and {searched} seeds at the level over phi = {}..{} rad/s",
            compact(range.lo),
            compact(range.hi)
        );
        let d = if d == Driver::ReducedModel && searched > 1000 { Driver::Grid } else { d };
        (d, if why.is_empty() { what } else { format!("{what}; {why}") })
    };
    Estimate::time(seconds, driver, detail)
}

/// The stable band around φ_op at `level` in `window` (`band`, a study's band): the
/// search of the whole window (`level_search`), an upper bound of the outward search
/// that stops at the nearest tongue on each side.
pub fn band(
    pc: &PointCost,
    s: &RegionSettings,
    criterion: &Criterion,
    seeds: &[Seed],
    window: Interval,
    level: f64,
) -> Estimate {
    let (seconds, searched) = level_search(pc, s, criterion, seeds, window, level);
    let (d, why) = pc.point_driver(window.lo);
    let what = format!(
        "{searched} seeds and the guard lattice over phi = {}..{} rad/s",
        compact(window.lo),
        compact(window.hi)
    );
    Estimate::time(seconds, d, if why.is_empty() { what } else { format!("{what}; {why}") })
}

/// The search for the tongues at the level over `windows` (a clear-bands candidate's
/// operating bands) and their onsets.
pub fn scan(
    pc: &PointCost,
    s: &RegionSettings,
    criterion: &Criterion,
    seeds: &[Seed],
    windows: &[Interval],
    level: f64,
) -> Estimate {
    let mut seconds = 0.0;
    for w in windows {
        let (t, _) = level_search(pc, s, criterion, seeds, *w, level);
        seconds += t;
        let onsets: f64 = seeds
            .iter()
            .filter(|x| x.order <= criterion.max_order && w.contains(x.phi))
            .map(|x| pc.table(x.phi, level).0 + bracket(s, 0.0, level, s.beta_tolerance) * pc.monodromy(x.phi, level))
            .sum();
        seconds += onsets;
    }
    let lowest = windows.iter().map(|w| w.lo).fold(f64::INFINITY, f64::min);
    let (d, why) = pc.point_driver(lowest);
    Estimate::time(seconds, d, if why.is_empty() { "the operating bands' tongues".into() } else { why })
}

/// `count` points on tables of their own at (φ, β) (a verification grid, a design's
/// band work per candidate).
pub fn points(pc: &PointCost, count: f64, phi: f64, beta: f64) -> Estimate {
    let (d, why) = pc.point_driver(phi);
    Estimate::time(count * pc.point(phi, beta), d, why)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn budgets_refuse_beyond_the_limits_and_name_the_driver() {
        let b = Budget::default();
        let cheap = Estimate::time(1.0, Driver::Grid, "x".into());
        assert!(b.admit("the chart", &cheap, &|_| "`--phi`".into()).is_ok());
        let dear = Estimate::time(1e300, Driver::LowFrequency, "91 points".into());
        let e = b.admit("the chart", &dear, &|d| format!("{d:?}")).unwrap_err();
        assert_eq!((e.resource, e.parameter.as_str()), (Resource::Time, "LowFrequency"));
        assert!(e.to_string().starts_with("the chart would take about 1.0e300 s of computing, more than the 3600 s allowed: 91 points; change LowFrequency"), "{e}");
        let nan = Estimate::time(f64::NAN, Driver::Grid, String::new());
        assert!(b.admit("x", &nan, &|_| String::new()).is_err(), "a NaN estimate is refused");
        assert!(Budget::new(2.0)
            .unwrap()
            .admit("the chart", &Estimate::time(1000.0, Driver::Grid, String::new()), &|_| String::new())
            .is_ok());
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(Budget::new(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn chebyshev_points_follow_the_coefficient_bound() {
        // a = 0.1: 2·0.05⁶/6! = 4.3e-11 at 8 points, 2·0.05⁷/7! = 3.1e-13 at 9.
        assert_eq!(chebyshev_points(0.1), 9.0);
        // a = 2: 2/14! = 2.3e-11 at 16 points, 2/18! = 3.1e-16 at 20.
        assert_eq!(chebyshev_points(2.0), 20.0);
        // Beyond the doubling threshold the table tries more counts.
        assert!(chebyshev_points(30.0) >= 64.0);
        assert!(chebyshev_points(f64::INFINITY) >= 64.0);
    }
}
