//! From ROSS's elements to rotorshunt's general form: materials, sections (Rayleigh or
//! Timoshenko, uniform or tapered), disks and plain bearings, or a refusal naming the
//! element. The rules are in
//! `docs/ross-format.md` (section "Mapping to rotorshunt").

use super::error::{ElementRef, Refusal, RossErrorKind};
use super::parse::{Bearing, Coefficient, RossFile, Shaft};
use super::table;
use crate::model::element;

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
    /// The speed Ω (rad/s) the bearings were evaluated at, if one was chosen.
    pub speed: Option<f64>,
    /// Materials, in order of first use.
    pub materials: Vec<MaterialOut>,
    /// Shaft sections, left to right.
    pub sections: Vec<SectionOut>,
    /// Disks, by node (then tag).
    pub disks: Vec<DiskOut>,
    /// Plain bearings, by node.
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
}

/// A `[[bearings]]` entry: one or more isotropic ROSS bearings at one node (ROSS adds the
/// matrices of bearings at one node; rotorshunt has one support per node, so they are
/// summed here).
#[derive(Debug, Clone, PartialEq)]
pub struct BearingOut {
    /// Shaft node of the support, ROSS's `n` (0-based, 0 = left end).
    pub node: i64,
    /// k = kxx = kyy (N/m).
    pub stiffness: f64,
    /// c = cxx = cyy (N·s/m).
    pub damping: f64,
    /// Added mass mxx = myy (kg), on the node.
    pub mass: f64,
    /// ROSS tags, with the number of tabulated frequencies if the coefficients were
    /// evaluated at the chosen speed.
    pub from: Vec<(String, Option<usize>)>,
}

fn refused(class: &str, tag: &str, n: Option<i64>, reason: Refusal) -> RossErrorKind {
    RossErrorKind::Refused {
        element: Some(Box::new(ElementRef { class: class.into(), tag: tag.into(), n })),
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

/// Map a parsed file; `speed` (rad/s) evaluates tabulated bearing coefficients.
pub fn map(file: &RossFile, speed: Option<f64>) -> Result<Imported, RossErrorKind> {
    let groups = shafts(file)?;
    let last_node = groups.len() as i64;
    let flat: Vec<&Shaft> = groups.iter().flatten().copied().collect();
    let (materials, element_material) = materials(&flat);
    let sections = sections(&groups, &materials, &element_material);
    let mut disks = Vec::new();
    for d in &file.disks {
        let fail = |r| refused("DiskElement", &d.tag, Some(d.n), r);
        for (key, value) in [("m", d.m), ("Ip", d.Ip), ("Id", d.Id)] {
            check(key, value, false).map_err(fail)?;
        }
        if !(0..=last_node).contains(&d.n) {
            return Err(fail(Refusal::NodeOffShaft { node: d.n, last: last_node }));
        }
        disks.push(DiskOut { node: d.n, mass: d.m, polar_inertia: d.Ip, diametral_inertia: d.Id, tag: d.tag.clone() });
    }
    disks.sort_by(|a, b| (a.node, &a.tag).cmp(&(b.node, &b.tag)));
    let mut plain: Vec<(i64, [f64; 3], String, Option<usize>)> = Vec::new();
    let mut sorted: Vec<&Bearing> = file.bearings.iter().collect();
    sorted.sort_by(|a, b| (a.n, &a.tag).cmp(&(b.n, &b.tag)));
    for b in sorted {
        let (kcm, table) = bearing(b, speed).map_err(|r| refused("BearingElement", &b.tag, Some(b.n), r))?;
        if !(0..=last_node).contains(&b.n) {
            let r = Refusal::NodeOffShaft { node: b.n, last: last_node };
            return Err(refused("BearingElement", &b.tag, Some(b.n), r));
        }
        plain.push((b.n, kcm, b.tag.clone(), table));
    }
    if let Some((class, tag, n)) = file.others.iter().min_by(|a, b| (&a.0, &a.1).cmp(&(&b.0, &b.1))) {
        return Err(refused(class, tag, *n, Refusal::UnknownClass(class.clone())));
    }
    if plain.is_empty() {
        return Err(RossErrorKind::Refused { element: None, reason: Box::new(Refusal::NoBearing) });
    }
    let mut bearings: Vec<BearingOut> = Vec::new();
    for (node, [k, c, m], tag, table) in plain {
        match bearings.last_mut().filter(|b| b.node == node) {
            Some(b) => {
                b.stiffness += k;
                b.damping += c;
                b.mass += m;
                b.from.push((tag, table));
            }
            None => bearings.push(BearingOut { node, stiffness: k, damping: c, mass: m, from: vec![(tag, table)] }),
        }
    }
    Ok(Imported { ross_version: file.ross_version.clone(), speed, materials, sections, disks, bearings })
}

/// The shaft elements grouped by `n`, each checked, numbered 0…N−1: per `n` the
/// element or, for ROSS's concentric layers (several elements of one `n`), all of them,
/// innermost first (by inner diameter, then tag).
fn shafts(file: &RossFile) -> Result<Vec<Vec<&Shaft>>, RossErrorKind> {
    let mut shafts: Vec<&Shaft> = file.shafts.iter().collect();
    // A total order even on a NaN diameter (refused below, after sorting).
    shafts.sort_by(|a, b| a.n.cmp(&b.n).then(a.idl.total_cmp(&b.idl)).then_with(|| a.tag.cmp(&b.tag)));
    if shafts.is_empty() {
        return Err(RossErrorKind::Schema {
            key: String::new(),
            message: "the file has no ShaftElement: a rotor needs a shaft".into(),
        });
    }
    let mut groups: Vec<Vec<&Shaft>> = Vec::new();
    for s in shafts {
        let fail = |r| refused("ShaftElement", &s.tag, Some(s.n), r);
        shaft(s).map_err(fail)?;
        if let Some(group) = groups.last_mut().filter(|g| g[0].n == s.n) {
            // A concentric layer: ROSS places nodes by the elements' L, so one n has one L.
            if s.L != group[0].L {
                let message = format!(
                    "n = {} is also the n of ShaftElement \"{}\" (a concentric layer), but L = {} m there and {} m here: the layers of one element span the same nodes",
                    s.n, group[0].tag, group[0].L, s.L
                );
                return Err(fail(Refusal::Numbering(message)));
            }
            group.push(s);
            continue;
        }
        let i = groups.len() as i64;
        if s.n != i {
            let message =
                format!("n = {} but no shaft element has n = {i}: ROSS numbers a shaft's elements 0 to N−1", s.n);
            return Err(fail(Refusal::Numbering(message)));
        }
        groups.push(vec![s]);
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
fn materials(shafts: &[&Shaft]) -> (Vec<MaterialOut>, Vec<usize>) {
    let ross_names: std::collections::HashSet<&str> = shafts.iter().map(|s| s.material.name.as_str()).collect();
    let mut out: Vec<MaterialOut> = Vec::new();
    let mut index = Vec::with_capacity(shafts.len());
    for s in shafts {
        let m = &s.material;
        let found = out.iter().position(|o| {
            o.ross_name == m.name && o.youngs_modulus == m.E && o.density == m.rho && o.shear_modulus == m.G_s
        });
        let i = found.unwrap_or_else(|| {
            let taken = |name: &str| out.iter().any(|o| o.name == name);
            let name = if taken(&m.name) {
                // The first variant of a name keeps it; a later variant takes a suffix
                // that neither the file nor an earlier variant uses.
                (2u64..)
                    .map(|k| format!("{}-{k}", m.name))
                    .find(|n| !ross_names.contains(n.as_str()) && !taken(n))
                    .unwrap_or_default()
            } else {
                m.name.clone()
            };
            out.push(MaterialOut {
                name,
                ross_name: m.name.clone(),
                youngs_modulus: m.E,
                density: m.rho,
                shear_modulus: m.G_s,
                timoshenko: false,
            });
            out.len() - 1
        });
        out[i].timoshenko |= s.shear_effects;
        index.push(i);
    }
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
                sec.length += s.L;
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
    out
}

/// Stiffness, damping and mass of an isotropic grounded bearing at the chosen speed, and
/// the length of its table when it has one.
fn bearing(b: &Bearing, speed: Option<f64>) -> Result<([f64; 3], Option<usize>), Refusal> {
    if let Some(link) = b.n_link {
        return Err(Refusal::Linked(link));
    }
    let freq: Option<&[f64]> = b.frequency.as_ref().map(Coefficient::values);
    let points = freq.map_or(1, <[f64]>::len).max(1);
    let lateral: [(&'static str, &Coefficient); 12] = [
        ("kxx", &b.kxx),
        ("kyy", &b.kyy),
        ("kxy", &b.kxy),
        ("kyx", &b.kyx),
        ("cxx", &b.cxx),
        ("cyy", &b.cyy),
        ("cxy", &b.cxy),
        ("cyx", &b.cyx),
        ("mxx", &b.mxx),
        ("myy", &b.myy),
        ("mxy", &b.mxy),
        ("myx", &b.myx),
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
        for &v in c.values() {
            if !v.is_finite() {
                return Err(Refusal::Value { key: (*key).into(), value: v, rule: "must be finite".into() });
            }
        }
    }
    for (i, unit) in [(0, "N/m"), (4, "N·s/m"), (8, "kg")] {
        let (x_key, x) = lateral[i];
        let (y_key, y) = lateral[i + 1];
        if let Some((a, b)) = x.values().iter().zip(y.values()).find(|(a, b)| a != b) {
            return Err(Refusal::Anisotropic { x_key, x: *a, y_key, y: *b, unit });
        }
        for (key, c) in [lateral[i + 2], lateral[i + 3]] {
            if let Some(&value) = c.values().iter().find(|v| **v != 0.0) {
                return Err(Refusal::CrossCoupled { key, value, unit });
            }
        }
    }
    let at = |c: &Coefficient| -> Result<f64, Refusal> {
        match (freq, points) {
            (_, 1) => Ok(c.values()[0]),
            (Some(f), _) => {
                let lo = f[0];
                let hi = f[f.len() - 1];
                let Some(w) = speed else { return Err(Refusal::SpeedDependent { points, lo, hi }) };
                if !(lo..=hi).contains(&w) {
                    return Err(Refusal::OutsideTable { speed: w, lo, hi });
                }
                table::evaluate(f, c.values(), w).ok_or(Refusal::Value {
                    key: "frequency".into(),
                    value: lo,
                    rule: "the table cannot be interpolated".into(),
                })
            }
            (None, _) => Ok(c.values()[0]),
        }
    };
    if let Some(f) = freq.filter(|f| f.len() > 1) {
        for (i, w) in f.windows(2).enumerate() {
            if !(w[0].is_finite() && w[1].is_finite() && w[1] > w[0]) {
                let rule = "the frequencies of the table must be finite and strictly increasing".to_string();
                return Err(Refusal::Value { key: format!("frequency[{}]", i + 1), value: w[1], rule });
            }
        }
    }
    let k = at(&b.kxx)?;
    let c = at(&b.cxx)?;
    let m = at(&b.mxx)?;
    for (key, v) in [("kxx", k), ("cxx", c), ("mxx", m)] {
        if v < 0.0 {
            let rule = match speed.filter(|_| points > 1) {
                Some(w) => format!("at the chosen speed {w} rad/s: must be ≥ 0"),
                None => "must be ≥ 0".into(),
            };
            return Err(Refusal::Value { key: key.into(), value: v, rule });
        }
    }
    Ok(([k, c, m], (points > 1).then_some(points)))
}
