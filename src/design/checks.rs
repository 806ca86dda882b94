//! Checks of a design against its machine that need a solve: they run when the design
//! does (the file layer only reads and checks the text).

use super::spec::DesignSpec;
use super::DesignError;
use crate::analysis::{Rotor, Settings};

/// The damping constraints' whirl tags against the assembled rotor's whirls at the lowest
/// operating speed (the tags of `rotorshunt modes` there): the first tag the model lacks
/// is refused ([`DesignError::UnknownMode`]). Nothing is solved when the spec has no
/// damping constraint.
pub fn modes_exist(rotor: &Rotor, settings: &Settings, spec: &DesignSpec) -> Result<(), DesignError> {
    if spec.constraints.damping.is_empty() {
        return Ok(());
    }
    let speed = spec.speeds.iter().copied().fold(f64::INFINITY, f64::min);
    let modes = crate::analysis::modes::whirl_modes_of(rotor, settings, speed)?;
    let tags: Vec<String> = modes.forward().chain(modes.backward()).map(|m| m.tag()).collect();
    for (index, z) in spec.constraints.damping.iter().enumerate() {
        if !tags.contains(&z.mode) {
            return Err(DesignError::UnknownMode { index, mode: z.mode.clone(), speed, available: tags });
        }
    }
    Ok(())
}
