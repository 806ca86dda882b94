//! Shared helpers for the integration tests: the problem catalogue lives in problems/.
#![allow(dead_code)]

pub mod pins;
pub mod scan;

use rotorshunt::problem::Problem;

/// `--set` values that draw a design report's before/after charts on a 40 × 7 grid instead
/// of the default 400 × 31 (`design.chart_phi_points`, `design.chart_beta_points`): for
/// the tests that check a design, its verification and its files, not its charts' detail
/// (tests/design.rs's widest-band report, report_html.rs and progress.rs draw the default
/// grid). The design and its verification do not read these keys.
pub const COARSE_CHARTS: [&str; 2] = ["design.chart_phi_points=40", "design.chart_beta_points=7"];
/// [`COARSE_CHARTS`] as command-line arguments.
pub const COARSE_CHART_ARGS: [&str; 4] = ["--set", COARSE_CHARTS[0], "--set", COARSE_CHARTS[1]];

/// `--set` values that run a design on a fixed reduced basis of 8 modes without its
/// refined-basis check (`analysis.reduced_modes`, `design.refined_check`): for the tests
/// that check what a design run does (its files, folders, progress, stops, records,
/// studies), not whether its answer holds on a larger basis. A basis sized by convergence
/// and the refined check cost tens of seconds a design; tests/true_bands.rs checks them.
pub const QUICK_BASIS: [&str; 2] = ["analysis.reduced_modes=8", "design.refined_check=false"];
/// [`QUICK_BASIS`] as command-line arguments.
pub const QUICK_BASIS_ARGS: [&str; 4] = ["--set", QUICK_BASIS[0], "--set", QUICK_BASIS[1]];
/// A coarse model for the tests of files, folders and exit codes (8 shaft elements, the
/// disk at node 2, 4 modes, no refined check): what they check is not the numbers.
pub const COARSE_MODEL_ARGS: [&str; 8] = [
    "--set",
    "shaft.elements=8",
    "--set",
    "disks[0].node=2",
    "--set",
    "analysis.reduced_modes=4",
    "--set",
    "design.refined_check=false",
];
/// The values of [`COARSE_MODEL_ARGS`] (each `key=value`), for `--set` lists and
/// `Problem::from_path`.
pub fn coarse_model() -> impl Iterator<Item = &'static str> {
    COARSE_MODEL_ARGS.into_iter().skip(1).step_by(2)
}
/// A fixed basis of 8 modes for `band`, `regions` and studies (`analysis.reduced_modes`):
/// for the tests that compare what two commands or two runs give on the same model.
pub const FIXED_BASIS_ARGS: [&str; 2] = ["--set", "analysis.reduced_modes=8"];

/// Path of a catalogue problem.
pub fn problem_path(name: &str) -> String {
    format!("{}/problems/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// Load a catalogue problem with overrides.
pub fn load(name: &str, overrides: &[&str]) -> Problem {
    let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    Problem::from_path(problem_path(name), &o).unwrap_or_else(|e| panic!("{e}"))
}

/// The band around `phi_op` at `level` (−) in `window` (rad/s) by the search of
/// `rotorshunt band` (the window's seeds, [`band_around`]) without what only names its
/// bounds: the full model's whirls and the catalogues of the bounding tongues. No edge
/// moves with them; the design's candidates search the same way.
pub fn unnamed_band(
    fs: &rotorshunt::analysis::floquet::FloquetSystem,
    s: &rotorshunt::analysis::regions::RegionSettings,
    window: rotorshunt::analysis::Interval,
    phi_op: f64,
    level: f64,
) -> rotorshunt::analysis::regions::Band {
    use rotorshunt::analysis::regions::{band_around, seeds_for, Level, Probe};
    let criterion = rotorshunt::analysis::Criterion::of(&fs.settings);
    let seeds = seeds_for(fs, None, window, criterion.max_order).unwrap();
    let probe = Probe::new(fs, s);
    band_around(&Level::new(&probe, criterion, level, window), &seeds, phi_op)
}

/// Relative difference.
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// The repository root.
pub fn root() -> &'static std::path::Path {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Every `.rs` file below `dir`, sorted (the source scan of tests/layers.rs).
pub fn rust_files(dir: &std::path::Path) -> Vec<std::path::PathBuf> {
    fn visit(dir: &std::path::Path, files: &mut Vec<std::path::PathBuf>) {
        for e in std::fs::read_dir(dir).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                visit(&p, files);
            } else if p.extension().is_some_and(|x| x == "rs") {
                files.push(p);
            }
        }
    }
    let mut files = Vec::new();
    visit(dir, &mut files);
    files.sort();
    files
}

/// The folder of generated input files: `rotorshunt-generated` in the system's temporary
/// folder (tests write nowhere in the repository).
pub fn generated_dir() -> std::path::PathBuf {
    std::env::temp_dir().join("rotorshunt-generated")
}

/// A generated input file `NAME` in [`generated_dir`] (too large or too odd to keep in the
/// repository), written by `write` unless already there, atomically (test binaries and
/// the tests inside one may run at once).
pub fn generated(name: &str, write: impl FnOnce(&std::path::Path)) -> std::path::PathBuf {
    let dir = generated_dir();
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    let path = dir.join(name);
    if !path.exists() {
        let tmp = dir.join(format!(".{name}.{}.{:?}", std::process::id(), std::thread::current().id()));
        write(&tmp);
        std::fs::rename(&tmp, &path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    }
    path
}

/// How the design refuses a file that loads: its damping constraints' whirl tags checked
/// against its rotor as `design::run` checks them (the loader solves nothing).
pub fn design_refusal(p: &Problem) -> Result<(), rotorshunt::design::DesignError> {
    let spec = p.design.as_ref().expect("a [design] table");
    let rotor = p.rotor()?;
    rotorshunt::design::checks::modes_exist(&rotor, &p.settings, spec)
}

/// `too_large.toml` in [`generated_dir`]: one byte over 17 MiB (sparse: cheap to make).
pub fn too_large_file() -> std::path::PathBuf {
    generated("too_large.toml", |p| {
        let f = std::fs::File::create(p).expect("create too_large.toml");
        f.set_len(17 * 1024 * 1024 + 1).expect("size too_large.toml");
    })
}

/// TOML text of about `bytes` bytes of 70-level dotted keys: each line makes 71 tables,
/// about 550 bytes of parser memory per byte of text.
pub fn dotted_keys_text(bytes: usize) -> String {
    let level = vec!["a"; 70].join(".");
    let mut text = String::with_capacity(bytes + 200);
    let mut i = 0;
    while text.len() < bytes {
        text.push_str(&format!("k{i}.{level} = 1\n"));
        i += 1;
    }
    text
}

/// `too_complex.toml` in [`generated_dir`]: 1 MiB of dotted keys (a 577 MB parse).
pub fn too_complex_file() -> std::path::PathBuf {
    generated("too_complex.toml", |p| std::fs::write(p, dotted_keys_text(1 << 20)).expect("write too_complex.toml"))
}

/// `problems/paper-closed.toml` with `n` `[[disks]]` (0.01 kg, J_p = 1e-5 kg m²) spread
/// over the shaft's 65 nodes, in place of its one disk.
pub fn many_disks_text(n: usize) -> String {
    let base = std::fs::read_to_string(problem_path("paper-closed.toml")).expect("paper-closed.toml");
    let (head, rest) = base.split_once("[[disks]]").expect("paper-closed.toml has a disk");
    let tail = &rest[rest.find("[ring]").expect("paper-closed.toml has [ring]")..];
    let mut text = String::from(head);
    for i in 0..n {
        text.push_str(&format!("[[disks]]\nnode = {}\nmass = 0.01\npolar_inertia = 1e-5\n\n", i * 64 / n.max(2)));
    }
    text + tail
}

/// A child process run to its end (or killed at its timeout), measured.
#[derive(Debug)]
pub struct Measured {
    /// Exit status (None when killed by a signal, e.g. at the timeout).
    pub code: Option<i32>,
    /// The signal that ended it (SIGABRT = 6 for an abort, SIGKILL = 9 at the timeout).
    pub signal: Option<i32>,
    /// Killed at the timeout.
    pub timed_out: bool,
    /// Wall time (s).
    pub seconds: f64,
    /// Peak resident memory of the child (kB), from `wait4`'s rusage (`ru_maxrss`). Linux
    /// counts the spawning process's own peak in it (the high-water mark before `exec` is
    /// kept), so a test that bounds it runs in a small binary of its own (tests/suite.rs).
    pub peak_kb: i64,
    /// Standard output.
    pub stdout: String,
    /// Standard error.
    pub stderr: String,
}

/// Run the binary with `args` in `dir`, killed after `timeout`; its exit, time and peak
/// RSS. The child is reaped by `wait4`, whose rusage is that child's own (not shared with
/// other children running at once).
#[allow(clippy::zombie_processes)] // reaped by wait4 below, not by Child::wait
pub fn run_measured(args: &[String], dir: &std::path::Path, timeout: std::time::Duration) -> Measured {
    use std::io::Read;
    use std::os::unix::process::ExitStatusExt;
    let start = std::time::Instant::now();
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_rotorshunt"))
        .args(args)
        .current_dir(dir)
        .env_remove("RUST_BACKTRACE")
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("spawn rotorshunt");
    let pid = child.id() as libc::pid_t;
    let mut out = child.stdout.take().expect("stdout");
    let mut err = child.stderr.take().expect("stderr");
    let reader_out = std::thread::spawn(move || {
        let mut v = Vec::new();
        let _ = out.read_to_end(&mut v);
        v
    });
    let reader_err = std::thread::spawn(move || {
        let mut v = Vec::new();
        let _ = err.read_to_end(&mut v);
        v
    });
    let mut status: libc::c_int = 0;
    // SAFETY: rusage is plain data, zero is a valid value.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let mut timed_out = false;
    loop {
        // SAFETY: pid is our own child; status and usage are valid for writes.
        let r = unsafe { libc::wait4(pid, &mut status, libc::WNOHANG, &mut usage) };
        if r == pid {
            break;
        }
        assert!(r == 0, "wait4 failed: {}", std::io::Error::last_os_error());
        if start.elapsed() > timeout && !timed_out {
            timed_out = true;
            // SAFETY: signalling our own, not yet reaped child.
            unsafe { libc::kill(pid, libc::SIGKILL) };
        }
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    let seconds = start.elapsed().as_secs_f64();
    let exit = std::process::ExitStatus::from_raw(status);
    let text = |v: Vec<u8>| String::from_utf8_lossy(&v).into_owned();
    Measured {
        code: exit.code(),
        signal: exit.signal(),
        timed_out,
        seconds,
        peak_kb: usage.ru_maxrss,
        stdout: text(reader_out.join().expect("stdout reader")),
        stderr: text(reader_err.join().expect("stderr reader")),
    }
}

/// The `.toml` file names directly in `dir`, sorted.
pub fn toml_names(dir: &std::path::Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".toml"))
        .collect();
    v.sort();
    v
}

/// Every file under `out/cases`, relative: result.json parsed without wall time and task,
/// the others as bytes. Lock files and temporaries must not be there.
pub fn case_files(
    out: &std::path::Path,
) -> std::collections::BTreeMap<std::path::PathBuf, Result<serde_json::Value, Vec<u8>>> {
    let mut files = std::collections::BTreeMap::new();
    let cases = out.join("cases");
    for d in std::fs::read_dir(&cases).unwrap() {
        let d = d.unwrap().path();
        for f in std::fs::read_dir(&d).unwrap() {
            let p = f.unwrap().path();
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            assert!(!name.starts_with(".rotorshunt-tmp.") && name != ".rotorshunt-case.lock", "{} left", p.display());
            let rel = p.strip_prefix(&cases).unwrap().to_path_buf();
            let bytes = std::fs::read(&p).unwrap();
            if name == "result.json" {
                let mut v: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
                v["seconds"] = serde_json::Value::Null;
                v["task"] = serde_json::Value::Null;
                files.insert(rel, Ok(v));
            } else {
                files.insert(rel, Err(bytes));
            }
        }
    }
    files
}

/// The rotorshunt binary of this build.
pub fn bin() -> std::process::Command {
    std::process::Command::new(env!("CARGO_BIN_EXE_rotorshunt"))
}

/// A fresh scratch folder `rotorshunt-{name}-{pid}` in the system's temporary folder
/// (removed if left by an earlier run; not created).
pub fn tmp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("rotorshunt-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// [`tmp`], created.
pub fn scratch(name: &str) -> std::path::PathBuf {
    let d = tmp(name);
    std::fs::create_dir_all(&d).unwrap_or_else(|e| panic!("{}: {e}", d.display()));
    d
}

/// Run a command that must succeed; its standard output.
pub fn run_ok(cmd: &mut std::process::Command) -> String {
    let out = cmd.output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// A JSON file, parsed.
pub fn json(path: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// `json` read back as the library's `T` writes the same JSON, every number bit for bit
/// (issue 30: results round-trip; serde_json's `float_roundtrip` reads each f64 back
/// exactly). Returns the value read.
pub fn reads_back<T: serde::Serialize + serde::de::DeserializeOwned>(json: &serde_json::Value) -> T {
    let read: T = serde_path_to_error::deserialize(json.clone())
        .unwrap_or_else(|e| panic!("{} does not read back: {e}", std::any::type_name::<T>()));
    assert!(
        &serde_json::to_value(&read).unwrap() == json,
        "{} read back writes other JSON",
        std::any::type_name::<T>()
    );
    read
}

/// A design report's `outcome` read back as the library's [`rotorshunt::DesignOutcome`]
/// ([`reads_back`]).
pub fn outcome_round_trips(outcome: &serde_json::Value) -> rotorshunt::DesignOutcome {
    reads_back(outcome)
}

/// A design report's text (report.md or report.html) without the wall time that ends its
/// cost line (`- cost: …, N.N s`, `<li>cost: …, N.N s</li>`).
pub fn without_report_wall_time(text: &str) -> String {
    text.lines()
        .map(|l| {
            if l.starts_with("- cost:") || l.starts_with("<li>cost:") {
                l.rsplit_once(", ").map_or(l, |(a, _)| a)
            } else {
                l
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// What [`check_design_report`] measured on a design folder's report.md.
#[allow(dead_code)]
pub struct ReportLayout {
    /// Lines of page one (before the first `---` line).
    pub page_one_lines: usize,
    /// Data rows of the region tables near the bands.
    pub near_region_rows: usize,
}

/// Checks of a design report's layout (issue: a report that reads in one minute): page
/// one ends at a `---` line within 60 lines and holds the question, the answer, the
/// circuit table and the verification; the region tables near the bands have fewer than
/// 25 rows in all; every PNG written is embedded (the key figure on page one) and every
/// embedded one exists; the glossary and settings table are there; the file list is the
/// folder's files exactly (hidden ones and sub-folders aside).
#[allow(dead_code)]
pub fn check_design_report(dir: &std::path::Path) -> ReportLayout {
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    let lines: Vec<&str> = md.lines().collect();
    let end = lines.iter().position(|l| *l == "---").expect("no end of page one (`---`)");
    let page_one = lines[..end].join("\n");
    assert!(end <= 60, "page one is {end} lines long");
    for part in ["**Question.**", "**Answer.**", "| branch |", "**Verification: ", "- Catalogue:", "- Grid:"] {
        assert!(page_one.contains(part), "page one lacks {part}:\n{page_one}");
    }
    assert!(page_one.contains("![") && page_one.contains(".png)"), "no key figure on page one");
    let section = |title: &str| -> Vec<&str> {
        let start = lines.iter().position(|l| l.starts_with(title)).unwrap_or_else(|| panic!("no {title}"));
        let stop = lines[start + 1..].iter().position(|l| l.starts_with("## ")).map_or(lines.len(), |p| start + 1 + p);
        lines[start..stop].to_vec()
    };
    let near = section("## Regions near the band");
    let near_region_rows = near.iter().filter(|l| l.starts_with("| ") && !l.starts_with("| region |")).count();
    assert!(near_region_rows < 25, "{near_region_rows} rows near the bands");
    for title in ["## Glossary", "## Settings"] {
        assert!(section(title).len() > 5, "{title} is empty");
    }
    let listed: std::collections::BTreeSet<String> = section("## Files")
        .iter()
        .filter_map(|l| l.strip_prefix("- `").and_then(|l| l.strip_suffix('`')))
        .map(str::to_string)
        .collect();
    let written: std::collections::BTreeSet<String> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.path().is_file())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| !n.starts_with('.'))
        .collect();
    assert_eq!(listed, written, "the file list does not match the folder");
    let embedded: std::collections::BTreeSet<String> = md
        .split("](")
        .skip(1)
        .filter_map(|t| t.split_once(')').map(|(f, _)| f.to_string()))
        .filter(|f| f.ends_with(".png"))
        .collect();
    let pngs: std::collections::BTreeSet<String> = written.iter().filter(|f| f.ends_with(".png")).cloned().collect();
    assert_eq!(embedded, pngs, "embedded figures differ from the PNGs written");
    ReportLayout { page_one_lines: end, near_region_rows }
}

/// A study file `dir/NAME` of quick regions cases on a coarse model of
/// problems/design-widest-band.toml (8 elements, 4 reduced modes, φ 1150–1350 rad/s,
/// β_max 0.5, level 0.3, φ_op 1230 rad/s); `cases` is TOML for `[[cases]]` and `[sweep]`.
pub fn coarse_study(dir: &std::path::Path, name: &str, cases: &str) -> std::path::PathBuf {
    let study = dir.join(name);
    let text = format!(
        r#"base = "{}"
phi = [1150.0, 1350.0]
beta_max = 0.5
level = 0.3
phi_op = 1230.0
set = ["shaft.elements=8", "disks[0].node=2", "analysis.reduced_modes=4", "design.refined_check=false"]

{cases}
"#,
        problem_path("design-widest-band.toml")
    );
    std::fs::write(&study, text).unwrap_or_else(|e| panic!("{}: {e}", study.display()));
    study
}

/// What stands at each path below `dir` (except `skip` and what is below it), not
/// following links: a file's bytes, a link's target, `dir`, `fifo` or `special`.
pub fn tree(dir: &std::path::Path, skip: &std::path::Path) -> std::collections::BTreeMap<std::path::PathBuf, String> {
    use std::os::unix::fs::FileTypeExt;
    let mut out = std::collections::BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p == skip {
                continue;
            }
            let t = std::fs::symlink_metadata(&p).unwrap().file_type();
            let what = if t.is_symlink() {
                format!("link {}", std::fs::read_link(&p).unwrap().display())
            } else if t.is_dir() {
                stack.push(p.clone());
                "dir".into()
            } else if t.is_file() {
                format!("file {:?}", std::fs::read(&p).unwrap())
            } else if t.is_fifo() {
                "fifo".into()
            } else {
                "special".into()
            };
            out.insert(p, what);
        }
    }
    out
}

/// A FIFO at `path` (panics when it cannot be made).
pub fn mkfifo(path: &std::path::Path) {
    let c = std::ffi::CString::new(path.to_str().unwrap()).unwrap();
    // SAFETY: a valid NUL-terminated path.
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0, "mkfifo {}", path.display());
}

/// A Jeffcott rotor: a 10 kg disk of polar inertia `polar` and diametral inertia
/// `diametral` (kg·m²) at the middle of a 0.4 m shaft of diameter 0.05 m whose density is
/// 1e-3 kg/m³ (7.9e-7 kg: 8e-8 of the disk), on two identical bearings kxx = `kx`,
/// kyy = `ky` (N/m) at its ends, undamped, at speed `speed` (rad/s).
pub fn jeffcott(kx: f64, ky: f64, polar: f64, diametral: f64, speed: f64) -> String {
    jeffcott_damped(kx, ky, polar, diametral, 0.0, speed)
}

/// [`jeffcott`] with a damping `c` (N·s/m) in x at each bearing (`cxx`).
pub fn jeffcott_damped(kx: f64, ky: f64, polar: f64, diametral: f64, c: f64, speed: f64) -> String {
    format!(
        r#"version = 1
title = "anisotropic Jeffcott rotor"
speed = {speed:?}
[[sections]]
length = 0.4
outer_diameter = 0.05
youngs_modulus = 2.0e11
density = 1.0e-3
elements = 4
[[disks]]
node = 2
mass = 10.0
polar_inertia = {polar:?}
diametral_inertia = {diametral:?}
eccentricity = 1.0e-4
[[bearings]]
node = 0
kxx = {kx:?}
kyy = {ky:?}
cxx = {c:?}
[[bearings]]
node = 4
kxx = {kx:?}
kyy = {ky:?}
cxx = {c:?}
[load]
alpha = 0.0
"#
    )
}

/// [`jeffcott_damped`] (kxx = 1e7, kyy = 8e6 N/m, cxx = 100 N·s/m, a 10 kg disk at
/// 500 rad/s) whose first bearing tabulates kxx, kyy and cxx over `points` speeds, 0 to
/// 10·(points − 1) rad/s, each within 10 % of its constant.
pub fn tabulated_jeffcott(points: usize) -> String {
    let table = |base: f64| -> String {
        let v: Vec<String> =
            (0..points).map(|i| format!("{:?}", base * (1.0 + 0.1 * (i as f64 * 0.37).sin()))).collect();
        format!("[{}]", v.join(", "))
    };
    let speeds: Vec<String> = (0..points).map(|i| format!("{:?}", 10.0 * i as f64)).collect();
    let text = jeffcott_damped(1e7, 8e6, 0.5, 0.3, 100.0, 500.0);
    let constant = "[[bearings]]\nnode = 0\nkxx = 10000000.0\nkyy = 8000000.0\ncxx = 100.0\n";
    assert!(text.contains(constant), "jeffcott's first bearing");
    let tabulated = format!(
        "[[bearings]]\nnode = 0\nspeeds = [{}]\nkxx = {}\nkyy = {}\ncxx = {}\n",
        speeds.join(", "),
        table(1e7),
        table(8e6),
        table(100.0)
    );
    text.replacen(constant, &tabulated, 1)
}

/// `long_table.toml` in [`generated_dir`]: [`tabulated_jeffcott`] one speed over
/// [`rotorshunt::problem::MAX_TABLE_POINTS`].
pub fn long_table_file() -> std::path::PathBuf {
    generated("long_table.toml", |p| {
        std::fs::write(p, tabulated_jeffcott(rotorshunt::problem::MAX_TABLE_POINTS + 1)).expect("write long_table.toml")
    })
}

/// A ROSS rotor as `Rotor.save` writes it (`format`: "toml" or "json") with `elements`
/// shaft elements of 0.01 m, each of its own material (ROSS's "Steel" with a density
/// 1e-3 kg/m³ above the element before: the importer names them Steel, Steel-2, …, and
/// every element is a section of its own), on two bearings of 1e6 N/m at nodes 0 and
/// `elements`: the importer's most work per element.
pub fn ross_rotor(elements: usize, format: &str) -> String {
    // Each table's keys and values as JSON text, which TOML reads too for these values.
    let element = |i: usize| -> Vec<(&str, String)> {
        let tag = format!("\"Shaft Element {i}\"");
        [("L", "0.01"), ("idl", "0.0"), ("odl", "0.05"), ("idr", "0.0"), ("odr", "0.05")]
            .map(|(k, v)| (k, v.to_string()))
            .into_iter()
            .chain([("n", i.to_string())])
            .chain([("axial_force", "0"), ("torque", "0"), ("shear_effects", "false")].map(|(k, v)| (k, v.to_string())))
            .chain([("rotary_inertia", "true"), ("gyroscopic", "true")].map(|(k, v)| (k, v.to_string())))
            .chain([("shear_method_calc", "\"cowper\"".to_string()), ("tag", tag)])
            .chain([("alpha", "0.0"), ("beta", "0.0")].map(|(k, v)| (k, v.to_string())))
            .collect()
    };
    let material = |i: usize| -> Vec<(&str, String)> {
        vec![
            ("name", "\"Steel\"".into()),
            ("rho", format!("{:?}", 7810.0 + 1e-3 * i as f64)),
            ("E", "211000000000.0".into()),
            ("G_s", "81200000000.0".into()),
            ("color", "\"#525252\"".into()),
        ]
    };
    let bearing = |tag: &str, n: usize| -> Vec<(&'static str, String)> {
        let mut b: Vec<(&str, String)> = ["cxx", "cxy", "cyx", "cyy", "czz", "kxy", "kyx", "kzz", "mxx", "mxy", "myx"]
            .into_iter()
            .chain(["myy", "mzz"])
            .map(|k| (k, "[0.0]".to_string()))
            .collect();
        b.extend([("kxx", "[1000000.0]".to_string()), ("kyy", "[1000000.0]".to_string())]);
        b.extend([("n", n.to_string()), ("tag", format!("\"{tag}\""))]);
        b
    };
    let bearings = [("Bearing 0", 0), ("Bearing 1", elements)];
    if format == "json" {
        let object = |pairs: Vec<(&str, String)>| -> String {
            let body: Vec<String> = pairs.iter().map(|(k, v)| format!("    \"{k}\": {v}")).collect();
            format!("{{\n{}\n  }}", body.join(",\n"))
        };
        let mut tables = vec!["  \"ross_version\": \"2.3.0\"".to_string()];
        for i in 0..elements {
            let mut e = element(i);
            e.push(("material", object(material(i))));
            tables.push(format!("  \"ShaftElement_Shaft Element {i}\": {}", object(e)));
        }
        for (tag, n) in bearings {
            tables.push(format!("  \"BearingElement_{tag}\": {}", object(bearing(tag, n))));
        }
        return format!("{{\n{}\n}}\n", tables.join(",\n"));
    }
    // TOML as ROSS writes it: a table per element, the materials' tables after them.
    let table = |header: String, pairs: Vec<(&str, String)>| -> String {
        let body: String = pairs.iter().map(|(k, v)| format!("{k} = {v}\n")).collect();
        format!("{header}\n{body}\n")
    };
    let mut text = String::from("ross_version = \"2.3.0\"\n\n");
    for i in 0..elements {
        text.push_str(&table(format!("[\"ShaftElement_Shaft Element {i}\"]"), element(i)));
    }
    for (tag, n) in bearings {
        text.push_str(&table(format!("[\"BearingElement_{tag}\"]"), bearing(tag, n)));
    }
    for i in 0..elements {
        text.push_str(&table(format!("[\"ShaftElement_Shaft Element {i}\".material]"), material(i)));
    }
    text
}

/// The Jeffcott rotor's shaft: E·I of its 0.05 m section (N·m²) and its length (m).
pub const JEFFCOTT_EI: f64 = 2.0e11 * std::f64::consts::PI * 0.05 * 0.05 * 0.05 * 0.05 / 64.0;
/// The Jeffcott rotor's span (m).
pub const JEFFCOTT_SPAN: f64 = 0.4;

/// The Jeffcott rotor's translational stiffness in one plane with bearings of `k` (N/m):
/// the shaft's mid-span 48EI/L³ (cubic beam elements reproduce a nodal load's static
/// deflection exactly) in series with the two bearings.
pub fn jeffcott_translation(k: f64) -> f64 {
    let shaft = 48.0 * JEFFCOTT_EI / JEFFCOTT_SPAN.powi(3);
    1.0 / (1.0 / shaft + 1.0 / (2.0 * k))
}

/// Its tilting stiffness (N·m/rad) in one plane: the shaft's 12EI/L under a moment at the
/// middle (by antisymmetry each half is a simply supported beam of L/2 under half the
/// moment at its end, θ = (M/2)(L/2)/(3EI); exact for cubic elements) in series with the
/// bearings' k·L²/2 against a rigid rotation about the middle (reactions ±M/L).
pub fn jeffcott_tilt(k: f64) -> f64 {
    let shaft = 12.0 * JEFFCOTT_EI / JEFFCOTT_SPAN;
    1.0 / (1.0 / shaft + 1.0 / (k * JEFFCOTT_SPAN * JEFFCOTT_SPAN / 2.0))
}

/// `rotorshunt check FILE` exits 2 and prints one `error:` line per expected (key, line),
/// in the file's order: every error of the file listed at once.
pub fn check_lists_errors(path: &std::path::Path, expected: &[(&str, usize)]) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_rotorshunt")).arg("check").arg(path).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    let lines: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error: ")).collect();
    assert_eq!(lines.len(), expected.len(), "{stderr}");
    for ((k, l), line) in expected.iter().zip(&lines) {
        assert!(line.contains(&format!("line {l}: key `{k}`")), "{line}");
    }
}

/// The problem files at the top of problems/ (no subfolders), by file name, sorted.
pub fn problem_names() -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(root().join("problems"))
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".toml"))
        .collect();
    names.sort();
    names
}
