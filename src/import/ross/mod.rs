//! Import of rotors saved by ROSS (the Python rotordynamics package,
//! `ross-rotordynamics`) with `Rotor.save`, as TOML or JSON.
//!
//! `parse` reads the file's element tables, `map` maps them to rotorshunt's general
//! form (materials, sections, disks, bearings and seals with their coefficient tables) or
//! refuses every element it cannot represent, and `write` renders the
//! problem file. The format and the mapping are in
//! `docs/ross-format.md`. SI units and rad/s throughout.

mod error;
pub(crate) mod map;
pub(crate) mod parse;
mod work;
pub(crate) mod write;

pub use error::{ElementRef, Format, Refusal, Refused, RossError, RossErrorKind};
pub use map::{BearingOut, DiskOut, LayerOut, MaterialOut, SectionOut};
pub use map::{Imported, SAME_LENGTH_RTOL};
pub use parse::SupportClass;
pub use work::Work;

use std::path::Path;

/// What the import may choose.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Options {
    /// Speed Ω (rad/s), written as the problem's `speed` (default 0). Tabulated bearing
    /// and seal coefficients are written as tables; every analysis evaluates them at its
    /// speed, as ROSS's `run_modal(speed)` does.
    pub speed: Option<f64>,
}

/// An imported rotor and its problem-file text.
#[derive(Debug, Clone, PartialEq)]
pub struct Import {
    /// The mapped rotor.
    pub rotor: Imported,
    /// The problem file (general form, commented).
    pub text: String,
}

/// Import the text of a ROSS file; `name` is used in messages and in the output's
/// comments, and decides the format by its extension (`parse::format_of`).
pub fn import_text(text: &str, name: &str, options: Options) -> Result<Import, RossError> {
    let err = |kind| RossError { file: name.to_string(), kind };
    let format = parse::format_of(Path::new(name), text);
    let file = parse::parse(text, format).map_err(err)?;
    let rotor = map::map(&file, options.speed).map_err(err)?;
    let text = write::render(&rotor, name);
    Ok(Import { rotor, text })
}

/// Why a ROSS file could not be imported: it could not be read as an input, or its
/// content was refused.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ImportError {
    /// The file could not be read as every input is read (size, kind, UTF-8, parse cost).
    #[error(transparent)]
    Read(#[from] crate::problem::ProblemError),
    /// Its content was refused.
    #[error(transparent)]
    Ross(#[from] RossError),
}

/// Import a ROSS file: read as every input is ([`crate::problem::read_input`]: a regular
/// file of bounded size, UTF-8, a TOML text of bounded parse cost).
pub fn import_path(path: &Path, options: Options) -> Result<Import, ImportError> {
    let bytes = crate::problem::read_input(path)?;
    let name = path.display().to_string();
    let text = crate::problem::input::text_of(&bytes, &name)?;
    if parse::format_of(path, text) == Format::Toml {
        crate::problem::input::check_parse_cost(text).map_err(|kind| crate::problem::ProblemError {
            file: name.clone(),
            location: crate::problem::Location::Unknown,
            key: String::new(),
            kind,
        })?;
    }
    Ok(import_text(text, &name, options)?)
}
