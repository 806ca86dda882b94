//! Input fuzzing of the problem loader: mutants of the bundled `problems/*.toml` files
//! (keys dropped, duplicated, retyped; NaN, ±inf, 0, negative, 1e308, 1e-308 and other
//! extreme numbers; text truncated at any byte; invalid UTF-8 inserted; deep nesting;
//! `--set` overrides) are fed as bytes to `Problem::from_bytes`, and the valid small ones
//! further to `Rotor::new` and `FloquetSystem::new` (what every analysis command does before
//! it analyses).
//!
//! Asserted for every case: no panic, no stack overflow, each case under `CASE_HANG_TIMEOUT`; each
//! rejection's message names the file, the key path when the error is about a key, and the
//! line whenever the text parses and the key (or its table) is in the file. Cases made by
//! one targeted mutation also check *which* key and line are blamed.
//!
//! The command-line flags and study fields are fuzzed in-process by the binary's own
//! tests (src/commands/flag_fuzz.rs), where the command layer lives.
//!
//! `FUZZ_CASES_DEFAULT` cases by default; `ROTORSHUNT_FUZZ_CASES=200000 cargo test --release
//! --test suite fuzz:: -- --nocapture` for a longer run. Counts and the slowest case are printed.

use proptest::prelude::*;
use proptest::test_runner::{Config, TestCaseError, TestRunner};
use rotorshunt::analysis::floquet::FloquetSystem;
use rotorshunt::analysis::Rotor;
use rotorshunt::problem::{Location, Problem, ProblemError, ProblemErrorKind};
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Cases of the default (CI) run.
const FUZZ_CASES_DEFAULT: u32 = 20_000;

/// Against hangs only, not a timing: no single case may take longer than this (a hang or
/// a runaway computation is orders of magnitude beyond it; cases take milliseconds, and a
/// loaded shared machine must not trip it). Timings belong to the benches.
const CASE_HANG_TIMEOUT: Duration = Duration::from_secs(30);

/// Depths of the nesting attacks: within, at and far beyond the parser's own limit.
const DEPTHS: [usize; 6] = [1, 79, 81, 1000, 10_000, 100_000];

/// Numbers injected into numeric keys.
const NUMBERS: [&str; 24] = [
    "nan",
    "+nan",
    "-nan",
    "inf",
    "+inf",
    "-inf",
    "0",
    "0.0",
    "-0.0",
    "-1",
    "-1e3",
    "1",
    "2",
    "1e9",
    "1e-9",
    "1e308",
    "-1e308",
    "1.7976931348623157e308",
    "1e-308",
    "4.9e-324",
    "9223372036854775807",
    "-9223372036854775808",
    "18446744073709551616",
    "1e400",
];

/// Values of another type than the key's: never valid for a numeric key.
const RETYPES: [&str; 8] = ["\"x\"", "\"1.0\"", "true", "[1, 2]", "[]", "{ a = 1 }", "{}", "1979-05-27T07:32:00Z"];

/// Byte sequences inserted: invalid UTF-8 (lone continuation, truncated sequences,
/// overlong, surrogate, 0xFF), NUL and control characters, and TOML punctuation.
const BYTES: [&[u8]; 14] = [
    &[0xFF],
    &[0x80],
    &[0xC3],
    &[0xE2, 0x82],
    &[0xF0, 0x9F, 0x98],
    &[0xC0, 0xAF],
    &[0xED, 0xA0, 0x80],
    &[0xFE, 0xFE, 0xFF],
    &[0x00],
    &[0x1B, b'['],
    b"\r",
    b"=",
    b"[",
    b"\"",
];

/// One key line of a problem file.
#[derive(Debug, Clone)]
struct KeyLine {
    /// 0-based line index.
    line: usize,
    /// Key path as the loader names it, e.g. `circuit.branches[1].c_f`.
    path: String,
}

/// A bundled problem text and its key lines.
#[derive(Debug, Clone)]
struct Base {
    name: String,
    text: String,
    keys: Vec<KeyLine>,
    /// 64 elements shrunk to 8 (disks moved to node 2): cheap enough to build the rotor.
    small: bool,
}

/// A header's dotted name as the loader's key path: each level that is an array of
/// tables (`counts`: entries so far, by resolved path) names its last entry, so that
/// `[rings.circuit]` under the second `[[rings]]` is `rings[1].circuit`.
fn resolve(name: &str, counts: &BTreeMap<String, usize>) -> String {
    let mut path = String::new();
    for part in name.split('.') {
        path = if path.is_empty() { part.trim().to_string() } else { format!("{path}.{}", part.trim()) };
        if let Some(n) = counts.get(&path) {
            path = format!("{path}[{}]", n - 1);
        }
    }
    path
}

/// Key lines with their paths, tracking `[table]` and `[[array]]` headers (nested arrays
/// of tables such as `[[rings.circuit.branches]]` included).
fn key_lines(text: &str) -> Vec<KeyLine> {
    let mut prefix = String::new();
    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    let mut out = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        if let Some(name) = line.strip_prefix("[[").and_then(|l| l.strip_suffix("]]")) {
            let name = name.trim();
            let (parent, last) = name.rsplit_once('.').map_or(("", name), |(p, l)| (p, l));
            let parent = resolve(parent, &counts);
            let path = if parent.is_empty() { last.trim().to_string() } else { format!("{parent}.{}", last.trim()) };
            let n = counts.entry(path.clone()).or_insert(0);
            prefix = format!("{path}[{n}]");
            *n += 1;
        } else if let Some(name) = line.strip_prefix('[').and_then(|l| l.strip_suffix(']')) {
            prefix = resolve(name.trim(), &counts);
        } else if let Some((key, _)) = line.split_once('=') {
            let key = key.trim();
            let path = if prefix.is_empty() { key.to_string() } else { format!("{prefix}.{key}") };
            out.push(KeyLine { line: i, path });
        }
    }
    out
}

fn bases() -> Vec<Base> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("problems");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("problems/")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 9, "only {} bundled problems", files.len());
    let mut out = Vec::new();
    for f in files {
        let text = std::fs::read_to_string(&f).expect("bundled problem is UTF-8");
        let name = f.file_name().expect("name").to_string_lossy().into_owned();
        assert!(Problem::from_text(&text, &name, &[]).is_ok(), "{name} must load unmutated");
        let elements = Problem::from_text(&text, &name, &[]).map(|p| p.model.shaft.elements()).unwrap_or(usize::MAX);
        // A file of at most 8 elements (an imported ROSS rotor, whose disks and bearings sit
        // at ROSS's nodes) is small already; the general form otherwise: every section down
        // to 2 elements (its supports sit at positions).
        let small_text = if elements <= 8 {
            text.clone()
        } else if text.contains("[[sections]]") {
            text.lines()
                .map(|l| if l.starts_with("elements = ") { "elements = 2".to_string() } else { l.to_string() })
                .collect::<Vec<_>>()
                .join("\n")
                .replace("node = 16 ", "node = 2 ")
        } else {
            // The disk's node and a design response's at it (node 16 of 64 is L/4, node 2 of 8).
            text.replacen("elements = 64 ", "elements = 8 ", 1).replace("node = 16 ", "node = 2 ")
        };
        assert!(elements <= 8 || small_text != text, "{name}: cannot shrink");
        let small = Problem::from_text(&small_text, &name, &[]).expect("shrunk problem loads");
        assert!(small.model.shaft.elements() <= 8);
        out.push(Base { keys: key_lines(&small_text), name: format!("small-{name}"), text: small_text, small: true });
        out.push(Base { keys: key_lines(&text), name, text, small: false });
    }
    out
}

/// How deeply nested content is written.
#[derive(Debug, Clone, Copy)]
enum Nest {
    /// `deep = [[[…]]]`.
    Arrays,
    /// `deep = [[[…` never closed.
    OpenArrays,
    /// `deep = { a = { a = … 1 } }`.
    InlineTables,
    /// `a.a.a.…a = 1`.
    DottedKey,
    /// `[a.a.…a]`.
    Header,
    /// `--set a.a.…a=1`.
    OverridePath,
    /// `--set speed=[[[…]]]`.
    OverrideValue,
}

#[derive(Debug, Clone)]
enum Mutation {
    /// Remove the key line (index modulo the key count).
    DropKey(usize),
    /// Remove any line.
    DropLine(usize),
    /// Repeat the key line right after itself.
    DuplicateKey(usize),
    /// Replace the value by one of another type (`RETYPES`).
    Retype(usize, usize),
    /// Replace the value by an extreme number (`NUMBERS`).
    Number(usize, usize),
    /// Cut the bytes at an offset (modulo the length + 1).
    Truncate(usize),
    /// Insert `BYTES[k]` at an offset.
    InsertBytes(usize, usize),
    /// Insert deeply nested content before a line, or as an override.
    Nest(Nest, usize, usize),
    /// `--set path=value` with a key of the file and a number or retyped value.
    Override(usize, usize, bool),
}

#[derive(Debug, Clone)]
struct Case {
    base: usize,
    mutations: Vec<Mutation>,
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let ix = any::<usize>();
    let nest = prop_oneof![
        Just(Nest::Arrays),
        Just(Nest::OpenArrays),
        Just(Nest::InlineTables),
        Just(Nest::DottedKey),
        Just(Nest::Header),
        Just(Nest::OverridePath),
        Just(Nest::OverrideValue),
    ];
    prop_oneof![
        2 => ix.prop_map(Mutation::DropKey),
        1 => ix.prop_map(Mutation::DropLine),
        1 => ix.prop_map(Mutation::DuplicateKey),
        3 => (ix, 0..RETYPES.len()).prop_map(|(k, r)| Mutation::Retype(k, r)),
        5 => (ix, 0..NUMBERS.len()).prop_map(|(k, n)| Mutation::Number(k, n)),
        2 => ix.prop_map(Mutation::Truncate),
        2 => (ix, 0..BYTES.len()).prop_map(|(at, b)| Mutation::InsertBytes(at, b)),
        1 => (nest, 0..DEPTHS.len(), ix).prop_map(|(n, d, at)| Mutation::Nest(n, DEPTHS[d], at)),
        1 => (ix, 0..NUMBERS.len() + RETYPES.len(), any::<bool>()).prop_map(|(k, v, b)| Mutation::Override(k, v, b)),
    ]
}

/// Cases of one to three mutations; single mutations are most frequent because they are
/// the ones whose blamed key and line are checked exactly.
fn case(bases: usize) -> impl Strategy<Value = Case> {
    (0..bases, prop::collection::vec(mutation(), 1..=3), 0..3usize).prop_map(|(base, mut mutations, keep)| {
        if keep > 0 {
            mutations.truncate(1);
        }
        Case { base, mutations }
    })
}

fn lines_of(bytes: &[u8]) -> Vec<Vec<u8>> {
    bytes.split(|&b| b == b'\n').map(<[u8]>::to_vec).collect()
}

fn join(lines: &[Vec<u8>]) -> Vec<u8> {
    lines.join(&b'\n')
}

/// The value part of a key line replaced by `value`, the comment kept.
fn replace_value(line: &[u8], value: &str) -> Vec<u8> {
    let text = String::from_utf8_lossy(line);
    let Some((key, rest)) = text.split_once('=') else { return line.to_vec() };
    let comment = if rest.trim_start().starts_with('"') { None } else { rest.find('#').map(|i| &rest[i..]) };
    match comment {
        Some(c) => format!("{key}= {value}   {c}").into_bytes(),
        None => format!("{key}= {value}").into_bytes(),
    }
}

fn nested(kind: Nest, depth: usize) -> String {
    match kind {
        Nest::Arrays | Nest::OverrideValue => format!("{}{}", "[".repeat(depth), "]".repeat(depth)),
        Nest::OpenArrays => "[".repeat(depth),
        Nest::InlineTables => format!("{}1{}", "{ a = ".repeat(depth), " }".repeat(depth)),
        Nest::DottedKey | Nest::Header | Nest::OverridePath => vec!["a"; depth].join("."),
    }
}

/// What the mutations made: bytes, overrides, and what a single mutation expects.
struct Mutant {
    bytes: Vec<u8>,
    overrides: Vec<String>,
    /// Set when one mutation on a known key line: (key path, 1-based line).
    target: Option<(String, usize)>,
}

fn apply(base: &Base, mutations: &[Mutation]) -> Mutant {
    let mut bytes = base.text.as_bytes().to_vec();
    let mut overrides = Vec::new();
    let keys = &base.keys;
    let pick = |k: usize| &keys[k % keys.len()];
    for m in mutations {
        let mut lines = lines_of(&bytes);
        match *m {
            Mutation::DropKey(k) => {
                let l = pick(k).line;
                if l < lines.len() {
                    lines.remove(l);
                }
            }
            Mutation::DropLine(k) => {
                let l = k % lines.len();
                lines.remove(l);
            }
            Mutation::DuplicateKey(k) => {
                let l = pick(k).line;
                if l < lines.len() {
                    let copy = lines[l].clone();
                    lines.insert(l + 1, copy);
                }
            }
            Mutation::Retype(k, r) => {
                let l = pick(k).line;
                if l < lines.len() {
                    lines[l] = replace_value(&lines[l], RETYPES[r]);
                }
            }
            Mutation::Number(k, n) => {
                let l = pick(k).line;
                if l < lines.len() {
                    lines[l] = replace_value(&lines[l], NUMBERS[n]);
                }
            }
            Mutation::Truncate(at) => {
                bytes.truncate(at % (bytes.len() + 1));
                continue;
            }
            Mutation::InsertBytes(at, b) => {
                let at = at % (bytes.len() + 1);
                bytes.splice(at..at, BYTES[b].iter().copied());
                continue;
            }
            Mutation::Nest(kind, depth, at) => {
                let text = nested(kind, depth);
                match kind {
                    Nest::OverridePath => overrides.push(format!("{text}=1")),
                    Nest::OverrideValue => overrides.push(format!("speed={text}")),
                    Nest::DottedKey => lines.insert(at % (lines.len() + 1), format!("{text} = 1").into_bytes()),
                    Nest::Header => lines.insert(at % (lines.len() + 1), format!("[{text}]").into_bytes()),
                    _ => lines.insert(at % (lines.len() + 1), format!("deep = {text}").into_bytes()),
                }
            }
            Mutation::Override(k, v, index_off) => {
                let mut path = pick(k).path.clone();
                if index_off {
                    // An index past the end, or a key below a value.
                    path = path.replacen("[0]", "[7]", 1).replacen("[1]", "[9]", 1) + ".x";
                }
                let value = if v < NUMBERS.len() { NUMBERS[v] } else { RETYPES[v - NUMBERS.len()] };
                overrides.push(format!("{path}={value}"));
                continue;
            }
        }
        bytes = join(&lines);
    }
    // An array of two numbers retyped to `[1, 2]` keeps its type: a valid value where the
    // key is a range (`design.response.speeds`), so no particular key is expected to fail.
    let array_kept = |k: usize, r: usize| {
        let original = base.text.lines().nth(pick(k).line).and_then(|l| l.split_once('=')).map(|(_, v)| v.trim());
        RETYPES[r] == "[1, 2]" && original.is_some_and(|v| v.starts_with('['))
    };
    let target = match mutations {
        [Mutation::Retype(k, r)] if array_kept(*k, *r) => None,
        [Mutation::Retype(k, _)] | [Mutation::Number(k, _)] | [Mutation::DropKey(k)] | [Mutation::DuplicateKey(k)] => {
            let key = pick(*k);
            Some((key.path.clone(), key.line + 1))
        }
        _ => None,
    };
    Mutant { bytes, overrides, target }
}

/// Counts of one run.
#[derive(Debug, Default)]
struct Stats {
    cases: u64,
    loaded: u64,
    rotors: u64,
    floquet: u64,
    analysis_errors: BTreeMap<String, u64>,
    rejected: BTreeMap<String, u64>,
    slowest: Duration,
    slowest_case: String,
}

/// The whole-message checks every rejection must pass.
fn check_error(e: &ProblemError, name: &str, bytes: &[u8]) -> Result<(), String> {
    let shown = e.to_string();
    if !shown.starts_with(name) {
        return Err(format!("message does not start with the file name: {shown}"));
    }
    if !e.key.is_empty() && !shown.contains(&format!("key `{}`", e.key)) {
        return Err(format!("message lacks the key path `{}`: {shown}", e.key));
    }
    let lines = bytes.iter().filter(|&&b| b == b'\n').count() + 1;
    match e.location {
        Location::Line(n) => {
            if !shown.contains(&format!(", line {n}:")) {
                return Err(format!("message lacks line {n}: {shown}"));
            }
            if n == 0 || n > lines {
                return Err(format!("line {n} outside the text's {lines} lines: {shown}"));
            }
        }
        Location::Override => {
            if !shown.contains("--set") {
                return Err(format!("override error does not say --set: {shown}"));
            }
        }
        Location::Unknown => {}
    }
    match &e.kind {
        // Text that does not parse still has a position.
        ProblemErrorKind::Syntax(_) | ProblemErrorKind::NotUtf8(_) if e.line().is_none() => {
            return Err(format!("syntax error without a line: {shown}"));
        }
        ProblemErrorKind::Read(_) => return Err(format!("read error on in-memory bytes: {shown}")),
        ProblemErrorKind::Syntax(_) | ProblemErrorKind::NotUtf8(_) | ProblemErrorKind::Empty => {}
        _ if e.location == Location::Unknown && !e.key.is_empty() => {
            // The text parses: a key (or its table) that is in the file must be located.
            let text =
                std::str::from_utf8(bytes).map_err(|_| format!("non-UTF-8 text passed the UTF-8 check: {shown}"))?;
            let top = e.key.split(['.', '[']).next().unwrap_or("");
            let table: toml::Table = toml::from_str(text).map_err(|_| format!("schema error on bad TOML: {shown}"))?;
            if table.contains_key(top) {
                return Err(format!("key `{}` is in the file (table `{top}`) but has no line: {shown}", e.key));
            }
        }
        _ => {}
    }
    Ok(())
}

/// Keys whose value another key's check depends on: an extreme value here may be
/// reported at the dependent key.
fn dependent(changed: &str, blamed: &str) -> bool {
    let dep = |a: &str, b: &str| changed.ends_with(a) && blamed.ends_with(b);
    // Disk nodes and positions depend on the shaft; derived C_p^S on the ring's angle and
    // θ_p; the k_eq2 check covers their combination.
    // In [design], an upper bound is checked against its lower bound (and φ_op, β_max
    // against the range and level), so a huge lower value is reported at the upper key.
    // The general form: nodes and positions depend on the sections; a support's node on
    // the others' (two rings at one node); the supports' count on each one's stiffness (a rotor
    // left with rigid-body modes is blamed at a bearing without stiffness, else at its
    // first support); a geometry disk's mass on its width and material (its overflow is
    // blamed at its outer diameter); the ring a design variable names on the rings'
    // names; a section's material on the materials; a support's coefficients on the
    // shaft's stiffness scale.
    let node_key = |k: &str| k.ends_with(".node") || k.ends_with(".position");
    let is_support = |k: &str| ["bearings", "seals", "rings"].iter().any(|t| k.starts_with(t));
    dep("shaft.elements", ".node")
        || dep("shaft.length", ".position")
        || (changed.starts_with("sections") && node_key(blamed))
        // Supports may share a node (a ring beside a bearing): sections that move them
        // onto one node leave a rigid-body mode, blamed at a support.
        || (changed.starts_with("sections")
            && ["bearings", "seals", "rings"].iter().any(|t| blamed.starts_with(t)))
        || (node_key(changed) && node_key(blamed))
        // A support moved onto another's node leaves one node holding the rotor: the
        // rigid-body mode is blamed at the first support, not the one that moved.
        || (node_key(changed) && is_support(changed) && is_support(blamed))
        || ((blamed.starts_with("bearings") || blamed.starts_with("rings"))
            && changed.starts_with(&format!("{blamed}.")))
        || (blamed == "sections" && (changed.starts_with("bearings") || changed.starts_with("rings")))
        || dep(".outer_diameter", ".inner_diameter")
        || (blamed.ends_with(".outer_diameter") && (changed.ends_with(".width") || changed.starts_with("materials")))
        || (changed.starts_with("materials") && blamed.ends_with(".material"))
        || dep(".name", ".ring")
        || dep(".lo", ".hi")
        || dep(".min", ".max")
        // A speed given in rpm that is dropped is missing at its rad/s key (either form).
        || changed == format!("{blamed}_rpm")
        || dep("design.phi_range[0]", "design.phi_range[1]")
        || (changed.starts_with("design.phi_range") && blamed.ends_with("design.phi_op"))
        || dep("design.level", "design.beta_max")
        || (changed.starts_with("ring") && blamed.starts_with("ring") && blamed.ends_with("k_eq2"))
        // A support's coefficients are judged against the shaft's own stiffness scale
        // (OutOfScale, whose message quotes the scale): a shaft made far softer (its
        // material, sections or elements) is blamed at the support now too stiff for it.
        || (["materials", "sections", "shaft"].iter().any(|t| changed.starts_with(t))
            && (blamed.starts_with("bearings") || blamed.starts_with("seals")))
}

/// Checks of a mutant made by one targeted mutation.
fn check_target(m: &Mutation, target: &(String, usize), result: &Result<Problem, ProblemError>) -> Result<(), String> {
    let (path, line) = target;
    // Names are free text too (`"x"` is a valid name; what refers to it is then blamed).
    let free_text = path == "title" || path == "source" || path.ends_with(".name");
    match (m, result) {
        // Free text takes a string, and a datetime as its text.
        (Mutation::Retype(_, r), Ok(_))
            if !(free_text && (RETYPES[*r].starts_with('"') || *r == RETYPES.len() - 1)) =>
        {
            Err(format!("`{path}` = {} was accepted", RETYPES[*r]))
        }
        (Mutation::Retype(..), Err(e)) if dependent(path, &e.key) => Ok(()),
        (Mutation::Retype(..), Err(e)) => {
            if &e.key != path || e.line() != Some(*line) {
                return Err(format!("retyped `{path}` (line {line}) blamed on `{}` line {:?}: {e}", e.key, e.line()));
            }
            Ok(())
        }
        (Mutation::Number(_, n), Err(e)) if matches!(e.kind, ProblemErrorKind::Syntax(_)) => {
            // Integers beyond i64 (and floats beyond f64) are TOML errors on their line.
            if e.line() != Some(*line) {
                return Err(format!("`{path}` = {} on line {line} reported at {:?}: {e}", NUMBERS[*n], e.location));
            }
            Ok(())
        }
        (Mutation::Number(_, n), Err(e)) => {
            if &e.key != path && !dependent(path, &e.key) {
                return Err(format!("`{path}` = {} blamed on `{}`: {e}", NUMBERS[*n], e.key));
            }
            if &e.key == path && e.line() != Some(*line) {
                return Err(format!("`{path}` = {} on line {line} reported at {:?}: {e}", NUMBERS[*n], e.location));
            }
            if NUMBERS[*n].contains("nan") || NUMBERS[*n].contains("inf") {
                // Not finite: refused as such, or as the wrong type for an integer key.
                let ok = matches!(e.kind, ProblemErrorKind::NotFinite(_) | ProblemErrorKind::Schema(_));
                if !ok {
                    return Err(format!("`{path}` = {}: unexpected kind {:?}", NUMBERS[*n], e.kind));
                }
            }
            Ok(())
        }
        (Mutation::Number(_, n), Ok(p)) if NUMBERS[*n].contains("nan") || NUMBERS[*n].contains("inf") => {
            // Only a key that does not enter the model may take a non-finite number, and
            // there is none: every numeric key is checked.
            Err(format!("`{path}` = {} was accepted (speed {})", NUMBERS[*n], p.model.speed))
        }
        (Mutation::DropKey(_), Err(e)) => {
            let parent = e.key.is_empty()
                || path == &e.key
                || path.starts_with(&format!("{}.", e.key))
                || dependent(path, &e.key);
            if !parent {
                return Err(format!("dropped `{path}` blamed on `{}`: {e}", e.key));
            }
            Ok(())
        }
        (Mutation::DuplicateKey(_), Err(e)) => {
            if !matches!(e.kind, ProblemErrorKind::Syntax(_)) || e.line() != Some(line + 1) {
                return Err(format!("duplicate `{path}` on line {} reported as {e}", line + 1));
            }
            Ok(())
        }
        (Mutation::DuplicateKey(_), Ok(_)) => Err(format!("duplicate `{path}` accepted")),
        _ => Ok(()),
    }
}

/// Load a mutant and, when it is valid and small, prepare it for analysis.
fn run_case(bases: &[Base], c: &Case, stats: &Mutex<Stats>) -> Result<(), String> {
    let base = &bases[c.base];
    let mutant = apply(base, &c.mutations);
    let start = Instant::now();
    let result = Problem::from_bytes(&mutant.bytes, &base.name, &mutant.overrides);
    let mut rotor_outcome = None;
    let mut floquet_ok = false;
    match &result {
        Err(e) => check_error(e, &base.name, &mutant.bytes)?,
        Ok(p) if base.small && p.model.shaft.elements() <= 8 => match Rotor::new(&p.model) {
            Ok(rotor) => {
                if !(rotor.critical_load.is_finite() && rotor.critical_load > 0.0) {
                    return Err(format!("P_cr = {} accepted", rotor.critical_load));
                }
                rotor_outcome = Some(None);
                match FloquetSystem::new(&rotor, &p.settings, p.model.speed) {
                    Ok(_) => floquet_ok = true,
                    Err(e) => {
                        rotor_outcome =
                            Some(Some(format!("floquet: {}", e.to_string().split(':').next().unwrap_or(""))))
                    }
                }
            }
            Err(e) => rotor_outcome = Some(Some(format!("rotor: {}", e.to_string().split(':').next().unwrap_or("")))),
        },
        Ok(_) => {}
    }
    let elapsed = start.elapsed();
    if let [m] = c.mutations.as_slice() {
        if let Some(t) = &mutant.target {
            check_target(m, t, &result)?;
        }
    }
    let mut s = stats.lock().expect("stats");
    s.cases += 1;
    match &result {
        Ok(_) => s.loaded += 1,
        Err(e) => *s.rejected.entry(e.kind.name().to_string()).or_default() += 1,
    }
    if let Some(outcome) = rotor_outcome {
        s.rotors += 1;
        if floquet_ok {
            s.floquet += 1;
        }
        if let Some(err) = outcome {
            *s.analysis_errors.entry(err).or_default() += 1;
        }
    }
    if elapsed > s.slowest {
        s.slowest = elapsed;
        s.slowest_case = format!("{} {:?}", base.name, c.mutations);
    }
    drop(s);
    if elapsed > CASE_HANG_TIMEOUT {
        return Err(format!("case took {elapsed:?}, a hang (timeout {CASE_HANG_TIMEOUT:?})"));
    }
    Ok(())
}

fn fuzz(cases: u32) {
    let bases = bases();
    let stats = Mutex::new(Stats::default());
    let config = Config { cases, failure_persistence: None, ..Config::default() };
    let mut runner = TestRunner::new(config);
    let started = Instant::now();
    let outcome = runner.run(&case(bases.len()), |c| run_case(&bases, &c, &stats).map_err(TestCaseError::fail));
    let s = stats.into_inner().expect("stats");
    println!(
        "fuzz: {} cases in {:.1} s ({} loaded, {} rejected); {} valid small problems prepared (rotor built), {} reduced for Floquet",
        s.cases,
        started.elapsed().as_secs_f64(),
        s.loaded,
        s.cases - s.loaded,
        s.rotors,
        s.floquet
    );
    println!("fuzz: rejections by kind: {:?}", s.rejected);
    println!("fuzz: analysis refusals of valid files: {:?}", s.analysis_errors);
    println!("fuzz: slowest case {:.3} ms: {}", s.slowest.as_secs_f64() * 1e3, s.slowest_case);
    if let Err(e) = outcome {
        panic!("{e}");
    }
    assert!(s.cases >= u64::from(cases), "only {} of {cases} cases ran", s.cases);
    // The strategies must reach both sides: valid mutants and each kind of rejection.
    assert!(s.loaded > 0 && s.rotors > 0, "no valid mutant reached the analysis");
    for kind in ["Syntax", "Schema", "NotFinite", "NotPositive", "NotUtf8", "Override"] {
        assert!(s.rejected.contains_key(kind), "no {kind} rejection in {} cases", s.cases);
    }
}

#[test]
fn mutated_problems_are_refused_cleanly() {
    let cases = std::env::var("ROTORSHUNT_FUZZ_CASES")
        .ok()
        .map(|v| v.parse().expect("ROTORSHUNT_FUZZ_CASES must be a whole number"))
        .unwrap_or(FUZZ_CASES_DEFAULT);
    fuzz(cases);
}

/// 10 000 and 100 000 levels of every kind of nesting: refused with a line (or as an
/// override), no stack overflow. Run on a thread with a small stack, like a test thread.
#[test]
fn deep_nesting_is_refused_without_overflow() {
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/paper-closed.toml"))
        .expect("paper-closed.toml");
    let run = move || {
        for depth in [10_000usize, 100_000] {
            for kind in [Nest::Arrays, Nest::OpenArrays, Nest::InlineTables, Nest::DottedKey, Nest::Header] {
                for at_line in [0usize, 7, 30] {
                    let mut lines: Vec<&str> = text.lines().collect();
                    let deep = nested(kind, depth);
                    let inserted = match kind {
                        Nest::DottedKey => format!("{deep} = 1"),
                        Nest::Header => format!("[{deep}]"),
                        _ => format!("deep = {deep}"),
                    };
                    lines.insert(at_line, &inserted);
                    let bytes = lines.join("\n").into_bytes();
                    let e = Problem::from_bytes(&bytes, "deep.toml", &[]).expect_err("deep nesting accepted");
                    assert_eq!(e.line(), Some(at_line + 1), "{kind:?} depth {depth} at line {}: {e}", at_line + 1);
                    check_error(&e, "deep.toml", &bytes).unwrap_or_else(|m| panic!("{kind:?} {depth}: {m}"));
                }
            }
            for set in
                [format!("{}=1", nested(Nest::OverridePath, depth)), format!("speed={}", nested(Nest::Arrays, depth))]
            {
                let e = Problem::from_bytes(text.as_bytes(), "deep.toml", &[set]).expect_err("deep override accepted");
                assert_eq!(e.location, Location::Override, "{e}");
                check_error(&e, "deep.toml", text.as_bytes()).unwrap_or_else(|m| panic!("{m}"));
            }
        }
    };
    std::thread::Builder::new().stack_size(2 << 20).spawn(run).expect("thread").join().expect("no panic");
}

/// Invalid UTF-8 anywhere: a typed error with the byte offset and its line.
#[test]
fn invalid_utf8_is_located() {
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/paper-open.toml"))
        .expect("paper-open.toml");
    // Offsets at line starts, inside ASCII and just after a multi-byte character.
    let after_omega = text.find('Ω').expect("Ω in the file") + 'Ω'.len_utf8();
    for at in [0, 1, 40, after_omega, text.len() / 2, text.len()] {
        let mut at = at;
        while !text.is_char_boundary(at) {
            at -= 1;
        }
        let mut bytes = text.as_bytes().to_vec();
        bytes.insert(at, 0xFF);
        let e = Problem::from_bytes(&bytes, "u.toml", &[]).expect_err("invalid UTF-8 accepted");
        assert_eq!(e.kind, ProblemErrorKind::NotUtf8(at), "{e}");
        let line = text.as_bytes()[..at].iter().filter(|&&b| b == b'\n').count() + 1;
        assert_eq!(e.line(), Some(line), "{e}");
        assert!(e.to_string().starts_with(&format!("u.toml, line {line}: the file is not UTF-8")), "{e}");
    }
}
