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
use crate::progress::{Progress, Silent};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::lu::{factorize_symbolic_lu, NumericLu, SymbolicLu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{c64, Conj, MatMut, MatRef, Par};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

mod peaks;
use peaks::refine_peaks;

pub use peaks::{split_note, Peak, PEAK_SPEED_TOLERANCE, SOLVES_PER_PEAK, SPLIT_PAIR_SPACING, UNBOUNDED_BANDWIDTH};

/// What a probe of the response is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
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
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
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
    let mut counts = [0usize; 2];
    for b in &rotor.model.bearings {
        let i = &mut counts[usize::from(b.kind == crate::model::SupportKind::Seal)];
        *i += 1;
        out.push(Probe {
            name: format!("journal at {} {} (node {})", b.kind, i, b.node),
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
    /// Real coordinates only: the skew gyroscopic G_r per stored entry, which enters as
    /// jΩ²·G_r (empty in complex coordinates, where G is in `inertia`).
    gyroscopic: Vec<f64>,
    /// Real coordinates only: the bearings and seals whose coefficients are added at each
    /// speed, and where (stored entry, bearing, coefficient index).
    supports: Vec<(usize, usize, usize)>,
    bearings: Vec<crate::model::Bearing>,
    /// Real coordinates only: the complex size n (real DOF i + n is DOF i's w).
    half: Option<usize>,
}

/// The sparsity pattern of an n × n dynamic stiffness (compressed columns) and its
/// symbolic LU, after checking that every matrix value and the unbalance are finite.
fn symbolic_lu<'a>(
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    mut values: impl Iterator<Item = &'a f64>,
    unbalance: &[c64],
) -> Result<(SymbolicSparseColMat<usize>, SymbolicLu<usize>), AnalysisError> {
    let non_finite = || LinalgError::NonFinite { what: "dynamic stiffness" };
    if values.any(|v| !v.is_finite()) || unbalance.iter().any(|z| !(z.re.is_finite() && z.im.is_finite())) {
        return Err(non_finite().into());
    }
    let pattern = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
    let symbolic = factorize_symbolic_lu(pattern.as_ref(), Default::default()).map_err(|_| non_finite())?;
    Ok((pattern, symbolic))
}

impl DynamicStiffness {
    /// The dynamic stiffness of `rotor` under its static load αP_cr.
    pub fn of(rotor: &Rotor) -> Result<DynamicStiffness, AnalysisError> {
        if rotor.real {
            return DynamicStiffness::real(rotor);
        }
        let s = &rotor.system;
        DynamicStiffness::new(Matrices::of(s), rotor.static_load())
    }

    /// The dynamic stiffness of the real coordinates,
    /// A(Ω) = K(Ω) − P·S − Ω²M + jΩ(C(Ω) + Ω·G_r): the realified isotropic part once,
    /// the bearings' and seals' coefficients added at each speed.
    fn real(rotor: &Rotor) -> Result<DynamicStiffness, AnalysisError> {
        let sys = crate::assembly::GeneralSystem::new(&rotor.system, &[], 0.0);
        let n2 = sys.size();
        let n = n2 / 2;
        let load = rotor.static_load();
        let bearings = rotor.model.bearings.clone();
        // Where each support's four entries sit (row, column) → (bearing, coefficient).
        let mut at: std::collections::HashMap<(usize, usize), Vec<(usize, usize)>> = Default::default();
        for (b, bearing) in bearings.iter().enumerate() {
            let d = sys.dofs.deflection(bearing.node);
            for (r, row) in [d, n + d].into_iter().enumerate() {
                for (c, col) in [d, n + d].into_iter().enumerate() {
                    let e = at.entry((row, col)).or_default();
                    e.push((b, 2 * r + c));
                    e.push((b, 4 + 2 * r + c));
                }
            }
        }
        let mut col_ptr = Vec::with_capacity(n2 + 1);
        let mut row_idx = Vec::new();
        let (mut stiffness, mut inertia, mut damping, mut gyroscopic) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let mut supports = Vec::new();
        col_ptr.push(0usize);
        for j in 0..n2 {
            for i in 0..n2 {
                let (m, c, k, s, g) = (sys.m[(i, j)], sys.c[(i, j)], sys.k[(i, j)], sys.s[(i, j)], sys.g[(i, j)]);
                let support = at.get(&(i, j));
                if i == j || m != 0.0 || c != 0.0 || k != 0.0 || s != 0.0 || g != 0.0 || support.is_some() {
                    if let Some(list) = support {
                        supports.extend(list.iter().map(|&(b, coefficient)| (row_idx.len(), b, coefficient)));
                    }
                    row_idx.push(i);
                    stiffness.push(k - load * s);
                    inertia.push(m);
                    damping.push(c);
                    gyroscopic.push(g);
                }
            }
            col_ptr.push(row_idx.len());
        }
        let values = stiffness.iter().chain(&inertia).chain(&damping).chain(&gyroscopic);
        let (pattern, symbolic) = symbolic_lu(n2, col_ptr, row_idx, values, &sys.unbalance)?;
        Ok(DynamicStiffness {
            pattern,
            symbolic,
            stiffness,
            inertia,
            damping,
            unbalance: sys.unbalance,
            gyroscopic,
            supports,
            bearings,
            half: Some(n),
        })
    }

    /// The amplitude (m) of the response `u` at complex DOF `dof` and its phase (rad): |U|
    /// and arg U of the circular whirl in complex coordinates; in real ones the
    /// semi-major axis of the ellipse (`crate::analysis::orbit::Orbit`) and the phase of
    /// its x (v) motion.
    pub fn amplitude(&self, u: &[c64], dof: usize) -> (f64, f64) {
        match self.half {
            None => (u[dof].norm(), u[dof].arg()),
            Some(n) => (crate::analysis::orbit::Orbit::of(u[dof], u[n + dof]).major, u[dof].arg()),
        }
    }

    /// Real coordinates only: the complex size n (real DOF i + n is DOF i's w).
    pub fn half(&self) -> Option<usize> {
        self.half
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
        let (pattern, symbolic) = symbolic_lu(n, col_ptr, row_idx, values, sys.unbalance)?;
        Ok(DynamicStiffness {
            pattern,
            symbolic,
            stiffness,
            inertia,
            damping,
            unbalance: sys.unbalance.to_vec(),
            gyroscopic: Vec::new(),
            supports: Vec::new(),
            bearings: Vec::new(),
            half: None,
        })
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
        for (v, g) in work.values.iter_mut().zip(&self.gyroscopic) {
            v.im += w2 * g;
        }
        for &(entry, b, coefficient) in &self.supports {
            let x = self.bearings[b].coefficient_at(coefficient, speed);
            if coefficient < 4 {
                work.values[entry].re += x;
            } else {
                work.values[entry].im += speed * x;
            }
        }
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
    /// Mass matrix M (kg; γL on the charge DOFs).
    pub m: MatRef<'a, f64>,
    /// Viscous damping matrix C (N·s/m): plain bearings' damping and the rings' η; γR on
    /// the charge DOFs.
    pub c: MatRef<'a, f64>,
    /// Stiffness matrix K: bending, ring springs and the Eq. (A8) coupling (N/m between
    /// deflection DOFs; γ/C_f on the charge DOFs).
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

/// The response at one probe over the speed grid.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ProbeResponse {
    /// The DOF this response is of: its name, kind, node and global index (flattened into
    /// the JSON object).
    #[serde(flatten)]
    pub probe: Probe,
    /// |U| at each speed (m; ring DOFs m too).
    pub amplitude: Vec<f64>,
    /// arg U at each speed (rad, in (−π, π]).
    pub phase: Vec<f64>,
    /// The refined peaks, by speed.
    pub peaks: Vec<Peak>,
    /// Samples (Ω rad/s, |U| m, arg U rad) of the analytic response between grid speeds
    /// that the peaks' refinement solved, by speed: a plot draws the grid and these
    /// together, so its curve passes through every refined peak. Not in the JSON (the
    /// peaks are).
    #[serde(skip)]
    pub refined: Vec<[f64; 3]>,
    /// Real coordinates only: the elliptical orbit at each speed (`amplitude` is then its
    /// semi-major axis and `phase` that of its x motion); absent in complex coordinates,
    /// where the orbit is the circle of radius `amplitude`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub orbit: Option<OrbitResponse>,
}

/// The synchronous orbit of a probe over the speeds, in real coordinates: x = v and y = w
/// as x(t) = |X|·cos(Ωt + arg X), and the ellipse they trace (`crate::analysis::orbit`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OrbitResponse {
    /// |X| (m).
    pub x_amplitude: Vec<f64>,
    /// arg X (rad, in (−π, π]).
    pub x_phase: Vec<f64>,
    /// |Y| (m).
    pub y_amplitude: Vec<f64>,
    /// arg Y (rad).
    pub y_phase: Vec<f64>,
    /// Semi-major axis |F| + |B| (m).
    pub major: Vec<f64>,
    /// Semi-minor axis ||F| − |B|| (m).
    pub minor: Vec<f64>,
    /// Radius |F| of the forward circular component (m).
    pub forward: Vec<f64>,
    /// Radius |B| of the backward circular component (m).
    pub backward: Vec<f64>,
}

impl OrbitResponse {
    fn of(x: &[c64], y: &[c64]) -> OrbitResponse {
        let orbits: Vec<crate::analysis::orbit::Orbit> =
            x.iter().zip(y).map(|(a, b)| crate::analysis::orbit::Orbit::of(*a, *b)).collect();
        OrbitResponse {
            x_amplitude: x.iter().map(|z| z.norm()).collect(),
            x_phase: x.iter().map(|z| z.arg()).collect(),
            y_amplitude: y.iter().map(|z| z.norm()).collect(),
            y_phase: y.iter().map(|z| z.arg()).collect(),
            major: orbits.iter().map(|o| o.major).collect(),
            minor: orbits.iter().map(|o| o.minor).collect(),
            forward: orbits.iter().map(|o| o.forward).collect(),
            backward: orbits.iter().map(|o| o.backward).collect(),
        }
    }
}

impl ProbeResponse {
    /// The drawn curve (Ω rad/s, |U| m, arg U rad): the grid and the refinement's samples
    /// ([`ProbeResponse::refined`]) merged by speed.
    pub fn curve(&self, speeds: &[f64]) -> Vec<[f64; 3]> {
        let mut out: Vec<[f64; 3]> =
            speeds.iter().zip(&self.amplitude).zip(&self.phase).map(|((w, a), p)| [*w, *a, *p]).collect();
        out.extend(self.refined.iter().copied());
        out.sort_by(|x, y| x[0].total_cmp(&y[0]));
        out.dedup_by(|x, y| x[0] == y[0]);
        out
    }

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
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct UnbalanceResult {
    /// Speeds Ω (rad/s), ascending.
    pub speeds: Vec<f64>,
    /// Static axial load αP_cr in the stiffness (N).
    pub static_load: f64,
    /// One response per probe.
    pub probes: Vec<ProbeResponse>,
}

impl UnbalanceResult {
    /// Real coordinates only: the response in one direction (`plane` 0: x, 1: y) as
    /// amplitude and phase per probe, without peaks (they are refined on the semi-major
    /// axis); `None` in complex coordinates.
    pub fn direction(&self, plane: usize) -> Option<UnbalanceResult> {
        let probes = self
            .probes
            .iter()
            .map(|p| {
                let o = p.orbit.as_ref()?;
                let (amplitude, phase) =
                    if plane == 0 { (&o.x_amplitude, &o.x_phase) } else { (&o.y_amplitude, &o.y_phase) };
                Some(ProbeResponse {
                    probe: p.probe.clone(),
                    amplitude: amplitude.clone(),
                    phase: phase.clone(),
                    peaks: Vec::new(),
                    refined: Vec::new(),
                    orbit: None,
                })
            })
            .collect::<Option<Vec<_>>>()?;
        Some(UnbalanceResult { speeds: self.speeds.clone(), static_load: self.static_load, probes })
    }
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
/// refined, advancing `progress` by one per speed of the grid.
///
/// A speed not begun when [`Progress::cancelled`] turns true is skipped and the result
/// comes back without speeds or probes, to be discarded (as a Campbell diagram's).
pub fn unbalance_response(
    rotor: &Rotor,
    speeds: &[f64],
    probes: &[Probe],
    progress: &dyn Progress,
) -> Result<UnbalanceResult, AnalysisError> {
    let a = DynamicStiffness::of(rotor)?;
    let (speeds, probes) = match responses(&a, speeds, probes, progress)? {
        Some(probes) => (speeds.to_vec(), probes),
        None => (Vec::new(), Vec::new()),
    };
    Ok(UnbalanceResult { speeds, static_load: rotor.static_load(), probes })
}

/// The response of any system `a` at `probes` over `speeds` (rad/s, ascending), with
/// every probe's peaks refined: [`unbalance_response`] without the model (stopped when
/// asked, it returns no probes). A probe whose DOF is not in the system is
/// [`AnalysisError::ProbeOffSystem`].
pub fn response_with(
    a: &DynamicStiffness,
    speeds: &[f64],
    probes: &[Probe],
    progress: &dyn Progress,
) -> Result<Vec<ProbeResponse>, AnalysisError> {
    Ok(responses(a, speeds, probes, progress)?.unwrap_or_default())
}

/// [`response_with`]; None when stopped.
fn responses(
    a: &DynamicStiffness,
    speeds: &[f64],
    probes: &[Probe],
    progress: &dyn Progress,
) -> Result<Option<Vec<ProbeResponse>>, AnalysisError> {
    check_speeds(speeds)?;
    // The unbalance force grows like Ω²: a response's speeds are bounded.
    for &w in speeds {
        super::limits::response_speed(w)?;
    }
    if let Some(p) = probes.iter().find(|p| p.dof >= a.size()) {
        return Err(AnalysisError::ProbeOffSystem { dof: p.dof, dofs: a.size() });
    }
    // Each probe's v DOF, and in real coordinates its w DOF after all of them.
    let mut dofs: Vec<usize> = probes.iter().map(|p| p.dof).collect();
    if let Some(n) = a.half() {
        dofs.extend(probes.iter().map(|p| n + p.dof));
    }
    let Some(grid) = at_speeds(a, speeds, &dofs, progress)? else {
        return Ok(None);
    };
    let count = probes.len();
    probes
        .par_iter()
        .enumerate()
        .map_init(Workspace::default, |work, (k, probe)| {
            let values: Vec<c64> = grid.iter().map(|row| row[k]).collect();
            let (amplitude, phase, orbit) = match a.half() {
                None => (values.iter().map(|z| z.norm()).collect(), values.iter().map(|z| z.arg()).collect(), None),
                Some(_) => {
                    let y: Vec<c64> = grid.iter().map(|row| row[count + k]).collect();
                    let orbit = OrbitResponse::of(&values, &y);
                    (orbit.major.clone(), orbit.x_phase.clone(), Some(orbit))
                }
            };
            let (peaks, refined) = refine_peaks(a, probe.dof, speeds, &amplitude, work)?;
            Ok(ProbeResponse { probe: probe.clone(), amplitude, phase, peaks, refined, orbit })
        })
        .collect::<Result<_, AnalysisError>>()
        .map(Some)
}

/// The largest amplitude (m) at shaft node `node` over `speeds` (rad/s, ascending), its
/// peaks refined on the analytic response: (speed in rad/s, amplitude in m, unbounded).
/// What an objective "minimise the peak response at a node" evaluates; only that DOF's
/// peaks are refined.
pub fn peak_at_node(rotor: &Rotor, node: usize, speeds: &[f64]) -> Result<(f64, f64, bool), AnalysisError> {
    let probe = node_probe(&rotor.system.dofs, node)?;
    let r = unbalance_response(rotor, speeds, std::slice::from_ref(&probe), &Silent)?;
    Ok(r.probes[0].largest(speeds))
}

/// U at `dofs` for each speed, in parallel over speeds; None when asked to stop (a speed
/// not begun then is skipped).
fn at_speeds(
    a: &DynamicStiffness,
    speeds: &[f64],
    dofs: &[usize],
    progress: &dyn Progress,
) -> Result<Option<Vec<Vec<c64>>>, AnalysisError> {
    let rows: Vec<Option<Vec<c64>>> = speeds
        .par_iter()
        .map_init(Workspace::default, |work, &w| {
            if progress.cancelled() {
                return Ok(None);
            }
            let u = a.solve(w, work)?;
            progress.advance(1);
            Ok(Some(dofs.iter().map(|&d| u[d]).collect()))
        })
        .collect::<Result<_, AnalysisError>>()?;
    Ok(rows.into_iter().collect())
}
