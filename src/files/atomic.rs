//! Writing one file so that a reader sees the old content or the new, never a part.

use super::{create_new, fault, replaceable};
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Prefix of [`write_atomic`]'s temporaries, `.rotorshunt-tmp.NAME.PID.N` (NAME the file
/// being written, PID the process, N a per-process counter): the tool's one hidden-name
/// prefix ([`super::names::HIDDEN_PREFIX`]), so the temporaries a killed run leaves can be
/// told from anything else.
pub const TEMPORARY_PREFIX: &str = super::names::HIDDEN_PREFIX;

/// Tries at a fresh temporary name before giving up (a name is only taken when a file
/// of that exact name already exists, which no run of this tool leaves behind).
const TEMPORARY_ATTEMPTS: usize = 64;

/// Counter N of the temporaries' names: unique within the process, across threads.
static TEMPORARIES: AtomicU64 = AtomicU64::new(0);

/// Write `bytes` to `path` atomically: a temporary file in the same directory, then a
/// rename, so a reader never sees a partial file and an interrupted run leaves the old
/// file (or none), never a truncated one. Refused: a link, folder or special file at
/// `path` (never replaced) and a read-only file (left as it is); a writable file that
/// is replaced keeps its permissions.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    let dir = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let existing = replaceable(path)?;
    let (tmp, mut f) = create_temporary(dir, &name)?;
    let written = (|| {
        fault::point();
        fault::full_disk(&name)?;
        f.write_all(bytes)?;
        if let Some(m) = existing.as_ref() {
            f.set_permissions(m.permissions())?;
        }
        f.sync_all()?;
        drop(f);
        // Checked again just before the rename: a link planted meanwhile is refused.
        replaceable(path)?;
        super::rename(&tmp, path)
    })();
    written.inspect_err(|_| {
        let _ = std::fs::remove_file(&tmp);
    })
}

/// A new temporary for `name` in `dir`, created exclusively (an existing file of that
/// name is never opened, let alone truncated).
fn create_temporary(dir: &Path, name: &str) -> io::Result<(PathBuf, std::fs::File)> {
    for _ in 0..TEMPORARY_ATTEMPTS {
        let n = TEMPORARIES.fetch_add(1, Ordering::Relaxed);
        let tmp = dir.join(format!("{TEMPORARY_PREFIX}{name}.{}.{n}", std::process::id()));
        match create_new(&tmp) {
            Ok(f) => return Ok((tmp, f)),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(e),
        }
    }
    Err(io::Error::new(
        io::ErrorKind::AlreadyExists,
        format!("{TEMPORARY_ATTEMPTS} temporary names for {name} are all taken in {}", dir.display()),
    ))
}

/// The file a temporary of [`write_atomic`] stands for: NAME of `.rotorshunt-tmp.NAME.PID.N`;
/// `None` for any other name.
pub fn temporary_target(name: &str) -> Option<&str> {
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    let (rest, n) = name.strip_prefix(TEMPORARY_PREFIX)?.rsplit_once('.')?;
    let (target, pid) = rest.rsplit_once('.')?;
    (digits(n) && digits(pid) && !target.is_empty()).then_some(target)
}

/// Remove the temporaries [`write_atomic`] leaves when a run is killed between creating
/// and renaming them, for the files `owned` accepts, in `dir` itself only: never in a
/// subfolder, never a file of any other name, never a directory or a link. The number
/// removed.
pub fn remove_temporaries(dir: &Path, owned: impl Fn(&str) -> bool) -> io::Result<usize> {
    let mut removed = 0;
    let entries = match std::fs::read_dir(dir) {
        Ok(entries) => entries,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(0),
        Err(e) => return Err(e),
    };
    for e in entries {
        let e = e?;
        let name = e.file_name();
        let Some(name) = name.to_str() else { continue };
        if temporary_target(name).is_some_and(&owned) && e.file_type()?.is_file() {
            fault::point();
            std::fs::remove_file(e.path())?;
            removed += 1;
        }
    }
    Ok(removed)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("rotorshunt-atomic-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn temporaries_are_recognised_by_name() {
        assert_eq!(temporary_target(".rotorshunt-tmp.result.json.1234.0"), Some("result.json"));
        assert_eq!(temporary_target(".rotorshunt-tmp.a.b.c.7.12"), Some("a.b.c"));
        for other in [
            "result.json",
            ".result.json.tmp1234",
            ".notes.tmp2024",
            ".rotorshunt-tmp.result.json.1234",
            ".rotorshunt-tmp.result.json.12x.3",
            ".rotorshunt-tmp..1.2",
            "rotorshunt-tmp.result.json.1.2",
        ] {
            assert_eq!(temporary_target(other), None, "{other}");
        }
    }

    #[test]
    fn cleanup_removes_only_owned_temporaries_in_the_folder_itself() {
        let dir = scratch("cleanup");
        let keep = [".notes.tmp2024", ".rotorshunt-tmp.notes.txt.1.2", "summary.json", ".rotorshunt-tmp.x"];
        for k in keep {
            std::fs::write(dir.join(k), k).unwrap();
        }
        std::fs::create_dir(dir.join("sub")).unwrap();
        std::fs::write(dir.join("sub/.rotorshunt-tmp.summary.json.1.2"), "nested").unwrap();
        std::fs::create_dir(dir.join(".rotorshunt-tmp.summary.json.5.6")).unwrap();
        std::fs::write(dir.join(".rotorshunt-tmp.summary.json.3.4"), "ours").unwrap();
        let removed = remove_temporaries(&dir, |t| t == "summary.json").unwrap();
        assert_eq!(removed, 1);
        assert!(!dir.join(".rotorshunt-tmp.summary.json.3.4").exists());
        for k in keep {
            assert_eq!(std::fs::read_to_string(dir.join(k)).unwrap(), k);
        }
        assert!(dir.join("sub/.rotorshunt-tmp.summary.json.1.2").exists(), "subfolders are not searched");
        assert!(dir.join(".rotorshunt-tmp.summary.json.5.6").is_dir(), "directories are not removed");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn read_only_files_are_refused_and_modes_kept() {
        use std::os::unix::fs::PermissionsExt;
        let dir = scratch("modes");
        let ro = dir.join("ro.txt");
        std::fs::write(&ro, "keep").unwrap();
        std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o444)).unwrap();
        let e = write_atomic(&ro, b"new").unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::PermissionDenied);
        assert!(e.to_string().contains("read-only (mode 444)"), "{e}");
        assert_eq!(std::fs::read_to_string(&ro).unwrap(), "keep");
        assert_eq!(std::fs::metadata(&ro).unwrap().permissions().mode() & 0o777, 0o444);
        let private = dir.join("private.txt");
        std::fs::write(&private, "old").unwrap();
        std::fs::set_permissions(&private, std::fs::Permissions::from_mode(0o600)).unwrap();
        write_atomic(&private, b"new").unwrap();
        assert_eq!(std::fs::read_to_string(&private).unwrap(), "new");
        assert_eq!(std::fs::metadata(&private).unwrap().permissions().mode() & 0o777, 0o600);
        let left: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(left.len(), 2, "no temporary left: {left:?}");
        std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o644)).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
