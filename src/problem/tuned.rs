//! The file side of a design: the machine a design of the file works on
//! ([`Problem::machine`]) and the tuned problem file (`tuned.toml`): the input with the
//! variables' values written into its branches.

use super::file::{BranchFile, ProblemFile};
use super::Problem;
use crate::design::machine::Machine;
use crate::model::Parameter;

/// One design variable's value in a tuned file: `parameter` of branch `branch` (from 0)
/// of ring `ring` (model order; `None`: every ring's), SI units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Setting {
    /// The ring (model order), or `None` for every ring's branch.
    pub ring: Option<usize>,
    /// The branch, from 0.
    pub branch: usize,
    /// C_f, L, ω or R.
    pub parameter: Parameter,
    /// The value (SI unit of the parameter).
    pub value: f64,
}

impl Problem {
    /// What a design of this problem works on: its model and settings, with the
    /// shorthand's one `[circuit]` shared by every ring ([`Machine::targets`]).
    pub fn machine(&self) -> Machine {
        Machine {
            model: self.model.clone(),
            settings: self.settings.clone(),
            regions: self.regions.clone(),
            shared_circuit: self.data.circuit.is_some(),
        }
    }
}

/// The TOML text of `base` with every setting written into its branches (the
/// shorthand's `[circuit]`, one ring's, or every ring's): a complete problem file. A
/// tuning frequency replaces the branch's inductance and the reverse, as a `--set` of
/// one of two alternative keys does. A setting naming a branch the file does not have
/// changes nothing. The speeds the input gave in rpm (`rpm`, as [`Problem::rpm`]) are
/// written back under their rpm keys with the values as given.
pub fn tuned_file(
    base: &ProblemFile,
    settings: &[Setting],
    rpm: &[(String, toml::Value)],
) -> Result<String, toml::ser::Error> {
    let mut data = base.clone();
    for s in settings {
        let targets: Vec<&mut BranchFile> = match (&mut data.circuit, s.ring) {
            (Some(c), _) => c.branches.get_mut(s.branch).into_iter().collect(),
            (None, Some(r)) => {
                data.rings.get_mut(r).and_then(|r| r.circuit.branches.get_mut(s.branch)).into_iter().collect()
            }
            (None, None) => data.rings.iter_mut().filter_map(|r| r.circuit.branches.get_mut(s.branch)).collect(),
        };
        for b in targets {
            set(b, s.parameter, s.value);
        }
    }
    Ok(with_rpm_keys(&toml::to_string(&data)?, rpm))
}

/// `text` (a serialised problem file, one key per line, arrays inline) with each rad/s
/// speed key that `rpm` gives in rpm (`speed_rpm`, `design.speeds_rpm`, …) replaced by
/// its rpm key and value as given.
fn with_rpm_keys(text: &str, rpm: &[(String, toml::Value)]) -> String {
    let mut table = String::new();
    let mut out = String::with_capacity(text.len());
    for line in text.lines() {
        let t = line.trim();
        if t.starts_with('[') {
            table = t.trim_matches(|c| c == '[' || c == ']').trim().to_string();
        }
        let replaced = rpm.iter().find_map(|(path, value)| {
            let (parent, key) = path.rsplit_once('.').unwrap_or(("", path));
            let rad = super::units::alternative_of(key)?;
            let prefix = format!("{rad} = ");
            (parent == table && t.starts_with(&prefix)).then(|| format!("{key} = {value}"))
        });
        out += replaced.as_deref().unwrap_or(line);
        out.push('\n');
    }
    out
}

fn set(b: &mut BranchFile, parameter: Parameter, x: f64) {
    match parameter {
        Parameter::CF => b.c_f = x,
        Parameter::Resistance => b.resistance = x,
        Parameter::Inductance => {
            b.inductance = Some(x);
            b.tuning_frequency = None;
        }
        Parameter::TuningFrequency => {
            b.tuning_frequency = Some(x);
            b.inductance = None;
        }
    }
}
