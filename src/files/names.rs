//! Names the tool records and the tokens that prove what it wrote.

use std::sync::atomic::{AtomicU64, Ordering};

/// `name` when it is a plain name: one path component, not empty, not `.` or `..`, no
/// separator and no NUL, so that joined to a folder it stays inside that folder.
pub fn plain_name(name: &str) -> Option<&str> {
    let plain = !name.is_empty()
        && name != "."
        && name != ".."
        && !name.contains(['/', '\\', '\0'])
        && std::path::Path::new(name).components().count() == 1;
    plain.then_some(name)
}

/// This host's name as it appears in file names (ASCII letters, digits, `.`, `-`; any
/// other character becomes `_`).
pub fn host() -> String {
    gethostname::gethostname()
        .to_string_lossy()
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() || c == '.' || c == '-' { c } else { '_' })
        .collect()
}

/// Tokens made by this process so far (part of each token's seed).
static TOKENS: AtomicU64 = AtomicU64::new(0);

/// A token unique to this run and call: 24 hex digits of SHA-256 over the host, the
/// process id, the time in nanoseconds, a per-process counter and the address of a
/// stack value. It names a staging folder and is recorded inside it, so a later run can
/// prove the folder is the tool's own before removing it (a user's folder that only
/// looks like one has no such record).
pub fn token() -> String {
    use sha2::{Digest, Sha256};
    let n = TOKENS.fetch_add(1, Ordering::Relaxed);
    let nanos = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_nanos());
    let local = 0u8;
    let seed = format!("{}|{}|{nanos}|{n}|{:p}", host(), std::process::id(), &local);
    Sha256::digest(seed.as_bytes()).iter().take(12).map(|b| format!("{b:02x}")).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_single_components_are_plain() {
        for ok in ["result.json", ".rotorshunt-out.json", "a b", "é", "..x", "x.."] {
            assert_eq!(plain_name(ok), Some(ok), "{ok}");
        }
        for bad in ["", ".", "..", "../x", "/etc/passwd", "a/b", "a\\b", "x\0y", "./x"] {
            assert_eq!(plain_name(bad), None, "{bad:?}");
        }
    }

    #[test]
    fn tokens_differ_and_are_hex() {
        let (a, b) = (token(), token());
        assert_ne!(a, b);
        assert_eq!(a.len(), 24);
        assert!(a.bytes().all(|c| c.is_ascii_hexdigit()));
    }
}
