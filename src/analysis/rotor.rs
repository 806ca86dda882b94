//! A model prepared for analysis: assembled once, reused at every speed and load.

use super::buckling::reference_load;
use super::AnalysisError;
use crate::assembly::SystemMatrices;
use crate::model::Model;

/// The model, its speed-independent matrices and its reference load P_cr.
#[derive(Debug, Clone)]
pub struct Rotor {
    /// The physics the matrices were assembled from.
    pub model: Model,
    /// M, C, K, S, G and the unbalance.
    pub system: SystemMatrices,
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
        Ok(Rotor { model: model.clone(), system: SystemMatrices::assemble(model), critical_load })
    }

    /// The static part of the axial load αP_cr (N).
    pub fn static_load(&self) -> f64 {
        self.model.load.alpha * self.critical_load
    }
}
