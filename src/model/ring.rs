//! The vibration ring, its piezo stacks and the current-flowing shunt (Eq. 1–4, A8).

use serde::Serialize;

/// One vibration ring with its bearing, at one shaft end (Eq. 1, 7–10). SI units.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Ring {
    /// Radial bearing stiffness k_b (N/m).
    pub k_b: f64,
    /// Equivalent mass of bearing and ring m_b (kg).
    pub m_b: f64,
    /// Mechanical damping η between shaft end and ring (N·s/m).
    pub eta: f64,
    /// Stiffness of the ring's mechanical structure k_1 (N/m).
    pub k_1: f64,
    /// Compression stiffness of one piezo stack k_2 (N/m).
    pub k_2: f64,
    /// Structural angle β of the ring (rad).
    pub angle: f64,
    /// Generalised electromechanical coupling coefficient θ_p (C/m).
    pub theta_p: f64,
    /// Stack capacitance at constant stress C_p^T (F), used by Eq. (4).
    pub cp_t: f64,
    /// Stack capacitance at constant strain C_p^S (F).
    pub cp_s: f64,
}

impl Ring {
    fn cot2(&self) -> f64 {
        let t = self.angle.tan();
        1.0 / (t * t)
    }

    /// Series stiffness of bearing and ring structure, k_eq of Eq. (1) (N/m).
    pub fn k_eq(&self) -> f64 {
        let c2 = self.angle.cos().powi(2);
        2.0 * self.k_1 * self.k_b * c2 / (self.k_b + 2.0 * self.k_1 * c2)
    }

    /// Piezo stack stiffness k_eq1 = 2·k_2·cot²β of Eq. (1) (N/m).
    pub fn k_eq1(&self) -> f64 {
        2.0 * self.k_2 * self.cot2()
    }

    /// Electromechanical coupling stiffness k_eq2 = 2·cot²β·θ_p²/C_p^S of Eq. (1) (N/m).
    pub fn k_eq2(&self) -> f64 {
        self.gamma() / self.cp_s
    }

    /// Scaling γ = 2·cot²β·θ_p² that symmetrises the shunt equations (Eq. A8), (V·m/C)·… so
    /// that γ·L is a mass (kg), γ·R a damping (N·s/m) and γ/C a stiffness (N/m).
    pub fn gamma(&self) -> f64 {
        2.0 * self.cot2() * self.theta_p * self.theta_p
    }

    /// C_p^S implied by a given k_eq2 (inverse of Eq. 1), F.
    pub fn cp_s_from_k_eq2(angle: f64, theta_p: f64, k_eq2: f64) -> f64 {
        let t = angle.tan();
        2.0 / (t * t) * theta_p * theta_p / k_eq2
    }
}

/// The state of the shunt circuits (section 3.1, docs/model.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CircuitState {
    /// Z_e → ∞: no charge flows, the ring is grounded by k_eq1 + k_eq2.
    Open,
    /// Z_e = 0: q̃ = a, the ring is grounded by k_eq1 alone.
    Short,
    /// N current-flowing branches, each adding one charge DOF per ring (Eq. A8).
    Closed,
}

impl std::fmt::Display for CircuitState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            CircuitState::Open => "open",
            CircuitState::Short => "short",
            CircuitState::Closed => "closed",
        })
    }
}

/// One branch of the current-flowing shunt (Fig. 15): C_f, L and R in series.
///
/// Two branches are equal when their C_f, L and R are: how the input gave L
/// ([`Branch::given`]) is not physics.
#[derive(Debug, Clone, Serialize)]
pub struct Branch {
    /// Filtering capacitance C_f (F).
    pub c_f: f64,
    /// Branch inductance L = L_t + L_f (H); may be 0 (a massless charge DOF).
    pub inductance: f64,
    /// Branch resistance R (Ω).
    pub resistance: f64,
    /// What the input held of the inductance: L itself, or the tuning frequency ω of
    /// Eq. (4), which [`Branch::set`] keeps when C_f changes.
    #[serde(skip)]
    pub given: Given,
}

impl PartialEq for Branch {
    fn eq(&self, other: &Branch) -> bool {
        self.c_f == other.c_f && self.inductance == other.inductance && self.resistance == other.resistance
    }
}

/// What the input held of a branch's inductance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Given {
    /// L itself (H).
    Inductance,
    /// The tuning frequency ω (rad/s) of Eq. (4): L follows from ω, C_f and C_p^T.
    TuningFrequency(f64),
}

/// A circuit parameter of a branch, as a design varies it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Parameter {
    /// Filtering capacitance C_f (F); searched on a log scale.
    CF,
    /// Inductance L (H); log scale.
    Inductance,
    /// Tuning frequency ω of Eq. (4) (rad/s), L following from it; log scale.
    TuningFrequency,
    /// Resistance R (Ω); linear scale (it may be 0).
    Resistance,
}

impl Parameter {
    /// The key of the parameter in `[[circuit.branches]]`.
    pub fn key(self) -> &'static str {
        match self {
            Parameter::CF => "c_f",
            Parameter::Inductance => "inductance",
            Parameter::TuningFrequency => "tuning_frequency",
            Parameter::Resistance => "resistance",
        }
    }

    /// Unit, for reports.
    pub fn unit(self) -> &'static str {
        match self {
            Parameter::CF => "F",
            Parameter::Inductance => "H",
            Parameter::TuningFrequency => "rad/s",
            Parameter::Resistance => "Ω",
        }
    }

    /// Whether a design works on ln(value) (positive, scale-free parameters).
    pub fn logarithmic(self) -> bool {
        !matches!(self, Parameter::Resistance)
    }
}

impl std::fmt::Display for Parameter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.key())
    }
}

/// Why a branch parameter cannot take a value: the rules the file layer checks a branch
/// of `[[circuit.branches]]` by.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum BranchError {
    /// The ring or the branch does not exist.
    #[error("ring {ring} has no branch {branch} (it has {branches}; branches count from 0)")]
    NoBranch {
        /// The ring (model order, from 0).
        ring: usize,
        /// The branch asked for (from 0).
        branch: usize,
        /// The branches the ring has (0 for a ring that does not exist).
        branches: usize,
    },
    /// NaN or infinite.
    #[error("{parameter} must be a finite number, found {value}", value = crate::numbers::number(*value))]
    NotFinite {
        /// The parameter set.
        parameter: Parameter,
        /// The value (SI unit of the parameter).
        value: f64,
    },
    /// ≤ 0 for C_f or ω.
    #[error("{parameter} must be positive, found {value}")]
    NotPositive {
        /// The parameter set.
        parameter: Parameter,
        /// The value (SI unit of the parameter).
        value: f64,
    },
    /// < 0 for L or R.
    #[error("{parameter} must not be negative, found {value}")]
    Negative {
        /// The parameter set.
        parameter: Parameter,
        /// The value (SI unit of the parameter).
        value: f64,
    },
    /// A valid value that makes a coefficient of the branch's charge DOF infinite (L of
    /// Eq. 4, or γL, γR, γ/C_f of Eq. A8): the analyses cannot run on it.
    #[error("{parameter} = {value:e} gives an infinite {what}")]
    Overflow {
        /// The parameter set.
        parameter: Parameter,
        /// The value (SI unit of the parameter).
        value: f64,
        /// The coefficient that overflows, e.g. `charge mass gamma L`.
        what: &'static str,
    },
}

impl Branch {
    /// A branch given by its inductance L (H).
    pub fn new(c_f: f64, inductance: f64, resistance: f64) -> Branch {
        Branch { c_f, inductance, resistance, given: Given::Inductance }
    }

    /// Inductance of Eq. (4) that tunes a branch to `omega` (rad/s):
    /// L = (C_p^T + C_f)/(ω²·C_p^T·C_f).
    pub fn tuned_inductance(cp_t: f64, c_f: f64, omega: f64) -> f64 {
        (cp_t + c_f) / (omega * omega * cp_t * c_f)
    }

    /// The frequency a branch of C_f and L is tuned to by Eq. (4) (rad/s); inverse of
    /// [`Branch::tuned_inductance`]. Infinite for L = 0.
    pub fn frequency_of(cp_t: f64, c_f: f64, inductance: f64) -> f64 {
        ((cp_t + c_f) / (inductance * cp_t * c_f)).sqrt()
    }

    /// The frequency the branch is tuned to by Eq. (4) (rad/s), from its C_f and L.
    pub fn tuning_frequency(&self, cp_t: f64) -> f64 {
        Branch::frequency_of(cp_t, self.c_f, self.inductance)
    }

    /// Set `parameter` to `value` (its SI unit) as a problem file would give it: C_f and
    /// ω finite and positive, L and R finite and non-negative. A tuning frequency sets L
    /// by Eq. (4) with `cp_t` (F), the C_p^T the branch is tuned with, and is held: a
    /// later C_f recomputes L. An inductance replaces a held tuning frequency. On an
    /// error the branch is unchanged.
    pub fn set(&mut self, parameter: Parameter, value: f64, cp_t: f64) -> Result<(), BranchError> {
        let check = |positive: bool| {
            if !value.is_finite() {
                Err(BranchError::NotFinite { parameter, value })
            } else if positive && value <= 0.0 {
                Err(BranchError::NotPositive { parameter, value })
            } else if value < 0.0 {
                Err(BranchError::Negative { parameter, value })
            } else {
                Ok(value)
            }
        };
        match parameter {
            Parameter::CF => {
                self.c_f = check(true)?;
                if let Given::TuningFrequency(w) = self.given {
                    self.inductance = Branch::tuned_inductance(cp_t, self.c_f, w);
                }
            }
            Parameter::Resistance => self.resistance = check(false)?,
            Parameter::Inductance => {
                self.inductance = check(false)?;
                self.given = Given::Inductance;
            }
            Parameter::TuningFrequency => {
                let w = check(true)?;
                self.inductance = Branch::tuned_inductance(cp_t, self.c_f, w);
                self.given = Given::TuningFrequency(w);
            }
        }
        Ok(())
    }

    /// Check that the branch's charge DOF has finite coefficients on a ring of coupling
    /// scale `gamma` (γ = 2cot²β·θ_p², Eq. A8) and, for a tuned branch, that Eq. (4) is
    /// finite with `cp_t` and the ring's own `ring_cp_t` (F): the checks the file layer
    /// makes of a closed circuit's branch. The error names the parameter behind the
    /// coefficient (L's: the inductance or the tuning frequency the input held) and its
    /// value. A γ that itself overflows is left to the analyses, as the file layer does.
    pub fn check_charge(&self, gamma: f64, cp_t: f64, ring_cp_t: f64) -> Result<(), BranchError> {
        let overflow = |parameter, value, what| Err(BranchError::Overflow { parameter, value, what });
        let l = match self.given {
            Given::Inductance => (Parameter::Inductance, self.inductance),
            Given::TuningFrequency(w) => (Parameter::TuningFrequency, w),
        };
        if let Given::TuningFrequency(_) = self.given {
            if !(1.0 / self.c_f).is_finite() {
                return overflow(Parameter::CF, self.c_f, "1/C_f (Eq. 4)");
            }
            if !(1.0 / cp_t).is_finite() || !(1.0 / ring_cp_t).is_finite() {
                return overflow(l.0, l.1, "1/C_p^T (Eq. 4)");
            }
            if !self.inductance.is_finite() {
                return overflow(l.0, l.1, "L (Eq. 4)");
            }
        }
        if !gamma.is_finite() {
            return Ok(());
        }
        if !(gamma * self.inductance).is_finite() {
            return overflow(l.0, l.1, "charge mass gamma L");
        }
        if !(gamma * self.resistance).is_finite() {
            return overflow(Parameter::Resistance, self.resistance, "charge damping gamma R");
        }
        if !(gamma / self.c_f).is_finite() {
            return overflow(Parameter::CF, self.c_f, "charge stiffness gamma / C_f");
        }
        Ok(())
    }
}

/// The shunt circuit attached to every piezo stack of both rings.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Circuit {
    /// Open, short or closed.
    pub state: CircuitState,
    /// The branches (used when closed; kept otherwise so a state switch is lossless).
    pub branches: Vec<Branch>,
}

impl Circuit {
    /// Number of charge DOFs each ring carries in this state.
    pub fn charge_dofs(&self) -> usize {
        match self.state {
            CircuitState::Closed => self.branches.len(),
            _ => 0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Table 1 of the paper, with C_p^S from the printed k_eq2 (docs/model.md).
    fn table1() -> Ring {
        let angle = 60f64.to_radians();
        Ring {
            k_b: 3.96e7,
            m_b: 0.15,
            eta: 0.0,
            k_1: 1.575e8,
            k_2: 1.1e8,
            angle,
            theta_p: 7.0356,
            cp_t: 1.8e-6,
            cp_s: Ring::cp_s_from_k_eq2(angle, 7.0356, 2.444e7),
        }
    }

    #[test]
    fn paper_section5_stiffnesses() {
        // Section 5: k_eq = 2.635e7, k_eq1 = 7.333e7, k_eq2 = 2.444e7 N/m (4 digits printed).
        let r = table1();
        assert!((r.k_eq() / 2.635e7 - 1.0).abs() < 5e-4, "{}", r.k_eq());
        assert!((r.k_eq1() / 7.333e7 - 1.0).abs() < 5e-4, "{}", r.k_eq1());
        assert!((r.k_eq2() / 2.444e7 - 1.0).abs() < 1e-12);
        assert!((r.cp_s / 1.3502e-6 - 1.0).abs() < 1e-4, "{}", r.cp_s);
    }

    #[test]
    fn paper_section5_inductances() {
        // Section 5: L1 = 0.9328 H, L2 = 1.5615 H from Eq. (4).
        let l1 = Branch::tuned_inductance(1.8e-6, 5e-6, 900.0);
        let l2 = Branch::tuned_inductance(1.8e-6, 1e-7, 2600.0);
        assert!((l1 - 0.9328).abs() < 5e-5, "{l1}");
        assert!((l2 - 1.5615).abs() < 5e-5, "{l2}");
        let b = Branch::new(5e-6, l1, 0.0);
        assert!((b.tuning_frequency(1.8e-6) - 900.0).abs() < 1e-9);
    }
}
