//! The file layer: read a TOML problem file, apply `--set` overrides, check every value
//! and translate it into [`crate::model::Model`] and [`crate::analysis::Settings`].
//! This is the only module that knows both the file format and the model.

mod design_keys;
mod error;
pub mod file;
pub(crate) mod general;
pub mod input;
pub(crate) mod plausibility;
pub mod provenance;
pub mod source;
pub mod study;
pub mod tuned;
pub mod units;
mod validate;

pub use error::{NameOf, ProblemError, ProblemErrorKind};
pub use file::ProblemFile;
pub use input::{read_input, read_toml, MAX_FILE_BYTES, MAX_PARSE_BYTES};
pub use plausibility::{Warning, WarningKind};
pub use source::Location;
pub use validate::{
    DERIVED_RANGE, MAX_BRANCHES, MAX_DISKS, MAX_DOFS, MAX_ELEMENTS, MAX_SUPPORT_DAMPING_RATIO,
    MAX_SUPPORT_STIFFNESS_RATIO, MAX_TABLE_POINTS,
};

use crate::analysis::Settings;
use crate::design::spec::DesignSpec;
use crate::model::Model;
use source::{deep_key_line, line_of, parse_override_value, set_path, LineIndex};
use std::path::Path;

/// A loaded, validated problem.
#[derive(Debug, Clone)]
pub struct Problem {
    /// The file name as given.
    pub file: String,
    /// The file's content after overrides (what was analysed).
    pub data: ProblemFile,
    /// The physics: shaft, disks, rings, circuit, load and speed.
    pub model: Model,
    /// Numerical settings (`[analysis]`).
    pub settings: Settings,
    /// Settings of the region search (`[regions]`, defaults where absent).
    pub regions: crate::analysis::regions::RegionSettings,
    /// The `[design]` problem, if the file has one.
    pub design: Option<DesignSpec>,
    /// The `--set` overrides applied, in order.
    pub overrides: Vec<String>,
    /// SHA-256 (hex) of the problem text followed by the overrides, one per line: what
    /// every output records to identify its input.
    pub input_sha256: String,
    /// Values that look like unit mistakes (`plausibility`); empty for a plausible file.
    pub warnings: Vec<Warning>,
    /// The file's text as read (before the overrides), so that a later refusal can name
    /// a key's line ([`Problem::locate`]); empty for data built in code.
    pub text: std::sync::Arc<str>,
    /// The speeds given in rpm (by the file or `--set`): each rpm key's path
    /// (`speed_rpm`, `design.speeds_rpm`) and its value as given; `data` holds them in
    /// rad/s. Text and titles echo these speeds in rpm ([`Problem::speed_unit`]), and a
    /// tuned file writes them back under the same keys.
    pub rpm: Vec<(String, toml::Value)>,
}

/// SHA-256 (hex) of a problem text and its overrides.
pub fn input_hash(text: &str, overrides: &[String]) -> String {
    use sha2::{Digest, Sha256};
    let mut h = Sha256::new();
    h.update(text.as_bytes());
    for o in overrides {
        h.update(b"\n--set ");
        h.update(o.as_bytes());
    }
    format!("{:x}", h.finalize())
}

/// The tool's default settings as text (`[analysis]` and `[regions]` in JSON): what a file
/// that leaves a setting out computes with. A record of results computed from a problem
/// text (a study case's) is tied to these, so that a version with other defaults (a
/// basis, a criterion) never takes such a record as its own.
pub fn default_settings_text() -> String {
    let analysis = serde_json::to_string(&crate::analysis::Settings::default()).unwrap_or_default();
    let regions = serde_json::to_string(&crate::analysis::regions::RegionSettings::default()).unwrap_or_default();
    format!("analysis {analysis}\nregions {regions}\n")
}

impl Problem {
    /// Where a key path of the file is: its line, `--set` when an override set it, or
    /// unknown (data built in code, or a key the file does not have).
    pub fn locate(&self, key: &str) -> Location {
        let mut index = LineIndex::new(&self.text);
        for o in &self.overrides {
            if let Some((k, _)) = o.split_once('=') {
                index.mark_overridden(k.trim());
            }
        }
        index.locate(key)
    }

    /// A refusal of `key` with `kind`, located in the file ([`Problem::locate`]).
    pub fn refuse(&self, key: &str, kind: ProblemErrorKind) -> ProblemError {
        ProblemError { file: self.file.clone(), location: self.locate(key), key: key.to_string(), kind }
    }

    /// The unit the problem's operating speeds are shown in: rpm when the file (or
    /// `--set`) gave `speed_rpm` or `design.speeds_rpm` (or `design.speed_range_rpm`),
    /// else rad/s.
    pub fn speed_unit(&self) -> crate::numbers::SpeedUnit {
        let rpm = self
            .rpm
            .iter()
            .any(|(k, _)| matches!(k.as_str(), "speed_rpm" | "design.speeds_rpm" | "design.speed_range_rpm"));
        crate::numbers::SpeedUnit::of(rpm)
    }

    /// The assembled rotor of the problem's model, P_cr computed or given.
    pub fn rotor(&self) -> Result<crate::analysis::Rotor, crate::analysis::AnalysisError> {
        crate::analysis::Rotor::new(&self.model)
    }

    /// The rotor at the file's speed, with the file's settings ([`OperatingPoint`]).
    ///
    /// [`OperatingPoint`]: crate::analysis::OperatingPoint
    pub fn operating_point(&self) -> Result<crate::analysis::OperatingPoint, crate::analysis::AnalysisError> {
        self.operating_point_at(self.model.speed)
    }

    /// The rotor at speed Ω (rad/s), with the file's settings.
    pub fn operating_point_at(
        &self,
        speed: f64,
    ) -> Result<crate::analysis::OperatingPoint, crate::analysis::AnalysisError> {
        let mut op = crate::analysis::OperatingPoint::new(&self.rotor()?, &self.settings, speed)?;
        op.regions = self.regions.clone();
        Ok(op)
    }

    /// Load `path` and apply overrides `key.path=value`. The file is read by
    /// [`read_input`]: a regular file of at most [`MAX_FILE_BYTES`].
    pub fn from_path(path: impl AsRef<Path>, overrides: &[String]) -> Result<Problem, ProblemError> {
        let path = path.as_ref();
        let bytes = read_input(path)?;
        Problem::from_bytes(&bytes, &path.display().to_string(), overrides)
    }

    /// Parse the raw bytes of a problem file; `name` is used in messages. Bytes that are
    /// not UTF-8 are refused with [`ProblemErrorKind::NotUtf8`] (offset and line of the
    /// first invalid byte).
    pub fn from_bytes(bytes: &[u8], name: &str, overrides: &[String]) -> Result<Problem, ProblemError> {
        Problem::from_text(input::text_of(bytes, name)?, name, overrides)
    }

    /// Parse problem text; `name` is used in messages. Time and memory are linear in the
    /// text's size; a text whose parse would need more than [`MAX_PARSE_BYTES`] is refused
    /// with [`ProblemErrorKind::TooComplex`] before parsing.
    pub fn from_text(text: &str, name: &str, overrides: &[String]) -> Result<Problem, ProblemError> {
        let err =
            |location, key: &str, kind| ProblemError { file: name.to_string(), location, key: key.to_string(), kind };
        // Before parsing: the parser's memory grows with the text's structure, not its size.
        input::check_parse_cost(text).map_err(|kind| err(Location::Unknown, "", kind))?;
        let mut table: toml::Table = toml::from_str(text).map_err(|e| {
            let (loc, kind) = syntax_error(text, &e);
            err(loc, "", kind)
        })?;
        if text.trim().is_empty() {
            return Err(err(Location::Unknown, "", ProblemErrorKind::Empty));
        }
        let mut index = LineIndex::new(text);
        // The version decides the schema: check it before anything else, so a newer file
        // is reported as such rather than as having unknown keys.
        if let Some(found) = table.get("version").and_then(toml::Value::as_integer) {
            if found != file::FORMAT_VERSION {
                // Locating parses the text again: free the document first.
                drop(table);
                let kind = ProblemErrorKind::Version { found, supported: file::FORMAT_VERSION };
                return Err(err(index.locate("version"), "version", kind));
            }
        }
        for o in overrides {
            let (key, value) = o.split_once('=').ok_or_else(|| {
                err(
                    Location::Override,
                    "",
                    ProblemErrorKind::Override { text: o.clone(), reason: "expected key.path=value".into() },
                )
            })?;
            let key = key.trim();
            // One of two alternative keys replaces the other when that one is the file's
            // (an earlier --set of it stays, and giving both is refused below).
            if let Some(other) = units::alternative_of(key) {
                if !index.is_overridden(&other) && units::has_path(&mut table, &other) {
                    units::remove_path(&mut table, &other);
                }
            }
            let override_error =
                |reason| err(Location::Override, key, ProblemErrorKind::Override { text: o.clone(), reason });
            let value = parse_override_value(value.trim()).map_err(override_error)?;
            set_path(&mut table, key, value).map_err(override_error)?;
            index.mark_overridden(key);
        }
        let rpm_given = units::rpm_given(&table);
        let rpm = units::convert_rpm(&mut table).map_err(|(key, kind)| err(index.locate(&key), &key, kind))?;
        let data: ProblemFile = serde_path_to_error::deserialize(toml::Value::Table(table)).map_err(|e| {
            let mut key = e.path().to_string();
            let message = e.inner().message().trim().to_string();
            if key == "." {
                key.clear();
            }
            // serde reports a missing or unknown key at its table; name the key itself.
            if let Some(field) =
                quoted_field(&message, "missing field `").or_else(|| quoted_field(&message, "unknown field `"))
            {
                if !key.ends_with(&field) {
                    key = if key.is_empty() { field } else { format!("{key}.{field}") };
                }
            }
            let key = units::file_key(&key, &rpm);
            // A missing speed may be given in rpm: name both keys.
            if let Some(rpm_key) = units::rpm_form(&key).filter(|_| message.starts_with("missing field")) {
                let rad = key.rsplit('.').next().unwrap_or(&key).to_string();
                return err(index.locate(&key), &key, ProblemErrorKind::NeitherGiven(rad, rpm_key));
            }
            err(index.locate(&key), &key, ProblemErrorKind::Schema(message))
        })?;
        let (model, settings) = validate::translate(&data).map_err(|(key, kind)| {
            let key = units::file_key(&key, &rpm);
            // Two alternatives given: blame --set if either came from the command line.
            let location = match (&kind, key.rsplit_once('.')) {
                (ProblemErrorKind::BothGiven(a, b), Some((parent, _)))
                    if index.is_overridden(&format!("{parent}.{a}"))
                        || index.is_overridden(&format!("{parent}.{b}")) =>
                {
                    Location::Override
                }
                _ => index.locate(&key),
            };
            let kind = located(kind, name, |k| {
                let k = units::file_key(k, &rpm);
                index.locate(&k)
            });
            err(location, &key, kind)
        })?;
        let mut design = design_keys::design(&data, &model).map_err(|(key, kind)| {
            let key = units::file_key(&key, &rpm);
            err(index.locate(&key), &key, kind)
        })?;
        let regions = validate::regions(&data).map_err(|(key, kind)| err(index.locate(&key), &key, kind))?;
        let warnings = plausibility::check(&data, &model, &rpm)
            .into_iter()
            .map(|(key, kind)| Warning { file: name.to_string(), location: index.locate(&key), key, kind })
            .collect();
        let mut problem = Problem {
            file: name.to_string(),
            data,
            model,
            settings,
            regions,
            design: None,
            overrides: overrides.to_vec(),
            input_sha256: input_hash(text, overrides),
            warnings,
            text: text.into(),
            rpm: rpm_given,
        };
        if let Some(spec) = &mut design {
            spec.speed_unit = problem.speed_unit();
        }
        problem.design = design;
        Ok(problem)
    }
}

impl Problem {
    /// A problem from edited file data (e.g. a candidate design): validated like a file,
    /// errors located by key path only. `file` and `overrides` describe where it came from.
    pub fn from_data(data: ProblemFile, file: &str, overrides: &[String]) -> Result<Problem, ProblemError> {
        let err = |(key, kind): validate::Failure| ProblemError {
            file: file.to_string(),
            location: Location::Unknown,
            key: key.clone(),
            kind: located(kind, file, |_| Location::Unknown),
        };
        let (model, settings) = validate::translate(&data).map_err(err)?;
        let design = design_keys::design(&data, &model).map_err(err)?;
        let regions = validate::regions(&data).map_err(err)?;
        // The edited data are the input: hash their TOML form.
        let input_sha256 = input_hash(&toml::to_string(&data).unwrap_or_default(), overrides);
        let warnings = plausibility::check(&data, &model, &[])
            .into_iter()
            .map(|(key, kind)| Warning { file: file.to_string(), location: Location::Unknown, key, kind })
            .collect();
        Ok(Problem {
            file: file.to_string(),
            data,
            model,
            settings,
            regions,
            design,
            overrides: overrides.to_vec(),
            input_sha256,
            warnings,
            text: "".into(),
            rpm: Vec::new(),
        })
    }
}

/// A TOML syntax error of a problem or study text, as one paragraph: the line (its
/// span's, or, for the errors the parser reports without one, a key path nested too
/// deep, the line of the offending key), and the parser's message on one line (its lines
/// joined by `; `) with the column.
pub fn syntax_error(text: &str, e: &toml::de::Error) -> (Location, ProblemErrorKind) {
    let message: Vec<&str> = e.message().lines().map(str::trim).filter(|l| !l.is_empty()).collect();
    let mut message = message.join("; ");
    let location = match e.span() {
        Some(s) => {
            let start = s.start.min(text.len());
            let line_start = text[..start].rfind('\n').map_or(0, |i| i + 1);
            let column = text.get(line_start..start).map_or(1, |l| l.chars().count() + 1);
            message += &format!(" (column {column})");
            Location::Line(line_of(text, start))
        }
        None => deep_key_line(text).map(Location::Line).unwrap_or(Location::Unknown),
    };
    (location, ProblemErrorKind::Syntax(message))
}

/// The errors a [`ProblemErrorKind::Several`] carries, given their file and located by
/// `locate` (their key to its line); any other kind as it is.
fn located(kind: ProblemErrorKind, file: &str, mut locate: impl FnMut(&str) -> Location) -> ProblemErrorKind {
    match kind {
        ProblemErrorKind::Several { first, more } => {
            let more = more
                .into_vec()
                .into_iter()
                .map(|e| ProblemError { file: file.to_string(), location: locate(&e.key), ..e })
                .collect();
            ProblemErrorKind::Several { first, more }
        }
        other => other,
    }
}

fn quoted_field(message: &str, prefix: &str) -> Option<String> {
    let rest = &message[message.find(prefix)? + prefix.len()..];
    Some(rest[..rest.find('`')?].to_string())
}
