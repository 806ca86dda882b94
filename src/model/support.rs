//! Supports: plain bearings and vibration rings, each at one shaft node.

use super::{Circuit, Ring};
use serde::Serialize;

/// A plain isotropic bearing: a spring and a damper to the ground at a shaft node, and an
/// optional bearing mass lumped at that node. It has no DOF of its own.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Bearing {
    /// Shaft node (0-based).
    pub node: usize,
    /// Radial stiffness k (N/m).
    pub stiffness: f64,
    /// Radial damping c (N·s/m).
    pub damping: f64,
    /// Bearing mass (kg), lumped at the node's deflection.
    pub mass: f64,
}

/// A vibration ring with its bearing (Eq. 1, 7–10) and its own shunt circuit (Eq. A8),
/// mounted at a shaft node.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RingSupport {
    /// Name, used in mode and region labels when circuits differ between rings.
    pub name: String,
    /// Shaft node (0-based).
    pub node: usize,
    /// The ring's mechanical and piezo parameters.
    pub ring: Ring,
    /// The circuit shunting this ring's stacks.
    pub circuit: Circuit,
}
