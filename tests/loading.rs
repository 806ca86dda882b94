//! Loading is linear and bounded: large files load fast, huge or odd inputs are refused
//! fast with a typed error (exit 2), and nothing waits on a FIFO or reads a device
//! forever. (`tests/parse_memory.rs` checks the parse-memory estimate.)
//!
//! Time bounds are generous (a loaded CI machine); the measured figures are printed
//! (`cargo test --release --test suite loading:: -- --nocapture`).

use crate::common;
use rotorshunt::problem::file::BranchFile;
use rotorshunt::problem::{Problem, ProblemError, ProblemErrorKind, MAX_DOFS, MAX_FILE_BYTES};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_rotorshunt");

/// How long a command may run before it counts as hung (a watchdog, not a timing: the
/// refusals take milliseconds; the timings are printed, and benches measure them).
const HANG_TIMEOUT: Duration = Duration::from_secs(20);

/// A fresh scratch directory for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("loading").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    dir
}

/// Run the binary, killing it if it runs longer than [`HANG_TIMEOUT`]; its output and wall time.
fn run(args: &[&str]) -> (Output, Duration) {
    let started = Instant::now();
    let mut child = Command::new(BIN)
        .args(args)
        .env_remove("RUST_BACKTRACE")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run rotorshunt");
    // Drain both pipes while waiting: a large output would block the child otherwise.
    let drain = |mut r: Box<dyn std::io::Read + Send>| {
        std::thread::spawn(move || {
            let mut v = Vec::new();
            let _ = r.read_to_end(&mut v);
            v
        })
    };
    let stdout = drain(Box::new(child.stdout.take().expect("stdout")));
    let stderr = drain(Box::new(child.stderr.take().expect("stderr")));
    let status = loop {
        if let Some(status) = child.try_wait().expect("poll rotorshunt") {
            break status;
        }
        if started.elapsed() > HANG_TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            panic!("rotorshunt {} still running after {HANG_TIMEOUT:?}", args.join(" "));
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let took = started.elapsed();
    let out =
        Output { status, stdout: stdout.join().expect("stdout reader"), stderr: stderr.join().expect("stderr reader") };
    (out, took)
}

/// Assert a refusal: exit 2, one `error:` line naming `what` (its time printed).
fn assert_refused(args: &[&str], what: &str) {
    let (out, took) = run(args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    println!("rotorshunt {}: {:.3} s: {}", args.join(" "), took.as_secs_f64(), stderr.trim());
    assert_eq!(out.status.code(), Some(2), "rotorshunt {}: {stderr}", args.join(" "));
    assert!(stderr.starts_with("error: ") && stderr.contains(what), "rotorshunt {}: {stderr}", args.join(" "));
    assert!(!stderr.contains("panicked"), "{stderr}");
}

fn path_str(p: &Path) -> &str {
    p.to_str().expect("UTF-8 path")
}

/// Load `path` in a thread; fail if it has not returned within [`HANG_TIMEOUT`] (a FIFO would
/// block the open forever).
fn load_within(path: &Path) -> Result<Problem, ProblemError> {
    let (tx, rx) = std::sync::mpsc::channel();
    let p = path.to_path_buf();
    std::thread::spawn(move || {
        let _ = tx.send(Problem::from_path(&p, &[]));
    });
    rx.recv_timeout(HANG_TIMEOUT).unwrap_or_else(|_| panic!("loading {} did not return", path.display()))
}

#[test]
fn ten_thousand_disks_check_fast() {
    let dir = scratch("disks");
    let file = dir.join("disks-10000.toml");
    std::fs::write(&file, common::many_disks_text(10_000)).expect("write disks");
    let started = Instant::now();
    let problem = Problem::from_path(&file, &[]).unwrap_or_else(|e| panic!("{e}"));
    println!("loading 10^4 disks: {:.3} s", started.elapsed().as_secs_f64());
    assert_eq!(problem.model.disks.len(), 10_000);
    let (out, took) = run(&["check", path_str(&file)]);
    println!("rotorshunt check on 10^4 disks: {:.3} s", took.as_secs_f64());
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("disk 10000: node 63"), "the summary lists every disk");
}

#[test]
fn errors_in_a_large_file_have_the_right_line() {
    // The last disk's mass made negative: its line, found without indexing every key.
    let text = common::many_disks_text(10_000);
    let at = text.rfind("mass = 0.01").expect("a disk mass");
    let text = format!("{}mass = -1.0{}", &text[..at], &text[at + "mass = 0.01".len()..]);
    let line = text[..at].matches('\n').count() + 1;
    let started = Instant::now();
    let e = Problem::from_text(&text, "disks.toml", &[]).expect_err("a negative mass");
    println!("negative mass in the last of 10^4 disks: {:.3} s: {e}", started.elapsed().as_secs_f64());
    assert_eq!(e.key, "disks[9999].mass");
    assert_eq!(e.line(), Some(line));
    assert_eq!(e.kind, ProblemErrorKind::NotPositive(-1.0));
}

#[test]
fn a_large_unknown_array_is_refused_fast() {
    let base = std::fs::read_to_string(common::problem_path("paper-closed.toml")).expect("paper-closed.toml");
    let junk: Vec<String> = (0..100_000).map(|i| i.to_string()).collect();
    let at = base.find("speed =").expect("a speed");
    let text = format!("{}junk = [{}]\n{}", &base[..at], junk.join(", "), &base[at..]);
    let line = base[..at].matches('\n').count() + 1;
    let dir = scratch("junk");
    let file = dir.join("junk.toml");
    std::fs::write(&file, &text).expect("write junk");
    let started = Instant::now();
    let e = Problem::from_path(&file, &[]).expect_err("an unknown key");
    let took = started.elapsed();
    println!("a 100 000-element unknown array refused in {:.3} s: {e}", took.as_secs_f64());
    assert_eq!(e.key, "junk");
    assert_eq!(e.line(), Some(line));
    assert!(matches!(&e.kind, ProblemErrorKind::Schema(m) if m.contains("unknown field `junk`")), "{e}");
    assert_refused(&["check", path_str(&file)], "unknown field `junk`");
}

#[test]
fn dev_zero_is_refused_by_every_route() {
    let zero = Path::new("/dev/zero");
    if !zero.exists() {
        return;
    }
    let e = load_within(zero).expect_err("/dev/zero is no problem file");
    assert_eq!(e.kind, ProblemErrorKind::NotARegularFile { kind: "a character device".into() }, "{e}");
    let dir = scratch("dev-zero");
    let out = dir.join("out");
    assert_refused(&["check", "/dev/zero"], "/dev/zero: the path is a character device");
    assert_refused(&["study", "/dev/zero", "--out", path_str(&out)], "/dev/zero: the path is a character device");
    let study = dir.join("study.toml");
    std::fs::write(&study, "base = \"/dev/zero\"\n[[cases]]\nname = \"a\"\n").expect("write study");
    assert_refused(&["study", path_str(&study), "--out", path_str(&out)], "/dev/zero: the path is a character device");
    let paper = common::problem_path("paper-open.toml");
    let chart = dir.join("chart");
    assert_refused(
        &[
            "chart",
            &paper,
            "--phi",
            "100:200:50",
            "--beta",
            "0:0.1:0.1",
            "--out",
            path_str(&chart),
            "--compare",
            "/dev/zero",
        ],
        "/dev/zero: the path is a character device",
    );
}

#[test]
fn a_fifo_is_refused_without_waiting() {
    let dir = scratch("fifo");
    let fifo = dir.join("problem.toml");
    match Command::new("mkfifo").arg(&fifo).status() {
        Ok(s) if s.success() => {}
        // No mkfifo program (not a Unix system): nothing to test.
        _ => return,
    }
    let e = load_within(&fifo).expect_err("a FIFO is no problem file");
    assert_eq!(e.kind, ProblemErrorKind::NotARegularFile { kind: "a FIFO (named pipe)".into() }, "{e}");
    assert_refused(&["check", path_str(&fifo)], "the path is a FIFO (named pipe), not a regular file");
    let study = dir.join("study.toml");
    std::fs::write(&study, "base = \"problem.toml\"\n[[cases]]\nname = \"a\"\n").expect("write study");
    let out = dir.join("out");
    assert_refused(&["study", path_str(&study), "--out", path_str(&out)], "the path is a FIFO");
    assert_refused(&["study", path_str(&fifo), "--out", path_str(&out)], "the path is a FIFO");
}

#[test]
fn a_directory_is_refused() {
    let dir = scratch("directory");
    let e = Problem::from_path(&dir, &[]).expect_err("a directory is no problem file");
    assert_eq!(e.kind, ProblemErrorKind::NotARegularFile { kind: "a directory".into() }, "{e}");
    assert_refused(&["check", path_str(&dir)], "the path is a directory, not a regular file");
}

#[cfg(unix)]
#[test]
fn links_are_followed_to_what_they_name() {
    let dir = scratch("links");
    let good = dir.join("good.toml");
    std::os::unix::fs::symlink(common::problem_path("paper-open.toml"), &good).expect("symlink");
    Problem::from_path(&good, &[]).unwrap_or_else(|e| panic!("a link to a problem file: {e}"));
    let zero = dir.join("zero.toml");
    std::os::unix::fs::symlink("/dev/zero", &zero).expect("symlink");
    let e = Problem::from_path(&zero, &[]).expect_err("a link to /dev/zero");
    assert!(matches!(e.kind, ProblemErrorKind::NotARegularFile { .. }), "{e}");
}

#[test]
fn a_file_over_16_mib_is_too_large() {
    let file = common::too_large_file();
    let size = std::fs::metadata(&file).expect("too_large.toml").len();
    assert!(size > MAX_FILE_BYTES);
    let e = Problem::from_path(&file, &[]).expect_err("17 MiB");
    assert_eq!(e.kind, ProblemErrorKind::TooLarge { size, limit: MAX_FILE_BYTES }, "{e}");
    assert_refused(&["check", path_str(&file)], "the file is too large");
    // One byte under the limit is read (and then fails as TOML: it is all zero bytes).
    let dir = scratch("too-large");
    let at_limit = dir.join("at-limit.toml");
    std::fs::File::create(&at_limit).and_then(|f| f.set_len(MAX_FILE_BYTES)).expect("16 MiB file");
    let e = Problem::from_path(&at_limit, &[]).expect_err("zero bytes are no TOML");
    assert!(!matches!(e.kind, ProblemErrorKind::TooLarge { .. }), "{e}");
}

#[test]
fn a_million_branches_or_disks_are_refused_quickly() {
    // By file: far over the size limit (58 MB), refused before reading.
    let base = std::fs::read_to_string(common::problem_path("paper-closed.toml")).expect("paper-closed.toml");
    let head = base.split("[[circuit.branches]]").next().expect("head");
    let mut text = String::from(head);
    for _ in 0..1_000_000 {
        text.push_str("[[circuit.branches]]\nc_f = 5e-6\ntuning_frequency = 900.0\n\n");
    }
    text.push_str("[load]\nalpha = 0.5\n");
    let dir = scratch("million");
    let file = dir.join("branches.toml");
    std::fs::write(&file, &text).expect("write branches");
    assert_refused(&["check", path_str(&file)], "the file is too large");
    // As text: too costly to parse (17 million tokens), refused before parsing.
    let started = Instant::now();
    let e = Problem::from_text(&text, "branches.toml", &[]).expect_err("a million branches");
    println!("10^6 branches as text refused in {:.3} s: {e}", started.elapsed().as_secs_f64());
    assert!(matches!(e.kind, ProblemErrorKind::TooComplex { .. }), "{e}");
    // As data (the library's builders): the DOF count, before anything is assembled.
    let mut data = common::load("paper-closed.toml", &[]).data;
    let branch = BranchFile { c_f: 5e-6, inductance: None, tuning_frequency: Some(900.0), resistance: 0.0 };
    data.circuit.as_mut().expect("shorthand").branches = vec![branch; 1_000_000];
    let started = Instant::now();
    let e = Problem::from_data(data.clone(), "branches", &[]).expect_err("a million branches");
    println!("10^6 branches as data refused in {:.3} s: {e}", started.elapsed().as_secs_f64());
    assert_eq!(e.kind, ProblemErrorKind::TooManyDofs { dofs: 2 * 65 + 2 + 2 * 1_000_000, limit: MAX_DOFS });
    assert_eq!(e.key, "circuit.branches");
    data.circuit.as_mut().expect("shorthand").branches.truncate(2);
    let disk = data.disks[0].clone();
    data.disks = vec![disk; 1_000_000];
    let e = Problem::from_data(data, "disks", &[]).expect_err("a million disks");
    assert_eq!(e.kind, ProblemErrorKind::TooManyEntries { count: 1_000_000, limit: rotorshunt::problem::MAX_DISKS });
    assert_eq!(e.key, "disks");
}

#[test]
fn the_dof_limit_is_the_assembled_size() {
    // The largest closed model the limit admits loads and assembles to that many DOFs;
    // one branch more is refused.
    let branches = (MAX_DOFS - (2 * 2001 + 2)) / 2;
    let mut data = common::load("paper-closed.toml", &[]).data;
    data.shaft.as_mut().expect("shorthand").elements = 2000;
    let circuit = data.circuit.as_mut().expect("shorthand");
    circuit.branches = vec![circuit.branches[0].clone(); branches];
    let p = Problem::from_data(data.clone(), "largest", &[]).unwrap_or_else(|e| panic!("{e}"));
    let dofs = rotorshunt::assembly::DofMap { nodes: 2001, branches: vec![branches; 2] }.len();
    assert!(dofs <= MAX_DOFS && dofs + 2 > MAX_DOFS, "{dofs} DOFs");
    assert_eq!(p.model.rings[0].circuit.charge_dofs(), branches);
    let circuit = data.circuit.as_mut().expect("shorthand");
    circuit.branches.push(circuit.branches[0].clone());
    let e = Problem::from_data(data, "one more", &[]).expect_err("one branch more");
    assert_eq!(e.kind, ProblemErrorKind::TooManyDofs { dofs: dofs + 2, limit: MAX_DOFS });
}

#[test]
fn a_text_too_costly_to_parse_is_refused_before_parsing() {
    let file = common::too_complex_file();
    let started = Instant::now();
    let e = Problem::from_path(&file, &[]).expect_err("1 MiB of dotted keys");
    println!("1 MiB of dotted keys refused in {:.3} s: {e}", started.elapsed().as_secs_f64());
    assert!(matches!(e.kind, ProblemErrorKind::TooComplex { .. }), "{e}");
    // A study file goes through the same check.
    let dir = scratch("too-complex");
    assert_refused(&["study", path_str(&file), "--out", path_str(&dir.join("out"))], "the TOML text is too complex");
    // Numbers are not tables: of the paper file's many `.`, only the two in
    // `[[circuit.branches]]` headers count (each header counts as a table, and so does its
    // `.`: [shaft], [[disks]], [ring], [circuit], 2 × 2, [load], [analysis]).
    let text = std::fs::read_to_string(common::problem_path("paper-closed.toml")).expect("paper-closed.toml");
    assert!(text.matches('.').count() > 20);
    let cost = rotorshunt::problem::input::TomlCost::of(&text);
    assert_eq!(cost.tables, 10, "{cost:?}");
    assert_eq!(cost.arrays, 0, "{cost:?}");
}
