//! The general form of a problem file (issue 16): `[[materials]]`, `[[sections]]`,
//! `[[bearings]]` and `[[rings]]` with their own circuits, the disks' geometry form, and
//! the checks on supports (one per node, no rigid-body mode). The shorthand (`[shaft]`,
//! `[ring]`, `[circuit]`) is translated in `validate.rs` onto the same model.

use super::file::*;
use super::validate::{
    circuit, derived, non_negative, place, positive, ring, section_quantities, within, Failure, Placed, SectionKeys,
    MAX_ELEMENTS,
};
use super::{NameOf, ProblemErrorKind as K};
use crate::model::{Beam, Bearing, RingSupport, Section, Shaft};

/// The key of the shaft topic's and of the supports topic's forms: mixing them in one
/// topic, or leaving a topic out, is refused here (before any value is read).
pub(super) fn forms(f: &ProblemFile) -> Result<ShaftForm<'_>, Failure> {
    let shaft = match (&f.shaft, &f.sections) {
        (Some(_), Some(_)) => return Err(("sections".into(), K::MixedForms("[shaft]".into(), "[[sections]]".into()))),
        (None, None) => return Err(("shaft".into(), K::Schema("missing field `shaft`".into()))),
        (Some(s), None) => ShaftForm::Shorthand(s),
        (None, Some(list)) => ShaftForm::Sections(list),
    };
    let general = if !f.rings.is_empty() {
        Some(("rings", "[[rings]]"))
    } else {
        (!f.bearings.is_empty()).then_some(("bearings", "[[bearings]]"))
    };
    let shorthand = if f.ring.is_some() { Some("[ring]") } else { f.circuit.is_some().then_some("[circuit]") };
    match (shorthand, general) {
        (Some(s), Some((key, g))) => Err((key.into(), K::MixedForms(s.into(), g.into()))),
        // A general shaft with no support is a free rotor: reported by `supports_check`.
        (None, None) if f.sections.is_some() => Ok(shaft),
        (None, None) => Err(("ring".into(), K::Schema("missing field `ring`".into()))),
        (Some(_), None) if f.ring.is_none() => Err(("ring".into(), K::Schema("missing field `ring`".into()))),
        (Some(_), None) if f.circuit.is_none() => Err(("circuit".into(), K::Schema("missing field `circuit`".into()))),
        _ => Ok(shaft),
    }
}

/// The form a file gives its shaft in: exactly one, as [`forms`] checks.
pub(super) enum ShaftForm<'a> {
    /// The version-1 shorthand `[shaft]` (one uniform section).
    Shorthand(&'a ShaftFile),
    /// The general `[[sections]]` list.
    Sections(&'a [SectionFile]),
}

/// E and ρ of a material name at `key`, and the material's index in `[[materials]]`.
fn material(key: &str, name: &str, materials: &[MaterialFile]) -> Result<(f64, f64, usize), Failure> {
    let j = materials.iter().position(|m| m.name == name).ok_or_else(|| {
        let known = materials.iter().map(|m| m.name.clone()).collect();
        (key.to_string(), K::UnknownName { what: NameOf::Material, name: name.into(), known })
    })?;
    Ok((materials[j].youngs_modulus, materials[j].density, j))
}

/// The shear modulus G (Pa) of a material's `shear_modulus` or `poisson_ratio` keys
/// (`prefix` their table, E its Young's modulus), each checked; `None` when neither is
/// given. ν = E/(2G) − 1 must lie in (−1, 0.5), the range of an isotropic material: for
/// G, G > E/3.
fn shear_modulus(prefix: &str, e: f64, g: Option<f64>, nu: Option<f64>) -> Result<Option<f64>, Failure> {
    match (g, nu) {
        (Some(_), Some(_)) => {
            Err((format!("{prefix}.poisson_ratio"), K::BothGiven("shear_modulus".into(), "poisson_ratio".into())))
        }
        (Some(g), None) => {
            let key = format!("{prefix}.shear_modulus");
            let g = positive(&key, g)?;
            if g <= e / 3.0 {
                let range = format!(
                    "above E/3 = {} Pa (Poisson's ratio E/(2G) - 1 below 0.5)",
                    crate::analysis::limits::number(e / 3.0)
                );
                return Err((key, K::OutOfRange { value: g, range }));
            }
            Ok(Some(g))
        }
        (None, Some(nu)) => {
            let key = format!("{prefix}.poisson_ratio");
            let nu = within(&key, nu, -1.0, 0.5, "between -1 and 0.5, exclusive (an isotropic material)")?;
            Ok(Some(e / (2.0 * (1.0 + nu))))
        }
        (None, None) => Ok(None),
    }
}

/// `[[materials]]`: finite positive E and ρ, a valid shear modulus or Poisson's ratio if
/// given, unique names. Returns each material's shear modulus.
fn materials(f: &ProblemFile) -> Result<Vec<Option<f64>>, Failure> {
    let mut shear = Vec::with_capacity(f.materials.len());
    for (i, m) in f.materials.iter().enumerate() {
        let key = format!("materials[{i}]");
        if f.materials[..i].iter().any(|n| n.name == m.name) {
            return Err((format!("{key}.name"), K::BadName { name: m.name.clone(), reason: "defined twice".into() }));
        }
        let e = positive(&format!("{key}.youngs_modulus"), m.youngs_modulus)?;
        positive(&format!("{key}.density"), m.density)?;
        shear.push(shear_modulus(&key, e, m.shear_modulus, m.poisson_ratio)?);
    }
    Ok(shear)
}

/// The left- and right-end diameters of the section (or layer) at `prefix` (m): D > 0
/// and 0 ≤ d < D at both ends; the right end's default to the left end's (uniform).
fn section_diameters(prefix: &str, s: &SectionFile) -> Result<[f64; 4], Failure> {
    let key = |name: &str| format!("{prefix}.{name}");
    let outer = positive(&key("outer_diameter"), s.outer_diameter)?;
    let inner = non_negative(&key("inner_diameter"), s.inner_diameter)?;
    if inner >= outer {
        return Err((key("inner_diameter"), K::InnerNotBelowOuter { inner, outer }));
    }
    // A taper to a zero outer diameter is `NotPositive` at its key.
    let outer_right = s.outer_diameter_right.map(|d| positive(&key("outer_diameter_right"), d)).transpose()?;
    let inner_right = s.inner_diameter_right.map(|d| non_negative(&key("inner_diameter_right"), d)).transpose()?;
    let (o, i_r) = (outer_right.unwrap_or(outer), inner_right.unwrap_or(inner));
    if i_r >= o {
        let at = if s.inner_diameter_right.is_some() { "inner_diameter_right" } else { "outer_diameter_right" };
        return Err((key(at), K::InnerNotBelowOuter { inner: i_r, outer: o }));
    }
    Ok([outer, inner, o, i_r])
}

/// `[[sections]]` as the shaft.
pub(super) fn sections(f: &ProblemFile, list: &[SectionFile]) -> Result<Shaft, Failure> {
    let material_shear = materials(f)?;
    let mut sections = Vec::with_capacity(list.len());
    let mut keys = Vec::with_capacity(list.len());
    let mut total_elements: i64 = 0;
    for (i, s) in list.iter().enumerate() {
        let key = |name: &str| format!("sections[{i}].{name}");
        if s.elements < 1 || s.elements > MAX_ELEMENTS {
            let range = format!("a whole number from 1 to {MAX_ELEMENTS}");
            return Err((key("elements"), K::OutOfRange { value: s.elements as f64, range }));
        }
        total_elements += s.elements;
        if total_elements > MAX_ELEMENTS {
            let range = format!("such that all sections have at most {MAX_ELEMENTS} elements in total");
            return Err((key("elements"), K::OutOfRange { value: s.elements as f64, range }));
        }
        let length = positive(&key("length"), s.length)?;
        let prefix = format!("sections[{i}]");
        let (mut section, mut section_keys) = tube(f, &prefix, s, &material_shear, length)?;
        for (j, layer) in s.layers.iter().enumerate() {
            let layer_prefix = format!("{prefix}.layers[{j}]");
            let (l, mut k) = tube(f, &layer_prefix, &layer.as_section(length, s.elements), &material_shear, length)?;
            // A layer's length is its section's.
            k.length = key("length");
            section.layers.push(l);
            section_keys.layers.push(k);
        }
        keys.push(section_keys);
        sections.push(section);
    }
    let shaft = Shaft { sections };
    let total = shaft.length();
    if !(total.is_finite() && total > 0.0) {
        return Err(("sections".into(), K::ShaftLength { total }));
    }
    section_quantities(&shaft, &keys)?;
    Ok(shaft)
}

/// One tube of the shaft at `prefix` (a section, or a layer of one, given as a section
/// of the section's `length` and elements): its diameters, material and beam theory, and
/// the keys its quantities come from.
fn tube(
    f: &ProblemFile,
    prefix: &str,
    s: &SectionFile,
    material_shear: &[Option<f64>],
    length: f64,
) -> Result<(Section, SectionKeys), Failure> {
    let key = |name: &str| format!("{prefix}.{name}");
    let [outer, inner, outer_right, inner_right] = section_diameters(prefix, s)?;
    let outer_keys = |left: (String, f64)| {
        let right = s.outer_diameter_right.map(|d| (key("outer_diameter_right"), d));
        (left, right)
    };
    // E, ρ, the shear modulus (if any), the keys they come from, and how the section
    // names its material in a message.
    let (youngs_modulus, density, shear, section_keys, named) = match (&s.material, s.youngs_modulus, s.density) {
        (Some(_), Some(_), _) => {
            return Err((key("youngs_modulus"), K::BothGiven("material".into(), "youngs_modulus".into())))
        }
        (Some(_), None, Some(_)) => return Err((key("density"), K::BothGiven("material".into(), "density".into()))),
        (Some(name), None, None) => {
            for (given, k) in
                [(s.shear_modulus.is_some(), "shear_modulus"), (s.poisson_ratio.is_some(), "poisson_ratio")]
            {
                if given {
                    return Err((key(k), K::BothGiven("material".into(), k.into())));
                }
            }
            let (e, d, j) = material(&key("material"), name, &f.materials)?;
            let m = &f.materials[j];
            let shear_key = if m.shear_modulus.is_some() { "shear_modulus" } else { "poisson_ratio" };
            let (outer, outer_right) = outer_keys((key("outer_diameter"), outer));
            let keys = SectionKeys {
                outer,
                outer_right,
                length: key("length"),
                youngs_modulus: format!("materials[{j}].youngs_modulus"),
                density: format!("materials[{j}].density"),
                shear_modulus: format!("materials[{j}].{shear_key}"),
                layers: Vec::new(),
            };
            (e, d, material_shear[j], keys, format!("material `{name}` (materials[{j}])"))
        }
        (None, None, _) => {
            return Err((prefix.to_string(), K::NeitherGiven("material".into(), "youngs_modulus".into())))
        }
        (None, Some(e), d) => {
            let d = d.ok_or_else(|| (key("density"), K::Schema("missing field `density`".into())))?;
            let e = positive(&key("youngs_modulus"), e)?;
            let g = shear_modulus(prefix, e, s.shear_modulus, s.poisson_ratio)?;
            let shear_key = if s.shear_modulus.is_some() { "shear_modulus" } else { "poisson_ratio" };
            let (outer, outer_right) = outer_keys((key("outer_diameter"), outer));
            let keys = SectionKeys {
                outer,
                outer_right,
                length: key("length"),
                youngs_modulus: key("youngs_modulus"),
                density: key("density"),
                shear_modulus: key(shear_key),
                layers: Vec::new(),
            };
            (e, d, g, keys, format!("this section ({prefix})"))
        }
    };
    let beam = match s.beam.unwrap_or_default() {
        BeamKind::Rayleigh => {
            if s.shear_coefficient.is_some() {
                return Err((key("shear_coefficient"), K::TimoshenkoOnly("shear_coefficient".into())));
            }
            Beam::Rayleigh
        }
        BeamKind::Timoshenko => {
            let shear_modulus = shear.ok_or_else(|| (key("beam"), K::NoShearModulus { material: named }))?;
            let shear_coefficient = s.shear_coefficient.map(|k| positive(&key("shear_coefficient"), k)).transpose()?;
            Beam::Timoshenko { shear_modulus, shear_coefficient }
        }
    };
    let section = Section {
        length,
        outer_diameter: outer,
        inner_diameter: inner,
        elements: s.elements as usize,
        youngs_modulus: positive(&key("youngs_modulus"), youngs_modulus)?,
        density: positive(&key("density"), density)?,
        outer_diameter_right: outer_right,
        inner_diameter_right: inner_right,
        beam,
        layers: Vec::new(),
    };
    Ok((section, section_keys))
}

/// A disk of the geometry form (m = ρπ(D² − d²)/4·w, J_p = m(D² + d²)/8,
/// J_d = J_p/2 + m·w²/12), or `None` when none of its keys is given.
pub(super) fn disk_geometry(key: &str, d: &DiskFile, f: &ProblemFile) -> Result<Option<(f64, f64, f64)>, Failure> {
    let geometry = d.outer_diameter.is_some()
        || d.inner_diameter.is_some()
        || d.width.is_some()
        || d.material.is_some()
        || d.density.is_some();
    if !geometry {
        return Ok(None);
    }
    for (name, given) in
        [("mass", d.mass), ("polar_inertia", d.polar_inertia), ("diametral_inertia", d.diametral_inertia)]
    {
        if given.is_some() {
            return Err((format!("{key}.{name}"), K::BothGiven(name.into(), "outer_diameter".into())));
        }
    }
    let k = |name: &str| format!("{key}.{name}");
    let missing = |name: &str| (k(name), K::Schema(format!("missing field `{name}`")));
    let outer = positive(&k("outer_diameter"), d.outer_diameter.ok_or_else(|| missing("outer_diameter"))?)?;
    let inner = non_negative(&k("inner_diameter"), d.inner_diameter.unwrap_or(0.0))?;
    if inner >= outer {
        return Err((k("inner_diameter"), K::InnerNotBelowOuter { inner, outer }));
    }
    let width = positive(&k("width"), d.width.ok_or_else(|| missing("width"))?)?;
    let (density, density_key) = match (&d.material, d.density) {
        (Some(_), Some(_)) => return Err((k("density"), K::BothGiven("material".into(), "density".into()))),
        (Some(name), None) => {
            let (_, rho, j) = material(&k("material"), name, &f.materials)?;
            (rho, format!("materials[{j}].density"))
        }
        (None, Some(rho)) => (rho, k("density")),
        (None, None) => return Err((key.into(), K::NeitherGiven("material".into(), "density".into()))),
    };
    let density = positive(&density_key, density)?;
    let (d2, i2) = (outer * outer, inner * inner);
    let mass = density * std::f64::consts::PI * (d2 - i2) / 4.0 * width;
    let polar = mass * (d2 + i2) / 8.0;
    let diametral = polar / 2.0 + mass * width * width / 12.0;
    // Each quantity's factors, with the power each enters with (m ∝ ρD²w).
    let factors = |d_power, w_power| {
        [(density_key.clone(), density, 1), (k("outer_diameter"), outer, d_power), (k("width"), width, w_power)]
    };
    let mass = derived(mass, "disk mass m = rho pi (D^2 - d^2) w / 4", &factors(2, 1))?;
    let polar = derived(polar, "polar inertia J_p = m (D^2 + d^2) / 8", &factors(4, 1))?;
    let diametral = derived(diametral, "diametral inertia J_d = J_p / 2 + m w^2 / 12", &factors(4, 3))?;
    Ok(Some((mass, polar, diametral)))
}

/// A ring name: letters, digits, `_` and `-` (it appears in labels like `r1@drive` and
/// region labels joined by `+`).
fn name_ok(name: &str) -> Result<(), String> {
    if name.is_empty() {
        return Err("a name must not be empty".into());
    }
    if !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-') {
        return Err("use only letters, digits, `_` and `-` (names appear in mode labels)".into());
    }
    Ok(())
}

/// `[[bearings]]` and `[[rings]]`.
pub(super) fn supports(f: &ProblemFile, shaft: &Shaft) -> Result<(Vec<Bearing>, Vec<RingSupport>), Failure> {
    let bearings = f
        .bearings
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let key = format!("bearings[{i}]");
            let k = |name: &str| format!("{key}.{name}");
            Ok(Bearing {
                node: place(&key, b.node, b.position, shaft, Placed::Support)?,
                stiffness: non_negative(&k("stiffness"), b.stiffness)?,
                damping: non_negative(&k("damping"), b.damping)?,
                mass: non_negative(&k("mass"), b.mass)?,
            })
        })
        .collect::<Result<Vec<_>, Failure>>()?;
    let mut rings: Vec<RingSupport> = Vec::with_capacity(f.rings.len());
    for (i, r) in f.rings.iter().enumerate() {
        let key = format!("rings[{i}]");
        let name = r.name.clone().unwrap_or_else(|| format!("ring{}", i + 1));
        name_ok(&name).map_err(|reason| (format!("{key}.name"), K::BadName { name: name.clone(), reason }))?;
        if rings.iter().any(|q| q.name == name) {
            let reason = "two rings have this name".to_string();
            return Err((format!("{key}.name"), K::BadName { name, reason }));
        }
        let node = place(&key, r.node, r.position, shaft, Placed::Support)?;
        let ring = ring(&key, &r.ring_keys(), &RingOverride::default())?;
        let circuit = circuit(&format!("{key}.circuit"), &r.circuit, &ring)?;
        rings.push(RingSupport { name, node, ring, circuit });
    }
    Ok((bearings, rings))
}

/// One support per node, and at least two supports with stiffness: the open-circuit
/// stiffness K at zero load is positive definite exactly when the supports hold both
/// rigid-body motions u = a + b·x of the free shaft (whose bending energy vanishes on
/// them and only on them), i.e. when two supports with positive stiffness sit at
/// distinct nodes. A ring always has stiffness to the ground on open circuit
/// (k_eq in series with k_eq1 + k_eq2); a bearing when k > 0.
pub(super) fn supports_check(f: &ProblemFile, bearings: &[Bearing], rings: &[RingSupport]) -> Result<(), Failure> {
    let shorthand = f.ring.is_some();
    let key_of = |i: usize| -> String {
        if shorthand {
            "ring".into()
        } else if i < bearings.len() {
            format!("bearings[{i}]")
        } else {
            format!("rings[{}]", i - bearings.len())
        }
    };
    let nodes: Vec<usize> = bearings.iter().map(|b| b.node).chain(rings.iter().map(|r| r.node)).collect();
    let mut seen = std::collections::HashMap::with_capacity(nodes.len());
    for (i, &node) in nodes.iter().enumerate() {
        if let Some(&first) = seen.get(&node) {
            let given = if i < bearings.len() { &f.bearings[i].node } else { &f.rings[i - bearings.len()].node };
            let key = format!("{}.{}", key_of(i), if given.is_some() { "node" } else { "position" });
            return Err((key, K::SupportsShareNode { node, first: key_of(first) }));
        }
        seen.insert(node, i);
    }
    let stiff = bearings.iter().filter(|b| b.stiffness > 0.0).count() + rings.len();
    if stiff < 2 {
        // Blame the first bearing without stiffness (giving it stiffness is the fix);
        // with none, the one support there is, or the shaft when there is none.
        let key = match bearings.iter().position(|b| b.stiffness <= 0.0) {
            Some(i) if !shorthand => format!("bearings[{i}].stiffness"),
            _ if nodes.is_empty() => "sections".to_string(),
            _ => key_of(0),
        };
        return Err((key, K::RigidBody { supports: stiff }));
    }
    Ok(())
}
