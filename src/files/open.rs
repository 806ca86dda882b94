//! Opening without following links, and what stands at a path.

use super::fault;
use std::fs::{File, Metadata, OpenOptions};
use std::io::{self, Read};
use std::path::Path;

/// Why the tool refuses a path: what stands there instead of a regular file or a
/// folder of its own. Carried inside an `io::Error` (kind `InvalidInput`).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{what} stands there, and the tool neither follows nor replaces it")]
pub struct Refused {
    /// What stands there: "a symbolic link", "a FIFO", "a device", …
    pub what: String,
}

fn refused(what: &str) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, Refused { what: what.to_string() })
}

/// What stands at a path, the final component not followed.
#[derive(Debug)]
pub enum Standing {
    /// Nothing.
    Missing,
    /// A regular file.
    File(Metadata),
    /// A folder (a real one, not a link to one).
    Dir,
    /// A symbolic link (to anything, or broken).
    Link,
    /// A FIFO, a device, a socket: what the text names.
    Special(&'static str),
}

/// What stands at `path` (`symlink_metadata`: a link is reported, not followed).
pub fn standing(path: &Path) -> io::Result<Standing> {
    let m = match std::fs::symlink_metadata(path) {
        Ok(m) => m,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(Standing::Missing),
        Err(e) => return Err(e),
    };
    let t = m.file_type();
    Ok(if t.is_symlink() {
        Standing::Link
    } else if t.is_dir() {
        Standing::Dir
    } else if t.is_file() {
        Standing::File(m)
    } else {
        Standing::Special(special_kind(&m))
    })
}

#[cfg(unix)]
fn special_kind(m: &Metadata) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    let t = m.file_type();
    if t.is_fifo() {
        "a FIFO"
    } else if t.is_char_device() || t.is_block_device() {
        "a device"
    } else if t.is_socket() {
        "a socket"
    } else {
        "a special file"
    }
}

#[cfg(not(unix))]
fn special_kind(_: &Metadata) -> &'static str {
    "a special file"
}

fn refuse_standing(s: &Standing) -> Option<io::Error> {
    match s {
        Standing::Link => Some(refused("a symbolic link")),
        Standing::Special(what) => Some(refused(what)),
        _ => None,
    }
}

/// Options that never follow a final symbolic link and never block on a FIFO.
fn no_follow(o: &mut OpenOptions) -> &mut OpenOptions {
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        o.custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK | libc::O_CLOEXEC);
    }
    o
}

/// The open file, refused unless it is a regular file (checked on the handle, so what
/// was opened is what was checked).
fn regular(file: File) -> io::Result<File> {
    let m = file.metadata()?;
    if m.is_file() {
        Ok(file)
    } else if m.is_dir() {
        Err(refused("a folder"))
    } else {
        Err(refused(special_kind(&m)))
    }
}

/// `O_NOFOLLOW` turns a link into `ELOOP`: say what it is.
fn link_as_refusal(e: io::Error) -> io::Error {
    #[cfg(unix)]
    if e.raw_os_error() == Some(libc::ELOOP) {
        return refused("a symbolic link");
    }
    e
}

/// Open a regular file for reading, never through a link.
fn open_read(path: &Path) -> io::Result<File> {
    no_follow(OpenOptions::new().read(true)).open(path).map_err(link_as_refusal).and_then(regular)
}

/// The bytes of the regular file at `path` (a link or special file is refused).
pub fn read(path: &Path) -> io::Result<Vec<u8>> {
    let mut bytes = Vec::new();
    open_read(path)?.read_to_end(&mut bytes)?;
    Ok(bytes)
}

/// The text of the regular file at `path` (a link or special file is refused).
pub fn read_to_string(path: &Path) -> io::Result<String> {
    String::from_utf8(read(path)?).map_err(|e| io::Error::new(io::ErrorKind::InvalidData, e))
}

/// Create a new file for writing: exclusively, never through a link (an existing name,
/// whatever stands there, is `AlreadyExists`).
pub fn create_new(path: &Path) -> io::Result<File> {
    fault::point();
    no_follow(OpenOptions::new().write(true).create_new(true)).open(path)
}

/// Open or create a lock file for reading and writing: never through a link, and only
/// a regular file with one name (a hard link would make two locks one). Whether it was
/// created is returned with it.
pub fn open_lock(path: &Path) -> io::Result<(File, bool)> {
    fault::point();
    match no_follow(OpenOptions::new().read(true).write(true).create_new(true)).open(path) {
        Ok(f) => Ok((f, true)),
        Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {
            let f = no_follow(OpenOptions::new().read(true).write(true)).open(path).map_err(link_as_refusal)?;
            Ok((single_name(regular(f)?)?, false))
        }
        Err(e) => Err(e),
    }
}

/// Open an existing lock file for reading only (never created, never through a link):
/// a regular file with one name.
pub fn open_existing(path: &Path) -> io::Result<File> {
    single_name(open_read(path)?)
}

/// The open file, refused when it has more than one name (hard links).
fn single_name(file: File) -> io::Result<File> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if file.metadata()?.nlink() > 1 {
            return Err(refused("a file with more than one name (a hard link)"));
        }
    }
    Ok(file)
}

/// The regular file at `path` that an output would replace, if any. Refused: a link or
/// special file there (never replaced), and a read-only file (a rename would replace it
/// whatever its mode).
pub fn replaceable(path: &Path) -> io::Result<Option<Metadata>> {
    let s = standing(path)?;
    if let Some(e) = refuse_standing(&s) {
        return Err(e);
    }
    match s {
        Standing::File(m) if m.permissions().readonly() => Err(io::Error::new(
            io::ErrorKind::PermissionDenied,
            format!(
                "the file is read-only{}, so it is not replaced: make it writable or choose another output folder",
                mode_text(&m)
            ),
        )),
        Standing::File(m) => Ok(Some(m)),
        Standing::Dir => Err(refused("a folder")),
        _ => Ok(None),
    }
}

#[cfg(unix)]
fn mode_text(m: &Metadata) -> String {
    use std::os::unix::fs::PermissionsExt;
    format!(" (mode {:o})", m.permissions().mode() & 0o7777)
}

#[cfg(not(unix))]
fn mode_text(_: &Metadata) -> String {
    String::new()
}

/// Whether a real folder stands at `path` (`false`: nothing). Refused: a link, a
/// special file or a regular file there.
pub fn real_dir(path: &Path) -> io::Result<bool> {
    match standing(path)? {
        Standing::Dir => Ok(true),
        Standing::Missing => Ok(false),
        Standing::File(_) => Err(refused("a file")),
        s => Err(refuse_standing(&s).unwrap_or_else(|| refused("something else"))),
    }
}

/// Create the folder `path` (its parent must exist); an existing name is `AlreadyExists`.
pub fn create_dir(path: &Path) -> io::Result<()> {
    fault::point();
    std::fs::create_dir(path)
}

/// The folder `path` of the tool's own, created if missing (its parent must exist):
/// whether it was created. Refused: a link, a file or a special file at `path`.
pub fn ensure_dir(path: &Path) -> io::Result<bool> {
    match create_dir(path) {
        Ok(()) => Ok(true),
        Err(e) if e.kind() == io::ErrorKind::AlreadyExists => real_dir(path).map(|_| false),
        Err(e) => Err(e),
    }
}

/// Remove the regular file at `path` when `ours` accepts its content (read without
/// following a link); whether it was removed. Nothing there is not an error; a link or
/// special file there is left alone (`false`).
pub fn remove_file_if(path: &Path, ours: impl FnOnce(&[u8]) -> bool) -> io::Result<bool> {
    let bytes = match read(path) {
        Ok(b) => b,
        Err(e) if e.kind() == io::ErrorKind::NotFound || e.kind() == io::ErrorKind::InvalidInput => return Ok(false),
        Err(e) => return Err(e),
    };
    if !ours(&bytes) {
        return Ok(false);
    }
    fault::point();
    std::fs::remove_file(path)?;
    Ok(true)
}

#[cfg(test)]
#[cfg(unix)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("rotorshunt-files-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn what(e: &io::Error) -> String {
        e.get_ref().and_then(|r| r.downcast_ref::<Refused>()).map(|r| r.what.clone()).unwrap_or_default()
    }

    #[test]
    fn links_and_fifos_are_refused_and_left_alone() {
        let dir = scratch("links");
        let victim = dir.join("victim.txt");
        std::fs::write(&victim, "keep").unwrap();
        std::os::unix::fs::symlink(&victim, dir.join("link")).unwrap();
        let fifo = dir.join("fifo");
        let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
        // SAFETY: mkfifo with a valid NUL-terminated path.
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0);
        assert_eq!(what(&read(&dir.join("link")).unwrap_err()), "a symbolic link");
        assert_eq!(what(&read(&fifo).unwrap_err()), "a FIFO");
        assert_eq!(what(&open_lock(&dir.join("link")).unwrap_err()), "a symbolic link");
        assert_eq!(what(&open_lock(&fifo).unwrap_err()), "a FIFO");
        assert_eq!(what(&replaceable(&dir.join("link")).unwrap_err()), "a symbolic link");
        assert_eq!(what(&replaceable(&fifo).unwrap_err()), "a FIFO");
        assert_eq!(create_new(&dir.join("link")).unwrap_err().kind(), io::ErrorKind::AlreadyExists);
        assert!(!remove_file_if(&dir.join("link"), |_| true).unwrap());
        assert_eq!(what(&real_dir(&dir.join("link")).unwrap_err()), "a symbolic link");
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "keep");
        assert!(std::fs::symlink_metadata(dir.join("link")).unwrap().file_type().is_symlink());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn files_are_removed_only_when_their_content_is_ours() {
        let dir = scratch("remove");
        let f = dir.join("a.txt");
        std::fs::write(&f, "mine").unwrap();
        assert!(!remove_file_if(&f, |b| b == b"ours").unwrap());
        assert!(f.exists());
        assert!(remove_file_if(&f, |b| b == b"mine").unwrap());
        assert!(!f.exists());
        assert!(!remove_file_if(&f, |_| true).unwrap(), "nothing there");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
