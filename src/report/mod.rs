//! Rendering only: tables, Markdown, CSV, SVG/PNG plots. Functions return values; files
//! are written by [`crate::files`] (re-exported here for the writers that use it).

pub mod campbell;
pub mod chart;
pub mod clip;
pub mod design;
pub mod glossary;
pub mod html;
pub mod plot;
pub mod study;
pub mod style;
pub mod summary;
pub mod unbalance;

pub use crate::files::{remove_temporaries, replaceable, temporary_target, write_atomic, TEMPORARY_PREFIX};

#[cfg(test)]
mod tests {
    use super::*;
    use std::io;

    fn scratch(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("rotorshunt-report-{name}-{}", std::process::id()));
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
