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
