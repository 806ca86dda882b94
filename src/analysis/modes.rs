//! Whirl frequencies from the quadratic eigenproblem of Eq. (16),
//! `(λ²M + λ(C − jΩG) + K − αP_cr·S) φ = 0`, solved in the structure-keeping first-order
//! form of [`solve_qep_definite`] (exactly zero damping when C = 0), or by shift-invert
//! (Eq. 18–21) where that form does not apply (a massless DOF with damping, a spread of
//! frequencies beyond [`crate::linalg::DEFINITE_FORM_SPREAD`]).
//!
//! λ = −ζ|λ| + jω: ω > 0 is a forward whirl, ω < 0 a backward whirl (docs/model.md).

use super::{AnalysisError, Rotor, Settings};
use crate::assembly::DofKind;
use crate::linalg::{qep_residual_with, solve_qep, solve_qep_definite, QepNorms};
use crate::model::Model;
use faer::{c64, Mat, MatRef, Par};
use serde::{Deserialize, Serialize};

/// Shift σ of Eq. (18) in 1/s. A passive system has no eigenvalue with Re λ > 0, so a
/// positive real shift never hits one; 1 s⁻¹ is far below every whirl frequency yet
/// keeps (A − σB) regular even when K − αP_cr·S is nearly singular.
pub const QEP_SHIFT: f64 = 1.0;

/// Relative QEP residual above which a mode is flagged: the solvers leave ≤ 1.5e-7 even
/// on the highest FE modes (~3.5e6 rad/s; measured on the Fig. 11 rotor) and ~1e-12 on
/// the whirls of interest, so 1e-6 and above mean the pair is not an eigenpair of the
/// model to working accuracy (e.g. Ω = 1e300 rad/s, where residuals reach 1).
pub const MODE_RESIDUAL_LIMIT: f64 = 1e-6;

/// Damping ratio below −this is flagged: the model is passive (η, R ≥ 0, so C ⪰ 0) and
/// has no negatively damped mode; a computed ζ < −1e-9 is the eigensolver's round-off
/// (shift-invert on a model it cannot hold in the first-order form).
pub const NEGATIVE_DAMPING_LIMIT: f64 = 1e-9;

/// Why a mode's numbers are not to be trusted (JSON `flag`: its name, number and message;
/// a note under the table).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ModeFlag {
    /// The relative QEP residual is above [`MODE_RESIDUAL_LIMIT`].
    Residual {
        /// The residual (−).
        residual: f64,
    },
    /// ζ below −[`NEGATIVE_DAMPING_LIMIT`] in a passive model.
    NegativeDamping {
        /// ζ (−).
        damping_ratio: f64,
    },
}

impl std::fmt::Display for ModeFlag {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ModeFlag::Residual { residual } => write!(
                f,
                "QEP residual {residual:.3e} is above {MODE_RESIDUAL_LIMIT:e}: not an eigenpair of the model to working accuracy"
            ),
            ModeFlag::NegativeDamping { damping_ratio } => write!(
                f,
                "damping ratio {damping_ratio:.3e} is negative in a passive model: eigensolver round-off, not physics"
            ),
        }
    }
}

/// The JSON form of a [`ModeFlag`]: the flag's name (`flag`), its number and the text of
/// its `Display` (`message`, not read back).
#[derive(Serialize, Deserialize)]
struct FlagJson {
    #[serde(flatten, with = "FlagData")]
    flag: ModeFlag,
    #[serde(default, skip_deserializing)]
    message: String,
}

/// [`ModeFlag`]'s variants as JSON names them (serde's mirror of the enum).
#[derive(Serialize, Deserialize)]
#[serde(remote = "ModeFlag", tag = "flag", rename_all = "kebab-case")]
enum FlagData {
    Residual { residual: f64 },
    NegativeDamping { damping_ratio: f64 },
}

impl Serialize for ModeFlag {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        FlagJson { flag: *self, message: self.to_string() }.serialize(serializer)
    }
}

impl<'de> Deserialize<'de> for ModeFlag {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        Ok(FlagJson::deserialize(deserializer)?.flag)
    }
}

/// Direction of a whirl relative to the spin.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Whirl {
    /// Im λ > 0 (complex coordinates), or every node's orbit forward (real coordinates):
    /// whirls with the spin.
    Forward,
    /// Im λ < 0, or every node's orbit backward: whirls against the spin.
    Backward,
    /// Real coordinates only: some nodes whirl forward and others backward, or every
    /// orbit is a line (`super::orbit::classify`).
    Mixed,
}

impl Whirl {
    /// `f`, `b` or `m`, as in the paper's ω_f, ω_b.
    pub fn letter(self) -> char {
        match self {
            Whirl::Forward => 'f',
            Whirl::Backward => 'b',
            Whirl::Mixed => 'm',
        }
    }

    /// The directions a model's whirls may take: forward and backward in complex
    /// coordinates, and mixed too in real ones.
    pub fn all() -> [Whirl; 3] {
        [Whirl::Forward, Whirl::Backward, Whirl::Mixed]
    }
}

/// Mechanical (rotor) or electrical (shunt) mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ModeKind {
    /// Most kinetic energy in the rotor and rings.
    Mechanical,
    /// Most kinetic energy in the shunt charges (the paper's r, s modes).
    Electrical,
}

/// One whirl mode at one speed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WhirlMode {
    /// Whirl frequency |Im λ| (rad/s).
    pub frequency: f64,
    /// Forward or backward whirl (sign of the eigenvalue's imaginary part).
    pub whirl: Whirl,
    /// Damping ratio ζ = −Re λ/|λ| (−).
    pub damping_ratio: f64,
    /// The paper's number: "1", "2", … for rotor modes, "r1", "r2", "s1", … for the
    /// electrical modes of branch 1, 2, … (Table 3).
    pub label: String,
    /// Mechanical or electrical, by the share of kinetic energy in the charges.
    pub kind: ModeKind,
    /// Share of kinetic energy in the charge DOFs (−).
    pub electrical_fraction: f64,
    /// Eigenvalue λ as [Re, Im] (1/s).
    pub eigenvalue: [f64; 2],
    /// Relative QEP residual (see [`crate::linalg::qep_residual`]).
    pub residual: f64,
    /// Real coordinates only: κ = ±minor/major of the largest node orbit (positive
    /// forward, `super::orbit::Orbit`); absent in complex coordinates, where every
    /// orbit is a circle.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ellipticity: Option<f64>,
    /// Why the numbers are not to be trusted (absent, and not serialised, when they are).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub flag: Option<ModeFlag>,
}

impl WhirlMode {
    /// `f1`, `b2`, `fr1`, …: whirl letter and label, as used in region labels.
    pub fn tag(&self) -> String {
        format!("{}{}", self.whirl.letter(), self.label)
    }
}

/// Whirl modes of the model at one speed. Serialised without its mode shapes, which a
/// result read back does not have (`shapes` is then 0 × 0).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ModesResult {
    /// Rotating speed Ω (rad/s).
    pub speed: f64,
    /// Reference load P_cr (N).
    pub critical_load: f64,
    /// Static load αP_cr included in the stiffness (N).
    pub static_load: f64,
    /// All whirl modes, sorted by frequency.
    pub modes: Vec<WhirlMode>,
    /// Mode shapes (unit 2-norm columns, same order as `modes`); not serialised.
    #[serde(skip, default = "Mat::new")]
    pub shapes: Mat<c64>,
    /// Whether the modes are those of the real coordinates (the general path), where
    /// [`ModesResult::lowest`] takes its whirls from a window ([`WHIRL_WINDOW`]).
    pub real: bool,
}

impl ModesResult {
    /// Forward whirls, lowest first.
    pub fn forward(&self) -> impl Iterator<Item = &WhirlMode> {
        self.modes.iter().filter(|m| m.whirl == Whirl::Forward)
    }
    /// Backward whirls, lowest first.
    pub fn backward(&self) -> impl Iterator<Item = &WhirlMode> {
        self.modes.iter().filter(|m| m.whirl == Whirl::Backward)
    }
    /// Mixed whirls (real coordinates only), lowest first.
    pub fn mixed(&self) -> impl Iterator<Item = &WhirlMode> {
        self.modes.iter().filter(|m| m.whirl == Whirl::Mixed)
    }
    /// The lowest `count` forward, `count` backward and `count` mixed whirls, sorted by
    /// frequency. In real coordinates, among the whirls of [`ModesResult::window`] only.
    pub fn lowest(&self, count: usize) -> Vec<WhirlMode> {
        self.lowest_indices(count).into_iter().map(|i| self.modes[i].clone()).collect()
    }

    /// The indices into `modes` of [`ModesResult::lowest`]'s whirls, in its order: by
    /// frequency, forward before backward before mixed at equal frequencies.
    pub fn lowest_indices(&self, count: usize) -> Vec<usize> {
        let window = self.window(count);
        let mut v: Vec<usize> = Vec::new();
        for whirl in Whirl::all() {
            v.extend(window.iter().copied().filter(|&i| self.modes[i].whirl == whirl).take(count));
        }
        v.sort_by(|&a, &b| self.modes[a].frequency.total_cmp(&self.modes[b].frequency));
        v
    }

    /// The indices (into `modes`, ascending, i.e. by frequency) of the whirls
    /// [`ModesResult::lowest`] chooses from: every whirl in complex coordinates; in real
    /// coordinates the lowest [`WHIRL_WINDOW`]·`count` by |λ| (ROSS's natural
    /// frequency ω_n), and any whirl degenerate with the last of them
    /// ([`DEGENERATE_WHIRLS`]). The window is what the shift-invert solver
    /// ([`lowest_whirls_of`]) must resolve, so both solvers list the same whirls.
    pub fn window(&self, count: usize) -> Vec<usize> {
        if !self.real {
            return (0..self.modes.len()).collect();
        }
        let modulus = |i: usize| c64::new(self.modes[i].eigenvalue[0], self.modes[i].eigenvalue[1]).norm();
        let mut order: Vec<usize> = (0..self.modes.len()).collect();
        order.sort_by(|&a, &b| modulus(a).total_cmp(&modulus(b)).then(a.cmp(&b)));
        let mut end = (WHIRL_WINDOW * count).min(order.len());
        while end > 0
            && end < order.len()
            && modulus(order[end]) - modulus(order[end - 1]) <= DEGENERATE_WHIRLS * modulus(order[end - 1])
        {
            end += 1;
        }
        let mut chosen = order[..end].to_vec();
        chosen.sort_unstable();
        chosen
    }
}

/// Whirl modes of `model` at speed Ω (rad/s), static load αP_cr included.
pub fn whirl_modes(model: &Model, settings: &Settings, speed: f64) -> Result<ModesResult, AnalysisError> {
    whirl_modes_of(&Rotor::new(model)?, settings, speed)
}

/// Whirl modes of a prepared rotor at speed Ω (rad/s).
pub fn whirl_modes_of(rotor: &Rotor, settings: &Settings, speed: f64) -> Result<ModesResult, AnalysisError> {
    settings.validate()?;
    if rotor.real {
        return real_modes(rotor, settings, speed);
    }
    let sys = &rotor.system;
    let d = sys.damping_at(speed);
    let k = sys.stiffness_at(rotor.static_load());
    let undamped = (0..sys.size()).all(|j| (0..sys.size()).all(|i| sys.c[(i, j)] == 0.0));
    let sol = match solve_qep_definite(sys.m.as_ref(), d.as_ref(), k.as_ref()) {
        Some(sol) => sol,
        None => {
            let mut sol = solve_qep(sys.m.as_ref(), d.as_ref(), k.as_ref(), QEP_SHIFT)?;
            if undamped {
                for (c, lambda) in sol.values.iter_mut().enumerate() {
                    *lambda = undamped_rayleigh(sys.m.as_ref(), d.as_ref(), k.as_ref(), *lambda, sol.vectors.col(c));
                }
            }
            sol
        }
    };
    let kinds = sys.dofs.kinds();
    let n = sys.size();
    let slots = electrical_slots(rotor);
    let norms = QepNorms::of(sys.m.as_ref(), d.as_ref(), k.as_ref());
    let mut mx = vec![c64::new(0.0, 0.0); n];

    let mut raw = Vec::new();
    for (col, &lambda) in sol.values.iter().enumerate() {
        let x = sol.vectors.col(col);
        let residual = qep_residual_with(&norms, sys.m.as_ref(), d.as_ref(), k.as_ref(), lambda, x);
        if !(lambda.re.is_finite() && lambda.im.is_finite() && residual.is_finite()) {
            continue; // not an eigenpair that can be reported
        }
        if lambda.im.abs() <= settings.oscillation_tolerance * lambda.norm() {
            continue; // non-oscillatory: not a whirl
        }
        let mut total = 0.0;
        let mut charge = 0.0;
        let mut per_branch = vec![0.0; slots.len()];
        // (M x)_i, column by column (each row's sum in column order, as a row loop would).
        mx.fill(c64::new(0.0, 0.0));
        for j in 0..n {
            let xj = x[j];
            for (i, v) in mx.iter_mut().enumerate() {
                *v += xj * sys.m[(i, j)];
            }
        }
        for i in 0..n {
            let e = (x[i].conj() * mx[i]).re;
            total += e;
            if kinds[i] == DofKind::Charge {
                charge += e;
            }
        }
        for (slot, acc) in slots.iter().zip(per_branch.iter_mut()) {
            for &(ring, b) in &slot.charges {
                let i = sys.dofs.charge(ring, b);
                *acc += sys.m[(i, i)] * x[i].norm_sqr();
            }
        }
        let fraction = if total > 0.0 { charge / total } else { 0.0 };
        let kind = if fraction > settings.electrical_fraction { ModeKind::Electrical } else { ModeKind::Mechanical };
        let branch = (kind == ModeKind::Electrical)
            .then(|| (0..per_branch.len()).max_by(|&a, &b| per_branch[a].total_cmp(&per_branch[b])).unwrap_or(0));
        let whirl = if lambda.im > 0.0 { Whirl::Forward } else { Whirl::Backward };
        // (an exactly imaginary λ has ζ = 0, not −0)
        let damping_ratio = if lambda.re == 0.0 { 0.0 } else { -lambda.re / lambda.norm() };
        let flag = if residual > MODE_RESIDUAL_LIMIT {
            Some(ModeFlag::Residual { residual })
        } else if damping_ratio < -NEGATIVE_DAMPING_LIMIT {
            Some(ModeFlag::NegativeDamping { damping_ratio })
        } else {
            None
        };
        raw.push(RawMode {
            col,
            branch,
            mode: WhirlMode {
                frequency: lambda.im.abs(),
                whirl,
                damping_ratio,
                label: String::new(),
                kind,
                electrical_fraction: fraction,
                eigenvalue: [lambda.re, lambda.im],
                residual,
                ellipticity: None,
                flag,
            },
        });
    }
    if raw.is_empty() {
        return Err(AnalysisError::NoWhirlModes {
            speed,
            eigenvalues: sol.values.len(),
            tolerance: settings.oscillation_tolerance,
        });
    }
    Ok(numbered(rotor, speed, raw, &slots, n, |i, col| sol.vectors[(i, col)], false))
}

/// A whirl found by a solver before numbering: its eigenvector's column, the mode, and
/// the electrical slot it belongs to (`None`: a rotor mode).
struct RawMode {
    col: usize,
    mode: WhirlMode,
    branch: Option<usize>,
}

/// The result of a solver's whirls `raw`: sorted and numbered ([`sort_and_label`]), each
/// shape the `rows` entries `entry(row, col)` of its eigenvector's column.
fn numbered(
    rotor: &Rotor,
    speed: f64,
    mut raw: Vec<RawMode>,
    slots: &[Slot],
    rows: usize,
    entry: impl Fn(usize, usize) -> c64,
    real: bool,
) -> ModesResult {
    sort_and_label(&mut raw, slots);
    let shapes = Mat::from_fn(rows, raw.len(), |i, c| entry(i, raw[c].col));
    ModesResult {
        speed,
        critical_load: rotor.critical_load,
        static_load: rotor.static_load(),
        modes: raw.into_iter().map(|r| r.mode).collect(),
        shapes,
        real,
    }
}

/// Sorts `raw` by frequency and numbers it per whirl direction: rotor modes 1, 2, …;
/// electrical modes by branch letter, count and ring suffix.
fn sort_and_label(raw: &mut [RawMode], slots: &[Slot]) {
    raw.sort_by(|a, b| a.mode.frequency.total_cmp(&b.mode.frequency));
    for whirl in Whirl::all() {
        let mut mech = 0;
        let mut elec = vec![0; slots.len()];
        for r in raw.iter_mut().filter(|r| r.mode.whirl == whirl) {
            r.mode.label = match r.branch {
                None => {
                    mech += 1;
                    mech.to_string()
                }
                Some(s) => {
                    elec[s] += 1;
                    format!("{}{}{}", branch_letter(slots[s].branch), elec[s], slots[s].suffix)
                }
            };
        }
    }
}

/// An electrical mode family: the charges whose kinetic energy decides that a mode
/// belongs to it, its branch and its label suffix.
struct Slot {
    /// (ring, branch) charge DOFs.
    charges: Vec<(usize, usize)>,
    /// Branch index (the letter: r, s, t, …).
    branch: usize,
    /// `""` or `@ringname`.
    suffix: String,
}

/// The electrical mode families. When two or more rings carry an identical circuit (the
/// shorthand always does), one per branch over all rings, labelled as in the paper
/// (`r1`, `r2`, `s1`, …: branch letter and count); otherwise (circuits that differ, or a
/// single ring) one per ring and branch, labelled with the ring's name (`r1@drive`,
/// `s1@aux`), so that a label says which support the mode belongs to.
fn electrical_slots(rotor: &Rotor) -> Vec<Slot> {
    let model = &rotor.model;
    let dofs = &rotor.system.dofs;
    if !model.labels_by_ring() {
        let branches = dofs.branches.first().copied().unwrap_or(0);
        return (0..branches)
            .map(|b| Slot { charges: (0..dofs.rings()).map(|r| (r, b)).collect(), branch: b, suffix: String::new() })
            .collect();
    }
    let mut slots = Vec::new();
    for (r, ring) in model.rings.iter().enumerate() {
        for b in 0..dofs.branches[r] {
            slots.push(Slot { charges: vec![(r, b)], branch: b, suffix: format!("@{}", ring.name) });
        }
    }
    slots
}

/// λ = jω refined by the Rayleigh functional of an undamped (C = 0) gyroscopic model:
/// with a = xᴴMx > 0, b = xᴴG̃x (G̃ = Im D = −ΩG), c = xᴴKx > 0 (all real: M, G̃, K real
/// symmetric), xᴴ(λ²M + λ·jG̃ + K)x = 0 at λ = jω reads a·ω² + b·ω − c = 0, whose roots
/// are real and of opposite signs: ω is the one of the whirl direction of λ, and the
/// damping is exactly zero, as it is for any conservative system. The Rayleigh functional
/// of a Hermitian problem is second-order accurate in the error of x. Shift-invert's
/// eigenvalues of the same model carry spurious damping of up to ±1e-3 on its high modes,
/// which this removes. λ is returned unchanged where a, c or the roots are not finite and
/// positive.
fn undamped_rayleigh(
    m: MatRef<'_, f64>,
    d: MatRef<'_, c64>,
    k: MatRef<'_, f64>,
    lambda: c64,
    x: faer::ColRef<'_, c64>,
) -> c64 {
    let n = m.nrows();
    let form = |entry: &dyn Fn(usize, usize) -> f64| {
        let mut acc = c64::new(0.0, 0.0);
        for j in 0..n {
            let mut col = c64::new(0.0, 0.0);
            for i in 0..n {
                col += x[i].conj() * entry(i, j);
            }
            acc += col * x[j];
        }
        acc.re
    };
    let a = form(&|i, j| m[(i, j)]);
    let b = form(&|i, j| d[(i, j)].im);
    let c = form(&|i, j| k[(i, j)]);
    if !(a > 0.0 && c > 0.0 && a.is_finite() && b.is_finite() && c.is_finite()) {
        return lambda;
    }
    // a·ω² + b·ω − c = 0 without cancellation: q = −(b + sign(b)·√(b² + 4ac))/2, roots q/a
    // and −c/q.
    let q = -0.5 * (b + b.signum() * (b * b + 4.0 * a * c).sqrt());
    let (w1, w2) = (q / a, -c / q);
    let omega = if (w1 > 0.0) == (lambda.im > 0.0) { w1 } else { w2 };
    if omega.is_finite() {
        c64::new(0.0, omega)
    } else {
        lambda
    }
}

/// The paper names the electrical modes of branch 1 `r` and of branch 2 `s`; further
/// branches continue the alphabet (t, u, …) and then use `e<branch>-`.
pub fn branch_letter(branch: usize) -> String {
    const LETTERS: [&str; 8] = ["r", "s", "t", "u", "v", "w", "x", "y"];
    LETTERS.get(branch).map(|s| s.to_string()).unwrap_or_else(|| format!("e{}-", branch + 1))
}

/// Relative distance below which two eigenvalues of the real coordinates are one
/// degenerate whirl frequency: an isotropic rotor at rest has each whirl twice (its
/// forward and backward circles), found to ~1e-14 apart, and any combination of the two
/// vectors is a mode. Such a cluster is turned into the combinations of extreme forward
/// and backward content (the circles, when the rotor is isotropic), as the complex
/// coordinates give them; whirls 1e-10 apart are a double whirl for every output.
pub const DEGENERATE_WHIRLS: f64 = 1e-10;

/// Whirls searched per whirl asked of each direction on the real path
/// ([`ModesResult::window`]): `modes --count N` lists the lowest N forward, N backward and
/// N mixed whirls among the lowest 4N whirls by |λ|. A window because the direction is
/// known only from a mode's orbits: an anisotropic rotor at rest has planar (mixed) modes
/// only, and its forward orbits may be FE modes a hundred times higher; three directions
/// and a quarter to spare (ROSS lists its lowest whirls whatever their direction).
pub const WHIRL_WINDOW: usize = 4;

/// First-order state (2 × the real DOFs) from which [`lowest_whirls_of`] uses the
/// shift-invert Krylov solver rather than the dense one: below it the dense solve takes a
/// few milliseconds (measured 3 ms at 200 states), and the Krylov space would be a good
/// part of the state.
pub const KRYLOV_MIN_STATE: usize = 200;

/// The largest Krylov space [`lowest_whirls_of`] grows, as a fraction 1/this of the
/// first-order state: its Rayleigh–Ritz solves cost ~(1/3)³ of the dense solve each, and
/// a window needing more is cheaper dense.
pub const KRYLOV_STATE_FRACTION: usize = 3;

/// Relative QEP residual ([`crate::linalg::qep_residual`]) every whirl of the window must
/// have on the shift-invert path, or the dense solver is used: the dense solver leaves
/// ~1e-13 on the lowest whirls, and a converged Krylov pair (relative Ritz residual
/// [`crate::linalg::KRYLOV_TOLERANCE`]) as little; 1e-10 is a thousand times that and ten
/// thousand below [`MODE_RESIDUAL_LIMIT`].
pub const KRYLOV_RESIDUAL_LIMIT: f64 = 1e-10;

/// The whirl modes [`ModesResult::lowest`]`(count)` lists, and on the real path the
/// window it chooses from: all the modes of [`whirl_modes_of`] in complex coordinates or
/// on a small model; on a large model in real coordinates, the whirls nearest λ = 0 by
/// block shift-invert Krylov ([`whirl_modes_nearest`]), falling back to the dense solve
/// when that does not resolve them.
pub fn lowest_whirls_of(
    rotor: &Rotor,
    settings: &Settings,
    speed: f64,
    count: usize,
) -> Result<ModesResult, AnalysisError> {
    whirls_at_least(rotor, settings, speed, WHIRL_WINDOW * count)
}

/// [`whirl_modes_of`], or on the real path of a large model at least the lowest `whirls`
/// whirls by |λ| (all those below the radius resolved).
pub(crate) fn whirls_at_least(
    rotor: &Rotor,
    settings: &Settings,
    speed: f64,
    whirls: usize,
) -> Result<ModesResult, AnalysisError> {
    if rotor.real && 2 * rotor.general_size() >= KRYLOV_MIN_STATE {
        let limit = 2 * rotor.general_size() / KRYLOV_STATE_FRACTION;
        if let Some(r) = whirl_modes_nearest(rotor, settings, speed, whirls, limit)? {
            return Ok(r);
        }
    }
    whirl_modes_of(rotor, settings, speed)
}

/// The lowest `whirls` whirls by |λ| of a rotor on the real path (every whirl with |λ|
/// below the radius the solve resolves: at least `whirls`, fewer only when the model has
/// fewer), by block shift-invert Krylov at σ = 0 ([`crate::linalg::ShiftInvert`]) with a
/// space of at most `limit` vectors. `Ok(None)` where that solve does not apply or does
/// not resolve them: the complex path, a singular K, a space beyond `limit`, a cluster
/// of as many eigenvalues as the block, a whirl of the window with a relative QEP
/// residual above [`KRYLOV_RESIDUAL_LIMIT`].
pub fn whirl_modes_nearest(
    rotor: &Rotor,
    settings: &Settings,
    speed: f64,
    whirls: usize,
    limit: usize,
) -> Result<Option<ModesResult>, AnalysisError> {
    whirl_modes_nearest_by(rotor, settings, speed, whirls, limit, NearestSolver::Block)
}

/// The eigensolver of [`whirl_modes_nearest_by`]'s shift-invert operator. `modes` uses
/// [`NearestSolver::Block`]; [`NearestSolver::Faer`] is kept as its measured comparison
/// (benches/modes.rs, docs/decisions.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NearestSolver {
    /// The block Krylov space with Rayleigh–Ritz ([`crate::linalg::ShiftInvert::nearest`]).
    Block,
    /// faer's partial eigensolver, Krylov–Schur
    /// ([`crate::linalg::ShiftInvert::nearest_by_faer`]).
    Faer,
}

/// [`whirl_modes_nearest`] with the operator's eigenpairs from `solver`: the same operator,
/// count, acceptance and fallback (`Ok(None)`), to compare the two solvers.
pub fn whirl_modes_nearest_by(
    rotor: &Rotor,
    settings: &Settings,
    speed: f64,
    whirls: usize,
    limit: usize,
    solver: NearestSolver,
) -> Result<Option<ModesResult>, AnalysisError> {
    if !rotor.real {
        return Ok(None);
    }
    let sys = rotor.general_at(speed);
    let d = sys.damping();
    let k = sys.stiffness_at(rotor.static_load());
    let Some(mut op) = crate::linalg::ShiftInvert::new(sys.m.as_ref(), d.as_ref(), k.as_ref(), 0.0, limit) else {
        return Ok(None);
    };
    // Each whirl is a conjugate pair; real eigenvalues (overdamped charges) are found too
    // and make the count grow below.
    let mut wanted = 2 * whirls.max(1);
    loop {
        let found = match solver {
            NearestSolver::Block => op.nearest(wanted),
            NearestSolver::Faer => op.nearest_by_faer(wanted, limit),
        };
        let Some(found) = found else { return Ok(None) };
        let n2 = sys.size();
        let kept: Vec<(c64, Vec<c64>)> = found
            .values
            .iter()
            .enumerate()
            .filter(|(_, l)| l.im > settings.oscillation_tolerance * l.norm())
            .map(|(c, l)| (*l, (0..n2).map(|i| found.vectors[(i, c)]).collect()))
            .collect();
        if kept.len() >= whirls || found.radius == f64::INFINITY {
            let (total, count) = (found.values.len(), kept.len());
            let r = real_result(rotor, settings, speed, &sys, &d, &k, kept, total)?;
            // Every pair found is reported (none dropped as not finite) and resolved.
            if r.modes.len() < count
                || r.modes.iter().any(|m| m.residual.is_nan() || m.residual > KRYLOV_RESIDUAL_LIMIT)
            {
                return Ok(None);
            }
            return Ok(Some(r));
        }
        wanted *= 2;
    }
}

/// Whirl modes in real coordinates (the general path): the real QEP of
/// [`crate::assembly::GeneralSystem`] at Ω, each whirl once (the eigenvalue with
/// Im λ > 0 of each conjugate pair), its direction and ellipticity from its shaft nodes'
/// orbits ([`super::orbit::classify`]). A backward whirl reports λ̄ (Im λ < 0), as the
/// complex coordinates do.
fn real_modes(rotor: &Rotor, settings: &Settings, speed: f64) -> Result<ModesResult, AnalysisError> {
    use crate::linalg::solve_qep_real;
    let sys = rotor.general_at(speed);
    let d = sys.damping();
    let k = sys.stiffness_at(rotor.static_load());
    let n2 = sys.size();
    let sol = match solve_qep_real(sys.m.as_ref(), d.as_ref(), k.as_ref()) {
        Some(sol) => sol,
        None => {
            let dc = Mat::from_fn(n2, n2, |i, j| c64::new(d[(i, j)], 0.0));
            solve_qep(sys.m.as_ref(), dc.as_ref(), k.as_ref(), QEP_SHIFT)?
        }
    };
    let total = sol.values.len();
    // One of each conjugate pair: Im λ > 0, oscillatory, finite.
    let kept: Vec<(c64, Vec<c64>)> = sol
        .values
        .iter()
        .enumerate()
        .filter(|(_, l)| l.re.is_finite() && l.im.is_finite())
        .filter(|(_, l)| l.im > settings.oscillation_tolerance * l.norm())
        .map(|(c, l)| (*l, (0..n2).map(|i| sol.vectors[(i, c)]).collect()))
        .collect();
    real_result(rotor, settings, speed, &sys, &d, &k, kept, total)
}

/// The whirl modes of eigenpairs `kept` (Im λ > 0, x of 2n real-coordinate entries) of
/// the real QEP of `sys` with velocity matrix `d` and stiffness `k`; `total` eigenvalues
/// were computed.
#[allow(clippy::too_many_arguments)]
fn real_result(
    rotor: &Rotor,
    settings: &Settings,
    speed: f64,
    sys: &crate::assembly::GeneralSystem,
    d: &Mat<f64>,
    k: &Mat<f64>,
    mut kept: Vec<(c64, Vec<c64>)>,
    total: usize,
) -> Result<ModesResult, AnalysisError> {
    let n2 = sys.size();
    let n = n2 / 2;
    let dc = Mat::from_fn(n2, n2, |i, j| c64::new(d[(i, j)], 0.0));
    let circulatory = (0..n2).any(|i| (0..i).any(|j| k[(i, j)] != k[(j, i)]));
    kept.sort_by(|a, b| a.0.im.total_cmp(&b.0.im));
    separate_planes(&mut kept, d, k);
    circularise(&mut kept, n);
    let kinds = sys.dofs.kinds();
    let slots = electrical_slots(rotor);
    let norms = QepNorms::of(sys.m.as_ref(), dc.as_ref(), k.as_ref());
    let nodes = sys.dofs.nodes;
    let mut raw = Vec::new();
    for (col, (lambda, x)) in kept.iter().enumerate() {
        let xc = faer::Col::from_fn(n2, |i| x[i]);
        let residual = qep_residual_with(&norms, sys.m.as_ref(), dc.as_ref(), k.as_ref(), *lambda, xc.as_ref());
        if !residual.is_finite() {
            continue;
        }
        // Kinetic energy xᴴMx by DOF (M is block diagonal, the same in both planes).
        let mut energy = vec![0.0; n];
        for plane in 0..2 {
            for i in 0..n {
                let mut acc = c64::new(0.0, 0.0);
                for j in 0..n {
                    let mij = sys.m[(plane * n + i, plane * n + j)];
                    if mij != 0.0 {
                        acc += x[plane * n + j] * mij;
                    }
                }
                energy[i] += (x[plane * n + i].conj() * acc).re;
            }
        }
        let all: f64 = energy.iter().sum();
        let charge: f64 = (0..n).filter(|&i| kinds[i] == DofKind::Charge).map(|i| energy[i]).sum();
        let per_branch: Vec<f64> = slots
            .iter()
            .map(|slot| {
                slot.charges
                    .iter()
                    .map(|&(ring, b)| {
                        let i = sys.dofs.charge(ring, b);
                        sys.m[(i, i)] * (x[i].norm_sqr() + x[n + i].norm_sqr())
                    })
                    .sum()
            })
            .collect();
        let fraction = if all > 0.0 { charge / all } else { 0.0 };
        let kind = if fraction > settings.electrical_fraction { ModeKind::Electrical } else { ModeKind::Mechanical };
        let branch = (kind == ModeKind::Electrical)
            .then(|| (0..per_branch.len()).max_by(|&a, &b| per_branch[a].total_cmp(&per_branch[b])).unwrap_or(0));
        let orbits: Vec<super::orbit::Orbit> = (0..nodes)
            .map(|node| {
                let dof = sys.dofs.deflection(node);
                super::orbit::Orbit::of(x[dof], x[n + dof])
            })
            .collect();
        let (whirl, kappa) = super::orbit::classify(&orbits);
        let damping_ratio = if lambda.re == 0.0 { 0.0 } else { -lambda.re / lambda.norm() };
        let flag = if residual > MODE_RESIDUAL_LIMIT {
            Some(ModeFlag::Residual { residual })
        } else if damping_ratio < -NEGATIVE_DAMPING_LIMIT {
            Some(ModeFlag::NegativeDamping { damping_ratio })
        } else {
            None
        };
        // A cross-coupled stiffness is circulatory: it may feed a mode, and a negative ζ
        // is then physics (e.g. oil whirl), not round-off.
        let flag = match flag {
            Some(ModeFlag::NegativeDamping { .. }) if circulatory => None,
            other => other,
        };
        let reported = if whirl == Whirl::Backward { lambda.conj() } else { *lambda };
        raw.push(RawMode {
            col,
            branch,
            mode: WhirlMode {
                frequency: lambda.im,
                whirl,
                damping_ratio,
                label: String::new(),
                kind,
                electrical_fraction: fraction,
                eigenvalue: [reported.re, reported.im],
                residual,
                ellipticity: Some(kappa),
                flag,
            },
        });
    }
    if raw.is_empty() {
        return Err(AnalysisError::NoWhirlModes {
            speed,
            eigenvalues: total,
            tolerance: settings.oscillation_tolerance,
        });
    }
    Ok(numbered(rotor, speed, raw, &slots, n2, |i, col| kept[col].1[i], true))
}

/// Share of a mode's 2-norm in its weaker plane below which `separate_planes` sets that
/// plane to zero: round-off of a solve mixes the planes by ~ε over the relative gap
/// between an x-plane and a y-plane whirl (measured 3e-12 on the Jeffcott rotor of
/// tests/fast_modes.rs from the Krylov solve); 1e-6 separates whirls down to gaps of
/// ~1e-10, where `circularise` takes over.
pub const PLANE_NOISE: f64 = 1e-6;

/// Where the planes do not couple (no gyroscopic term at the speed, no cross-coupled
/// stiffness or damping, M block diagonal as always), every whirl that is not degenerate
/// lies in one plane: its orbits are lines. The dense solver keeps the other plane
/// exactly zero (its reductions keep zero blocks), a Krylov solve from a random start
/// leaves round-off there, which would give a line orbit a direction
/// ([`super::orbit::LINE_TOLERANCE`]); so a plane holding less than [`PLANE_NOISE`] of
/// a mode is set to zero, on both solvers' modes alike.
fn separate_planes(modes: &mut [(c64, Vec<c64>)], d: &Mat<f64>, k: &Mat<f64>) {
    let n = d.nrows() / 2;
    let coupled = |a: &Mat<f64>| (0..n).any(|j| (0..n).any(|i| a[(i, n + j)] != 0.0 || a[(n + i, j)] != 0.0));
    if coupled(d) || coupled(k) {
        return;
    }
    for (_, x) in modes.iter_mut() {
        let norm = |part: &[c64]| part.iter().map(|v| v.norm_sqr()).sum::<f64>().sqrt();
        let (a, b) = (norm(&x[..n]), norm(&x[n..]));
        let weak = if b <= PLANE_NOISE * a {
            n..2 * n
        } else if a <= PLANE_NOISE * b {
            0..n
        } else {
            continue;
        };
        for v in &mut x[weak] {
            *v = c64::new(0.0, 0.0);
        }
        let total = norm(x);
        if total > 0.0 && total.is_finite() {
            for v in x.iter_mut() {
                *v /= total;
            }
        }
    }
}

/// Within each cluster of degenerate whirls ([`DEGENERATE_WHIRLS`]) of `modes` (sorted by
/// Im λ; vectors of 2n real-coordinate entries), replace the vectors by the combinations
/// that diagonalise the forward-minus-backward content Σ(|F_i|² − |B_i|²) over the
/// complex DOFs i against Σ|x|²: in an isotropic rotor, the forward and the backward
/// circle.
fn circularise(modes: &mut [(c64, Vec<c64>)], n: usize) {
    use faer::linalg::triangular_solve::{solve_lower_triangular_in_place, solve_upper_triangular_in_place};
    let j = c64::new(0.0, 1.0);
    let mut start = 0;
    while start < modes.len() {
        let mut end = start + 1;
        while end < modes.len() && (modes[end].0 - modes[start].0).norm() <= DEGENERATE_WHIRLS * modes[start].0.norm() {
            end += 1;
        }
        let k = end - start;
        if k >= 2 {
            let x = Mat::from_fn(2 * n, k, |i, c| modes[start + c].1[i]);
            let yf = Mat::from_fn(n, k, |i, c| (x[(i, c)] + j * x[(n + i, c)]) * 0.5);
            let yb = Mat::from_fn(n, k, |i, c| (x[(i, c)] - j * x[(n + i, c)]) * 0.5);
            // Aᴴ·B of two column sets.
            let inner = |p: &Mat<c64>, q: &Mat<c64>| {
                Mat::from_fn(k, k, |a, b| (0..p.nrows()).map(|i| p[(i, a)].conj() * q[(i, b)]).sum::<c64>())
            };
            let (pf, pb, gram) = (inner(&yf, &yf), inner(&yb, &yb), inner(&x, &x));
            let w = Mat::from_fn(k, k, |a, b| pf[(a, b)] - pb[(a, b)]);
            if let Ok(l) = crate::linalg::seq::cholesky(gram.as_ref()) {
                // L⁻¹·W·L⁻ᴴ, Hermitian.
                let mut t = w.clone();
                solve_lower_triangular_in_place(l.as_ref(), t.as_mut(), Par::Seq);
                let mut h = Mat::from_fn(k, k, |a, b| t[(b, a)].conj());
                solve_lower_triangular_in_place(l.as_ref(), h.as_mut(), Par::Seq);
                let h = Mat::from_fn(k, k, |a, b| (h[(a, b)] + h[(b, a)].conj()) * 0.5);
                if let Ok(e) = crate::linalg::seq::self_adjoint_eigen(h.as_ref()) {
                    let mut c = e.vectors;
                    let lh = Mat::from_fn(k, k, |a, b| l[(b, a)].conj());
                    solve_upper_triangular_in_place(lh.as_ref(), c.as_mut(), Par::Seq);
                    let rotated = crate::linalg::seq::product(x.as_ref(), c.as_ref());
                    for col in 0..k {
                        let norm = (0..2 * n).map(|i| rotated[(i, col)].norm_sqr()).sum::<f64>().sqrt();
                        if norm > 0.0 && norm.is_finite() {
                            modes[start + col].1 = (0..2 * n).map(|i| rotated[(i, col)] / norm).collect();
                        }
                    }
                }
            }
        }
        start = end;
    }
}
