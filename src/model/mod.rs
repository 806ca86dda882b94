//! Physics of the rotor – vibration ring – shunt system, with no I/O (sections 2–3).
//!
//! All quantities are SI: m, kg, N, Pa, F, H, Ω, s, rad and rad/s.

pub mod element;
mod ring;

pub use ring::{Branch, Circuit, CircuitState, Ring};
use serde::Serialize;

/// A uniform solid circular shaft modelled by Rayleigh beam elements.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Shaft {
    /// Length L (m).
    pub length: f64,
    /// Radius r (m).
    pub radius: f64,
    /// Number of equal elements n (n + 1 nodes).
    pub elements: usize,
    /// Young's modulus E (Pa).
    pub youngs_modulus: f64,
    /// Density ρ (kg/m³).
    pub density: f64,
}

impl Shaft {
    /// Cross-section area A = πr² (m²).
    pub fn area(&self) -> f64 {
        std::f64::consts::PI * self.radius * self.radius
    }
    /// Diametral second moment I = πr⁴/4 (m⁴); the polar one is 2I.
    pub fn inertia(&self) -> f64 {
        std::f64::consts::PI * self.radius.powi(4) / 4.0
    }
    /// Element length l = L/n (m).
    pub fn element_length(&self) -> f64 {
        self.length / self.elements as f64
    }
    /// Number of nodes n + 1.
    pub fn nodes(&self) -> usize {
        self.elements + 1
    }
    /// Shaft mass ρAL (kg).
    pub fn mass(&self) -> f64 {
        self.density * self.area() * self.length
    }
    /// Euler buckling load of the pinned-pinned shaft π²EI/L² (N), a closed-form bound.
    pub fn euler_load(&self) -> f64 {
        std::f64::consts::PI.powi(2) * self.youngs_modulus * self.inertia() / self.length.powi(2)
    }
}

/// A rigid disk lumped at a shaft node (Eq. 6).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Disk {
    /// Node index, 0-based (0 = left end).
    pub node: usize,
    /// Mass m (kg).
    pub mass: f64,
    /// Polar moment of inertia J_p (kg·m²).
    pub polar_inertia: f64,
    /// Diametral moment of inertia J_d (kg·m²).
    pub diametral_inertia: f64,
    /// Unbalance eccentricity e (m).
    pub eccentricity: f64,
    /// Unbalance phase γ (rad).
    pub phase: f64,
}

/// The periodic axial load P(t) = P_cr·(α + β·cos φt).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Load {
    /// Static load coefficient α (−), 0 ≤ α < 1.
    pub alpha: f64,
    /// P_cr given in the file (N); `None` computes it (open-circuit supports).
    pub critical_load: Option<f64>,
}

/// The whole rotor system as described by a problem file.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Model {
    /// The shaft.
    pub shaft: Shaft,
    /// Rigid disks.
    pub disks: Vec<Disk>,
    /// Ring and bearing at x = 0.
    pub left: Ring,
    /// Ring and bearing at x = L.
    pub right: Ring,
    /// The shunt circuit of every piezo stack.
    pub circuit: Circuit,
    /// Axial load.
    pub load: Load,
    /// Rotating speed Ω (rad/s).
    pub speed: f64,
}

impl Model {
    /// Total mechanical mass: shaft plus disks (kg); ring masses not included.
    pub fn rotor_mass(&self) -> f64 {
        self.shaft.mass() + self.disks.iter().map(|d| d.mass).sum::<f64>()
    }

    /// The same model with another circuit state.
    pub fn with_state(&self, state: CircuitState) -> Model {
        let mut m = self.clone();
        m.circuit.state = state;
        m
    }
}
