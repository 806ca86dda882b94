//! The imported rotor as problem-file text (general form, `problems/README.md`), each
//! line commented with its unit and the ROSS element it came from.

use super::map::{BearingOut, Imported};
use crate::model::{SupportKind, COEFFICIENT_NAMES};

/// Column at which a line's comment starts (as in `problems/*.toml`).
const COMMENT_COLUMN: usize = 30;

/// A float as TOML: Rust's shortest round-trip form, which TOML reads back exactly.
fn num(v: f64) -> String {
    format!("{v:?}")
}

/// A TOML basic string.
fn string(s: &str) -> String {
    toml::Value::String(s.to_string()).to_string()
}

/// Text for a comment: one line, no control characters.
fn plain(s: &str) -> String {
    s.chars().map(|c| if c.is_control() { ' ' } else { c }).collect()
}

/// `key = value` padded to the comment column, then `# comment`.
fn line(out: &mut String, assignment: &str, comment: &str) {
    if comment.is_empty() {
        out.push_str(assignment);
        out.push('\n');
        return;
    }
    let pad = COMMENT_COLUMN.saturating_sub(assignment.chars().count()).max(1);
    out.push_str(&format!("{assignment}{}# {}\n", " ".repeat(pad), plain(comment)));
}

/// The diameters, material and beam theory of a section or a layer.
fn tube_lines(
    out: &mut String,
    right: Option<(f64, f64)>,
    outer: f64,
    inner: f64,
    material: &str,
    timoshenko: Option<Option<f64>>,
) {
    match right {
        None => {
            line(out, &format!("outer_diameter = {}", num(outer)), "m, ROSS odl = odr");
            line(out, &format!("inner_diameter = {}", num(inner)), "m, ROSS idl = idr");
        }
        Some((outer_right, inner_right)) => {
            line(out, &format!("outer_diameter = {}", num(outer)), "m, ROSS odl (tapered)");
            line(out, &format!("inner_diameter = {}", num(inner)), "m, ROSS idl");
            line(out, &format!("outer_diameter_right = {}", num(outer_right)), "m, ROSS odr");
            line(out, &format!("inner_diameter_right = {}", num(inner_right)), "m, ROSS idr");
        }
    }
    line(out, &format!("material = {}", string(material)), "");
    if let Some(kappa) = timoshenko {
        line(out, "beam = \"timoshenko\"", "ROSS shear_effects = true (rotary_inertia, gyroscopic = true)");
        match kappa {
            None => out.push_str("# shear coefficient: Cowper's, as ROSS's shear_method_calc = \"cowper\"\n"),
            Some(k) => line(
                out,
                &format!("shear_coefficient = {}", num(k)),
                "κ (−), as ROSS computes it for shear_method_calc = \"hutchinson\"",
            ),
        }
    }
}

/// The problem file of an imported rotor. `source` is the ROSS file as given.
pub fn render(r: &Imported, source: &str) -> String {
    let version = r.ross_version.as_deref().unwrap_or("(version not recorded)");
    let stem = std::path::Path::new(source).file_stem().map(|s| s.to_string_lossy().into_owned());
    let stem = stem.unwrap_or_else(|| source.to_string());
    let mut out = String::new();
    out.push_str(&format!(
        "# Imported by `rotorshunt import-ross` ({}) from {}, a rotor saved by ROSS {} (Rotor.save).\n",
        crate::problem::provenance::TOOL,
        plain(source),
        plain(version)
    ));
    out.push_str(
        "# The mapping is in docs/ross-format.md. Units: SI, rad/s. ROSS's axial and torsional\n\
         # coefficients (kzz, czz, mzz; G_s of Rayleigh elements) act on motion rotorshunt's\n\
         # lateral model does not have, and are left out. Tabulated bearing and seal\n\
         # coefficients are kept as tables over `speeds` (ROSS's frequency), evaluated at\n\
         # each analysis's speed as ROSS's run_modal does. There is no vibration ring: add\n\
         # [[rings]] by editing.\n",
    );
    out.push_str("version = 1\n");
    out.push_str(&format!("title = {}\n", string(&format!("{stem} (imported from ROSS)"))));
    out.push_str(&format!(
        "source = {}\n",
        string(&format!("ROSS {version} file {source}, by rotorshunt import-ross"))
    ));
    let speed_note = match r.speed {
        Some(_) => "Ω (rad/s): --speed of import-ross",
        None => "Ω (rad/s): not in ROSS's file; 0 unless import-ross --speed",
    };
    line(&mut out, &format!("speed = {}", num(r.speed.unwrap_or(0.0))), speed_note);
    for m in &r.materials {
        out.push('\n');
        let from = if m.name == m.ross_name {
            format!("ROSS material {}", m.ross_name)
        } else {
            format!("ROSS material {} with other values than the first of that name", m.ross_name)
        };
        line(&mut out, "[[materials]]", &from);
        line(&mut out, &format!("name = {}", string(&m.name)), "");
        line(&mut out, &format!("youngs_modulus = {}", num(m.youngs_modulus)), "E (Pa), ROSS material.E");
        line(&mut out, &format!("density = {}", num(m.density)), "ρ (kg/m³), ROSS material.rho");
        if m.timoshenko {
            line(&mut out, &format!("shear_modulus = {}", num(m.shear_modulus)), "G (Pa), ROSS material.G_s");
        }
    }
    for s in &r.sections {
        out.push('\n');
        let last_n = s.first_n + s.elements as i64 - 1;
        let from = if s.elements == 1 {
            format!("ROSS ShaftElement \"{}\" (n = {})", s.tags.0, s.first_n)
        } else {
            format!("ROSS ShaftElements n = {}…{} (\"{}\" … \"{}\")", s.first_n, last_n, s.tags.0, s.tags.1)
        };
        line(&mut out, "[[sections]]", &from);
        line(
            &mut out,
            &format!("length = {}", num(s.length)),
            &format!("m: Σ L of {} element(s) of L = {} m", s.elements, num(s.element_length)),
        );
        tube_lines(&mut out, s.right, s.outer_diameter, s.inner_diameter, &s.material, s.timoshenko);
        let kind = if s.timoshenko.is_some() { "Timoshenko" } else { "Rayleigh" };
        let note = match s.timoshenko {
            None => "Rayleigh elements (ROSS: shear_effects = false, rotary_inertia and gyroscopic = true)".to_string(),
            Some(_) => format!("{kind} elements"),
        };
        line(&mut out, &format!("elements = {}", s.elements), &note);
        for layer in &s.layers {
            let from = if layer.tags.0 == layer.tags.1 {
                format!("ROSS ShaftElement \"{}\", a concentric layer", layer.tags.0)
            } else {
                format!("ROSS ShaftElements \"{}\" … \"{}\", concentric layers", layer.tags.0, layer.tags.1)
            };
            line(&mut out, "[[sections.layers]]", &from);
            tube_lines(
                &mut out,
                layer.right,
                layer.outer_diameter,
                layer.inner_diameter,
                &layer.material,
                layer.timoshenko,
            );
        }
    }
    for d in &r.disks {
        out.push('\n');
        if d.class == "PointMass" {
            line(&mut out, "[[disks]]", &format!("ROSS PointMass \"{}\": a mass on the shaft, no inertia", d.tag));
            line(&mut out, &format!("node = {}", d.node), "ROSS n");
            line(&mut out, &format!("mass = {}", num(d.mass)), "m (kg), ROSS mx = my");
            line(&mut out, "polar_inertia = 0.0", "J_p (kg·m²): a point mass has none");
            line(&mut out, "diametral_inertia = 0.0", "J_d (kg·m²): a point mass has none");
            continue;
        }
        line(&mut out, "[[disks]]", &format!("ROSS DiskElement \"{}\"", d.tag));
        line(&mut out, &format!("node = {}", d.node), "ROSS n");
        line(&mut out, &format!("mass = {}", num(d.mass)), "m (kg), ROSS m");
        line(&mut out, &format!("polar_inertia = {}", num(d.polar_inertia)), "J_p (kg·m²), ROSS Ip");
        line(&mut out, &format!("diametral_inertia = {}", num(d.diametral_inertia)), "J_d (kg·m²), ROSS Id");
    }
    for kind in [SupportKind::Bearing, SupportKind::Seal] {
        for b in r.bearings.iter().filter(|b| b.kind == kind) {
            out.push('\n');
            support_lines(&mut out, b);
        }
    }
    out.push('\n');
    line(&mut out, "[load]", "ROSS has no periodic axial load: set α and the load here");
    line(&mut out, "alpha = 0.0", "static load coefficient α of P(t) = P_cr(α + β cos φt)");
    out
}

/// A coefficient's value(s): a number, or an array over the table's speeds.
fn values(v: &[f64]) -> String {
    if v.len() == 1 {
        num(v[0])
    } else {
        format!("[{}]", v.iter().map(|x| num(*x)).collect::<Vec<_>>().join(", "))
    }
}

/// One `[[bearings]]` or `[[seals]]` entry.
fn support_lines(out: &mut String, b: &BearingOut) {
    let table = match b.kind {
        SupportKind::Bearing => "[[bearings]]",
        SupportKind::Seal => "[[seals]]",
    };
    line(out, table, &format!("ROSS {} \"{}\"", b.class, b.tag));
    line(out, &format!("node = {}", b.node), "ROSS n");
    if b.isotropic() {
        let c = &b.coefficients;
        line(out, &format!("stiffness = {}", num(c[0][0])), "k (N/m), ROSS kxx = kyy");
        line(out, &format!("damping = {}", num(c[4][0])), "c (N·s/m), ROSS cxx = cyy");
    } else {
        if !b.speeds.is_empty() {
            line(
                out,
                &format!("speeds = {}", values(&b.speeds)),
                &format!("rad/s, ROSS frequency: {} points, interpolated at the speed as ROSS does", b.speeds.len()),
            );
        }
        for (name, v) in COEFFICIENT_NAMES.iter().zip(&b.coefficients) {
            let unit = if name.starts_with('k') { "N/m" } else { "N·s/m" };
            let note = if v.len() == 1 && !b.speeds.is_empty() {
                format!("{unit}, ROSS {name}, the same at every frequency")
            } else {
                format!("{unit}, ROSS {name}")
            };
            line(out, &format!("{name} = {}", values(v)), &note);
        }
    }
    line(out, &format!("mass = {}", num(b.mass)), "kg, ROSS mxx = myy, added to the node's mass as in ROSS");
}
