//! What a design works on: the model, the analysis settings and the region search's
//! settings, with how the file's circuit keys map onto the rings. The file layer builds
//! it ([`crate::problem::Problem::machine`]); a candidate is the same machine with the
//! design variables set on its model, so nothing in it describes another model.

use crate::analysis::regions::RegionSettings;
use crate::analysis::Settings;
use crate::model::Model;

/// The machine a design tunes.
#[derive(Debug, Clone)]
pub struct Machine {
    /// The physics: shaft, disks, rings, circuits, load and speed.
    pub model: Model,
    /// Numerical settings of the analyses (`[analysis]`).
    pub settings: Settings,
    /// Settings of the region search (`[regions]`).
    pub regions: RegionSettings,
    /// Whether every ring's circuit is one shared circuit (the shorthand's `[circuit]`):
    /// a design variable then sets the branch in every ring, tuned with the first
    /// ring's C_p^T ([`Machine::targets`]).
    pub shared_circuit: bool,
}

/// A branch a design variable sets in the model: ring `ring` (model order), whose
/// tuning frequency gives L by Eq. (4) with `cp_t` (F).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Target {
    /// The ring, model order.
    pub ring: usize,
    /// C_p^T of Eq. (4) for this ring's branches (F).
    pub cp_t: f64,
}

impl Machine {
    /// A machine whose rings each have their own circuit.
    pub fn new(model: Model, settings: Settings, regions: RegionSettings) -> Machine {
        Machine { model, settings, regions, shared_circuit: false }
    }

    /// The rings whose branch a design variable on `ring` (model order; `None`: every
    /// ring) sets, each with the C_p^T its tuning frequency uses: a shared circuit is
    /// every ring's, tuned with the first ring's C_p^T whichever ring is named; a ring's
    /// own circuit is tuned with its own C_p^T.
    pub fn targets(&self, ring: Option<usize>) -> Vec<Target> {
        let rings = &self.model.rings;
        let own = |r: usize| Target { ring: r, cp_t: rings.get(r).map_or(f64::NAN, |s| s.ring.cp_t) };
        match (self.shared_circuit, ring) {
            (true, _) => {
                let cp_t = rings.first().map_or(f64::NAN, |s| s.ring.cp_t);
                (0..rings.len()).map(|r| Target { ring: r, cp_t }).collect()
            }
            (false, Some(r)) => vec![own(r)],
            (false, None) => (0..rings.len()).map(own).collect(),
        }
    }

    /// The same machine with another model (a candidate's, or one built with component
    /// tolerances).
    pub fn with_model(&self, model: Model) -> Machine {
        Machine { model, ..self.clone() }
    }
}
