//! Value checks with key paths, and translation of the file types into the model.

use super::file::*;
use super::ProblemErrorKind as K;
use crate::analysis::limits::{self, ParamError, Quantity};
use crate::analysis::{Interval, Settings};
use crate::assembly::DofMap;
use crate::design::spec::{
    Band, DesignSpec, Objective, ObjectiveKind, Parameter, Variable, MAX_ITERATIONS, MAX_STARTS,
};
use crate::model::{Branch, Circuit, CircuitState, Disk, Load, Model, Ring, Shaft};

/// A key path and what is wrong there.
pub type Failure = (String, K);

/// Upper bound on shaft elements: the dense eigensolvers cost O(n³), and 2 000 elements
/// already mean a 8 000 × 8 000 complex state matrix.
pub const MAX_ELEMENTS: i64 = 2000;

/// Upper bound on the model's complex DOFs, 2 per shaft node + 2 ring + 2 per closed
/// branch ([`crate::assembly::DofMap::len`]). The dense solvers hold several n × n
/// matrices and a 2n × 2n complex state matrix: `check` at 4 008 DOFs (2 000 elements, 2
/// branches) peaks at 2 GB. The limit admits the longest shaft [`MAX_ELEMENTS`] allows
/// with up to 48 closed branches, and refuses larger models before anything is assembled.
pub const MAX_DOFS: usize = 4100;

/// Upper bound on `[[circuit.branches]]`: each closed branch adds an electrical mode per
/// ring, and a reduced model keeps at most 200 modes (`analysis.reduced_modes`), so more
/// than 100 branches cannot all be represented.
pub const MAX_BRANCHES: usize = 100;

/// Upper bound on `[[disks]]`. Disks only add to the diagonal of M and G at the at most
/// 2 001 nodes, so a model needs few; each costs about 2.3 KB to parse and a line of the
/// `check` summary (10⁵ disks load in 0.3 s and 240 MB).
pub const MAX_DISKS: usize = 100_000;

fn finite(key: &str, v: f64) -> Result<f64, Failure> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err((key.into(), K::NotFinite(v)))
    }
}

fn positive(key: &str, v: f64) -> Result<f64, Failure> {
    if finite(key, v)? > 0.0 {
        Ok(v)
    } else {
        Err((key.into(), K::NotPositive(v)))
    }
}

fn non_negative(key: &str, v: f64) -> Result<f64, Failure> {
    if finite(key, v)? >= 0.0 {
        Ok(v)
    } else {
        Err((key.into(), K::Negative(v)))
    }
}

fn within(key: &str, v: f64, lo: f64, hi: f64, range: &str) -> Result<f64, Failure> {
    let v = finite(key, v)?;
    if v > lo && v < hi {
        Ok(v)
    } else {
        Err((key.into(), K::OutOfRange { value: v, range: range.into() }))
    }
}

/// A parameter rule's result at `key` ([`crate::analysis::limits`]: the rules every route
/// shares).
fn rule<T>(key: &str, r: Result<T, ParamError>) -> Result<T, Failure> {
    r.map_err(|e| (key.into(), K::from(&e)))
}

/// A φ range's rule at `key[0]`/`key[1]`, whichever end breaks it.
fn range_rule(key: &str, lo: f64, hi: f64) -> Result<Interval, Failure> {
    limits::phi_range(lo, hi).map_err(|e| {
        let end = if e.quantity == Quantity::RangeLow { 0 } else { 1 };
        (format!("{key}[{end}]"), K::from(&e))
    })
}

fn one_of(key: &str, a: (&str, Option<f64>), b: (&str, Option<f64>)) -> Result<(), Failure> {
    match (a.1, b.1) {
        (Some(_), Some(_)) => Err((format!("{key}.{}", b.0), K::BothGiven(a.0.into(), b.0.into()))),
        (None, None) => Err((key.into(), K::NeitherGiven(a.0.into(), b.0.into()))),
        _ => Ok(()),
    }
}

/// Highest tongue order the search may be asked for: orders cost a few evaluations per
/// pair each, and beyond 32 the tongues of any physical rotor are thinner than any φ
/// tolerance (their width shrinks like β^k).
pub const MAX_TONGUE_ORDER: usize = 32;

/// Check every value and build the model and settings.
pub fn translate(f: &ProblemFile) -> Result<(Model, Settings), Failure> {
    if f.version != FORMAT_VERSION {
        return Err(("version".into(), K::Version { found: f.version, supported: FORMAT_VERSION }));
    }
    let speed = rule("speed", limits::speed(f.speed))?;
    let shaft = shaft(&f.shaft)?;
    sizes(f, &shaft)?;
    let disks =
        f.disks.iter().enumerate().map(|(i, d)| disk(&format!("disks[{i}]"), d, &shaft)).collect::<Result<_, _>>()?;
    let left = ring("ring", &f.ring, &RingOverride::default())?;
    let right = match &f.ring.right {
        Some(r) => ring("ring.right", &f.ring, r)?,
        None => left.clone(),
    };
    let circuit = circuit(&f.circuit, &left)?;
    let right_key = if f.ring.right.is_some() { "ring.right" } else { "ring" };
    charges(&f.circuit, &circuit, [(&left, "ring"), (&right, right_key)])?;
    let load = Load {
        alpha: within(
            "load.alpha",
            f.load.alpha,
            f64::NEG_INFINITY,
            1.0,
            "below 1 (alpha >= 1 means the static load alone buckles the shaft)",
        )?,
        critical_load: f.load.critical_load.map(|p| positive("load.critical_load", p)).transpose()?,
    };
    let settings = settings(&f.analysis)?;
    Ok((Model { shaft, disks, left, right, circuit, load, speed }, settings))
}

fn shaft(s: &ShaftFile) -> Result<Shaft, Failure> {
    if s.elements < 1 || s.elements > MAX_ELEMENTS {
        return Err((
            "shaft.elements".into(),
            K::OutOfRange { value: s.elements as f64, range: format!("a whole number from 1 to {MAX_ELEMENTS}") },
        ));
    }
    Ok(Shaft {
        length: positive("shaft.length", s.length)?,
        radius: positive("shaft.radius", s.radius)?,
        elements: s.elements as usize,
        youngs_modulus: positive("shaft.youngs_modulus", s.youngs_modulus)?,
        density: positive("shaft.density", s.density)?,
    })
}

/// Refuse a model too large to analyse before any per-entry work or allocation.
fn sizes(f: &ProblemFile, shaft: &Shaft) -> Result<(), Failure> {
    let branches = f.circuit.branches.len();
    let closed = f.circuit.state == CircuitState::Closed;
    let dofs = DofMap { nodes: shaft.nodes(), branches: if closed { branches } else { 0 } }.len();
    if dofs > MAX_DOFS {
        return Err(("circuit.branches".into(), K::TooManyDofs { dofs, limit: MAX_DOFS }));
    }
    if branches > MAX_BRANCHES {
        return Err(("circuit.branches".into(), K::TooManyEntries { count: branches, limit: MAX_BRANCHES }));
    }
    if f.disks.len() > MAX_DISKS {
        return Err(("disks".into(), K::TooManyEntries { count: f.disks.len(), limit: MAX_DISKS }));
    }
    Ok(())
}

fn disk(key: &str, d: &DiskFile, shaft: &Shaft) -> Result<Disk, Failure> {
    one_of(key, ("node", d.node.map(|n| n as f64)), ("position", d.position))?;
    let node = match (d.node, d.position) {
        (Some(n), _) => {
            if n < 0 || n as usize > shaft.elements {
                return Err((format!("{key}.node"), K::DiskNodeOffShaft { node: n, last: shaft.elements }));
            }
            n as usize
        }
        (None, Some(p)) => {
            let p = finite(&format!("{key}.position"), p)?;
            if !(0.0..=shaft.length).contains(&p) {
                return Err((format!("{key}.position"), K::DiskOffShaft { position: p, length: shaft.length }));
            }
            (p / shaft.element_length()).round() as usize
        }
        (None, None) => unreachable!("checked by one_of"),
    };
    let polar_inertia = non_negative(&format!("{key}.polar_inertia"), d.polar_inertia)?;
    Ok(Disk {
        node,
        mass: positive(&format!("{key}.mass"), d.mass)?,
        polar_inertia,
        diametral_inertia: match d.diametral_inertia {
            Some(j) => non_negative(&format!("{key}.diametral_inertia"), j)?,
            None => polar_inertia / 2.0,
        },
        eccentricity: non_negative(&format!("{key}.eccentricity"), d.eccentricity)?,
        phase: finite(&format!("{key}.phase"), d.phase)?,
    })
}

fn ring(key: &str, base: &RingFile, o: &RingOverride) -> Result<Ring, Failure> {
    let k = |name: &str| format!("{key}.{name}");
    let angle_deg =
        within(&k("angle_deg"), o.angle_deg.unwrap_or(base.angle_deg), 0.0, 90.0, "between 0 and 90 degrees")?;
    let angle = angle_deg.to_radians();
    let theta_p = positive(&k("theta_p"), o.theta_p.unwrap_or(base.theta_p))?;
    // The right end may replace cp_s by k_eq2 or the reverse: an override of either wins.
    let (cp_s, k_eq2) = match (o.cp_s, o.k_eq2) {
        (None, None) => (base.cp_s, base.k_eq2),
        (cp_s, k_eq2) => (cp_s, k_eq2),
    };
    one_of(key, ("cp_s", cp_s), ("k_eq2", k_eq2))?;
    let cp_s = match (cp_s, k_eq2) {
        (Some(c), _) => positive(&k("cp_s"), c)?,
        // A tiny k_eq2 can overflow C_p^S: check the derived value too.
        // A tiny k_eq2 can overflow C_p^S: check the derived value too.
        (None, Some(k2)) => {
            let k2 = positive(&k("k_eq2"), k2)?;
            let cp_s = Ring::cp_s_from_k_eq2(angle, theta_p, k2);
            if !cp_s.is_finite() {
                let range = "large enough that C_p^S = 2 cot^2(beta) theta_p^2 / k_eq2 is finite";
                return Err((k("k_eq2"), K::OutOfRange { value: k2, range: range.into() }));
            }
            cp_s
        }
        (None, None) => unreachable!("checked by one_of"),
    };
    Ok(Ring {
        k_b: positive(&k("k_b"), o.k_b.unwrap_or(base.k_b))?,
        m_b: positive(&k("m_b"), o.m_b.unwrap_or(base.m_b))?,
        eta: non_negative(&k("eta"), o.eta.unwrap_or(base.eta))?,
        k_1: positive(&k("k_1"), o.k_1.unwrap_or(base.k_1))?,
        k_2: positive(&k("k_2"), o.k_2.unwrap_or(base.k_2))?,
        angle,
        theta_p,
        cp_t: positive(&k("cp_t"), o.cp_t.unwrap_or(base.cp_t))?,
        cp_s,
    })
}

fn circuit(c: &CircuitFile, ring: &Ring) -> Result<Circuit, Failure> {
    if c.state == CircuitState::Closed && c.branches.is_empty() {
        return Err(("circuit.branches".into(), K::NoBranches));
    }
    let branches = c
        .branches
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let key = format!("circuit.branches[{i}]");
            one_of(&key, ("inductance", b.inductance), ("tuning_frequency", b.tuning_frequency))?;
            let c_f = positive(&format!("{key}.c_f"), b.c_f)?;
            let inductance = match (b.inductance, b.tuning_frequency) {
                (Some(l), _) => non_negative(&format!("{key}.inductance"), l)?,
                (None, Some(w)) => {
                    Branch::tuned_inductance(ring.cp_t, c_f, positive(&format!("{key}.tuning_frequency"), w)?)
                }
                (None, None) => unreachable!("checked by one_of"),
            };
            Ok(Branch { c_f, inductance, resistance: non_negative(&format!("{key}.resistance"), b.resistance)? })
        })
        .collect::<Result<_, Failure>>()?;
    Ok(Circuit { state: c.state, branches })
}

/// Every branch's charge DOF must have finite coefficients at both rings: mass γL,
/// damping γR and stiffness γ/C_f (γ = 2cot²β·θ_p², Eq. A8), and L itself when it comes
/// from a tuning frequency, L = (1/C_f + 1/C_p^T)/ω² (Eq. 4). Valid inputs can still
/// overflow them (L = inf from ω = 1e-300 rad/s or a subnormal C_f; γL = inf from
/// L = 1e308 H), and the analyses cannot run on an infinite matrix entry. The error is
/// reported at the input that overflows: for a product, the factor furthest from 1 (in
/// orders of magnitude). A ring whose γ itself overflows is left to the analyses, as
/// before. L = 0 (no mass) is fine: a massless charge.
fn charges(file: &CircuitFile, circuit: &Circuit, rings: [(&Ring, &str); 2]) -> Result<(), Failure> {
    if circuit.state != CircuitState::Closed {
        return Ok(());
    }
    let orders = |x: f64| x.abs().ln().abs();
    for (i, (b, given)) in circuit.branches.iter().zip(&file.branches).enumerate() {
        let key = |name: &str| format!("circuit.branches[{i}].{name}");
        let out = |name: &str, value: f64, what: &str| {
            Err((key(name), K::OutOfRange { value, range: format!("one that gives a finite {what}") }))
        };
        for (ring, prefix) in rings {
            let ring_key = |name: &str| format!("{prefix}.{name}");
            if let (None, Some(w)) = (given.inductance, given.tuning_frequency) {
                if !(1.0 / b.c_f).is_finite() {
                    return out("c_f", b.c_f, "1/C_f (Eq. 4)");
                }
                if !(1.0 / ring.cp_t).is_finite() {
                    let range = "one that gives a finite 1/C_p^T (Eq. 4)".to_string();
                    return Err((ring_key("cp_t"), K::OutOfRange { value: ring.cp_t, range }));
                }
                if !b.inductance.is_finite() {
                    return out("tuning_frequency", w, &format!("L (here L = {:e} H)", b.inductance));
                }
            }
            let gamma = ring.gamma();
            if !gamma.is_finite() {
                continue;
            }
            // γ = 2cot²β·θ_p²: the ring key behind it is θ_p unless cot²β is the larger.
            let cot2 = gamma / (2.0 * ring.theta_p * ring.theta_p);
            let (gamma_key, gamma_value) = if orders(cot2) > orders(ring.theta_p * ring.theta_p) {
                (ring_key("angle_deg"), ring.angle.to_degrees())
            } else {
                (ring_key("theta_p"), ring.theta_p)
            };
            let blame = |name: &str, value: f64, what: &str| -> Failure {
                let what = format!("{what} (gamma = {gamma:.4})");
                let range = format!("one that gives a finite {what}");
                if orders(value) >= orders(gamma) {
                    (key(name), K::OutOfRange { value, range })
                } else {
                    (gamma_key.clone(), K::OutOfRange { value: gamma_value, range })
                }
            };
            let l_name = if given.inductance.is_some() { "inductance" } else { "tuning_frequency" };
            if !(gamma * b.inductance).is_finite() {
                let mut e = blame("inductance", b.inductance, "charge mass gamma L");
                if e.0 == key("inductance") {
                    e.0 = key(l_name);
                    if let (K::OutOfRange { value, .. }, Some(w)) = (&mut e.1, given.tuning_frequency) {
                        *value = w;
                    }
                }
                return Err(e);
            }
            if !(gamma * b.resistance).is_finite() {
                return Err(blame("resistance", b.resistance, "charge damping gamma R"));
            }
            if !(gamma / b.c_f).is_finite() {
                return Err(blame("c_f", b.c_f, "charge stiffness gamma / C_f"));
            }
        }
    }
    Ok(())
}

fn settings(s: &Settings) -> Result<Settings, Failure> {
    within("analysis.mac_threshold", s.mac_threshold, 0.0, 1.0 + 1e-12, "in (0, 1]")?;
    within("analysis.electrical_fraction", s.electrical_fraction, 0.0, 1.0, "in (0, 1)")?;
    within("analysis.oscillation_tolerance", s.oscillation_tolerance, 0.0, 1.0, "in (0, 1)")?;
    within("analysis.max_step_phase", s.max_step_phase, 0.0, 10.0, "in (0, 10) rad")?;
    within("analysis.instability_tolerance", s.instability_tolerance, 1.0, f64::INFINITY, "above 1")?;
    let count = |key: &str, v: usize, lo: usize, hi: usize| -> Result<(), Failure> {
        if v < lo || v > hi {
            return Err((
                key.into(),
                K::OutOfRange { value: v as f64, range: format!("a whole number from {lo} to {hi}") },
            ));
        }
        Ok(())
    };
    count("analysis.reduced_modes", s.reduced_modes, 1, 200)?;
    count("analysis.steps_per_period", s.steps_per_period, 2, 1 << 16)?;
    count("analysis.reference_steps", s.reference_steps, 2, 1 << 20)?;
    // The criterion's floors: 0 (nothing ignored) up to any finite value.
    non_negative("analysis.min_growth_rate", s.min_growth_rate)?;
    non_negative("analysis.min_tongue_width", s.min_tongue_width)?;
    count("analysis.max_tongue_order", s.max_tongue_order, 1, MAX_TONGUE_ORDER)?;
    Ok(s.clone())
}

/// Default φ range of a design's catalogues and band searches (rad/s): the paper's charts.
const DEFAULT_PHI_RANGE: [f64; 2] = [100.0, 8000.0];
/// Default Nelder–Mead starts and iterations.
const DEFAULT_STARTS: i64 = 4;
const DEFAULT_ITERATIONS: i64 = 40;

/// Check `[design]` against the rest of the file.
pub fn design(f: &ProblemFile) -> Result<Option<DesignSpec>, Failure> {
    let Some(d) = &f.design else { return Ok(None) };
    let range = d.phi_range.unwrap_or(DEFAULT_PHI_RANGE);
    let range = range_rule("design.phi_range", range[0], range[1])?;
    // The level is a load coefficient up to β_max, whose default follows it.
    let level = rule("design.level", limits::level(d.level, limits::MAX_BETA))?;
    let beta_max = rule("design.beta_max", limits::beta_max(d.beta_max.unwrap_or(1.0_f64.max(level))))?;
    rule("design.level", limits::level(level, beta_max))?;
    let speeds = match &d.speeds {
        Some(v) if v.is_empty() => return Err(("design.speeds".into(), K::Schema("needs at least one speed".into()))),
        Some(v) => v
            .iter()
            .enumerate()
            .map(|(i, &w)| rule(&format!("design.speeds[{i}]"), limits::speed(w)))
            .collect::<Result<Vec<_>, _>>()?,
        None => vec![f.speed],
    };
    let phi_op = d.phi_op.map(|p| rule("design.phi_op", limits::phi_op(p, range))).transpose()?;
    let bands = d
        .bands
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let key = format!("design.bands[{i}]");
            let Interval { lo, hi } = limits::band(b.lo, b.hi).map_err(|e| {
                let end = if e.quantity == Quantity::RangeLow { "lo" } else { "hi" };
                (format!("{key}.{end}"), K::from(&e))
            })?;
            let clearance = rule(&format!("{key}.clearance"), limits::span(b.clearance))?;
            Ok(Band { lo, hi, clearance })
        })
        .collect::<Result<Vec<_>, Failure>>()?;
    // Each objective takes its own data; a key of the other one is a mistake, not a hint.
    let objective = match d.objective {
        ObjectiveKind::WidestStableBand => {
            if !bands.is_empty() {
                return Err((
                    "design.bands".into(),
                    K::Schema("[[design.bands]] belong to the clear-bands objective, not widest-stable-band".into()),
                ));
            }
            let Some(phi_op) = phi_op else {
                return Err((
                    "design.phi_op".into(),
                    K::Schema("the widest-stable-band objective needs `phi_op` (rad/s)".into()),
                ));
            };
            Objective::WidestStableBand { phi_op }
        }
        ObjectiveKind::ClearBands => {
            if phi_op.is_some() {
                return Err((
                    "design.phi_op".into(),
                    K::Schema("`phi_op` belongs to the widest-stable-band objective, not clear-bands".into()),
                ));
            }
            if bands.is_empty() {
                return Err((
                    "design.bands".into(),
                    K::Schema("the clear-bands objective needs [[design.bands]]".into()),
                ));
            }
            Objective::ClearBands { bands }
        }
    };
    if d.variables.is_empty() {
        return Err(("design.variables".into(), K::Schema("a design needs at least one [[design.variables]]".into())));
    }
    if f.circuit.state != CircuitState::Closed {
        return Err((
            "circuit.state".into(),
            K::Schema("a design changes the shunt branches: the circuit must be `closed`".into()),
        ));
    }
    let mut variables: Vec<Variable> = Vec::new();
    for (i, v) in d.variables.iter().enumerate() {
        let key = format!("design.variables[{i}]");
        let n = f.circuit.branches.len();
        if v.branch < 1 || v.branch as usize > n {
            return Err((
                format!("{key}.branch"),
                K::OutOfRange { value: v.branch as f64, range: format!("a branch number from 1 to {n}") },
            ));
        }
        let min = if v.parameter.logarithmic() {
            positive(&format!("{key}.min"), v.min)?
        } else {
            non_negative(&format!("{key}.min"), v.min)?
        };
        let max = finite(&format!("{key}.max"), v.max)?;
        if max <= min {
            return Err((format!("{key}.max"), K::OutOfRange { value: max, range: format!("above min = {min}") }));
        }
        let var = Variable { branch: v.branch as usize - 1, parameter: v.parameter, min, max };
        let exclusive = |p: Parameter| matches!(p, Parameter::Inductance | Parameter::TuningFrequency);
        if variables.iter().any(|w| {
            w.branch == var.branch
                && (w.parameter == var.parameter || (exclusive(w.parameter) && exclusive(var.parameter)))
        }) {
            return Err((
                format!("{key}.parameter"),
                K::Schema(format!(
                    "branch {} already has a variable for this parameter (inductance and tuning_frequency are one)",
                    v.branch
                )),
            ));
        }
        variables.push(var);
    }
    let count = |key: &str, v: Option<i64>, default: i64, hi: u64| -> Result<usize, Failure> {
        let v = v.unwrap_or(default);
        let n = u64::try_from(v).unwrap_or(0);
        rule(key, limits::count(n, 1, hi).map_err(|e| ParamError { value: v as f64, ..e })).map(|n| n as usize)
    };
    Ok(Some(DesignSpec {
        objective,
        level,
        phi_range: (range.lo, range.hi),
        beta_max,
        speeds,
        variables,
        starts: count("design.starts", d.starts, DEFAULT_STARTS, MAX_STARTS)?,
        max_iterations: count("design.max_iterations", d.max_iterations, DEFAULT_ITERATIONS, MAX_ITERATIONS)?,
    }))
}
