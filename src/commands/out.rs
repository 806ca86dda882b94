//! The output directory: created on demand, written atomically, never allowed to replace
//! an input of the run (compared by canonical path, so a symbolic link to an input is
//! refused too) and, in a folder a study owns, never allowed to replace a file the study
//! did not write.

use super::study::Ledger;
use crate::report::write_atomic;
use crate::Error;
use std::path::{Path, PathBuf};

/// A directory that receives a command's output files.
pub struct OutDir {
    dir: PathBuf,
    /// Canonical paths of the run's inputs, with what each is ("the --compare file").
    inputs: Vec<(PathBuf, String)>,
    /// The record of a study-owned folder.
    ledger: Option<Ledger>,
}

impl OutDir {
    /// Create `dir` (and parents) if needed; `input` is the problem file to protect.
    pub fn create(dir: &Path, input: &str) -> Result<OutDir, Error> {
        OutDir::with_inputs(dir, &[(Path::new(input), "the input problem file")])
    }

    /// Create `dir` (and parents) if needed, protecting every input: `(path, what it is)`.
    pub fn with_inputs(dir: &Path, inputs: &[(&Path, &str)]) -> Result<OutDir, Error> {
        let out = OutDir::planned(dir, inputs);
        std::fs::create_dir_all(dir)
            .map_err(|e| Error::Output { path: dir.display().to_string(), message: e.to_string() })?;
        Ok(out)
    }

    /// The output folder `dir`, not created yet, protecting `inputs`.
    pub(crate) fn planned(dir: &Path, inputs: &[(&Path, &str)]) -> OutDir {
        let inputs = inputs
            .iter()
            .filter_map(|(p, what)| std::fs::canonicalize(p).ok().map(|c| (c, what.to_string())))
            .collect();
        OutDir { dir: dir.to_path_buf(), inputs, ledger: None }
    }

    /// This folder, recording its files in `ledger` (a study-owned folder).
    pub(crate) fn with_ledger(self, ledger: Ledger) -> OutDir {
        OutDir { ledger: Some(ledger), ..self }
    }

    /// The ledger of a study-owned folder.
    pub(crate) fn ledger(&self) -> Option<&Ledger> {
        self.ledger.as_ref()
    }

    /// The path of an output file.
    pub fn path(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }

    /// An output error for a file of this directory.
    pub fn error(&self, name: &str, e: impl std::fmt::Display) -> Error {
        Error::Output { path: self.path(name).display().to_string(), message: e.to_string() }
    }

    /// Refuse, before any work, the output names that are an input of the run (or a link
    /// to one): [`Error::OutputIsInput`].
    pub fn check_outputs(&self, names: &[&str]) -> Result<(), Error> {
        names.iter().try_for_each(|name| self.check_not_input(name))
    }

    fn check_not_input(&self, name: &str) -> Result<(), Error> {
        let path = self.path(name);
        if let Ok(target) = std::fs::canonicalize(&path) {
            if let Some((_, what)) = self.inputs.iter().find(|(input, _)| *input == target) {
                return Err(Error::OutputIsInput { path: path.display().to_string(), input: what.clone() });
            }
        }
        Ok(())
    }

    /// Write a file atomically. Refused: an input of the run ([`Error::OutputIsInput`]); in
    /// a study-owned folder, an existing file the study did not write ([`Error::NotOwned`]);
    /// a read-only file ([`Error::Output`]).
    pub fn write(&self, name: &str, bytes: &[u8]) -> Result<(), Error> {
        self.check_not_input(name)?;
        if let Some(ledger) = &self.ledger {
            ledger.claim(name, &self.path(name))?;
        }
        write_atomic(&self.path(name), bytes).map_err(|e| self.error(name, e))
    }
}

/// `value` as pretty JSON, the one way JSON output is written (a
/// serialisation failure, e.g. a map with non-string keys, is an output error naming
/// `what`, not a panic).
pub(crate) fn json_pretty<T: serde::Serialize + ?Sized>(value: &T, what: &str) -> Result<String, Error> {
    serde_json::to_string_pretty(value)
        .map_err(|e| Error::Output { path: what.to_string(), message: format!("cannot serialise it as JSON: {e}") })
}

/// `value` as compact JSON (large outputs: charts, responses, locks), as [`json_pretty`].
pub(crate) fn json_compact<T: serde::Serialize + ?Sized>(value: &T, what: &str) -> Result<String, Error> {
    serde_json::to_string(value)
        .map_err(|e| Error::Output { path: what.to_string(), message: format!("cannot serialise it as JSON: {e}") })
}
