//! The tuned problem file a design writes (`tuned.toml`, or `best-effort.toml`).

use super::design::{design_file_name, status_word};
use super::TOOL;
use crate::commands::Error;
use rotorshunt::design::DesignOutcome;
use rotorshunt::problem::tuned::{tuned_file, Setting};
use rotorshunt::problem::Problem;

/// The tuned problem file: the input (with overrides applied) with the tuned values of
/// `outcome`'s variables in its branches ([`tuned_file`]), under a header naming where it
/// came from (and, for a result that cannot be handed on, that it is not one).
pub fn tuned_toml(source: &Problem, outcome: &DesignOutcome) -> Result<String, Error> {
    let settings: Vec<Setting> = outcome
        .spec
        .variables
        .iter()
        .zip(&outcome.after)
        .map(|(v, &value)| Setting { ring: v.ring, branch: v.branch, parameter: v.parameter, value })
        .collect();
    let body = tuned_file(&source.data, &settings, &source.rpm)
        .map_err(|e| Error::Output { path: design_file_name(outcome.status).into(), message: e.to_string() })?;
    let warning = if outcome.status.is_result() {
        String::new()
    } else {
        format!(
            "# NOT A RESULT: the design is {}; this is the optimiser's best effort, for inspection only.\n",
            status_word(outcome.status)
        )
    };
    Ok(format!(
        "{warning}# Tuned by {TOOL} from {}{} (status: {}).\n# Circuit values are the optimiser's; every other key is the input's.\n{body}",
        source.file,
        if source.overrides.is_empty() { String::new() } else { format!(" with --set {}", source.overrides.join(" ")) },
        status_word(outcome.status)
    ))
}
