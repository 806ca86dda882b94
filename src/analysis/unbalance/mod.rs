//! Steady-state synchronous response to the disks' unbalance (issue 17).
//!
//! With u = U·e^{jΩt} in Eq. (14), `M ü + (C − jΩG) u̇ + (K − αP_cr·S) u = Ω²·q_u·e^{jΩt}`
//! (q_u = Σ m e e^{jγ} at the disks' deflection DOFs, [`SystemMatrices::unbalance`]) becomes
//! one complex linear system per speed Ω:
//!
//! `(−Ω²M + jΩ(C − jΩG) + K − αP_cr·S) U = Ω²·q_u`, i.e. `(K − αP_cr·S − Ω²(M − G) + jΩC) U = Ω²·q_u`,
//!
//! the same sign conventions as the time response of [`super::response`] (B0 holds
//! −(C − jΩG), the force Ω²·Φᵀq_u·e^{jΩt}). The matrix is sparse (the shaft's FE band and
//! the supports' couplings): its pattern is analysed once (faer's sparse LU, column
//! ordering and symbolic factorisation) and each speed costs one numeric factorisation and
//! solve, sequential (`Par::Seq`); speeds run in parallel with rayon, each independent of
//! the others, so results are the same for any thread count.
//!
//! **Amplitude and phase.** u = v + jw is the complex deflection (v vertical, w
//! horizontal); the isotropic rotor whirls synchronously on a circle of radius |U| (m),
//! and u(t) = |U|·e^{j(Ωt + ψ)} with the phase ψ = arg U in (−π, π] (rad): the angle of
//! the deflection from the v axis towards w at t = 0, the reference of the disks' `phase`
//! γ. A single unbalance at γ = 0 has ψ ≈ 0 far below a critical speed, ψ = −π/2 at an
//! isolated resonance and ψ → −π above it (the deflection lags the heavy spot).
//!
//! **Peaks** are the interior local maxima of the amplitude over the speed grid, each
//! refined by a golden-section search on the analytic response (a solve at any Ω) between
//! its two grid neighbours. The **amplification factor** of a peak is the half-power
//! (−3 dB) one of API 684: AF = Ω_peak/(Ω₂ − Ω₁), with Ω₁ < Ω_peak < Ω₂ the nearest
//! speeds at which the amplitude falls to A_peak/√2 (located by bisection on the analytic
//! response), given only when both lie inside the speed range.

use super::{AnalysisError, Rotor};
use crate::assembly::{DofMap, SystemMatrices};
use crate::linalg::LinalgError;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::lu::{factorize_symbolic_lu, NumericLu, SymbolicLu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{c64, Conj, MatMut, MatRef, Par};
use rayon::prelude::*;
use serde::Serialize;

/// Relative width (of Ω_peak) of the bracket at which the golden-section search of a peak
/// stops: 1e-10 is a thousand times below [`UNBOUNDED_BANDWIDTH`], so every peak counted
/// as bounded is located well inside its half-power band, and about the f64 resolution of
/// the location of a smooth maximum (√ε ≈ 1.5e-8 of its width) for widths down to 1e-2 Ω.
pub const PEAK_SPEED_TOLERANCE: f64 = 1e-10;

/// Relative half-power bandwidth (Ω₂ − Ω₁)/Ω_peak below which a peak is reported
/// `unbounded`: an undamped mode (η = 0 and R = 0, the paper's rotor) has a pole at its
/// critical speed, and its refined "peak" is limited only by how close the search gets
/// to it (a bandwidth of ~[`PEAK_SPEED_TOLERANCE`]). 1e-7, an amplification factor of 10⁷,
/// is far beyond any damped machine (ζ = 1e-5 gives 5·10⁴) and a thousand times above
/// what the refinement resolves.
pub const UNBOUNDED_BANDWIDTH: f64 = 1e-7;

/// Bisection steps locating a half-power speed: the bracket (at most the speed range)
/// shrinks by 2⁻⁶⁰, far below [`PEAK_SPEED_TOLERANCE`] of any speed.
const HALF_POWER_STEPS: usize = 60;

/// Golden-section steps at most: a bracket of the whole admitted speed range shrinks by
/// 0.618¹²⁰ ≈ 1e-25, below [`PEAK_SPEED_TOLERANCE`] of any peak.
const GOLDEN_STEPS: usize = 120;

/// Solves of the analytic response a peak may cost at most (golden section and both
/// half-power bisections): what the cost estimate counts per peak.
pub const SOLVES_PER_PEAK: usize = GOLDEN_STEPS + 2 * HALF_POWER_STEPS;

/// What a probe of the response is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ProbeKind {
    /// A disk's deflection (its node).
    Disk,
    /// The shaft's deflection at a support (the journal in a ring's bearing).
    Journal,
    /// A vibration ring's displacement a (the bearing housing).
    Ring,
    /// A shaft node asked for by the user.
    Node,
}

/// A DOF whose response is reported.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Probe {
    /// Name for tables and legends, e.g. `disk 1 (node 16)`, `left ring`.
    pub name: String,
    /// What it is.
    pub kind: ProbeKind,
    /// The shaft node (absent for a ring DOF).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub node: Option<usize>,
    /// Index of the DOF in the global vector.
    pub dof: usize,
}

/// The probes of every support: the journal (shaft deflection) at each plain bearing, and
/// the journal and the ring DOF of each vibration ring (the shorthand's rings are named
/// `left` and `right`).
fn support_probes(rotor: &Rotor) -> Vec<Probe> {
    let dofs = &rotor.system.dofs;
    let mut out = Vec::new();
    for (i, b) in rotor.model.bearings.iter().enumerate() {
        out.push(Probe {
            name: format!("journal at bearing {} (node {})", i + 1, b.node),
            kind: ProbeKind::Journal,
            node: Some(b.node),
            dof: dofs.deflection(b.node),
        });
    }
    for (i, r) in rotor.model.rings.iter().enumerate() {
        out.push(Probe {
            name: format!("journal at ring {} (node {})", r.name, r.node),
            kind: ProbeKind::Journal,
            node: Some(r.node),
            dof: dofs.deflection(r.node),
        });
        out.push(Probe { name: format!("ring {}", r.name), kind: ProbeKind::Ring, node: None, dof: dofs.ring(i) });
    }
    out
}

/// The probes of a response: every node carrying disks (one probe for the disks there), the journal at every support, every ring's DOF, and
/// the shaft `nodes` asked for (in that order). A node beyond the shaft is
/// [`AnalysisError::ProbeNodeOffShaft`].
pub fn probes(rotor: &Rotor, nodes: &[usize]) -> Result<Vec<Probe>, AnalysisError> {
    let dofs = &rotor.system.dofs;
    let mut out = Vec::new();
    for node in disk_nodes(&rotor.model) {
        let numbers: Vec<String> = (rotor.model.disks.iter().enumerate())
            .filter(|(_, d)| d.node == node)
            .map(|(i, _)| (i + 1).to_string())
            .collect();
        let which = if numbers.len() == 1 { "disk" } else { "disks" };
        out.push(Probe {
            name: format!("{which} {} (node {node})", numbers.join(", ")),
            kind: ProbeKind::Disk,
            node: Some(node),
            dof: dofs.deflection(node),
        });
    }
    out.extend(support_probes(rotor));
    for &node in nodes {
        out.push(node_probe(dofs, node)?);
    }
    Ok(out)
}

/// The nodes that carry disks, ascending, each once.
pub fn disk_nodes(model: &crate::model::Model) -> Vec<usize> {
    let mut nodes: Vec<usize> = model.disks.iter().map(|d| d.node).collect();
    nodes.sort_unstable();
    nodes.dedup();
    nodes
}

/// The probe of shaft node `node`, or [`AnalysisError::ProbeNodeOffShaft`].
pub fn node_probe(dofs: &DofMap, node: usize) -> Result<Probe, AnalysisError> {
    if node >= dofs.nodes {
        return Err(AnalysisError::ProbeNodeOffShaft { node, last: dofs.nodes - 1 });
    }
    Ok(Probe { name: format!("node {node}"), kind: ProbeKind::Node, node: Some(node), dof: dofs.deflection(node) })
}

/// The dynamic stiffness A(Ω) = K − P·S − Ω²(M − G) + jΩC of a system in sparse form, its
/// pattern analysed once, and the forcing per unit Ω².
pub struct DynamicStiffness {
    pattern: SymbolicSparseColMat<usize>,
    symbolic: SymbolicLu<usize>,
    /// Per stored entry: K − P·S, M − G and C.
    stiffness: Vec<f64>,
    inertia: Vec<f64>,
    damping: Vec<f64>,
    /// q_u (kg·m): the force is Ω²·q_u.
    unbalance: Vec<c64>,
}

impl DynamicStiffness {
    /// The dynamic stiffness of `rotor` under its static load αP_cr.
    pub fn of(rotor: &Rotor) -> Result<DynamicStiffness, AnalysisError> {
        let s = &rotor.system;
        DynamicStiffness::new(Matrices::of(s), rotor.static_load())
    }

    /// The dynamic stiffness of any real symmetric system (M, C, K, S, G, q_u) under the
    /// static axial load `load` (N): K − load·S is its stiffness.
    pub fn new(sys: Matrices<'_>, load: f64) -> Result<DynamicStiffness, AnalysisError> {
        let n = sys.m.nrows();
        let entry = |i: usize, j: usize| [sys.m[(i, j)], sys.c[(i, j)], sys.k[(i, j)], sys.s[(i, j)], sys.g[(i, j)]];
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        let (mut stiffness, mut inertia, mut damping) = (Vec::new(), Vec::new(), Vec::new());
        col_ptr.push(0usize);
        for j in 0..n {
            for i in 0..n {
                let [m, c, k, s, g] = entry(i, j);
                // The diagonal always: no structurally empty column, whatever the values.
                if i == j || m != 0.0 || c != 0.0 || k != 0.0 || s != 0.0 || g != 0.0 {
                    row_idx.push(i);
                    stiffness.push(k - load * s);
                    inertia.push(m - g);
                    damping.push(c);
                }
            }
            col_ptr.push(row_idx.len());
        }
        let values = stiffness.iter().chain(&inertia).chain(&damping);
        if values.chain(sys.unbalance.iter().flat_map(|z| [&z.re, &z.im])).any(|v| !v.is_finite()) {
            return Err(LinalgError::NonFinite { what: "dynamic stiffness" }.into());
        }
        let pattern = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        let symbolic = factorize_symbolic_lu(pattern.as_ref(), Default::default())
            .map_err(|_| LinalgError::NonFinite { what: "dynamic stiffness" })?;
        Ok(DynamicStiffness { pattern, symbolic, stiffness, inertia, damping, unbalance: sys.unbalance.to_vec() })
    }

    /// Number of DOFs.
    pub fn size(&self) -> usize {
        self.unbalance.len()
    }

    /// The response U (m, and the charges' units) at speed Ω (rad/s), reusing `work`.
    pub fn solve(&self, speed: f64, work: &mut Workspace) -> Result<Vec<c64>, AnalysisError> {
        let w2 = speed * speed;
        work.values.clear();
        work.values.extend(
            self.stiffness
                .iter()
                .zip(&self.inertia)
                .zip(&self.damping)
                .map(|((k, m), c)| c64::new(k - w2 * m, speed * c)),
        );
        let mut rhs: Vec<c64> = self.unbalance.iter().map(|q| q * w2).collect();
        if work.values.iter().chain(&rhs).any(|z| !(z.re.is_finite() && z.im.is_finite())) {
            return Err(LinalgError::NonFinite { what: "dynamic stiffness" }.into());
        }
        let singular = || AnalysisError::SingularAtSpeed { speed };
        let a = SparseColMatRef::new(self.pattern.as_ref(), &work.values);
        let par = Par::Seq;
        let params = Default::default();
        let factor_req = self.symbolic.factorize_numeric_lu_scratch::<c64>(par, params);
        let solve_req = self.symbolic.solve_in_place_scratch::<c64>(1, par);
        let need = factor_req.or(solve_req);
        if work.buffer.as_ref().is_none_or(|(req, _)| *req != need) {
            work.buffer = Some((need, MemBuffer::new(need)));
        }
        let Some((_, mem)) = work.buffer.as_mut() else { return Err(singular()) };
        let lu = self
            .symbolic
            .factorize_numeric_lu(&mut work.numeric, a, par, MemStack::new(mem), params)
            .map_err(|_| singular())?;
        let n = rhs.len();
        let x = MatMut::from_column_major_slice_mut(&mut rhs, n, 1);
        lu.solve_in_place_with_conj(Conj::No, x, par, MemStack::new(mem));
        if rhs.iter().any(|z| !(z.re.is_finite() && z.im.is_finite())) {
            return Err(singular());
        }
        Ok(rhs)
    }
}

/// The real symmetric matrices of a system and its unbalance, as
/// [`SystemMatrices`] holds them (or a reduced model's).
#[derive(Clone, Copy)]
pub struct Matrices<'a> {
    /// M.
    pub m: MatRef<'a, f64>,
    /// C.
    pub c: MatRef<'a, f64>,
    /// K.
    pub k: MatRef<'a, f64>,
    /// S (per unit axial load).
    pub s: MatRef<'a, f64>,
    /// G (per unit speed).
    pub g: MatRef<'a, f64>,
    /// q_u (kg·m).
    pub unbalance: &'a [c64],
}

impl<'a> Matrices<'a> {
    /// The matrices of an assembled model.
    pub fn of(s: &'a SystemMatrices) -> Matrices<'a> {
        Matrices {
            m: s.m.as_ref(),
            c: s.c.as_ref(),
            k: s.k.as_ref(),
            s: s.s.as_ref(),
            g: s.g.as_ref(),
            unbalance: &s.unbalance,
        }
    }
}

/// Scratch of [`DynamicStiffness::solve`], one per thread.
#[derive(Default)]
pub struct Workspace {
    values: Vec<c64>,
    numeric: NumericLu<usize, c64>,
    buffer: Option<(faer::dyn_stack::StackReq, MemBuffer)>,
}

/// A peak of a probe's amplitude.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Peak {
    /// Speed of the refined maximum Ω_peak (rad/s).
    pub speed: f64,
    /// Amplitude there (m).
    pub amplitude: f64,
    /// Phase there (rad, convention of the module).
    pub phase: f64,
    /// Half-power speeds [Ω₁, Ω₂] (rad/s); absent when one lies beyond the speed range
    /// (or beyond a neighbouring higher peak).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub half_power: Option<[f64; 2]>,
    /// API 684 amplification factor Ω_peak/(Ω₂ − Ω₁) (−); absent with `half_power`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub amplification_factor: Option<f64>,
    /// The peak is a pole of the response (half-power bandwidth below
    /// [`UNBOUNDED_BANDWIDTH`]·Ω_peak): an undamped critical speed, whose amplitude is
    /// limited only by the refinement, not by the physics.
    pub unbounded: bool,
}

/// The response at one probe over the speed grid.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ProbeResponse {
    /// Where.
    #[serde(flatten)]
    pub probe: Probe,
    /// |U| at each speed (m; ring DOFs m too).
    pub amplitude: Vec<f64>,
    /// arg U at each speed (rad, in (−π, π]).
    pub phase: Vec<f64>,
    /// The refined peaks, by speed.
    pub peaks: Vec<Peak>,
}

impl ProbeResponse {
    /// The largest amplitude over the range, grid ends and refined peaks included:
    /// (speed in rad/s, amplitude in m, unbounded).
    pub fn largest(&self, speeds: &[f64]) -> (f64, f64, bool) {
        let mut best = (f64::NAN, f64::NEG_INFINITY, false);
        for (i, &a) in self.amplitude.iter().enumerate() {
            if a > best.1 {
                best = (speeds[i], a, false);
            }
        }
        for p in &self.peaks {
            if p.amplitude > best.1 {
                best = (p.speed, p.amplitude, p.unbounded);
            }
        }
        best
    }
}

/// The unbalance response over a speed grid.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct UnbalanceResult {
    /// Speeds Ω (rad/s), ascending.
    pub speeds: Vec<f64>,
    /// Static axial load αP_cr in the stiffness (N).
    pub static_load: f64,
    /// One response per probe.
    pub probes: Vec<ProbeResponse>,
}

/// Check a speed grid: at least one speed, each finite and ≥ 0, strictly ascending.
pub fn check_speeds(speeds: &[f64]) -> Result<(), AnalysisError> {
    if speeds.is_empty() {
        return Err(AnalysisError::NoSpeeds);
    }
    for &w in speeds {
        super::limits::speed(w)?;
    }
    if let Some(i) = speeds.windows(2).position(|p| p[1] <= p[0]) {
        return Err(AnalysisError::SpeedsNotAscending { index: i + 1, speed: speeds[i + 1], previous: speeds[i] });
    }
    Ok(())
}

/// The response at `probes` over `speeds` (rad/s, ascending), with every probe's peaks
/// refined. `tick` is called once per speed of the grid.
pub fn unbalance_response(
    rotor: &Rotor,
    speeds: &[f64],
    probes: &[Probe],
    tick: &(dyn Fn() + Sync),
) -> Result<UnbalanceResult, AnalysisError> {
    let a = DynamicStiffness::of(rotor)?;
    let probes = response_with(&a, speeds, probes, tick)?;
    Ok(UnbalanceResult { speeds: speeds.to_vec(), static_load: rotor.static_load(), probes })
}

/// The response of any system `a` at `probes` over `speeds` (rad/s, ascending), with
/// every probe's peaks refined: [`unbalance_response`] without the model. A probe whose
/// DOF is not in the system is [`AnalysisError::ProbeOffSystem`].
pub fn response_with(
    a: &DynamicStiffness,
    speeds: &[f64],
    probes: &[Probe],
    tick: &(dyn Fn() + Sync),
) -> Result<Vec<ProbeResponse>, AnalysisError> {
    check_speeds(speeds)?;
    if let Some(p) = probes.iter().find(|p| p.dof >= a.size()) {
        return Err(AnalysisError::ProbeOffSystem { dof: p.dof, dofs: a.size() });
    }
    let dofs: Vec<usize> = probes.iter().map(|p| p.dof).collect();
    let grid = at_speeds(a, speeds, &dofs, tick)?;
    probes
        .par_iter()
        .enumerate()
        .map_init(Workspace::default, |work, (k, probe)| {
            let values: Vec<c64> = grid.iter().map(|row| row[k]).collect();
            let amplitude: Vec<f64> = values.iter().map(|z| z.norm()).collect();
            let phase = values.iter().map(|z| z.arg()).collect();
            let peaks = refine_peaks(a, probe.dof, speeds, &amplitude, work)?;
            Ok(ProbeResponse { probe: probe.clone(), amplitude, phase, peaks })
        })
        .collect()
}

/// The largest amplitude (m) at shaft node `node` over `speeds` (rad/s, ascending), its
/// peaks refined on the analytic response: (speed in rad/s, amplitude in m, unbounded).
/// What an objective "minimise the peak response at a node" evaluates; only that DOF's
/// peaks are refined.
pub fn peak_at_node(rotor: &Rotor, node: usize, speeds: &[f64]) -> Result<(f64, f64, bool), AnalysisError> {
    let probe = node_probe(&rotor.system.dofs, node)?;
    let r = unbalance_response(rotor, speeds, std::slice::from_ref(&probe), &|| {})?;
    Ok(r.probes[0].largest(speeds))
}

/// U at `dofs` for each speed, in parallel over speeds.
fn at_speeds(
    a: &DynamicStiffness,
    speeds: &[f64],
    dofs: &[usize],
    tick: &(dyn Fn() + Sync),
) -> Result<Vec<Vec<c64>>, AnalysisError> {
    speeds
        .par_iter()
        .map_init(Workspace::default, |work, &w| {
            let u = a.solve(w, work)?;
            tick();
            Ok(dofs.iter().map(|&d| u[d]).collect())
        })
        .collect()
}

/// The amplitude |U_dof| (m) at speed Ω.
fn amplitude_at(a: &DynamicStiffness, dof: usize, speed: f64, work: &mut Workspace) -> Result<c64, AnalysisError> {
    Ok(a.solve(speed, work)?[dof])
}

/// The interior local maxima of `amp` over `speeds`, refined.
fn refine_peaks(
    a: &DynamicStiffness,
    dof: usize,
    speeds: &[f64],
    amp: &[f64],
    work: &mut Workspace,
) -> Result<Vec<Peak>, AnalysisError> {
    let mut peaks = Vec::new();
    for i in 1..amp.len().saturating_sub(1) {
        // Strict on the left, not on the right: a flat top counts once.
        if !(amp[i] > amp[i - 1] && amp[i] >= amp[i + 1]) {
            continue;
        }
        let (speed, value) = golden_max(a, dof, speeds[i - 1], speeds[i + 1], (speeds[i], amp[i]), work)?;
        let amplitude = value.norm();
        let half = amplitude / std::f64::consts::SQRT_2;
        let left = half_power(a, dof, speeds, amp, speed, half, Side::Below, work)?;
        let right = half_power(a, dof, speeds, amp, speed, half, Side::Above, work)?;
        let half_power = left.zip(right).map(|(l, r)| [l, r]);
        let width = half_power.map(|[l, r]| r - l);
        let unbounded = width.is_some_and(|w| w < UNBOUNDED_BANDWIDTH * speed);
        peaks.push(Peak {
            speed,
            amplitude,
            phase: value.arg(),
            half_power,
            amplification_factor: width.filter(|w| *w > 0.0).map(|w| speed / w),
            unbounded,
        });
    }
    Ok(peaks)
}

/// Golden-section maximisation of |U_dof| on [lo, hi], which holds the grid maximum
/// `best` (speed, amplitude): the refined (speed, U). The grid point is kept if the search
/// finds nothing higher (a maximum at a bracket end).
fn golden_max(
    a: &DynamicStiffness,
    dof: usize,
    lo: f64,
    hi: f64,
    best: (f64, f64),
    work: &mut Workspace,
) -> Result<(f64, c64), AnalysisError> {
    const INV_PHI: f64 = 0.618_033_988_749_894_9;
    let (mut lo, mut hi) = (lo, hi);
    let mut x1 = hi - INV_PHI * (hi - lo);
    let mut x2 = lo + INV_PHI * (hi - lo);
    let mut f1 = amplitude_at(a, dof, x1, work)?;
    let mut f2 = amplitude_at(a, dof, x2, work)?;
    for _ in 0..GOLDEN_STEPS {
        if hi - lo <= PEAK_SPEED_TOLERANCE * best.0.max(f64::MIN_POSITIVE) {
            break;
        }
        if f1.norm() >= f2.norm() {
            hi = x2;
            (x2, f2) = (x1, f1);
            x1 = hi - INV_PHI * (hi - lo);
            f1 = amplitude_at(a, dof, x1, work)?;
        } else {
            lo = x1;
            (x1, f1) = (x2, f2);
            x2 = lo + INV_PHI * (hi - lo);
            f2 = amplitude_at(a, dof, x2, work)?;
        }
    }
    let (x, f) = if f1.norm() >= f2.norm() { (x1, f1) } else { (x2, f2) };
    if f.norm() >= best.1 {
        Ok((x, f))
    } else {
        Ok((best.0, amplitude_at(a, dof, best.0, work)?))
    }
}

#[derive(Clone, Copy, PartialEq)]
enum Side {
    Below,
    Above,
}

/// The nearest speed on `side` of the peak at `peak` where the amplitude falls to `half`:
/// the first grid speed beyond the peak below `half`, then bisection between it and the
/// last speed at or above `half`. None when the grid ends first, or rises above the peak
/// amplitude (√2·half) first (a higher neighbouring peak).
#[allow(clippy::too_many_arguments)]
fn half_power(
    a: &DynamicStiffness,
    dof: usize,
    speeds: &[f64],
    amp: &[f64],
    peak: f64,
    half: f64,
    side: Side,
    work: &mut Workspace,
) -> Result<Option<f64>, AnalysisError> {
    let top = half * std::f64::consts::SQRT_2;
    let order: Box<dyn Iterator<Item = usize>> = match side {
        Side::Above => Box::new((0..speeds.len()).filter(|&i| speeds[i] > peak)),
        Side::Below => Box::new((0..speeds.len()).rev().filter(|&i| speeds[i] < peak)),
    };
    let mut inside = peak;
    for i in order {
        if amp[i] > top {
            return Ok(None);
        }
        if amp[i] < half {
            let mut outside = speeds[i];
            for _ in 0..HALF_POWER_STEPS {
                let mid = 0.5 * (inside + outside);
                if mid == inside || mid == outside {
                    break;
                }
                if amplitude_at(a, dof, mid, work)?.norm() >= half {
                    inside = mid;
                } else {
                    outside = mid;
                }
            }
            return Ok(Some(0.5 * (inside + outside)));
        }
        inside = speeds[i];
    }
    Ok(None)
}
