//! The output directory of a command: never allowed to replace an input of the run
//! (compared by canonical path, so a symbolic link to an input is refused too) and, in a
//! folder a study owns, never allowed to replace a file the study did not write.
//!
//! A command's `--out` folder ([`OutDir::create`], [`OutDir::with_inputs`]) is written
//! through a staging folder: every file goes first into a fresh hidden folder, and only
//! [`OutDir::commit`], after the last file, moves them into place. So a run that fails or
//! is interrupted leaves the folder as it was (or no folder at all):
//! - a folder that does not exist yet is staged beside it, `PARENT/.NAME.tmp-HOST-PID`,
//!   and renamed into place whole on success (it appears complete or not at all);
//! - an existing folder is staged inside it, `DIR/.rotorshunt-out.tmp-HOST-PID`, and on
//!   success each file is renamed over its old version (one rename per file), the files
//!   a previous run of the same command wrote and this one did not are removed (a stale
//!   `compare.json` of an earlier `chart --compare`), and every other file is left alone.
//!
//! The files a command wrote are recorded in the folder's `.rotorshunt-out.json`, per
//! command, with their SHA-256: a file is removed as stale only when the same command
//! recorded it and it still has the recorded content, so a file the user put there or
//! edited is never removed. A staging folder that a killed run left (SIGKILL; on SIGINT
//! and SIGTERM the binary removes it, [`remove_unfinished`]) is removed by the next run
//! into the same folder when it names this host and a process that no longer runs.

use super::study::Ledger;
use crate::report::{replaceable, write_atomic};
use crate::Error;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The record of the files each command wrote into an output folder.
pub const MANIFEST: &str = ".rotorshunt-out.json";
/// Prefix of the staging folder inside an existing output folder.
const INSIDE_PREFIX: &str = ".rotorshunt-out.tmp-";

/// Staging folders of this process not yet committed or removed (for [`remove_unfinished`]).
/// A commit holds the lock while it moves files, so an interruption sees a folder either
/// fully committed or not at all.
static LIVE: Mutex<Vec<(PathBuf, Vec<PathBuf>)>> = Mutex::new(Vec::new());

/// A directory that receives a command's output files.
pub struct OutDir {
    dir: PathBuf,
    /// Canonical paths of the run's inputs, with what each is ("the --compare file").
    inputs: Vec<(PathBuf, String)>,
    /// The record of a study-owned folder.
    ledger: Option<Ledger>,
    /// Where the files go until [`OutDir::commit`] (None: straight into `dir`).
    staging: Option<Staging>,
}

/// The staging folder of an output folder.
struct Staging {
    /// The folder the files go to on commit (canonical when it exists).
    target: PathBuf,
    /// The staging folder.
    temp: PathBuf,
    /// Whether the target existed when staging began (files are moved one by one).
    existed: bool,
    /// Parent folders created for it, deepest first (removed again if nothing is committed).
    created: Vec<PathBuf>,
    /// SHA-256 of each file written, by name.
    written: Mutex<BTreeMap<String, String>>,
    committed: bool,
}

/// `.rotorshunt-out.json`: per command, the files it wrote last and their SHA-256.
#[derive(Debug, Default, Serialize, Deserialize)]
struct Manifest {
    /// Format version of this file.
    format: u32,
    commands: BTreeMap<String, BTreeMap<String, String>>,
}

fn output_error(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Output { path: path.display().to_string(), message: e.to_string() }
}

fn sha256(bytes: &[u8]) -> String {
    use sha2::{Digest, Sha256};
    Sha256::digest(bytes).iter().map(|b| format!("{b:02x}")).collect()
}

/// This host's name as it appears in staging folder names (no path separators).
fn host() -> String {
    gethostname::gethostname()
        .to_string_lossy()
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() || c == '.' || c == '-' { c } else { '_' })
        .collect()
}

/// Whether process `pid` of this host has ended.
#[cfg(unix)]
fn ended(pid: u32) -> bool {
    let Ok(pid) = libc::pid_t::try_from(pid) else { return false };
    // SAFETY: kill with signal 0 sends nothing; it only checks that the process exists.
    let alive = unsafe { libc::kill(pid, 0) } == 0;
    !alive && io::Error::last_os_error().raw_os_error() == Some(libc::ESRCH)
}

#[cfg(not(unix))]
fn ended(_pid: u32) -> bool {
    false
}

/// Remove the staging folders named `PREFIX HOST-PID` in `dir` that a killed run of this
/// host left: folders only, whose process has ended.
fn remove_stale(dir: &Path, prefix: &str) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    let me = host();
    for e in entries.flatten() {
        let name = e.file_name();
        let Some(rest) = name.to_str().and_then(|n| n.strip_prefix(prefix)) else { continue };
        let Some((h, pid)) = rest.rsplit_once('-') else { continue };
        let Ok(pid) = pid.parse::<u32>() else { continue };
        if h == me && pid != std::process::id() && e.file_type().is_ok_and(|t| t.is_dir()) && ended(pid) {
            let _ = std::fs::remove_dir_all(e.path());
        }
    }
}

/// Refuse an `--out` that exists and is not a folder (a file, a link to one, a broken
/// link, a FIFO, …): [`Error::OutIsNotAFolder`]. A path that cannot be looked at (a
/// parent that is a file) is an [`Error::Output`].
pub fn check_folder(dir: &Path) -> Result<(), Error> {
    let not_folder = |what: &str| Err(Error::OutIsNotAFolder { path: dir.display().to_string(), what: what.into() });
    match std::fs::metadata(dir) {
        Ok(m) if m.is_dir() => Ok(()),
        Ok(m) if m.is_file() => not_folder("a file"),
        Ok(_) => not_folder("a special file (not a regular file or folder)"),
        Err(e) if e.kind() == io::ErrorKind::NotFound => {
            if std::fs::symlink_metadata(dir).is_ok() {
                not_folder("a broken symbolic link")
            } else {
                Ok(())
            }
        }
        Err(e) => Err(output_error(dir, e)),
    }
}

impl Staging {
    /// Stage the output folder `dir` (module docs).
    fn begin(dir: &Path) -> Result<Staging, Error> {
        check_folder(dir)?;
        let pid = std::process::id();
        let host = host();
        let mut created = Vec::new();
        let (target, temp, existed) = if dir.exists() {
            let target = std::fs::canonicalize(dir).map_err(|e| output_error(dir, e))?;
            remove_stale(&target, INSIDE_PREFIX);
            if let (Some(parent), Some(name)) = (target.parent(), target.file_name()) {
                remove_stale(parent, &format!(".{}.tmp-", name.to_string_lossy()));
            }
            let temp = target.join(format!("{INSIDE_PREFIX}{host}-{pid}"));
            (target, temp, true)
        } else {
            let name = dir.file_name().ok_or_else(|| output_error(dir, "the path does not name a folder"))?;
            let parent = dir.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
            let mut missing = parent;
            while !missing.as_os_str().is_empty() && !missing.exists() {
                created.push(missing.to_path_buf());
                missing = missing.parent().unwrap_or(Path::new(""));
            }
            std::fs::create_dir_all(parent).map_err(|e| output_error(dir, e))?;
            let prefix = format!(".{}.tmp-", name.to_string_lossy());
            remove_stale(parent, &prefix);
            (dir.to_path_buf(), parent.join(format!("{prefix}{host}-{pid}")), false)
        };
        // A leftover of this very process id (a pid reused after a kill) is stale too.
        let _ = std::fs::remove_dir_all(&temp);
        let mut live = LIVE.lock().unwrap_or_else(|p| p.into_inner());
        if let Err(e) = std::fs::create_dir(&temp) {
            for p in &created {
                let _ = std::fs::remove_dir(p);
            }
            return Err(output_error(dir, e));
        }
        live.push((temp.clone(), created.clone()));
        Ok(Staging { target, temp, existed, created, written: Mutex::new(BTreeMap::new()), committed: false })
    }

    /// Move the staged files into place (module docs); `command` names the manifest entry.
    fn commit(&mut self, command: &str) -> Result<(), Error> {
        let live = LIVE.lock().unwrap_or_else(|p| p.into_inner());
        let written = std::mem::take(&mut *self.written.lock().unwrap_or_else(|p| p.into_inner()));
        let manifest_path = self.target.join(MANIFEST);
        let mut manifest = if self.existed { read_manifest(&manifest_path) } else { Manifest::default() };
        manifest.format = 1;
        let previous = manifest.commands.insert(command.to_string(), written.clone()).unwrap_or_default();
        let text = json_pretty(&manifest, MANIFEST)? + "\n";
        let moved = if self.existed {
            self.move_files(&written, &previous, &text)
        } else {
            std::fs::write(self.temp.join(MANIFEST), &text)
                .and_then(|_| std::fs::rename(&self.temp, &self.target))
                .map_err(|e| output_error(&self.target, e))
        };
        drop(live);
        moved?;
        self.committed = true;
        let _ = std::fs::remove_dir(&self.temp);
        deregister(&self.temp);
        Ok(())
    }

    /// Into an existing folder: each file over its old version (keeping a replaced file's
    /// mode), then the stale files of `previous`, then the manifest.
    fn move_files(
        &self,
        written: &BTreeMap<String, String>,
        previous: &BTreeMap<String, String>,
        manifest: &str,
    ) -> Result<(), Error> {
        for name in written.keys() {
            let (from, to) = (self.temp.join(name), self.target.join(name));
            let moved = replaceable(&to).and_then(|existing| {
                if let Some(m) = existing.filter(|m| m.is_file()) {
                    std::fs::set_permissions(&from, m.permissions())?;
                }
                std::fs::rename(&from, &to)
            });
            moved.map_err(|e| output_error(&to, e))?;
        }
        for (name, hash) in previous.iter().filter(|(n, _)| !written.contains_key(*n)) {
            let path = self.target.join(name);
            let ours = std::fs::symlink_metadata(&path).is_ok_and(|m| m.is_file())
                && std::fs::read(&path).is_ok_and(|b| sha256(&b) == *hash);
            if ours {
                std::fs::remove_file(&path).map_err(|e| output_error(&path, e))?;
            }
        }
        let path = self.target.join(MANIFEST);
        write_atomic(&path, manifest.as_bytes()).map_err(|e| output_error(&path, e))
    }
}

/// The manifest at `path`; empty when missing or unreadable (then no file is stale).
fn read_manifest(path: &Path) -> Manifest {
    std::fs::read(path).ok().and_then(|b| serde_json::from_slice(&b).ok()).unwrap_or_default()
}

fn deregister(temp: &Path) {
    LIVE.lock().unwrap_or_else(|p| p.into_inner()).retain(|(t, _)| t != temp);
}

impl Drop for Staging {
    fn drop(&mut self) {
        if self.committed {
            return;
        }
        let _ = std::fs::remove_dir_all(&self.temp);
        for p in &self.created {
            let _ = std::fs::remove_dir(p);
        }
        deregister(&self.temp);
    }
}

/// Remove every staging folder of this process that is not committed (and the parent
/// folders made for it), and keep any commit from starting: for the binary's handler of
/// SIGINT and SIGTERM, just before the process ends. A commit under way finishes first.
pub fn remove_unfinished() {
    let live = LIVE.lock().unwrap_or_else(|p| p.into_inner());
    for (temp, created) in live.iter() {
        let _ = std::fs::remove_dir_all(temp);
        for p in created {
            let _ = std::fs::remove_dir(p);
        }
    }
    // The process is about to end: no commit may begin after the cleanup.
    std::mem::forget(live);
}

impl OutDir {
    /// The `--out` folder `dir` of a command, staged (module docs); `input` is the
    /// problem file to protect. Refused: `dir` exists and is not a folder
    /// ([`Error::OutIsNotAFolder`]).
    pub fn create(dir: &Path, input: &str) -> Result<OutDir, Error> {
        OutDir::with_inputs(dir, &[(Path::new(input), "the input problem file")])
    }

    /// The staged `--out` folder `dir`, protecting every input: `(path, what it is)`.
    pub fn with_inputs(dir: &Path, inputs: &[(&Path, &str)]) -> Result<OutDir, Error> {
        let out = OutDir::planned(dir, inputs);
        let staging = Staging::begin(dir)?;
        Ok(OutDir { staging: Some(staging), ..out })
    }

    /// The output folder `dir`, not created yet, written directly (a study's folders,
    /// which their ledger and manifest keep safe), protecting `inputs`.
    pub(crate) fn planned(dir: &Path, inputs: &[(&Path, &str)]) -> OutDir {
        let inputs = inputs
            .iter()
            .filter_map(|(p, what)| std::fs::canonicalize(p).ok().map(|c| (c, what.to_string())))
            .collect();
        OutDir { dir: dir.to_path_buf(), inputs, ledger: None, staging: None }
    }

    /// This folder, recording its files in `ledger` (a study-owned folder).
    pub(crate) fn with_ledger(self, ledger: Ledger) -> OutDir {
        OutDir { ledger: Some(ledger), ..self }
    }

    /// The ledger of a study-owned folder.
    pub(crate) fn ledger(&self) -> Option<&Ledger> {
        self.ledger.as_ref()
    }

    /// The path of an output file (where it is once committed).
    pub fn path(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }

    /// A file this run has written (from the staging folder until it is committed).
    pub fn written(&self, name: &str) -> Option<Vec<u8>> {
        let written = match &self.staging {
            Some(s) => s.written.lock().unwrap_or_else(|p| p.into_inner()).contains_key(name),
            None => true,
        };
        let path = match &self.staging {
            Some(s) => s.temp.join(name),
            None => self.path(name),
        };
        if written {
            std::fs::read(path).ok()
        } else {
            None
        }
    }

    /// An output error for a file of this directory.
    pub fn error(&self, name: &str, e: impl std::fmt::Display) -> Error {
        output_error(&self.path(name), e)
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

    /// Write a file (staged, or atomically into a study's folder). Refused: an input of
    /// the run ([`Error::OutputIsInput`]); in a study-owned folder, an existing file the
    /// study did not write ([`Error::NotOwned`]); a read-only file ([`Error::Output`]).
    pub fn write(&self, name: &str, bytes: &[u8]) -> Result<(), Error> {
        self.check_not_input(name)?;
        if let Some(ledger) = &self.ledger {
            ledger.claim(name, &self.path(name))?;
        }
        match &self.staging {
            Some(s) => {
                replaceable(&self.path(name)).map_err(|e| self.error(name, e))?;
                std::fs::write(s.temp.join(name), bytes).map_err(|e| self.error(name, e))?;
                s.written.lock().unwrap_or_else(|p| p.into_inner()).insert(name.to_string(), sha256(bytes));
                Ok(())
            }
            None => write_atomic(&self.path(name), bytes).map_err(|e| self.error(name, e)),
        }
    }

    /// Write a figure as `stem.svg` and `stem.png` (each by [`OutDir::write`]).
    pub fn figure(&self, stem: &str, figure: &dyn crate::report::plot::Figure) -> Result<(), Error> {
        let svg = format!("{stem}.svg");
        self.write(&svg, figure.svg().map_err(|e| self.error(&svg, e))?.as_bytes())?;
        let png = format!("{stem}.png");
        self.write(&png, &figure.png().map_err(|e| self.error(&png, e))?)
    }

    /// Put the written files in place, as `command`'s output (module docs). A folder
    /// written directly (a study's) has nothing to do. An `OutDir` dropped without a
    /// commit leaves its folder as it was.
    pub fn commit(mut self, command: &str) -> Result<(), Error> {
        match self.staging.as_mut() {
            Some(s) => s.commit(command),
            None => Ok(()),
        }
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

/// The figures this run wrote into the folder, for a page that embeds them.
impl crate::report::html::Figures for OutDir {
    fn svg(&self, name: &str) -> Option<String> {
        let stem = crate::report::html::plain_name(name)?.trim_end_matches(".png");
        self.written(&format!("{stem}.svg")).and_then(|b| String::from_utf8(b).ok())
    }
    fn png(&self, name: &str) -> Option<Vec<u8>> {
        crate::report::html::plain_name(name).filter(|n| n.ends_with(".png")).and_then(|n| self.written(n))
    }
}
