//! Analysis settings: plain struct, defaults written once, validated by the problem layer.

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
        }
    }
}
