//! Analysis settings: plain struct, defaults written once, checked by [`Settings::validate`]
//! (the file layer for `[analysis]`, every analysis for a struct built in code).

use serde::{Deserialize, Serialize};

/// Numerical policies of the analyses, recorded in every output.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Settings {
    /// Minimum modal assurance criterion for a Campbell track to continue from one speed
    /// to the next (−). Below it the track is flagged as a possible mode crossing or swap.
    pub mac_threshold: f64,
    /// Share of a mode's kinetic energy in the shunt charge DOFs above which it is
    /// labelled electrical (−).
    pub electrical_fraction: f64,
    /// |Im λ|/|λ| below which an eigenvalue is non-oscillatory (overdamped) and is not a
    /// whirl (−).
    pub oscillation_tolerance: f64,
    /// Number of modes M of the reduced model used by the Floquet analysis (Eq. 22).
    pub reduced_modes: usize,
    /// The paper's instability criterion: unstable when max|μ| exceeds this (Eq. 28).
    pub instability_tolerance: f64,
    /// Growth-rate floor σ_min of the declared criterion (1/s): an unstable point whose
    /// growth rate ln(max|μ|)/T is below it does not count in stable bands, designs and
    /// studies (it is listed as ignored). 0 keeps the paper's criterion.
    pub min_growth_rate: f64,
    /// Smallest width at β_op (rad/s) of a tongue that counts in stable bands, designs and
    /// studies; narrower ones are listed as ignored. 0 keeps the paper's criterion.
    pub min_tongue_width: f64,
    /// Highest order k of the tongues (ω_i + ω_j)/k searched at β_op: the stable bands are
    /// complete up to this order (the stated guarantee).
    pub max_tongue_order: usize,
    /// Monodromy path used by charts and points.
    pub method: MonodromyMethod,
    /// CFM4 steps per period of the fast path (minimum; doubled automatically where the
    /// per-φ interpolant needs it).
    pub steps_per_period: usize,
    /// Steps per period of the reference DSTM path (Eq. 26–27).
    pub reference_steps: usize,
    /// Largest phase of the lowest basis mode over one CFM4 step (rad): long periods
    /// (low φ) get more steps, h ≤ max_step_phase/ω_min.
    pub max_step_phase: f64,
    /// `auto` (the complex coordinates u = v + jw where the supports are isotropic, the
    /// real coordinates (v, w) otherwise) or `real` (the real coordinates always: the
    /// general path, e.g. to check it against the complex one).
    #[serde(default, skip_serializing_if = "is_auto")]
    pub coordinates: crate::model::Coordinates,
}

fn is_auto(c: &crate::model::Coordinates) -> bool {
    *c == crate::model::Coordinates::Auto
}

/// Which monodromy path to use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MonodromyMethod {
    /// CFM4 with per-φ Chebyshev exponentials and the half-period symmetry.
    Fast,
    /// The paper's discrete state transition matrix (Eq. 26–27).
    Dstm,
}

/// Highest tongue order the search may be asked for: orders cost a few evaluations per
/// pair each, and beyond 32 the tongues of any physical rotor are thinner than any φ
/// tolerance (their width shrinks like β^k).
pub const MAX_TONGUE_ORDER: usize = 32;

/// A setting that breaks its rule: the field (as in `[analysis]`) and the rule.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("analysis.{field}: {rule}")]
pub struct SettingsError {
    /// The field, e.g. `steps_per_period`.
    pub field: &'static str,
    /// The rule broken, with the value.
    pub rule: SettingsRule,
}

/// The rule a setting breaks (the words are those of the file layer's kinds of the same
/// names).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SettingsRule {
    /// NaN or infinite.
    #[error("must be a finite number, found {}", crate::analysis::limits::number(*.0))]
    NotFinite(f64),
    /// Negative where a floor is asked.
    #[error("must not be negative, found {}", crate::analysis::limits::number(*.0))]
    Negative(f64),
    /// Outside its range, described in words.
    #[error("must be {range}, found {}", crate::analysis::limits::number(*value))]
    OutOfRange {
        /// The value given.
        value: f64,
        /// The range, e.g. `in (0, 1]`.
        range: String,
    },
}

impl SettingsRule {
    /// The error kind, named as docs/errors.md heads it (the file layer's kind of the
    /// same rule).
    pub fn kind(&self) -> &'static str {
        match self {
            SettingsRule::NotFinite(_) => "NotFinite",
            SettingsRule::Negative(_) => "Negative",
            SettingsRule::OutOfRange { .. } => "OutOfRange",
        }
    }
}

impl Settings {
    /// Check every setting against its rule, in field order; the first broken is
    /// returned. Every analysis that takes settings runs this check, so a struct built in
    /// code is held to the rules of the `[analysis]` table.
    pub fn validate(&self) -> Result<(), SettingsError> {
        let err = |field, rule| Err(SettingsError { field, rule });
        let within = |field: &'static str, v: f64, lo: f64, hi: f64, range: &str| -> Result<(), SettingsError> {
            if !v.is_finite() {
                return err(field, SettingsRule::NotFinite(v));
            }
            if v > lo && v < hi {
                Ok(())
            } else {
                err(field, SettingsRule::OutOfRange { value: v, range: range.into() })
            }
        };
        let count = |field: &'static str, v: usize, lo: usize, hi: usize| -> Result<(), SettingsError> {
            if (lo..=hi).contains(&v) {
                Ok(())
            } else {
                let range = format!("a whole number from {lo} to {hi}");
                err(field, SettingsRule::OutOfRange { value: v as f64, range })
            }
        };
        let floor = |field: &'static str, v: f64| -> Result<(), SettingsError> {
            match v {
                v if !v.is_finite() => err(field, SettingsRule::NotFinite(v)),
                v if v < 0.0 => err(field, SettingsRule::Negative(v)),
                _ => Ok(()),
            }
        };
        within("mac_threshold", self.mac_threshold, 0.0, 1.0 + 1e-12, "in (0, 1]")?;
        within("electrical_fraction", self.electrical_fraction, 0.0, 1.0, "in (0, 1)")?;
        within("oscillation_tolerance", self.oscillation_tolerance, 0.0, 1.0, "in (0, 1)")?;
        within("max_step_phase", self.max_step_phase, 0.0, 10.0, "in (0, 10) rad")?;
        within("instability_tolerance", self.instability_tolerance, 1.0, f64::INFINITY, "above 1")?;
        count("reduced_modes", self.reduced_modes, 1, 200)?;
        count("steps_per_period", self.steps_per_period, 2, 1 << 16)?;
        count("reference_steps", self.reference_steps, 2, 1 << 20)?;
        // The criterion's floors: 0 (nothing ignored) up to any finite value.
        floor("min_growth_rate", self.min_growth_rate)?;
        floor("min_tongue_width", self.min_tongue_width)?;
        count("max_tongue_order", self.max_tongue_order, 1, MAX_TONGUE_ORDER)
    }
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            // 0.9: neighbouring speeds of a reasonable step change a mode shape little;
            // distinct modes of the same whirl direction have MAC ≪ 0.9.
            mac_threshold: 0.9,
            electrical_fraction: 0.5,
            // Damping ratios up to 1 − 1e-12 still count as whirls.
            oscillation_tolerance: 1e-9,
            // The paper reduces to M = 4 (open, Ω = 0) and M = 8 (closed); 8 covers both.
            reduced_modes: 8,
            instability_tolerance: 1.0001,
            // Nothing ignored: the paper's criterion as it stands.
            min_growth_rate: 0.0,
            min_tongue_width: 0.0,
            // 8: the f1+b1 tongues of the paper's rotor reach β = 0.3 up to order 7 in
            // φ ≥ 100 rad/s; each order costs a few evaluations per pair and order.
            max_tongue_order: 8,
            method: MonodromyMethod::Fast,
            // 32 CFM4 steps: max|μ| within 1e-6 of a converged reference at every tested
            // point of the paper's problems, and within 1e-5 of 4× finer on the Fig. 11
            // grid (tests/floquet_paths.rs, tests/convergence.rs).
            steps_per_period: 32,
            // The DSTM is second order: 4096 steps give ~1e-8 on the paper's problems.
            reference_steps: 4096,
            // The parametric coupling of the reduced model scales like its lowest whirl
            // frequency (P_cr·S̃_kk/ω_k ≈ ω₁ for beam modes), so bounding h·ω_min bounds the
            // CFM4 error whatever φ: 0.125 rad keeps the Fig. 11 grid within 1e-5 of 4× finer
            // (measured worst 2.5e-5 at 0.2 rad, 3e-4 at 0.3).
            max_step_phase: 0.125,
            coordinates: crate::model::Coordinates::Auto,
        }
    }
}
