//! Where things are in a problem file: key paths to lines, and `--set` overrides.

use toml::de::{DeTable, DeValue};
use toml::Spanned;

/// Where key paths are in a problem file, e.g. `disks[0].mass` → line 14, and which key
/// paths were set by `--set`.
///
/// Only errors need a line, so nothing is indexed while loading: [`LineIndex::locate`]
/// parses the text again and follows the one path asked for. Loading stays linear in the
/// file size however many keys the file has, and an error costs one more parse.
#[derive(Debug, Clone)]
pub struct LineIndex<'a> {
    text: &'a str,
    overridden: Vec<String>,
}

/// 1-based line of a byte offset.
pub fn line_of(text: &str, offset: usize) -> usize {
    line_of_bytes(text.as_bytes(), offset)
}

/// Depth of a key path (dotted key or table header) that the TOML parser refuses, with
/// "recursion limit" and no position (toml 1.x: 80 segments).
pub const KEY_DEPTH_LIMIT: usize = 80;

/// 1-based line of the first key path with at least [`KEY_DEPTH_LIMIT`] segments: where a
/// TOML error without a position ("recursion limit") comes from. Dots are counted in the
/// key parts of a line (a table header, or the text before each `=`), not in values.
pub fn deep_key_line(text: &str) -> Option<usize> {
    text.lines()
        .position(|line| {
            let line = line.trim_start();
            let dots = match line.strip_prefix('[') {
                Some(header) => header.split(']').next().unwrap_or(header).matches('.').count(),
                None => {
                    let parts: Vec<&str> = line.split('=').collect();
                    parts[..parts.len() - 1].iter().map(|p| p.matches('.').count()).sum()
                }
            };
            dots + 1 >= KEY_DEPTH_LIMIT
        })
        .map(|i| i + 1)
}

/// 1-based line of a byte offset in raw bytes (which need not be UTF-8).
pub fn line_of_bytes(bytes: &[u8], offset: usize) -> usize {
    bytes[..offset.min(bytes.len())].iter().filter(|&&b| b == b'\n').count() + 1
}

impl<'a> LineIndex<'a> {
    /// The index of a problem text (which must parse as TOML for lines to be found).
    pub fn new(text: &'a str) -> LineIndex<'a> {
        LineIndex { text, overridden: Vec::new() }
    }

    /// Mark a key path as set on the command line.
    pub fn mark_overridden(&mut self, path: &str) {
        self.overridden.push(path.to_string());
    }

    /// True when `path` was set by a `--set` override.
    pub fn is_overridden(&self, path: &str) -> bool {
        self.overridden.iter().any(|o| o == path)
    }

    /// Byte offset in the text of the deepest part of `path` it holds (a key, or an
    /// array element), whatever the overrides; `None` when the text does not parse or
    /// holds not even the path's first key.
    pub fn offset(&self, path: &str) -> Option<usize> {
        let doc = DeTable::parse(self.text).ok()?;
        offset_in_table(doc.get_ref(), path)
    }

    /// Where a key path comes from: `Some(line)` in the file, or `None` when it (or a
    /// parent) was set on the command line or is absent (then the nearest present parent's
    /// line is used if there is one). A path below an override is the override's, by a
    /// key (`design.response` set, `design.response.node` blamed) or by an array index
    /// (`design.speeds` set, `design.speeds[0]` blamed); so is the table above a key set
    /// (`bearings[0]` when `bearings[0].stiffness` is set).
    pub fn locate(&self, path: &str) -> Location {
        let below = |o: &str| path.strip_prefix(o).is_some_and(|rest| rest.starts_with(['.', '[']));
        if self.overridden.iter().any(|o| path == o || below(o) || o.starts_with(&format!("{path}."))) {
            return Location::Override;
        }
        let Ok(doc) = DeTable::parse(self.text) else { return Location::Unknown };
        match offset_in_table(doc.get_ref(), path) {
            Some(offset) => Location::Line(line_of(self.text, offset)),
            None => Location::Unknown,
        }
    }
}

/// Where a key's value came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Location {
    /// A line of the file (1-based).
    Line(usize),
    /// A `--set` override.
    Override,
    /// Not in the file (e.g. a missing top-level key).
    Unknown,
}

/// Byte offset of the deepest part of `path` present below `table`: the key of a table
/// entry, or the start of an array element. `None` when not even the first key is there.
fn offset_in_table(table: &DeTable<'_>, path: &str) -> Option<usize> {
    // The next key runs to the first `.` or `[`; a quoted key may itself hold those
    // characters, so failing the plain split, take the longest key the path starts with.
    let plain = &path[..path.find(['.', '[']).unwrap_or(path.len())];
    let (key, value) = table.get_key_value(plain).or_else(|| {
        table
            .iter()
            .filter(|(k, _)| {
                let k: &str = k.get_ref();
                path.strip_prefix(k).is_some_and(|rest| rest.is_empty() || rest.starts_with(['.', '[']))
            })
            .max_by_key(|(k, _)| k.get_ref().len())
    })?;
    let here = key.span().start;
    Some(offset_in_value(value, &path[key.get_ref().len()..]).unwrap_or(here))
}

/// Byte offset of the deepest part of `rest` (`.key…` or `[i]…`, or empty) below `value`.
fn offset_in_value(value: &Spanned<DeValue<'_>>, rest: &str) -> Option<usize> {
    if let Some(path) = rest.strip_prefix('.') {
        return match value.get_ref() {
            DeValue::Table(t) => offset_in_table(t, path),
            _ => None,
        };
    }
    let inner = rest.strip_prefix('[')?;
    let close = inner.find(']')?;
    let i: usize = inner[..close].parse().ok()?;
    let DeValue::Array(a) = value.get_ref() else { return None };
    let element = a.get(i)?;
    Some(offset_in_value(element, &inner[close + 1..]).unwrap_or(element.span().start))
}

/// One segment of a key path: a table key or an array index.
enum Segment<'a> {
    Key(&'a str),
    Index(usize),
}

fn segments(path: &str) -> Option<Vec<Segment<'_>>> {
    let mut out = Vec::new();
    for part in path.split('.') {
        let (name, mut rest) = match part.find('[') {
            Some(i) => (&part[..i], &part[i..]),
            None => (part, ""),
        };
        if name.is_empty() {
            return None;
        }
        out.push(Segment::Key(name));
        while let Some(stripped) = rest.strip_prefix('[') {
            let end = stripped.find(']')?;
            out.push(Segment::Index(stripped[..end].parse().ok()?));
            rest = &stripped[end + 1..];
        }
        if !rest.is_empty() {
            return None;
        }
    }
    Some(out)
}

/// Parse the value of a `--set` override: exactly one TOML value (`2000`, `5e-6`, `true`,
/// `"x"`, `[1, 2]`, a trailing `# comment` allowed), or else the bare text as a string
/// (`open`). Anything after the value is refused with the reason: another key or table
/// (`1000\nspeed=5`, which TOML reads as a second key), or a line break in a bare text.
pub fn parse_override_value(text: &str) -> Result<toml::Value, String> {
    match toml::from_str::<toml::Table>(&format!("v = {text}")) {
        Ok(mut t) => {
            let value = t.remove("v");
            match value {
                Some(v) if t.is_empty() => Ok(v),
                _ => {
                    let keys: Vec<String> = t.keys().map(|k| format!("`{k}`")).collect();
                    Err(format!(
                        "a --set value is one TOML value, and more follows it: {} {}",
                        if keys.len() == 1 { "the key" } else { "the keys" },
                        keys.join(", ")
                    ))
                }
            }
        }
        Err(_) if text.contains(['\n', '\r']) => {
            Err("a --set value is one TOML value on one line, and this one has a line break".into())
        }
        Err(_) => Ok(toml::Value::String(text.to_string())),
    }
}

/// `text` on one line, for a message: line breaks, tabs and other control characters as
/// escapes (`\n`, `\u{1b}`).
pub fn one_line(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if c.is_control() => out.push_str(&c.escape_unicode().to_string()),
            c => out.push(c),
        }
    }
    out
}

/// Set `path` (e.g. `circuit.branches[1].resistance`) to `value` in `table`, creating
/// missing tables on the way. Fails with a reason when the path does not fit the document.
pub fn set_path(table: &mut toml::Table, path: &str, value: toml::Value) -> Result<(), String> {
    let segs = segments(path).ok_or_else(|| format!("`{path}` is not a key path like `a.b` or `a.b[0].c`"))?;
    // The file may not nest deeper either; and each level below costs stack.
    if segs.len() >= KEY_DEPTH_LIMIT {
        return Err(format!(
            "the key path has {} levels, more than the {} a problem file may have",
            segs.len(),
            KEY_DEPTH_LIMIT - 1
        ));
    }
    match segs.split_first() {
        Some((Segment::Key(k), rest)) => {
            if rest.is_empty() {
                table.insert((*k).to_string(), value);
                return Ok(());
            }
            let next = table.entry((*k).to_string()).or_insert_with(|| toml::Value::Table(toml::Table::new()));
            set_in_value(next, rest, value)
        }
        _ => Err(format!("`{path}` must start with a key")),
    }
}

fn set_in_value(cur: &mut toml::Value, segs: &[Segment<'_>], value: toml::Value) -> Result<(), String> {
    let Some((first, rest)) = segs.split_first() else {
        *cur = value;
        return Ok(());
    };
    let next = match first {
        Segment::Key(k) => {
            let t = cur.as_table_mut().ok_or_else(|| format!("`{k}` is inside a value that is not a table"))?;
            if rest.is_empty() {
                t.insert((*k).to_string(), value);
                return Ok(());
            }
            t.entry((*k).to_string()).or_insert_with(|| toml::Value::Table(toml::Table::new()))
        }
        Segment::Index(n) => {
            let a =
                cur.as_array_mut().ok_or_else(|| format!("index [{n}] is applied to a value that is not an array"))?;
            let len = a.len();
            a.get_mut(*n).ok_or_else(|| format!("index [{n}] is out of range: the array has {len} entries"))?
        }
    };
    set_in_value(next, rest, value)
}
