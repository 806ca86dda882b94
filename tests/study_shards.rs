//! Shards of a study (issue 19): the shards of the sweep of
//! `problems/studies/resistance-speed.toml` (on a coarse model) for N = 1, 2, 3, 7 are
//! disjoint, cover the plan and merge to the unsharded summary; a
//! planted cost imbalance is spread; a killed task and a "lost node" are recovered by
//! rerunning what `study status` prints, with every result equal to a fresh run's; two
//! tasks given one shard run each case once; bad shards and folders are refused without
//! touching a file; a 10 000-case plan, its dry run, status and merge list every case.

use crate::common;

use serde_json::Value;
use std::collections::{BTreeMap, BTreeSet};
use std::os::unix::process::ExitStatusExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_rotorshunt"));
    c.env("RAYON_NUM_THREADS", "2").env_remove("SLURM_ARRAY_TASK_ID").env_remove("SLURM_CPUS_PER_TASK");
    c
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rotorshunt-shards-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

fn run(args: &[&str], out: Option<&Path>) -> Output {
    let mut c = bin();
    c.args(args);
    if let Some(o) = out {
        c.arg("--out").arg(o);
    }
    c.output().unwrap()
}

fn ok(o: &Output) -> String {
    assert!(o.status.success(), "exit {:?}: {}{}", o.status.code(), text(&o.stdout), text(&o.stderr));
    text(&o.stdout)
}

/// A study of quick regions cases on a coarse model; `cases` is TOML for `[[cases]]` and
/// `[sweep]`.
fn quick_study(dir: &Path, name: &str, cases: &str) -> PathBuf {
    let study = dir.join(name);
    std::fs::write(
        &study,
        format!(
            "base = \"{}\"\nphi = [1150.0, 1350.0]\nbeta_max = 0.5\nlevel = 0.3\nphi_op = 1230.0\nset = [\"shaft.elements=8\", \"disks[0].node=2\", \"analysis.reduced_modes=4\", \"design.refined_check=false\"]\n\n{cases}\n",
            common::problem_path("design-widest-band.toml")
        ),
    )
    .unwrap();
    study
}

const SWEEP_12: &str =
    "[sweep]\nspeed = [1000.0, 2000.0, 3000.0]\n\"circuit.branches[0].resistance\" = [0.0, 10.0, 50.0, 100.0]\n";

/// The plan as `study plan --shards N --json` gives it: (index, kind, shard, name).
fn plan(study: &str, shards: u32) -> Vec<(u64, String, u32, String)> {
    plan_json(study, Some(shards))["list"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            (
                c["index"].as_u64().unwrap(),
                c["kind"].as_str().unwrap().to_string(),
                c["shard"].as_u64().unwrap() as u32,
                c["name"].as_str().unwrap().to_string(),
            )
        })
        .collect()
}

/// summary.json without what differs between runs: wall times and the task.
fn summary(out: &Path) -> Value {
    let mut v: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary/summary.json")).unwrap()).unwrap();
    for c in v["cases"].as_array_mut().unwrap() {
        c["seconds"] = Value::Null;
        c["task"] = Value::Null;
    }
    v
}

/// summary.csv without its `seconds` column.
fn summary_csv(out: &Path) -> Vec<Vec<String>> {
    let mut r = csv::Reader::from_path(out.join("summary/summary.csv")).unwrap();
    let header: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    let skip = header.iter().position(|h| h == "seconds").unwrap();
    let mut rows = vec![header.clone()];
    for rec in r.records() {
        rows.push(rec.unwrap().iter().enumerate().filter(|(i, _)| *i != skip).map(|(_, s)| s.to_string()).collect());
    }
    rows[0].remove(skip);
    rows
}

/// `study plan --json`: the plan's hash and its cases (index, id, folder, name, kind,
/// overrides, input hash; with `shards`, its shard).
fn plan_json(study: &str, shards: Option<u32>) -> Value {
    let shards = shards.map(|n| n.to_string());
    let mut args = vec!["study", "plan", study, "--json"];
    if let Some(n) = &shards {
        args.extend(["--shards", n]);
    }
    serde_json::from_str(&ok(&run(&args, None))).unwrap()
}

/// Sorted task numbers written as Slurm's `--array` syntax reads them, runs of
/// consecutive numbers as `A-B` (`sbatch(1)`): `[0, 2, 3, 4]` is `0,2-4`.
fn slurm_list(numbers: &[u32]) -> String {
    let mut runs: Vec<(u32, u32)> = Vec::new();
    for &n in numbers {
        match runs.last_mut() {
            Some((_, end)) if *end + 1 == n => *end = n,
            _ => runs.push((n, n)),
        }
    }
    runs.iter().map(|(a, b)| if a == b { a.to_string() } else { format!("{a}-{b}") }).collect::<Vec<_>>().join(",")
}

/// The unsharded run of a study into `out` (the reference).
fn reference(study: &str, out: &Path) {
    ok(&run(&["study", study], Some(out)));
}

#[test]
fn shards_are_disjoint_cover_the_plan_and_merge_to_the_unsharded_summary() {
    let dir = scratch("cover");
    // The bundled study's sweep (3 speeds x 4 resistances) on the coarse model: what is
    // checked is the split and the merge, not the cases' physics (tests/slurm.rs runs the
    // bundled study itself).
    let study = quick_study(&dir, "study.toml", SWEEP_12).display().to_string();
    let whole = dir.join("whole");
    reference(&study, &whole);
    let names: Vec<String> = plan(&study, 1).into_iter().map(|c| c.3).collect();
    assert_eq!(names.len(), 12);
    let cases = plan_json(&study, None)["list"].clone();
    for n in [1u32, 2, 3, 7] {
        let p = plan(&study, n);
        // Disjoint and covering: every case in exactly one shard, every shard non-empty.
        let mut per: BTreeMap<u32, Vec<u64>> = BTreeMap::new();
        for (i, _, s, _) in &p {
            assert!(*s < n);
            per.entry(*s).or_default().push(*i);
        }
        assert_eq!(per.len(), n as usize, "N = {n}: {per:?}");
        let all: BTreeSet<u64> = per.values().flatten().copied().collect();
        assert_eq!(all, (0..12).collect(), "N = {n}");
        assert_eq!(per.values().map(Vec::len).sum::<usize>(), 12, "N = {n}: a case in two shards");
        // Equal costs: shard sizes differ by at most one.
        let sizes: Vec<usize> = per.values().map(Vec::len).collect();
        assert!(sizes.iter().max().unwrap() - sizes.iter().min().unwrap() <= 1, "N = {n}: {sizes:?}");
        let out = dir.join(format!("n{n}"));
        let mut ran = BTreeSet::new();
        for k in 0..n {
            let o = ok(&run(&["study", &study, "--shard", &format!("{k}/{n}")], Some(&out)));
            assert!(o.contains(&format!("study: shard {k}/{n} of 12 cases: {} cases (", per[&k].len())), "{o}");
            assert!(!out.join("summary/summary.json").exists(), "a shard writes no summary");
            // The run records which task ran which case.
            for i in &per[&k] {
                let folder = cases[*i as usize]["folder"].as_str().unwrap().to_string();
                let r = common::json(&out.join("cases").join(&folder).join("result.json"));
                assert_eq!(r["task"]["shard"].as_str(), Some(format!("{k}/{n}").as_str()));
                assert!(r["task"]["pid"].as_u64().unwrap() > 0);
                assert!(ran.insert(folder), "case {i} run by two shards");
            }
        }
        let m = ok(&run(&["study", "merge", out.to_str().unwrap()], None));
        eprintln!("N = {n}: {}", m.lines().next().unwrap());
        assert!(m.contains("12 cases in") && m.contains("12 done, 0 failed, 0 missing, 0 running"), "{m}");
        assert_eq!(summary(&out), summary(&whole), "N = {n}: merged summary differs from the unsharded run's");
        assert_eq!(summary_csv(&out), summary_csv(&whole), "N = {n}");
        assert_eq!(common::case_files(&out), common::case_files(&whole), "N = {n}: case files differ");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_planted_cost_imbalance_is_spread_over_the_shards() {
    let dir = scratch("imbalance");
    let mut cases = String::new();
    for (i, speed) in [(0, 2000.0), (1, 2100.0)] {
        cases += &format!("[[cases]]\nname = \"design-{i}\"\nkind = \"design\"\nset = [\"speed={speed}\"]\n");
    }
    let study = quick_study(
        &dir,
        "study.toml",
        &format!(
            "{cases}[sweep]\nspeed = [{}]\n",
            (1..=10).map(|i| format!("{}.0", 1000 + 10 * i)).collect::<Vec<_>>().join(", ")
        ),
    );
    let study = study.to_str().unwrap();
    for n in 2..=12u32 {
        let p = plan(study, n);
        assert_eq!(p.len(), 12);
        let design: Vec<u32> = p.iter().filter(|c| c.1 == "design").map(|c| c.2).collect();
        assert_eq!(design.len(), 2);
        assert_ne!(design[0], design[1], "N = {n}: both design cases in shard {}", design[0]);
        // The design shards take the fewest regions cases.
        let count = |s: u32| p.iter().filter(|c| c.2 == s).count();
        for s in 0..n {
            if !design.contains(&s) {
                assert!(count(s) >= count(design[0]).min(count(design[1])), "N = {n}: {p:?}");
            }
        }
    }
    // The same plan on every call (deterministic).
    assert_eq!(plan(study, 3), plan(study, 3));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Start shard `shard` of `study` into `out` and SIGKILL it once `ready` says so; whether
/// it died of the signal.
fn kill_when(study: &Path, out: &Path, shard: &str, ready: impl Fn() -> bool) -> bool {
    let mut child = bin()
        .arg("study")
        .arg(study)
        .arg("--out")
        .arg(out)
        .args(["--shard", shard])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let hang_deadline = Instant::now() + Duration::from_secs(120);
    while !ready() && Instant::now() < hang_deadline {
        if child.try_wait().unwrap().is_some() {
            return false;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    child.kill().unwrap();
    child.wait().unwrap().signal() == Some(9)
}

fn results_in(out: &Path) -> usize {
    std::fs::read_dir(out.join("cases"))
        .map(|d| d.filter_map(|e| e.ok()).filter(|e| e.path().join("result.json").exists()).count())
        .unwrap_or(0)
}

fn status_json(out: &Path) -> (Option<i32>, Value) {
    let o = run(&["study", "status", out.to_str().unwrap(), "--json"], None);
    (o.status.code(), serde_json::from_str(&text(&o.stdout)).unwrap_or_else(|e| panic!("{e}: {}", text(&o.stderr))))
}

#[test]
fn a_killed_task_and_a_lost_node_are_recovered_by_rerunning_what_status_prints() {
    let dir = scratch("faults");
    let study = quick_study(&dir, "study.toml", SWEEP_12);
    let whole = dir.join("whole");
    reference(study.to_str().unwrap(), &whole);
    let out = dir.join("out");
    // Shard 0/3 runs to its end; shard 1/3 is killed (SIGKILL) after its first result;
    // shard 2/3 "loses its node": killed as soon as its first case folder exists, its lock
    // then naming another host, with a temporary planted beside the case's files.
    ok(&run(&["study", study.to_str().unwrap(), "--shard", "0/3"], Some(&out)));
    let done0 = results_in(&out);
    let mut tries = 0;
    while !kill_when(&study, &out, "1/3", || results_in(&out) > done0) {
        tries += 1;
        assert!(tries < 3, "shard 1/3 ended before it could be killed");
    }
    let before2: BTreeSet<PathBuf> = std::fs::read_dir(out.join("cases")).unwrap().map(|e| e.unwrap().path()).collect();
    let new_folder = || {
        std::fs::read_dir(out.join("cases")).unwrap().map(|e| e.unwrap().path()).find(|p| {
            !before2.contains(p) && p.join(".rotorshunt-case.json").exists() && !p.join("result.json").exists()
        })
    };
    let mut tries = 0;
    while !kill_when(&study, &out, "2/3", || new_folder().is_some()) {
        tries += 1;
        assert!(tries < 3, "shard 2/3 ended before it could be killed");
    }
    if let Some(partial) = new_folder() {
        let lock = partial.join(".rotorshunt-case.lock");
        std::fs::write(&lock, "{\"pid\":4242,\"host\":\"lost-node.invalid\",\"study\":\"x\",\"started_unix_s\":0}\n")
            .unwrap();
        // A half-written manifest update of the lost task (a temporary is always of a recorded
        // entry: the study records a file before it writes it).
        std::fs::write(partial.join(".rotorshunt-tmp..rotorshunt-case.json.4242.0"), "{\"half").unwrap();
    }
    let (code, s) = status_json(&out);
    eprintln!("after the faults: {} done, {} missing, rerun --array={}", s["done"], s["missing"], s["array"]);
    assert_eq!(code, Some(5), "{s}");
    assert_eq!(s["running"], 0, "{s}");
    assert!(s["missing"].as_u64().unwrap() >= 1, "{s}");
    assert_eq!(s["done"].as_u64().unwrap() + s["missing"].as_u64().unwrap(), 12, "{s}");
    let array = s["array"].as_str().unwrap().to_string();
    let shards: Vec<String> =
        s["rerun_shards"].as_array().unwrap().iter().map(|v| v.as_str().unwrap().to_string()).collect();
    assert!(shards.contains(&"2/3".to_string()) && !shards.contains(&"0/3".to_string()), "{shards:?}");
    let numbers: Vec<u32> = shards.iter().map(|s| s.split('/').next().unwrap().parse().unwrap()).collect();
    assert_eq!(array, slurm_list(&numbers));
    // The text form prints the same rerun lists.
    let t = text(&run(&["study", "status", out.to_str().unwrap()], None).stdout);
    assert!(t.contains(&format!("rerun: --array={array}\n")), "{t}");
    assert!(
        t.contains(&format!(
            "rerun: {}\n",
            shards.iter().map(|s| format!("--shard {s}")).collect::<Vec<_>>().join(" ")
        )),
        "{t}"
    );
    for sh in &shards {
        let o = ok(&run(&["study", study.to_str().unwrap(), "--shard", sh], Some(&out)));
        assert!(o.contains("0 failed"), "{o}");
    }
    let (code, s) = status_json(&out);
    assert_eq!((code, s["done"].as_u64()), (Some(0), Some(12)), "{s}");
    ok(&run(&["study", "merge", out.to_str().unwrap()], None));
    // No result lost, duplicated or half written: every file equals the fresh run's.
    assert_eq!(common::case_files(&out), common::case_files(&whole));
    assert_eq!(summary(&out), summary(&whole));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn two_tasks_given_the_same_shard_run_each_case_once() {
    let dir = scratch("twice");
    let study = quick_study(&dir, "study.toml", SWEEP_12);
    let whole = dir.join("whole");
    reference(study.to_str().unwrap(), &whole);
    for trial in 0..2 {
        let out = dir.join(format!("out-{trial}"));
        let spawn = || {
            bin()
                .arg("study")
                .arg(&study)
                .arg("--out")
                .arg(&out)
                .args(["--shard", "0/2"])
                .stdout(Stdio::piped())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap()
        };
        let (a, b) = (spawn(), spawn());
        let outs = [a.wait_with_output().unwrap(), b.wait_with_output().unwrap()];
        let mut ran = 0;
        for o in &outs {
            let t = ok(o);
            eprintln!("trial {trial}: {}", t.lines().next().unwrap());
            let n: Vec<usize> = t.split(|c: char| !c.is_ascii_digit()).filter_map(|w| w.parse().ok()).collect();
            // "study: shard 0/2 of 12 cases: 6 cases (R run, S skipped as finished, B running in another task, F failed)"
            let (cases, r, s, busy, failed) = (n[3], n[4], n[5], n[6], n[7]);
            assert_eq!((cases, failed), (6, 0), "{t}");
            assert_eq!(r + s + busy, 6, "{t}");
            ran += r;
        }
        assert_eq!(ran, 6, "each case of the shard is computed once");
        ok(&run(&["study", study.to_str().unwrap(), "--shard", "1/2"], Some(&out)));
        ok(&run(&["study", "merge", out.to_str().unwrap()], None));
        assert_eq!(common::case_files(&out), common::case_files(&whole), "trial {trial}");
        assert_eq!(summary(&out), summary(&whole), "trial {trial}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Every entry below `dir` with its bytes (files) or nothing (folders); empty if absent.
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Option<Vec<u8>>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else { continue };
        for e in entries {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p.clone());
                out.insert(p, None);
            } else {
                out.insert(p.clone(), Some(std::fs::read(&p).unwrap()));
            }
        }
    }
    out
}

#[test]
fn bad_shards_and_folders_are_refused_without_touching_a_file() {
    let dir = scratch("bad");
    let study = quick_study(&dir, "study.toml", SWEEP_12);
    let s = study.to_str().unwrap();
    let fresh = dir.join("fresh");
    let refused = |args: &[&str], env: &[(&str, &str)], out: &Path, what: &str| {
        let before = snapshot(&dir);
        let mut c = bin();
        c.args(args);
        for (k, v) in env {
            c.env(k, v);
        }
        let t = Instant::now();
        let o = c.output().unwrap();
        let e = text(&o.stderr);
        eprintln!("{args:?} {env:?}: {} ({:.2} s)", e.trim(), t.elapsed().as_secs_f64());
        assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
        assert!(e.starts_with("error: ") && e.contains(what), "{args:?}: {e}");
        assert_eq!(e.lines().count(), 1, "one paragraph: {e}");
        assert_eq!(snapshot(&dir), before, "{args:?} touched a file");
        assert!(out != fresh || !out.exists(), "{} created", out.display());
    };
    let f = fresh.to_str().unwrap();
    refused(
        &["study", s, "--out", f, "--shard", "0/0"],
        &[],
        &fresh,
        "--shard 0/0: the number of shards must be at least 1",
    );
    refused(&["study", s, "--out", f, "--shard", "5/4"], &[], &fresh, "--shard 5/4: shard 5 of 4 does not exist");
    refused(&["study", s, "--out", f, "--shard", "4/4"], &[], &fresh, "shards are numbered 0 to 3 (0-based)");
    refused(&["study", s, "--out", f, "--shard", "0/13"], &[], &fresh, "more shards than the plan's 12 cases");
    refused(
        &["study", s, "--out", f, "--shards", "4"],
        &[("SLURM_ARRAY_TASK_ID", "abc")],
        &fresh,
        "SLURM_ARRAY_TASK_ID abc: not a shard number",
    );
    refused(
        &["study", s, "--out", f, "--shards", "4"],
        &[("SLURM_ARRAY_TASK_ID", "4")],
        &fresh,
        "SLURM_ARRAY_TASK_ID 4: shard 4 of 4 does not exist",
    );
    refused(&["study", s, "--out", f, "--shards", "4"], &[], &fresh, "which is not set");
    refused(&["study", s, "--out", f], &[("SLURM_ARRAY_TASK_ID", "1")], &fresh, "records no shard count");
    refused(
        &["study", "slurm", s, "--out", f, "--tasks", "4", "--submit", "--sbatch", "/nonexistent/sbatch"],
        &[],
        &fresh,
        "cannot submit: the program `/nonexistent/sbatch` is not an executable file",
    );
    refused(&["study", "slurm", s, "--out", f, "--tasks", "0"], &[], &fresh, "--tasks 0");
    {
        let before = snapshot(&dir);
        let o = bin()
            .args(["study", "slurm", s, "--out", f, "--tasks", "4", "--submit"])
            .env("PATH", "/nonexistent")
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2));
        assert!(
            text(&o.stderr).contains("cannot submit: the program `sbatch` is not found in PATH"),
            "{}",
            text(&o.stderr)
        );
        assert_eq!(snapshot(&dir), before);
    }
    // A folder holding another plan's results: refused for a shard, for status's counts it
    // is the study file as it is now.
    let other = dir.join("other");
    let two =
        quick_study(&dir, "two.toml", "[[cases]]\nname = \"a\"\n[[cases]]\nname = \"b\"\nset = [\"speed=2500.0\"]\n");
    ok(&run(&["study", two.to_str().unwrap()], Some(&other)));
    let o = other.to_str().unwrap();
    refused(&["study", s, "--out", o, "--shard", "0/2"], &[], &other, "holds results of another plan (plan ");
    refused(&["study", "slurm", s, "--out", o, "--tasks", "2"], &[], &other, "holds results of another plan");
    // The same study file, edited: a shard is refused, and status and merge count against the
    // file as it is now, ignoring the old results with a warning.
    quick_study(&dir, "two.toml", "[[cases]]\nname = \"a\"\n[[cases]]\nname = \"c\"\nset = [\"speed=2600.0\"]\n");
    refused(
        &["study", two.to_str().unwrap(), "--out", o, "--shard", "0/2"],
        &[],
        &other,
        "holds results of another plan",
    );
    let st = run(&["study", "status", o], None);
    let t = text(&st.stdout);
    assert_eq!(st.status.code(), Some(5), "{t}");
    assert!(t.contains("2 cases in 1 shard: 1 done, 0 failed, 1 missing, 0 running"), "{t}");
    assert!(t.contains("warning: the study file") && t.contains("no longer gives the folder's plan"), "{t}");
    assert!(t.contains("warning: 1 folders not in the plan (cases/b)"), "{t}");
    let m = run(&["study", "merge", o], None);
    let mt = text(&m.stdout);
    assert!(mt.contains("(1 cases)") && mt.contains("cases/b"), "{mt}");
    let rows: Value =
        serde_json::from_str(&std::fs::read_to_string(other.join("summary/summary.json")).unwrap()).unwrap();
    assert_eq!(rows["cases"].as_array().unwrap().len(), 1, "the case no longer in the plan is not merged");
    // status and merge on a folder that is not a study's.
    for cmd in ["status", "merge"] {
        refused(
            &["study", cmd, dir.join("no-study").to_str().unwrap()],
            &[],
            &dir.join("no-study"),
            "is not a study folder",
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_10000_case_plan_and_its_status_list_every_case() {
    let dir = scratch("scale");
    let values = |n: usize, base: f64| (0..n).map(|i| format!("{:.1}", base + i as f64)).collect::<Vec<_>>().join(", ");
    let study = quick_study(
        &dir,
        "study.toml",
        &format!(
            "[sweep]\nspeed = [{}]\n\"circuit.branches[0].resistance\" = [{}]\n",
            values(100, 1000.0),
            values(100, 0.0)
        ),
    );
    let out = dir.join("out");
    let t = Instant::now();
    let o = run(&["study", study.to_str().unwrap(), "--shard", "6/7", "--dry-run"], Some(&out));
    let dry = t.elapsed().as_secs_f64();
    let listing = ok(&o);
    assert!(
        listing.contains("# dry run: shard 6/7, 1428 of the 10000 cases; nothing is written"),
        "{}",
        &listing[..600]
    );
    assert_eq!(listing.lines().filter(|l| l.as_bytes().first().is_some_and(u8::is_ascii_digit)).count(), 1428);
    assert!(!out.exists(), "a dry run writes nothing");
    let t = Instant::now();
    let all = ok(&run(&["study", "plan", study.to_str().unwrap(), "--shards", "7"], None));
    let plan_seconds = t.elapsed().as_secs_f64();
    assert_eq!(all.lines().count(), 4 + 10_000);
    // Printed, not asserted: durations belong to benches (the listing's counts are above).
    eprintln!("10 000-case plan: --dry-run of one shard {dry:.3} s, `study plan --shards 7` {plan_seconds:.3} s");

    // A folder of 10 000 finished results, as the study writes them.
    let listed = plan_json(study.to_str().unwrap(), None);
    let (cases, plan_hash) = (listed["list"].as_array().unwrap(), listed["plan_sha256"].as_str().unwrap());
    let canonical = std::fs::canonicalize(&study).unwrap().display().to_string();
    std::fs::create_dir_all(out.join("cases")).unwrap();
    // The records as docs/studies.md describes them: the folder's manifest, each case
    // folder's manifest and its result.
    let tool = format!("rotorshunt {}", env!("CARGO_PKG_VERSION"));
    let study_manifest = serde_json::json!({
        "format": 1, "role": "study", "tool": tool, "study": canonical, "plan_sha256": plan_hash,
        "cases": 10_000, "shards": 7, "created": ["cases"], "temporaries": "",
    });
    std::fs::write(out.join(".rotorshunt-study.json"), study_manifest.to_string()).unwrap();
    let t = Instant::now();
    for c in cases {
        let d = out.join("cases").join(c["folder"].as_str().unwrap());
        std::fs::create_dir(&d).unwrap();
        let manifest = serde_json::json!({
            "format": 1, "role": "case", "tool": tool, "study": canonical, "case": c["name"],
            "created": ["result.json"], "temporaries": "",
        });
        std::fs::write(d.join(".rotorshunt-case.json"), manifest.to_string()).unwrap();
        let r = serde_json::json!({
            "name": c["name"], "id": c["id"], "slug": c["folder"], "kind": c["kind"], "overrides": c["overrides"],
            "input_hash": c["input_hash"], "status": "ok", "error": null, "metrics": {"regions": 3},
            "seconds": 0.5, "task": {"host": "", "pid": 0}, "tool": tool,
        });
        std::fs::write(d.join("result.json"), serde_json::to_string_pretty(&r).unwrap()).unwrap();
    }
    eprintln!("wrote 10 000 results in {:.2} s", t.elapsed().as_secs_f64());
    let t = Instant::now();
    let o = run(&["study", "status", out.to_str().unwrap()], None);
    let seconds = t.elapsed().as_secs_f64();
    let st = ok(&o);
    eprintln!("study status over 10 000 finished results: {seconds:.3} s: {}", st.lines().next().unwrap());
    assert!(st.contains("10000 cases in 7 shards: 10000 done, 0 failed, 0 missing, 0 running"), "{st}");
    let t = Instant::now();
    let m = ok(&run(&["study", "merge", out.to_str().unwrap()], None));
    eprintln!("study merge over 10 000 finished results: {:.3} s", t.elapsed().as_secs_f64());
    assert!(m.contains("(10000 cases)"), "{m}");
    std::fs::remove_dir_all(&dir).unwrap();
}
