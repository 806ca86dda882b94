//! Errors of the file layer: each names the file, the line (when the text parses) and
//! the key path, and carries the offending value.

use super::source::Location;
use crate::analysis::limits::{number, ParamError, Rule};
use thiserror::Error;

/// What is wrong with a problem file.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum ProblemErrorKind {
    /// The file cannot be read.
    #[error("cannot read the file: {0}")]
    Read(String),
    /// The path is not a regular file (or a link to one): a directory, a FIFO, a device
    /// or a socket. Refused before opening.
    #[error("the path is {kind}, not a regular file (only regular files and links to them are read)")]
    NotARegularFile {
        /// What it is, e.g. `a directory`, `a FIFO (named pipe)`, `a character device`.
        kind: String,
    },
    /// The file is larger than [`super::input::MAX_FILE_BYTES`].
    #[error("the file is too large: {size} bytes, more than the {} MiB ({limit} bytes) an input file may have", limit >> 20)]
    TooLarge {
        /// Bytes found (from the file's size, or read before stopping).
        size: u64,
        /// The limit (bytes).
        limit: u64,
    },
    /// Parsing the TOML text would need more memory than
    /// [`super::input::MAX_PARSE_BYTES`] (see [`super::input::TomlCost`]).
    #[error(
        "the TOML text is too complex: parsing {tokens} tokens (up to {tables} tables, {arrays} arrays, {keys} keys) would take about {} MiB, more than the {} MiB allowed",
        estimate >> 20,
        limit >> 20
    )]
    TooComplex {
        /// Tokens of the text.
        tokens: u64,
        /// Tables the text may create, at most.
        tables: u64,
        /// Arrays of the text.
        arrays: u64,
        /// Key/value pairs of the text.
        keys: u64,
        /// Estimated parse memory (bytes).
        estimate: u64,
        /// The limit (bytes).
        limit: u64,
    },
    /// The file is not valid UTF-8 text.
    #[error("the file is not UTF-8 text (invalid byte at offset {0})")]
    NotUtf8(usize),
    /// The file has no content.
    #[error(
        "the file is empty: a problem file needs at least `version`, `speed`, [shaft], [ring], [circuit] and [load]"
    )]
    Empty,
    /// The text is not valid TOML.
    #[error("TOML syntax error: {0}")]
    Syntax(String),
    /// A key is not part of the format (serde: unknown field), a required key is
    /// missing, or a value has the wrong type.
    #[error("{0}")]
    Schema(String),
    /// Unsupported `version`.
    #[error("format version {found} is not supported (this build reads version {supported})")]
    Version {
        /// Found.
        found: i64,
        /// Supported.
        supported: i64,
    },
    /// NaN or infinite.
    #[error("must be a finite number, found {}", number(*.0))]
    NotFinite(f64),
    /// ≤ 0 where a positive value is needed.
    #[error("must be positive, found {}", number(*.0))]
    NotPositive(f64),
    /// < 0 where a non-negative value is needed.
    #[error("must not be negative, found {}", number(*.0))]
    Negative(f64),
    /// `design --pareto` on a `[design]` table without a trade-off between the peak
    /// response and the band around φ_op ([`crate::design::pareto::trade_off`]).
    #[error("no Pareto front (--pareto): {0}")]
    NoTradeOff(String),
    /// Outside an allowed range.
    #[error("must be {range}, found {}", number(*value))]
    OutOfRange {
        /// The value.
        value: f64,
        /// The allowed range, in words.
        range: String,
    },
    /// Two alternative keys both given.
    #[error("give either `{0}` or `{1}`, not both")]
    BothGiven(String, String),
    /// Neither of two alternative keys given.
    #[error("give one of `{0}` or `{1}`")]
    NeitherGiven(String, String),
    /// A disk position off the shaft.
    #[error("disk position {position} m is outside the shaft (0 to {length} m)", position = crate::analysis::limits::number(*position), length = crate::analysis::limits::number(*length))]
    DiskOffShaft {
        /// m.
        position: f64,
        /// m.
        length: f64,
    },
    /// A disk node index that does not exist.
    #[error("disk node {node} does not exist: the shaft has nodes 0 to {last}")]
    DiskNodeOffShaft {
        /// The index.
        node: i64,
        /// The last node index n.
        last: usize,
    },
    /// More entries in an array of tables (`[[disks]]`, `[[circuit.branches]]`) than
    /// allowed.
    #[error("{count} entries, more than the {limit} allowed")]
    TooManyEntries {
        /// Entries found.
        count: usize,
        /// The limit.
        limit: usize,
    },
    /// The model would have more complex DOFs than the dense solvers are given
    /// ([`super::MAX_DOFS`]).
    #[error(
        "the model would have {dofs} complex DOFs (2 per shaft node, 2 for the rings, 2 per closed branch), more than the {limit} allowed"
    )]
    TooManyDofs {
        /// DOFs of the model.
        dofs: usize,
        /// The limit.
        limit: usize,
    },
    /// A support (`[[bearings]]`, `[[rings]]`) node index that does not exist.
    #[error("node {node} does not exist: the shaft has nodes 0 to {last}")]
    NodeOffShaft {
        /// The index.
        node: i64,
        /// The last node index Σ elements.
        last: usize,
    },
    /// A support position off the shaft.
    #[error("position {position} m is outside the shaft (0 to {length} m)", position = crate::analysis::limits::number(*position), length = crate::analysis::limits::number(*length))]
    PositionOffShaft {
        /// m.
        position: f64,
        /// The shaft's length (m).
        length: f64,
    },
    /// Two vibration rings at one node (bearings and seals may share a node with anything).
    #[error("node {node} already carries a vibration ring (`{first}`): two rings at one node (bearings and seals may share a node with a ring or with each other)")]
    SupportsShareNode {
        /// The node.
        node: usize,
        /// Key of the support that is there first, e.g. `bearings[0]`.
        first: String,
    },
    /// The supports leave the rotor free to move as a rigid body: the open-circuit
    /// stiffness at zero load is singular.
    #[error(
        "unsupported: rigid-body mode(s): {supports} support(s) with stiffness, at least 2 at distinct nodes are needed (a free rotor translates and tilts; one support lets it tilt about that node)"
    )]
    RigidBody {
        /// Supports with positive stiffness.
        supports: usize,
    },
    /// A direct stiffness (kxx, kyy) of a bearing or seal below zero.
    #[error("a direct stiffness must not be negative, found {} N/m{}", number(*value), at_speed(*speed))]
    NegativeStiffness {
        /// The value (N/m).
        value: f64,
        /// The table speed of the value (rad/s); `None` for a constant.
        speed: Option<f64>,
    },
    /// A bearing's or seal's damping matrix whose symmetric part is not positive
    /// semi-definite: some motion would draw energy from the support.
    #[error("the damping matrix [[cxx, cxy], [cyx, cyy]] = [[{}, {}], [{}, {}]] N s/m{} is not positive semi-definite: its symmetric part has the eigenvalue {} N s/m, so the support would feed energy into some motion", number(c[0][0]), number(c[0][1]), number(c[1][0]), number(c[1][1]), at_speed(*speed), number(*eigenvalue))]
    DampingNotSemiDefinite {
        /// The matrix (N·s/m).
        c: [[f64; 2]; 2],
        /// The smallest eigenvalue of its symmetric part (N·s/m).
        eigenvalue: f64,
        /// The table speed (rad/s); `None` for constants.
        speed: Option<f64>,
    },
    /// A bearing's or seal's coefficient far beyond the shaft's own scale, where the
    /// eigen-solution is no longer trustworthy (issue 50): a stiffness |k| above
    /// [`super::MAX_SUPPORT_STIFFNESS_RATIO`] times the shaft's stiffness scale
    /// ([`crate::model::Shaft::stiffness_scale`]), or a damping |c| above
    /// [`super::MAX_SUPPORT_DAMPING_RATIO`] times its damping scale √(K_s·M_s).
    #[error("{}", out_of_scale(coefficient, *value, *scale, *speed))]
    OutOfScale {
        /// The coefficient's key: a stiffness (`stiffness`, `kxx`, `kxy`, `kyx`, `kyy`) or
        /// a damping (`damping`, `cxx`, …).
        coefficient: &'static str,
        /// The value (N/m, or N·s/m).
        value: f64,
        /// The shaft's scale in the same unit (N/m, or N·s/m); the ratio admitted is
        /// [`super::MAX_SUPPORT_STIFFNESS_RATIO`] for a stiffness,
        /// [`super::MAX_SUPPORT_DAMPING_RATIO`] for a damping.
        scale: f64,
        /// The table speed of the value (rad/s); `None` for a constant.
        speed: Option<f64>,
    },
    /// The speeds of a coefficient table that do not increase strictly.
    #[error("the table speeds must increase strictly: speeds[{index}] = {} rad/s is not above speeds[{}] = {} rad/s", number(*speed), index - 1, number(*previous))]
    TableSpeedsNotIncreasing {
        /// Index of the offending speed.
        index: usize,
        /// Its value (rad/s).
        speed: f64,
        /// The speed before it (rad/s).
        previous: f64,
    },
    /// A coefficient array whose length differs from the support's `speeds`.
    #[error("{}", table_length(*values, *speeds))]
    TableLength {
        /// Values of the coefficient's array.
        values: usize,
        /// Speeds of the support's table (0: no `speeds` given).
        speeds: usize,
    },
    /// A coefficient table with more speeds than [`super::MAX_TABLE_POINTS`]: each
    /// evaluation of a tabulated coefficient costs time in proportion to its table's
    /// length.
    #[error("the table has {points} speeds, more than the {limit} a coefficient table may have (each evaluation at a speed costs time in proportion to the table's length)")]
    TableTooLong {
        /// Speeds of the table.
        points: usize,
        /// The limit, [`super::MAX_TABLE_POINTS`].
        limit: usize,
    },
    /// Several errors found at once (a bearing's and seal's coefficient checks report
    /// every one in the file): the first's text, then each of the others on a line of its
    /// own, as the command line prints errors.
    #[error("{first}{}", more.iter().map(|e| format!("\nerror: {e}")).collect::<String>())]
    Several {
        /// The first error's kind (the outer error carries its key and location).
        first: Box<ProblemErrorKind>,
        /// The others, each with its key and location.
        more: Box<[ProblemError]>,
    },
    /// An inner diameter not below the outer one.
    #[error("inner diameter {inner} m must be below the outer diameter {outer} m", inner = crate::analysis::limits::number(*inner), outer = crate::analysis::limits::number(*outer))]
    InnerNotBelowOuter {
        /// d (m).
        inner: f64,
        /// D (m).
        outer: f64,
    },
    /// The sections sum to no length (an empty `sections = []`), or their sum overflows.
    #[error("the sections sum to {total} m: a shaft needs a finite positive length", total = crate::analysis::limits::number(*total))]
    ShaftLength {
        /// The sum (m).
        total: f64,
    },
    /// A material or ring name that the file does not define.
    #[error("unknown {what} `{name}` (the file defines: {})", if known.is_empty() { "none".to_string() } else { known.join(", ") })]
    UnknownName {
        /// What the name names.
        what: NameOf,
        /// The name given.
        name: String,
        /// The names defined, in file order.
        known: Box<[String]>,
    },
    /// A name that cannot be used: defined twice, empty, or with characters other than
    /// letters, digits, `_` and `-` (names appear in labels such as `r1@drive`).
    #[error("name `{name}`: {reason}")]
    BadName {
        /// The name.
        name: String,
        /// Why.
        reason: String,
    },
    /// The shorthand and the general form given for one topic.
    #[error("give either the shorthand `{0}` or the general form `{1}`, not both")]
    MixedForms(String, String),
    /// A Timoshenko section whose material gives neither a shear modulus nor a Poisson's
    /// ratio.
    #[error("beam = \"timoshenko\" needs the shear modulus of {material}: give `shear_modulus` (Pa) or `poisson_ratio` there")]
    NoShearModulus {
        /// Where the section's material is given, e.g. ``material `steel` ([[materials]] entry 1)``.
        material: String,
    },
    /// A key of Timoshenko sections (`shear_coefficient`) on a Rayleigh section.
    #[error("`{0}` applies to Timoshenko sections only: give beam = \"timoshenko\" or remove it")]
    TimoshenkoOnly(String),
    /// C_p^S (given, or from k_eq2 by Eq. 1) not below C_p^T: physically impossible, a
    /// piezo stack's capacitance at constant strain is always below its capacitance at
    /// constant stress (C_p^S = C_p^T·(1 − k²), k its coupling factor).
    #[error("C_p^S = {cp_s:.4e} F is not below C_p^T = {cp_t:e} F, which is physically impossible: a piezo stack's capacitance at constant strain is below its capacitance at constant stress (C_p^S = C_p^T (1 - k^2), k its coupling factor){}", derivation(*angle_deg, *from_k_eq2))]
    ClampedCapacitance {
        /// C_p^S (F).
        cp_s: f64,
        /// C_p^T (F).
        cp_t: f64,
        /// The ring's angle β (degrees, as given).
        angle_deg: f64,
        /// k_eq2 (N/m), when C_p^S follows from it (C_p^S = 2cot²β·θ_p²/k_eq2).
        from_k_eq2: Option<f64>,
    },
    /// A design constraint on a whirl tag the model does not have at the lowest operating
    /// speed.
    #[error(
        "the model has no whirl mode `{mode}` at speed {speed} rad/s; its lowest modes there are {}",
        crate::analysis::tag_list(available)
    )]
    UnknownMode {
        /// The tag given.
        mode: String,
        /// The speed the tags are taken at (rad/s).
        speed: f64,
        /// The model's tags there, forward then backward, lowest first.
        available: Box<[String]>,
    },
    /// A closed circuit without branches.
    #[error("a closed circuit needs at least one [[circuit.branches]] entry")]
    NoBranches,
    /// A `--set` that does not apply.
    #[error("cannot apply --set {}: {reason}", super::source::one_line(text))]
    Override {
        /// The override text.
        text: String,
        /// Why.
        reason: String,
    },
}

/// What a name in a problem file names ([`ProblemErrorKind::UnknownName`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NameOf {
    /// A `[[materials]]` entry.
    Material,
    /// A ring (`[[rings]]` `name`; the shorthand's are `left` and `right`).
    Ring,
}

impl std::fmt::Display for NameOf {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            NameOf::Material => "material",
            NameOf::Ring => "ring",
        })
    }
}

/// A problem-file error with its location.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{file}{}: {}{kind}", where_(location), key_(key))]
pub struct ProblemError {
    /// The file name as given.
    pub file: String,
    /// Line of the key, or override.
    pub location: Location,
    /// Key path, e.g. `disks[0].mass`; empty for whole-file errors.
    pub key: String,
    /// What is wrong, with the value given.
    pub kind: ProblemErrorKind,
}

/// ` at speed S rad/s` of a table entry, or nothing.
fn at_speed(speed: Option<f64>) -> String {
    speed.map_or(String::new(), |w| format!(" at speed {} rad/s", number(w)))
}

/// The text of [`ProblemErrorKind::OutOfScale`]: the ratio, the scale and what it is,
/// and how a rigid support is modelled.
fn out_of_scale(coefficient: &str, value: f64, scale: f64, speed: Option<f64>) -> String {
    let sig = |x: f64| format!("{x:.4e}");
    let stiffness = coefficient == "stiffness" || coefficient.starts_with('k');
    let limit = if stiffness { super::MAX_SUPPORT_STIFFNESS_RATIO } else { super::MAX_SUPPORT_DAMPING_RATIO };
    let (unit, what, rigid) = if stiffness {
        (
            "N/m",
            "stiffness scale (the largest translational entry on the diagonal of its stiffness matrix)",
            format!(
                "a rigid support is modelled by a stiffness far above the shaft's within that ratio, not by {} N/m ({} N/m, 1e6 times the scale, already holds the node to about 1e-6 of a mode)",
                number(value),
                sig(1e6 * scale)
            ),
        )
    } else {
        (
            "N s/m",
            "damping scale sqrt(K_s M_s) (critical damping of its stiffest node)",
            "check the value and its unit (N s/m)".to_string(),
        )
    };
    format!(
        "{coefficient} = {} {unit}{} is {} times the shaft's own {what}, {} {unit}: beyond {} times it the eigen-solution is no longer trustworthy; {rigid}",
        number(value),
        at_speed(speed),
        sig(value.abs() / scale),
        sig(scale),
        crate::analysis::limits::compact(limit),
    )
}

/// The message of [`ProblemErrorKind::TableLength`].
fn table_length(values: usize, speeds: usize) -> String {
    if speeds == 0 {
        format!("an array of {values} values needs `speeds`, the table's speeds (rad/s), one per value")
    } else {
        format!("the array has {values} values but `speeds` has {speeds}: give one value per speed")
    }
}

impl ProblemErrorKind {
    /// The kind's name: the heading of its section in docs/errors.md and the name other
    /// front ends give it. Matched here, in the crate, so that a new kind has a name
    /// before it compiles (the enum is `#[non_exhaustive]` to users).
    pub fn name(&self) -> &'static str {
        use ProblemErrorKind as K;
        match self {
            K::Read(_) => "Read",
            K::NotARegularFile { .. } => "NotARegularFile",
            K::TooLarge { .. } => "TooLarge",
            K::TooComplex { .. } => "TooComplex",
            K::NotUtf8(_) => "NotUtf8",
            K::Empty => "Empty",
            K::Syntax(_) => "Syntax",
            K::Schema(_) => "Schema",
            K::Version { .. } => "Version",
            K::NotFinite(_) => "NotFinite",
            K::NotPositive(_) => "NotPositive",
            K::Negative(_) => "Negative",
            K::NoTradeOff(_) => "NoTradeOff",
            K::OutOfRange { .. } => "OutOfRange",
            K::BothGiven(..) => "BothGiven",
            K::NeitherGiven(..) => "NeitherGiven",
            K::DiskOffShaft { .. } => "DiskOffShaft",
            K::DiskNodeOffShaft { .. } => "DiskNodeOffShaft",
            K::TooManyEntries { .. } => "TooManyEntries",
            K::TooManyDofs { .. } => "TooManyDofs",
            K::NodeOffShaft { .. } => "NodeOffShaft",
            K::PositionOffShaft { .. } => "PositionOffShaft",
            K::SupportsShareNode { .. } => "SupportsShareNode",
            K::RigidBody { .. } => "RigidBody",
            K::NegativeStiffness { .. } => "NegativeStiffness",
            K::DampingNotSemiDefinite { .. } => "DampingNotSemiDefinite",
            K::OutOfScale { .. } => "OutOfScale",
            K::TableSpeedsNotIncreasing { .. } => "TableSpeedsNotIncreasing",
            K::TableLength { .. } => "TableLength",
            K::TableTooLong { .. } => "TableTooLong",
            K::Several { .. } => "Several",
            K::InnerNotBelowOuter { .. } => "InnerNotBelowOuter",
            K::ShaftLength { .. } => "ShaftLength",
            K::UnknownName { .. } => "UnknownName",
            K::BadName { .. } => "BadName",
            K::MixedForms(..) => "MixedForms",
            K::NoShearModulus { .. } => "NoShearModulus",
            K::TimoshenkoOnly(_) => "TimoshenkoOnly",
            K::ClampedCapacitance { .. } => "ClampedCapacitance",
            K::UnknownMode { .. } => "UnknownMode",
            K::NoBranches => "NoBranches",
            K::Override { .. } => "Override",
        }
    }
}

impl ProblemError {
    /// The errors this one stands for: itself, or, for [`ProblemErrorKind::Several`], the
    /// first (with the outer key and location) and the others.
    pub fn all(&self) -> Vec<ProblemError> {
        match &self.kind {
            ProblemErrorKind::Several { first, more } => {
                let mut v = vec![ProblemError { kind: (**first).clone(), ..self.clone() }];
                v.extend(more.iter().cloned());
                v
            }
            _ => vec![self.clone()],
        }
    }
}

/// How C_p^S was found, and the hint for an angle that looks like radians.
fn derivation(angle_deg: f64, from_k_eq2: Option<f64>) -> String {
    let mut s = match from_k_eq2 {
        Some(k) => {
            format!(
                "; here C_p^S = 2 cot^2(beta) theta_p^2 / k_eq2 with k_eq2 = {k:e} N/m and angle_deg = {}",
                number(angle_deg)
            )
        }
        None => String::new(),
    };
    if angle_deg <= std::f64::consts::FRAC_PI_2 {
        s += &format!(
            "; angle_deg is in degrees, and {a} looks like radians ({a} rad = {:.4} degrees)",
            angle_deg.to_degrees(),
            a = number(angle_deg)
        );
    }
    s
}

pub(super) fn where_(l: &Location) -> String {
    match l {
        Location::Line(n) => format!(", line {n}"),
        Location::Override => ", --set".to_string(),
        Location::Unknown => String::new(),
    }
}

pub(super) fn key_(k: &str) -> String {
    if k.is_empty() {
        String::new()
    } else {
        format!("key `{k}`: ")
    }
}

impl ProblemError {
    /// The 1-based line, when the key is in the file.
    pub fn line(&self) -> Option<usize> {
        match self.location {
            Location::Line(n) => Some(n),
            _ => None,
        }
    }
}

/// A parameter rule broken ([`crate::analysis::limits`]) as the file layer's kind: the
/// sign and finiteness rules keep their own kinds, the others are [`ProblemErrorKind::OutOfRange`]
/// with the rule's range. The message is the same text the rule gives.
impl From<&ParamError> for ProblemErrorKind {
    fn from(e: &ParamError) -> ProblemErrorKind {
        match e.rule {
            Rule::NotFinite => ProblemErrorKind::NotFinite(e.value),
            Rule::NotPositive => ProblemErrorKind::NotPositive(e.value),
            Rule::Negative => ProblemErrorKind::Negative(e.value),
            Rule::NotSet => ProblemErrorKind::Schema(format!("a required value ({:?}) was not set", e.quantity)),
            ref other => ProblemErrorKind::OutOfRange { value: e.value, range: other.range() },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{limits, Interval};

    #[test]
    fn a_broken_rule_reads_the_same_as_its_file_kind() {
        let errors = [
            limits::speed(f64::NAN).unwrap_err(),
            limits::beta_max(0.0).unwrap_err(),
            limits::speed(-1.0).unwrap_err(),
            limits::beta_max(1e300).unwrap_err(),
            limits::phi_range(1000.0, 500.0).unwrap_err(),
            limits::phi_range(1e-3, 1e3).unwrap_err(),
            limits::level(0.7, 0.5).unwrap_err(),
            limits::phi_op(1e9 / 1e3, Interval::new(1.0, 10.0)).unwrap_err(),
            limits::count(0, 1, 5).unwrap_err(),
        ];
        for e in errors {
            assert_eq!(ProblemErrorKind::from(&e).to_string(), e.to_string());
        }
    }
}
