//! Value checks with key paths, and translation of the file types into the model.

use super::file::*;
use super::general;
use super::ProblemErrorKind as K;
use crate::analysis::limits::{self, ParamError, Quantity};
use crate::analysis::regions::RegionSettings;
use crate::analysis::{Interval, Settings};
use crate::assembly::DofMap;
use crate::model::{Bearing, Branch, Circuit, CircuitState, Disk, Given, Load, Model, Ring, RingSupport, Shaft};

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

/// Upper bound on the speeds of a bearing's or seal's coefficient table (`speeds`, and
/// each tabulated coefficient with it). Every evaluation of a tabulated coefficient at a
/// speed solves the table's not-a-knot spline anew, in time and memory linear in its
/// length (12 ns per point: 12 µs per coefficient at 1 000 points, about 0.1 ms per support
/// and speed for its eight), and an unbalance sweep or a design's response evaluates them
/// at thousands of speeds. Tables of fluid-film bearings and seals (ROSS's examples, a
/// bearing code's output) have tens of points; a finer table adds nothing a spline
/// through it can use, while one of 10⁵ points would cost 1.4 ms per coefficient.
pub const MAX_TABLE_POINTS: usize = 1000;

/// Largest ratio of a bearing's or seal's stiffness coefficient |k| (kxx, kxy, kyx, kyy)
/// to the shaft's own stiffness scale K_s ([`crate::model::Shaft::stiffness_scale`], the
/// largest translational diagonal entry of its stiffness matrix). Beyond some ratio the
/// dense eigensolvers no longer resolve the modes the supports pin: measured on
/// `problems/ross-rotor-example.toml` with both bearings at K (docs/decisions.md, issue
/// 50), the lowest four forward whirls leave the pinned limit by more than 1e-6 from
/// K/K_s ≈ 1e13–1e14 on 2 and 3 shaft elements, 1e18–1e20 on 6 (where f1 alone holds to
/// 1e50: the 1e65 N/m is 1e57), 1e43 on 12, and not up to 1e80 on 24 or more.
/// 1e10 keeps a factor of 1e3 below the worst of them, and is 1e4 above the "rigid"
/// supports the tests use (1e15 N/m on a tube with K_s ≈ 4e10 N/m).
pub const MAX_SUPPORT_STIFFNESS_RATIO: f64 = 1e10;

/// Largest ratio of a bearing's or seal's damping coefficient |c| to the shaft's damping
/// scale √(K_s·M_s) (the critical damping of its stiffest node; M_s
/// [`crate::model::Shaft::mass_scale`]). Measured as above (docs/decisions.md): the
/// whirls' QEP residuals pass 1e-6 (where `modes` flags them) from c ≈ 1e17 N·s/m on the
/// 2- and 6-element rotors, 6e12 and 2e13 times their damping scales 1.7e4 and 5.6e3
/// N·s/m; 1e9 keeps a factor of 1e3 below. Real bearings and squeeze-film dampers stay
/// far inside (damping ratios of order 1 on the stiffest node at most).
pub const MAX_SUPPORT_DAMPING_RATIO: f64 = 1e9;

pub(super) fn finite(key: &str, v: f64) -> Result<f64, Failure> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err((key.into(), K::NotFinite(v)))
    }
}

pub(super) fn positive(key: &str, v: f64) -> Result<f64, Failure> {
    if finite(key, v)? > 0.0 {
        Ok(v)
    } else {
        Err((key.into(), K::NotPositive(v)))
    }
}

pub(super) fn non_negative(key: &str, v: f64) -> Result<f64, Failure> {
    if finite(key, v)? >= 0.0 {
        Ok(v)
    } else {
        Err((key.into(), K::Negative(v)))
    }
}

pub(super) fn within(key: &str, v: f64, lo: f64, hi: f64, range: &str) -> Result<f64, Failure> {
    let v = finite(key, v)?;
    if v > lo && v < hi {
        Ok(v)
    } else {
        Err((key.into(), K::OutOfRange { value: v, range: range.into() }))
    }
}

/// One factor of a derived quantity: the input key it comes from, the value given there,
/// and the power it enters the quantity with (a diameter enters an area squared).
pub(super) type Factor = (String, f64, i32);

/// Range of a quantity derived from inputs (SI units): the dense solvers form products
/// and squares of matrix entries (Cholesky factors, norms, residuals), so an entry must
/// leave its square finite and nonzero, below √f64::MAX ≈ 1.3e154 and above its
/// reciprocal, with room for sums over the elements and the assembly's coefficients. Any
/// real rotor's masses, inertias and stiffnesses are dozens of decades inside.
pub const DERIVED_RANGE: (f64, f64) = (1e-150, 1e150);

/// A quantity derived from inputs (a mass, a stiffness, an inertia) must lie in
/// [`DERIVED_RANGE`]: the analyses cannot run on an infinite or vanished matrix entry.
/// When it is not, the input blamed is the factor that is out of range, the one furthest
/// from 1 in orders of magnitude as it enters the quantity (|power · ln x|), at its own key
/// and with its own value: a huge width names the width, a huge density the density's key.
pub(super) fn derived(value: f64, what: &str, factors: &[Factor]) -> Result<f64, Failure> {
    let (lo, hi) = DERIVED_RANGE;
    if (lo..=hi).contains(&value) {
        return Ok(value);
    }
    let weight = |f: &Factor| (f64::from(f.2) * f.1.abs().ln()).abs();
    let (key, x) = factors
        .iter()
        .max_by(|a, b| weight(a).total_cmp(&weight(b)))
        .map_or((String::new(), value), |f| (f.0.clone(), f.1));
    let range = format!(
        "one that keeps the {what} between {} and {} (SI units; here {})",
        limits::number(lo),
        limits::number(hi),
        limits::number(value)
    );
    Err((key, K::OutOfRange { value: x, range }))
}

/// The keys a section's values come from, for [`section_quantities`].
pub(super) struct SectionKeys {
    /// The key of its outer size and the value given there (`shaft.radius` in the
    /// shorthand).
    pub outer: (String, f64),
    /// The key of a tapered section's right-end outer diameter and its value.
    pub outer_right: Option<(String, f64)>,
    /// The length's key.
    pub length: String,
    /// The key of E (the section's, the material's or `shaft.youngs_modulus`).
    pub youngs_modulus: String,
    /// The key of ρ.
    pub density: String,
    /// The key of the shear modulus (or Poisson's ratio) of a Timoshenko section.
    pub shear_modulus: String,
    /// The keys of the section's concentric layers, in order.
    pub layers: Vec<SectionKeys>,
}

/// Every shaft quantity the assembly builds, in [`DERIVED_RANGE`] ([`derived`]): per
/// section, at each end of a tapered one, the area A, the second moment I, and the element
/// terms ρAl, ρAl³, ρI/l, ρIl, EI/l and EI/l³ (l the element length), for a Timoshenko
/// section the shear stiffness κGA/l, then the shaft's mass.
pub(super) fn section_quantities(shaft: &Shaft, keys: &[SectionKeys]) -> Result<(), Failure> {
    for (s, k) in shaft.sections.iter().zip(keys) {
        tube_quantities(s, k)?;
        for (layer, layer_keys) in s.layers.iter().zip(&k.layers) {
            tube_quantities(layer, layer_keys)?;
        }
    }
    shaft_mass(shaft, keys)
}

/// [`section_quantities`] of one section or layer.
fn tube_quantities(s: &crate::model::Section, k: &SectionKeys) -> Result<(), Failure> {
    let ends = if s.is_uniform() { 1 } else { 2 };
    for end in 0..ends {
        let outer_key = if end == 0 { &k.outer } else { k.outer_right.as_ref().unwrap_or(&k.outer) };
        let outer = |power| (outer_key.0.clone(), outer_key.1, power);
        let length = |power| (k.length.clone(), s.length, power);
        let rho = (k.density.clone(), s.density, 1);
        let e = (k.youngs_modulus.clone(), s.youngs_modulus, 1);
        let l = s.element_length();
        let (a, i) = if end == 0 {
            (s.area(), s.inertia())
        } else {
            let (o, d) = s.diameters_at(1.0);
            let pi = std::f64::consts::PI;
            (pi * (o * o - d * d) / 4.0, pi * (o.powi(4) - d.powi(4)) / 64.0)
        };
        derived(a, "cross-section area A", &[outer(2)])?;
        derived(i, "second moment of area I", &[outer(4)])?;
        let terms = [
            (s.density * a * l, "element mass rho A l", [rho.clone(), outer(2), length(1)]),
            (s.density * a * l * l * l, "element mass term rho A l^3", [rho.clone(), outer(2), length(3)]),
            (s.density * i / l, "element rotary inertia term rho I / l", [rho.clone(), outer(4), length(-1)]),
            (s.density * i * l, "element rotary inertia term rho I l", [rho.clone(), outer(4), length(1)]),
            (s.youngs_modulus * i / l, "element stiffness term E I / l", [e.clone(), outer(4), length(-1)]),
            (s.youngs_modulus * i / (l * l * l), "element stiffness E I / l^3", [e.clone(), outer(4), length(-3)]),
        ];
        for (value, what, factors) in terms {
            derived(value, what, &factors)?;
        }
        if let crate::model::Beam::Timoshenko { shear_modulus, .. } = s.beam {
            let kappa_g = s.element(0).shear.unwrap_or(shear_modulus);
            let g = (k.shear_modulus.clone(), shear_modulus, 1);
            derived(kappa_g * a / l, "element shear stiffness kappa G A / l", &[g, outer(2), length(-1)])?;
        }
    }
    Ok(())
}

/// The shaft's mass in [`DERIVED_RANGE`].
fn shaft_mass(shaft: &Shaft, keys: &[SectionKeys]) -> Result<(), Failure> {
    let mass = shaft.mass();
    if !(DERIVED_RANGE.0..=DERIVED_RANGE.1).contains(&mass) {
        // Each section's mass is finite: blame the heaviest one's largest factor.
        let heaviest = shaft.sections.iter().zip(keys).max_by(|a, b| a.0.mass().total_cmp(&b.0.mass()));
        if let Some((s, k)) = heaviest {
            let factors =
                [(k.density.clone(), s.density, 1), (k.outer.0.clone(), k.outer.1, 2), (k.length.clone(), s.length, 1)];
            derived(mass, "shaft mass", &factors)?;
        }
    }
    Ok(())
}

/// A parameter rule's result at `key` ([`crate::analysis::limits`]: the rules every route
/// shares).
pub(super) fn rule<T>(key: &str, r: Result<T, ParamError>) -> Result<T, Failure> {
    r.map_err(|e| (key.into(), K::from(&e)))
}

/// A φ range's rule at `key[0]`/`key[1]`, whichever end breaks it.
pub(super) fn range_rule(key: &str, lo: f64, hi: f64) -> Result<Interval, Failure> {
    limits::phi_range(lo, hi).map_err(|e| {
        let end = if e.quantity == Quantity::RangeLow { 0 } else { 1 };
        (format!("{key}[{end}]"), K::from(&e))
    })
}

fn one_of<A, B>(key: &str, a: (&str, Option<A>), b: (&str, Option<B>)) -> Result<OneOf<A, B>, Failure> {
    match (a.1, b.1) {
        (Some(_), Some(_)) => Err((format!("{key}.{}", b.0), K::BothGiven(a.0.into(), b.0.into()))),
        (None, None) => Err((key.into(), K::NeitherGiven(a.0.into(), b.0.into()))),
        (Some(x), None) => Ok(OneOf::First(x)),
        (None, Some(y)) => Ok(OneOf::Second(y)),
    }
}

/// What stands at a node placed by [`place`]: its errors name it.
#[derive(Clone, Copy)]
pub(super) enum Placed {
    /// A rigid disk (`DiskNodeOffShaft`, `DiskOffShaft`).
    Disk,
    /// A plain bearing or a ring (`NodeOffShaft`, `PositionOffShaft`).
    Support,
}

/// The node of a disk or a support at `key`, from its `node` or its `position` (m,
/// snapped to the nearest node): exactly one given, on the shaft.
pub(super) fn place(
    key: &str,
    node: Option<i64>,
    position: Option<f64>,
    shaft: &Shaft,
    what: Placed,
) -> Result<usize, Failure> {
    match one_of(key, ("node", node), ("position", position))? {
        OneOf::First(n) => {
            let last = shaft.last_node();
            if n < 0 || n as usize > last {
                let kind = match what {
                    Placed::Disk => K::DiskNodeOffShaft { node: n, last },
                    Placed::Support => K::NodeOffShaft { node: n, last },
                };
                return Err((format!("{key}.node"), kind));
            }
            Ok(n as usize)
        }
        OneOf::Second(p) => {
            let p = finite(&format!("{key}.position"), p)?;
            let length = shaft.length();
            if !(0.0..=length).contains(&p) {
                let kind = match what {
                    Placed::Disk => K::DiskOffShaft { position: p, length },
                    Placed::Support => K::PositionOffShaft { position: p, length },
                };
                return Err((format!("{key}.position"), kind));
            }
            Ok(shaft.nearest_node(p))
        }
    }
}

/// The one value of two exclusive keys that a table gave (see [`one_of`]).
enum OneOf<A, B> {
    /// The first key's value.
    First(A),
    /// The second key's value.
    Second(B),
}

/// Check every value and build the model and settings.
pub fn translate(f: &ProblemFile) -> Result<(Model, Settings), Failure> {
    if f.version != FORMAT_VERSION {
        return Err(("version".into(), K::Version { found: f.version, supported: FORMAT_VERSION }));
    }
    let speed = rule("speed", limits::speed(f.speed))?;
    let shaft = match general::forms(f)? {
        general::ShaftForm::Shorthand(s) => shaft(s)?,
        general::ShaftForm::Sections(list) => general::sections(f, list)?,
    };
    sizes(f, &shaft)?;
    let disks = f
        .disks
        .iter()
        .enumerate()
        .map(|(i, d)| disk(&format!("disks[{i}]"), d, &shaft, f))
        .collect::<Result<_, _>>()?;
    let (bearings, rings) = match (&f.ring, &f.circuit) {
        (Some(r), Some(c)) => (Vec::<Bearing>::new(), shorthand_rings(r, c, &shaft)?),
        _ => general::supports(f, &shaft)?,
    };
    match (&f.circuit, f.ring.as_ref().map(|r| r.right.is_some())) {
        (Some(c), Some(has_right)) => {
            let right_key = if has_right { "ring.right" } else { "ring" };
            let both = [(&rings[0].ring, "ring".to_string()), (&rings[1].ring, right_key.to_string())];
            charges(c, &rings[0].circuit, "circuit", &both)?;
        }
        _ => {
            for (i, r) in rings.iter().enumerate() {
                let prefix = format!("rings[{i}].circuit");
                charges(&f.rings[i].circuit, &r.circuit, &prefix, &[(&r.ring, format!("rings[{i}]"))])?;
            }
        }
    }
    general::supports_check(f, &bearings, &rings)?;
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
    let coordinates = settings.coordinates;
    Ok((Model { shaft, disks, bearings, rings, load, speed, coordinates }, settings))
}

/// The shorthand's supports: the ring `left` at node 0 and `right` (with `[ring.right]`'s
/// overrides) at the last node, both on the circuit `[circuit]` (tuned with the left
/// ring's C_p^T, Eq. 4).
fn shorthand_rings(r: &RingFile, c: &CircuitFile, shaft: &Shaft) -> Result<Vec<RingSupport>, Failure> {
    let left = ring("ring", r, &RingOverride::default())?;
    let right = match &r.right {
        Some(o) => ring("ring.right", r, o)?,
        None => left.clone(),
    };
    let circuit = circuit("circuit", c, &left)?;
    Ok(vec![
        RingSupport { name: "left".into(), node: 0, ring: left, circuit: circuit.clone() },
        RingSupport { name: "right".into(), node: shaft.last_node(), ring: right, circuit },
    ])
}

fn shaft(s: &ShaftFile) -> Result<Shaft, Failure> {
    if s.elements < 1 || s.elements > MAX_ELEMENTS {
        return Err((
            "shaft.elements".into(),
            K::OutOfRange { value: s.elements as f64, range: format!("a whole number from 1 to {MAX_ELEMENTS}") },
        ));
    }
    let shaft = Shaft::uniform(
        positive("shaft.length", s.length)?,
        positive("shaft.radius", s.radius)?,
        s.elements as usize,
        positive("shaft.youngs_modulus", s.youngs_modulus)?,
        positive("shaft.density", s.density)?,
    );
    let keys = SectionKeys {
        outer: ("shaft.radius".into(), s.radius),
        outer_right: None,
        length: "shaft.length".into(),
        youngs_modulus: "shaft.youngs_modulus".into(),
        density: "shaft.density".into(),
        shear_modulus: String::new(),
        layers: Vec::new(),
    };
    section_quantities(&shaft, &[keys])?;
    Ok(shaft)
}

/// Refuse a model too large to analyse before any per-entry work or allocation.
fn sizes(f: &ProblemFile, shaft: &Shaft) -> Result<(), Failure> {
    let closed = |c: &CircuitFile| if c.state == CircuitState::Closed { c.branches.len() } else { 0 };
    let (branches, key): (Vec<usize>, &str) = match &f.circuit {
        Some(c) if f.rings.is_empty() => (vec![closed(c); 2], "circuit.branches"),
        _ => (f.rings.iter().map(|r| closed(&r.circuit)).collect(), "rings"),
    };
    let dofs = DofMap { nodes: shaft.nodes(), branches }.len();
    if dofs > MAX_DOFS {
        return Err((key.into(), K::TooManyDofs { dofs, limit: MAX_DOFS }));
    }
    let circuits = f
        .circuit
        .iter()
        .map(|c| ("circuit.branches".to_string(), c))
        .chain(f.rings.iter().enumerate().map(|(i, r)| (format!("rings[{i}].circuit.branches"), &r.circuit)));
    for (key, c) in circuits {
        if c.branches.len() > MAX_BRANCHES {
            return Err((key, K::TooManyEntries { count: c.branches.len(), limit: MAX_BRANCHES }));
        }
    }
    for (key, n) in [("disks", f.disks.len()), ("bearings", f.bearings.len()), ("rings", f.rings.len())] {
        if n > MAX_DISKS {
            return Err((key.into(), K::TooManyEntries { count: n, limit: MAX_DISKS }));
        }
    }
    Ok(())
}

fn disk(key: &str, d: &DiskFile, shaft: &Shaft, f: &ProblemFile) -> Result<Disk, Failure> {
    let node = place(key, d.node, d.position, shaft, Placed::Disk)?;
    let (mass, polar_inertia, diametral_inertia) = match general::disk_geometry(key, d, f)? {
        Some(geometry) => geometry,
        None => {
            let missing = |name: &str| (format!("{key}.{name}"), K::Schema(format!("missing field `{name}`")));
            let mass = d.mass.ok_or_else(|| missing("mass"))?;
            let polar = d.polar_inertia.ok_or_else(|| missing("polar_inertia"))?;
            let polar_inertia = non_negative(&format!("{key}.polar_inertia"), polar)?;
            let mass = positive(&format!("{key}.mass"), mass)?;
            let diametral = match d.diametral_inertia {
                Some(j) => non_negative(&format!("{key}.diametral_inertia"), j)?,
                None => polar_inertia / 2.0,
            };
            (mass, polar_inertia, diametral)
        }
    };
    Ok(Disk {
        node,
        mass,
        polar_inertia,
        diametral_inertia,
        eccentricity: non_negative(&format!("{key}.eccentricity"), d.eccentricity)?,
        phase: finite(&format!("{key}.phase"), d.phase)?,
    })
}

pub(super) fn ring(key: &str, base: &RingFile, o: &RingOverride) -> Result<Ring, Failure> {
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
    let cp_s = match one_of(key, ("cp_s", cp_s), ("k_eq2", k_eq2))? {
        OneOf::First(c) => positive(&k("cp_s"), c)?,
        // A tiny k_eq2 can overflow C_p^S: check the derived value too.
        OneOf::Second(k2) => {
            let k2 = positive(&k("k_eq2"), k2)?;
            let cp_s = Ring::cp_s_from_k_eq2(angle, theta_p, k2);
            if !cp_s.is_finite() {
                let range = "large enough that C_p^S = 2 cot^2(beta) theta_p^2 / k_eq2 is finite";
                return Err((k("k_eq2"), K::OutOfRange { value: k2, range: range.into() }));
            }
            cp_s
        }
    };
    let cp_t = positive(&k("cp_t"), o.cp_t.unwrap_or(base.cp_t))?;
    if cp_s >= cp_t {
        // Blame what set C_p^S: the key itself, or k_eq2, or an angle that looks like
        // radians (a tiny β makes cot²β, and so C_p^S, thousands of times too large).
        let given_cp_s = k_eq2.is_none();
        let key = if given_cp_s {
            k("cp_s")
        } else if angle_deg <= std::f64::consts::FRAC_PI_2 {
            k("angle_deg")
        } else {
            k("k_eq2")
        };
        let from_k_eq2 = if given_cp_s { None } else { k_eq2 };
        return Err((key, K::ClampedCapacitance { cp_s, cp_t, angle_deg, from_k_eq2 }));
    }
    Ok(Ring {
        k_b: positive(&k("k_b"), o.k_b.unwrap_or(base.k_b))?,
        m_b: positive(&k("m_b"), o.m_b.unwrap_or(base.m_b))?,
        eta: non_negative(&k("eta"), o.eta.unwrap_or(base.eta))?,
        k_1: positive(&k("k_1"), o.k_1.unwrap_or(base.k_1))?,
        k_2: positive(&k("k_2"), o.k_2.unwrap_or(base.k_2))?,
        angle,
        theta_p,
        cp_t,
        cp_s,
    })
}

pub(super) fn circuit(prefix: &str, c: &CircuitFile, ring: &Ring) -> Result<Circuit, Failure> {
    if c.state == CircuitState::Closed && c.branches.is_empty() {
        return Err((format!("{prefix}.branches"), K::NoBranches));
    }
    let branches = c
        .branches
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let key = format!("{prefix}.branches[{i}]");
            let tuning = one_of(&key, ("inductance", b.inductance), ("tuning_frequency", b.tuning_frequency))?;
            let c_f = positive(&format!("{key}.c_f"), b.c_f)?;
            let (inductance, given) = match tuning {
                OneOf::First(l) => (non_negative(&format!("{key}.inductance"), l)?, Given::Inductance),
                OneOf::Second(w) => {
                    let w = positive(&format!("{key}.tuning_frequency"), w)?;
                    (Branch::tuned_inductance(ring.cp_t, c_f, w), Given::TuningFrequency(w))
                }
            };
            let resistance = non_negative(&format!("{key}.resistance"), b.resistance)?;
            Ok(Branch { c_f, inductance, resistance, given })
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
fn charges(file: &CircuitFile, circuit: &Circuit, prefix: &str, rings: &[(&Ring, String)]) -> Result<(), Failure> {
    if circuit.state != CircuitState::Closed {
        return Ok(());
    }
    let orders = |x: f64| x.abs().ln().abs();
    for (i, (b, given)) in circuit.branches.iter().zip(&file.branches).enumerate() {
        let key = |name: &str| format!("{prefix}.branches[{i}].{name}");
        let out = |name: &str, value: f64, what: &str| {
            Err((key(name), K::OutOfRange { value, range: format!("one that gives a finite {what}") }))
        };
        for (ring, ring_prefix) in rings {
            let ring_key = |name: &str| format!("{ring_prefix}.{name}");
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

/// Most iterations, levels or orders a `[regions]` count may ask for: far above the
/// defaults (8–60), and low enough that a typo cannot ask for an endless search.
const MAX_REGION_COUNT: usize = 10_000;

/// Check `[regions]`: tolerances and steps positive and finite, margins non-negative,
/// counts from 1 to [`MAX_REGION_COUNT`].
pub fn regions(f: &ProblemFile) -> Result<RegionSettings, Failure> {
    let r = &f.regions;
    for (key, v) in [
        ("beta_bracket", r.beta_bracket),
        ("beta_tolerance", r.beta_tolerance),
        ("phi_tolerance", r.phi_tolerance),
        ("tip_tolerance", r.tip_tolerance),
        ("guard_step", r.guard_step),
        ("edge_step[0]", r.edge_step.absolute),
        ("edge_step[1]", r.edge_step.relative),
    ] {
        positive(&format!("regions.{key}"), v)?;
    }
    non_negative("regions.tip_margin[0]", r.tip_margin.relative)?;
    non_negative("regions.tip_margin[1]", r.tip_margin.absolute)?;
    for (key, v) in [
        ("max_order", r.max_order),
        ("tracking_levels", r.tracking_levels),
        ("tip_iterations", r.tip_iterations),
        ("centre_iterations", r.centre_iterations),
    ] {
        if !(1..=MAX_REGION_COUNT).contains(&v) {
            let range = format!("a whole number from 1 to {MAX_REGION_COUNT}");
            return Err((format!("regions.{key}"), K::OutOfRange { value: v as f64, range }));
        }
    }
    Ok(r.clone())
}

fn settings(s: &Settings) -> Result<Settings, Failure> {
    use crate::analysis::settings::SettingsRule as R;
    s.validate().map_err(|e| {
        let kind = match e.rule {
            R::NotFinite(v) => K::NotFinite(v),
            R::Negative(v) => K::Negative(v),
            R::OutOfRange { value, range } => K::OutOfRange { value, range },
        };
        (format!("analysis.{}", e.field), kind)
    })?;
    Ok(s.clone())
}
