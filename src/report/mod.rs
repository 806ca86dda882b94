//! Rendering only: tables, Markdown, CSV, SVG/PNG plots. Functions return values; the
//! one I/O helper, [`write_atomic`], is what every command uses to write files.

pub mod campbell;
pub mod chart;
pub mod design;
pub mod plot;
pub mod summary;

use std::path::Path;

/// Write `bytes` to `path` atomically: a temporary file in the same directory, then a
/// rename, so a reader never sees a partial file and an interrupted run leaves the old
/// file (or none), never a truncated one.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write;
    let dir = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let tmp = dir.join(format!(".{name}.tmp{}", std::process::id()));
    let mut f = std::fs::File::create(&tmp)?;
    f.write_all(bytes)?;
    f.sync_all()?;
    drop(f);
    std::fs::rename(&tmp, path).inspect_err(|_| {
        let _ = std::fs::remove_file(&tmp);
    })
}

/// Whether `name` is a temporary file of [`write_atomic`] (`.NAME.tmpPID`).
fn is_temporary(name: &str) -> bool {
    name.starts_with('.')
        && name.rsplit_once(".tmp").is_some_and(|(_, pid)| !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit()))
}

/// Remove the temporaries [`write_atomic`] leaves behind when a run is killed between
/// creating and renaming them, in `dir` and below; the number removed.
pub fn remove_temporaries(dir: &Path) -> std::io::Result<usize> {
    let mut removed = 0;
    let Ok(entries) = std::fs::read_dir(dir) else { return Ok(0) };
    for e in entries {
        let e = e?;
        let path = e.path();
        if e.file_type()?.is_dir() {
            removed += remove_temporaries(&path)?;
        } else if is_temporary(&e.file_name().to_string_lossy()) {
            std::fs::remove_file(&path)?;
            removed += 1;
        }
    }
    Ok(removed)
}

#[cfg(test)]
mod tests {
    #[test]
    fn temporaries_are_recognised_by_name() {
        assert!(super::is_temporary(".result.json.tmp1234"));
        assert!(!super::is_temporary("result.json"));
        assert!(!super::is_temporary(".result.json.tmp"));
        assert!(!super::is_temporary(".config.tmpx"));
    }
}
