//! ROSS's saved rotor as data: the tables of `Rotor.save` (TOML or JSON), read into typed
//! elements. Only the form is checked here; what rotorshunt can represent is decided in
//! [`super::map`]. The format is described in `docs/ross-format.md`.

use super::error::{Format, RossErrorKind};
use serde::Deserialize;

/// A saved rotor: its elements by class, each with its table name.
#[derive(Debug, Clone, Default)]
pub struct RossFile {
    /// `ross_version`, when present.
    pub ross_version: Option<String>,
    /// `ShaftElement` tables, in table-name order.
    pub shafts: Vec<Shaft>,
    /// The rotor's `DiskElement_<tag>` tables, in table-name order.
    pub disks: Vec<Disk>,
    /// The rotor's `BearingElement_<tag>` tables, in table-name order.
    pub bearings: Vec<Bearing>,
    /// Tables of other classes: (class, tag, n if the table has one).
    pub others: Vec<(String, String, Option<i64>)>,
}

/// A `ShaftElement` (`shaft_element.py`, `ShaftElement.save`). Lengths in m.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct Shaft {
    /// Element length L (m).
    pub L: f64,
    /// Inner diameter at the left node (m).
    pub idl: f64,
    /// Outer diameter at the left node (m).
    pub odl: f64,
    /// Inner diameter at the right node (m).
    pub idr: f64,
    /// Outer diameter at the right node (m).
    pub odr: f64,
    /// The element's material.
    pub material: Material,
    /// Element number, also its left node.
    pub n: i64,
    /// Static axial force (N).
    pub axial_force: f64,
    /// Static torque (N·m).
    pub torque: f64,
    /// Timoshenko shear in the element (ROSS's default `true`); the importer refuses it.
    pub shear_effects: bool,
    /// Rotary inertia in M.
    pub rotary_inertia: bool,
    /// Gyroscopic matrix G in the element (default `true`); the importer refuses `false`.
    pub gyroscopic: bool,
    /// Shear coefficient formula (used only with shear effects).
    #[serde(default)]
    pub shear_method_calc: Option<String>,
    /// The element's name.
    pub tag: String,
    /// Proportional damping coefficient on M (1/s).
    pub alpha: f64,
    /// Proportional damping coefficient on K (s).
    pub beta: f64,
}

/// A shaft element's `material` sub-table (`materials.py`).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct Material {
    /// ROSS's material name (`material.name`); elements may give one name different values.
    pub name: String,
    /// Density ρ (kg/m³).
    pub rho: f64,
    /// Young's modulus E (Pa).
    pub E: f64,
    /// Shear modulus (Pa): torsion and Timoshenko shear only.
    pub G_s: f64,
    /// ROSS's plot colour of the material; read, not used.
    #[serde(default)]
    pub color: Option<String>,
}

/// A `DiskElement` (`disk_element.py`).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(non_snake_case)]
pub struct Disk {
    /// Node n of the disk (0-based, ROSS's numbering).
    pub n: i64,
    /// Mass (kg).
    pub m: f64,
    /// Diametral inertia J_d (kg·m²).
    pub Id: f64,
    /// Polar inertia J_p (kg·m²).
    pub Ip: f64,
    /// The element's name.
    pub tag: String,
    /// ROSS's drawing scale of the disk (−); plotting only, not used.
    #[serde(default)]
    pub scale_factor: Option<f64>,
    /// ROSS's plot colour of the disk; plotting only, not used.
    #[serde(default)]
    pub color: Option<String>,
}

/// One coefficient of a bearing: ROSS writes an array (one value per tabulated
/// frequency); a single number is read as a one-value array.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(untagged)]
pub enum Coefficient {
    /// A single value.
    One(f64),
    /// Values per tabulated frequency.
    Many(Vec<f64>),
}

impl Coefficient {
    /// The values.
    pub fn values(&self) -> &[f64] {
        match self {
            Coefficient::One(v) => std::slice::from_ref(v),
            Coefficient::Many(v) => v,
        }
    }
}

/// A `BearingElement` (`bearing_seal_element.py`, `BearingElement.save`). Stiffness in
/// N/m, damping in N·s/m, mass in kg, frequencies in rad/s.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Bearing {
    /// Node n of the bearing (0-based); it connects n to the ground unless `n_link` is set.
    pub n: i64,
    /// The node the bearing connects to instead of the ground.
    #[serde(default)]
    pub n_link: Option<i64>,
    /// Direct stiffness k_xx (N/m): one value, or one per `frequency` entry (spin speed).
    pub kxx: Coefficient,
    /// Cross-coupled stiffness k_xy (N/m), like `kxx`; the importer refuses it non-zero.
    pub kxy: Coefficient,
    /// Cross-coupled stiffness k_yx (N/m), like `kxx`; the importer refuses it non-zero.
    pub kyx: Coefficient,
    /// Direct stiffness k_yy (N/m), like `kxx`; the importer needs it equal to `kxx`.
    pub kyy: Coefficient,
    /// Axial stiffness k_zz (N/m), like `kxx`; `None` when absent. Dropped by the importer
    /// (axial motion is not modelled).
    #[serde(default)]
    pub kzz: Option<Coefficient>,
    /// Direct damping c_xx (N·s/m): one value, or one per `frequency` entry (spin speed).
    pub cxx: Coefficient,
    /// Cross-coupled damping c_xy (N·s/m), like `cxx`; the importer refuses it non-zero.
    pub cxy: Coefficient,
    /// Cross-coupled damping c_yx (N·s/m), like `cxx`; the importer refuses it non-zero.
    pub cyx: Coefficient,
    /// Direct damping c_yy (N·s/m), like `cxx`; the importer needs it equal to `cxx`.
    pub cyy: Coefficient,
    /// Axial damping c_zz (N·s/m), like `cxx`; `None` when absent. Dropped by the importer
    /// (axial motion is not modelled).
    #[serde(default)]
    pub czz: Option<Coefficient>,
    /// Direct added mass m_xx (kg) on the node: one value, or one per `frequency` entry.
    pub mxx: Coefficient,
    /// Cross-coupled added mass m_xy (kg), like `mxx`; the importer refuses it non-zero.
    pub mxy: Coefficient,
    /// Cross-coupled added mass m_yx (kg), like `mxx`; the importer refuses it non-zero.
    pub myx: Coefficient,
    /// Direct added mass m_yy (kg), like `mxx`; the importer needs it equal to `mxx`.
    pub myy: Coefficient,
    /// Axial added mass m_zz (kg), like `mxx`; `None` when absent. Dropped by the importer
    /// (axial motion is not modelled).
    #[serde(default)]
    pub mzz: Option<Coefficient>,
    /// Frequencies (rad/s) of the tabulated coefficients; absent or null: constant.
    #[serde(default)]
    pub frequency: Option<Coefficient>,
    /// The element's name.
    pub tag: String,
    /// ROSS's drawing scale of the bearing (−); plotting only, not used.
    #[serde(default)]
    pub scale_factor: Option<f64>,
    /// ROSS's plot colour of the bearing; plotting only, not used.
    #[serde(default)]
    pub color: Option<String>,
}

/// Top-level keys that are not elements.
const NOT_ELEMENTS: [&str; 3] = ["_note", "ross_version", "parameters"];

/// The format of a file: by its extension (as ROSS's `Rotor.load` decides), else by its
/// first non-blank character (`{` for JSON).
pub fn format_of(path: &std::path::Path, text: &str) -> Format {
    match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
        Some("json") => Format::Json,
        Some("toml") => Format::Toml,
        _ if text.trim_start().starts_with('{') => Format::Json,
        _ => Format::Toml,
    }
}

/// Parse a saved rotor's text.
pub fn parse(text: &str, format: Format) -> Result<RossFile, RossErrorKind> {
    let doc: serde_json::Value = match format {
        Format::Toml => toml::from_str(text).map_err(|e| RossErrorKind::Syntax {
            format,
            line: e.span().map(|s| crate::problem::source::line_of(text, s.start)),
            message: e.message().trim().to_string(),
        })?,
        Format::Json => serde_json::from_str(text).map_err(|e| {
            // serde_json ends its message with the position, which the error carries.
            let full = e.to_string();
            let position = format!(" at line {} column {}", e.line(), e.column());
            let message = full.strip_suffix(&position).unwrap_or(&full).to_string();
            RossErrorKind::Syntax { format, line: Some(e.line()), message }
        })?,
    };
    let serde_json::Value::Object(map) = doc else {
        return Err(RossErrorKind::Schema {
            key: String::new(),
            message: "the file is not a table of elements".into(),
        });
    };
    let mut file = RossFile::default();
    for (name, value) in map {
        if NOT_ELEMENTS.contains(&name.as_str()) {
            if name == "ross_version" {
                file.ross_version = value.as_str().map(String::from);
            }
            continue;
        }
        let key = format!("[\"{name}\"]");
        let Some((class, tag)) = name.split_once('_') else {
            return Err(RossErrorKind::Schema {
                key,
                message: "not an element table: ROSS names each element's table `<Class>_<tag>`".into(),
            });
        };
        if !value.is_object() {
            return Err(RossErrorKind::Schema { key, message: "an element must be a table".into() });
        }
        match class {
            "ShaftElement" => file.shafts.push(element(&key, value)?),
            "DiskElement" => file.disks.push(element(&key, value)?),
            "BearingElement" => file.bearings.push(element(&key, value)?),
            _ => {
                let n = value.get("n").and_then(serde_json::Value::as_i64);
                file.others.push((class.to_string(), tag.to_string(), n));
            }
        }
    }
    Ok(file)
}

/// One element table, its errors located by key path below `key`.
fn element<T: serde::de::DeserializeOwned>(key: &str, value: serde_json::Value) -> Result<T, RossErrorKind> {
    serde_path_to_error::deserialize(value).map_err(|e| {
        let path = e.path().to_string();
        let message = e.inner().to_string();
        // serde names a missing or unknown key in its message; put it in the path.
        let field = quoted(&message, "missing field `").or_else(|| quoted(&message, "unknown field `"));
        let mut full = if path == "." { key.to_string() } else { format!("{key}.{path}") };
        if let Some(f) = field {
            if !full.ends_with(&f) {
                full = format!("{full}.{f}");
            }
        }
        let message = if message.starts_with("unknown field") {
            format!("{message} (this importer reads the format of ROSS 2.3.0)")
        } else {
            message
        };
        RossErrorKind::Schema { key: full, message }
    })
}

fn quoted(message: &str, prefix: &str) -> Option<String> {
    let rest = &message[message.find(prefix)? + prefix.len()..];
    Some(rest[..rest.find('`')?].to_string())
}
