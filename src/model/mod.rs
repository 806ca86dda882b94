//! Physics of the rotor – vibration ring – shunt system, with no I/O (sections 2–3).
//!
//! All quantities are SI: m, kg, N, Pa, F, H, Ω, s, rad and rad/s.

pub(crate) mod element;
mod ring;
mod shaft;
mod support;

pub use element::BeamElement;
pub use ring::{Branch, BranchError, Circuit, CircuitState, Given, Parameter, Ring};
use serde::Serialize;
pub use shaft::{Beam, Section, Shaft};
pub use support::{interpolate, Bearing, Matrix2, RingSupport, SupportKind, SupportMatrices, COEFFICIENT_NAMES};

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
    /// The shaft (sections left to right).
    pub shaft: Shaft,
    /// Rigid disks (`[[disks]]`, in file order): mass m, inertias J_p and J_d, and
    /// unbalance (e, γ) at a shaft node.
    pub disks: Vec<Disk>,
    /// Bearings and seals (no DOF of their own), `[[bearings]]` then `[[seals]]` in file
    /// order.
    pub bearings: Vec<Bearing>,
    /// Vibration rings in file order (the shorthand: `left` at node 0, `right` at node n),
    /// each with its own circuit. Their DOFs follow the shaft's in this order.
    pub rings: Vec<RingSupport>,
    /// Static part of the axial load P(t) = P_cr·(α + β·cos φt): α and P_cr; β and φ are
    /// the analysis's.
    pub load: Load,
    /// Rotating speed Ω (rad/s).
    pub speed: f64,
    /// Which coordinates the analyses run in (`[analysis] coordinates`).
    pub coordinates: Coordinates,
}

/// The coordinates the analyses run in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Coordinates {
    /// The complex coordinates u = v + jw where the model is isotropic (every bearing and
    /// seal constant, kxx = kyy, cxx = cyy, no cross-coupling), the real ones otherwise.
    #[default]
    Auto,
    /// The real coordinates (v, w) whatever the model (the general path).
    Real,
}

impl Model {
    /// Whether the complex coordinates carry the model: every bearing and seal isotropic
    /// ([`Bearing::is_isotropic`]) and [`Coordinates::Auto`].
    pub fn is_isotropic(&self) -> bool {
        self.bearings.iter().all(Bearing::is_isotropic)
    }

    /// Whether the analyses run in real coordinates: an anisotropic, cross-coupled or
    /// speed-dependent support, or `coordinates = "real"`.
    pub fn real_coordinates(&self) -> bool {
        self.coordinates == Coordinates::Real || !self.is_isotropic()
    }

    /// Total mechanical mass: shaft plus disks (kg); ring and bearing masses not included.
    pub fn rotor_mass(&self) -> f64 {
        self.shaft.mass() + self.disks.iter().map(|d| d.mass).sum::<f64>()
    }

    /// The same model with every ring's circuit in another state.
    pub fn with_state(&self, state: CircuitState) -> Model {
        let mut m = self.clone();
        for r in &mut m.rings {
            r.circuit.state = state;
        }
        m
    }

    /// The circuit every ring carries, when all rings carry an identical one (the
    /// shorthand always does); `None` when they differ or there is no ring.
    pub fn shared_circuit(&self) -> Option<&Circuit> {
        let first = &self.rings.first()?.circuit;
        self.rings.iter().all(|r| &r.circuit == first).then_some(first)
    }

    /// The circuit state in words: `closed`, `open`, `short`, or, when the rings' states
    /// differ, each ring's (`drive closed, aux open`).
    pub fn state_text(&self) -> String {
        match self.rings.first() {
            Some(first) if self.rings.iter().all(|r| r.circuit.state == first.circuit.state) => {
                first.circuit.state.to_string()
            }
            Some(_) => {
                self.rings.iter().map(|r| format!("{} {}", r.name, r.circuit.state)).collect::<Vec<_>>().join(", ")
            }
            None => "no".to_string(),
        }
    }

    /// Whether electrical modes and circuits are named by ring: unless two or more rings
    /// carry an identical circuit (the shorthand's layout, whose modes are the paper's r1,
    /// r2, s1, …), a label must say which ring a mode or branch belongs to.
    pub fn labels_by_ring(&self) -> bool {
        !(self.rings.len() >= 2 && self.shared_circuit().is_some())
    }

    /// The branch `branch` of ring `ring` (both from 0, model order).
    fn branch_mut(&mut self, ring: usize, branch: usize) -> Result<&mut Branch, BranchError> {
        let branches = self.rings.get(ring).map_or(0, |r| r.circuit.branches.len());
        self.rings.get_mut(ring).and_then(|r| r.circuit.branches.get_mut(branch)).ok_or(BranchError::NoBranch {
            ring,
            branch,
            branches,
        })
    }

    /// Set `parameter` of branch `branch` of ring `ring` to `value` (its SI unit) by
    /// [`Branch::set`], a tuning frequency through Eq. (4) with `cp_t` (F).
    pub fn set_branch(
        &mut self,
        ring: usize,
        branch: usize,
        parameter: Parameter,
        value: f64,
        cp_t: f64,
    ) -> Result<(), BranchError> {
        self.branch_mut(ring, branch)?.set(parameter, value, cp_t)
    }

    /// Check, after [`Model::set_branch`], that branch `branch` of ring `ring` has finite
    /// charge coefficients on its ring ([`Branch::check_charge`], a tuning through Eq. (4)
    /// with `cp_t`, F); only a closed circuit has charges.
    pub fn check_branch(&self, ring: usize, branch: usize, cp_t: f64) -> Result<(), BranchError> {
        let support = self.rings.get(ring);
        let branches = support.map_or(0, |r| r.circuit.branches.len());
        let Some((support, b)) = support.and_then(|r| Some((r, r.circuit.branches.get(branch)?))) else {
            return Err(BranchError::NoBranch { ring, branch, branches });
        };
        if support.circuit.state != CircuitState::Closed {
            return Ok(());
        }
        b.check_charge(support.ring.gamma(), cp_t, support.ring.cp_t)
    }

    /// Index of the ring named `name`.
    pub fn ring_index(&self, name: &str) -> Option<usize> {
        self.rings.iter().position(|r| r.name == name)
    }
}
