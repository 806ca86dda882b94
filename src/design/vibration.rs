//! Vibration suppression in a design: the peak unbalance response at a node (the
//! min-peak-response objective), the constraints any objective may carry, and the classic
//! single-mode RL shunt tuning that seeds the optimiser.
//!
//! **Classic tuning.** For a series R–L shunt on a piezoelectric element whose mode has
//! the effective coupling K² = (ω_D² − ω_E²)/ω_E² (ω_D, ω_E the mode's open- and
//! short-circuit frequencies), the equal-peak (fixed-point, Den Hartog type) optimum of
//! the mechanical response is
//!
//! ```text
//! δ_opt = ω_e/ω_E = √(1 + K²)   (so ω_e = ω_D),      r_opt = R·C·ω_E = √(3/2)·K,
//! ```
//!
//! the tuning of Hagood & von Flotow, "Damping of structural vibrations with
//! piezoelectric materials and passive electrical networks", J. Sound Vib. 146(2),
//! 243–268 (1991), and the resistance of Thomas, Ducarne & Deü, "Performance of
//! piezoelectric shunts for vibration reduction", Smart Mater. Struct. 21, 015008 (2012)
//! (their electrical damping ratio ξ_e = √(3/8)·k, r = 2ξ_e). Hagood & von Flotow's own
//! resistance √2·K/(1 + K²) lies 15 % above the min–max optimum of their two-mode model
//! (`docs/decisions.md`, "Classic RL tuning"), so the fixed-point value is used.
//!
//! with ω_e = 1/√(L·C) the electrical frequency of the loop and C its capacitance. In this
//! model a branch is the loop C_p^S – C_f – L – R (Eq. A8: charge mass γL, damping γR,
//! stiffness γ(1/C_p^S + 1/C_f)); its two reference states are **open**, the branch
//! removed (no current), and **short**, the branch with L = R = 0 (the stack shunted by
//! C_f alone; C_f → ∞ is the true short circuit). ω_D is the mode's synchronous critical
//! speed Ω* (ω = Ω, where unbalance excites it) with the branch open, ω_E its frequency
//! at Ω* with the branch short. The loop's capacitance C is the one the structure sees
//! (the ring DOF and the shaft move with the charge, so it lies between the clamped
//! C_p^S·C_f/(C_p^S + C_f) and the free one of Eq. 4): at a trial L with R = 0 the two
//! coupled forward frequencies ω₁, ω₂ nearest ω_D obey ω₁²ω₂² = ω_e²ω_E² in the two-mode
//! model, which gives ω_e and C = 1/(L·ω_e²). Then L_opt = 1/(ω_D²·C) and
//! R_opt = √(3/2)·K/(C·ω_E); Eq. (4) (with C_p^T) converts L to the branch's
//! `tuning_frequency`.

use super::evaluate::{
    frequency_margin, intrusions, machine_at, margin_shortfall, operating_bands, operating_bands_at, Candidate,
    EvalContext,
};
use super::machine::Machine;
use super::spec::{DesignSpec, Parameter, Response};
use super::DesignError;
use crate::analysis::damping::mode_damping;
use crate::analysis::modes::whirl_modes_of;
use crate::analysis::unbalance::{node_probe, peak_at_node, unbalance_response, UnbalanceResult};
use crate::analysis::{Rotor, Settings};
use crate::model::{CircuitState, Model};
use crate::progress::Silent;
use serde::{Deserialize, Serialize};

/// Fixed-point iterations Ω ← ω(Ω) of a synchronous critical speed at most; the
/// gyroscopic slope dω/dΩ of a rotor whirl is well below 1, so the error shrinks by that
/// factor per step.
const CRITICAL_ITERATIONS: usize = 60;
/// Relative change of the fixed-point iteration at which a critical speed is taken as
/// converged: far below the per-cent differences the seed is about.
const CRITICAL_TOLERANCE: f64 = 1e-10;
/// Forward rotor whirls (f1, f2, …) looked at for the target mode of the classic tuning.
const TARGET_CANDIDATES: usize = 4;

/// The largest amplitude at the response node over its speeds.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PeakValue {
    /// Speed of the largest amplitude (rad/s).
    pub speed: f64,
    /// The amplitude (m).
    pub amplitude: f64,
    /// The peak is a pole (an undamped critical speed): its amplitude is limited only by
    /// the refinement.
    pub unbounded: bool,
}

/// The peak at `r`'s node over its speed grid, refined ([`peak_at_node`]).
pub fn peak_of(rotor: &Rotor, r: &Response) -> Result<PeakValue, DesignError> {
    let (speed, amplitude, unbounded) = peak_at_node(rotor, r.node, &r.grid())?;
    Ok(PeakValue { speed, amplitude, unbounded })
}

/// Successive parabolic steps at most refining one local maximum of the recheck.
const PARABOLIC_STEPS: usize = 200;
/// The recheck's refinement stops when its bracket, or its last step, is below this
/// fraction of the speed: the bracket of the optimiser's golden-section search
/// ([`crate::analysis::unbalance::PEAK_SPEED_TOLERANCE`]), so a bounded peak's
/// amplitude is resolved far below the 0.5 % agreement asked.
const PARABOLIC_BRACKET: f64 = 1e-10;
/// Every this many steps the recheck bisects the larger side of its bracket instead of a
/// parabolic step, so that a bracket end that stops moving cannot stall it.
const BISECT_EVERY: usize = 3;

/// The peak at `r`'s node found again, independently of [`peak_of`]: on a grid of
/// (points − 1)·`factor` + 1 speeds over the range, every interior local maximum refined
/// by successive parabolic interpolation of 1/|U|² (a quadratic in Ω near a resonance,
/// where |U| is Lorentzian), safeguarded by bisection; the largest of those and the grid's
/// end values. `unbounded` when the amplitude half of
/// [`crate::analysis::unbalance::UNBOUNDED_BANDWIDTH`]·Ω away on either side of the peak is
/// below 1/√2 of it: a half-power band narrower than that (a pole). Returns the peak and
/// the number of grid speeds.
pub fn peak_recheck(rotor: &Rotor, r: &Response, factor: usize) -> Result<(PeakValue, usize), DesignError> {
    use crate::analysis::unbalance::UNBOUNDED_BANDWIDTH;
    use crate::analysis::unbalance::{DynamicStiffness, Workspace};
    use rayon::prelude::*;
    let n = (r.points.max(2) - 1) * factor.max(1) + 1;
    let (lo, hi) = (r.speeds.lo, r.speeds.hi);
    let speeds: Vec<f64> = (0..n).map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64).collect();
    for &w in &speeds {
        crate::analysis::limits::response_speed(w).map_err(crate::analysis::AnalysisError::from)?;
    }
    let dof = node_probe(&rotor.system.dofs, r.node)?.dof;
    let a = DynamicStiffness::of(rotor)?;
    let amp = |w: f64, work: &mut Workspace| -> Result<f64, DesignError> { Ok(a.amplitude(&a.solve(w, work)?, dof).0) };
    let samples: Vec<f64> = speeds
        .par_iter()
        .map_init(Workspace::default, |work, &w| amp(w, work))
        .collect::<Result<Vec<f64>, DesignError>>()?;
    let mut work = Workspace::default();
    let mut best = (speeds[0], samples[0]);
    if samples[n - 1] > best.1 {
        best = (speeds[n - 1], samples[n - 1]);
    }
    for i in 1..n - 1 {
        if !(samples[i] > samples[i - 1] && samples[i] >= samples[i + 1]) {
            continue;
        }
        // Minimise g = 1/|U|² on the bracket (a, b, c), b the best point so far.
        let g = |x: f64| 1.0 / (x * x);
        let (mut a0, mut b0, mut c0) = (speeds[i - 1], speeds[i], speeds[i + 1]);
        let (mut ga, mut gb, mut gc) = (g(samples[i - 1]), g(samples[i]), g(samples[i + 1]));
        let mut top = (b0, samples[i]);
        for step in 0..PARABOLIC_STEPS {
            if c0 - a0 <= PARABOLIC_BRACKET * b0 {
                break;
            }
            let num = (b0 - a0).powi(2) * (gb - gc) - (b0 - c0).powi(2) * (gb - ga);
            let den = (b0 - a0) * (gb - gc) - (b0 - c0) * (gb - ga);
            let vertex = b0 - 0.5 * num / den;
            let bisect = (c0 - b0).max(b0 - a0);
            let x = if step % BISECT_EVERY == BISECT_EVERY - 1
                || !vertex.is_finite()
                || vertex <= a0
                || vertex >= c0
                || vertex == b0
            {
                if c0 - b0 > b0 - a0 {
                    b0 + 0.5 * bisect
                } else {
                    b0 - 0.5 * bisect
                }
            } else {
                vertex
            };
            let ax = amp(x, &mut work)?;
            let gx = g(ax);
            let moved = (x - b0).abs();
            if gx < gb {
                if x < b0 {
                    (c0, gc) = (b0, gb);
                } else {
                    (a0, ga) = (b0, gb);
                }
                (b0, gb) = (x, gx);
                top = (x, ax);
            } else if x < b0 {
                (a0, ga) = (x, gx);
            } else {
                (c0, gc) = (x, gx);
            }
            if moved <= PARABOLIC_BRACKET * b0 {
                break;
            }
        }
        if top.1 > best.1 {
            best = top;
        }
    }
    let (speed, amplitude) = best;
    let half = amplitude / std::f64::consts::SQRT_2;
    let d = 0.5 * UNBOUNDED_BANDWIDTH * speed;
    let unbounded = amp(speed - d, &mut work)? < half && amp(speed + d, &mut work)? < half;
    Ok((PeakValue { speed, amplitude, unbounded }, n))
}

/// The response at `r`'s node over its grid, with its peaks (for reports).
pub fn response_of(rotor: &Rotor, r: &Response) -> Result<UnbalanceResult, DesignError> {
    let probe = node_probe(&rotor.system.dofs, r.node)?;
    Ok(unbalance_response(rotor, &r.grid(), std::slice::from_ref(&probe), &crate::progress::Silent)?)
}

/// What a constraint is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ConstraintKind {
    /// The operating bands clear at β_op: value = total intrusion (rad/s), limit 0.
    BandsClear,
    /// The stable band around φ_op at least a width: value = the smallest signed width
    /// over the speeds (rad/s).
    BandWidth,
    /// The peak response at most a limit: value = the peak (m).
    Peak,
    /// A whirl's damping ratio at least a limit: value = its smallest ζ over the
    /// operating speeds (−).
    Damping,
    /// `[design.margins]`: value = the frequency margin min(φ_op − lo, hi − φ_op) of the
    /// band around φ_op at the margin level (1 + beta)·β_op, the smallest over the speeds
    /// (rad/s; minus the depth into the tongue where φ_op is unstable there), limit `phi`.
    Margins,
}

/// Scale of the margin constraint's relative violation (rad/s): a shortfall is judged
/// relative to the frequency margin asked, or to this where less is asked (a margin of
/// 0 only asks φ_op to be stable at the margin level): 10 rad/s is 50 lattice cells of
/// the band edges (0.125 rad/s) and under 1 % of the paper's φ_op.
pub const MARGIN_SCALE: f64 = 10.0;

/// One constraint judged on one design.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ConstraintCheck {
    /// What it is about.
    pub kind: ConstraintKind,
    /// In words, e.g. `zeta of f1 >= 0.02`.
    pub name: String,
    /// The design's value (unit of the kind).
    pub value: f64,
    /// The limit (same unit).
    pub limit: f64,
    /// Whether it is met.
    pub met: bool,
    /// How far it is missed, relative to its scale (0 when met): intrusion over the band's
    /// guarded width, or the shortfall over the limit. What the optimiser's penalty sums.
    pub violation: f64,
}

/// The constraints of the spec on the design `c` (every kind the spec has), and its peak
/// when the spec has a response. The context's counter gets the Floquet evaluations.
pub fn check_constraints(
    c: &Candidate,
    ev: &EvalContext<'_>,
    peak: Option<PeakValue>,
) -> Result<Vec<ConstraintCheck>, DesignError> {
    let spec = ev.spec;
    let k = &spec.constraints;
    let mut out = Vec::new();
    if !k.bands.is_empty() {
        let ints = intrusions(c, ev)?;
        let mut violation = 0.0;
        let mut total = 0.0;
        for it in ints.iter().filter(|i| i.inside) {
            let b = &spec.kept_clear()[it.band];
            total += it.violation();
            violation += it.violation() / b.guarded().width().max(f64::MIN_POSITIVE);
        }
        out.push(ConstraintCheck {
            kind: ConstraintKind::BandsClear,
            name: format!("{} operating band(s) clear at beta_op = {}", k.bands.len(), spec.level),
            value: total,
            limit: 0.0,
            met: total == 0.0,
            violation,
        });
    }
    if let Some(w) = k.min_band_width {
        let bands = operating_bands(c, ev, w.phi_op)?;
        let width = bands.iter().map(|b| b.signed_width()).fold(f64::INFINITY, f64::min);
        out.push(floor(
            ConstraintKind::BandWidth,
            format!("stable band around {} rad/s >= {} rad/s", w.phi_op, w.width),
            width,
            w.width,
        ));
    }
    if let (Some(m), Some(phi_op)) = (k.margins, spec.phi_op()) {
        let bands = operating_bands_at(c, ev, phi_op, m.level(spec.level))?;
        let shortfall = margin_shortfall(&bands, &m);
        out.push(ConstraintCheck {
            kind: ConstraintKind::Margins,
            name: format!(
                "band around {phi_op} rad/s at beta = {:.6} ((1 + {}) beta_op) with phi_op >= {} rad/s from each edge",
                m.level(spec.level),
                m.beta,
                m.phi
            ),
            value: frequency_margin(&bands),
            limit: m.phi,
            met: shortfall == 0.0,
            violation: shortfall / m.phi.max(MARGIN_SCALE),
        });
    }
    if let (Some(limit), Some(p)) = (k.max_peak, peak) {
        let met = p.amplitude <= limit;
        out.push(ConstraintCheck {
            kind: ConstraintKind::Peak,
            name: format!("peak response <= {limit:e} m"),
            value: p.amplitude,
            limit,
            met,
            violation: if met { 0.0 } else { p.amplitude / limit - 1.0 },
        });
    }
    if !k.damping.is_empty() {
        let zetas = damping_ratios(&c.rotor, &c.machine.settings, spec)?;
        for (f, z) in k.damping.iter().zip(zetas) {
            out.push(floor(ConstraintKind::Damping, format!("zeta of {} >= {}", f.mode, f.min), z, f.min));
        }
    }
    Ok(out)
}

/// A constraint value ≥ limit.
fn floor(kind: ConstraintKind, name: String, value: f64, limit: f64) -> ConstraintCheck {
    let met = value >= limit;
    let scale = limit.abs().max(f64::MIN_POSITIVE);
    ConstraintCheck { kind, name, value, limit, met, violation: if met { 0.0 } else { (limit - value) / scale } }
}

/// The smallest ζ over the operating speeds of each damping constraint's whirl, tracked
/// from the lowest speed ([`mode_damping`]).
pub fn damping_ratios(rotor: &Rotor, settings: &Settings, spec: &DesignSpec) -> Result<Vec<f64>, DesignError> {
    let tags: Vec<String> = spec.constraints.damping.iter().map(|d| d.mode.clone()).collect();
    Ok(mode_damping(rotor, settings, &ascending(&spec.speeds), &tags, &Silent)?
        .into_iter()
        .map(|m| m.min_damping_ratio)
        .collect())
}

/// The speeds sorted, each once.
pub fn ascending(speeds: &[f64]) -> Vec<f64> {
    let mut v = speeds.to_vec();
    v.sort_by(f64::total_cmp);
    v.dedup();
    v
}

/// The classic tuning of the target mode (module docs) and the design it seeds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ClassicTuning {
    /// The target mode's tag (a forward rotor whirl, `f1`, `f2`, …): the lowest whose
    /// open-branch critical speed lies in the response range (else the nearest to it).
    pub mode: String,
    /// The ring (model order) and branch (from 0) tuned.
    pub ring: Option<usize>,
    /// Branch index from 0.
    pub branch: usize,
    /// Critical speed with the branch open, ω_D (rad/s).
    pub omega_open: f64,
    /// The mode's frequency at that speed with the branch's L = R = 0, ω_E (rad/s).
    pub omega_short: f64,
    /// Effective coupling K² = (ω_D² − ω_E²)/ω_E² (−).
    pub coupling: f64,
    /// The loop's capacitance as the structure sees it, C (F) (module docs).
    pub capacitance: f64,
    /// L_opt (H).
    pub inductance: f64,
    /// R_opt (Ω).
    pub resistance: f64,
    /// L_opt as the branch's tuning frequency of Eq. (4) (rad/s).
    pub tuning_frequency: f64,
    /// The design variables at the classic tuning, clamped to their bounds (SI units).
    pub values: Vec<f64>,
    /// Whether a value had to be clamped to a bound.
    pub clamped: bool,
}

/// The synchronous critical speed of the forward whirl tagged `tag`: Ω = ω_tag(Ω), by
/// fixed-point iteration from `start` (rad/s). None when the tag disappears.
fn critical_speed(rotor: &Rotor, settings: &Settings, tag: &str, start: f64) -> Result<Option<f64>, DesignError> {
    let mut w = start;
    for _ in 0..CRITICAL_ITERATIONS {
        let modes = whirl_modes_of(rotor, settings, w)?;
        let Some(f) = modes.forward().find(|m| m.tag() == tag).map(|m| m.frequency) else { return Ok(None) };
        if (f - w).abs() <= CRITICAL_TOLERANCE * f {
            return Ok(Some(f));
        }
        w = f;
    }
    Ok(Some(w))
}

/// The forward whirl tagged `tag` at speed Ω (rad/s).
fn forward_frequency(rotor: &Rotor, settings: &Settings, tag: &str, speed: f64) -> Result<Option<f64>, DesignError> {
    Ok(whirl_modes_of(rotor, settings, speed)?.forward().find(|m| m.tag() == tag).map(|m| m.frequency))
}

/// The model with branch `branch` of the rings `rings` at inductance L (H) and R = 0.
fn with_branch(model: &Model, rings: &[usize], branch: usize, inductance: f64) -> Model {
    let mut m = model.clone();
    for &r in rings {
        let b = &mut m.rings[r].circuit.branches[branch];
        b.inductance = inductance;
        b.resistance = 0.0;
    }
    m
}

/// The model with branch `branch` of the rings `rings` removed (open) or with L = R = 0
/// (short, C_f only).
fn branch_state(model: &Model, rings: &[usize], branch: usize, open: bool) -> Model {
    let mut m = model.clone();
    for &r in rings {
        let c = &mut m.rings[r].circuit;
        if open {
            c.branches.remove(branch);
            if c.branches.is_empty() {
                c.state = CircuitState::Open;
            }
        } else {
            c.branches[branch].inductance = 0.0;
            c.branches[branch].resistance = 0.0;
        }
    }
    m
}

/// The classic tuning for `spec`'s response range, on the branch of the first tuning
/// (or resistance) variable; None without such a variable or without a response.
pub fn classic_tuning(base: &Machine, spec: &DesignSpec) -> Result<Option<ClassicTuning>, DesignError> {
    let Some(response) = spec.response() else { return Ok(None) };
    let target = spec
        .variables
        .iter()
        .find(|v| matches!(v.parameter, Parameter::TuningFrequency | Parameter::Inductance))
        .or_else(|| spec.variables.iter().find(|v| v.parameter == Parameter::Resistance));
    let Some(target) = target else { return Ok(None) };
    let rings: Vec<usize> = match target.ring {
        Some(r) => vec![r],
        None => (0..base.model.rings.len()).collect(),
    };
    let Some(&first) = rings.first() else { return Ok(None) };
    let settings = &base.settings;
    let open = Rotor::new(&branch_state(&base.model, &rings, target.branch, true))?;
    let short = Rotor::new(&branch_state(&base.model, &rings, target.branch, false))?;
    // The target: the lowest forward rotor whirl whose open critical speed is in range.
    let at_rest = whirl_modes_of(&open, settings, 0.0)?;
    let rotor_tags: Vec<(String, f64)> = at_rest
        .forward()
        .filter(|m| m.label.chars().all(|c| c.is_ascii_digit()))
        .take(TARGET_CANDIDATES)
        .map(|m| (m.tag(), m.frequency))
        .collect();
    let mut best: Option<(String, f64, f64)> = None;
    for (tag, w0) in rotor_tags {
        let Some(w) = critical_speed(&open, settings, &tag, w0)? else { continue };
        let distance = (response.speeds.lo - w).max(w - response.speeds.hi).max(0.0);
        if best.as_ref().is_none_or(|b| distance < b.2) {
            best = Some((tag, w, distance));
        }
        if distance == 0.0 {
            break;
        }
    }
    let Some((mode, speed, _)) = best else { return Ok(None) };
    // Every frequency at the open critical speed Ω* = ω_D, where unbalance excites it.
    let omega_open = speed;
    let Some(omega_short) = forward_frequency(&short, settings, &mode, speed)? else { return Ok(None) };
    let ring = &base.model.rings[first];
    let b = &ring.circuit.branches[target.branch];
    let coupling = ((omega_open * omega_open - omega_short * omega_short) / (omega_short * omega_short)).max(0.0);
    // The loop's capacitance as the structure sees it: from the two coupled forward
    // frequencies ω₁, ω₂ nearest ω_D with R = 0 at a trial L, ω_e² = ω₁²ω₂²/ω_E² (the
    // product of the roots of the two-mode model), and C = 1/(L·ω_e²). The trial L is
    // the clamped loop's tuning to ω_D, C_p^S·C_f/(C_p^S + C_f).
    let clamped_c = ring.ring.cp_s * b.c_f / (ring.ring.cp_s + b.c_f);
    let trial = 1.0 / (omega_open * omega_open * clamped_c);
    let closed = Rotor::new(&with_branch(&base.model, &rings, target.branch, trial))?;
    let modes = whirl_modes_of(&closed, settings, speed)?;
    let mut near: Vec<f64> = modes.forward().map(|m| m.frequency).collect();
    near.sort_by(|x, y| (x - omega_open).abs().total_cmp(&(y - omega_open).abs()));
    let capacitance = match near[..] {
        [w1, w2, ..] => {
            let we2 = (w1 * w2 / omega_short).powi(2);
            1.0 / (trial * we2)
        }
        _ => clamped_c,
    };
    let inductance = 1.0 / (omega_open * omega_open * capacitance);
    let resistance = (1.5 * coupling).sqrt() / (capacitance * omega_short);
    let tuning_frequency = crate::model::Branch::frequency_of(ring.ring.cp_t, b.c_f, inductance);
    let mut clamped = false;
    let values: Vec<f64> = spec
        .variables
        .iter()
        .zip(super::evaluate::values_of(base, spec))
        .map(|(v, x)| {
            let same = v.branch == target.branch && v.ring == target.ring;
            let want = match v.parameter {
                Parameter::TuningFrequency if same => tuning_frequency,
                Parameter::Inductance if same => inductance,
                Parameter::Resistance if same => resistance,
                _ => x,
            };
            let y = want.clamp(v.min, v.max);
            clamped |= y != want;
            y
        })
        .collect();
    Ok(Some(ClassicTuning {
        mode,
        ring: target.ring,
        branch: target.branch,
        omega_open,
        omega_short,
        coupling,
        capacitance,
        inductance,
        resistance,
        tuning_frequency,
        values,
        clamped,
    }))
}

/// The rotor of the design at `values` (SI units).
pub fn rotor_at(base: &Machine, spec: &DesignSpec, values: &[f64]) -> Result<(Machine, Rotor), DesignError> {
    let machine = machine_at(base, spec, values)?;
    let rotor = Rotor::new(&machine.model)?;
    Ok((machine, rotor))
}

/// One design the tuned shunt is compared with in a min-peak report (issue 27, point 6):
/// its largest response at the objective's node and the amplification factor of that peak.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Baseline {
    /// `open circuit` (every ring's electrodes open: the machine without the shunt's
    /// resonance), `reference circuit`, `classic tuning` or `tuned`.
    pub design: String,
    /// The largest amplitude over the response range, peaks refined (m), and its speed.
    pub peak: PeakValue,
    /// API 684 amplification factor Ω_peak/(Ω₂ − Ω₁) of that peak (−); None when the
    /// largest amplitude is at an end of the range or a half-power speed lies beyond it.
    pub amplification_factor: Option<f64>,
    /// The speed (rad/s) of the other peak of the split pair the largest peak belongs to
    /// (`crate::analysis::unbalance::SPLIT_PAIR_SPACING`): its amplification factor
    /// measures one peak of the two.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub split_pair: Option<f64>,
}

impl Baseline {
    /// The baseline `design` read from its response at the node (`response_of`).
    pub fn of(design: &str, response: &UnbalanceResult) -> Baseline {
        let p = &response.probes[0];
        let (speed, amplitude, unbounded) = p.largest(&response.speeds);
        // The amplification factor of the refined peak that is the largest amplitude.
        let peak = p.peaks.iter().find(|k| k.speed == speed && k.amplitude == amplitude);
        Baseline {
            design: design.to_string(),
            peak: PeakValue { speed, amplitude, unbounded },
            amplification_factor: peak.and_then(|k| k.amplification_factor),
            split_pair: peak.and_then(|k| k.split_pair),
        }
    }
}

/// The baselines of a min-peak report over the response range `r`: the open circuit of
/// the base model and the classic tuning (its `classic` values, when there is one), each
/// computed here, beside the reference circuit and the tuned design from their responses
/// the report already has (`before`, `after`); the same response computation for all.
pub fn baselines(
    base: &Machine,
    spec: &DesignSpec,
    r: &Response,
    classic: Option<&[f64]>,
    before: &UnbalanceResult,
    after: &UnbalanceResult,
) -> Result<Vec<Baseline>, DesignError> {
    let of_model = |design: &str, model: &Model| -> Result<Baseline, DesignError> {
        Ok(Baseline::of(design, &response_of(&Rotor::new(model)?, r)?))
    };
    let mut out = vec![of_model("open circuit", &base.model.with_state(CircuitState::Open))?];
    out.push(Baseline::of("reference circuit", before));
    if let Some(c) = classic {
        out.push(of_model("classic tuning", &machine_at(base, spec, c)?.model)?);
    }
    out.push(Baseline::of("tuned", after));
    Ok(out)
}

/// The unbalance response and damping ratios of the reference and the tuned design of
/// `out` (with a `[design.response]`), and the min-peak design's baselines.
pub(crate) fn vibration_report(
    base: &Machine,
    spec: &DesignSpec,
    out: &mut crate::design::optimise::DesignOutcome,
) -> Result<(), DesignError> {
    use crate::design::optimise::{CrossingDamping, Findings, VibrationReport, REPORT_DAMPING_WHIRLS};
    if let Some(r) = spec.response() {
        let vibration = |values: &[f64]| -> Result<_, DesignError> {
            let (m, rotor) = rotor_at(base, spec, values)?;
            let response = response_of(&rotor, r)?;
            let speeds = ascending(&spec.speeds);
            let silent = crate::progress::Silent;
            let damping =
                crate::analysis::damping::lowest_damping(&rotor, &m.settings, &speeds, REPORT_DAMPING_WHIRLS, &silent)?;
            // At the critical speed the run-up crosses: where the response peaks.
            let (speed, _, _) = response.probes[0].largest(&response.speeds);
            let whirls = crate::analysis::damping::lowest_damping(
                &rotor,
                &m.settings,
                &[speed],
                REPORT_DAMPING_WHIRLS,
                &silent,
            )?;
            Ok((response, damping, CrossingDamping { speed, whirls }))
        };
        let (before, damping_before, crossing_before) = vibration(&out.before)?;
        let (after, damping_after, crossing_after) = vibration(&out.after)?;
        if let Findings::MinPeak(f) = &mut out.findings {
            let classic = f.classic_design.as_ref().map(|j| j.values.clone());
            f.baselines = baselines(base, spec, r, classic.as_deref(), &before, &after)?;
        }
        let unconstrained = match out.peak_findings().filter(|f| !f.unconstrained.constraints.is_empty()) {
            Some(f) => Some(vibration(&f.unconstrained.values.clone())?.0),
            None => None,
        };
        out.vibration = Some(VibrationReport {
            response: r.clone(),
            before,
            after,
            unconstrained,
            damping_before,
            damping_after,
            crossing_before: Some(crossing_before),
            crossing_after: Some(crossing_after),
        });
    }
    Ok(())
}
