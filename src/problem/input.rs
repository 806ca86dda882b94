//! Reading input files within bounds: only regular files, at most [`MAX_FILE_BYTES`], and
//! TOML text whose parse fits in [`MAX_PARSE_BYTES`]. Every file the command line reads
//! (problem files, `--compare` files, study files and their base) comes through here.

use super::source::{line_of_bytes, Location};
use super::{ProblemError, ProblemErrorKind};
use std::io::Read;
use std::path::Path;
use toml_parser::lexer::TokenKind;

/// Largest input file read (bytes, 16 MiB). The catalogue's files are a few KB and a file
/// of 10⁵ `[[disks]]` is 5.4 MB, so no real input comes near it; the cap keeps a device,
/// a growing file or a huge file from being read into memory.
pub const MAX_FILE_BYTES: u64 = 16 * 1024 * 1024;

/// Largest estimated memory of parsing a TOML text (bytes, 448 MiB; see [`TomlCost`]).
/// The TOML parser needs 40 to 550 times the text's size depending on its structure, so
/// [`MAX_FILE_BYTES`] alone does not bound it (a 1 MiB file of dotted keys takes 577 MB).
/// The estimate is at least 9 % above what parsing allocates for every structure tried
/// (`tests/parse_memory.rs`), so a load stays under about 470 MB, and a file of
/// 10⁵ `[[disks]]` (estimated at 422 MiB, allocating about 255 MB) still loads.
pub const MAX_PARSE_BYTES: u64 = 448 * 1024 * 1024;

/// Parser memory per TOML token (bytes). toml 1.2 keeps every token and an event per
/// token (24 bytes each; the token vector may grow to twice its length) and each value in
/// its table or array: an array of small integers, the densest in values, allocates 94
/// bytes per token.
const BYTES_PER_TOKEN: u64 = 110;

/// Parser memory per table (bytes), beyond its tokens: a non-empty table is a B-tree node
/// of 11 key/value slots, about 1.1 KB. A level of a dotted key allocates 1 180 bytes with
/// its two tokens.
const BYTES_PER_TABLE: u64 = 1100;

/// Parser memory per key/value pair (bytes), beyond its tokens and table: its slot in a
/// B-tree node that may be half full, and its key's own copy when escaped. Inline tables
/// of 12 escaped keys (whose nodes split) allocate 560 bytes per key with its 4 tokens.
const BYTES_PER_KEY: u64 = 100;

/// Parser memory per array (bytes), beyond its tokens: a non-empty array's first
/// allocation holds 4 values. A one-element array `[1]` allocates 485 bytes with its 4
/// tokens.
const BYTES_PER_ARRAY: u64 = 300;

/// An upper estimate of what parsing a TOML text costs, from one pass of the TOML lexer
/// (linear time; memory one byte per nesting level).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TomlCost {
    /// Tokens of the text (keys, values, punctuation, blanks, comments).
    pub tokens: u64,
    /// Tables the text may create, at most: inline tables, `[header]`s and `[[header]]`s,
    /// and each `.` of a key (a dotted key or header creates a table per level). A `.`
    /// inside a value counts too unless it is the point of a number or time (`0.7`).
    pub tables: u64,
    /// Arrays of the text (`[` in a value).
    pub arrays: u64,
    /// Key/value pairs (`=`).
    pub keys: u64,
    /// Bytes of the text (strings with escapes are copied).
    pub bytes: u64,
}

/// What is open around the lexer: an array or an inline table.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Open {
    Array,
    Table,
}

/// A token as the table count needs it.
#[derive(Clone, Copy, Default)]
struct Seen {
    kind: Option<TokenKind>,
    /// An atom that may start a number or a time (a digit, after an optional sign).
    numeric: bool,
    /// An atom that starts with a digit (the fraction of a number or time).
    digit: bool,
    /// A `.` met inside a value, decided two tokens later.
    value_dot: bool,
}

impl TomlCost {
    /// Count the tokens and possible tables of `text`.
    pub fn of(text: &str) -> TomlCost {
        let mut cost = TomlCost { tokens: 0, tables: 0, arrays: 0, keys: 0, bytes: text.len() as u64 };
        // One byte per nesting level.
        let mut open: Vec<Open> = Vec::new();
        // In a key (line start, or after `{` or `,` in an inline table) until `=`.
        let mut in_key = true;
        // On a `[header]` or `[[header]]` line.
        let mut in_header = false;
        let mut last_significant: Option<TokenKind> = None;
        // The four tokens before the current one, oldest first.
        let mut recent = [Seen::default(); 4];
        let source = toml_parser::Source::new(text);
        for token in source.lex() {
            cost.tokens += 1;
            let kind = token.kind();
            let raw = source.get(token.span()).map(|r| r.as_str()).unwrap_or_default();
            let mut seen = Seen {
                kind: Some(kind),
                numeric: kind == TokenKind::Atom
                    && raw.trim_start_matches(['+', '-']).starts_with(|c: char| c.is_ascii_digit()),
                digit: kind == TokenKind::Atom && raw.starts_with(|c: char| c.is_ascii_digit()),
                value_dot: false,
            };
            match kind {
                TokenKind::Newline if open.is_empty() => {
                    in_key = true;
                    in_header = false;
                }
                TokenKind::Equals => {
                    cost.keys += 1;
                    in_key = false;
                }
                TokenKind::LeftSquareBracket => {
                    if in_key && open.is_empty() && !in_header {
                        in_header = true;
                        cost.tables += 1;
                    } else if !(in_header && last_significant == Some(TokenKind::LeftSquareBracket)) {
                        // An array (the second `[` of `[[header]]` is the same table).
                        open.push(Open::Array);
                        cost.arrays += 1;
                        in_key = false;
                    }
                }
                TokenKind::RightSquareBracket if !in_header && open.last() == Some(&Open::Array) => {
                    open.pop();
                }
                TokenKind::LeftCurlyBracket => {
                    cost.tables += 1;
                    open.push(Open::Table);
                    in_key = true;
                }
                TokenKind::RightCurlyBracket => {
                    if open.last() == Some(&Open::Table) {
                        open.pop();
                    }
                    in_key = false;
                }
                TokenKind::Comma if open.last() == Some(&Open::Table) => in_key = true,
                TokenKind::Dot if in_key || in_header => cost.tables += 1,
                TokenKind::Dot => seen.value_dot = true,
                _ => {}
            }
            if recent[2].value_dot && !number_point(&recent, &seen) {
                cost.tables += 1;
            }
            if !matches!(kind, TokenKind::Whitespace | TokenKind::Comment) {
                last_significant = Some(kind);
            }
            recent = [recent[1], recent[2], recent[3], seen];
        }
        // The text's last two tokens have no successor.
        let end = Seen::default();
        if recent[2].value_dot && !number_point(&recent, &end) {
            cost.tables += 1;
        }
        if recent[3].value_dot {
            cost.tables += 1;
        }
        cost
    }

    /// The estimated parse memory (bytes).
    pub fn estimate(&self) -> u64 {
        self.bytes
            .saturating_add(self.tokens.saturating_mul(BYTES_PER_TOKEN))
            .saturating_add(self.tables.saturating_mul(BYTES_PER_TABLE))
            .saturating_add(self.arrays.saturating_mul(BYTES_PER_ARRAY))
            .saturating_add(self.keys.saturating_mul(BYTES_PER_KEY))
    }
}

/// Whether the `.` at `recent[2]` is the point of a number or time (`0.7`, `1.5e3`,
/// `00:32:00.999`): a sign- or digit-led atom before it, a digit-led atom after it, and no
/// `.` next to those (`1.2.3` is a dotted key, whose levels are tables).
fn number_point(recent: &[Seen; 4], current: &Seen) -> bool {
    recent[1].numeric
        && recent[0].kind != Some(TokenKind::Dot)
        && recent[3].digit
        && current.kind != Some(TokenKind::Dot)
}

/// The error of a whole file (no line, no key).
fn file_error(path: &Path, kind: ProblemErrorKind) -> ProblemError {
    ProblemError { file: path.display().to_string(), location: Location::Unknown, key: String::new(), kind }
}

/// What a file that is not a regular file is, in words.
fn describe(file_type: std::fs::FileType) -> String {
    if file_type.is_dir() {
        return "a directory".into();
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if file_type.is_fifo() {
            return "a FIFO (named pipe)".into();
        }
        if file_type.is_char_device() {
            return "a character device".into();
        }
        if file_type.is_block_device() {
            return "a block device".into();
        }
        if file_type.is_socket() {
            return "a socket".into();
        }
    }
    "not a regular file".into()
}

/// Refuse what is not a regular file of at most [`MAX_FILE_BYTES`].
fn check_metadata(path: &Path, metadata: &std::fs::Metadata) -> Result<(), ProblemError> {
    if !metadata.is_file() {
        return Err(file_error(path, ProblemErrorKind::NotARegularFile { kind: describe(metadata.file_type()) }));
    }
    if metadata.len() > MAX_FILE_BYTES {
        return Err(file_error(path, ProblemErrorKind::TooLarge { size: metadata.len(), limit: MAX_FILE_BYTES }));
    }
    Ok(())
}

/// Read an input file's bytes: a regular file (or a link to one) of at most
/// [`MAX_FILE_BYTES`]. The type and size are checked before opening (opening a FIFO would
/// wait for a writer), again on the open file (in case the path changed in between; on
/// Unix it is opened non-blocking, so that even then nothing waits), and the read stops
/// one byte past the limit, so a file that grows or misreports its size cannot fill
/// memory.
pub fn read_input(path: &Path) -> Result<Vec<u8>, ProblemError> {
    let io = |e: std::io::Error| file_error(path, ProblemErrorKind::Read(e.to_string()));
    check_metadata(path, &std::fs::metadata(path).map_err(io)?)?;
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NONBLOCK);
    }
    let file = options.open(path).map_err(io)?;
    let metadata = file.metadata().map_err(io)?;
    check_metadata(path, &metadata)?;
    // The size was checked against the limit, so this allocation is bounded.
    let mut bytes = Vec::with_capacity(metadata.len() as usize + 1);
    file.take(MAX_FILE_BYTES + 1).read_to_end(&mut bytes).map_err(io)?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(file_error(path, ProblemErrorKind::TooLarge { size: bytes.len() as u64, limit: MAX_FILE_BYTES }));
    }
    Ok(bytes)
}

/// The text of raw bytes, or [`ProblemErrorKind::NotUtf8`] with the offset and line of the
/// first invalid byte; `name` is used in messages.
pub fn text_of<'a>(bytes: &'a [u8], name: &str) -> Result<&'a str, ProblemError> {
    std::str::from_utf8(bytes).map_err(|e| ProblemError {
        file: name.to_string(),
        location: Location::Line(line_of_bytes(bytes, e.valid_up_to())),
        key: String::new(),
        kind: ProblemErrorKind::NotUtf8(e.valid_up_to()),
    })
}

/// Refuse a TOML text whose parse would need more than [`MAX_PARSE_BYTES`].
pub fn check_parse_cost(text: &str) -> Result<(), ProblemErrorKind> {
    let cost = TomlCost::of(text);
    if cost.estimate() > MAX_PARSE_BYTES {
        return Err(ProblemErrorKind::TooComplex {
            tokens: cost.tokens,
            tables: cost.tables,
            arrays: cost.arrays,
            keys: cost.keys,
            estimate: cost.estimate(),
            limit: MAX_PARSE_BYTES,
        });
    }
    Ok(())
}

/// Read a TOML file other than a problem file (a study file): [`read_input`], UTF-8 and
/// [`check_parse_cost`], with the same errors as a problem file.
pub fn read_toml(path: &Path) -> Result<String, ProblemError> {
    let bytes = read_input(path)?;
    let text = text_of(&bytes, &path.display().to_string())?;
    check_parse_cost(text).map_err(|kind| file_error(path, kind))?;
    Ok(text.to_string())
}
