//! Where things are in a problem file: key paths to lines, and `--set` overrides.

use std::collections::BTreeMap;
use toml::de::{DeTable, DeValue};
use toml::Spanned;

/// Key path → 1-based line of its key in the file text, e.g. `disks[0].mass` → 14.
#[derive(Debug, Clone, Default)]
pub struct LineIndex {
    lines: BTreeMap<String, usize>,
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

impl LineIndex {
    /// Index every key of a parsed document.
    pub fn new(text: &str, doc: &Spanned<DeTable<'_>>) -> LineIndex {
        let mut lines = BTreeMap::new();
        walk_table(text, doc.get_ref(), "", &mut lines);
        LineIndex { lines, overridden: Vec::new() }
    }

    /// Mark a key path as set on the command line.
    pub fn mark_overridden(&mut self, path: &str) {
        self.overridden.push(path.to_string());
    }

    /// True when `path` was set by a `--set` override.
    pub fn is_overridden(&self, path: &str) -> bool {
        self.overridden.iter().any(|o| o == path)
    }

    /// Where a key path comes from: `Some(line)` in the file, or `None` when it (or a
    /// parent) was set on the command line or is absent (then the nearest present parent's
    /// line is used if there is one).
    pub fn locate(&self, path: &str) -> Location {
        if self
            .overridden
            .iter()
            .any(|o| path == o || path.starts_with(&format!("{o}.")) || o.starts_with(&format!("{path}.")))
        {
            return Location::Override;
        }
        let mut p = path.to_string();
        loop {
            if let Some(&l) = self.lines.get(&p) {
                return Location::Line(l);
            }
            match p.rfind(['.', '[']) {
                Some(i) => p.truncate(i),
                None => return Location::Unknown,
            }
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

fn join(prefix: &str, key: &str) -> String {
    if prefix.is_empty() {
        key.to_string()
    } else {
        format!("{prefix}.{key}")
    }
}

fn walk_table(text: &str, table: &DeTable<'_>, prefix: &str, out: &mut BTreeMap<String, usize>) {
    for (k, v) in table.iter() {
        let path = join(prefix, k.get_ref());
        out.insert(path.clone(), line_of(text, k.span().start));
        walk_value(text, v, &path, out);
    }
}

fn walk_value(text: &str, v: &Spanned<DeValue<'_>>, path: &str, out: &mut BTreeMap<String, usize>) {
    match v.get_ref() {
        DeValue::Table(t) => walk_table(text, t, path, out),
        DeValue::Array(a) => {
            for (i, e) in a.iter().enumerate() {
                let p = format!("{path}[{i}]");
                out.insert(p.clone(), line_of(text, e.span().start));
                walk_value(text, e, &p, out);
            }
        }
        _ => {}
    }
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

/// Parse the value of a `--set` override: any TOML value (`2000`, `5e-6`, `true`,
/// `"x"`, `[1, 2]`), or else the bare text as a string (`open`).
pub fn parse_override_value(text: &str) -> toml::Value {
    toml::from_str::<toml::Table>(&format!("v = {text}"))
        .ok()
        .and_then(|mut t| t.remove("v"))
        .unwrap_or_else(|| toml::Value::String(text.to_string()))
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
