//! The locks of a study's folders: [`StudyLock`] keeps a second run out of the `--out`
//! folder while one runs (or, for the shards of one study, while one sets it up);
//! [`CaseLock`] keeps two tasks out of one case folder. Each is an advisory `flock` on a
//! file that records its holder, released by the kernel when the holder dies.

use super::folder::{output_error, CASE_LOCK, LOCK};
use crate::commands::out::json_compact;
use crate::Error;
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
    /// Locked; the holder the file recorded, if it was left by an earlier run (`Some(None)`
    /// when it recorded none).
    Locked(LockFile, Option<Option<Holder>>),
    /// Another process holds it.
    Busy(Option<Holder>),
    /// Lockable, but it records another host (refused by the caller's choice).
    OtherHost(Holder),
}

/// Try the lock file at `path` once for `study`: create it or open it, flock it without
/// waiting, and write this process into it. A lockable file is stale and taken over,
/// except one recording another host when `other_host_is_live`.
fn try_lock(path: &Path, study: &str, other_host_is_live: bool) -> Result<Attempt, Error> {
    let me = host();
    for _ in 0..LOCK_ATTEMPTS {
        let mut options = std::fs::OpenOptions::new();
        options.read(true).write(true);
        let (mut file, fresh) = match options.clone().create_new(true).open(path) {
            Ok(f) => (f, true),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => match options.open(path) {
                Ok(f) => (f, false),
                Err(e) if e.kind() == io::ErrorKind::NotFound => continue,
                Err(e) => return Err(output_error(path, e)),
            },
            Err(e) => return Err(output_error(path, e)),
        };
        match FileExt::try_lock(&file) {
            Ok(()) => {}
            Err(TryLockError::WouldBlock) => return Ok(Attempt::Busy(read_holder(&mut file))),
            Err(TryLockError::Error(e)) => return Err(output_error(path, format!("cannot lock: {e}"))),
        }
        // Its holder may have removed the file between the open and the lock: this
        // file is then no one's lock, so start again.
        if !same_file(&file, path) {
            continue;
        }
        let previous = if fresh { None } else { read_holder(&mut file) };
        if let Some(h) = previous.as_ref().filter(|h| h.host != me && other_host_is_live) {
            return Ok(Attempt::OtherHost(h.clone()));
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

fn taken_over_note(previous: Option<Option<Holder>>) -> Option<String> {
    previous.map(|p| match p {
        Some(h) => format!(
            "note: took over the lock of an earlier run (pid {} on host {}) that is no longer running",
            h.pid, h.host
        ),
        None => "note: took over a lock left by an earlier run that is no longer running".to_string(),
    })
}

impl StudyLock {
    fn locked(out: &Path, h: Option<Holder>) -> Error {
        Error::StudyLocked {
            dir: out.display().to_string(),
            lock: out.join(LOCK).display().to_string(),
            pid: h.as_ref().map(|h| h.pid),
            host: h.map(|h| h.host),
        }
    }

    /// Take the lock of `out` for `study`, or refuse with [`Error::StudyLocked`].
    pub(crate) fn acquire(out: &Path, study: &str) -> Result<StudyLock, Error> {
        match try_lock(&out.join(LOCK), study, true)? {
            Attempt::Locked(file, previous) => Ok(StudyLock { _file: file, taken_over: taken_over_note(previous) }),
            Attempt::Busy(h) => Err(StudyLock::locked(out, h)),
            Attempt::OtherHost(h) => Err(StudyLock::locked(out, Some(h))),
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
                    return Err(StudyLock::locked(out, Some(h)))
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
    /// Take the lock of case folder `dir`: `Err(holder)` if another run holds it after
    /// [`CASE_LOCK_TRIES`] tries.
    pub(crate) fn acquire(dir: &Path, study: &str) -> Result<Result<CaseLock, Option<Holder>>, Error> {
        let mut last = None;
        for attempt in 0..CASE_LOCK_TRIES {
            if attempt > 0 {
                std::thread::sleep(CASE_LOCK_PAUSE);
            }
            match try_lock(&dir.join(CASE_LOCK), study, false)? {
                Attempt::Locked(file, _) => return Ok(Ok(CaseLock { _file: file })),
                Attempt::Busy(h) => last = h,
                Attempt::OtherHost(h) => last = Some(h),
            }
        }
        Ok(Err(last))
    }
}

/// Whether another process holds the case lock of `dir` now (`study status`): the holder
/// (`None` inside when it recorded none), or `None` when no one does. Never writes: a
/// missing lock file is not created, and a stale one is left as it is.
pub(crate) fn case_running(dir: &Path) -> Option<Option<String>> {
    let mut file = std::fs::OpenOptions::new().read(true).open(dir.join(CASE_LOCK)).ok()?;
    match FileExt::try_lock_shared(&file) {
        Ok(()) => {
            let _ = FileExt::unlock(&file);
            None
        }
        Err(TryLockError::WouldBlock) => {
            Some(read_holder(&mut file).map(|h| format!("pid {} on host {}", h.pid, h.host)))
        }
        Err(TryLockError::Error(_)) => None,
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
