//! The crate's error type, composed from the layers' errors.

use thiserror::Error;

/// Any failure of a rotorshunt operation.
#[derive(Debug, Error)]
pub enum Error {
    /// A problem file is unreadable or invalid.
    #[error(transparent)]
    Problem(#[from] crate::problem::ProblemError),
    /// An analysis failed on valid input (e.g. a load at buckling).
    #[error("analysis failed: {0}")]
    Analysis(#[from] crate::analysis::AnalysisError),
    /// A design run failed.
    #[error("design failed: {0}")]
    Design(#[from] crate::design::DesignError),
    /// A study file is unreadable or invalid.
    #[error("study file {file}: {message}")]
    Study {
        /// The study file.
        file: String,
        /// What is wrong (with the key path).
        message: String,
    },
    /// Bad command-line argument (range syntax, counts).
    #[error("argument `{argument}`: {message}")]
    Argument {
        /// The argument's name.
        argument: String,
        /// What is wrong.
        message: String,
    },
    /// Writing an output failed.
    #[error("cannot write {path}: {message}")]
    Output {
        /// The file or directory.
        path: String,
        /// Why.
        message: String,
    },
}
