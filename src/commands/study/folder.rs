//! What a study owns on disk, and nothing more.
//!
//! - The `--out` folder's manifest [`MANIFEST`] records the study (its file's canonical
//!   path and the plan's hash) and the entries the study created there (`cases` and the
//!   summaries); each case folder's manifest [`CASE_MANIFEST`] records the files that case
//!   wrote. An entry is recorded before it is first written, and the manifests are
//!   written atomically.
//! - Anything in the `--out` folder that its manifest does not record is the user's: the
//!   study refuses the folder ([`Error::FolderNotEmpty`]) unless allowed, and even then
//!   never writes, replaces or deletes such an entry ([`Error::NotOwned`]).
//! - The temporaries a killed run leaves (`.rotorshunt-tmp.NAME.PID.N`) are removed only
//!   for recorded entries, and only in the `--out` folder itself and in the study's own
//!   case folders: the user's tree is never walked.
//! - [`StudyLock`] keeps a second run out of the folder while one runs, or, for the
//!   shards of one study, while one sets the folder up; [`CaseLock`] keeps two tasks out
//!   of one case folder. The commit point of a case is the atomic rename of its
//!   `result.json`: the locks save duplicate work, correctness does not rest on them
//!   (docs/decisions.md, "Shards in one folder").

pub(crate) use super::lock::{case_running, CaseLock, StudyLock};
use super::TOOL;
use crate::commands::out::json_pretty;
use crate::commands::Error;
use rotorshunt::files::{remove_temporaries, temporary_target, write_atomic};
use serde::{Deserialize, Serialize};
use std::collections::BTreeSet;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

/// The manifest of a study's `--out` folder.
pub(crate) const MANIFEST: &str = ".rotorshunt-study.json";
/// The manifest of a case folder.
pub(crate) const CASE_MANIFEST: &str = ".rotorshunt-case.json";
/// The lock file of a study's `--out` folder.
pub(crate) const LOCK: &str = ".rotorshunt-study.lock";
/// The lock file of a case folder, held while a task runs the case.
pub(crate) const CASE_LOCK: &str = ".rotorshunt-case.lock";
/// The folder of the case folders.
pub(crate) const CASES: &str = "cases";
/// The folder of `study slurm`'s job scripts and Slurm's logs.
pub(crate) const SLURM_DIR: &str = "slurm";
/// The folder of the summaries (`summary.csv`, `summary.json`, `summary.md`, and the
/// `figure.{svg,png}` of a sweep), replaced
/// whole by each merge so that a reader finds the three of one generation.
pub(crate) const SUMMARY: &str = "summary";
/// The summaries, as paths inside the `--out` folder (checked against the run's inputs
/// before any work).
pub(crate) const SUMMARY_FILES: [&str; 5] =
    ["summary/summary.csv", "summary/summary.json", "summary/summary.md", "summary/figure.svg", "summary/figure.png"];
/// The entries a study writes in its `--out` folder besides its manifest and lock.
pub(crate) const ROOT_OUTPUTS: [&str; 3] = [CASES, SUMMARY, SLURM_DIR];

/// Format of the manifests.
const MANIFEST_FORMAT: u32 = 1;
/// How a manifest names the temporaries a killed run may leave beside its entries.
const TEMPORARIES: &str = ".rotorshunt-tmp.<entry>.<pid>.<n>, beside a recorded entry or this manifest";
/// Entries named by [`Error::FolderNotEmpty`]; the rest are counted.
const LISTED_ENTRIES: usize = 5;

/// What a manifest describes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Role {
    /// A study's `--out` folder.
    Study,
    /// A case folder under `cases/`.
    Case,
}

/// The manifest of a folder a study owns: `.rotorshunt-study.json` in its `--out` folder,
/// `.rotorshunt-case.json` in each case folder.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Manifest {
    /// Format of this record (1).
    pub format: u32,
    /// The folder's role.
    pub role: Role,
    /// Tool and version that last wrote it.
    pub tool: String,
    /// The study file (canonical path) that created the folder.
    pub study: String,
    /// SHA-256 of the plan (study folder): base text, study parameters, every case's
    /// name, kind and overrides.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plan_sha256: Option<String>,
    /// Number of cases in the plan (study folder).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cases: Option<u64>,
    /// The number of shards the study is split into (study folder; set by `study slurm`
    /// or the first sharded run). Sharded runs with another count are refused.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shards: Option<u32>,
    /// The case's name (case folder).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub case: Option<String>,
    /// Entries of this folder the study created: files, and the `cases` folder.
    pub created: BTreeSet<String>,
    /// The temporaries a killed run may leave.
    pub temporaries: String,
    /// Entries of `created` as found on disk that are not plain names inside the folder
    /// (`../x`, absolute paths): dropped when read, never followed, and warned about.
    #[serde(skip)]
    pub ignored: Vec<String>,
}

/// Who a study is: its file and its plan.
#[derive(Debug, Clone)]
pub(crate) struct Identity {
    /// Canonical path of the study file.
    pub(crate) study: String,
    /// [`super::plan::Plan::survey`]'s hash.
    pub(crate) plan: String,
    /// Number of cases.
    pub(crate) cases: u64,
}

impl Manifest {
    fn study(id: &Identity) -> Manifest {
        Manifest {
            format: MANIFEST_FORMAT,
            role: Role::Study,
            tool: TOOL.into(),
            study: id.study.clone(),
            plan_sha256: Some(id.plan.clone()),
            cases: Some(id.cases),
            shards: None,
            case: None,
            created: BTreeSet::new(),
            temporaries: TEMPORARIES.into(),
            ignored: Vec::new(),
        }
    }

    fn case(study: &str, name: &str) -> Manifest {
        Manifest {
            format: MANIFEST_FORMAT,
            role: Role::Case,
            tool: TOOL.into(),
            study: study.into(),
            plan_sha256: None,
            cases: None,
            shards: None,
            case: Some(name.into()),
            created: BTreeSet::new(),
            temporaries: TEMPORARIES.into(),
            ignored: Vec::new(),
        }
    }

    /// A manifest read back from disk, checked as input: its format and role, and its
    /// entries (those that are not plain names are moved to `ignored`).
    pub(crate) fn parse(text: &str, role: Role) -> Result<Manifest, String> {
        let mut m: Manifest = serde_json::from_str(text).map_err(|e| e.to_string())?;
        let (plain, ignored): (BTreeSet<String>, BTreeSet<String>) =
            std::mem::take(&mut m.created).into_iter().partition(|n| rotorshunt::files::plain_name(n).is_some());
        m.created = plain;
        m.ignored = ignored.into_iter().collect();
        if m.format != MANIFEST_FORMAT {
            return Err(format!("format {} (this build reads {MANIFEST_FORMAT})", m.format));
        }
        if m.role != role {
            return Err(format!("role {:?}, expected {role:?}", m.role).to_lowercase());
        }
        Ok(m)
    }
}

impl Manifest {
    /// The warning on the entries dropped when it was read (none if there were none).
    pub(crate) fn ignored_warning(&self, path: &Path) -> Option<String> {
        (!self.ignored.is_empty()).then(|| {
            let shown: Vec<String> =
                self.ignored.iter().take(LISTED_ENTRIES).map(|n| format!("{n:?}")).collect();
            format!(
                "warning: {} records {} entr{} that {} not a plain name inside the folder ({}{}): ignored, never followed, and dropped from the record",
                path.display(),
                self.ignored.len(),
                if self.ignored.len() == 1 { "y" } else { "ies" },
                if self.ignored.len() == 1 { "is" } else { "are" },
                shown.join(", "),
                if self.ignored.len() > LISTED_ENTRIES { ", …" } else { "" }
            )
        })
    }
}

pub(crate) fn output_error(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Output { path: path.display().to_string(), message: e.to_string() }
}

/// The manifest of a folder a study owns, kept in step with the writes into it.
pub(crate) struct Ledger {
    path: PathBuf,
    record: Mutex<Manifest>,
}

impl Ledger {
    fn new(path: PathBuf, manifest: Manifest) -> Ledger {
        Ledger { path, record: Mutex::new(manifest) }
    }

    fn record(&self) -> MutexGuard<'_, Manifest> {
        // A panic elsewhere cannot leave the set half-updated: use it as it is.
        self.record.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn save(&self, m: &Manifest) -> Result<(), Error> {
        let text = json_pretty(m, "the JSON output")? + "\n";
        write_atomic(&self.path, text.as_bytes()).map_err(|e| output_error(&self.path, e))
    }

    /// Write the manifest as it is.
    pub(crate) fn flush(&self) -> Result<(), Error> {
        let m = self.record();
        self.save(&m)
    }

    /// The warning on entries of the manifest as found that were dropped (see
    /// [`Manifest::ignored_warning`]).
    pub(crate) fn ignored_warning(&self) -> Option<String> {
        self.record().ignored_warning(&self.path)
    }

    /// Whether the study created `name` in this folder.
    pub(crate) fn owns(&self, name: &str) -> bool {
        self.record().created.contains(name)
    }

    /// Make `name` (at `path`) the study's before it is written: a recorded entry is; a
    /// new one is recorded (the manifest rewritten first); an existing entry that is not
    /// recorded is the user's and refused.
    pub(crate) fn claim(&self, name: &str, path: &Path) -> Result<(), Error> {
        let mut m = self.record();
        if m.created.contains(name) {
            return Ok(());
        }
        match std::fs::symlink_metadata(path) {
            Ok(_) => return Err(Error::NotOwned { path: path.display().to_string() }),
            Err(e) if e.kind() == io::ErrorKind::NotFound => {}
            Err(e) => return Err(output_error(path, e)),
        }
        m.created.insert(name.to_string());
        let saved = self.save(&m);
        if saved.is_err() {
            m.created.remove(name);
        }
        saved
    }
}

/// What the `--out` folder holds for this study, checked before anything is written and
/// again under the lock: its manifest, if the folder is this study's (the same study file,
/// or the same plan from a study file that moved). Refused: another study's or an
/// unreadable manifest ([`Error::OtherStudy`]); entries the manifest does not record
/// ([`Error::FolderNotEmpty`]) unless `allow_non_empty`; and, even then, such an entry
/// where the study writes ([`Error::NotOwned`]). With `same_plan` (a sharded run,
/// `study slurm`) a manifest of any other
/// plan is refused ([`Error::PlanMismatch`]), even from the same study file.
pub(crate) fn inspect_as(
    out: &Path,
    id: &Identity,
    allow_non_empty: bool,
    same_plan: bool,
) -> Result<Option<Manifest>, Error> {
    // The entries are listed before the manifest is read: an entry is recorded before it
    // is first written, so a manifest read after the listing records every entry a study
    // created before it (read the other way round, a second task of the same study saw the
    // first one's `cases` folder but not yet its manifest, and refused the folder).
    let entries: Vec<String> = match std::fs::read_dir(out) {
        Ok(entries) => entries
            .map(|e| e.map(|e| e.file_name().to_string_lossy().into_owned()))
            .collect::<Result<_, _>>()
            .map_err(|e| output_error(out, e))?,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(output_error(out, e)),
    };
    let other = |owner: String| Error::OtherStudy { dir: out.display().to_string(), owner };
    let manifest = match rotorshunt::files::read_to_string(&out.join(MANIFEST)) {
        Ok(text) => {
            let m = Manifest::parse(&text, Role::Study)
                .map_err(|e| other(format!("a study manifest {MANIFEST} that cannot be read ({e})")))?;
            if same_plan && m.plan_sha256.as_deref() != Some(&id.plan) {
                return Err(Error::PlanMismatch {
                    dir: out.display().to_string(),
                    study: m.study.clone(),
                    found: m.plan_sha256.clone().unwrap_or_default(),
                    advice: "shards split one plan's cases, so a sharded run or `study slurm` needs a folder of its own plan: give a new --out folder, or finish that plan there (an unsharded run of the same study file resumes into it)".into(),
                });
            }
            if m.study != id.study && m.plan_sha256.as_deref() != Some(&id.plan) {
                return Err(other(format!("the study {}", m.study)));
            }
            Some(m)
        }
        Err(e) if e.kind() == io::ErrorKind::NotFound => None,
        Err(e) => return Err(other(format!("a study manifest {MANIFEST} that cannot be read ({e})"))),
    };
    let recorded = manifest.as_ref().map(|m| m.created.clone()).unwrap_or_default();
    let mut foreign = Vec::new();
    for name in entries {
        let ours = name == MANIFEST
            || name == LOCK
            || recorded.contains(&name)
            || temporary_target(&name).is_some_and(|t| t == MANIFEST || recorded.contains(t))
            || rotorshunt::files::staging_parts(&name).is_some_and(|(e, _, _)| recorded.contains(e));
        if !ours {
            foreign.push(name);
        }
    }
    foreign.sort();
    if !foreign.is_empty() && !allow_non_empty {
        return Err(Error::FolderNotEmpty {
            dir: out.display().to_string(),
            count: foreign.len(),
            entries: foreign.into_iter().take(LISTED_ENTRIES).collect(),
        });
    }
    if let Some(clash) = foreign.iter().find(|f| ROOT_OUTPUTS.contains(&f.as_str())) {
        return Err(Error::NotOwned { path: out.join(clash).display().to_string() });
    }
    Ok(manifest)
}

/// The ledger of the `--out` folder, under the lock: the manifest found by [`inspect_as`]
/// brought up to date with this run's identity (or a new one), written, and the
/// temporaries of its entries removed. Also says what changed since the last run.
/// `adjust` is applied to the manifest before it is written (the shard
/// count of a sharded run); an error of `adjust` leaves the folder as it was.
pub(crate) fn open_root_with(
    out: &Path,
    id: &Identity,
    found: Option<Manifest>,
    adjust: impl FnOnce(&mut Manifest) -> Result<(), Error>,
) -> Result<(Ledger, Vec<String>), Error> {
    let mut notes = Vec::new();
    let mut manifest = match found {
        None => Manifest::study(id),
        Some(mut m) => {
            notes.extend(m.ignored_warning(&out.join(MANIFEST)));
            if m.study != id.study {
                notes.push(format!(
                    "note: the study file moved from {} (same plan): the manifest now names it",
                    m.study
                ));
            }
            if m.plan_sha256.as_deref() != Some(&id.plan) {
                notes.push(format!(
                    "note: the plan changed since the last run into {} (base, parameters or cases): the manifest is updated; folders of cases no longer in the plan are kept but left out of the summary",
                    out.display()
                ));
            }
            m.study = id.study.clone();
            m.plan_sha256 = Some(id.plan.clone());
            m.cases = Some(id.cases);
            m.tool = TOOL.into();
            m
        }
    };
    adjust(&mut manifest)?;
    let ledger = Ledger::new(out.join(MANIFEST), manifest);
    ledger.flush()?;
    remove_temporaries(out, |t| t == MANIFEST || ledger.owns(t)).map_err(|e| output_error(out, e))?;
    Ok((ledger, notes))
}

/// The manifest of a study's `--out` folder as it is, for reading (`status`, `merge`, the
/// shard count of a Slurm task): `None` without one.
pub(crate) fn read_manifest(out: &Path) -> Result<Option<Manifest>, String> {
    match rotorshunt::files::read_to_string(&out.join(MANIFEST)) {
        Ok(text) => Manifest::parse(&text, Role::Study).map(Some),
        Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(e.to_string()),
    }
}

/// The ledger of a study's `--out` folder with its manifest as found (under the lock), for
/// `merge`: nothing in it changes but the entries claimed.
pub(crate) fn root_ledger(out: &Path, manifest: Manifest) -> Ledger {
    Ledger::new(out.join(MANIFEST), manifest)
}

/// A case folder opened by a run.
pub(crate) enum CaseFolder {
    /// This run holds the case: the folder's ledger and the case lock.
    Held(Box<Ledger>, CaseLock),
    /// Another run holds the case lock: its holder, as `pid P on host H`, if recorded.
    Busy(Option<String>),
}

/// Open a case folder for a run, creating it if it is new. An existing folder is the
/// study's if it has its case manifest, or holds nothing but that manifest's temporaries
/// and the case lock (a run killed just after creating it); anything else is refused
/// ([`Error::NotOwned`]) before anything is written into it. Then the case lock is taken
/// ([`CaseFolder::Busy`] if another run holds it) and, under it, the manifest read or
/// written and the temporaries of recorded files removed.
pub(crate) fn open_case(dir: &Path, study: &str, name: &str) -> Result<CaseFolder, Error> {
    let path = dir.join(CASE_MANIFEST);
    match rotorshunt::files::create_dir(dir) {
        Ok(()) => {}
        Err(e) if e.kind() == io::ErrorKind::AlreadyExists => check_case_folder(dir)?,
        Err(e) => return Err(output_error(dir, e)),
    }
    let lock = match CaseLock::acquire(dir, study)? {
        Ok(lock) => lock,
        Err(holder) => return Ok(CaseFolder::Busy(holder.shown())),
    };
    let found = match rotorshunt::files::read_to_string(&path) {
        Ok(text) => Some(Manifest::parse(&text, Role::Case).map_err(|e| output_error(&path, e))?),
        Err(e) if e.kind() == io::ErrorKind::NotFound => None,
        Err(e) => return Err(Error::io(&path, &e)),
    };
    // A new manifest is written at once, and one found with entries that are not plain
    // names is written back without them.
    let rewrite = found.as_ref().is_none_or(|m| !m.ignored.is_empty());
    let ledger = Ledger::new(path, found.unwrap_or_else(|| Manifest::case(study, name)));
    if rewrite {
        ledger.flush()?;
    }
    remove_temporaries(dir, |t| t == CASE_MANIFEST || ledger.owns(t)).map_err(|e| output_error(dir, e))?;
    Ok(CaseFolder::Held(Box::new(ledger), lock))
}

/// Whether an existing case folder is the study's (see [`open_case`]).
fn check_case_folder(dir: &Path) -> Result<(), Error> {
    let not_owned = || Error::NotOwned { path: dir.display().to_string() };
    // A file there is the user's; a link or special file is refused (never followed).
    match rotorshunt::files::standing(dir).map_err(|e| Error::io(dir, &e))? {
        rotorshunt::files::Standing::Dir => {}
        rotorshunt::files::Standing::File(_) => return Err(not_owned()),
        rotorshunt::files::Standing::Missing => {
            return Err(output_error(dir, "it disappeared while the study opened it"))
        }
        _ => return Err(rotorshunt::files::real_dir(dir).err().map_or_else(not_owned, |e| Error::io(dir, &e))),
    }
    // The folder is listed first and its manifest read only if listed: another run of the
    // study that created the folder a moment ago (two tasks given the same shard) may
    // rename its manifest in at any time, and a folder listed before that holds only the
    // lock and the manifest's temporaries, which are the study's too.
    let mut entries = Vec::new();
    for e in std::fs::read_dir(dir).map_err(|e| output_error(dir, e))? {
        entries.push(e.map_err(|e| output_error(dir, e))?.file_name());
    }
    if entries.iter().any(|e| e == CASE_MANIFEST) {
        let path = dir.join(CASE_MANIFEST);
        let text = rotorshunt::files::read_to_string(&path).map_err(|e| Error::io(&path, &e))?;
        return Manifest::parse(&text, Role::Case).map(|_| ()).map_err(|e| output_error(&path, e));
    }
    let ours = |e: &std::ffi::OsString| e == CASE_LOCK || e.to_str().and_then(temporary_target) == Some(CASE_MANIFEST);
    if entries.iter().all(ours) {
        Ok(())
    } else {
        Err(not_owned())
    }
}
