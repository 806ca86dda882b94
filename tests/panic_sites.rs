//! Every call in src/ that panics by design (`expect`, `unwrap()`, `unreachable!`,
//! `panic!`, the `assert` family, `todo!`, `unimplemented!`) outside `#[cfg(test)]`
//! modules is listed in docs/invariants.md with the reason it cannot fire on data, and
//! every entry there names a call that still exists. Comments, strings and doc examples
//! are not code and are skipped.

mod common;

use std::path::Path;

/// The calls that panic by design, as they appear in code (after [`blank`]).
const PANICKING: [&str; 11] = [
    ".expect(",
    ".unwrap()",
    ".unwrap_unchecked(",
    "unreachable!",
    "panic!",
    "assert!",
    "assert_eq!",
    "assert_ne!",
    "debug_assert",
    "todo!",
    "unimplemented!",
];

fn ident(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// The text with comments and the contents of string and char literals replaced by
/// spaces (quotes and line breaks kept), so that only code is searched.
fn blank(text: &str) -> String {
    let c: Vec<char> = text.chars().collect();
    let mut out: Vec<char> = c.clone();
    let mut i = 0;
    let wipe = |out: &mut Vec<char>, from: usize, to: usize| {
        for x in out.iter_mut().take(to).skip(from) {
            if *x != '\n' {
                *x = ' ';
            }
        }
    };
    while i < c.len() {
        let prev_ident = i > 0 && ident(c[i - 1]);
        if c[i] == '/' && c.get(i + 1) == Some(&'/') {
            let end = (i..c.len()).find(|&k| c[k] == '\n').unwrap_or(c.len());
            wipe(&mut out, i, end);
            i = end;
        } else if c[i] == '/' && c.get(i + 1) == Some(&'*') {
            let (mut depth, mut k) = (1, i + 2);
            while k < c.len() && depth > 0 {
                if c[k] == '/' && c.get(k + 1) == Some(&'*') {
                    depth += 1;
                    k += 1;
                } else if c[k] == '*' && c.get(k + 1) == Some(&'/') {
                    depth -= 1;
                    k += 1;
                }
                k += 1;
            }
            wipe(&mut out, i, k);
            i = k;
        } else if c[i] == 'r' && !prev_ident && matches!(c.get(i + 1), Some('"') | Some('#')) {
            // A raw string r"…" or r#"…"#: ends at a quote followed by as many hashes.
            let hashes = c[i + 1..].iter().take_while(|&&x| x == '#').count();
            let open = i + 1 + hashes;
            if c.get(open) != Some(&'"') {
                i += 1;
                continue;
            }
            let mut k = open + 1;
            while k < c.len()
                && !(c[k] == '"' && c[k + 1..].iter().take(hashes).filter(|&&x| x == '#').count() == hashes)
            {
                k += 1;
            }
            wipe(&mut out, open + 1, k);
            i = k + 1 + hashes;
        } else if c[i] == '"' {
            let mut k = i + 1;
            while k < c.len() && c[k] != '"' {
                k += if c[k] == '\\' { 2 } else { 1 };
            }
            wipe(&mut out, i + 1, k);
            i = k + 1;
        } else if c[i] == '\'' {
            // A char literal ('x', '\n', '\u{…}'), or else a lifetime ('a).
            if c.get(i + 1) == Some(&'\\') {
                let k = (i + 2..c.len()).find(|&k| c[k] == '\'').unwrap_or(c.len());
                wipe(&mut out, i + 1, k);
                i = k + 1;
            } else if c.get(i + 2) == Some(&'\'') {
                wipe(&mut out, i + 1, i + 2);
                i += 3;
            } else {
                i += 1;
            }
        } else {
            i += 1;
        }
    }
    out.into_iter().collect()
}

/// Lines (0-based) inside `#[cfg(test)]` items: from the attribute to the brace that
/// closes the item's first block.
fn test_lines(code: &str) -> Vec<bool> {
    let lines: Vec<&str> = code.lines().collect();
    let mut inside = vec![false; lines.len()];
    let mut l = 0;
    while l < lines.len() {
        if !lines[l].contains("#[cfg(test)]") {
            l += 1;
            continue;
        }
        let (mut depth, mut opened, mut k) = (0i64, false, l);
        while k < lines.len() {
            inside[k] = true;
            for ch in lines[k].chars() {
                match ch {
                    '{' => {
                        depth += 1;
                        opened = true;
                    }
                    '}' => depth -= 1,
                    _ => {}
                }
            }
            if opened && depth == 0 {
                break;
            }
            k += 1;
        }
        l = k + 1;
    }
    inside
}

/// One panicking call found in src/: its file (relative to the repository), the call and
/// the original line.
#[derive(Debug)]
struct Site {
    file: String,
    call: &'static str,
    line: usize,
    text: String,
}

fn sites_in(path: &Path, rel: &str) -> Vec<Site> {
    let text = std::fs::read_to_string(path).unwrap();
    let code = blank(&text);
    let tests = test_lines(&code);
    let original: Vec<&str> = text.lines().collect();
    let mut found = Vec::new();
    for (n, line) in code.lines().enumerate() {
        if tests[n] {
            continue;
        }
        for call in PANICKING {
            for (at, _) in line.match_indices(call) {
                // `assert!` inside `debug_assert!` is the latter's; a name must start here.
                let starts_word = call.starts_with('.') || at == 0 || !ident(line[..at].chars().last().unwrap_or(' '));
                if starts_word {
                    found.push(Site { file: rel.into(), call, line: n + 1, text: original[n].trim().into() });
                }
            }
        }
    }
    found
}

/// The entries of docs/invariants.md: bullets "- `file`: `code` — why".
fn entries(doc: &str) -> Vec<(String, String)> {
    doc.lines()
        .filter_map(|l| l.strip_prefix("- `src/"))
        .filter_map(|rest| {
            let (file, rest) = rest.split_once('`')?;
            let code = rest.split('`').nth(1)?;
            Some((format!("src/{file}"), code.to_string()))
        })
        .collect()
}

#[test]
fn every_panicking_call_is_a_listed_invariant() {
    let root = common::root();
    let files = common::rust_files(&root.join("src"));
    let mut sites = Vec::new();
    for f in &files {
        let rel = f.strip_prefix(root).unwrap().to_string_lossy().replace('\\', "/");
        sites.extend(sites_in(f, &rel));
    }
    let doc = std::fs::read_to_string(root.join("docs/invariants.md")).unwrap();
    let listed = entries(&doc);
    assert!(!listed.is_empty(), "docs/invariants.md lists no entry");
    let unlisted: Vec<&Site> = sites
        .iter()
        .filter(|s| !listed.iter().any(|(f, code)| *f == s.file && s.text.contains(code.as_str())))
        .collect();
    let stale: Vec<&(String, String)> = listed
        .iter()
        .filter(|(f, code)| !sites.iter().any(|s| s.file == *f && s.text.contains(code.as_str())))
        .collect();
    println!("{} files scanned, {} panicking calls outside tests, {} listed", files.len(), sites.len(), listed.len());
    for s in &sites {
        println!("  {}:{} {}", s.file, s.line, s.text);
    }
    assert!(
        unlisted.is_empty(),
        "panicking calls not in docs/invariants.md (remove them or list them with why they hold): {unlisted:#?}"
    );
    assert!(stale.is_empty(), "docs/invariants.md lists calls that are no longer in src/: {stale:?}");
}

#[test]
fn the_scanner_sees_code_only() {
    let text = concat!(
        "fn f() { let s = \"x.unwrap() panic!\"; // y.expect(\n",
        "    /* assert!(a) */ let c = '\\''; let r = r#\"todo!\"#; g::<'static>(); }\n",
        "fn h() { v.unwrap(); debug_assert!(true); }\n",
        "#[cfg(test)]\n",
        "mod tests {\n",
        "    fn t() { x.unwrap(); }\n",
        "}\n",
        "fn k() { unreachable!(\"}\") }\n",
    );
    let dir = std::env::temp_dir().join(format!("rotorshunt-panic-sites-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("sample.rs");
    std::fs::write(&file, text).unwrap();
    let found: Vec<(usize, &str)> = sites_in(&file, "sample.rs").iter().map(|s| (s.line, s.call)).collect();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(found, vec![(3, ".unwrap()"), (3, "debug_assert"), (8, "unreachable!")]);
}
