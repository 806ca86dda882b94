//! ROSS's saved rotor as data: the tables of `Rotor.save` (TOML or JSON), read into typed
//! elements. Only the form is checked here; what rotorshunt can represent is decided in
//! [`super::map`]. The format is described in `docs/ross-format.md`.

use super::error::{Format, Refusal, RossErrorKind};
use serde::Deserialize;
use std::collections::{HashMap, HashSet};

/// A saved rotor: its elements by class, each with its table name.
#[derive(Debug, Clone, Default)]
pub struct RossFile {
    /// `ross_version`, when present.
    pub ross_version: Option<String>,
    /// `ShaftElement` tables, in table-name order.
    pub shafts: Vec<Shaft>,
    /// The rotor's `DiskElement_<tag>` tables, in table-name order.
    pub disks: Vec<Disk>,
    /// The rotor's bearings and seals (`BearingElement_<tag>`, `SealElement_<tag>` and
    /// the bearing classes whose saved coefficients are ROSS's model, [`SupportClass`]),
    /// in table-name order.
    pub bearings: Vec<Bearing>,
    /// The rotor's `PointMass_<tag>` tables, in table-name order.
    pub point_masses: Vec<PointMass>,
    /// Tables of other classes, or of a class whose saved form carries what rotorshunt
    /// cannot represent (a magnetic bearing's controller).
    pub others: Vec<Other>,
}

/// A table the importer does not map to an element.
#[derive(Debug, Clone, PartialEq)]
pub struct Other {
    /// The class as the table name gives it (`<Class>_<tag>`).
    pub class: String,
    /// The tag.
    pub tag: String,
    /// `n`, if the table has one.
    pub n: Option<i64>,
    /// Line of the table in the file, when found.
    pub line: Option<usize>,
    /// A magnetic bearing: ROSS saves a `MagneticBearingElement` under `BearingElement`
    /// with its controller's parameters (`kp_pid`, `g0`, …).
    pub magnetic: bool,
}

/// The ROSS class of a bearing or seal table. Each saves the coefficients ROSS's
/// `run_modal` uses (`BearingElement.save`); the classes that compute them from a
/// geometry (ball and roller bearings, the short cylindrical bearing) also save that
/// geometry, which the importer reads past (`SupportClass::parameters`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SupportClass {
    /// `BearingElement`.
    #[default]
    Bearing,
    /// `SealElement`: imported as `[[seals]]`.
    Seal,
    /// `BallBearingElement`: constant coefficients from the balls' geometry.
    BallBearing,
    /// `RollerBearingElement`: constant coefficients from the rollers' geometry.
    RollerBearing,
    /// `CylindricalBearing`: coefficients tabulated over its `speed` (ROSS's frequency).
    Cylindrical,
}

impl SupportClass {
    /// The class name ROSS writes.
    pub fn name(self) -> &'static str {
        match self {
            SupportClass::Bearing => "BearingElement",
            SupportClass::Seal => "SealElement",
            SupportClass::BallBearing => "BallBearingElement",
            SupportClass::RollerBearing => "RollerBearingElement",
            SupportClass::Cylindrical => "CylindricalBearing",
        }
    }

    fn of(class: &str) -> Option<SupportClass> {
        [
            SupportClass::Bearing,
            SupportClass::Seal,
            SupportClass::BallBearing,
            SupportClass::RollerBearing,
            SupportClass::Cylindrical,
        ]
        .into_iter()
        .find(|c| c.name() == class)
    }

    /// The keys of the class's own geometry, saved beside the coefficients it gave
    /// (`bearing_seal_element.py`, each class's `__init__` and `_save_attrs`): read past,
    /// as the coefficients are what ROSS's model uses.
    fn parameters(self) -> &'static [&'static str] {
        match self {
            SupportClass::Bearing | SupportClass::Seal => &[],
            SupportClass::BallBearing => &["n_balls", "d_balls", "fs", "alpha"],
            SupportClass::RollerBearing => &["n_rollers", "l_rollers", "fs", "alpha"],
            SupportClass::Cylindrical => &[
                "weight",
                "bearing_length",
                "journal_diameter",
                "radial_clearance",
                "oil_viscosity",
                "eccentricity",
                "attitude_angle",
                "sommerfeld",
                "modified_sommerfeld",
            ],
        }
    }
}

/// The parameters of ROSS's `MagneticBearingElement` (its controller and actuator), by
/// which a magnetic bearing saved under `BearingElement` is recognised.
const MAGNETIC_KEYS: [&str; 7] = ["g0", "i0", "ag", "nw", "kp_pid", "kd_pid", "ki_pid"];

/// A `PointMass` (`point_mass.py`): translational mass at node `n`, no inertia.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointMass {
    /// Node (a shaft node, or an extra node beyond the shaft: a pedestal).
    pub n: i64,
    /// The mass given to ROSS (kg) when mx, my and mz were not; absent otherwise.
    #[serde(default)]
    pub m: Option<f64>,
    /// Mass in x (kg).
    pub mx: f64,
    /// Mass in y (kg).
    pub my: f64,
    /// Axial mass (kg); axial motion is not modelled.
    #[serde(default)]
    pub mz: Option<f64>,
    /// The element's name.
    pub tag: String,
    /// ROSS's drawing scale; plotting only, not used.
    #[serde(default)]
    pub scale_factor: Option<f64>,
    /// ROSS's plot colour; plotting only, not used.
    #[serde(default)]
    pub color: Option<String>,
    /// Line of the table in the file, when found.
    #[serde(skip)]
    pub line: Option<usize>,
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
    /// Timoshenko shear in the element (ROSS's default `true`).
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
    /// Line of the table in the file, when found.
    #[serde(skip)]
    pub line: Option<usize>,
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
    /// Line of the table in the file, when found.
    #[serde(skip)]
    pub line: Option<usize>,
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

/// A `BearingElement` or `SealElement` (`bearing_seal_element.py`, `BearingElement.save`),
/// or another bearing class of [`SupportClass`]. Stiffness in N/m, damping in N·s/m, mass
/// in kg, frequencies in rad/s.
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
    /// Cross-coupled stiffness k_xy (N/m), like `kxx`.
    pub kxy: Coefficient,
    /// Cross-coupled stiffness k_yx (N/m), like `kxx`.
    pub kyx: Coefficient,
    /// Direct stiffness k_yy (N/m), like `kxx`.
    pub kyy: Coefficient,
    /// Axial stiffness k_zz (N/m), like `kxx`; `None` when absent. Dropped by the importer
    /// (axial motion is not modelled).
    #[serde(default)]
    pub kzz: Option<Coefficient>,
    /// Direct damping c_xx (N·s/m): one value, or one per `frequency` entry (spin speed).
    pub cxx: Coefficient,
    /// Cross-coupled damping c_xy (N·s/m), like `cxx`.
    pub cxy: Coefficient,
    /// Cross-coupled damping c_yx (N·s/m), like `cxx`.
    pub cyx: Coefficient,
    /// Direct damping c_yy (N·s/m), like `cxx`.
    pub cyy: Coefficient,
    /// Axial damping c_zz (N·s/m), like `cxx`; `None` when absent. Dropped by the importer
    /// (axial motion is not modelled).
    #[serde(default)]
    pub czz: Option<Coefficient>,
    /// Direct added mass m_xx (kg) on the node: one value, or one per `frequency` entry.
    pub mxx: Coefficient,
    /// Cross-coupled added mass m_xy (kg), like `mxx`; the importer needs it 0.
    pub mxy: Coefficient,
    /// Cross-coupled added mass m_yx (kg), like `mxx`; the importer needs it 0.
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
    /// A seal's leakage (kg/s), saved by `SealElement`; not used.
    #[serde(default)]
    pub seal_leakage: Option<f64>,
    /// The ROSS class of the table.
    #[serde(skip)]
    pub class: SupportClass,
    /// Line of the table in the file, when found.
    #[serde(skip)]
    pub line: Option<usize>,
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

/// The 1-based lines of a text's table headers (`["<Class>_<tag>"]` in TOML, a key
/// `"<Class>_<tag>":` at the start of a line in JSON), found in one pass over the text so
/// that naming each element's line costs a look-up, not a scan.
pub struct TableLines {
    format: Format,
    /// Each header as written (TOML: between the brackets, trimmed; JSON: the quoted
    /// key) → its first line.
    lines: HashMap<String, usize>,
}

impl TableLines {
    /// The headers of `text`, read as `format`.
    pub fn of(text: &str, format: Format) -> TableLines {
        let mut lines = HashMap::new();
        let mut scanned = 0;
        for (i, l) in text.lines().enumerate() {
            scanned += 1;
            let l = l.trim();
            let header = match format {
                Format::Toml => l.strip_prefix('[').and_then(|l| l.strip_suffix(']')).map(str::trim),
                Format::Json => json_key(l),
            };
            if let Some(h) = header {
                lines.entry(h.to_string()).or_insert(i + 1);
            }
        }
        super::work::add(|w| w.lines_scanned += scanned);
        TableLines { format, lines }
    }

    /// The line of the table `name` (`["<Class>_<tag>"]` in TOML, the top-level key
    /// `"<Class>_<tag>"` in JSON), for messages; `None` when it is not found as ROSS
    /// writes it.
    pub fn line(&self, name: &str) -> Option<usize> {
        let quoted = serde_json::Value::String(name.to_string()).to_string();
        let quoted = self.lines.get(&quoted).copied();
        match self.format {
            Format::Toml => [self.lines.get(name).copied(), quoted].into_iter().flatten().min(),
            Format::Json => quoted,
        }
    }
}

/// The JSON string that opens `line`, with its quotes, when a `:` follows it (a key).
fn json_key(line: &str) -> Option<&str> {
    let rest = line.strip_prefix('"')?;
    let mut escaped = false;
    for (i, c) in rest.char_indices() {
        match c {
            _ if escaped => escaped = false,
            '\\' => escaped = true,
            '"' => {
                let end = i + 2;
                return line[end..].trim_start().starts_with(':').then(|| &line[..end]);
            }
            _ => {}
        }
    }
    None
}

/// The shaft elements of a parsed document, counted before any is converted: the
/// distinct `n` of its `ShaftElement` tables (concentric layers share their element's
/// `n`), a table without an integer `n` counted as an element of its own.
fn shaft_elements(map: &serde_json::Map<String, serde_json::Value>) -> usize {
    let mut numbers = HashSet::new();
    let mut unnumbered = 0;
    for (name, value) in map {
        if name.split_once('_').is_some_and(|(class, _)| class == "ShaftElement") {
            match value.get("n").and_then(serde_json::Value::as_i64) {
                Some(n) => {
                    numbers.insert(n);
                }
                None => unnumbered += 1,
            }
        }
    }
    numbers.len() + unnumbered
}

/// A number the importer cannot read as a finite f64, at a key: `nan`, `inf`, a float
/// beyond f64's range (`1e400`) or an integer beyond 64 bits. Named by its key and line
/// rather than by what the conversion to JSON values makes of it (a NaN became `null`,
/// "invalid type: null"; a huge integer "JSON number out of range").
fn not_finite(key: String, line: Option<usize>, literal: &str, integer: bool) -> RossErrorKind {
    let why = if integer { " (an integer beyond the 64 bits a number is read with)" } else { "" };
    RossErrorKind::Schema { key, line, message: format!("`{literal}` is not a finite number{why}") }
}

/// The first number of a TOML text that is not a finite f64 ([`not_finite`]), by key path
/// (`["<Class>_<tag>"].key`, `[i]` in arrays) and line; `None` when every number is one,
/// or when the text does not parse (its syntax error is reported as before).
fn toml_not_finite(text: &str) -> Option<RossErrorKind> {
    use toml::de::{DeTable, DeValue};
    fn scan(value: &toml::Spanned<DeValue<'_>>, path: &str) -> Option<(String, usize, String, bool)> {
        match value.get_ref() {
            DeValue::Float(f) => {
                let finite = f.as_str().parse::<f64>().is_ok_and(f64::is_finite);
                (!finite).then(|| (path.to_string(), value.span().start, f.as_str().to_string(), false))
            }
            DeValue::Integer(i) => i64::from_str_radix(i.as_str(), i.radix())
                .is_err()
                .then(|| (path.to_string(), value.span().start, i.to_string(), true)),
            DeValue::Array(a) => a.iter().enumerate().find_map(|(j, v)| scan(v, &format!("{path}[{j}]"))),
            DeValue::Table(t) => t.iter().find_map(|(k, v)| scan(v, &format!("{path}.{}", k.get_ref()))),
            _ => None,
        }
    }
    let doc = DeTable::parse(text).ok()?;
    let (key, offset, literal, integer) = doc.get_ref().iter().find_map(|(k, v)| {
        let top = format!("[\"{}\"]", k.get_ref());
        match v.get_ref() {
            DeValue::Table(t) => t.iter().find_map(|(k, v)| scan(v, &format!("{top}.{}", k.get_ref()))),
            _ => scan(v, &top),
        }
    })?;
    Some(not_finite(key, Some(crate::problem::source::line_of(text, offset)), &literal, integer))
}

/// The key path (`["<Class>_<tag>"].key`, `[i]` in arrays) of the JSON value at byte
/// `offset`, from the objects and arrays opened before it: where serde_json stopped on a
/// number out of range, which its error does not name.
fn json_key_at(text: &str, offset: usize) -> String {
    enum Open {
        Object(Option<String>),
        Array(usize),
    }
    let mut stack: Vec<Open> = Vec::new();
    let mut last = None;
    let mut chars = text[..offset.min(text.len())].chars();
    while let Some(c) = chars.next() {
        match c {
            '"' => {
                let mut s = String::new();
                while let Some(d) = chars.next() {
                    match d {
                        '\\' => s.extend(chars.next()),
                        '"' => break,
                        _ => s.push(d),
                    }
                }
                last = Some(s);
            }
            ':' => {
                if let Some(Open::Object(key)) = stack.last_mut() {
                    *key = last.take();
                }
            }
            ',' => {
                if let Some(Open::Array(i)) = stack.last_mut() {
                    *i += 1;
                }
            }
            '{' => stack.push(Open::Object(None)),
            '[' => stack.push(Open::Array(0)),
            '}' | ']' => {
                stack.pop();
            }
            _ => {}
        }
    }
    let mut path = String::new();
    for (depth, open) in stack.iter().enumerate() {
        match open {
            Open::Object(Some(k)) if depth == 0 => path.push_str(&format!("[\"{k}\"]")),
            Open::Object(Some(k)) => path.push_str(&format!(".{k}")),
            Open::Object(None) => {}
            Open::Array(i) => path.push_str(&format!("[{i}]")),
        }
    }
    path
}

/// Parse a saved rotor's text.
pub fn parse(text: &str, format: Format) -> Result<RossFile, RossErrorKind> {
    let doc: serde_json::Value = match format {
        Format::Toml => toml::from_str(text).map_err(|e| {
            toml_not_finite(text).unwrap_or_else(|| RossErrorKind::Syntax {
                format,
                line: e.span().map(|s| crate::problem::source::line_of(text, s.start)),
                message: e.message().trim().to_string(),
            })
        })?,
        Format::Json => serde_json::from_str(text).map_err(|e| {
            // serde_json ends its message with the position, which the error carries.
            let full = e.to_string();
            let position = format!(" at line {} column {}", e.line(), e.column());
            let message = full.strip_suffix(&position).unwrap_or(&full).to_string();
            if message == "number out of range" {
                // The number ends at the column; its text starts after the key's `:`.
                let start: usize = text.split_inclusive('\n').take(e.line() - 1).map(str::len).sum();
                let offset = start + e.column();
                let line = &text[start..offset.min(text.len())];
                let literal = line.rsplit(':').next().unwrap_or(line).trim().trim_end_matches(',');
                return not_finite(json_key_at(text, offset), Some(e.line()), literal, false);
            }
            RossErrorKind::Syntax { format, line: Some(e.line()), message }
        })?,
    };
    // A NaN or infinity that TOML reads becomes `null` among JSON values: name it first
    // (ROSS writes `null` itself for some keys, so only a text that gave one is scanned).
    fn has_null(v: &serde_json::Value) -> bool {
        match v {
            serde_json::Value::Null => true,
            serde_json::Value::Array(a) => a.iter().any(has_null),
            serde_json::Value::Object(m) => m.values().any(has_null),
            _ => false,
        }
    }
    if format == Format::Toml && has_null(&doc) {
        if let Some(e) = toml_not_finite(text) {
            return Err(e);
        }
    }
    let serde_json::Value::Object(map) = doc else {
        return Err(RossErrorKind::Schema {
            key: String::new(),
            line: None,
            message: "the file is not a table of elements".into(),
        });
    };
    // The size limit before any element is converted: rotorshunt's shaft holds at most
    // MAX_ELEMENTS elements, and a larger rotor is refused as a whole.
    let count = shaft_elements(&map);
    let limit = usize::try_from(crate::problem::MAX_ELEMENTS).unwrap_or(usize::MAX);
    if count > limit {
        return Err(RossErrorKind::Refused {
            element: None,
            reason: Box::new(Refusal::TooManyElements { count, limit }),
            more: Box::new([]),
        });
    }
    let lines = TableLines::of(text, format);
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
                line: lines.line(&name),
                key,
                message: "not an element table: ROSS names each element's table `<Class>_<tag>`".into(),
            });
        };
        if !value.is_object() {
            let line = lines.line(&name);
            return Err(RossErrorKind::Schema { key, line, message: "an element must be a table".into() });
        }
        let line = lines.line(&name);
        let mut value = value;
        match class {
            "ShaftElement" => {
                file.shafts.push(Shaft { line, ..element(&key, line, value)? });
                super::work::add(|w| w.shaft_elements_converted += 1);
            }
            "DiskElement" => file.disks.push(Disk { line, ..element(&key, line, value)? }),
            "PointMass" => file.point_masses.push(PointMass { line, ..element(&key, line, value)? }),
            _ => {
                let n = value.get("n").and_then(serde_json::Value::as_i64);
                let magnetic = class == "MagneticBearingElement"
                    || (class == "BearingElement" && MAGNETIC_KEYS.iter().any(|k| value.get(k).is_some()));
                match SupportClass::of(class).filter(|_| !magnetic) {
                    Some(support) => {
                        if let Some(map) = value.as_object_mut() {
                            for k in support.parameters() {
                                map.remove(*k);
                            }
                            if support == SupportClass::Cylindrical {
                                // Its table is over `speed`, which it passes to
                                // BearingElement as `frequency`.
                                if let Some(speed) = map.remove("speed") {
                                    map.insert("frequency".into(), speed);
                                }
                            }
                        }
                        file.bearings.push(Bearing { class: support, line, ..element(&key, line, value)? });
                    }
                    None => file.others.push(Other { class: class.into(), tag: tag.into(), n, line, magnetic }),
                }
            }
        }
    }
    Ok(file)
}

/// One element table, its errors located by key path below `key`.
fn element<T: serde::de::DeserializeOwned>(
    key: &str,
    line: Option<usize>,
    value: serde_json::Value,
) -> Result<T, RossErrorKind> {
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
        RossErrorKind::Schema { key: full, line, message }
    })
}

fn quoted(message: &str, prefix: &str) -> Option<String> {
    let rest = &message[message.find(prefix)? + prefix.len()..];
    Some(rest[..rest.find('`')?].to_string())
}
