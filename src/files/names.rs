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

/// The one prefix of every hidden name the tool makes beside a user's files: the
/// temporaries of atomic writes, `.rotorshunt-tmp.NAME.PID.N` ([`super::write_atomic`]),
/// and the staging folders of output folders, `.rotorshunt-tmp.NAME.TOKEN`, where the old
/// folder of a swap waits as `.rotorshunt-tmp.NAME.TOKEN-old` ([`staging_name`]). No user
/// file is named like this; even so, nothing so named is removed on its name alone: a
/// temporary must be a plain file of a recorded entry, a staging folder must carry its
/// token in its own record.
pub const HIDDEN_PREFIX: &str = ".rotorshunt-tmp.";

/// Suffix of the name under which the old folder of a swap waits.
const OLD_SUFFIX: &str = "-old";

/// Hex digits of a [`token`].
const TOKEN_DIGITS: usize = 24;

/// The staging folder of the folder `name` for the run of `token` (the folder it replaces
/// waits under [`old_staging`] where folders cannot be exchanged).
pub fn staging_name(name: &str, token: &str) -> String {
    format!("{HIDDEN_PREFIX}{name}.{token}")
}

/// The name the folder a staging folder replaces waits under, where folders cannot be
/// exchanged: the staging folder's own path with the old suffix.
pub fn old_staging(staging: &std::path::Path) -> std::path::PathBuf {
    let mut name = staging.as_os_str().to_owned();
    name.push(OLD_SUFFIX);
    std::path::PathBuf::from(name)
}

/// The parts of a staging folder's name: the folder it stands for, the token and
/// whether it is the old folder of a swap; by name only (whether it is the tool's is
/// proved by its record before anything removes it).
pub fn staging_parts(name: &str) -> Option<(&str, &str, bool)> {
    let (entry, rest) = name.strip_prefix(HIDDEN_PREFIX)?.rsplit_once('.')?;
    let (token, old) = match rest.strip_suffix(OLD_SUFFIX) {
        Some(t) => (t, true),
        None => (rest, false),
    };
    (is_token(token) && !entry.is_empty()).then_some((entry, token, old))
}

/// Whether `s` is a token as [`token`] makes them.
pub fn is_token(s: &str) -> bool {
    s.len() == TOKEN_DIGITS && s.bytes().all(|b| b.is_ascii_hexdigit())
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
    Sha256::digest(seed.as_bytes()).iter().take(TOKEN_DIGITS / 2).map(|b| format!("{b:02x}")).collect()
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

    #[test]
    fn staging_names_are_read_back_and_look_alikes_are_not() {
        let t = token();
        for name in ["out", "run.1", "a b"] {
            let staged = staging_name(name, &t);
            assert!(staged.starts_with(HIDDEN_PREFIX));
            assert_eq!(staging_parts(&staged), Some((name, t.as_str(), false)), "{staged}");
            let old = old_staging(std::path::Path::new(&staged));
            assert_eq!(staging_parts(old.to_str().unwrap()), Some((name, t.as_str(), true)), "{}", old.display());
        }
        // Not the tool's scheme: the old `.NAME.tmp-TOKEN` form, short or non-hex tokens,
        // no folder name, an atomic write's temporary (`.PID.N`).
        for other in [
            ".out.tmp-0123456789abcdef01234567".to_string(),
            format!("{HIDDEN_PREFIX}out.0123456789abcdef0123456"),
            format!("{HIDDEN_PREFIX}out.0123456789abcdef0123456g"),
            format!("{HIDDEN_PREFIX}.{t}"),
            format!("{HIDDEN_PREFIX}out.json.1234.5"),
            "out".to_string(),
        ] {
            assert_eq!(staging_parts(&other), None, "{other}");
        }
    }
}
