//! A model prepared for analysis: assembled once, reused at every speed and load.

use super::buckling::reference_load;
use super::AnalysisError;
use crate::assembly::{GeneralSystem, SystemMatrices};
use crate::model::Model;

/// The model, its speed-independent matrices and its reference load P_cr.
#[derive(Debug, Clone)]
pub struct Rotor {
    /// The physics the matrices were assembled from.
    pub model: Model,
    /// M, C, K, S, G and the unbalance of the complex coordinates; on the general path
    /// ([`Rotor::real`]) without the bearings' and seals' stiffness and damping, which
    /// [`Rotor::general_at`] adds in real coordinates.
    pub system: SystemMatrices,
    /// Whether the analyses run in real coordinates (the general path,
    /// [`Model::real_coordinates`]).
    pub real: bool,
    /// P_cr (N): given, or computed with open-circuit supports.
    pub critical_load: f64,
}

impl Rotor {
    /// Assemble the model and compute P_cr.
    pub fn new(model: &Model) -> Result<Rotor, AnalysisError> {
        let critical_load = reference_load(model)?;
        if model.load.alpha >= 1.0 {
            return Err(AnalysisError::StaticLoadBuckles { alpha: model.load.alpha, critical_load });
        }
        let real = model.real_coordinates();
        let system = SystemMatrices::assemble_with(model, !real);
        Ok(Rotor { model: model.clone(), system, real, critical_load })
    }

    /// The system in real coordinates at speed Ω (rad/s): the supports' coefficients
    /// taken at Ω ([`GeneralSystem`]). Meaningful on the general path ([`Rotor::real`]).
    pub fn general_at(&self, speed: f64) -> GeneralSystem {
        GeneralSystem::new(&self.system, &self.model.bearings, speed)
    }

    /// Number of real DOFs of the general path (twice the complex ones).
    pub fn general_size(&self) -> usize {
        2 * self.system.size()
    }

    /// The static part of the axial load αP_cr (N).
    pub fn static_load(&self) -> f64 {
        self.model.load.alpha * self.critical_load
    }
}
