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
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Branch {
    /// Filtering capacitance C_f (F).
    pub c_f: f64,
    /// Branch inductance L = L_t + L_f (H); may be 0 (a massless charge DOF).
    pub inductance: f64,
    /// Branch resistance R (Ω).
    pub resistance: f64,
}

impl Branch {
    /// Inductance of Eq. (4) that tunes a branch to `omega` (rad/s):
    /// L = (C_p^T + C_f)/(ω²·C_p^T·C_f).
    pub fn tuned_inductance(cp_t: f64, c_f: f64, omega: f64) -> f64 {
        (cp_t + c_f) / (omega * omega * cp_t * c_f)
    }

    /// The frequency the branch is tuned to by Eq. (4) (rad/s); inverse of
    /// [`Branch::tuned_inductance`]. Infinite for L = 0.
    pub fn tuning_frequency(&self, cp_t: f64) -> f64 {
        ((cp_t + self.c_f) / (self.inductance * cp_t * self.c_f)).sqrt()
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
        let b = Branch { c_f: 5e-6, inductance: l1, resistance: 0.0 };
        assert!((b.tuning_frequency(1.8e-6) - 900.0).abs() < 1e-9);
    }
}
