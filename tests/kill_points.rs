//! Kill points (issue 26): the file layer's test-only fault hook
//! (`ROTORSHUNT_TEST_KILL_AT=N`, src/files/fault.rs) kills the binary with SIGKILL at its
//! N-th write, rename or removal. At every such point of `chart --out` over an existing
//! folder the folder is, afterwards, entirely the old one or entirely the new one (the
//! user's files in it both times), and the next run leaves no leftover beside it. Points
//! are counted, not timed: N runs from 1 until a run finishes without being killed.

use crate::common;

use std::collections::BTreeMap;
use std::os::unix::process::ExitStatusExt;
use std::path::{Path, PathBuf};
use std::process::Command;

const SIGKILL: i32 = 9;
/// A run with more fault points than this is a run that never finishes (a bug).
const MAX_POINTS: u64 = 400;

type Snapshot = BTreeMap<PathBuf, Option<Vec<u8>>>;

/// Every entry below `dir`, relative, with each file's bytes (None for a folder), and
/// the output manifest reduced to its `commands` (the token of the run that staged it
/// differs from run to run).
fn snapshot(dir: &Path) -> Snapshot {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            let rel = p.strip_prefix(dir).unwrap().to_path_buf();
            let m = std::fs::symlink_metadata(&p).unwrap();
            if m.is_dir() {
                out.insert(rel, None);
                stack.push(p);
            } else if m.file_type().is_symlink() {
                out.insert(rel, Some(std::fs::read_link(&p).unwrap().into_os_string().into_encoded_bytes()));
            } else if rel == Path::new(".rotorshunt-out.json") {
                let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&p).unwrap()).unwrap();
                out.insert(rel, Some(v["commands"].to_string().into_bytes()));
            } else {
                out.insert(rel, Some(std::fs::read(&p).unwrap()));
            }
        }
    }
    out
}

fn copy_tree(from: &Path, to: &Path) {
    let status = Command::new("cp").arg("-a").arg(from).arg(to).status().unwrap();
    assert!(status.success());
}

fn chart(args: &[&str], out: &Path, kill_at: Option<u64>) -> std::process::Output {
    let mut c = common::bin();
    c.arg("chart").arg(common::problem_path("paper-open.toml")).args(args).arg("--out").arg(out);
    if let Some(n) = kill_at {
        c.env("ROTORSHUNT_TEST_KILL_AT", n.to_string());
    }
    c.output().unwrap()
}

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<_> =
        std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    v.sort();
    v
}

#[test]
fn chart_over_an_existing_folder_is_old_or_new_at_every_kill_point() {
    let dir = common::tmp("kill-points-chart");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let old_args = ["--phi", "500", "--beta", "0.1"];
    let new_args = ["--phi", "500:600:3", "--beta", "0.1"];
    // The old folder: an earlier chart, a user's file, folder and link in it.
    let pristine = dir.join("pristine");
    assert!(chart(&old_args, &pristine, None).status.success());
    std::fs::write(pristine.join("notes.txt"), "the user's notes\n").unwrap();
    std::fs::create_dir(pristine.join("data")).unwrap();
    std::fs::write(pristine.join("data/run.log"), "kept\n").unwrap();
    std::os::unix::fs::symlink("notes.txt", pristine.join("notes-link")).unwrap();
    let old = snapshot(&pristine);
    // The new folder, from an uninterrupted run over a copy.
    let reference_parent = dir.join("reference");
    std::fs::create_dir(&reference_parent).unwrap();
    copy_tree(&pristine, &reference_parent.join("out"));
    assert!(chart(&new_args, &reference_parent.join("out"), None).status.success());
    let new = snapshot(&reference_parent.join("out"));
    assert_ne!(old, new, "the two runs must differ for the test to tell them apart");
    assert_eq!(names(&reference_parent), ["out"], "an uninterrupted run leaves nothing beside the folder");

    let (mut killed, mut saw_old, mut saw_new) = (0, 0, 0);
    let parent = dir.join("run");
    let out = parent.join("out");
    for n in 1..=MAX_POINTS {
        let _ = std::fs::remove_dir_all(&parent);
        std::fs::create_dir(&parent).unwrap();
        copy_tree(&pristine, &out);
        let run = chart(&new_args, &out, Some(n));
        if run.status.success() {
            assert_eq!(snapshot(&out), new, "the run that passed all {} points", n - 1);
            break;
        }
        assert_eq!(run.status.signal(), Some(SIGKILL), "point {n}: {}", String::from_utf8_lossy(&run.stderr));
        killed += 1;
        let found = snapshot(&out);
        if found == old {
            saw_old += 1;
        } else if found == new {
            saw_new += 1;
        } else {
            let differ: Vec<_> = old
                .keys()
                .chain(new.keys())
                .chain(found.keys())
                .filter(|k| found.get(*k) != old.get(*k) && found.get(*k) != new.get(*k))
                .collect();
            panic!("kill at point {n}: the folder is neither old nor new; entries of neither: {differ:?}");
        }
        // The next run cleans up after the killed one and writes the new folder.
        let again = chart(&new_args, &out, None);
        assert!(again.status.success(), "point {n}: {}", String::from_utf8_lossy(&again.stderr));
        assert_eq!(snapshot(&out), new, "after the kill at point {n}, the next run");
        assert_eq!(names(&parent), ["out"], "after the kill at point {n}, the next run left leftovers");
    }
    eprintln!("{killed} kill points: {saw_old} left the old folder, {saw_new} the new one");
    assert!(killed >= 10, "only {killed} fault points: the hook is not reached by the writes");
    assert!(saw_old > 0 && saw_new > 0, "kills both before and after the swap: {saw_old} old, {saw_new} new");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A study of two quick regions cases on the coarse model.
fn two_case_study(dir: &Path) -> PathBuf {
    common::coarse_study(
        dir,
        "study.toml",
        "[[cases]]\nname = \"low\"\nset = [\"speed=1500.0\"]\n\n[[cases]]\nname = \"high\"\nset = [\"speed=2500.0\"]\n",
    )
}

fn merge(out: &Path, kill_at: Option<u64>) -> std::process::Output {
    let mut c = common::bin();
    c.arg("study").arg("merge").arg(out);
    if let Some(n) = kill_at {
        c.env("ROTORSHUNT_TEST_KILL_AT", n.to_string());
    }
    c.output().unwrap()
}

#[test]
fn study_merge_summaries_are_one_generation_at_every_kill_point() {
    let dir = common::tmp("kill-points-merge");
    std::fs::create_dir_all(&dir).unwrap();
    let study = two_case_study(&dir);
    let pristine = dir.join("pristine");
    let o = common::bin().arg("study").arg(&study).arg("--out").arg(&pristine).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // An older generation of the three summaries: each marked, so each file tells which
    // generation it is of.
    for f in ["summary.csv", "summary.json", "summary.md"] {
        let p = pristine.join("summary").join(f);
        let mut bytes = std::fs::read(&p).unwrap();
        bytes.extend_from_slice(b"\n(an older generation)\n");
        std::fs::write(&p, bytes).unwrap();
    }
    let old = snapshot(&pristine.join("summary"));
    let reference = dir.join("reference");
    copy_tree(&pristine, &reference);
    assert!(merge(&reference, None).status.success());
    let new = snapshot(&reference.join("summary"));
    assert_ne!(old, new);

    let out = dir.join("out");
    let (mut killed, mut saw_old, mut saw_new) = (0, 0, 0);
    for n in 1..=MAX_POINTS {
        let _ = std::fs::remove_dir_all(&out);
        copy_tree(&pristine, &out);
        let run = merge(&out, Some(n));
        if run.status.success() {
            assert_eq!(snapshot(&out.join("summary")), new, "the merge that passed all {} points", n - 1);
            break;
        }
        assert_eq!(run.status.signal(), Some(SIGKILL), "point {n}: {}", String::from_utf8_lossy(&run.stderr));
        killed += 1;
        let found = snapshot(&out.join("summary"));
        if found == old {
            saw_old += 1;
        } else if found == new {
            saw_new += 1;
        } else {
            panic!("kill at point {n}: summary/ mixes generations: {:?}", found.keys().collect::<Vec<_>>());
        }
        let again = merge(&out, None);
        assert!(again.status.success(), "point {n}: {}", String::from_utf8_lossy(&again.stderr));
        assert_eq!(snapshot(&out.join("summary")), new, "after the kill at point {n}, the next merge");
        let left: Vec<_> =
            names(&out).into_iter().filter(|n| n.contains(".tmp-") || n.contains("rotorshunt-tmp")).collect();
        assert!(left.is_empty(), "after the kill at point {n}, the next merge left {left:?}");
    }
    eprintln!("study merge: {killed} kill points: {saw_old} left the old summaries, {saw_new} the new ones");
    assert!(killed >= 5, "only {killed} fault points");
    assert!(saw_old > 0 && saw_new > 0, "{saw_old} old, {saw_new} new");
    std::fs::remove_dir_all(&dir).unwrap();
}
