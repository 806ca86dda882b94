//! From ROSS's elements to rotorshunt's general form: materials, sections (Rayleigh or
//! Timoshenko, uniform or tapered), disks (and point masses on the shaft), bearings and
//! seals with their full coefficient matrices and speed tables; or the refusals, every
//! one of the file, each naming its element. The rules are in `docs/ross-format.md`
//! (section "`rotorshunt import-ross`: the mapping, and what it refuses").

use super::error::{ElementRef, Refusal, Refused, RossErrorKind};
use super::parse::{Bearing, Coefficient, RossFile, Shaft, SupportClass};
use crate::model::{element, SupportKind};

/// Relative tolerance within which consecutive shaft elements have "the same" length and
/// may share a section. ROSS writes lengths in Python's shortest round-trip form, and a
/// length computed as `0.6/6` is saved as 0.09999999999999999 next to 0.1: those differ by
/// one or two ulps (2e-16 relative). A section then spreads its total length evenly, which
/// moves a node by at most this fraction of an element, far below any mesh effect;
/// elements of really different lengths stay in separate sections, so that every node
/// stays where ROSS has it.
pub const SAME_LENGTH_RTOL: f64 = 1e-12;

/// The imported rotor, ready to be written as a problem file (SI units, rad/s).
#[derive(Debug, Clone, PartialEq)]
pub struct Imported {
    /// `ross_version` of the file.
    pub ross_version: Option<String>,
    /// The speed Ω (rad/s) chosen for the problem, if one was.
    pub speed: Option<f64>,
    /// Materials, in order of first use.
    pub materials: Vec<MaterialOut>,
    /// Shaft sections, left to right.
    pub sections: Vec<SectionOut>,
    /// Disks and point masses on the shaft, by node (then tag).
    pub disks: Vec<DiskOut>,
    /// Bearings and seals, by node (then tag).
    pub bearings: Vec<BearingOut>,
}

/// A `[[materials]]` entry.
#[derive(Debug, Clone, PartialEq)]
pub struct MaterialOut {
    /// Name (ROSS's, with `-2`, `-3`, … when ROSS gave one name different values).
    pub name: String,
    /// The material's name in the ROSS file (`material.name`), before `name`'s `-2`, `-3`
    /// suffix.
    pub ross_name: String,
    /// E (Pa).
    pub youngs_modulus: f64,
    /// ρ (kg/m³).
    pub density: f64,
    /// G (Pa), ROSS's `G_s`.
    pub shear_modulus: f64,
    /// Whether a Timoshenko section uses the material (then its `shear_modulus` is
    /// written).
    pub timoshenko: bool,
}

/// A `[[sections]]` entry: a run of consecutive uniform ROSS shaft elements of one beam
/// theory, or one tapered element.
#[derive(Debug, Clone, PartialEq)]
pub struct SectionOut {
    /// Total length (m), the sum of the elements' L.
    pub length: f64,
    /// Outer diameter (m).
    pub outer_diameter: f64,
    /// Inner diameter (m).
    pub inner_diameter: f64,
    /// Outer and inner diameter at the right end (m), ROSS's odr and idr, when they
    /// differ from the left end's (a tapered element, alone in its section).
    pub right: Option<(f64, f64)>,
    /// Timoshenko elements (ROSS's `shear_effects = true`), with the shear coefficient to
    /// write: `None` for ROSS's default Cowper formula (rotorshunt's default too).
    pub timoshenko: Option<Option<f64>>,
    /// Material name (a [`MaterialOut::name`]).
    pub material: String,
    /// Number of elements.
    pub elements: usize,
    /// `n` of the first element (its left node).
    pub first_n: i64,
    /// Tags of the first and last element.
    pub tags: (String, String),
    /// L of the first element (m).
    pub element_length: f64,
    /// Concentric layers over the section's elements (ROSS's other elements of the same
    /// `n`s), outermost last.
    pub layers: Vec<LayerOut>,
}

/// A `[[sections.layers]]` entry: ROSS's elements stacked on a section's elements.
#[derive(Debug, Clone, PartialEq)]
pub struct LayerOut {
    /// Outer diameter (m).
    pub outer_diameter: f64,
    /// Inner diameter (m).
    pub inner_diameter: f64,
    /// Outer and inner diameter at the right end (m), when tapered.
    pub right: Option<(f64, f64)>,
    /// As [`SectionOut::timoshenko`].
    pub timoshenko: Option<Option<f64>>,
    /// Material name (a [`MaterialOut::name`]).
    pub material: String,
    /// Tags of the first and last element of the layer.
    pub tags: (String, String),
}

/// A `[[disks]]` entry.
#[derive(Debug, Clone, PartialEq)]
pub struct DiskOut {
    /// Shaft node of the disk, ROSS's `n` (0-based, 0 = left end).
    pub node: i64,
    /// m (kg).
    pub mass: f64,
    /// J_p (kg·m²).
    pub polar_inertia: f64,
    /// J_d (kg·m²).
    pub diametral_inertia: f64,
    /// ROSS's `tag` of the disk element, quoted in the comment of the written `[[disks]]`
    /// entry.
    pub tag: String,
    /// `DiskElement`, or `PointMass` for a point mass on the shaft (mass only).
    pub class: &'static str,
}

/// A `[[bearings]]` or `[[seals]]` entry: one ROSS bearing or seal, grounded at a shaft
/// node (several may share a node, as in ROSS, whose matrices add).
#[derive(Debug, Clone, PartialEq)]
pub struct BearingOut {
    /// Bearing (`[[bearings]]`) or seal (`[[seals]]`).
    pub kind: SupportKind,
    /// The ROSS class (`BearingElement`, `SealElement`, …).
    pub class: &'static str,
    /// Shaft node of the support, ROSS's `n` (0-based, 0 = left end).
    pub node: i64,
    /// ROSS's `frequency` (rad/s) when a coefficient varies over it; empty otherwise.
    pub speeds: Vec<f64>,
    /// kxx, kxy, kyx, kyy (N/m), cxx, cxy, cyx, cyy (N·s/m), in the order of
    /// [`crate::model::COEFFICIENT_NAMES`]: one value when constant over the table, else
    /// one per entry of `speeds`.
    pub coefficients: [Vec<f64>; 8],
    /// Added mass mxx = myy (kg), on the node.
    pub mass: f64,
    /// The ROSS tag.
    pub tag: String,
}

impl BearingOut {
    /// Whether the support is written with the isotropic keys `stiffness` and `damping`:
    /// constant, kxx = kyy, cxx = cyy and no cross terms.
    pub fn isotropic(&self) -> bool {
        let c = &self.coefficients;
        c.iter().all(|v| v.len() == 1)
            && c[0][0] == c[3][0]
            && c[4][0] == c[7][0]
            && [1, 2, 5, 6].iter().all(|&i| c[i][0] == 0.0)
    }
}

fn refused(class: &str, tag: &str, n: Option<i64>, line: Option<usize>, reason: Refusal) -> Refused {
    Refused {
        element: Some(Box::new(ElementRef { class: class.into(), tag: tag.into(), n, line })),
        reason: Box::new(reason),
    }
}

/// A value that must be finite and > 0 (`positive`) or ≥ 0.
fn check(key: &str, value: f64, positive: bool) -> Result<(), Refusal> {
    let ok = value.is_finite() && if positive { value > 0.0 } else { value >= 0.0 };
    if ok {
        return Ok(());
    }
    let rule = if positive { "must be finite and > 0" } else { "must be finite and ≥ 0" };
    Err(Refusal::Value { key: key.into(), value, rule: rule.into() })
}

/// Map a parsed file; `speed` (rad/s) is the problem's speed Ω. Every element is
/// checked; when any is refused, the error lists them all (shaft elements by `n`, disks,
/// point masses, bearings and seals by `n`, other classes, the rotor).
pub fn map(file: &RossFile, speed: Option<f64>) -> Result<Imported, RossErrorKind> {
    let mut refusals: Vec<Refused> = Vec::new();
    let groups = shafts(file, &mut refusals)?;
    // The shaft's last node as ROSS numbers it, even when the numbering is refused.
    let last_node = file.shafts.iter().map(|s| s.n.saturating_add(1)).max().unwrap_or(0);
    let mut disks = Vec::new();
    for d in &file.disks {
        let fail = |r| refused("DiskElement", &d.tag, Some(d.n), d.line, r);
        let values = [("m", d.m), ("Ip", d.Ip), ("Id", d.Id)];
        if let Some(r) = values.iter().find_map(|(key, value)| check(key, *value, false).err()) {
            refusals.push(fail(r));
        } else if !(0..=last_node).contains(&d.n) {
            refusals.push(fail(Refusal::NodeOffShaft { node: d.n, last: last_node }));
        } else {
            disks.push(DiskOut {
                node: d.n,
                mass: d.m,
                polar_inertia: d.Ip,
                diametral_inertia: d.Id,
                tag: d.tag.clone(),
                class: "DiskElement",
            });
        }
    }
    for p in &file.point_masses {
        let fail = |r| refused("PointMass", &p.tag, Some(p.n), p.line, r);
        match point_mass(p, last_node) {
            Ok(mass) => disks.push(DiskOut {
                node: p.n,
                mass,
                polar_inertia: 0.0,
                diametral_inertia: 0.0,
                tag: p.tag.clone(),
                class: "PointMass",
            }),
            Err(r) => refusals.push(fail(r)),
        }
    }
    disks.sort_by(|a, b| (a.node, &a.tag).cmp(&(b.node, &b.tag)));
    let mut bearings: Vec<BearingOut> = Vec::new();
    let mut sorted: Vec<&Bearing> = file.bearings.iter().collect();
    sorted.sort_by(|a, b| (a.n, &a.tag).cmp(&(b.n, &b.tag)));
    for b in sorted {
        match bearing(b, last_node) {
            Ok(out) => bearings.push(out),
            Err(r) => refusals.push(refused(b.class.name(), &b.tag, Some(b.n), b.line, r)),
        }
    }
    let mut others: Vec<_> = file.others.iter().collect();
    others.sort_by(|a, b| (&a.class, &a.tag).cmp(&(&b.class, &b.tag)));
    for o in others {
        let reason = if o.magnetic { Refusal::Magnetic } else { Refusal::UnknownClass(o.class.clone()) };
        refusals.push(refused(&o.class, &o.tag, o.n, o.line, reason));
    }
    if file.bearings.is_empty() {
        refusals.push(Refused { element: None, reason: Box::new(Refusal::NoBearing) });
    }
    if !refusals.is_empty() {
        let first = refusals.remove(0);
        return Err(RossErrorKind::Refused { element: first.element, reason: first.reason, more: refusals.into() });
    }
    let flat: Vec<&Shaft> = groups.iter().flatten().copied().collect();
    let (materials, element_material) = materials(&flat);
    let sections = sections(&groups, &materials, &element_material);
    Ok(Imported { ross_version: file.ross_version.clone(), speed, materials, sections, disks, bearings })
}

/// The mass (kg) of a point mass on the shaft, which rotorshunt holds as a disk without
/// inertia; a point mass off the shaft is a pedestal.
fn point_mass(p: &super::parse::PointMass, last_node: i64) -> Result<f64, Refusal> {
    check("mx", p.mx, false)?;
    check("my", p.my, false)?;
    if p.n > last_node {
        return Err(Refusal::Pedestal { node: p.n, last: last_node });
    }
    if p.n < 0 {
        return Err(Refusal::NodeOffShaft { node: p.n, last: last_node });
    }
    if p.mx != p.my {
        return Err(Refusal::PointMassAnisotropic { mx: p.mx, my: p.my });
    }
    Ok(p.mx)
}

/// The shaft elements grouped by `n`, each checked, numbered 0…N−1: per `n` the
/// element or, for ROSS's concentric layers (several elements of one `n`), all of them,
/// innermost first (by inner diameter, then tag). Refused elements are added to
/// `refusals` and left out.
fn shafts<'a>(file: &'a RossFile, refusals: &mut Vec<Refused>) -> Result<Vec<Vec<&'a Shaft>>, RossErrorKind> {
    let mut shafts: Vec<&Shaft> = file.shafts.iter().collect();
    // A total order even on a NaN diameter (refused below, after sorting).
    shafts.sort_by(|a, b| a.n.cmp(&b.n).then(a.idl.total_cmp(&b.idl)).then_with(|| a.tag.cmp(&b.tag)));
    if shafts.is_empty() {
        return Err(RossErrorKind::Schema {
            key: String::new(),
            line: None,
            message: "the file has no ShaftElement: a rotor needs a shaft".into(),
        });
    }
    let mut groups: Vec<Vec<&Shaft>> = Vec::new();
    // The next element number expected, the n of the element before, and whether that n
    // has a group (its first element was accepted).
    let (mut next, mut last_n, mut grouped) = (0i64, None, false);
    for s in shafts {
        let fail = |r| refused("ShaftElement", &s.tag, Some(s.n), s.line, r);
        let first_of_n = last_n != Some(s.n);
        last_n = Some(s.n);
        if first_of_n {
            grouped = false;
            if s.n != next {
                let message = if s.n > next {
                    format!("n = {} but no shaft element has n = {next}: ROSS numbers a shaft's elements 0 to N−1", s.n)
                } else {
                    format!("n = {}: ROSS numbers a shaft's elements 0 to N−1", s.n)
                };
                refusals.push(fail(Refusal::Numbering(message)));
                next = s.n.saturating_add(1);
                continue;
            }
            next = s.n + 1;
        }
        if let Err(r) = shaft(s) {
            refusals.push(fail(r));
            continue;
        }
        if first_of_n {
            groups.push(vec![s]);
            grouped = true;
            continue;
        }
        // A concentric layer (another element of the same n); left out when the n has no
        // group, its first element refused.
        let Some(group) = groups.last_mut().filter(|_| grouped) else { continue };
        // ROSS places nodes by the elements' L, so one n has one L.
        if s.L != group[0].L {
            let message = format!(
                "n = {} is also the n of ShaftElement \"{}\" (a concentric layer), but L = {} m there and {} m here: the layers of one element span the same nodes",
                s.n, group[0].tag, group[0].L, s.L
            );
            refusals.push(fail(Refusal::Numbering(message)));
            continue;
        }
        group.push(s);
    }
    Ok(groups)
}

/// One shaft element's refusals, in the order docs/ross-format.md lists them.
fn shaft(s: &Shaft) -> Result<(), Refusal> {
    check("L", s.L, true)?;
    check("odl", s.odl, true)?;
    check("odr", s.odr, true)?;
    check("idl", s.idl, false)?;
    check("idr", s.idr, false)?;
    check("material.rho", s.material.rho, true)?;
    check("material.E", s.material.E, true)?;
    if s.shear_effects {
        check("material.G_s", s.material.G_s, true)?;
        let poisson = s.material.E / (2.0 * s.material.G_s) - 1.0;
        if !(poisson > -1.0 && poisson < 0.5) {
            let rule = format!(
                "Poisson's ratio E/(2 G_s) - 1 = {} must lie between -1 and 0.5 (an isotropic material) for a Timoshenko element",
                crate::analysis::limits::number(poisson)
            );
            return Err(Refusal::Value { key: "material.G_s".into(), value: s.material.G_s, rule });
        }
        shear_method(s)?;
    }
    if !s.rotary_inertia {
        return Err(Refusal::EffectOff("rotary_inertia"));
    }
    if !s.gyroscopic {
        return Err(Refusal::EffectOff("gyroscopic"));
    }
    for (key, inner, outer_key, outer) in [("idl", s.idl, "odl", s.odl), ("idr", s.idr, "odr", s.odr)] {
        if inner >= outer {
            let rule = format!("the inner diameter must be below the outer one, {outer_key} = {} m", outer);
            return Err(Refusal::Value { key: key.into(), value: inner, rule });
        }
    }
    for (key, value, unit) in [("axial_force", s.axial_force, "N"), ("torque", s.torque, "N·m")] {
        if value != 0.0 {
            return Err(Refusal::Preload { key, value, unit });
        }
    }
    for (key, value) in [("alpha", s.alpha), ("beta", s.beta)] {
        if value != 0.0 {
            return Err(Refusal::ShaftDamping { key, value });
        }
    }
    Ok(())
}

/// The shear coefficient to write for a Timoshenko element: `None` for ROSS's default
/// `cowper` (rotorshunt's default formula, evaluated on the same diameters), the value
/// ROSS computes for `hutchinson`; any other name is not ROSS's.
fn shear_method(s: &Shaft) -> Result<Option<f64>, Refusal> {
    match s.shear_method_calc.as_deref().unwrap_or("cowper") {
        "cowper" => Ok(None),
        "hutchinson" => {
            let poisson = s.material.E / (2.0 * s.material.G_s) - 1.0;
            let ratio = ((s.idl + s.idr) / 2.0) / ((s.odl + s.odr) / 2.0);
            Ok(Some(element::ross_hutchinson_shear_coefficient(poisson, ratio)))
        }
        other => Err(Refusal::ShearMethod(other.to_string())),
    }
}

/// Distinct materials in order of first use, and each element's material index. ROSS
/// keeps a material per element; one name with different values becomes `name-2`, …:
/// the first free suffix, skipping every name the file uses itself (a real `Steel-2`)
/// and every name already given, so the problem's material names are all distinct.
/// Linear in the elements: materials are found by hashing, and each name's suffixes are
/// tried from where its last search stopped (a name once taken stays taken, so no
/// smaller suffix becomes free).
fn materials(shafts: &[&Shaft]) -> (Vec<MaterialOut>, Vec<usize>) {
    use std::collections::{HashMap, HashSet};
    let ross_names: HashSet<&str> = shafts.iter().map(|s| s.material.name.as_str()).collect();
    let mut out: Vec<MaterialOut> = Vec::new();
    let mut index = Vec::with_capacity(shafts.len());
    // A material by its ROSS name and values, compared as `==` compares them: −0 as +0,
    // and a NaN (which equals nothing) never found.
    let mut known: HashMap<(&str, [u64; 3]), usize> = HashMap::new();
    let mut given: HashSet<String> = HashSet::new();
    let mut next_suffix: HashMap<&str, u64> = HashMap::new();
    let mut tried = 0;
    for s in shafts {
        let m = &s.material;
        let values = [m.E, m.rho, m.G_s];
        let key = (!values.iter().any(|v| v.is_nan()))
            .then(|| (m.name.as_str(), values.map(|v| if v == 0.0 { 0 } else { v.to_bits() })));
        let found = key.and_then(|k| known.get(&k).copied());
        let i = found.unwrap_or_else(|| {
            tried += 1;
            let name = if given.contains(&m.name) {
                // The first variant of a name keeps it; a later variant takes a suffix
                // that neither the file nor an earlier variant uses.
                let k = next_suffix.entry(m.name.as_str()).or_insert(2);
                loop {
                    let candidate = format!("{}-{k}", m.name);
                    *k += 1;
                    tried += 1;
                    if !ross_names.contains(candidate.as_str()) && !given.contains(&candidate) {
                        break candidate;
                    }
                }
            } else {
                m.name.clone()
            };
            given.insert(name.clone());
            out.push(MaterialOut {
                name,
                ross_name: m.name.clone(),
                youngs_modulus: m.E,
                density: m.rho,
                shear_modulus: m.G_s,
                timoshenko: false,
            });
            if let Some(k) = key {
                known.insert(k, out.len() - 1);
            }
            out.len() - 1
        });
        out[i].timoshenko |= s.shear_effects;
        index.push(i);
    }
    super::work::add(|w| w.material_names_tried += tried);
    (out, index)
}

/// What makes a tube (an element, or a layer of one) a section's or a layer's: its
/// material, diameters (and right-end ones when tapered) and beam theory.
type Tube = (usize, f64, f64, Option<(f64, f64)>, Option<Option<f64>>);

fn tube(s: &Shaft, material: usize) -> Tube {
    let right = (s.odl != s.odr || s.idl != s.idr).then_some((s.odr, s.idr));
    // Checked by `shaft` before: a Timoshenko element's method is ROSS's.
    let timoshenko = s.shear_effects.then(|| shear_method(s).ok().flatten());
    (material, s.odl, s.idl, right, timoshenko)
}

/// Runs of consecutive `n` whose elements (and layers) are uniform with the same
/// diameters, materials, beam theory and length; an `n` with a tapered element is a
/// section of its own.
fn sections(groups: &[Vec<&Shaft>], materials: &[MaterialOut], material: &[usize]) -> Vec<SectionOut> {
    let mut out: Vec<SectionOut> = Vec::new();
    // Each section's element lengths, summed as the decimals ROSS wrote at the end.
    let mut lengths: Vec<Vec<f64>> = Vec::new();
    let mut last: Vec<Tube> = Vec::new();
    let mut index = 0;
    for group in groups {
        let tubes: Vec<Tube> = group.iter().enumerate().map(|(k, s)| tube(s, material[index + k])).collect();
        index += group.len();
        let s = group[0];
        let uniform = tubes.iter().all(|t| t.3.is_none());
        let same = out.last().is_some_and(|sec| {
            uniform && tubes == last && (s.L - sec.element_length).abs() <= SAME_LENGTH_RTOL * sec.element_length
        });
        match out.last_mut().filter(|_| same) {
            Some(sec) => {
                if let Some(l) = lengths.last_mut() {
                    l.push(s.L);
                }
                sec.elements += 1;
                sec.tags.1 = s.tag.clone();
                for (layer, e) in sec.layers.iter_mut().zip(&group[1..]) {
                    layer.tags.1 = e.tag.clone();
                }
            }
            None => {
                let layers = group[1..]
                    .iter()
                    .zip(&tubes[1..])
                    .map(|(e, t)| LayerOut {
                        outer_diameter: t.1,
                        inner_diameter: t.2,
                        right: t.3,
                        timoshenko: t.4,
                        material: materials[t.0].name.clone(),
                        tags: (e.tag.clone(), e.tag.clone()),
                    })
                    .collect();
                let t = &tubes[0];
                lengths.push(vec![s.L]);
                out.push(SectionOut {
                    length: s.L,
                    outer_diameter: t.1,
                    inner_diameter: t.2,
                    right: t.3,
                    timoshenko: t.4,
                    material: materials[t.0].name.clone(),
                    elements: 1,
                    first_n: s.n,
                    tags: (s.tag.clone(), s.tag.clone()),
                    element_length: s.L,
                    layers,
                })
            }
        }
        last = tubes;
    }
    for (sec, l) in out.iter_mut().zip(&lengths) {
        sec.length = decimal_sum(l);
    }
    out
}

/// The sum of `values` as the decimals they print as (each f64's shortest round-trip
/// form, which is what ROSS saved), rounded once: three elements of 0.1 make a section of
/// 0.3, not the float sum 0.30000000000000004. Falls back to the float sum when the
/// decimals do not fit an exact 128-bit sum (exponents far apart).
pub fn decimal_sum(values: &[f64]) -> f64 {
    let float = values.iter().sum::<f64>();
    // (digits, exponent): value = digits · 10^exponent.
    let parts: Option<Vec<(i128, i32)>> = values
        .iter()
        .map(|v| {
            if !v.is_finite() {
                return None;
            }
            let text = format!("{v:e}");
            let (mantissa, exp) = text.split_once('e')?;
            let exp: i32 = exp.parse().ok()?;
            let (int, frac) = mantissa.split_once('.').unwrap_or((mantissa, ""));
            let digits: i128 = format!("{int}{frac}").parse().ok()?;
            Some((digits, exp - frac.len() as i32))
        })
        .collect();
    let Some(parts) = parts else { return float };
    let Some(low) = parts.iter().map(|p| p.1).min() else { return 0.0 };
    let mut total: i128 = 0;
    for (digits, exp) in parts {
        let scaled =
            u32::try_from(exp - low).ok().and_then(|e| 10i128.checked_pow(e)).and_then(|f| digits.checked_mul(f));
        match scaled.and_then(|x| total.checked_add(x)) {
            Some(t) => total = t,
            None => return float,
        }
    }
    format!("{total}e{low}").parse().unwrap_or(float)
}

/// A grounded bearing or seal with its full coefficients and table, or why not.
fn bearing(b: &Bearing, last_node: i64) -> Result<BearingOut, Refusal> {
    if let Some(link) = b.n_link {
        return Err(Refusal::Linked(link));
    }
    if !(0..=last_node).contains(&b.n) {
        return Err(Refusal::NodeOffShaft { node: b.n, last: last_node });
    }
    let freq: &[f64] = b.frequency.as_ref().map_or(&[], Coefficient::values);
    let points = freq.len().max(1);
    let limit = crate::problem::MAX_TABLE_POINTS;
    if freq.len() > limit {
        let rule = format!(
            "the table has {} frequencies, more than the {limit} a problem's coefficient table may have (docs/errors.md, TableTooLong)",
            freq.len()
        );
        return Err(Refusal::Value { key: "frequency".into(), value: freq.len() as f64, rule });
    }
    // In rotorshunt's order (COEFFICIENT_NAMES), then the masses.
    let lateral: [(&'static str, &Coefficient); 12] = [
        ("kxx", &b.kxx),
        ("kxy", &b.kxy),
        ("kyx", &b.kyx),
        ("kyy", &b.kyy),
        ("cxx", &b.cxx),
        ("cxy", &b.cxy),
        ("cyx", &b.cyx),
        ("cyy", &b.cyy),
        ("mxx", &b.mxx),
        ("mxy", &b.mxy),
        ("myx", &b.myx),
        ("myy", &b.myy),
    ];
    let axial = [("kzz", &b.kzz), ("czz", &b.czz), ("mzz", &b.mzz)];
    let lengths = lateral.iter().map(|(k, c)| (*k, c.values().len()));
    let lengths = lengths.chain(axial.iter().filter_map(|(k, c)| c.as_ref().map(|c| (*k, c.values().len()))));
    for (key, len) in lengths {
        if len != points {
            let rule = format!("has {len} values, but the bearing is tabulated at {points} frequencies");
            return Err(Refusal::Value { key: key.into(), value: len as f64, rule });
        }
    }
    for (key, c) in &lateral {
        if let Some(&v) = c.values().iter().find(|v| !v.is_finite()) {
            return Err(Refusal::Value { key: (*key).into(), value: v, rule: "must be finite".into() });
        }
    }
    for (i, &w) in freq.iter().enumerate() {
        let bad = if !w.is_finite() || w < 0.0 {
            Some("the frequencies of the table must be finite and ≥ 0 (rad/s)")
        } else if i > 0 && w <= freq[i - 1] {
            Some("the frequencies of the table must increase strictly")
        } else {
            None
        };
        if let Some(rule) = bad {
            return Err(Refusal::Value { key: format!("frequency[{i}]"), value: w, rule: rule.into() });
        }
    }
    let at = |i: usize, j: usize| lateral[i].1.values()[j];
    let frequency = |j: usize| (points > 1).then(|| freq[j]);
    for (i, key) in [(0, "kxx"), (3, "kyy")] {
        if let Some((j, &value)) = lateral[i].1.values().iter().enumerate().find(|(_, v)| **v < 0.0) {
            return Err(Refusal::NegativeStiffness { key, value, frequency: frequency(j) });
        }
    }
    for j in 0..points {
        let c = [[at(4, j), at(5, j)], [at(6, j), at(7, j)]];
        let eigenvalue = crate::problem::general::smallest_symmetric_eigenvalue(c);
        let scale = c.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
        if eigenvalue < -crate::problem::general::DAMPING_ROUND_OFF * scale {
            return Err(Refusal::DampingNotSemiDefinite { c, eigenvalue, frequency: frequency(j) });
        }
    }
    let mass = support_mass(&lateral[8..])?;
    let mut coefficients: [Vec<f64>; 8] = Default::default();
    for (out, (_, c)) in coefficients.iter_mut().zip(&lateral[..8]) {
        let v = c.values();
        // A coefficient constant over the table is written as a constant.
        *out = if v.iter().all(|x| *x == v[0]) { vec![v[0]] } else { v.to_vec() };
    }
    let speeds = if coefficients.iter().any(|v| v.len() > 1) { freq.to_vec() } else { Vec::new() };
    let kind = if b.class == SupportClass::Seal { SupportKind::Seal } else { SupportKind::Bearing };
    Ok(BearingOut { kind, class: b.class.name(), node: b.n, speeds, coefficients, mass, tag: b.tag.clone() })
}

/// The mass of a support (kg) from ROSS's mxx, mxy, myx, myy: rotorshunt lumps one
/// constant mass at the node in both directions.
fn support_mass(m: &[(&'static str, &Coefficient)]) -> Result<f64, Refusal> {
    let (mxx, myy) = (m[0].1.values(), m[3].1.values());
    for (key, c) in [m[1], m[2]] {
        if let Some(v) = c.values().iter().find(|v| **v != 0.0) {
            return Err(Refusal::SupportMass(format!("{key} = {} kg, a cross-coupled mass", limits_number(*v))));
        }
    }
    if let Some((a, b)) = mxx.iter().zip(myy).find(|(a, b)| a != b) {
        let detail = format!("mxx = {} kg but myy = {} kg", limits_number(*a), limits_number(*b));
        return Err(Refusal::SupportMass(detail));
    }
    if let Some(v) = mxx.iter().find(|v| **v != mxx[0]) {
        let detail = format!(
            "mxx = {} kg and {} kg in the table, a mass that varies with the speed",
            limits_number(mxx[0]),
            limits_number(*v)
        );
        return Err(Refusal::SupportMass(detail));
    }
    check("mxx", mxx[0], false)?;
    Ok(mxx[0])
}

fn limits_number(v: f64) -> String {
    crate::analysis::limits::number(v)
}

#[cfg(test)]
mod tests {
    use super::decimal_sum;

    #[test]
    fn a_section_length_is_the_sum_of_the_decimals_ross_wrote() {
        assert_eq!(0.1 + 0.1 + 0.1, 0.30000000000000004);
        assert_eq!(decimal_sum(&[0.1, 0.1, 0.1]), 0.3);
        assert_eq!(decimal_sum(&[0.25; 6]), 1.5);
        assert_eq!(decimal_sum(&[0.035500000000000004]), 0.035500000000000004);
        assert_eq!(decimal_sum(&[0.09999999999999999; 6]), 0.6);
        assert_eq!(decimal_sum(&[1e-300, 1e300]), 1e300);
        assert_eq!(decimal_sum(&[]), 0.0);
    }
}
