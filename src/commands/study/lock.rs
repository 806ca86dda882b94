//! The locks of a study's folders: [`StudyLock`] keeps a second run out of the `--out`
//! folder while one runs (or, for the shards of one study, while one sets it up);
//! [`CaseLock`] keeps two tasks out of one case folder. Each is an advisory `flock` on a
//! file that records its holder, released by the kernel when the holder dies.

use super::folder::{output_error, CASE_LOCK, LOCK};
use crate::commands::out::json_compact;
use crate::commands::Error;
use fs4::{FileExt, TryLockError};
use serde::{Deserialize, Serialize};
use std::fs::File;
use std::io::{self, Read, Seek, Write};
use std::path::{Path, PathBuf};

/// Tries at the lock when its file is removed between opening and locking it (its holder
/// ending), each of which is a fresh start.
const LOCK_ATTEMPTS: usize = 8;
/// How long a shard or `merge` waits for another task's setup of the `--out` folder: a
/// setup holds the lock for a manifest write (milliseconds), so a minute means a run
/// that holds the folder for its whole length (an unsharded study) or a hung filesystem.
const SETUP_LOCK_WAIT: std::time::Duration = std::time::Duration::from_secs(60);
/// Poll interval while waiting for the setup lock.
const SETUP_LOCK_POLL: std::time::Duration = std::time::Duration::from_millis(25);
/// Tries at a case lock before the case is left to the task that holds it: `study status`
/// holds a case lock for microseconds to see whether a case is running.
const CASE_LOCK_TRIES: usize = 5;
/// Pause between those tries.
const CASE_LOCK_PAUSE: std::time::Duration = std::time::Duration::from_millis(20);

/// What a lock file records of its holder.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub(crate) struct Holder {
    pub(crate) pid: u32,
    pub(crate) host: String,
    study: String,
    started_unix_s: u64,
}

/// The longest host name a lock may record (Linux's `HOST_NAME_MAX` is 64; a fully
/// qualified name is at most 253 characters).
const MAX_HOST_CHARS: usize = 253;

/// What a lock file found on disk records, checked as input: a lock is a record another
/// process (or a user) may have written.
#[derive(Debug, Clone)]
pub(crate) enum Recorded {
    /// Nothing (a run killed between creating the file and writing it).
    Empty,
    /// A holder with every field, each valid.
    Holder(Holder),
    /// Text that is not a valid holder: why, and the host it names if it names one.
    Invalid { why: String, host: Option<String> },
}

impl Recorded {
    /// Check the text of a lock file.
    pub(crate) fn parse(text: &str) -> Recorded {
        if text.trim().is_empty() {
            return Recorded::Empty;
        }
        let value: serde_json::Value = match serde_json::from_str(text) {
            Ok(v) => v,
            Err(e) => return Recorded::Invalid { why: format!("not JSON ({e})"), host: None },
        };
        let host = value.get("host").and_then(|h| h.as_str()).filter(|h| valid_host(h)).map(str::to_string);
        let invalid = |why: String| Recorded::Invalid { why, host: host.clone() };
        let h: Holder = match serde_json::from_value(value.clone()) {
            Ok(h) => h,
            Err(e) => return invalid(format!("not a lock record ({e})")),
        };
        if h.pid == 0 {
            return invalid("pid 0".into());
        }
        if !valid_host(&h.host) {
            return invalid("a host name that is empty, too long or not printable".into());
        }
        Recorded::Holder(h)
    }

    /// The holder, if valid.
    fn holder(&self) -> Option<&Holder> {
        match self {
            Recorded::Holder(h) => Some(h),
            _ => None,
        }
    }

    /// How a message names the holder (`None`: not recorded).
    pub(crate) fn shown(&self) -> Option<String> {
        (!matches!(self, Recorded::Empty)).then(|| self.describe())
    }

    /// How a message names the holder: `pid P on host H`, or what the record is.
    pub(crate) fn describe(&self) -> String {
        match self {
            Recorded::Empty => "holder not recorded".into(),
            Recorded::Holder(h) => format!("pid {} on host {}", h.pid, h.host),
            Recorded::Invalid { why, host: Some(host) } => {
                format!("a record naming host {host} that is invalid: {why}")
            }
            Recorded::Invalid { why, host: None } => format!("a record that is invalid: {why}"),
        }
    }
}

fn valid_host(h: &str) -> bool {
    !h.is_empty() && h.chars().count() <= MAX_HOST_CHARS && h.chars().all(|c| !c.is_control() && !c.is_whitespace())
}

fn host() -> String {
    gethostname::gethostname().to_string_lossy().into_owned()
}

/// A lock file that this process holds (flock): removed when dropped if it is still the
/// file at its path.
struct LockFile {
    file: File,
    path: PathBuf,
}

impl Drop for LockFile {
    fn drop(&mut self) {
        // Still holding the lock: remove the file if it is still this lock's.
        if same_file(&self.file, &self.path) {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

/// One try at a lock file.
enum Attempt {
    /// Locked; what the file recorded, if it was left by an earlier run.
    Locked(LockFile, Option<Recorded>),
    /// Another process holds it.
    Busy(Recorded),
    /// Lockable, but it records another host, or is invalid so that its host is unknown
    /// (refused by the caller's choice).
    OtherHost(Recorded),
}

/// Try the lock file at `path` once for `study`: create it or open it (never through a
/// link, only a regular file with one name: [`rotorshunt::files::open_lock`]), flock it
/// without waiting, and write this process into it. A lockable file is stale and taken
/// over, except, when `other_host_is_live`, one recording another host or one whose
/// record is invalid (its host cannot be told). A lock held by this very process (two
/// of its lock names leading to one file) is an error, never "another task".
fn try_lock(path: &Path, study: &str, other_host_is_live: bool) -> Result<Attempt, Error> {
    let me = host();
    for _ in 0..LOCK_ATTEMPTS {
        let (mut file, fresh) = match rotorshunt::files::open_lock(path) {
            Ok(opened) => opened,
            Err(e) if e.kind() == io::ErrorKind::NotFound => continue,
            Err(e) => return Err(Error::io(path, &e)),
        };
        match FileExt::try_lock(&file) {
            Ok(()) => {}
            Err(TryLockError::WouldBlock) => {
                let recorded = read_record(&mut file);
                if let Some(h) = recorded.holder().filter(|h| h.pid == std::process::id() && h.host == me) {
                    return Err(output_error(
                        path,
                        format!("this run itself (pid {}) holds this lock under another name: two of the study's lock files are one file", h.pid),
                    ));
                }
                return Ok(Attempt::Busy(recorded));
            }
            Err(TryLockError::Error(e)) => return Err(output_error(path, format!("cannot lock: {e}"))),
        }
        // Its holder may have removed the file between the open and the lock: this
        // file is then no one's lock, so start again.
        if !same_file(&file, path) {
            continue;
        }
        let previous = if fresh { Recorded::Empty } else { read_record(&mut file) };
        if other_host_is_live {
            let foreign = match &previous {
                Recorded::Holder(h) => h.host != me,
                Recorded::Invalid { host, .. } => host.as_deref() != Some(me.as_str()),
                Recorded::Empty => false,
            };
            if foreign {
                return Ok(Attempt::OtherHost(previous));
            }
        }
        let holder = Holder {
            pid: std::process::id(),
            host: me.clone(),
            study: study.to_string(),
            started_unix_s: std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(0, |d| d.as_secs()),
        };
        let text = json_compact(&holder, "the JSON output")? + "\n";
        (|| {
            file.set_len(0)?;
            file.rewind()?;
            file.write_all(text.as_bytes())?;
            file.sync_all()
        })()
        .map_err(|e| output_error(path, e))?;
        let taken_over = (!fresh).then_some(previous);
        return Ok(Attempt::Locked(LockFile { file, path: path.to_path_buf() }, taken_over));
    }
    Err(output_error(path, format!("the lock file kept disappearing ({LOCK_ATTEMPTS} attempts)")))
}

/// The lock of a study's `--out` folder: the file [`LOCK`], locked exclusively with the
/// operating system's advisory lock (flock) and holding the holder's pid, host, study
/// and start time. The kernel releases the lock when its holder dies, even by SIGKILL:
/// a lock file that can be locked is stale and is taken over. An unsharded run holds it
/// for its whole length and refuses a lock that records another host, whose runs this
/// host's kernel may not see (network filesystems). A sharded run, `study slurm` and
/// `merge` hold it only while they set up or write the folder's own files, wait for it
/// ([`StudyLock::wait`]), and take over a lockable file whatever host it names: those
/// holders are brief, and a lock left by a task on a lost node must not stop the rest of
/// the array. The file is removed when the lock is dropped, on every return path.
pub(crate) struct StudyLock {
    _file: LockFile,
    /// The note on a stale lock taken over.
    pub(crate) taken_over: Option<String>,
}

fn taken_over_note(previous: Option<Recorded>) -> Option<String> {
    previous.map(|p| match p {
        Recorded::Holder(h) => format!(
            "note: took over the lock of an earlier run (pid {} on host {}) that is no longer running",
            h.pid, h.host
        ),
        Recorded::Empty => "note: took over a lock left by an earlier run that is no longer running".to_string(),
        invalid => format!(
            "warning: took over a lock that no process holds, whose record was not the tool's ({})",
            invalid.describe()
        ),
    })
}

impl StudyLock {
    fn locked(out: &Path, r: Recorded) -> Error {
        let (pid, host) = match r {
            Recorded::Holder(h) => (Some(h.pid), Some(h.host)),
            Recorded::Invalid { host, .. } => (None, host),
            Recorded::Empty => (None, None),
        };
        Error::StudyLocked { dir: out.display().to_string(), lock: out.join(LOCK).display().to_string(), pid, host }
    }

    /// Take the lock of `out` for `study`, or refuse with [`Error::StudyLocked`].
    pub(crate) fn acquire(out: &Path, study: &str) -> Result<StudyLock, Error> {
        match try_lock(&out.join(LOCK), study, true)? {
            Attempt::Locked(file, previous) => Ok(StudyLock { _file: file, taken_over: taken_over_note(previous) }),
            Attempt::Busy(h) => Err(StudyLock::locked(out, h)),
            Attempt::OtherHost(h) => Err(StudyLock::locked(out, h)),
        }
    }

    /// Take the lock of `out` for `study`, waiting up to [`SETUP_LOCK_WAIT`] for another
    /// holder ([`Error::StudyLocked`] after that).
    pub(crate) fn wait(out: &Path, study: &str) -> Result<StudyLock, Error> {
        let deadline = std::time::Instant::now() + SETUP_LOCK_WAIT;
        loop {
            match try_lock(&out.join(LOCK), study, false)? {
                Attempt::Locked(file, previous) => {
                    return Ok(StudyLock { _file: file, taken_over: taken_over_note(previous) })
                }
                Attempt::Busy(h) if std::time::Instant::now() >= deadline => return Err(StudyLock::locked(out, h)),
                Attempt::OtherHost(h) if std::time::Instant::now() >= deadline => {
                    return Err(StudyLock::locked(out, h))
                }
                Attempt::Busy(_) | Attempt::OtherHost(_) => std::thread::sleep(SETUP_LOCK_POLL),
            }
        }
    }
}

/// The lock of one case folder, [`CASE_LOCK`]: held while a run opens, runs and commits
/// the case. A lockable file is taken over whatever host it names.
pub(crate) struct CaseLock {
    _file: LockFile,
}

impl CaseLock {
    /// Take the lock of case folder `dir`: `Err(what the lock records)` if another run
    /// holds it after [`CASE_LOCK_TRIES`] tries.
    pub(crate) fn acquire(dir: &Path, study: &str) -> Result<Result<CaseLock, Recorded>, Error> {
        let mut last = Recorded::Empty;
        for attempt in 0..CASE_LOCK_TRIES {
            if attempt > 0 {
                std::thread::sleep(CASE_LOCK_PAUSE);
            }
            match try_lock(&dir.join(CASE_LOCK), study, false)? {
                Attempt::Locked(file, _) => return Ok(Ok(CaseLock { _file: file })),
                Attempt::Busy(h) | Attempt::OtherHost(h) => last = h,
            }
        }
        Ok(Err(last))
    }
}

/// Whether another process holds the case lock of `dir` now (`study status`): how the
/// lock names its holder (`Some(None)`: not recorded), or `None` when no one holds it. Never writes: a missing lock
/// file is not created, and a stale one is left as it is; a link or a file with other
/// names there is no lock of the study's (`None`).
pub(crate) fn case_running(dir: &Path) -> Option<Option<String>> {
    let mut file = rotorshunt::files::open_existing(&dir.join(CASE_LOCK)).ok()?;
    match FileExt::try_lock_shared(&file) {
        Ok(()) => {
            let _ = FileExt::unlock(&file);
            None
        }
        Err(TryLockError::WouldBlock) => Some(read_record(&mut file).shown()),
        Err(TryLockError::Error(_)) => None,
    }
}

/// What the open lock file records (read from its start).
fn read_record(file: &mut File) -> Recorded {
    let mut text = String::new();
    if file.rewind().is_err() || file.read_to_string(&mut text).is_err() {
        return Recorded::Invalid { why: "cannot be read as text".into(), host: None };
    }
    Recorded::parse(&text)
}

/// Whether the open `file` is the file at `path` now.
#[cfg(unix)]
fn same_file(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), std::fs::symlink_metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

/// Whether the open `file` is the file at `path` now (without inode numbers: whether a
/// file is there).
#[cfg(not(unix))]
fn same_file(_: &File, path: &Path) -> bool {
    std::fs::symlink_metadata(path).is_ok_and(|m| m.is_file())
}
