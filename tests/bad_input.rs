//! Bad input must be refused cleanly: exit code 2, a one-paragraph message that names the
//! file, the line and the key, no panic, and the input file left untouched.
//!
//! Fixtures: `tests/fixtures/bad/*.toml` are copies of `problems/paper-closed.toml` with one
//! defect each. The expected message (a substring of stderr) is the first line of the file,
//! `# expect: <substring>`, or, when the first line cannot hold it (a file that is not UTF-8,
//! an empty file), the content of the sidecar `tests/fixtures/bad/<stem>.expect`.
//! `tests/fixtures/good/*.toml` are valid variants that must load.

use crate::common;
use rotorshunt::problem::Problem;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_rotorshunt");
const EXPECT_PREFIX: &str = "# expect: ";

fn fixture_dir(kind: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests").join("fixtures").join(kind)
}

/// The `*.toml` files of `tests/fixtures/<kind>`, sorted.
fn fixtures(kind: &str) -> Vec<PathBuf> {
    let dir = fixture_dir(kind);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()))
        .map(|entry| entry.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
}

fn name_of(path: &Path) -> String {
    path.file_name().expect("fixture has a file name").to_string_lossy().into_owned()
}

/// The expected message substring: the sidecar `<stem>.expect` if there is one, else the
/// `# expect: ` first line.
fn expectation(path: &Path) -> String {
    let sidecar = path.with_extension("expect");
    if sidecar.exists() {
        let text =
            std::fs::read_to_string(&sidecar).unwrap_or_else(|e| panic!("cannot read {}: {e}", sidecar.display()));
        let text = text.trim();
        assert!(!text.is_empty(), "{} is empty", sidecar.display());
        return text.to_string();
    }
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let first = bytes.split(|&b| b == b'\n').next().unwrap_or_default();
    let first = String::from_utf8_lossy(first);
    let expect = first
        .trim_end_matches('\r')
        .strip_prefix(EXPECT_PREFIX)
        .unwrap_or_else(|| {
            panic!("{}: first line must be `{EXPECT_PREFIX}<message>` (or add {})", path.display(), sidecar.display())
        })
        .trim();
    assert!(!expect.is_empty(), "{}: empty expectation", path.display());
    expect.to_string()
}

/// The `N` of the first `line N` in an expectation.
fn expected_line(expect: &str) -> Option<usize> {
    expect.match_indices("line ").find_map(|(i, m)| {
        let word_start = expect[..i].chars().next_back().is_none_or(|c| !c.is_alphanumeric() && c != '_');
        if !word_start {
            return None;
        }
        let rest = &expect[i + m.len()..];
        let digits: String = rest.chars().take_while(|c| c.is_ascii_digit()).collect();
        digits.parse().ok()
    })
}

fn run(args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .env_remove("RUST_BACKTRACE")
        .output()
        .unwrap_or_else(|e| panic!("cannot run {BIN}: {e}"))
}

fn stderr_of(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// What is wrong with the binary's reaction to a bad input, if anything.
fn refusal_problems(out: &Output, must_contain: &[&str]) -> Vec<String> {
    let stderr = stderr_of(out);
    let mut problems = Vec::new();
    if out.status.code() != Some(2) {
        problems.push(format!("exit code {:?}, expected 2", out.status.code()));
    }
    if stderr.contains("panicked") {
        problems.push("the program panicked".into());
    }
    if stderr.trim().is_empty() {
        problems.push("stderr is empty".into());
    }
    if stderr.trim().contains("\n\n") || stderr.lines().any(|l| l.trim().is_empty()) {
        problems.push("stderr is not a single paragraph (blank line)".into());
    }
    for s in must_contain {
        if !stderr.contains(s) {
            problems.push(format!("stderr lacks {s:?}"));
        }
    }
    problems
}

fn fail_if_any(failures: Vec<String>) {
    assert!(failures.is_empty(), "{} failure(s):\n{}", failures.len(), failures.join("\n"));
}

#[test]
fn fixtures_exist() {
    let bad = fixtures("bad");
    assert!(bad.len() >= 40, "only {} bad fixtures", bad.len());
    for required in ["not_utf8.toml", "empty.toml"] {
        assert!(bad.iter().any(|p| name_of(p) == required), "missing bad/{required}");
    }
    assert!(!fixtures("good").is_empty(), "no good fixtures");
    // Every sidecar belongs to a fixture.
    for entry in std::fs::read_dir(fixture_dir("bad")).expect("bad fixtures") {
        let p = entry.expect("directory entry").path();
        if p.extension().is_some_and(|e| e == "expect") {
            assert!(p.with_extension("toml").exists(), "{} has no fixture", p.display());
        }
    }
}

#[test]
fn bad_fixtures_are_refused_by_the_binary() {
    let mut failures = Vec::new();
    for path in fixtures("bad") {
        let name = name_of(&path);
        let expect = expectation(&path);
        let out = run(&["check", path.to_str().expect("UTF-8 path")]);
        let problems = refusal_problems(&out, &[&expect, &name]);
        if !out.stdout.is_empty() {
            failures.push(format!("{name}: stdout is not empty: {}", String::from_utf8_lossy(&out.stdout)));
        }
        if !problems.is_empty() {
            failures.push(format!(
                "{name}: {}\n    expected: {expect}\n    stderr:   {}",
                problems.join("; "),
                stderr_of(&out).trim_end()
            ));
        }
    }
    fail_if_any(failures);
}

#[test]
fn bad_fixtures_are_refused_by_the_library_with_the_right_line() {
    let mut failures = Vec::new();
    for path in fixtures("bad") {
        let name = name_of(&path);
        let expect = expectation(&path);
        match Problem::from_path(&path, &[]) {
            // A damping constraint's whirl tag needs the model's whirls: the loader reads
            // it, and the design refuses it before any candidate (the file layer solves
            // nothing; tests/file_layer.rs), with the same words as `check`.
            Ok(p) if p.design.as_ref().is_some_and(|d| !d.constraints.damping.is_empty()) => {
                match common::design_refusal(&p) {
                    Ok(()) => failures.push(format!("{name}: loaded and its whirl tags accepted")),
                    Err(e) => {
                        let words = expect.split_once("`: ").map_or(expect.as_str(), |(_, w)| w);
                        if !e.to_string().contains(words) {
                            failures.push(format!("{name}: the design's message lacks {words:?}\n    got: {e}"));
                        }
                    }
                }
            }
            Ok(_) => failures.push(format!("{name}: loaded without error")),
            Err(e) => {
                let message = e.to_string();
                if !message.contains(&expect) {
                    failures.push(format!("{name}: message lacks {expect:?}\n    got: {message}"));
                }
                // A `line N` in the expectation must be the error's line; no line in the
                // expectation means the error has none either (e.g. a missing table).
                let want = expected_line(&expect);
                if e.line() != want {
                    failures.push(format!("{name}: line() = {:?}, expected {want:?}\n    got: {message}", e.line()));
                }
            }
        }
    }
    fail_if_any(failures);
}

#[test]
fn good_fixtures_load() {
    let mut failures = Vec::new();
    for path in fixtures("good") {
        let name = name_of(&path);
        if let Err(e) = Problem::from_path(&path, &[]) {
            failures.push(format!("{name}: library refused it: {e}"));
        }
        let out = run(&["check", path.to_str().expect("UTF-8 path")]);
        if out.status.code() != Some(0) {
            failures.push(format!(
                "{name}: exit code {:?}, expected 0; stderr: {}",
                out.status.code(),
                stderr_of(&out).trim_end()
            ));
        }
    }
    fail_if_any(failures);
}

fn paper_closed() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("problems")
        .join("paper-closed.toml")
        .to_str()
        .expect("UTF-8 path")
        .to_string()
}

#[test]
fn bad_overrides_are_refused() {
    let file = paper_closed();
    // 10 000 levels overflowed the stack of a library caller's thread before the depth
    // limit (found by tests/fuzz.rs).
    let deep = format!("{}=1", vec!["a"; 10_000].join("."));
    let cases: &[(&str, &[&str])] = &[
        (&deep, &["--set", "the key path has 10000 levels, more than the 79 a problem file may have"]),
        ("shaft.elements=0", &["--set", "key `shaft.elements`", "from 1 to 2000, found 0"]),
        ("nosuch.key=1", &["--set", "key `nosuch`", "unknown field `nosuch`"]),
        (
            "circuit.branches[5].resistance=1",
            &["--set", "circuit.branches[5].resistance", "index [5] is out of range: the array has 2 entries"],
        ),
        ("speed", &["--set speed", "expected key.path=value"]),
        (
            "circuit.branches[0].resistance=-3",
            &["--set", "key `circuit.branches[0].resistance`", "must not be negative, found -3"],
        ),
    ];
    let mut failures = Vec::new();
    for (set, want) in cases {
        let mut must: Vec<&str> = want.to_vec();
        must.push("paper-closed.toml");
        let out = run(&["check", &file, "--set", set]);
        let problems = refusal_problems(&out, &must);
        if !problems.is_empty() {
            failures.push(format!("--set {set}: {}\n    stderr: {}", problems.join("; "), stderr_of(&out).trim_end()));
        }
        // The library reports an override, not a line of the file.
        match Problem::from_path(&file, &[set.to_string()]) {
            Ok(_) => failures.push(format!("--set {set}: the library accepted it")),
            Err(e) if e.line().is_some() => {
                failures.push(format!("--set {set}: line() = {:?}, expected None: {e}", e.line()))
            }
            Err(_) => {}
        }
    }
    fail_if_any(failures);
}

#[test]
fn bad_command_lines_fail_without_panic() {
    let file = paper_closed();
    let missing = fixture_dir("bad").join("no-such-file.toml");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["modes", &file, "--no-such-flag"], "--no-such-flag"),
        (vec!["modes", missing.to_str().expect("UTF-8 path")], "cannot read the file"),
    ];
    for (args, want) in cases {
        let out = run(&args);
        let stderr = stderr_of(&out);
        assert!(!out.status.success(), "{args:?} succeeded");
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?} panicked: {stderr}");
        assert!(stderr.contains(want), "{args:?}: stderr lacks {want:?}: {stderr}");
    }
    assert!(!missing.exists(), "the tool created {}", missing.display());
}

#[test]
fn inputs_are_never_modified() {
    for path in fixtures("bad").into_iter().chain(fixtures("good")) {
        let before = std::fs::read(&path).expect("read fixture");
        let p = path.to_str().expect("UTF-8 path");
        run(&["check", p]);
        run(&["check", p, "--set", "speed=1500"]);
        run(&["modes", p, "--count", "1"]);
        let after = std::fs::read(&path).expect("read fixture");
        assert!(before == after, "{} was modified", path.display());
    }
}

#[test]
fn expected_line_parses_the_first_line_number() {
    assert_eq!(expected_line("line 11: key `a`: x"), Some(11));
    assert_eq!(expected_line("f.toml, line 2: not UTF-8"), Some(2));
    assert_eq!(expected_line("key `shaft`: missing field `shaft`"), None);
    assert_eq!(expected_line("deadline 5"), None);
}
