//! The problem-file format, version 1: serde types mirroring the TOML, user data only.
//! Every key is documented in `problems/README.md`; units are SI and rad/s.

use crate::analysis::regions::RegionSettings;
use crate::analysis::Settings;
pub use crate::design::spec::ObjectiveKind;
use crate::model::CircuitState;
pub use crate::model::Parameter;
use serde::{Deserialize, Serialize};

/// The only format version this build reads.
pub const FORMAT_VERSION: i64 = 1;

/// A whole problem file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProblemFile {
    /// Format version; must be 1.
    pub version: i64,
    /// Short title shown in reports.
    #[serde(default)]
    pub title: Option<String>,
    /// Where the data come from.
    #[serde(default)]
    pub source: Option<String>,
    /// Rotating speed Ω (rad/s).
    pub speed: f64,
    /// `[[materials]]` (general form): named E and ρ that sections and disks refer to.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub materials: Vec<MaterialFile>,
    /// The shorthand shaft: one uniform solid section (exclusive with `[[sections]]`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shaft: Option<ShaftFile>,
    /// `[[sections]]` (general form): the shaft's sections, left to right.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sections: Option<Vec<SectionFile>>,
    /// Rigid disks (`[[disks]]`).
    #[serde(default)]
    pub disks: Vec<DiskFile>,
    /// The shorthand rings: the same ring at both ends unless `[ring.right]` overrides,
    /// both on `[circuit]` (exclusive with `[[bearings]]` and `[[rings]]`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ring: Option<RingFile>,
    /// The shorthand's shunt circuit, shared by both rings.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub circuit: Option<CircuitFile>,
    /// `[[bearings]]` (general form): bearings with stiffness and damping matrices.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub bearings: Vec<BearingFile>,
    /// `[[seals]]` (general form): seals, with the keys of `[[bearings]]`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub seals: Vec<BearingFile>,
    /// `[[rings]]` (general form): vibration rings, each with its own circuit.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub rings: Vec<RingSupportFile>,
    /// The axial load.
    pub load: LoadFile,
    /// Numerical settings of the analyses (`[analysis]`: reduced modes M, instability
    /// tolerance, monodromy method, …); defaults when absent.
    #[serde(default)]
    pub analysis: Settings,
    /// Settings of the region search (`[regions]`); defaults when absent.
    #[serde(default, skip_serializing_if = "RegionSettings::is_default")]
    pub regions: RegionSettings,
    /// A shunt design problem (`rotorshunt design`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub design: Option<DesignFile>,
}

/// `[design]`: what the shunt design should achieve and what it may change.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DesignFile {
    /// The objective's name: `widest-stable-band`, `clear-bands` or `min-peak-response`
    /// ([`ObjectiveKind::all`]).
    pub objective: ObjectiveKind,
    /// β_op: the dynamic load level of bands and edges (−).
    pub level: f64,
    /// φ_op (rad/s): the operating frequency whose stable band is widened.
    #[serde(default)]
    pub phi_op: Option<f64>,
    /// [φ_lo, φ_hi] (rad/s) searched by catalogues and band searches; default [100, 8000].
    #[serde(default)]
    pub phi_range: Option<[f64; 2]>,
    /// β_max of the catalogues (−); default 1.
    #[serde(default)]
    pub beta_max: Option<f64>,
    /// Operating speeds Ω (rad/s); default the file's `speed`.
    #[serde(default)]
    pub speeds: Option<Vec<f64>>,
    /// A range of operating speeds [lo, hi] (rad/s) over which the design must hold
    /// (instead of `speeds`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speed_range: Option<Vec<f64>>,
    /// `[[design.bands]]`: operating bands with clearances (clear-bands).
    #[serde(default)]
    pub bands: Vec<BandFile>,
    /// `[[design.variables]]`: what may change.
    pub variables: Vec<VariableFile>,
    /// Nelder–Mead starts; default 4.
    #[serde(default)]
    pub starts: Option<i64>,
    /// Iterations per start (Nelder–Mead) or sequential convex steps; default 40.
    #[serde(default)]
    pub max_iterations: Option<i64>,
    /// φ points of each before/after chart of the design report (2–4000); default 400.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub chart_phi_points: Option<i64>,
    /// β points of each before/after chart of the design report (2–401); default 31.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub chart_beta_points: Option<i64>,
    /// Whether the verification checks the tuned design again on a basis twice as large
    /// (default true).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refined_check: Option<bool>,
    /// Whether the local searches start from a map of the objective over the box
    /// (default true; false: from the first Halton points).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub map: Option<bool>,
    /// `[design.warnings]`: the margins under which page one warns.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub warnings: Option<WarningsFile>,
    /// `[design.response]`: the unbalance response of the min-peak-response objective and
    /// the peak constraint.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub response: Option<ResponseFile>,
    /// `[design.constraints]`: what the result must meet, whatever the objective.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub constraints: Option<ConstraintsFile>,
    /// `[design.margins]`: load and frequency margins of the band around `phi_op`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub margins: Option<MarginsFile>,
    /// `[design.tolerances]`: relative tolerances of the shunt's components.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerances: Option<TolerancesFile>,
    /// `[design.objective_options]`: keys of the objective's own, read and checked by the
    /// objective that `objective` names (one that takes none refuses the table).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub objective_options: Option<toml::Table>,
}

/// `[design.tolerances]`: relative tolerances (−, each in [0, 1), default 0) of every
/// component of a kind, and the Monte Carlo samples of the check on the result.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TolerancesFile {
    /// Of every inductance L (−).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inductance: Option<f64>,
    /// Of every resistance R (−).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resistance: Option<f64>,
    /// Of every branch capacitance C_f (−).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub c_f: Option<f64>,
    /// Of every stack capacitance C_p^T (−).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cp_t: Option<f64>,
    /// Monte Carlo samples of the check (1–10 000); default 200.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub samples: Option<i64>,
}

/// `[design.warnings]`: page one warns of a margin under these (each ≥ 0).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WarningsFile {
    /// Load margin (−, onset/β_op − 1); default 0.10.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub load_margin: Option<f64>,
    /// Frequency margin as a share of φ_op (−); default 0.05.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frequency_margin: Option<f64>,
}

/// `[design.margins]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MarginsFile {
    /// Load margin (−, relative to β_op, ≥ 0): the band holds for every β up to
    /// (1 + beta)·β_op; default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub beta: Option<f64>,
    /// Frequency margin (rad/s, ≥ 0): φ_op at least this far from each edge of that band;
    /// default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub phi: Option<f64>,
}

/// `[design.response]`: the unbalance response at a shaft node over a speed range.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ResponseFile {
    /// The shaft node (0 to the number of shaft elements).
    pub node: i64,
    /// [lo, hi] (rad/s), lo < hi.
    pub speeds: Vec<f64>,
    /// Grid speeds over the range, ends included; default 201.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub points: Option<i64>,
}

/// `[design.constraints]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConstraintsFile {
    /// The stable band around `design.phi_op` at β_op at least this wide (rad/s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_band_width: Option<f64>,
    /// The largest unbalance amplitude at `design.response.node` over its speeds at most
    /// this (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_peak: Option<f64>,
    /// `[[design.constraints.damping]]`: damping-ratio floors of named whirls.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub damping: Vec<DampingFile>,
}

/// `[[design.constraints.damping]]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DampingFile {
    /// The whirl's tag at the lowest operating speed, e.g. `f1`, `br1` (`rotorshunt modes`).
    pub mode: String,
    /// The least damping ratio ζ (−), in [0, 1).
    pub min: f64,
}

/// `[[design.bands]]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BandFile {
    /// Lower end (rad/s).
    pub lo: f64,
    /// Upper end (rad/s).
    pub hi: f64,
    /// Clearance on each side (rad/s); default 0.
    #[serde(default)]
    pub clearance: f64,
}

/// `[[design.variables]]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VariableFile {
    /// The ring (general form: its `name`) whose branch this is; omitted: every ring
    /// (valid only while all rings carry an identical circuit).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ring: Option<String>,
    /// Branch number, counted from 1 in the order of the circuit's branches.
    pub branch: i64,
    /// `c_f`, `inductance`, `tuning_frequency` or `resistance`.
    pub parameter: Parameter,
    /// Lower bound (unit of the parameter).
    pub min: f64,
    /// Upper bound of the variable, in the unit of `parameter` (F, H, rad/s or Ω).
    pub max: f64,
}

/// `[shaft]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShaftFile {
    /// L (m).
    pub length: f64,
    /// r (m).
    pub radius: f64,
    /// Number of Rayleigh beam elements n.
    pub elements: i64,
    /// E (Pa).
    pub youngs_modulus: f64,
    /// ρ (kg/m³).
    pub density: f64,
}

/// `[[materials]]`: a named material.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialFile {
    /// Name sections and disks refer to (`material = "steel"`); unique.
    pub name: String,
    /// E (Pa).
    pub youngs_modulus: f64,
    /// ρ (kg/m³).
    pub density: f64,
    /// Shear modulus G (Pa), needed by Timoshenko sections; or give `poisson_ratio`.
    /// E/(2G) − 1 must lie in (−1, 0.5): G > E/3.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shear_modulus: Option<f64>,
    /// Poisson's ratio ν (−), in (−1, 0.5): G = E/(2(1 + ν)); or give `shear_modulus`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub poisson_ratio: Option<f64>,
}

/// `beam` of a `[[sections]]` entry: the beam theory of its elements.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum BeamKind {
    /// Rayleigh beams (bending, rotary inertia, gyroscopic; no shear deformation).
    #[default]
    Rayleigh,
    /// Timoshenko beams (Rayleigh plus shear deformation).
    Timoshenko,
}

/// `[[sections]]`: a solid or hollow section of the shaft, uniform or tapered.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SectionFile {
    /// Length (m).
    pub length: f64,
    /// Outer diameter D (m).
    pub outer_diameter: f64,
    /// Inner diameter d (m); default 0 (solid); below D.
    #[serde(default)]
    pub inner_diameter: f64,
    /// Outer diameter at the right end (m), for a tapered section (D varies linearly
    /// from `outer_diameter` at the left end); default `outer_diameter`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub outer_diameter_right: Option<f64>,
    /// Inner diameter at the right end (m), for a tapered bore; default `inner_diameter`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inner_diameter_right: Option<f64>,
    /// A `[[materials]]` name; or give `youngs_modulus` and `density` here.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    /// E (Pa).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub youngs_modulus: Option<f64>,
    /// ρ (kg/m³).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density: Option<f64>,
    /// Shear modulus G (Pa) with `youngs_modulus` here (no `material`); or `poisson_ratio`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shear_modulus: Option<f64>,
    /// Poisson's ratio ν (−) with `youngs_modulus` here (no `material`); or `shear_modulus`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub poisson_ratio: Option<f64>,
    /// `rayleigh` (default) or `timoshenko`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub beam: Option<BeamKind>,
    /// Shear coefficient κ (−, > 0) of a Timoshenko section; default Cowper's (1966) for
    /// a circular tube, from Poisson's ratio and each element's d/D (docs/model.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shear_coefficient: Option<f64>,
    /// Number of equal elements in the section (≥ 1).
    pub elements: i64,
    /// `[[sections.layers]]`: concentric layers over the section's nodes (a sleeve).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub layers: Vec<LayerFile>,
}

/// `[[sections.layers]]`: a concentric tube over its section's length and elements, of its
/// own diameters, material and beam theory; its element matrices add to the section's
/// (ROSS's shaft elements of one `n`). The keys mean what they mean in `[[sections]]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LayerFile {
    /// Outer diameter D (m), at the left end when tapered.
    pub outer_diameter: f64,
    /// Inner diameter d (m); default 0; below D.
    #[serde(default)]
    pub inner_diameter: f64,
    /// Outer diameter at the right end (m); default `outer_diameter`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub outer_diameter_right: Option<f64>,
    /// Inner diameter at the right end (m); default `inner_diameter`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inner_diameter_right: Option<f64>,
    /// A `[[materials]]` name; or give `youngs_modulus` and `density` here.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    /// E (Pa).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub youngs_modulus: Option<f64>,
    /// ρ (kg/m³).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density: Option<f64>,
    /// Shear modulus G (Pa) with `youngs_modulus` here; or `poisson_ratio`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shear_modulus: Option<f64>,
    /// Poisson's ratio ν (−) with `youngs_modulus` here; or `shear_modulus`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub poisson_ratio: Option<f64>,
    /// `rayleigh` (default) or `timoshenko`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub beam: Option<BeamKind>,
    /// Shear coefficient κ (−, > 0) of a Timoshenko layer; default Cowper's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shear_coefficient: Option<f64>,
}

impl LayerFile {
    /// The layer as a section of `length` (m) and `elements`, to share its checks.
    pub fn as_section(&self, length: f64, elements: i64) -> SectionFile {
        SectionFile {
            length,
            outer_diameter: self.outer_diameter,
            inner_diameter: self.inner_diameter,
            outer_diameter_right: self.outer_diameter_right,
            inner_diameter_right: self.inner_diameter_right,
            material: self.material.clone(),
            youngs_modulus: self.youngs_modulus,
            density: self.density,
            shear_modulus: self.shear_modulus,
            poisson_ratio: self.poisson_ratio,
            beam: self.beam,
            shear_coefficient: self.shear_coefficient,
            elements,
            layers: Vec::new(),
        }
    }
}

/// `[[bearings]]` and `[[seals]]`: a support with stiffness and damping matrices, placed
/// by `node` or `position`. Either the isotropic `stiffness` and `damping` (kxx = kyy,
/// cxx = cyy, no cross-coupling) or the eight coefficients, each a number or an array of
/// one value per speed of `speeds`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BearingFile {
    /// Node index, 0 = left end.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub node: Option<i64>,
    /// Position along the shaft (m); snapped to the nearest node.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position: Option<f64>,
    /// Isotropic stiffness k = kxx = kyy (N/m); or give `kxx` (and `kyy`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stiffness: Option<f64>,
    /// Isotropic damping c = cxx = cyy (N·s/m); or give `cxx` (and `cyy`); default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<f64>,
    /// Direct stiffness kxx (N/m): F_x = −(kxx·x + kxy·y) − …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kxx: Option<CoefficientFile>,
    /// Cross-coupled stiffness kxy (N/m); default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kxy: Option<CoefficientFile>,
    /// Cross-coupled stiffness kyx (N/m): F_y = −(kyx·x + kyy·y) − …; default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kyx: Option<CoefficientFile>,
    /// Direct stiffness kyy (N/m); default kxx.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kyy: Option<CoefficientFile>,
    /// Direct damping cxx (N·s/m); default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cxx: Option<CoefficientFile>,
    /// Cross-coupled damping cxy (N·s/m); default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cxy: Option<CoefficientFile>,
    /// Cross-coupled damping cyx (N·s/m); default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cyx: Option<CoefficientFile>,
    /// Direct damping cyy (N·s/m); default cxx.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cyy: Option<CoefficientFile>,
    /// Speeds of the coefficient tables (rad/s), strictly increasing; needed when a
    /// coefficient is an array.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speeds: Option<Vec<f64>>,
    /// Support mass (kg), lumped at the node; default 0.
    #[serde(default)]
    pub mass: f64,
}

/// A support coefficient: one number (constant) or one number per table speed.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum CoefficientFile {
    /// A constant.
    Constant(f64),
    /// One value per speed of the support's `speeds`.
    Table(Vec<f64>),
}

impl CoefficientFile {
    /// The values: one for a constant.
    pub fn values(&self) -> Vec<f64> {
        match self {
            CoefficientFile::Constant(x) => vec![*x],
            CoefficientFile::Table(v) => v.clone(),
        }
    }
}

impl<'de> Deserialize<'de> for CoefficientFile {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl<'de> serde::de::Visitor<'de> for Visitor {
            type Value = CoefficientFile;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a number or an array of numbers (one per speed of `speeds`)")
            }
            fn visit_f64<E>(self, v: f64) -> Result<CoefficientFile, E> {
                Ok(CoefficientFile::Constant(v))
            }
            fn visit_i64<E>(self, v: i64) -> Result<CoefficientFile, E> {
                Ok(CoefficientFile::Constant(v as f64))
            }
            fn visit_u64<E>(self, v: u64) -> Result<CoefficientFile, E> {
                Ok(CoefficientFile::Constant(v as f64))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<CoefficientFile, A::Error> {
                let mut v = Vec::new();
                while let Some(x) = seq.next_element::<f64>()? {
                    v.push(x);
                }
                Ok(CoefficientFile::Table(v))
            }
        }
        d.deserialize_any(Visitor)
    }
}

/// `[[rings]]`: a vibration ring (today's `[ring]` keys) at a node or position, with its
/// own `[rings.circuit]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RingSupportFile {
    /// Name used in labels and design variables; default `ring1`, `ring2`, … (file order).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Node index, 0 = left end.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub node: Option<i64>,
    /// Position along the shaft (m); snapped to the nearest node.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position: Option<f64>,
    /// Bearing stiffness k_b (N/m).
    pub k_b: f64,
    /// Bearing + ring mass m_b (kg).
    pub m_b: f64,
    /// Mechanical damping η (N·s/m).
    #[serde(default)]
    pub eta: f64,
    /// Ring structure stiffness k_1 (N/m).
    pub k_1: f64,
    /// Piezo stack stiffness k_2 (N/m).
    pub k_2: f64,
    /// Structural angle β (degrees, 0 < β < 90).
    pub angle_deg: f64,
    /// Coupling coefficient θ_p (C/m).
    pub theta_p: f64,
    /// C_p^T (F).
    pub cp_t: f64,
    /// C_p^S (F); give this or `k_eq2`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cp_s: Option<f64>,
    /// k_eq2 (N/m); give this or `cp_s`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k_eq2: Option<f64>,
    /// This ring's shunt circuit.
    pub circuit: CircuitFile,
}

impl RingSupportFile {
    /// The ring keys as a `[ring]` table (no override), to share its checks.
    pub fn ring_keys(&self) -> RingFile {
        RingFile {
            k_b: self.k_b,
            m_b: self.m_b,
            eta: self.eta,
            k_1: self.k_1,
            k_2: self.k_2,
            angle_deg: self.angle_deg,
            theta_p: self.theta_p,
            cp_t: self.cp_t,
            cp_s: self.cp_s,
            k_eq2: self.k_eq2,
            right: None,
        }
    }
}

/// `[[disks]]`: placed by `node` (0-based) or `position` (m from the left end); given by
/// `mass`, `polar_inertia` (and `diametral_inertia`) or by its geometry (`outer_diameter`,
/// `inner_diameter`, `width`, `material`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DiskFile {
    /// Node index, 0 = left end.
    #[serde(default)]
    pub node: Option<i64>,
    /// Position along the shaft (m); snapped to the nearest node.
    #[serde(default)]
    pub position: Option<f64>,
    /// m (kg) (mass form).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass: Option<f64>,
    /// J_p (kg·m²) (mass form).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub polar_inertia: Option<f64>,
    /// J_d (kg·m²); default J_p/2 (thin disk) (mass form).
    #[serde(default)]
    pub diametral_inertia: Option<f64>,
    /// Outer diameter D (m) (geometry form).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub outer_diameter: Option<f64>,
    /// Inner (bore) diameter d (m), default 0 (geometry form).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inner_diameter: Option<f64>,
    /// Width w (m) (geometry form).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub width: Option<f64>,
    /// A `[[materials]]` name (geometry form; or give `density`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    /// ρ (kg/m³) (geometry form, instead of `material`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density: Option<f64>,
    /// Unbalance eccentricity e (m).
    #[serde(default)]
    pub eccentricity: f64,
    /// Unbalance phase γ (rad).
    #[serde(default)]
    pub phase: f64,
}

/// `[ring]`: vibration ring and bearing (Eq. 1, 7–10).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RingFile {
    /// Bearing stiffness k_b (N/m).
    pub k_b: f64,
    /// Bearing + ring mass m_b (kg).
    pub m_b: f64,
    /// Mechanical damping η (N·s/m).
    #[serde(default)]
    pub eta: f64,
    /// Ring structure stiffness k_1 (N/m).
    pub k_1: f64,
    /// Piezo stack stiffness k_2 (N/m).
    pub k_2: f64,
    /// Structural angle β (degrees, 0 < β < 90).
    pub angle_deg: f64,
    /// Coupling coefficient θ_p (C/m).
    pub theta_p: f64,
    /// C_p^T (F).
    pub cp_t: f64,
    /// C_p^S (F); give this or `k_eq2`.
    #[serde(default)]
    pub cp_s: Option<f64>,
    /// k_eq2 (N/m), from which C_p^S follows by Eq. (1); give this or `cp_s`.
    #[serde(default)]
    pub k_eq2: Option<f64>,
    /// Values that differ at the right end (x = L).
    #[serde(default)]
    pub right: Option<RingOverride>,
}

/// `[ring.right]`: any subset of the ring keys, for the right end only.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RingOverride {
    /// k_b (N/m).
    pub k_b: Option<f64>,
    /// m_b (kg).
    pub m_b: Option<f64>,
    /// η (N·s/m).
    pub eta: Option<f64>,
    /// k_1 (N/m).
    pub k_1: Option<f64>,
    /// k_2 (N/m).
    pub k_2: Option<f64>,
    /// β (degrees).
    pub angle_deg: Option<f64>,
    /// θ_p (C/m).
    pub theta_p: Option<f64>,
    /// C_p^T (F).
    pub cp_t: Option<f64>,
    /// C_p^S (F).
    pub cp_s: Option<f64>,
    /// k_eq2 (N/m).
    pub k_eq2: Option<f64>,
}

/// `[circuit]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CircuitFile {
    /// `open`, `short` or `closed`.
    pub state: CircuitState,
    /// `[[circuit.branches]]`: needed (N ≥ 1) when closed.
    #[serde(default)]
    pub branches: Vec<BranchFile>,
}

/// `[[circuit.branches]]`: C_f, R and either L or the tuning frequency of Eq. (4).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BranchFile {
    /// Filtering capacitance C_f (F).
    pub c_f: f64,
    /// Inductance L (H); give this or `tuning_frequency`.
    #[serde(default)]
    pub inductance: Option<f64>,
    /// ω of Eq. (4) (rad/s), from which L follows; give this or `inductance`.
    #[serde(default)]
    pub tuning_frequency: Option<f64>,
    /// Resistance R (Ω).
    #[serde(default)]
    pub resistance: f64,
}

/// `[load]`: P(t) = P_cr·(α + β cos φt).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadFile {
    /// Static load coefficient α (−), below 1.
    pub alpha: f64,
    /// P_cr (N); computed (open-circuit supports) when absent.
    #[serde(default)]
    pub critical_load: Option<f64>,
}
