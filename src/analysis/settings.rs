//! Analysis settings: plain struct, defaults written once, checked by [`Settings::validate`]
//! (the file layer for `[analysis]`, every analysis for a struct built in code).

use serde::{Deserialize, Serialize};

/// Default `oscillation_tolerance`: the |Im λ|/|λ| = √(1 − ζ²) at or below which a root
/// is overdamped, not a whirl. At this ratio ζ = 0.98514 and the logarithmic decrement
/// 2πζ/√(1 − ζ²) is 52·ln 2 ≈ 36.04: the root's motion falls below f64's resolution,
/// 2⁻⁵² of its start, within one period of its frequency, so it never completes a whirl
/// anyone could observe (1/√(1 + (52 ln 2/2π)²) = 0.171732). Such roots were listed as
/// whirls, and numbered first (issue 50): ROSS's compressor at rest had one of ζ =
/// 0.999996 as a forward whirl at 2.48 rad/s, `fig8-eta4000.toml` at 2000 rad/s four as
/// f1, f2, b1, b2. No root of a bundled problem at its speeds, nor of ROSS's reference
/// lists, comes near it (the most damped, 0.966, is a whirl of ROSS's compressor).
pub const OVERDAMPED_RATIO: f64 = 0.171732;

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
    /// |Im λ|/|λ| = √(1 − ζ²) at or below which an eigenvalue is non-oscillatory
    /// (overdamped) and is not a whirl (−); default [`OVERDAMPED_RATIO`].
    pub oscillation_tolerance: f64,
    /// Number of modes M of the reduced model used by the Floquet analysis (Eq. 22):
    /// `auto` (the default) sizes it by convergence ([`crate::analysis::basis`]): the
    /// basis is enlarged until the answers asked for move less than the convergence
    /// tolerance; a number fixes it (the paper's figures use 4 and 8).
    pub reduced_modes: ModeCount,
    /// Which modes make the reduced basis ([`Basis`]): `loaded` (the default) or the
    /// paper's `unloaded`.
    pub basis: Basis,
    /// Relative tolerance of the basis's convergence (−): an answer has converged when
    /// its band edges (and tongue edges) move by at most this fraction of the band's width
    /// (or `convergence_absolute`, whichever is larger) and its growths by this fraction of
    /// themselves, at the last enlargement of the basis.
    pub convergence_relative: f64,
    /// Absolute floor of the edges' convergence tolerance (rad/s).
    pub convergence_absolute: f64,
    /// Relative tolerance of the onsets' convergence (−): an onset has converged when it
    /// moves by at most this fraction of itself at the last enlargement of the basis.
    pub convergence_onset: f64,
    /// The paper's instability criterion (Eq. 28): unstable when max|μ| exceeds this.
    /// Unset by default: a point is then unstable when its growth per period exceeds the
    /// fast path's floor less the decay margin ([`crate::analysis::criterion`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub instability_tolerance: Option<f64>,
    /// σ_req, the decay margin (1/s): a point is unstable when its growth per period
    /// ln max|μ| exceeds ε − σ_req·T, so every mode must decay at least at this rate. 0
    /// (the default) asks only that nothing grows. Not with `instability_tolerance`.
    pub decay_margin: f64,
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

/// The number of modes of the reduced model: sized by convergence, or fixed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModeCount {
    /// Sized by convergence of the answers asked for (`"auto"` in a file).
    Auto,
    /// Exactly this many modes M (a whole number in a file).
    Fixed(usize),
}

impl ModeCount {
    /// The fixed count, if there is one.
    pub fn fixed(&self) -> Option<usize> {
        match self {
            ModeCount::Auto => None,
            ModeCount::Fixed(m) => Some(*m),
        }
    }
}

impl Serialize for ModeCount {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            ModeCount::Auto => s.serialize_str("auto"),
            ModeCount::Fixed(m) => s.serialize_u64(*m as u64),
        }
    }
}

impl<'de> Deserialize<'de> for ModeCount {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Visit;
        impl serde::de::Visitor<'_> for Visit {
            type Value = ModeCount;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a whole number of modes or \"auto\"")
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<ModeCount, E> {
                usize::try_from(v).map(ModeCount::Fixed).map_err(|_| E::custom(format!("{v} modes is too many")))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<ModeCount, E> {
                u64::try_from(v)
                    .map_err(|_| E::invalid_value(serde::de::Unexpected::Signed(v), &self))
                    .and_then(|v| self.visit_u64(v))
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<ModeCount, E> {
                if v == "auto" {
                    Ok(ModeCount::Auto)
                } else {
                    Err(E::invalid_value(serde::de::Unexpected::Str(v), &self))
                }
            }
        }
        d.deserialize_any(Visit)
    }
}

/// Which modes the reduced basis of the Floquet analysis is made of (Eq. 22).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Basis {
    /// The undamped modes of (K − αP_cr·S, M) at Ω = 0: the system under its static
    /// load, whose answers converge with fewer modes (docs/decisions.md, "The basis").
    Loaded,
    /// The paper's: the undamped modes of (K, M) at Ω = 0 without axial load.
    Unloaded,
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

/// Most modes a reduced model may keep, fixed or sized by convergence.
pub const MAX_REDUCED_MODES: usize = 200;

impl Settings {
    /// The rule that makes a point unstable ([`crate::analysis::criterion::Threshold`]):
    /// the paper's tolerance on max|μ| when one is set, the growth rule otherwise.
    pub fn threshold(&self) -> crate::analysis::criterion::Threshold {
        use crate::analysis::criterion::{Threshold, PATH_FLOOR};
        match self.instability_tolerance {
            Some(tolerance) => Threshold::Multiplier { tolerance },
            None => Threshold::Growth { floor: PATH_FLOOR, decay_margin: self.decay_margin },
        }
    }

    /// These settings with the reduced model fixed at `modes` modes.
    pub fn with_modes(&self, modes: usize) -> Settings {
        Settings { reduced_modes: ModeCount::Fixed(modes), ..self.clone() }
    }
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
        if let Some(t) = self.instability_tolerance {
            within("instability_tolerance", t, 1.0, f64::INFINITY, "above 1")?;
        }
        floor("decay_margin", self.decay_margin)?;
        if self.decay_margin > 0.0 && self.instability_tolerance.is_some() {
            let range = "0 when instability_tolerance is set (two criteria: keep one)".to_string();
            return err("decay_margin", SettingsRule::OutOfRange { value: self.decay_margin, range });
        }
        if self.decay_margin > 0.0 && self.min_growth_rate > 0.0 {
            let range = "0 when decay_margin is set (a margin on decay and a floor on growth contradict)".to_string();
            return err("min_growth_rate", SettingsRule::OutOfRange { value: self.min_growth_rate, range });
        }
        if let ModeCount::Fixed(m) = self.reduced_modes {
            count("reduced_modes", m, 1, MAX_REDUCED_MODES)?;
        }
        within("convergence_relative", self.convergence_relative, 0.0, 1.0, "in (0, 1)")?;
        within("convergence_absolute", self.convergence_absolute, 0.0, f64::INFINITY, "above 0 rad/s")?;
        within("convergence_onset", self.convergence_onset, 0.0, 1.0, "in (0, 1)")?;
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
            // Damping ratios up to 0.98514 count as whirls; beyond, a root decays below
            // f64's resolution within one period.
            oscillation_tolerance: OVERDAMPED_RATIO,
            // Sized by convergence; the paper's files fix M = 4 (open, Ω = 0) and M = 8
            // (closed) with the unloaded basis.
            reduced_modes: ModeCount::Auto,
            basis: Basis::Loaded,
            // The tolerance on band edges: 0.25 % of the band's width, at least
            // 0.5 rad/s (four cells of the edges' 0.125 rad/s lattice).
            convergence_relative: 0.0025,
            convergence_absolute: 0.5,
            // 1 %: twice the onset search's own repeatability on a thin higher-order
            // tongue (the f2+s2 (k = 2) onset of the Fig. 11 rotor is found at 0.2913 and
            // 0.2928 on bases that agree to 1e-3 rad/s in its edges, 0.5 % apart); a load
            // margin of +30 % then holds to ±0.3 points.
            convergence_onset: 0.01,
            // The growth criterion (ln max|μ| above the path's floor), no decay margin.
            instability_tolerance: None,
            decay_margin: 0.0,
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
