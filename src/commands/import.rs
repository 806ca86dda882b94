//! `rotorshunt import-ross ROTOR.{toml,json} --out PROBLEM.toml [--speed W] [--force]`.

use super::bounds;
use crate::commands::Error;
use rotorshunt::analysis::limits;
use rotorshunt::files;
use rotorshunt::import::ross::{self, Options};
use std::io::Write;
use std::path::Path;

/// Convert a ROSS `Rotor.save` file into a problem file at `out`. An existing `out` is
/// refused ([`Error::OutputExists`]) unless `force`, and is never the input
/// ([`Error::OutputIsInput`], even with `force`); nothing is written when the import is
/// refused, or when the problem it gives does not load (a [`rotorshunt::problem::ProblemError`]
/// naming `out` "as imported"). `speed` (rad/s) becomes the problem's speed.
pub fn import_ross_cmd(file: &Path, out: &Path, speed: Option<f64>, force: bool) -> Result<String, Error> {
    let speed = speed.map(|w| bounds::flag("--speed", limits::speed(w))).transpose()?;
    // A folder where the one problem file goes is bad input, refused before any work.
    if std::fs::symlink_metadata(out).is_ok_and(|m| m.is_dir()) {
        return Err(folder_given(out));
    }
    if let (Ok(a), Ok(b)) = (std::fs::canonicalize(file), std::fs::canonicalize(out)) {
        if a == b {
            return Err(Error::OutputIsInput { path: out.display().to_string(), input: "the ROSS file".into() });
        }
    }
    let import = ross::import_path(file, Options { speed })?;
    // What is written must load: the general form's own checks (e.g. a rotor on one
    // bearing keeps a rigid-body mode) refuse it before anything is written.
    let name = format!("{} (as imported from {})", out.display(), file.display());
    rotorshunt::problem::Problem::from_text(&import.text, &name, &[])?;
    let output = |e: std::io::Error| Error::io(out, &e);
    // What stands at `out` is looked at, not followed: a link, FIFO or device there is
    // refused with or without --force (a rename would replace the node itself).
    let exists = match files::standing(out).map_err(output)? {
        files::Standing::Missing => false,
        files::Standing::File(_) => true,
        files::Standing::Dir => return Err(folder_given(out)),
        _ => return Err(output(files::replaceable(out).err().unwrap_or_else(|| std::io::Error::other("not a file")))),
    };
    if exists && !force {
        return Err(Error::OutputExists { path: out.display().to_string() });
    }
    if exists {
        files::write_atomic(out, import.text.as_bytes()).map_err(output)?;
    } else {
        write_new(out, import.text.as_bytes()).map_err(|e| match e.kind() {
            std::io::ErrorKind::AlreadyExists => Error::OutputExists { path: out.display().to_string() },
            _ => output(e),
        })?;
    }
    let r = &import.rotor;
    let elements: usize = r.sections.iter().map(|s| s.elements).sum();
    Ok(format!(
        "import-ross: {} shaft elements in {} section(s), {} disk(s), {} bearing(s), {} seal(s); wrote {} (add [[rings]] by editing)\n",
        elements,
        r.sections.len(),
        r.disks.len(),
        r.bearings.iter().filter(|b| b.kind == rotorshunt::model::SupportKind::Bearing).count(),
        r.bearings.iter().filter(|b| b.kind == rotorshunt::model::SupportKind::Seal).count(),
        out.display()
    ))
}

/// `--out` names a folder: `import-ross` writes one problem file (exit 2, bad input).
fn folder_given(out: &Path) -> Error {
    Error::Argument {
        argument: "--out".into(),
        message: format!(
            "{} is a folder, and import-ross writes one problem file: give the path of a file, e.g. {}",
            out.display(),
            out.join("rotor.toml").display()
        ),
    }
}

/// Write a file that must not exist yet: created exclusively (an existing file, or one
/// created in the meantime, is never opened), removed again if writing fails.
fn write_new(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut f = files::create_new(path)?;
    f.write_all(bytes).and_then(|_| f.sync_all()).inspect_err(|_| {
        let _ = std::fs::remove_file(path);
    })
}
