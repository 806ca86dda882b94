//! The output directory: created on demand, written atomically, and never allowed to
//! overwrite the problem file that is being read.

use crate::report::write_atomic;
use crate::Error;
use std::path::{Path, PathBuf};

/// A directory that receives a command's output files.
pub struct OutDir {
    dir: PathBuf,
    input: Option<PathBuf>,
}

impl OutDir {
    /// Create `dir` (and parents) if needed; `input` is the problem file to protect.
    pub fn create(dir: &Path, input: &str) -> Result<OutDir, Error> {
        std::fs::create_dir_all(dir)
            .map_err(|e| Error::Output { path: dir.display().to_string(), message: e.to_string() })?;
        Ok(OutDir { dir: dir.to_path_buf(), input: std::fs::canonicalize(input).ok() })
    }

    /// The path of an output file.
    pub fn path(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }

    /// An output error for a file of this directory.
    pub fn error(&self, name: &str, e: impl std::fmt::Display) -> Error {
        Error::Output { path: self.path(name).display().to_string(), message: e.to_string() }
    }

    /// Write a file atomically, refusing to replace the input problem file.
    pub fn write(&self, name: &str, bytes: &[u8]) -> Result<(), Error> {
        let path = self.path(name);
        if let (Some(input), Ok(target)) = (&self.input, std::fs::canonicalize(&path)) {
            if *input == target {
                return Err(self.error(name, "this is the input problem file; choose another --out directory"));
            }
        }
        write_atomic(&path, bytes).map_err(|e| self.error(name, e))
    }
}
