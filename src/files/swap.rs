//! Renames: plain, without replacing, and exchanging two folders in one step.

use super::fault;
use std::io;
use std::path::Path;

/// Rename `from` to `to` (replacing a file at `to`), after a fault point.
pub fn rename(from: &Path, to: &Path) -> io::Result<()> {
    fault::point();
    std::fs::rename(from, to)
}

#[cfg(target_os = "linux")]
fn renameat2(from: &Path, to: &Path, flags: rustix::fs::RenameFlags) -> io::Result<()> {
    rustix::fs::renameat_with(rustix::fs::CWD, from, rustix::fs::CWD, to, flags).map_err(io::Error::from)
}

/// Whether an error says the file system or kernel lacks a `renameat2` flag.
#[cfg(target_os = "linux")]
fn unsupported(e: &io::Error) -> bool {
    use rustix::io::Errno;
    let lacks = [Errno::INVAL, Errno::NOSYS, Errno::NOTSUP];
    e.raw_os_error().is_some_and(|n| lacks.contains(&Errno::from_raw_os_error(n)))
}

/// Rename `from` to `to` only if nothing stands at `to` (`AlreadyExists` otherwise):
/// `RENAME_NOREPLACE` where the kernel and file system have it, else a check just
/// before the rename.
pub fn rename_new(from: &Path, to: &Path) -> io::Result<()> {
    fault::point();
    #[cfg(target_os = "linux")]
    match renameat2(from, to, rustix::fs::RenameFlags::NOREPLACE) {
        Err(e) if unsupported(&e) => {}
        done => return done,
    }
    if std::fs::symlink_metadata(to).is_ok() {
        return Err(io::Error::new(io::ErrorKind::AlreadyExists, "the target exists"));
    }
    std::fs::rename(from, to)
}

/// Exchange the folders `a` and `b` in one step (`RENAME_EXCHANGE`): a reader of either
/// path sees one of the two whole, never neither. `Ok(false)` where the kernel or file
/// system cannot (the caller then renames in two steps).
pub fn exchange(a: &Path, b: &Path) -> io::Result<bool> {
    fault::point();
    #[cfg(target_os = "linux")]
    match renameat2(a, b, rustix::fs::RenameFlags::EXCHANGE) {
        Ok(()) => return Ok(true),
        Err(e) if unsupported(&e) => {}
        Err(e) => return Err(e),
    }
    let _ = (a, b);
    Ok(false)
}

/// Make `to` a new hard link to the regular file `from` (never through a link at `to`:
/// an existing name is `AlreadyExists`).
pub fn hard_link(from: &Path, to: &Path) -> io::Result<()> {
    fault::point();
    std::fs::hard_link(from, to)
}

/// Make `to` a new symbolic link with the same text as the link `from` (neither is
/// followed).
pub fn copy_link(from: &Path, to: &Path) -> io::Result<()> {
    let text = std::fs::read_link(from)?;
    fault::point();
    #[cfg(unix)]
    return std::os::unix::fs::symlink(text, to);
    #[cfg(not(unix))]
    return Err(io::Error::new(io::ErrorKind::Unsupported, format!("cannot copy the link to {}", text.display())));
}

/// Remove the folder `path` and everything in it, links inside removed as links (never
/// followed); refused when a link or anything but a folder stands at `path`.
pub fn remove_dir_all(path: &Path) -> io::Result<()> {
    if !super::real_dir(path)? {
        return Ok(());
    }
    fault::point();
    std::fs::remove_dir_all(path)
}

#[cfg(test)]
#[cfg(target_os = "linux")]
mod tests {
    use super::*;

    #[test]
    fn folders_exchange_whole_and_new_names_never_replace() {
        let dir = std::env::temp_dir().join(format!("rotorshunt-swap-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let (a, b) = (dir.join("a"), dir.join("b"));
        std::fs::create_dir_all(&a).unwrap();
        std::fs::create_dir_all(&b).unwrap();
        std::fs::write(a.join("x"), "from a").unwrap();
        std::fs::write(b.join("x"), "from b").unwrap();
        if exchange(&a, &b).unwrap() {
            assert_eq!(std::fs::read_to_string(a.join("x")).unwrap(), "from b");
            assert_eq!(std::fs::read_to_string(b.join("x")).unwrap(), "from a");
        }
        assert_eq!(rename_new(&a, &b).unwrap_err().kind(), io::ErrorKind::AlreadyExists);
        let c = dir.join("c");
        rename_new(&a, &c).unwrap();
        assert!(c.join("x").exists() && !a.exists());
        std::os::unix::fs::symlink(&c, dir.join("link")).unwrap();
        assert!(remove_dir_all(&dir.join("link")).is_err());
        assert!(c.join("x").exists(), "a link to a folder is not a folder to empty");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
