//! The second configuration of `chart` and `unbalance` (`--compare FILE2` or
//! `--compare-set key=value`) and its legend name.

use super::layer_name;
use crate::commands::Error;
use rotorshunt::problem::{Problem, Warning};
use std::path::Path;

/// The compared configuration and its legend name.
pub struct Compared {
    /// The name in the text output: the compared file's name, or, for `--compare-set`,
    /// its circuit state and the `--compare-set` overrides.
    pub label: String,
    /// The compared problem.
    pub problem: Problem,
}

impl Compared {
    /// The compared problem's plausibility warnings that `main` does not have (the same
    /// key and kind), for printing after `main`'s.
    pub fn new_warnings<'a>(&'a self, main: &'a Problem) -> impl Iterator<Item = &'a Warning> + 'a {
        self.problem.warnings.iter().filter(|w| !main.warnings.iter().any(|m| m.key == w.key && m.kind == w.kind))
    }
}

/// The configuration of `--compare FILE2` (read with the main overrides `set`) or of
/// `--compare-set` (the main `file` with `set` and then `compare_set`); `None` when
/// neither is given.
pub fn compared(
    file: &Path,
    set: &[String],
    compare: Option<&Path>,
    compare_set: &[String],
) -> Result<Option<Compared>, Error> {
    match (compare, compare_set.is_empty()) {
        (Some(path), _) => {
            let problem = Problem::from_path(path, set)?;
            let label = file_name(&problem.file);
            Ok(Some(Compared { label, problem }))
        }
        (None, false) => {
            let all: Vec<String> = set.iter().chain(compare_set).cloned().collect();
            let problem = Problem::from_path(file, &all)?;
            // The compare problem carries the main --set overrides too: name it by its
            // state and the --compare-set overrides only.
            let label = layer_name(&Problem { overrides: compare_set.to_vec(), ..problem.clone() });
            Ok(Some(Compared { label, problem }))
        }
        (None, true) => Ok(None),
    }
}

/// The last component of a path (`tuned.toml` of `out/tuned.toml`), or the path itself.
fn file_name(path: &str) -> String {
    Path::new(path).file_name().map_or_else(|| path.to_string(), |n| n.to_string_lossy().into_owned())
}

/// The legend names of two files' layers: each file's name with its overrides
/// (`rotor.toml`, `tuned.toml [speed=1200]`), the paths when the names are equal, so two
/// files that share a title (a design's `tuned.toml` and its input) never get one name.
pub fn file_layer_names(main: &Problem, other: &Problem) -> (String, String) {
    let (mut a, mut b) = (file_name(&main.file), file_name(&other.file));
    if a == b {
        (a, b) = (main.file.clone(), other.file.clone());
    }
    let with = |name: String, p: &Problem| match p.overrides.as_slice() {
        [] => name,
        o => format!("{name} [{}]", o.join(", ")),
    };
    (with(a, main), with(b, other))
}
