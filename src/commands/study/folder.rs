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
//! - [`StudyLock`] keeps a second run out of the folder while one runs.

use super::TOOL;
use crate::report::{remove_temporaries, temporary_target, write_atomic};
use crate::Error;
use fs4::{FileExt, TryLockError};
use serde::{Deserialize, Serialize};
use std::collections::BTreeSet;
use std::fs::File;
use std::io::{self, Read, Seek, Write};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

/// The manifest of a study's `--out` folder.
pub(crate) const MANIFEST: &str = ".rotorshunt-study.json";
/// The manifest of a case folder.
pub(crate) const CASE_MANIFEST: &str = ".rotorshunt-case.json";
/// The lock file of a study's `--out` folder.
pub(crate) const LOCK: &str = ".rotorshunt-study.lock";
/// The folder of the case folders.
pub(crate) const CASES: &str = "cases";
/// The entries a study writes in its `--out` folder besides its manifest and lock.
pub(crate) const ROOT_OUTPUTS: [&str; 4] = [CASES, "summary.csv", "summary.json", "summary.md"];

/// Format of the manifests.
const MANIFEST_FORMAT: u32 = 1;
/// How a manifest names the temporaries a killed run may leave beside its entries.
const TEMPORARIES: &str = ".rotorshunt-tmp.<entry>.<pid>.<n>, beside a recorded entry or this manifest";
/// Entries named by [`Error::FolderNotEmpty`]; the rest are counted.
const LISTED_ENTRIES: usize = 5;
/// Tries at the lock when its file is removed between opening and locking it (its holder
/// ending), each of which is a fresh start.
const LOCK_ATTEMPTS: usize = 8;

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
    /// The case's name (case folder).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub case: Option<String>,
    /// Entries of this folder the study created: files, and the `cases` folder.
    pub created: BTreeSet<String>,
    /// The temporaries a killed run may leave.
    pub temporaries: String,
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
            case: None,
            created: BTreeSet::new(),
            temporaries: TEMPORARIES.into(),
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
            case: Some(name.into()),
            created: BTreeSet::new(),
            temporaries: TEMPORARIES.into(),
        }
    }

    fn parse(text: &str, role: Role) -> Result<Manifest, String> {
        let m: Manifest = serde_json::from_str(text).map_err(|e| e.to_string())?;
        if m.format != MANIFEST_FORMAT {
            return Err(format!("format {} (this build reads {MANIFEST_FORMAT})", m.format));
        }
        if m.role != role {
            return Err(format!("role {:?}, expected {role:?}", m.role).to_lowercase());
        }
        Ok(m)
    }
}

fn output_error(path: &Path, e: impl std::fmt::Display) -> Error {
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
        let text = serde_json::to_string_pretty(m).expect("plain data serialises") + "\n";
        write_atomic(&self.path, text.as_bytes()).map_err(|e| output_error(&self.path, e))
    }

    /// Write the manifest as it is.
    pub(crate) fn flush(&self) -> Result<(), Error> {
        let m = self.record();
        self.save(&m)
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
/// where the study writes ([`Error::NotOwned`]).
pub(crate) fn inspect(out: &Path, id: &Identity, allow_non_empty: bool) -> Result<Option<Manifest>, Error> {
    let entries = match std::fs::read_dir(out) {
        Ok(entries) => entries,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(output_error(out, e)),
    };
    let other = |owner: String| Error::OtherStudy { dir: out.display().to_string(), owner };
    let manifest = match std::fs::read_to_string(out.join(MANIFEST)) {
        Ok(text) => {
            let m = Manifest::parse(&text, Role::Study)
                .map_err(|e| other(format!("a study manifest {MANIFEST} that cannot be read ({e})")))?;
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
    for e in entries {
        let name = e.map_err(|e| output_error(out, e))?.file_name().to_string_lossy().into_owned();
        let ours = name == MANIFEST
            || name == LOCK
            || recorded.contains(&name)
            || temporary_target(&name).is_some_and(|t| t == MANIFEST || recorded.contains(t));
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

/// The ledger of the `--out` folder, under the lock: the manifest found by [`inspect`]
/// brought up to date with this run's identity (or a new one), written, and the
/// temporaries of its entries removed. Also says what changed since the last run.
pub(crate) fn open_root(out: &Path, id: &Identity, found: Option<Manifest>) -> Result<(Ledger, Vec<String>), Error> {
    let mut notes = Vec::new();
    let manifest = match found {
        None => Manifest::study(id),
        Some(mut m) => {
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
    let ledger = Ledger::new(out.join(MANIFEST), manifest);
    ledger.flush()?;
    remove_temporaries(out, |t| t == MANIFEST || ledger.owns(t)).map_err(|e| output_error(out, e))?;
    Ok((ledger, notes))
}

/// The ledger of a case folder, creating the folder if it is new. An existing folder is
/// the study's if it has its case manifest, or holds nothing but that manifest's
/// temporaries (a run killed just after creating it); anything else is refused
/// ([`Error::NotOwned`]). The temporaries of recorded files are removed.
pub(crate) fn open_case(dir: &Path, study: &str, name: &str) -> Result<Ledger, Error> {
    let path = dir.join(CASE_MANIFEST);
    let found = match std::fs::create_dir(dir) {
        Ok(()) => None,
        Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {
            let not_owned = || Error::NotOwned { path: dir.display().to_string() };
            if !std::fs::symlink_metadata(dir).map_err(|e| output_error(dir, e))?.is_dir() {
                return Err(not_owned());
            }
            match std::fs::read_to_string(&path) {
                Ok(text) => Some(Manifest::parse(&text, Role::Case).map_err(|e| output_error(&path, e))?),
                Err(e) if e.kind() == io::ErrorKind::NotFound => {
                    for e in std::fs::read_dir(dir).map_err(|e| output_error(dir, e))? {
                        let entry = e.map_err(|e| output_error(dir, e))?.file_name();
                        if entry.to_str().and_then(temporary_target) != Some(CASE_MANIFEST) {
                            return Err(not_owned());
                        }
                    }
                    None
                }
                Err(e) => return Err(output_error(&path, e)),
            }
        }
        Err(e) => return Err(output_error(dir, e)),
    };
    let fresh = found.is_none();
    let ledger = Ledger::new(path, found.unwrap_or_else(|| Manifest::case(study, name)));
    if fresh {
        ledger.flush()?;
    }
    remove_temporaries(dir, |t| t == CASE_MANIFEST || ledger.owns(t)).map_err(|e| output_error(dir, e))?;
    Ok(ledger)
}

/// What a lock file records of its holder.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Holder {
    pid: u32,
    host: String,
    study: String,
    started_unix_s: u64,
}

fn host() -> String {
    gethostname::gethostname().to_string_lossy().into_owned()
}

/// The lock of a study's `--out` folder: the file [`LOCK`], locked exclusively with the
/// operating system's advisory lock (flock) and holding the holder's pid, host, study
/// and start time. The kernel releases the lock when its holder dies, even by SIGKILL:
/// a lock file that can be locked is stale and is taken over, unless it records another
/// host, whose runs this host's kernel cannot see (network filesystems): that one is
/// refused like a live lock. The file is removed when the lock is dropped, on every
/// return path.
pub(crate) struct StudyLock {
    file: File,
    path: PathBuf,
    /// The note on a stale lock taken over.
    pub(crate) taken_over: Option<String>,
}

impl StudyLock {
    /// Take the lock of `out` for `study`, or refuse with [`Error::StudyLocked`].
    pub(crate) fn acquire(out: &Path, study: &str) -> Result<StudyLock, Error> {
        let path = out.join(LOCK);
        let locked = |h: Option<Holder>| Error::StudyLocked {
            dir: out.display().to_string(),
            lock: path.display().to_string(),
            pid: h.as_ref().map(|h| h.pid),
            host: h.map(|h| h.host),
        };
        let me = host();
        for _ in 0..LOCK_ATTEMPTS {
            let mut options = std::fs::OpenOptions::new();
            options.read(true).write(true);
            let (mut file, fresh) = match options.clone().create_new(true).open(&path) {
                Ok(f) => (f, true),
                Err(e) if e.kind() == io::ErrorKind::AlreadyExists => match options.open(&path) {
                    Ok(f) => (f, false),
                    Err(e) if e.kind() == io::ErrorKind::NotFound => continue,
                    Err(e) => return Err(output_error(&path, e)),
                },
                Err(e) => return Err(output_error(&path, e)),
            };
            match FileExt::try_lock(&file) {
                Ok(()) => {}
                Err(TryLockError::WouldBlock) => return Err(locked(read_holder(&mut file))),
                Err(TryLockError::Error(e)) => return Err(output_error(&path, format!("cannot lock: {e}"))),
            }
            // Its holder may have removed the file between the open and the lock: this
            // file is then no one's lock, so start again.
            if !same_file(&file, &path) {
                continue;
            }
            let previous = if fresh { None } else { read_holder(&mut file) };
            if let Some(h) = previous.as_ref().filter(|h| h.host != me) {
                return Err(locked(Some(h.clone())));
            }
            let taken_over = (!fresh).then(|| match &previous {
                Some(h) => format!(
                    "note: took over the lock of an earlier run (pid {} on host {}) that is no longer running",
                    h.pid, h.host
                ),
                None => "note: took over a lock left by an earlier run that is no longer running".to_string(),
            });
            let holder = Holder {
                pid: std::process::id(),
                host: me.clone(),
                study: study.to_string(),
                started_unix_s: std::time::SystemTime::now()
                    .duration_since(std::time::UNIX_EPOCH)
                    .map_or(0, |d| d.as_secs()),
            };
            let text = serde_json::to_string(&holder).expect("plain data serialises") + "\n";
            (|| {
                file.set_len(0)?;
                file.rewind()?;
                file.write_all(text.as_bytes())?;
                file.sync_all()
            })()
            .map_err(|e| output_error(&path, e))?;
            return Ok(StudyLock { file, path, taken_over });
        }
        Err(output_error(&path, format!("the lock file kept disappearing ({LOCK_ATTEMPTS} attempts)")))
    }
}

impl Drop for StudyLock {
    fn drop(&mut self) {
        // Still holding the lock: remove the file if it is still this lock's.
        if same_file(&self.file, &self.path) {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

fn read_holder(file: &mut File) -> Option<Holder> {
    let mut text = String::new();
    file.rewind().ok()?;
    file.read_to_string(&mut text).ok()?;
    serde_json::from_str(&text).ok()
}

/// Whether the open `file` is the file at `path` now.
#[cfg(unix)]
fn same_file(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), std::fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

/// Whether the open `file` is the file at `path` now (without inode numbers: whether a
/// file is there).
#[cfg(not(unix))]
fn same_file(_: &File, path: &Path) -> bool {
    path.exists()
}
