//! The output directory of a command: never allowed to replace an input of the run
//! (compared by canonical path, so a symbolic link to an input is refused too) and, in a
//! folder a study owns, never allowed to replace a file the study did not write.
//!
//! A command's `--out` folder ([`OutDir::create`], [`OutDir::with_inputs`]) is written
//! through a staging folder beside it, `PARENT/.rotorshunt-tmp.NAME.TOKEN` (TOKEN unique
//! to the run, [`files::token`]; the tool's one hidden-name scheme,
//! [`files::staging_name`]): every file goes first into the staging folder, and only
//! [`OutDir::commit`], after the last file, puts the whole set in place in one step.
//! So a reader, and a run that fails or is killed at any point, sees the old folder or
//! the new one, never a mix:
//! - a folder that does not exist yet: the staging folder is renamed into place
//!   (`RENAME_NOREPLACE`);
//! - an existing folder: what the new folder keeps of it (the user's files and
//!   folders, other commands' outputs) is carried into the staging folder as hard links
//!   (links as links, copies where a hard link cannot be made), the two folders are
//!   exchanged in one `renameat2(RENAME_EXCHANGE)`, and the old one, now at the staging
//!   name, is removed. Where the file system cannot exchange, the old folder is renamed
//!   aside first (a reader may then find no folder for an instant, never a mixed one).
//!
//! The files a command wrote are recorded in the folder's `.rotorshunt-out.json`, per
//! command, with their SHA-256, and with the token of the run that staged it: a file is
//! dropped as stale only when the same command recorded it and it still has the
//! recorded content, so a file the user put there or edited is never removed; a recorded
//! name that is not a plain name inside the folder is ignored with a warning. A staging
//! folder a killed run left (SIGKILL; on SIGINT and SIGTERM the binary removes it,
//! [`remove_unfinished`]) is removed by the next run only when it proves to be the
//! tool's: its own record carries the token of its name and names a process of this
//! host that has ended, or the folder's record names it as the old folder of the last
//! swap. A user's folder that merely looks like one is left alone.

use super::study::Ledger;
use crate::commands::Error;
use rotorshunt::files;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The record of the files each command wrote into an output folder.
pub const MANIFEST: &str = ".rotorshunt-out.json";
/// Format of [`MANIFEST`].
const MANIFEST_FORMAT: u32 = 1;

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
    /// The staging folder, beside the target.
    temp: PathBuf,
    /// This run's token (in the staging folder's name and record).
    token: String,
    /// Whether the target existed when staging began.
    existed: bool,
    /// Parent folders created for it, deepest first (removed again if nothing is committed).
    created: Vec<PathBuf>,
    /// SHA-256 of each file written, by name.
    written: Mutex<BTreeMap<String, String>>,
    /// Warnings about what was found on disk (tampered records, leftovers kept).
    notes: Vec<String>,
    committed: bool,
}

/// `.rotorshunt-out.json`: per command, the files it wrote last and their SHA-256.
#[derive(Debug, Default, Serialize, Deserialize)]
struct Manifest {
    /// Format version of this file.
    format: u32,
    commands: BTreeMap<String, BTreeMap<String, String>>,
    /// The run that staged this folder.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    staged_by: Option<Stager>,
}

/// Who staged a folder: the proof a later run needs before removing a staging folder.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Stager {
    /// The run's token, also in the staging folder's name.
    token: String,
    /// Host name ([`files::host`]).
    host: String,
    /// Process id.
    pid: u32,
}

fn output_error(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Output { path: path.display().to_string(), message: e.to_string() }
}

fn io_error(path: &Path) -> impl Fn(io::Error) -> Error + '_ {
    move |e| Error::io(path, &e)
}

fn sha256(bytes: &[u8]) -> String {
    use sha2::{Digest, Sha256};
    Sha256::digest(bytes).iter().map(|b| format!("{b:02x}")).collect()
}

/// Whether process `pid` of this host has ended.
#[cfg(unix)]
fn ended(pid: u32) -> bool {
    let Ok(pid) = libc::pid_t::try_from(pid) else { return false };
    if pid <= 0 {
        return false;
    }
    // SAFETY: kill with signal 0 sends nothing; it only checks that the process exists.
    let alive = unsafe { libc::kill(pid, 0) } == 0;
    !alive && io::Error::last_os_error().raw_os_error() == Some(libc::ESRCH)
}

#[cfg(not(unix))]
fn ended(_pid: u32) -> bool {
    false
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

/// The manifest at `path` as found: empty when missing, unreadable or not a regular
/// file (then no file is stale); recorded names that are not plain names are dropped
/// with a warning in `notes`.
fn read_manifest(path: &Path, notes: &mut Vec<String>) -> Manifest {
    let found = match files::read(path) {
        Ok(bytes) => bytes,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Manifest::default(),
        Err(e) => {
            notes.push(format!("warning: {} is ignored ({e}): no file is dropped as stale", path.display()));
            return Manifest::default();
        }
    };
    let mut m: Manifest = match serde_json::from_slice(&found) {
        Ok(m) => m,
        Err(e) => {
            notes.push(format!(
                "warning: {} is not a record this tool wrote ({e}): it is replaced, and no file is dropped as stale",
                path.display()
            ));
            return Manifest::default();
        }
    };
    for (command, names) in m.commands.iter_mut() {
        names.retain(|name, _| {
            let plain = files::plain_name(name).is_some() && name != MANIFEST;
            if !plain {
                notes.push(format!(
                    "warning: {} records {:?} for `{command}`, which is not a plain name inside the folder: it is ignored",
                    path.display(),
                    name
                ));
            }
            plain
        });
    }
    m
}

/// This run's record in a folder it stages.
fn stager(token: &str) -> Stager {
    Stager { token: token.to_string(), host: files::host(), pid: std::process::id() }
}

/// Whether a folder's entry is a temporary of its record that a killed run left: named
/// so, and a plain file as every temporary is (a folder or link so named is a user's and
/// is kept).
fn manifest_temporary(name: &str, entry: &std::fs::DirEntry) -> bool {
    files::temporary_target(name).is_some_and(|t| t == MANIFEST) && entry.file_type().is_ok_and(|t| t.is_file())
}

impl Staging {
    /// Stage the output folder `dir` (module docs).
    fn begin(dir: &Path) -> Result<Staging, Error> {
        check_folder(dir)?;
        let mut created = Vec::new();
        let existed = dir.exists();
        let target = if existed {
            std::fs::canonicalize(dir).map_err(|e| output_error(dir, e))?
        } else {
            let parent = dir.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
            let mut missing = parent;
            while !missing.as_os_str().is_empty() && !missing.exists() {
                created.push(missing.to_path_buf());
                missing = missing.parent().unwrap_or(Path::new(""));
            }
            std::fs::create_dir_all(parent).map_err(|e| output_error(dir, e))?;
            dir.to_path_buf()
        };
        let (Some(parent), Some(name)) = (target.parent(), target.file_name()) else {
            return Err(output_error(dir, "the path does not name a folder"));
        };
        let parent = if parent.as_os_str().is_empty() { Path::new(".") } else { parent };
        let name = name.to_string_lossy().into_owned();
        let mut notes = Vec::new();
        remove_stale(parent, &name, &target, &mut notes);
        let token = files::token();
        let temp = parent.join(files::staging_name(&name, &token));
        let mut live = LIVE.lock().unwrap_or_else(|p| p.into_inner());
        if let Err(e) = files::create_dir(&temp) {
            for p in &created {
                let _ = std::fs::remove_dir(p);
            }
            return Err(Error::io(dir, &e));
        }
        live.push((temp.clone(), created.clone()));
        // The staging folder's record, first of all: what proves it the tool's own.
        let record = Manifest { format: MANIFEST_FORMAT, commands: BTreeMap::new(), staged_by: Some(stager(&token)) };
        let text = json_pretty(&record, MANIFEST)? + "\n";
        files::create_new(&temp.join(MANIFEST))
            .and_then(|mut f| std::io::Write::write_all(&mut f, text.as_bytes()))
            .map_err(|e| Error::io(dir, &e))?;
        Ok(Staging {
            target,
            temp,
            token,
            existed,
            created,
            written: Mutex::new(BTreeMap::new()),
            notes,
            committed: false,
        })
    }

    /// Write one staged file.
    fn write(&self, name: &str, bytes: &[u8]) -> io::Result<()> {
        use std::io::Write;
        let path = self.temp.join(name);
        let mut f = files::create_new(&path)?;
        f.write_all(bytes)?;
        self.written.lock().unwrap_or_else(|p| p.into_inner()).insert(name.to_string(), sha256(bytes));
        Ok(())
    }

    /// Put the staged folder in place (module docs); `command` names the manifest entry.
    fn commit(&mut self, command: &str) -> Result<Vec<String>, Error> {
        let live = LIVE.lock().unwrap_or_else(|p| p.into_inner());
        let written = std::mem::take(&mut *self.written.lock().unwrap_or_else(|p| p.into_inner()));
        let mut manifest = if self.existed {
            read_manifest(&self.target.join(MANIFEST), &mut self.notes)
        } else {
            Manifest::default()
        };
        manifest.format = MANIFEST_FORMAT;
        manifest.staged_by = Some(stager(&self.token));
        let previous = manifest.commands.insert(command.to_string(), written.clone()).unwrap_or_default();
        let text = json_pretty(&manifest, MANIFEST)? + "\n";
        let done = if self.existed {
            self.keep_mode()
                .and_then(|_| self.carry_over(&written, &previous))
                .and_then(|_| self.write_manifest(&text))
                .and_then(|_| self.swap(&manifest))
        } else {
            self.write_manifest(&text).and_then(|_| {
                files::rename_new(&self.temp, &self.target).map_err(|e| match e.kind() {
                    io::ErrorKind::AlreadyExists => output_error(
                        &self.target,
                        "the folder was created by something else while this run wrote its files; nothing was replaced",
                    ),
                    _ => Error::io(&self.target, &e),
                })
            })
        };
        drop(live);
        done?;
        self.committed = true;
        deregister(&self.temp);
        Ok(std::mem::take(&mut self.notes))
    }

    /// Give the staging folder the old folder's permissions (and, where this process
    /// may, its owner), so the swap changes the files, not who may read them.
    fn keep_mode(&self) -> Result<(), Error> {
        let m = std::fs::symlink_metadata(&self.target).map_err(io_error(&self.target))?;
        std::fs::set_permissions(&self.temp, m.permissions()).map_err(io_error(&self.temp))?;
        #[cfg(unix)]
        {
            use std::os::unix::fs::MetadataExt;
            // Only root may give a folder away; for anyone else the owner is already theirs.
            let _ = std::os::unix::fs::lchown(&self.temp, Some(m.uid()), Some(m.gid()));
        }
        Ok(())
    }

    fn write_manifest(&self, text: &str) -> Result<(), Error> {
        files::write_atomic(&self.temp.join(MANIFEST), text.as_bytes()).map_err(io_error(&self.target))
    }

    /// Carry into the staging folder what the new folder keeps of the old one: every
    /// entry but the files this run wrote, the manifest, and the files this command
    /// wrote last time, still unchanged, that it did not write again (stale).
    fn carry_over(&self, written: &BTreeMap<String, String>, previous: &BTreeMap<String, String>) -> Result<(), Error> {
        let entries = std::fs::read_dir(&self.target).map_err(io_error(&self.target))?;
        for e in entries {
            let e = e.map_err(io_error(&self.target))?;
            let name = e.file_name();
            let text = name.to_string_lossy();
            if written.contains_key(text.as_ref()) || text == MANIFEST {
                continue;
            }
            let from = e.path();
            if let Some(hash) = previous.get(text.as_ref()) {
                if files::read(&from).is_ok_and(|b| sha256(&b) == *hash) {
                    continue;
                }
            }
            if manifest_temporary(&text, &e) {
                continue;
            }
            carry(&from, &self.temp.join(&name)).map_err(io_error(&from))?;
        }
        Ok(())
    }

    /// Exchange the staging folder with the target, then remove the old folder.
    fn swap(&self, manifest: &Manifest) -> Result<(), Error> {
        let exchanged = files::exchange(&self.temp, &self.target).map_err(io_error(&self.target))?;
        let old = if exchanged {
            self.temp.clone()
        } else {
            let old = files::old_staging(&self.temp);
            files::rename_new(&self.target, &old).map_err(io_error(&self.target))?;
            if let Err(e) = files::rename_new(&self.temp, &self.target) {
                let _ = files::rename_new(&old, &self.target);
                return Err(Error::io(&self.target, &e));
            }
            old
        };
        retire(&old, &self.target, manifest, &mut Vec::new());
        Ok(())
    }
}

/// Put `from` (an entry of the old folder) at `to` in the staging folder without
/// copying data where it can: a file as a hard link (a copy with its permissions
/// where linking fails), a link as a new link with the same text (never followed), a
/// folder as a new folder of carried entries. A FIFO, device or socket is refused.
fn carry(from: &Path, to: &Path) -> io::Result<()> {
    match files::standing(from)? {
        files::Standing::Missing => Ok(()),
        files::Standing::File(m) => files::hard_link(from, to).or_else(|_| {
            let bytes = files::read(from)?;
            let mut f = files::create_new(to)?;
            std::io::Write::write_all(&mut f, &bytes)?;
            f.set_permissions(m.permissions())
        }),
        files::Standing::Link => files::copy_link(from, to),
        files::Standing::Dir => {
            files::create_dir(to)?;
            for e in std::fs::read_dir(from)? {
                let e = e?;
                carry(&e.path(), &to.join(e.file_name()))?;
            }
            Ok(())
        }
        files::Standing::Special(what) => Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            files::Refused { what: format!("{what} (which a new folder cannot carry over)") },
        )),
    }
}

/// Remove `old`, the previous version of `target` after a swap: first every entry it
/// holds that the new folder lacks and that is not a stale output (one added while the
/// run wrote) is moved into the new folder, so nothing of the user's is lost.
fn retire(old: &Path, target: &Path, manifest: &Manifest, notes: &mut Vec<String>) {
    let mut previous = Manifest::default();
    if let Ok(b) = files::read(&old.join(MANIFEST)) {
        previous = serde_json::from_slice(&b).unwrap_or_default();
    }
    let stale = |name: &str, path: &Path| {
        previous.commands.iter().any(|(c, names)| {
            names.get(name).is_some_and(|h| files::read(path).is_ok_and(|b| sha256(&b) == *h))
                && !manifest.commands.get(c).is_some_and(|n| n.contains_key(name))
        })
    };
    if let Ok(entries) = std::fs::read_dir(old) {
        for e in entries.flatten() {
            let name = e.file_name();
            let text = name.to_string_lossy();
            let kept = target.join(&name);
            if text == MANIFEST || files::standing(&kept).is_ok_and(|s| !matches!(s, files::Standing::Missing)) {
                continue;
            }
            if manifest_temporary(&text, &e) || stale(&text, &e.path()) {
                continue;
            }
            if files::rename_new(&e.path(), &kept).is_err() {
                notes.push(format!(
                    "warning: {} could not be moved back into {}",
                    e.path().display(),
                    target.display()
                ));
            }
        }
    }
    if let Err(e) = files::remove_dir_all(old) {
        notes.push(format!("warning: the old folder {} could not be removed: {e}", old.display()));
    }
}

/// Remove the staging folders of the folder `name` in `parent` that a killed run left,
/// when they prove to be the tool's (module docs); others are left, with a note when
/// they carry a token this host could check.
fn remove_stale(parent: &Path, name: &str, target: &Path, notes: &mut Vec<String>) {
    let Ok(entries) = std::fs::read_dir(parent) else { return };
    let mut target_notes = Vec::new();
    let current = files::real_dir(target)
        .ok()
        .filter(|d| *d)
        .map(|_| read_manifest(&target.join(MANIFEST), &mut target_notes))
        .and_then(|m| m.staged_by.map(|s| (s, m.commands)));
    let me = files::host();
    for e in entries.flatten() {
        let entry = e.file_name();
        let Some((of, token, old)) = entry.to_str().and_then(files::staging_parts) else { continue };
        if of != name || !files::real_dir(&e.path()).unwrap_or(false) {
            continue;
        }
        let gone = |s: &Stager| s.host == me && s.pid != std::process::id() && ended(s.pid);
        // The old folder of the last swap: the target's own record names its token.
        if let Some((s, commands)) = current.as_ref().filter(|(s, _)| s.token == token && gone(s)) {
            let m = Manifest { format: MANIFEST_FORMAT, commands: commands.clone(), staged_by: Some(s.clone()) };
            retire(&e.path(), target, &m, notes);
            continue;
        }
        if old {
            continue;
        }
        // An unfinished staging folder: its own record carries its token.
        let own = files::read(&e.path().join(MANIFEST))
            .ok()
            .and_then(|b| serde_json::from_slice::<Manifest>(&b).ok())
            .and_then(|m| m.staged_by);
        match own {
            Some(s) if s.token == token && gone(&s) => {
                if let Err(err) = files::remove_dir_all(&e.path()) {
                    notes.push(format!(
                        "warning: the unfinished staging folder {} could not be removed: {err}",
                        e.path().display()
                    ));
                }
            }
            // A run killed between creating the folder and its record leaves it empty:
            // removing an empty folder loses nothing (remove_dir refuses any other).
            None => {
                let _ = std::fs::remove_dir(e.path());
            }
            // Another live run's, or one of another host: not this run's to judge.
            Some(_) => {}
        }
    }
}

fn deregister(temp: &Path) {
    LIVE.lock().unwrap_or_else(|p| p.into_inner()).retain(|(t, _)| t != temp);
}

impl Drop for Staging {
    fn drop(&mut self) {
        if self.committed {
            return;
        }
        let _ = files::remove_dir_all(&self.temp);
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
        let _ = files::remove_dir_all(temp);
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

    /// The staged folder `name` inside this one, protecting the same inputs (a study's
    /// `summary/`, swapped whole). Refused: a link or anything but a folder at `name`
    /// ([`Error::Unsafe`]), and in a study-owned folder an entry the study did not create.
    pub(crate) fn sub(&self, name: &str) -> Result<OutDir, Error> {
        let path = self.path(name);
        if let Some(ledger) = &self.ledger {
            ledger.claim(name, &path)?;
        }
        files::real_dir(&path).map_err(|e| Error::io(&path, &e))?;
        let staging = Staging::begin(&path)?;
        Ok(OutDir { dir: path, inputs: self.inputs.clone(), ledger: None, staging: Some(staging) })
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
                files::replaceable(&self.path(name)).map_err(|e| Error::io(&self.path(name), &e))?;
                s.write(name, bytes).map_err(|e| Error::io(&self.path(name), &e))
            }
            None => files::write_atomic(&self.path(name), bytes).map_err(|e| Error::io(&self.path(name), &e)),
        }
    }

    /// Write a figure as `stem.svg` and `stem.png` (each by [`OutDir::write`]).
    pub fn figure(&self, stem: &str, figure: &dyn rotorshunt::report::plot::Figure) -> Result<(), Error> {
        let svg = format!("{stem}.svg");
        self.write(&svg, figure.svg().map_err(|e| self.error(&svg, e))?.as_bytes())?;
        let png = format!("{stem}.png");
        self.write(&png, &figure.png().map_err(|e| self.error(&png, e))?)
    }

    /// Put the written files in place, as `command`'s output (module docs), and return
    /// tell `progress` what was found on disk and ignored (record entries, leftovers that
    /// could not be removed), one `warning: ` line each. A folder written directly (a
    /// study's) has nothing to do. An `OutDir` dropped without a commit leaves its
    /// folder as it was.
    pub fn commit(mut self, command: &str, progress: &dyn rotorshunt::progress::Progress) -> Result<(), Error> {
        let notes = match self.staging.as_mut() {
            Some(s) => s.commit(command)?,
            None => Vec::new(),
        };
        notes.iter().for_each(|n| progress.notice(n));
        Ok(())
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
impl rotorshunt::report::html::Figures for OutDir {
    fn svg(&self, name: &str) -> Option<String> {
        let stem = rotorshunt::report::html::plain_name(name)?.trim_end_matches(".png");
        self.written(&format!("{stem}.svg")).and_then(|b| String::from_utf8(b).ok())
    }
    fn png(&self, name: &str) -> Option<Vec<u8>> {
        rotorshunt::report::html::plain_name(name).filter(|n| n.ends_with(".png")).and_then(|n| self.written(n))
    }
}
