//! Static buckling load P_cr: the smallest positive P with (K − P·S)x = 0 (section 5).

use crate::assembly::{GeneralSystem, SystemMatrices};
use crate::linalg::{definite_eigen, LinalgError};
use crate::model::{CircuitState, Model};

/// The buckling load of the model's own supports (N).
///
/// `K` is positive definite and `S` positive semi-definite (∫w′²dx), so with
/// `S x = θ K x` the largest θ gives P_cr = 1/θ_max.
pub fn buckling_load(system: &SystemMatrices) -> Result<f64, LinalgError> {
    let eig = definite_eigen(system.k.as_ref(), system.s.as_ref())?;
    let theta = eig.values.first().copied().unwrap_or(0.0);
    if theta.is_finite() && theta > 0.0 {
        Ok(1.0 / theta)
    } else {
        Err(LinalgError::NotPositiveDefinite { what: "geometric stiffness" })
    }
}

/// The reference load P_cr used for α and β: the value given in the file, or else the
/// buckling load with the rings on open circuit (docs/model.md). Using one reference for every
/// circuit state keeps P(t) = P_cr(α + β cos φt) the same physical load when open and
/// closed circuits are compared (Fig. 11).
///
/// With anisotropic or cross-coupled supports the stiffness is that of the real
/// coordinates with the supports' coefficients at the model's speed, and of it the
/// symmetric part (the conservative forces; the skew part of a cross-coupled support is
/// circulatory and has no static buckling load of its own): one reference for every
/// analysis speed of the problem (docs/model.md).
pub fn reference_load(model: &Model) -> Result<f64, LinalgError> {
    match model.load.critical_load {
        Some(p) => Ok(p),
        None if model.is_isotropic() => buckling_load(&SystemMatrices::assemble(&model.with_state(CircuitState::Open))),
        None => {
            let open = model.with_state(CircuitState::Open);
            let iso = SystemMatrices::assemble_with(&open, false);
            let general = GeneralSystem::new(&iso, &open.bearings, model.speed);
            let eig = definite_eigen(general.symmetric_stiffness().as_ref(), general.s.as_ref())?;
            let theta = eig.values.first().copied().unwrap_or(0.0);
            if theta.is_finite() && theta > 0.0 {
                Ok(1.0 / theta)
            } else {
                Err(LinalgError::NotPositiveDefinite { what: "geometric stiffness" })
            }
        }
    }
}
