//! Errors of the ROSS importer: each names the file and, for a refusal, the ROSS element
//! (class, tag and node) and why rotorshunt cannot represent it.

use thiserror::Error;

/// A ROSS rotor file that cannot be imported.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{file}: {kind}")]
pub struct RossError {
    /// The ROSS file as given.
    pub file: String,
    /// What is wrong.
    pub kind: RossErrorKind,
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
    #[error("not a ROSS rotor file: `{key}`: {message}")]
    Schema {
        /// Key path, e.g. `["ShaftElement_Shaft Element 0"].L`.
        key: String,
        /// What is wrong.
        message: String,
    },
    /// An element (or the rotor as a whole) that rotorshunt cannot represent (boxed:
    /// the refusals carry their values).
    #[error("{} cannot be imported: {reason}", element_text(element))]
    Refused {
        /// The element; `None` for the rotor as a whole (e.g. no bearing).
        element: Option<Box<ElementRef>>,
        /// Why.
        reason: Box<Refusal>,
    },
}

/// A ROSS element as messages name it: its class, its tag and its node.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ElementRef {
    /// ROSS class, e.g. `ShaftElement`, `BearingElement`, `PointMass`.
    pub class: String,
    /// The element's tag (ROSS's name for it, unique in a rotor).
    pub tag: String,
    /// The element's `n` (a shaft element's number and left node, or a node).
    pub n: Option<i64>,
}

impl std::fmt::Display for ElementRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} \"{}\"", self.class, self.tag)?;
        if let Some(n) = self.n {
            write!(f, " (n = {n})")?;
        }
        Ok(())
    }
}

/// Why an element cannot be imported. Values are SI (m, kg, N/m, N·s/m, rad/s).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum Refusal {
    /// A class other than `ShaftElement`, `DiskElement` and `BearingElement`.
    #[error("rotorshunt imports ShaftElement, DiskElement and BearingElement only; a {0} has no equivalent")]
    UnknownClass(String),
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
    /// the outer one).
    #[error("{key} = {value}: {rule}", value = crate::analysis::limits::number(*value))]
    Value {
        /// The key.
        key: String,
        /// Its value.
        value: f64,
        /// The rule, e.g. "must be finite and > 0".
        rule: String,
    },
    /// Different coefficients in x and y.
    #[error("{x_key} = {x} {unit} but {y_key} = {y} {unit}: an anisotropic support, and rotorshunt's complex-coordinate model needs isotropic ones", x = crate::analysis::limits::number(*x), y = crate::analysis::limits::number(*y))]
    Anisotropic {
        /// `kxx`, `cxx` or `mxx`.
        x_key: &'static str,
        /// Its value (the first tabulated value that differs).
        x: f64,
        /// `kyy`, `cyy` or `myy`.
        y_key: &'static str,
        /// Its value.
        y: f64,
        /// Unit of both.
        unit: &'static str,
    },
    /// A non-zero cross-coupling coefficient.
    #[error("{key} = {value} {unit}: a cross-coupled support, and rotorshunt's bearings have no cross terms", value = crate::analysis::limits::number(*value))]
    CrossCoupled {
        /// `kxy`, `kyx`, `cxy`, `cyx`, `mxy` or `myx`.
        key: &'static str,
        /// Its value (the first non-zero one).
        value: f64,
        /// Its unit.
        unit: &'static str,
    },
    /// Coefficients tabulated against frequency, and no speed chosen.
    #[error("its coefficients are tabulated at {points} frequencies from {lo} to {hi} rad/s: they depend on the speed, so give --speed Ω (rad/s) to evaluate them at Ω as ROSS's run_modal does", lo = crate::analysis::limits::number(*lo), hi = crate::analysis::limits::number(*hi))]
    SpeedDependent {
        /// Table length.
        points: usize,
        /// Lowest tabulated frequency (rad/s).
        lo: f64,
        /// Highest (rad/s).
        hi: f64,
    },
    /// The chosen speed is outside the bearing's table.
    #[error("--speed {speed} rad/s is outside its table of coefficients, {lo} to {hi} rad/s, and ROSS's extrapolated spline is not imported: choose a speed inside the table or extend the table in ROSS", speed = crate::analysis::limits::number(*speed), lo = crate::analysis::limits::number(*lo), hi = crate::analysis::limits::number(*hi))]
    OutsideTable {
        /// The chosen speed (rad/s).
        speed: f64,
        /// Lowest tabulated frequency (rad/s).
        lo: f64,
        /// Highest (rad/s).
        hi: f64,
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
    /// A rotor without bearings.
    #[error("the rotor has no BearingElement: a free-free rotor has rigid-body modes (ROSS drops them silently), and rotorshunt refuses an unsupported rotor")]
    NoBearing,
}

fn line_text(line: Option<usize>) -> String {
    line.map(|l| format!(", line {l}")).unwrap_or_default()
}

fn element_text(element: &Option<Box<ElementRef>>) -> String {
    match element {
        Some(e) => format!("ROSS {e}"),
        None => "the ROSS rotor".into(),
    }
}
