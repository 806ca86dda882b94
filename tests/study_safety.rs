//! A study owns only what it writes: a user's files under its `--out` folder survive a
//! killed and resumed run byte for byte, a second study on the same folder is refused
//! while the first completes, case names never leave their folders, inputs inside the
//! output folder and read-only outputs are never replaced, and an oversized sweep is
//! refused at once.

use crate::common;

use serde_json::Value;
use std::collections::{BTreeMap, BTreeSet};
use std::os::unix::fs::PermissionsExt;
use std::os::unix::process::ExitStatusExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_rotorshunt"));
    c.env("RAYON_NUM_THREADS", "2");
    c
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rotorshunt-safety-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A study of quick regions cases on the coarse model; `cases` is TOML for `[[cases]]` and
/// `[sweep]`.
fn write_study(dir: &Path, name: &str, cases: &str) -> PathBuf {
    common::coarse_study(dir, name, cases)
}

fn study(study: &Path, out: &Path, extra: &[&str]) -> Output {
    bin().arg("study").arg(study).arg("--out").arg(out).args(extra).output().unwrap()
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// Every entry below `dir` (relative), with the bytes and mode of files and the mode of
/// folders.
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, (Option<Vec<u8>>, u32)> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            let meta = std::fs::symlink_metadata(&p).unwrap();
            let mode = meta.permissions().mode() & 0o7777;
            let rel = p.strip_prefix(dir).unwrap().to_path_buf();
            if meta.is_dir() {
                stack.push(p.clone());
                out.insert(rel, (None, mode));
            } else {
                out.insert(rel, (Some(std::fs::read(&p).unwrap()), mode));
            }
        }
    }
    out
}

/// (N, R, S, F) of the line `study: N cases (R run, S skipped as finished, F failed)`.
fn counts(stdout: &str) -> (usize, usize, usize, usize) {
    let line = stdout.lines().find(|l| l.starts_with("study: ")).unwrap_or_else(|| panic!("no summary: {stdout}"));
    let n: Vec<usize> = line.split(|c: char| !c.is_ascii_digit()).filter_map(|w| w.parse().ok()).take(4).collect();
    (n[0], n[1], n[2], n[3])
}

/// The rows of `summary.json`: (name, folder) in order.
fn summary_rows(out: &Path) -> Vec<(String, String)> {
    let v: Value = serde_json::from_str(&std::fs::read_to_string(out.join("summary/summary.json")).unwrap()).unwrap();
    v["cases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| (c["name"].as_str().unwrap().to_string(), c["slug"].as_str().unwrap().to_string()))
        .collect()
}

/// Every row of the summary has its own folder under `cases/` whose result.json is that
/// case's and succeeded, and `cases/` holds nothing else.
fn assert_every_case_finished(out: &Path, expected: &[String]) {
    let rows = summary_rows(out);
    let names: Vec<&String> = rows.iter().map(|(n, _)| n).collect();
    assert_eq!(names, expected.iter().collect::<Vec<_>>(), "the summary lists exactly the study's cases");
    let folders: BTreeSet<String> =
        std::fs::read_dir(out.join("cases")).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    assert_eq!(folders, rows.iter().map(|(_, s)| s.clone()).collect::<BTreeSet<_>>(), "one folder per case");
    for (name, folder) in &rows {
        let r: Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("cases").join(folder).join("result.json")).unwrap())
                .unwrap();
        assert_eq!(r["name"], name.as_str());
        assert_eq!(r["status"], "ok", "{r}");
    }
}

/// The names of a sweep over these keys (sorted) and values, the last key fastest.
fn sweep_names(keys: &[(&str, &[&str])]) -> Vec<String> {
    let mut names = vec![String::new()];
    for (k, values) in keys {
        names = names
            .iter()
            .flat_map(|n| {
                values.iter().map(move |v| if n.is_empty() { format!("{k}={v}") } else { format!("{n},{k}={v}") })
            })
            .collect();
    }
    names
}

const SWEEP_12: &str = r#"[sweep]
speed = [1000.0, 2000.0, 3000.0]
"circuit.branches[0].resistance" = [0.0, 10.0, 50.0, 100.0]
"#;

fn sweep_12_names() -> Vec<String> {
    sweep_names(&[
        ("circuit.branches[0].resistance", &["0.0", "10.0", "50.0", "100.0"]),
        ("speed", &["1000.0", "2000.0", "3000.0"]),
    ])
}

/// Plant a user's files, old-style temporaries among them, under `home`.
fn plant(home: &Path) {
    let files: [(&str, &str, u32); 7] = [
        (".notes.tmp2024", "hidden notes, named like the old temporaries", 0o600),
        ("projects/deep/er/.index.tmp7", "a deep index", 0o644),
        (".cache/.db.tmp99", "a cache database", 0o640),
        ("notes.txt", "plain notes", 0o644),
        (".cache/nested/blob", "nested in .cache", 0o444),
        (".rotorshunt-tmp.notes.txt.1.2", "named like a new temporary, of a file the study never writes", 0o644),
        ("projects/.rotorshunt-tmp.summary.json.1.2", "named like a study temporary, outside the study", 0o644),
    ];
    for (path, content, mode) in files {
        let p = home.join(path);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(&p, content).unwrap();
        std::fs::set_permissions(&p, std::fs::Permissions::from_mode(mode)).unwrap();
    }
    std::fs::create_dir_all(home.join(".cache/empty")).unwrap();
}

/// Start the study, kill it (SIGKILL) as soon as its first case has finished; whether it
/// died of the signal (not if it ended first).
fn kill_after_first_case(study: &Path, out: &Path) -> bool {
    let mut child = bin()
        .arg("study")
        .arg(study)
        .arg("--out")
        .arg(out)
        .arg("--allow-non-empty")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let hang_deadline = Instant::now() + Duration::from_secs(120);
    loop {
        if child.try_wait().unwrap().is_some() {
            return false;
        }
        let done = std::fs::read_dir(out.join("cases"))
            .map(|d| d.filter_map(|e| e.ok()).any(|e| e.path().join("result.json").exists()))
            .unwrap_or(false);
        if done || Instant::now() > hang_deadline {
            break;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    child.kill().unwrap();
    child.wait().unwrap().signal() == Some(9)
}

#[test]
fn planted_files_survive_a_killed_and_resumed_study() {
    let dir = scratch("decoys");
    let study_file = write_study(&dir, "study.toml", SWEEP_12);
    let home = dir.join("home");
    plant(&home);
    let planted = snapshot(&home);

    // Without --allow-non-empty the folder is refused and nothing in it changes.
    let o = study(&study_file, &home, &[]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    let stderr = text(&o.stderr);
    assert!(stderr.contains("holds 5 entries this study did not create"), "{stderr}");
    assert!(stderr.contains("--allow-non-empty"), "{stderr}");
    assert_eq!(snapshot(&home), planted, "a refused study touches nothing");

    // Killed mid-run, then resumed.
    let mut attempts = 0;
    while !kill_after_first_case(&study_file, &home) {
        attempts += 1;
        assert!(attempts < 3, "the study ended before it could be killed, {attempts} times");
        // Start again from the planted files alone.
        for entry in [".rotorshunt-study.json", ".rotorshunt-study.lock", "cases", "summary"] {
            let p = home.join(entry);
            if p.is_dir() {
                std::fs::remove_dir_all(&p).unwrap();
            } else if p.exists() {
                std::fs::remove_file(&p).unwrap();
            }
        }
    }
    let after_kill = snapshot(&home);
    for (p, v) in &planted {
        assert_eq!(after_kill.get(p), Some(v), "{} changed by the killed run", p.display());
    }
    let o = study(&study_file, &home, &["--allow-non-empty"]);
    let stdout = text(&o.stdout);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let (n, run, skipped, failed) = counts(&stdout);
    eprintln!("resumed: {stdout}");
    assert_eq!((n, failed), (12, 0), "{stdout}");
    assert_eq!(run + skipped, n);
    assert!(skipped >= 1, "the case finished before the kill is skipped: {stdout}");
    assert!(stdout.contains("took over the lock of an earlier run"), "{stdout}");

    let end = snapshot(&home);
    for (p, v) in &planted {
        assert_eq!(end.get(p), Some(v), "{} changed", p.display());
    }
    // Beside the planted entries: the study's own, and no lock or temporary.
    let top: BTreeSet<String> =
        std::fs::read_dir(&home).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    let mut expected: BTreeSet<String> =
        [".notes.tmp2024", "projects", ".cache", "notes.txt", ".rotorshunt-tmp.notes.txt.1.2"].map(String::from).into();
    expected.extend([".rotorshunt-study.json", "cases", "summary"].map(String::from));
    assert_eq!(top, expected);
    let manifest: Value =
        serde_json::from_str(&std::fs::read_to_string(home.join(".rotorshunt-study.json")).unwrap()).unwrap();
    assert_eq!(manifest["created"], serde_json::json!(["cases", "summary"]));
    assert_every_case_finished(&home, &sweep_12_names());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_second_study_on_the_same_folder_is_refused_and_the_first_completes() {
    let dir = scratch("concurrent");
    let a = write_study(&dir, "a.toml", SWEEP_12);
    let b = write_study(
        &dir,
        "b.toml",
        "[[cases]]\nname = \"b-low\"\nset = [\"speed=500.0\"]\n[[cases]]\nname = \"b-high\"\nset = [\"speed=2500.0\"]\n",
    );
    let names_a = sweep_12_names();
    let names_b = vec!["b-low".to_string(), "b-high".to_string()];
    let trials = 5;
    let mut outcomes = BTreeMap::new();
    for trial in 0..trials {
        let out = dir.join(format!("out-{trial}"));
        // Alternate which one starts first.
        let (first, second) = if trial % 2 == 0 { (&a, &b) } else { (&b, &a) };
        let spawn = |s: &Path| {
            bin()
                .arg("study")
                .arg(s)
                .arg("--out")
                .arg(&out)
                .stdout(Stdio::piped())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap()
        };
        let c1 = spawn(first);
        let c2 = spawn(second);
        let (o1, o2) = (c1.wait_with_output().unwrap(), c2.wait_with_output().unwrap());
        let codes = (o1.status.code(), o2.status.code());
        let (winner, loser, lost) = match codes {
            (Some(0), Some(2)) => (first, &o2, second),
            (Some(2), Some(0)) => (second, &o1, first),
            _ => panic!("trial {trial}: exit codes {codes:?}: {} / {}", text(&o1.stderr), text(&o2.stderr)),
        };
        let why = text(&loser.stderr);
        let kind = if why.contains("is in use by another study run") {
            "locked"
        } else if why.contains("belongs to the study") {
            "other study"
        } else {
            panic!("trial {trial}: {why}")
        };
        assert!(why.contains(&out.display().to_string()), "{why}");
        eprintln!(
            "trial {trial}: {} won, {} refused ({kind})",
            winner.file_name().unwrap().to_string_lossy(),
            lost.file_name().unwrap().to_string_lossy()
        );
        *outcomes.entry(kind).or_insert(0) += 1;
        assert_every_case_finished(&out, if winner == &a { &names_a } else { &names_b });
        assert!(!out.join(".rotorshunt-study.lock").exists(), "the lock is removed at the end");
    }
    eprintln!("refusals over {trials} trials: {outcomes:?}");

    // The same study twice at once: one runs, the other is refused or, started after the
    // first ended, resumes with every case skipped.
    for trial in 0..3 {
        let out = dir.join(format!("same-{trial}"));
        let spawn = || {
            bin()
                .arg("study")
                .arg(&a)
                .arg("--out")
                .arg(&out)
                .stdout(Stdio::piped())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap()
        };
        let (c1, c2) = (spawn(), spawn());
        let outs = [c1.wait_with_output().unwrap(), c2.wait_with_output().unwrap()];
        let ok: Vec<&Output> = outs.iter().filter(|o| o.status.success()).collect();
        assert!(!ok.is_empty(), "{} / {}", text(&outs[0].stderr), text(&outs[1].stderr));
        for o in outs.iter().filter(|o| !o.status.success()) {
            assert_eq!(o.status.code(), Some(2));
            assert!(text(&o.stderr).contains("is in use by another study run"), "{}", text(&o.stderr));
        }
        if ok.len() == 2 {
            let runs: Vec<usize> = ok.iter().map(|o| counts(&text(&o.stdout)).1).collect();
            assert!(runs.contains(&0), "two runs both computed cases: {runs:?}");
        }
        assert_every_case_finished(&out, &names_a);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn case_names_stay_inside_their_own_folders() {
    let dir = scratch("names");
    let long = "x".repeat(300);
    let names = ["..", ".", "", "a/b", "a\\b", "a_b", "a b", "../escape", "/etc/escape", ".hidden", "Mixed", &long];
    let mut cases = String::new();
    for n in names {
        cases += &format!("[[cases]]\nname = {}\n", Value::String(n.to_string()));
    }
    let study_file = write_study(&dir, "study.toml", &cases);
    let out = dir.join("out");
    let o = study(&study_file, &out, &[]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(!out.join("result.json").exists() && !out.join("cases/result.json").exists());
    let beside: BTreeSet<String> =
        std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    assert_eq!(beside, ["out", "study.toml"].map(String::from).into(), "nothing written beside --out");
    assert_every_case_finished(&out, &names.map(String::from));
    for (_, folder) in summary_rows(&out) {
        assert!(!folder.starts_with('.') && folder.len() <= 100, "{folder}");
        assert!(folder.bytes().all(|b| b.is_ascii_alphanumeric() || b"-_.=,".contains(&b)), "{folder}");
    }
    // A re-run skips every one of them: no two share a folder.
    let again = study(&study_file, &out, &[]);
    assert_eq!(counts(&text(&again.stdout)), (names.len(), 0, names.len(), 0), "{}", text(&again.stdout));

    // Folder names are compared ignoring case, and a repeated sweep value is a repeated name.
    for (cases, what) in [
        ("[[cases]]\nname = \"Run\"\n[[cases]]\nname = \"run\"\n", "cases `Run` and `run` would share the folder"),
        ("[sweep]\nspeed = [1000.0, 1000.0]\n", "two cases are named `speed=1000.0`"),
    ] {
        let s = write_study(&dir, "dup.toml", cases);
        let out = dir.join("dup");
        let o = study(&s, &out, &[]);
        assert_eq!(o.status.code(), Some(2));
        assert!(text(&o.stderr).contains(what), "{}", text(&o.stderr));
        assert!(!out.exists(), "a refused study creates nothing");
    }
    // Sweep values differing only in case get their own folders.
    let s = write_study(&dir, "cased.toml", "[sweep]\ntitle = [\"A\", \"a\"]\n");
    let out = dir.join("cased");
    let o = study(&s, &out, &[]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert_every_case_finished(&out, &["title=\"A\"".to_string(), "title=\"a\"".to_string()]);
    let lower: BTreeSet<String> = summary_rows(&out).into_iter().map(|(_, f)| f.to_ascii_lowercase()).collect();
    assert_eq!(lower.len(), 2);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_changed_plan_resumes_into_its_own_folder() {
    let dir = scratch("changed");
    let two =
        "[[cases]]\nname = \"low\"\nset = [\"speed=500.0\"]\n[[cases]]\nname = \"high\"\nset = [\"speed=2500.0\"]\n";
    let study_file = write_study(&dir, "study.toml", two);
    let out = dir.join("out");
    assert!(study(&study_file, &out, &[]).status.success());
    write_study(&dir, "study.toml", &format!("{two}[[cases]]\nname = \"mid\"\nset = [\"speed=1500.0\"]\n"));
    let o = study(&study_file, &out, &[]);
    let stdout = text(&o.stdout);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert_eq!(counts(&stdout), (3, 1, 2, 0), "{stdout}");
    assert!(stdout.contains("the plan changed"), "{stdout}");
    assert_every_case_finished(&out, &["low", "high", "mid"].map(String::from));
    // A case dropped from the plan keeps its folder but leaves the summary.
    write_study(&dir, "study.toml", "[[cases]]\nname = \"high\"\nset = [\"speed=2500.0\"]\n");
    let o = study(&study_file, &out, &[]);
    assert_eq!(counts(&text(&o.stdout)), (1, 0, 1, 0), "{}", text(&o.stdout));
    assert_eq!(summary_rows(&out).len(), 1);
    assert!(out.join("cases/low/result.json").exists());
    // Another study file with another plan is refused.
    let other = write_study(&dir, "other.toml", "[[cases]]\nname = \"z\"\n");
    let o = study(&other, &out, &["--allow-non-empty", "--force"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o.stderr)
            .contains(&format!("belongs to the study {}", std::fs::canonicalize(&study_file).unwrap().display())),
        "{}",
        text(&o.stderr)
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn inputs_inside_the_output_folder_are_never_overwritten() {
    let dir = scratch("inputs");
    let problem = common::problem_path("paper-open.toml");
    let o7 = dir.join("o7");
    std::fs::create_dir_all(o7.join("summary")).unwrap();
    // A study whose base is the summary.md of its --out folder.
    std::fs::copy(&problem, o7.join("summary/summary.md")).unwrap();
    let s = dir.join("study.toml");
    std::fs::write(&s, "base = \"o7/summary/summary.md\"\nphi = [1000.0, 1100.0]\n[[cases]]\nname = \"one\"\n")
        .unwrap();
    let before = snapshot(&o7);
    for extra in [&[][..], &["--allow-non-empty"][..], &["--allow-non-empty", "--force"][..]] {
        let o = study(&s, &o7, extra);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {}", text(&o.stderr));
        let e = text(&o.stderr);
        assert!(e.contains("summary.md: it is the study's base problem file of this run"), "{e}");
        assert_eq!(snapshot(&o7), before, "{extra:?}");
    }
    // chart --compare o7/compare.json --out o7.
    std::fs::copy(&problem, o7.join("compare.json")).unwrap();
    let before = snapshot(&o7);
    let chart = |extra: &[&str]| {
        bin().args(["chart", &problem, "--phi", "500", "--beta", "0.1", "--out"]).arg(&o7).args(extra).output().unwrap()
    };
    let compare = o7.join("compare.json");
    let o = chart(&["--compare", compare.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("compare.json: it is the --compare file of this run"), "{}", text(&o.stderr));
    assert_eq!(snapshot(&o7), before, "nothing written, the compare file byte-identical");
    // An output that is a link to an input.
    std::os::unix::fs::symlink(&problem, o7.join("growth.png")).unwrap();
    let o = chart(&[]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("growth.png: it is the input problem file of this run"), "{}", text(&o.stderr));
    assert!(std::fs::symlink_metadata(o7.join("growth.png")).unwrap().file_type().is_symlink());
    assert!(!o7.join("chart.json").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_read_only_output_is_an_error_and_left_as_it_is() {
    let dir = scratch("readonly");
    let out = dir.join("design");
    std::fs::create_dir_all(&out).unwrap();
    let tuned = out.join("tuned.toml");
    std::fs::write(&tuned, "# the user's tuned circuit\n").unwrap();
    std::fs::set_permissions(&tuned, std::fs::Permissions::from_mode(0o444)).unwrap();
    let o = bin()
        .args(["design", &common::problem_path("design-widest-band.toml")])
        .args(common::COARSE_MODEL_ARGS)
        .args(["--set", "design.starts=1", "--set", "design.max_iterations=3"])
        .args(["--set", "design.phi_range=[1000.0, 1500.0]", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1), "{}", text(&o.stderr));
    let e = text(&o.stderr);
    assert!(e.contains(&format!("cannot write {}: the file is read-only (mode 444)", tuned.display())), "{e}");
    assert_eq!(std::fs::read(&tuned).unwrap(), b"# the user's tuned circuit\n");
    assert_eq!(std::fs::metadata(&tuned).unwrap().permissions().mode() & 0o777, 0o444);
    std::fs::set_permissions(&tuned, std::fs::Permissions::from_mode(0o644)).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn an_oversized_sweep_is_refused_at_once() {
    let dir = scratch("oversized");
    let mut sweep = String::from("[sweep]\n");
    for k in
        ["speed", "load.alpha", "ring.eta", "ring.k_b", "ring.m_b", "disks[0].mass", "shaft.radius", "shaft.length"]
    {
        let values: Vec<String> = (1..=10).map(|i| format!("{}.0", i)).collect();
        sweep += &format!("\"{k}\" = [{}]\n", values.join(", "));
    }
    let s = write_study(&dir, "study.toml", &sweep);
    let out = dir.join("out");
    let t = Instant::now();
    let o = study(&s, &out, &[]);
    let seconds = t.elapsed().as_secs_f64();
    eprintln!("8 keys x 10 values refused in {seconds:.3} s");
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    let e = text(&o.stderr);
    assert!(e.contains("the plan has 100000000 cases, more than the limit of 1000000"), "{e}");
    assert!(!out.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}
