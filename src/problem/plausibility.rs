//! Plausibility of a valid problem: values that no real rotor has, most often a unit
//! mistake (mm for m, MPa for Pa, radians for degrees, rpm for rad/s). They are warnings,
//! not errors: the model is well defined and the analyses run; only what is physically
//! impossible (C_p^S ≥ C_p^T) is refused, in `validate.rs`. Every threshold is a named
//! constant with its reason.

use super::file::ProblemFile;
use super::source::Location;
use super::units::RAD_PER_S_PER_RPM;
use crate::analysis::warnings::RangeWarning;
use crate::model::Model;
use serde::Serialize;
use thiserror::Error;

/// Lowest plausible Young's modulus of a shaft or disk material (Pa). Engineering solids
/// start about here: nylon and other structural polymers have 2–4 GPa, magnesium 45 GPa,
/// steels 200–210 GPa. A steel's modulus typed in MPa (2.06e5) or GPa (206) falls 6 or
/// 9 orders of magnitude below the steel it means, and far below this.
pub const MIN_YOUNGS_MODULUS: f64 = 1e9;

/// Highest plausible Young's modulus (Pa): tungsten has 411 GPa, carbon-fibre composites
/// along the fibre up to about 500 GPa; only diamond (1.05e12 Pa) is stiffer.
pub const MAX_YOUNGS_MODULUS: f64 = 1e12;

/// Heaviest plausible shaft or disk (kg). The heaviest machinery rotors, those of large
/// turbine generators, weigh 2–3e5 kg; a shaft whose length and radius are typed in mm
/// but read as m is 1e9 times heavier than meant (the paper's 3.9 kg shaft becomes
/// 3.9e9 kg), a radius alone in mm 1e6 times.
pub const MAX_MASS: f64 = 1e6;

/// Highest plausible shaft slenderness L/D (length over the largest outer diameter).
/// Machinery shafts have L/D of about 5 to 50 (the paper's 23) and long line shafts stay
/// below about 100; a length typed in mm but read as m makes it thousands.
pub const MAX_SLENDERNESS: f64 = 200.0;

/// Highest plausible peripheral speed Ω·r at the rotor's largest radius (m/s). A solid
/// disk bursts when the stress at its centre, ρv²(3 + ν)/8, reaches the ultimate
/// strength: at v ≈ 560 m/s for a 1 GPa steel (ρ = 7850 kg/m³, ν = 0.3) and ≈ 780 m/s for
/// titanium Ti-6Al-4V (1.1 GPa, 4430 kg/m³), so no metal rotor runs above this. A speed
/// in rpm read as rad/s is 9.55 times too fast: a rotor at 100 m/s seems at 955 m/s.
pub const MAX_PERIPHERAL_SPEED: f64 = 800.0;

/// Largest `angle_deg` that is also a value in radians of an angle in (0°, 90°) (π/2):
/// the paper's 60° typed in radians is 1.047. So small an angle (below 1.6°) would make
/// the ring's stack stiffness k_eq1 = 2k_2·cot²β over 2 600 times k_2.
pub const MAX_RADIAN_LIKE_ANGLE: f64 = std::f64::consts::FRAC_PI_2;

/// One implausible value, with the numbers that make it so. The text (`Display`) is what
/// the command line prints after `warning: FILE, line N: key `K`: `.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum WarningKind {
    /// A Young's modulus outside the range of engineering solids.
    #[error(
        "E = {value:e} Pa is far from any metal or composite ({lo:e} to {hi:e} Pa): check the unit (Pa, not MPa or GPa)"
    )]
    YoungsModulus {
        /// E (Pa).
        value: f64,
        /// Lower end of the plausible range (Pa).
        lo: f64,
        /// Upper end (Pa).
        hi: f64,
    },
    /// A shaft or disk heavier than any machinery rotor.
    #[error("the {what} weighs {mass:.4e} kg, more than any machinery rotor ({limit:e} kg): check the units (kg, and lengths in m, not mm)")]
    Mass {
        /// `shaft` or `disk`.
        what: &'static str,
        /// Its mass (kg).
        mass: f64,
        /// The limit (kg).
        limit: f64,
    },
    /// A shaft far more slender than machinery shafts.
    #[error("the shaft's slenderness L/D = {length:.4e} m / {diameter:.4e} m = {ratio:.4e} is above {limit} (machinery shafts stay far below): check the length and diameter units (m)")]
    Slenderness {
        /// L (m).
        length: f64,
        /// The largest outer diameter D (m).
        diameter: f64,
        /// L/D.
        ratio: f64,
        /// The limit.
        limit: f64,
    },
    /// A ring angle small enough to be a value in radians.
    #[error("angle_deg = {angle_deg} degrees is at most pi/2: it looks like radians ({angle_deg} rad = {:.4} degrees); the key is in degrees", angle_deg.to_degrees(), angle_deg = crate::analysis::limits::number(*angle_deg))]
    AngleInRadians {
        /// The angle given (degrees).
        angle_deg: f64,
    },
    /// A speed whose peripheral speed no metal rotor survives: likely rpm given as rad/s.
    #[error("{speed} rad/s gives a peripheral speed of {peripheral:.4e} m/s at the radius {radius:.4} m, above the {limit} m/s at which metal disks burst: a speed in rpm is given as `{rpm_key}` (or check that the lengths are in m)", speed = crate::analysis::limits::number(*speed))]
    PeripheralSpeed {
        /// Ω (rad/s).
        speed: f64,
        /// The largest radius of the rotor (m).
        radius: f64,
        /// Ω·radius (m/s).
        peripheral: f64,
        /// The limit (m/s).
        limit: f64,
        /// The rpm key to use instead.
        rpm_key: String,
    },
    /// A speed given in rpm whose peripheral speed no metal rotor survives.
    #[error("{rpm} rpm gives a peripheral speed of {peripheral:.4e} m/s at the radius {radius:.4} m, above the {limit} m/s at which metal disks burst", rpm = crate::analysis::limits::number(*rpm))]
    PeripheralSpeedRpm {
        /// n (rpm).
        rpm: f64,
        /// The largest radius of the rotor (m).
        radius: f64,
        /// Ω·radius (m/s).
        peripheral: f64,
        /// The limit (m/s).
        limit: f64,
    },
    /// A speed outside a bearing's or seal's coefficient table: its coefficients are
    /// held at the nearest end of the table (not extrapolated).
    #[error("{speed} rad/s is outside the table's speeds ({lo} to {hi} rad/s): the coefficients are held at their value at {} rad/s, not extrapolated", if speed < lo { lo } else { hi }, speed = crate::analysis::limits::number(*speed), lo = crate::analysis::limits::number(*lo), hi = crate::analysis::limits::number(*hi))]
    OutsideTable {
        /// The speed (rad/s).
        speed: f64,
        /// The table's first speed (rad/s).
        lo: f64,
        /// Its last speed (rad/s).
        hi: f64,
    },
    /// A φ range that no instability region can reach (found by the analysis, which needs
    /// the whirls; located here).
    #[error(transparent)]
    Range(RangeWarning),
}

impl WarningKind {
    /// The kind's name, as `docs/errors.md` lists it (`YoungsModulus`, …): the `kind` of
    /// a warning in JSON.
    pub fn name(&self) -> &'static str {
        match self {
            WarningKind::YoungsModulus { .. } => "YoungsModulus",
            WarningKind::Mass { .. } => "Mass",
            WarningKind::Slenderness { .. } => "Slenderness",
            WarningKind::AngleInRadians { .. } => "AngleInRadians",
            WarningKind::PeripheralSpeed { .. } => "PeripheralSpeed",
            WarningKind::PeripheralSpeedRpm { .. } => "PeripheralSpeedRpm",
            WarningKind::OutsideTable { .. } => "OutsideTable",
            WarningKind::Range(r) => r.name(),
        }
    }
}

/// A plausibility warning on a problem file: where it is (file, line or `--set`, key
/// path or flag) and what looks wrong. Printed by the command line as
/// `warning: FILE, line N: key `K`: …`; in JSON as `{kind, key, line, message}`.
#[derive(Debug, Clone, PartialEq)]
pub struct Warning {
    /// The file name as given.
    pub file: String,
    /// Line of the key, or override, or unknown (a flag, a computed quantity).
    pub location: Location,
    /// Key path (`shaft.youngs_modulus`) or flag (`--phi`) concerned.
    pub key: String,
    /// What looks wrong, with the values.
    pub kind: WarningKind,
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        // A flag is named as the command line's argument errors name it.
        let key = if self.key.starts_with("--") {
            format!("argument `{}`: ", self.key)
        } else {
            super::error::key_(&self.key)
        };
        write!(f, "{}{}: {key}{}", self.file, super::error::where_(&self.location), self.kind)
    }
}

impl Serialize for Warning {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        #[derive(Serialize)]
        struct Json<'a> {
            kind: &'static str,
            key: &'a str,
            #[serde(skip_serializing_if = "Option::is_none")]
            line: Option<usize>,
            #[serde(skip_serializing_if = "std::ops::Not::not")]
            set: bool,
            message: String,
        }
        let line = match self.location {
            Location::Line(n) => Some(n),
            _ => None,
        };
        Json {
            kind: self.kind.name(),
            key: &self.key,
            line,
            set: self.location == Location::Override,
            message: self.kind.to_string(),
        }
        .serialize(s)
    }
}

/// The plausibility warnings of a valid file and its model, as (key path, kind), in
/// file order of the topics: materials and shaft, disks, rings, speeds. `rpm` lists the
/// rad/s keys that were given in rpm (`speed`, `design.speeds`, `design.response.speeds`).
pub(super) fn check(f: &ProblemFile, model: &Model, rpm: &[String]) -> Vec<(String, WarningKind)> {
    let mut out = Vec::new();
    // The file's speed (and the design's) outside a support's table.
    let mut speeds = vec![model.speed];
    if let Some(d) = &f.design {
        speeds.extend(d.speeds.iter().flatten().copied());
        speeds.extend(d.speed_range.iter().flatten().copied());
    }
    let tables = [("bearings", f.bearings.len()), ("seals", f.seals.len())];
    let keys = tables.iter().flat_map(|(t, n)| (0..*n).map(move |i| format!("{t}[{i}].speeds")));
    for (b, key) in model.bearings.iter().zip(keys) {
        if let Some(&speed) = speeds.iter().find(|&&w| b.outside_table(w)) {
            let (lo, hi) = (b.speeds[0], b.speeds[b.speeds.len() - 1]);
            out.push((key, WarningKind::OutsideTable { speed, lo, hi }));
        }
    }
    let mut modulus = |key: String, value: f64| {
        if !(MIN_YOUNGS_MODULUS..=MAX_YOUNGS_MODULUS).contains(&value) {
            out.push((key, WarningKind::YoungsModulus { value, lo: MIN_YOUNGS_MODULUS, hi: MAX_YOUNGS_MODULUS }));
        }
    };
    if let Some(s) = &f.shaft {
        modulus("shaft.youngs_modulus".into(), s.youngs_modulus);
    }
    for (i, m) in f.materials.iter().enumerate() {
        modulus(format!("materials[{i}].youngs_modulus"), m.youngs_modulus);
    }
    for (i, s) in f.sections.iter().flatten().enumerate() {
        if let Some(e) = s.youngs_modulus {
            modulus(format!("sections[{i}].youngs_modulus"), e);
        }
    }
    let shorthand = f.shaft.is_some();
    let sections = &model.shaft.sections;
    let shaft_mass: f64 = sections
        .iter()
        .map(|s| {
            if !s.is_uniform() {
                return s.mass();
            }
            let area = std::f64::consts::PI * (s.outer_diameter.powi(2) - s.inner_diameter.powi(2)) / 4.0;
            s.density * area * s.length
        })
        .sum();
    if shaft_mass > MAX_MASS {
        let key = if shorthand { "shaft" } else { "sections" };
        out.push((key.into(), WarningKind::Mass { what: "shaft", mass: shaft_mass, limit: MAX_MASS }));
    }
    let length = model.shaft.length();
    let diameter = sections.iter().map(|s| s.outer_diameter.max(s.outer_diameter_right)).fold(0.0, f64::max);
    let ratio = length / diameter;
    if ratio > MAX_SLENDERNESS {
        let key = if shorthand { "shaft.length" } else { "sections" };
        out.push((key.into(), WarningKind::Slenderness { length, diameter, ratio, limit: MAX_SLENDERNESS }));
    }
    // The rotor's largest radius: the shaft's, or a disk's outer radius (its geometry, or
    // the solid disk of the same mass and J_p, r = √(2J_p/m)).
    let mut radius = diameter / 2.0;
    for (i, (d, disk)) in f.disks.iter().zip(&model.disks).enumerate() {
        let geometry = d.outer_diameter.is_some();
        if disk.mass > MAX_MASS {
            let key = format!("disks[{i}].{}", if geometry { "outer_diameter" } else { "mass" });
            out.push((key, WarningKind::Mass { what: "disk", mass: disk.mass, limit: MAX_MASS }));
        }
        let r = match d.outer_diameter {
            Some(outer) => outer / 2.0,
            None => (2.0 * disk.polar_inertia / disk.mass).sqrt(),
        };
        if r.is_finite() {
            radius = radius.max(r);
        }
    }
    let mut angle = |key: String, angle_deg: f64| {
        if angle_deg <= MAX_RADIAN_LIKE_ANGLE {
            out.push((key, WarningKind::AngleInRadians { angle_deg }));
        }
    };
    if let Some(r) = &f.ring {
        angle("ring.angle_deg".into(), r.angle_deg);
        if let Some(a) = r.right.as_ref().and_then(|o| o.angle_deg) {
            angle("ring.right.angle_deg".into(), a);
        }
    }
    for (i, r) in f.rings.iter().enumerate() {
        angle(format!("rings[{i}].angle_deg"), r.angle_deg);
    }
    let mut speed = |key: &str, rpm_key: &str, in_rpm: bool, w: f64| {
        let peripheral = w * radius;
        if peripheral > MAX_PERIPHERAL_SPEED {
            let limit = MAX_PERIPHERAL_SPEED;
            if in_rpm {
                let rpm = w / RAD_PER_S_PER_RPM;
                out.push((rpm_key.into(), WarningKind::PeripheralSpeedRpm { rpm, radius, peripheral, limit }));
            } else {
                let rpm_key = rpm_key.split('[').next().unwrap_or(rpm_key).to_string();
                out.push((key.into(), WarningKind::PeripheralSpeed { speed: w, radius, peripheral, limit, rpm_key }));
            }
        }
    };
    speed("speed", "speed_rpm", rpm.iter().any(|k| k == "speed"), model.speed);
    if let Some(speeds) = f.design.as_ref().and_then(|d| d.speeds.as_ref()) {
        let in_rpm = rpm.iter().any(|k| k == "design.speeds");
        for (i, &w) in speeds.iter().enumerate() {
            speed(&format!("design.speeds[{i}]"), &format!("design.speeds_rpm[{i}]"), in_rpm, w);
        }
    }
    out
}
