//! Errors of the ROSS importer: each names the file and, for a refusal, the ROSS element
//! (class, tag and node) and why rotorshunt cannot represent it.

use thiserror::Error;

/// A ROSS rotor file that cannot be imported. Its text is `FILE: what`; when several
/// elements are refused, each further one follows on a line of its own as
/// `error: FILE: what`, as the command line prints errors.
#[derive(Debug, Clone, PartialEq)]
pub struct RossError {
    /// The ROSS file as given.
    pub file: String,
    /// What is wrong.
    pub kind: RossErrorKind,
}

impl std::fmt::Display for RossError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.file, self.kind)?;
        if let RossErrorKind::Refused { more, .. } = &self.kind {
            for r in more.iter() {
                write!(f, "\nerror: {}: {r}", self.file)?;
            }
        }
        Ok(())
    }
}

impl std::error::Error for RossError {}

/// One refused element (or the rotor as a whole) and why.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{} cannot be imported: {reason}", element_text(element))]
pub struct Refused {
    /// The element; `None` for the rotor as a whole (e.g. no bearing).
    pub element: Option<Box<ElementRef>>,
    /// Why.
    pub reason: Box<Refusal>,
}

/// The two text formats of ROSS's `Rotor.save`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// `.toml`.
    Toml,
    /// `.json`.
    Json,
}

impl std::fmt::Display for Format {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Format::Toml => "TOML",
            Format::Json => "JSON",
        })
    }
}

/// What is wrong with a ROSS file.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum RossErrorKind {
    /// The text is not valid TOML or JSON.
    #[error("{format} syntax error{}: {message}", line_text(*line))]
    Syntax {
        /// The format the file was read as.
        format: Format,
        /// 1-based line, when the parser gives one.
        line: Option<usize>,
        /// The parser's message.
        message: String,
    },
    /// Valid text, but not a rotor as ROSS 2.3.0's `Rotor.save` writes it: a missing or
    /// unknown key, a value of the wrong type, a table name without its class.
    #[error("not a ROSS rotor file{}: `{key}`: {message}", line_text(*line))]
    Schema {
        /// Key path, e.g. `["ShaftElement_Shaft Element 0"].L`.
        key: String,
        /// 1-based line of the element's table, when known.
        line: Option<usize>,
        /// What is wrong.
        message: String,
    },
    /// Elements (or the rotor as a whole) that rotorshunt cannot represent: the first
    /// (boxed: the refusals carry their values), and every other one found in the file,
    /// in the order shaft elements (by `n`), disks, point masses, bearings and seals (by
    /// `n`), other classes, the rotor.
    #[error("{} cannot be imported: {reason}", element_text(element))]
    Refused {
        /// The element; `None` for the rotor as a whole (e.g. no bearing).
        element: Option<Box<ElementRef>>,
        /// Why.
        reason: Box<Refusal>,
        /// The other refusals of the file.
        more: Box<[Refused]>,
    },
}

impl RossErrorKind {
    /// The kind's name, as docs/errors.md heads its section.
    pub fn name(&self) -> &'static str {
        match self {
            RossErrorKind::Syntax { .. } => "RossSyntax",
            RossErrorKind::Schema { .. } => "RossSchema",
            RossErrorKind::Refused { .. } => "RossRefused",
        }
    }
}

/// A ROSS element as messages name it: its class, its tag, its node and the line of its
/// table.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ElementRef {
    /// ROSS class, e.g. `ShaftElement`, `BearingElement`, `PointMass`.
    pub class: String,
    /// The element's tag (ROSS's name for it, unique in a rotor).
    pub tag: String,
    /// The element's `n` (a shaft element's number and left node, or a node).
    pub n: Option<i64>,
    /// 1-based line of the element's table in the file, when known.
    pub line: Option<usize>,
}

impl std::fmt::Display for ElementRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} \"{}\"", self.class, self.tag)?;
        match (self.n, self.line) {
            (Some(n), Some(l)) => write!(f, " (n = {n}, line {l})"),
            (Some(n), None) => write!(f, " (n = {n})"),
            (None, Some(l)) => write!(f, " (line {l})"),
            (None, None) => Ok(()),
        }
    }
}

/// Why an element cannot be imported. Values are SI (m, kg, N/m, N·s/m, rad/s).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum Refusal {
    /// A class the importer does not read.
    #[error("rotorshunt imports ShaftElement, DiskElement, PointMass, BearingElement, SealElement, BallBearingElement, RollerBearingElement and CylindricalBearing; a {0} is not read (its saved form was not checked against ROSS): rebuild it in ROSS as a BearingElement or SealElement with its coefficients")]
    UnknownClass(String),
    /// A magnetic bearing (its controller's parameters are in the table).
    #[error("a magnetic bearing: ROSS saves its control loop (kp_pid, kd_pid, ki_pid, g0, i0, …) and gives run_modal the controller's frequency response taken at the spin speed; rotorshunt has no control loop, and its Floquet analysis would apply those coefficients at every frequency of the motion")]
    Magnetic,
    /// A `shear_method_calc` other than ROSS's `cowper` and `hutchinson`.
    #[error(
        "shear_method_calc = \"{0}\": ROSS 2.3.0 computes the shear coefficient by \"cowper\" or \"hutchinson\" only"
    )]
    ShearMethod(String),
    /// `rotary_inertia = false` or `gyroscopic = false`.
    #[error("{0} = false, but rotorshunt's beam elements always have rotary inertia and gyroscopic effects: build it in ROSS with {0}=True")]
    EffectOff(&'static str),
    /// A static axial force or torque.
    #[error("{key} = {value} {unit}: a static preload whose stiffness ROSS adds to K; rotorshunt's axial load is the problem's P(t) ([load])", value = crate::analysis::limits::number(*value))]
    Preload {
        /// `axial_force` or `torque`.
        key: &'static str,
        /// Its value.
        value: f64,
        /// `N` or `N·m`.
        unit: &'static str,
    },
    /// Proportional shaft damping.
    #[error(
        "{key} = {value}: proportional damping of the shaft (C = alpha·M + beta·K), which rotorshunt does not model",
        value = crate::analysis::limits::number(*value)
    )]
    ShaftDamping {
        /// `alpha` or `beta`.
        key: &'static str,
        /// Its value.
        value: f64,
    },
    /// Shaft element numbers that are not 0…N−1, each once.
    #[error("{0}")]
    Numbering(String),
    /// A value out of its range (not finite, not positive, an inner diameter not below
    /// the outer one, a table that does not increase, an array of another length).
    #[error("{key} = {value}: {rule}", value = crate::analysis::limits::number(*value))]
    Value {
        /// The key.
        key: String,
        /// Its value.
        value: f64,
        /// The rule, e.g. "must be finite and > 0".
        rule: String,
    },
    /// A negative direct stiffness of a bearing or seal.
    #[error("{key} = {value} N/m{}: a negative direct stiffness, which rotorshunt's supports refuse (docs/errors.md, NegativeStiffness)", at_frequency(*frequency), value = crate::analysis::limits::number(*value))]
    NegativeStiffness {
        /// `kxx` or `kyy`.
        key: &'static str,
        /// Its value (N/m).
        value: f64,
        /// The tabulated frequency (rad/s), for a table.
        frequency: Option<f64>,
    },
    /// A damping matrix whose symmetric part is not positive semi-definite.
    #[error("[[cxx, cxy], [cyx, cyy]] = [[{}, {}], [{}, {}]] N·s/m{}: its symmetric part has the eigenvalue {} < 0, so the support would feed energy into some motion, which rotorshunt's supports refuse (docs/errors.md, DampingNotSemiDefinite)", n(c[0][0]), n(c[0][1]), n(c[1][0]), n(c[1][1]), at_frequency(*frequency), n(*eigenvalue))]
    DampingNotSemiDefinite {
        /// The damping matrix (N·s/m).
        c: [[f64; 2]; 2],
        /// The smallest eigenvalue of its symmetric part (N·s/m).
        eigenvalue: f64,
        /// The tabulated frequency (rad/s), for a table.
        frequency: Option<f64>,
    },
    /// A support mass rotorshunt cannot hold: it lumps one constant mass at the node,
    /// the same in x and y.
    #[error(
        "{0}: rotorshunt lumps one constant mass at a support's node, the same in x and y (mxx = myy, mxy = myx = 0)"
    )]
    SupportMass(String),
    /// A point mass with different masses in x and y.
    #[error("mx = {mx} kg but my = {my} kg: rotorshunt's node masses are the same in x and y", mx = crate::analysis::limits::number(*mx), my = crate::analysis::limits::number(*my))]
    PointMassAnisotropic {
        /// Mass in x (kg).
        mx: f64,
        /// Mass in y (kg).
        my: f64,
    },
    /// A bearing linked to another node (`n_link`).
    #[error("n_link = {0}: the bearing connects node n to node {0} (a pedestal), not to the ground, and rotorshunt's bearings are grounded")]
    Linked(i64),
    /// A disk or bearing at a node that is not on the shaft.
    #[error("node {node} is not on the shaft, whose nodes are 0 to {last}")]
    NodeOffShaft {
        /// The node.
        node: i64,
        /// The last shaft node.
        last: i64,
    },
    /// A point mass beyond the shaft's last node: a pedestal, with DOFs of its own.
    #[error("node {node} is beyond the shaft's last node {last}: a point mass there is a pedestal, a node of its own that an n_link bearing ties to the shaft, and rotorshunt's supports have no DOFs of their own")]
    Pedestal {
        /// The node.
        node: i64,
        /// The last shaft node.
        last: i64,
    },
    /// More shaft elements than a problem may have ([`crate::problem::MAX_ELEMENTS`]),
    /// counted as the file is read, before any element is converted.
    #[error("{count} shaft elements (the distinct n of its ShaftElement tables), more than the {limit} a problem's shaft may have (MAX_ELEMENTS: the dense eigensolvers' cost grows as the cube of the model's size); refused before any element was converted")]
    TooManyElements {
        /// Shaft elements in the file.
        count: usize,
        /// The limit, [`crate::problem::MAX_ELEMENTS`].
        limit: usize,
    },
    /// A rotor without bearings.
    #[error("the rotor has no BearingElement or SealElement: a free-free rotor has rigid-body modes (ROSS drops them silently), and rotorshunt refuses an unsupported rotor")]
    NoBearing,
}

fn line_text(line: Option<usize>) -> String {
    line.map(|l| format!(", line {l}")).unwrap_or_default()
}

fn at_frequency(frequency: Option<f64>) -> String {
    frequency.map(|w| format!(" at the tabulated frequency {} rad/s", n(w))).unwrap_or_default()
}

fn n(v: f64) -> String {
    crate::analysis::limits::number(v)
}

fn element_text(element: &Option<Box<ElementRef>>) -> String {
    match element {
        Some(e) => format!("ROSS {e}"),
        None => "the ROSS rotor".into(),
    }
}
