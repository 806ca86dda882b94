//! The general form of a problem file (issue 16): `[[materials]]`, `[[sections]]`,
//! `[[bearings]]` and `[[rings]]` with their own circuits, the disks' geometry form, and
//! the checks on supports (one per node, no rigid-body mode). The shorthand (`[shaft]`,
//! `[ring]`, `[circuit]`) is translated in `validate.rs` onto the same model.

use super::file::*;
use super::validate::{
    circuit, derived, non_negative, place, positive, ring, section_quantities, within, Failure, Placed, SectionKeys,
    MAX_ELEMENTS, MAX_SUPPORT_DAMPING_RATIO, MAX_SUPPORT_STIFFNESS_RATIO, MAX_TABLE_POINTS,
};
use super::{Location, ProblemError};
use super::{NameOf, ProblemErrorKind as K};
use crate::model::{Beam, Bearing, RingSupport, Section, Shaft, SupportKind, COEFFICIENT_NAMES};

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
    } else if !f.bearings.is_empty() {
        Some(("bearings", "[[bearings]]"))
    } else {
        (!f.seals.is_empty()).then_some(("seals", "[[seals]]"))
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
/// given, unique names. Returns each material's shear modulus (`Err(())` for a material
/// with a failure: its sections' checks that need it are skipped), and the failures.
fn materials(f: &ProblemFile) -> (Vec<Result<Option<f64>, ()>>, Vec<Failure>) {
    let mut shear = Vec::with_capacity(f.materials.len());
    let mut failures = Vec::new();
    for (i, m) in f.materials.iter().enumerate() {
        let key = format!("materials[{i}]");
        let checked = (|| {
            if f.materials[..i].iter().any(|n| n.name == m.name) {
                return Err((
                    format!("{key}.name"),
                    K::BadName { name: m.name.clone(), reason: "defined twice".into() },
                ));
            }
            let e = positive(&format!("{key}.youngs_modulus"), m.youngs_modulus)?;
            positive(&format!("{key}.density"), m.density)?;
            shear_modulus(&key, e, m.shear_modulus, m.poisson_ratio)
        })();
        match checked {
            Ok(g) => shear.push(Ok(g)),
            Err(failure) => {
                failures.push(failure);
                shear.push(Err(()));
            }
        }
    }
    (shear, failures)
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

/// `[[sections]]` as the shaft. The checks of the materials and of every section and
/// layer (a shear coefficient ≤ 0, a Poisson's ratio outside (−1, 0.5), a taper to a zero
/// diameter, …) are all reported at once ([`K::Several`]), one per material, section or
/// layer and independent check.
pub(super) fn sections(f: &ProblemFile, list: &[SectionFile]) -> Result<Shaft, Failure> {
    let (material_shear, mut failures) = materials(f);
    let mut sections = Vec::with_capacity(list.len());
    let mut keys = Vec::with_capacity(list.len());
    let mut total_elements: i64 = 0;
    for (i, s) in list.iter().enumerate() {
        let key = |name: &str| format!("sections[{i}].{name}");
        if s.elements < 1 || s.elements > MAX_ELEMENTS {
            let range = format!("a whole number from 1 to {MAX_ELEMENTS}");
            failures.push((key("elements"), K::OutOfRange { value: s.elements as f64, range }));
            continue;
        }
        total_elements += s.elements;
        if total_elements > MAX_ELEMENTS {
            let range = format!("such that all sections have at most {MAX_ELEMENTS} elements in total");
            failures.push((key("elements"), K::OutOfRange { value: s.elements as f64, range }));
            continue;
        }
        let length = match positive(&key("length"), s.length) {
            Ok(length) => length,
            Err(failure) => {
                failures.push(failure);
                continue;
            }
        };
        let prefix = format!("sections[{i}]");
        let tubes = std::iter::once((prefix.clone(), s.clone())).chain(
            s.layers
                .iter()
                .enumerate()
                .map(|(j, l)| (format!("{prefix}.layers[{j}]"), l.as_section(length, s.elements))),
        );
        let mut built = Vec::new();
        for (tube_prefix, section) in tubes {
            match tube(f, &tube_prefix, &section, &material_shear, length) {
                Ok(t) => built.push(t),
                Err(mut found) => failures.append(&mut found),
            }
        }
        if built.len() != 1 + s.layers.len() {
            continue;
        }
        let mut built = built.into_iter();
        let Some((mut section, mut section_keys)) = built.next() else { continue };
        for (l, mut k) in built {
            // A layer's length is its section's.
            k.length = key("length");
            section.layers.push(l);
            section_keys.layers.push(k);
        }
        keys.push(section_keys);
        sections.push(section);
    }
    if let Some(first) = several(failures) {
        return Err(first);
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
    material_shear: &[Result<Option<f64>, ()>],
    length: f64,
) -> Result<(Section, SectionKeys), Vec<Failure>> {
    let key = |name: &str| format!("{prefix}.{name}");
    let mut failures = Vec::new();
    // The diameters (a taper to zero among them), the material and the shear coefficient
    // are checked independently: each failure is reported.
    let diameters = section_diameters(prefix, s).map_err(|f| failures.push(f)).ok();
    if let (Some(k), BeamKind::Timoshenko) = (s.shear_coefficient, s.beam.unwrap_or_default()) {
        if let Err(failure) = positive(&key("shear_coefficient"), k) {
            failures.push(failure);
        }
    }
    let outer = diameters.map_or(f64::NAN, |d| d[0]);
    let outer_keys = |left: (String, f64)| {
        let right = s.outer_diameter_right.map(|d| (key("outer_diameter_right"), d));
        (left, right)
    };
    // E, ρ, the shear modulus (if any), the keys they come from, and how the section
    // names its material in a message.
    let material = (|| -> Result<_, Failure> {
        Ok(match (&s.material, s.youngs_modulus, s.density) {
            (Some(_), Some(_), _) => {
                return Err((key("youngs_modulus"), K::BothGiven("material".into(), "youngs_modulus".into())))
            }
            (Some(_), None, Some(_)) => {
                return Err((key("density"), K::BothGiven("material".into(), "density".into())))
            }
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
                // A material with a failure of its own: reported there, nothing more here.
                let Ok(g) = material_shear.get(j).copied().unwrap_or(Err(())) else { return Ok(None) };
                Some((e, d, g, keys, format!("material `{name}` (materials[{j}])")))
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
                Some((e, d, g, keys, format!("this section ({prefix})")))
            }
        })
    })();
    let material = match material {
        Ok(m) => m,
        Err(failure) => {
            failures.push(failure);
            None
        }
    };
    let (Some([outer, inner, outer_right, inner_right]), Some((youngs_modulus, density, shear, section_keys, named))) =
        (diameters, material)
    else {
        return Err(failures);
    };
    let beam = match s.beam.unwrap_or_default() {
        BeamKind::Rayleigh => {
            if s.shear_coefficient.is_some() {
                failures.push((key("shear_coefficient"), K::TimoshenkoOnly("shear_coefficient".into())));
            }
            Beam::Rayleigh
        }
        BeamKind::Timoshenko => {
            if shear.is_none() {
                failures.push((key("beam"), K::NoShearModulus { material: named }));
            }
            // (its sign checked above)
            Beam::Timoshenko { shear_modulus: shear.unwrap_or(f64::NAN), shear_coefficient: s.shear_coefficient }
        }
    };
    if !failures.is_empty() {
        return Err(failures);
    }
    let section = Section {
        length,
        outer_diameter: outer,
        inner_diameter: inner,
        elements: s.elements as usize,
        youngs_modulus: positive(&key("youngs_modulus"), youngs_modulus).map_err(|f| vec![f])?,
        density: positive(&key("density"), density).map_err(|f| vec![f])?,
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

/// `[[bearings]]`, `[[seals]]` and `[[rings]]`. The coefficient checks of the bearings
/// and seals (a negative direct stiffness, a damping matrix that is not positive
/// semi-definite, table speeds that do not increase, an array of another length than
/// `speeds`) are all reported at once ([`K::Several`]).
pub(super) fn supports(f: &ProblemFile, shaft: &Shaft) -> Result<(Vec<Bearing>, Vec<RingSupport>), Failure> {
    let mut bearings = Vec::with_capacity(f.bearings.len() + f.seals.len());
    let mut failures: Vec<Failure> = Vec::new();
    let tables = [("bearings", &f.bearings, SupportKind::Bearing), ("seals", &f.seals, SupportKind::Seal)];
    let stiffness_scale = shaft.stiffness_scale();
    let scales = Scales { stiffness: stiffness_scale, damping: (stiffness_scale * shaft.mass_scale()).sqrt() };
    for (table, list, kind) in tables {
        for (i, b) in list.iter().enumerate() {
            let key = format!("{table}[{i}]");
            let node = place(&key, b.node, b.position, shaft, Placed::Support)?;
            let mass = non_negative(&format!("{key}.mass"), b.mass)?;
            match coefficients(&key, b, scales) {
                Ok((speeds, coefficients)) => bearings.push(Bearing { kind, node, speeds, coefficients, mass }),
                Err(mut found) => failures.append(&mut found),
            }
        }
    }
    if let Some(first) = several(failures) {
        return Err(first);
    }
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

/// The failures found, as one: the first with the others attached ([`K::Several`]). A
/// failure found twice (one key feeding two coefficients, as `stiffness` feeds kxx and
/// kyy) is reported once.
pub(super) fn several(failures: Vec<Failure>) -> Option<Failure> {
    let mut failures = failures.into_iter().fold(Vec::new(), |mut seen: Vec<Failure>, f| {
        // By key and message: a NaN value makes the kinds themselves unequal.
        if !seen.iter().any(|(k, e)| *k == f.0 && e.to_string() == f.1.to_string()) {
            seen.push(f);
        }
        seen
    });
    if failures.is_empty() {
        return None;
    }
    let (key, first) = failures.remove(0);
    if failures.is_empty() {
        return Some((key, first));
    }
    let more = failures
        .into_iter()
        .map(|(key, kind)| ProblemError { file: String::new(), location: Location::Unknown, key, kind })
        .collect();
    Some((key, K::Several { first: Box::new(first), more }))
}

/// Smallest eigenvalue of the symmetric part of a 2×2 matrix.
pub(crate) fn smallest_symmetric_eigenvalue(c: [[f64; 2]; 2]) -> f64 {
    let (a, d, b) = (c[0][0], c[1][1], 0.5 * (c[0][1] + c[1][0]));
    let mean = 0.5 * (a + d);
    mean - (0.25 * (a - d) * (a - d) + b * b).sqrt()
}

/// Relative round-off allowed in the damping check: the smallest eigenvalue of the
/// symmetric part of a 2×2 matrix is computed to ~1e-15 of its largest entry; a matrix
/// built semi-definite (e.g. c·[[1, 1], [1, 1]]) must not be refused for that.
pub(crate) const DAMPING_ROUND_OFF: f64 = 1e-12;

/// A support's table speeds (rad/s) and its eight coefficients ([`COEFFICIENT_NAMES`]).
type Coefficients = (Vec<f64>, [Vec<f64>; 8]);

/// The shaft's own scales the supports' coefficients are judged against: its stiffness
/// scale K_s (N/m) and damping scale √(K_s·M_s) (N·s/m).
#[derive(Clone, Copy)]
struct Scales {
    stiffness: f64,
    damping: f64,
}

/// The speeds and the eight coefficients of a bearing or seal at `key`, or every failure
/// of its coefficient checks (each coefficient within [`MAX_SUPPORT_STIFFNESS_RATIO`] or
/// [`MAX_SUPPORT_DAMPING_RATIO`] of the shaft's `scales` among them).
fn coefficients(key: &str, b: &BearingFile, scales: Scales) -> Result<Coefficients, Vec<Failure>> {
    let k = |name: &str| format!("{key}.{name}");
    let one = |x: f64| CoefficientFile::Constant(x);
    let mut failures = Vec::new();
    // The isotropic keys, or the direct coefficients; never both.
    let direct = |iso: Option<f64>, iso_name: &str, xx: &Option<CoefficientFile>, yy: &Option<CoefficientFile>| {
        let (xx_name, yy_name) = if iso_name == "stiffness" { ("kxx", "kyy") } else { ("cxx", "cyy") };
        match (iso, xx, yy) {
            (Some(_), Some(_), _) => Err((k(xx_name), K::BothGiven(iso_name.into(), xx_name.into()))),
            (Some(_), None, Some(_)) => Err((k(yy_name), K::BothGiven(iso_name.into(), yy_name.into()))),
            (Some(v), None, None) => Ok(Some((one(v), one(v)))),
            (None, Some(x), y) => Ok(Some((x.clone(), y.clone().unwrap_or_else(|| x.clone())))),
            (None, None, Some(_)) => Err((k(yy_name), K::NeitherGiven(xx_name.into(), iso_name.into()))),
            (None, None, None) => Ok(None),
        }
    };
    let stiffness = direct(b.stiffness, "stiffness", &b.kxx, &b.kyy).map_err(|f| vec![f])?;
    let Some((kxx, kyy)) = stiffness else {
        return Err(vec![(key.into(), K::NeitherGiven("stiffness".into(), "kxx".into()))]);
    };
    let (cxx, cyy) = direct(b.damping, "damping", &b.cxx, &b.cyy).map_err(|f| vec![f])?.unwrap_or((one(0.0), one(0.0)));
    let zero = || one(0.0);
    let given = [
        kxx,
        b.kxy.clone().unwrap_or_else(zero),
        b.kyx.clone().unwrap_or_else(zero),
        kyy,
        cxx,
        b.cxy.clone().unwrap_or_else(zero),
        b.cyx.clone().unwrap_or_else(zero),
        cyy,
    ];
    // The key each coefficient came from: an isotropic key stands for both directions.
    let source = |i: usize| -> String {
        match i {
            0 | 3 if b.stiffness.is_some() => k("stiffness"),
            4 | 7 if b.damping.is_some() => k("damping"),
            3 if b.kyy.is_none() => k("kxx"),
            7 if b.cyy.is_none() && b.cxx.is_some() => k("cxx"),
            _ => k(COEFFICIENT_NAMES[i]),
        }
    };
    let speeds = b.speeds.clone().unwrap_or_default();
    // Before any entry is checked: a table's length bounds what it costs.
    if speeds.len() > MAX_TABLE_POINTS {
        return Err(vec![(k("speeds"), K::TableTooLong { points: speeds.len(), limit: MAX_TABLE_POINTS })]);
    }
    for (j, &w) in speeds.iter().enumerate() {
        if let Err(e) = crate::analysis::limits::speed(w) {
            failures.push((k("speeds"), K::from(&e)));
        } else if j > 0 && w <= speeds[j - 1] {
            failures.push((k("speeds"), K::TableSpeedsNotIncreasing { index: j, speed: w, previous: speeds[j - 1] }));
        }
    }
    let mut values: Vec<Vec<f64>> = Vec::with_capacity(8);
    for (i, c) in given.iter().enumerate() {
        let v = c.values();
        let table = matches!(c, CoefficientFile::Table(_));
        if table && v.len() != speeds.len() {
            // Reported once per key (kyy defaulting to kxx shares kxx's array).
            let entry = (source(i), K::TableLength { values: v.len(), speeds: speeds.len() });
            if !failures.contains(&entry) {
                failures.push(entry);
            }
        }
        if let Some(x) = v.iter().find(|x| !x.is_finite()) {
            let entry = (source(i), K::NotFinite(*x));
            if !failures.contains(&entry) {
                failures.push(entry);
            }
        }
        values.push(v);
    }
    if !failures.is_empty() {
        return Err(failures);
    }
    // Per table point (or once for constants): direct stiffnesses ≥ 0, damping ⪰ 0.
    let points = values.iter().map(Vec::len).max().unwrap_or(1);
    let at = |i: usize, j: usize| if values[i].len() == 1 { values[i][0] } else { values[i][j] };
    let speed_of = |j: usize| (points > 1).then(|| speeds[j]);
    for i in [0, 3] {
        if let Some((j, &value)) = values[i].iter().enumerate().find(|(_, v)| **v < 0.0) {
            let entry = (source(i), K::NegativeStiffness { value, speed: speed_of(j) });
            if !failures.contains(&entry) {
                failures.push(entry);
            }
        }
    }
    for j in 0..points {
        let c = [[at(4, j), at(5, j)], [at(6, j), at(7, j)]];
        let eigenvalue = smallest_symmetric_eigenvalue(c);
        let scale = c.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
        if eigenvalue < -DAMPING_ROUND_OFF * scale {
            let culprit =
                if b.damping.is_some() || (b.cxy.is_none() && b.cyx.is_none()) { source(4) } else { k("cxy") };
            failures.push((culprit, K::DampingNotSemiDefinite { c, eigenvalue, speed: speed_of(j) }));
            break;
        }
    }
    // Each coefficient within its ratio of the shaft's own scale (the first table point
    // beyond it), named as the key it came from.
    for (i, v) in values.iter().enumerate() {
        let (scale, limit) = if i < 4 {
            (scales.stiffness, MAX_SUPPORT_STIFFNESS_RATIO)
        } else {
            (scales.damping, MAX_SUPPORT_DAMPING_RATIO)
        };
        if let Some((j, &value)) = v.iter().enumerate().find(|(_, x)| x.abs() > limit * scale) {
            let key = source(i);
            let named = key.rsplit('.').next().unwrap_or_default();
            let coefficient = ["stiffness", "damping"]
                .into_iter()
                .chain(COEFFICIENT_NAMES)
                .find(|n| *n == named)
                .unwrap_or(COEFFICIENT_NAMES[i]);
            let speed = (v.len() > 1).then(|| speeds[j]);
            let entry = (key, K::OutOfScale { coefficient, value, scale, speed });
            if !failures.contains(&entry) {
                failures.push(entry);
            }
        }
    }
    if !failures.is_empty() {
        return Err(failures);
    }
    let mut out: [Vec<f64>; 8] = Default::default();
    for (o, v) in out.iter_mut().zip(values) {
        *o = v;
    }
    Ok((speeds, out))
}

/// One support per node, and at least two supports with stiffness: the open-circuit
/// stiffness K at zero load is positive definite exactly when the supports hold both
/// rigid-body motions u = a + b·x of the free shaft (whose bending energy vanishes on
/// them and only on them), i.e. when two supports with positive stiffness sit at
/// distinct nodes. A ring always has stiffness to the ground on open circuit
/// (k_eq in series with k_eq1 + k_eq2); a bearing when k > 0.
pub(super) fn supports_check(f: &ProblemFile, bearings: &[Bearing], rings: &[RingSupport]) -> Result<(), Failure> {
    let shorthand = f.ring.is_some();
    let ring_key = |i: usize| -> String {
        if shorthand {
            "ring".into()
        } else {
            format!("rings[{i}]")
        }
    };
    // At most one ring per node; bearings and seals add to whatever is there.
    let mut seen = std::collections::HashMap::with_capacity(rings.len());
    for (i, r) in rings.iter().enumerate() {
        if let Some(&first) = seen.get(&r.node) {
            let given = &f.rings[i].node;
            let key = format!("{}.{}", ring_key(i), if given.is_some() { "node" } else { "position" });
            return Err((key, K::SupportsShareNode { node: r.node, first: ring_key(first) }));
        }
        seen.insert(r.node, i);
    }
    // A bearing or seal holds the shaft when both direct stiffnesses are positive at every
    // table speed.
    let holds = |b: &Bearing| b.coefficients[0].iter().chain(&b.coefficients[3]).all(|&k| k > 0.0);
    let mut held: Vec<usize> =
        bearings.iter().filter(|b| holds(b)).map(|b| b.node).chain(rings.iter().map(|r| r.node)).collect();
    held.sort_unstable();
    held.dedup();
    let stiff = held.len();
    if stiff < 2 {
        // Blame the first bearing without stiffness (giving it stiffness is the fix);
        // with none, the one support there is, or the shaft when there is none.
        let key_of = |i: usize| {
            let b = &bearings[i];
            let (table, j) = if i < f.bearings.len() { ("bearings", i) } else { ("seals", i - f.bearings.len()) };
            let file = if table == "bearings" { &f.bearings[j] } else { &f.seals[j] };
            let name = if file.stiffness.is_some() {
                "stiffness"
            } else if b.coefficients[0].iter().any(|&k| k <= 0.0) {
                "kxx"
            } else {
                "kyy"
            };
            format!("{table}[{j}].{name}")
        };
        let key = match bearings.iter().position(|b| !holds(b)) {
            Some(i) if !shorthand => key_of(i),
            _ if bearings.is_empty() && rings.is_empty() => "sections".to_string(),
            _ if !bearings.is_empty() => {
                if f.bearings.is_empty() {
                    "seals[0]".into()
                } else {
                    "bearings[0]".into()
                }
            }
            _ => ring_key(0),
        };
        return Err((key, K::RigidBody { supports: stiff }));
    }
    Ok(())
}
