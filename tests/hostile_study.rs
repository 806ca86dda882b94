//! A hostile or careless study folder (issue 26): for `study`, `study --shard`, `study
//! merge`, `study status` and `study slurm`, links in place of every name the study
//! records or uses (its lock and manifest, `cases/`, a case folder, a case's lock,
//! manifest and `result.json`, `summary/`, `slurm/`), FIFOs where a result or summary
//! goes, hard-linked locks, manifests whose
//! entries name `../x` and absolute paths, and a user's folders named like staging
//! folders. Every file outside `--out` stays byte-identical and in place, and each plant
//! is refused (the plant named) or ignored with a warning. Then the records read back
//! (tests/hostile_folder.rs covers the other commands): tampered locks, manifests and
//! results are refused or recomputed and never reach a summary, and a full disk leaves
//! the summary and `study status` agreeing.

use crate::common;

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Output;

/// A study of two quick regions cases on a coarse model, in `dir`.
fn two_case_study(dir: &Path) -> PathBuf {
    common::coarse_study(dir, "study.toml", "[sweep]\n\"circuit.branches[0].resistance\" = [0.0, 50.0]\n")
}

fn run(args: &[&str], study: &Path, out: &Path, env: &[(&str, &str)]) -> Output {
    let mut c = common::bin();
    c.env("RAYON_NUM_THREADS", "2");
    for (k, v) in env {
        c.env(k, v);
    }
    // `run` is `study STUDY`; the others are subcommands of `study`.
    match args[0] {
        "merge" | "status" => c.arg("study").arg(args[0]).arg(out),
        "run" => c.arg("study").arg(study).arg("--out").arg(out).args(&args[1..]),
        sub => c.arg("study").arg(sub).arg(study).arg("--out").arg(out).args(&args[1..]),
    };
    c.output().unwrap()
}

fn all(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

/// The case folders of `out`, sorted.
fn case_dirs(out: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(out.join("cases")).unwrap().map(|e| e.unwrap().path()).collect();
    v.sort();
    v
}

fn link(target: &Path, at: &Path) {
    let _ = std::fs::remove_file(at);
    let _ = std::fs::remove_dir_all(at);
    std::os::unix::fs::symlink(target, at).unwrap();
}

/// How a plant is made: given the parent with its victims, and `out`.
type Make = Box<dyn Fn(&Path, &Path)>;

/// One plant: a name, how to make it in `out`, the command, and what the run must say.
struct Plant {
    name: &'static str,
    make: Make,
    args: &'static [&'static str],
    says: &'static [&'static str],
}

fn plants() -> Vec<Plant> {
    let victim = |parent: &Path| parent.join("victim.txt");
    let victim_dir = |parent: &Path| parent.join("victim_dir");
    let lock = ".rotorshunt-study.lock";
    let case_lock = ".rotorshunt-case.lock";
    let mut v: Vec<Plant> = Vec::new();
    for args in
        [&["run", "--force"][..], &["run", "--shard", "0/2"][..], &["merge"][..], &["slurm", "--tasks", "2"][..]]
    {
        v.push(Plant {
            name: "study lock a link",
            make: Box::new(move |p, out| link(&victim(p), &out.join(lock))),
            args,
            says: &["a symbolic link"],
        });
    }
    v.push(Plant {
        name: "study manifest a link",
        make: Box::new(move |p, out| {
            let copy = p.join("manifest-copy.json");
            std::fs::copy(out.join(".rotorshunt-study.json"), &copy).unwrap();
            link(&copy, &out.join(".rotorshunt-study.json"));
        }),
        args: &["run", "--force"],
        says: &["a symbolic link"],
    });
    v.push(Plant {
        name: "cases/ a link",
        make: Box::new(move |p, out| link(&victim_dir(p), &out.join("cases"))),
        args: &["run", "--force"],
        says: &["a symbolic link"],
    });
    v.push(Plant {
        name: "a case folder a link",
        make: Box::new(move |p, out| link(&victim_dir(p), &case_dirs(out)[0])),
        args: &["run", "--force"],
        says: &["a symbolic link"],
    });
    for args in [&["run", "--force"][..], &["run", "--shard", "1/2", "--force"][..]] {
        v.push(Plant {
            name: "case lock a link",
            make: Box::new(move |p, out| {
                for d in case_dirs(out) {
                    link(&victim(p), &d.join(case_lock));
                }
            }),
            args,
            says: &["a symbolic link"],
        });
    }
    v.push(Plant {
        name: "two case locks one file",
        make: Box::new(move |_, out| {
            let d = case_dirs(out);
            std::fs::write(d[0].join(case_lock), "").unwrap();
            let _ = std::fs::remove_file(d[1].join(case_lock));
            std::fs::hard_link(d[0].join(case_lock), d[1].join(case_lock)).unwrap();
        }),
        args: &["run", "--force"],
        says: &["more than one name"],
    });
    v.push(Plant {
        name: "case manifest a link",
        make: Box::new(move |p, out| {
            let d = &case_dirs(out)[0];
            let copy = p.join("case-manifest-copy.json");
            std::fs::copy(d.join(".rotorshunt-case.json"), &copy).unwrap();
            link(&copy, &d.join(".rotorshunt-case.json"));
        }),
        args: &["run", "--force"],
        says: &["a symbolic link"],
    });
    v.push(Plant {
        name: "result.json a link",
        make: Box::new(move |p, out| link(&victim(p), &case_dirs(out)[0].join("result.json"))),
        args: &["run"],
        says: &["a symbolic link"],
    });
    v.push(Plant {
        name: "result.json a link, merged",
        make: Box::new(move |p, out| link(&victim(p), &case_dirs(out)[0].join("result.json"))),
        args: &["merge"],
        says: &["not valid records"],
    });
    v.push(Plant {
        name: "result.json a FIFO",
        make: Box::new(move |_, out| {
            let r = case_dirs(out)[0].join("result.json");
            std::fs::remove_file(&r).unwrap();
            common::mkfifo(&r);
        }),
        args: &["run"],
        says: &["a FIFO"],
    });
    v.push(Plant {
        name: "a summary a FIFO",
        make: Box::new(move |_, out| {
            let f = out.join("summary/summary.md");
            std::fs::remove_file(&f).unwrap();
            common::mkfifo(&f);
        }),
        args: &["merge"],
        says: &["a FIFO"],
    });
    v.push(Plant {
        name: "summary/ a link",
        make: Box::new(move |p, out| link(&victim_dir(p), &out.join("summary"))),
        args: &["merge"],
        says: &["a symbolic link"],
    });
    v.push(Plant {
        name: "slurm/ a link",
        make: Box::new(move |p, out| {
            // The study's own slurm/ first (recorded), then a link in its place.
            let o = run(&["slurm", "--tasks", "2"], &p.join("study.toml"), out, &[]);
            assert_eq!(o.status.code(), Some(0), "{}", all(&o));
            std::fs::write(victim_dir(p).join("study.sbatch"), "#!/bin/sh\n# the user's own\n").unwrap();
            link(&victim_dir(p), &out.join("slurm"));
        }),
        args: &["slurm", "--tasks", "2"],
        says: &["a symbolic link"],
    });
    for args in [&["run", "--force"][..], &["merge"][..], &["status"][..]] {
        v.push(Plant {
            name: "manifests naming ../victim.txt and an absolute path",
            make: Box::new(move |p, out| {
                for (m, role_dir) in [
                    (".rotorshunt-study.json", out.to_path_buf()),
                    (".rotorshunt-case.json", case_dirs(out)[0].clone()),
                ] {
                    let path = role_dir.join(m);
                    let mut r: Value = serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
                    let created = r["created"].as_array_mut().unwrap();
                    created.push("../victim.txt".into());
                    created.push(victim(p).display().to_string().into());
                    created.push("../../../victim.txt".into());
                    std::fs::write(&path, r.to_string()).unwrap();
                }
            }),
            args,
            says: &["\"../victim.txt\"", "not a plain name"],
        });
    }
    v.push(Plant {
        name: "user folders named like staging folders",
        make: Box::new(move |_, out| {
            for user in [".rotorshunt-tmp.summary.vm-999999", ".rotorshunt-tmp.summary.0123456789abcdef01234567"] {
                std::fs::create_dir(out.join(user)).unwrap();
                std::fs::write(out.join(user).join("mine.txt"), "the user's\n").unwrap();
            }
        }),
        args: &["merge"],
        says: &[],
    });
    v
}

fn bring_back(out: &Path, study: &Path) {
    let _ = std::fs::remove_dir_all(out);
    let o = run(&["run"], study, out, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", all(&o));
}

#[test]
fn every_study_subcommand_refuses_or_ignores_each_plant_and_touches_nothing_outside() {
    let parent = common::tmp("hostile-study");
    std::fs::create_dir_all(parent.join("victim_dir")).unwrap();
    std::fs::write(parent.join("victim.txt"), "the user's file outside --out\n").unwrap();
    std::fs::write(parent.join("victim_dir/inner.txt"), "inside the user's folder\n").unwrap();
    let study = two_case_study(&parent);
    let out = parent.join("out");
    let mut count = 0;
    for p in plants() {
        bring_back(&out, &study);
        (p.make)(&parent, &out);
        let before = common::tree(&parent, &out);
        let staged_users: Vec<PathBuf> = std::fs::read_dir(&out)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.join("mine.txt").exists())
            .collect();
        let o = run(p.args, &study, &out, &[]);
        let text = all(&o);
        assert!(o.status.code().is_some(), "{}: killed", p.name);
        for s in p.says {
            assert!(text.contains(s), "{} ({:?}): expected {s:?} in: {text}", p.name, p.args);
        }
        assert!(!text.contains("panicked"), "{}: {text}", p.name);
        assert_eq!(
            common::tree(&parent, &out),
            before,
            "{} ({:?}): something outside --out changed: {text}",
            p.name,
            p.args
        );
        for u in &staged_users {
            assert!(u.join("mine.txt").exists(), "{}: a user's folder in --out was removed", p.name);
        }
        eprintln!("{} ({:?}): exit {:?}, nothing outside changed", p.name, p.args, o.status.code());
        count += 1;
    }
    eprintln!("{count} plants over study, --shard, merge, status and slurm: nothing outside --out changed");
    std::fs::remove_dir_all(&parent).unwrap();
}

/// A tampering of a result: what it is, how it is done, and what the refusal says.
type Tamper = (&'static str, Box<dyn Fn(&mut Value)>, &'static str);

/// The rows of summary/summary.json.
fn summary(out: &Path) -> Vec<Value> {
    common::json(&out.join("summary/summary.json"))["cases"].as_array().unwrap().clone()
}

fn status_counts(out: &Path) -> Value {
    let o = common::bin().args(["study", "status"]).arg(out).arg("--json").output().unwrap();
    serde_json::from_slice(&o.stdout).unwrap_or_else(|e| panic!("{e}: {}", all(&o)))
}

#[test]
fn tampered_records_are_refused_or_recomputed_never_summarised() {
    let parent = common::tmp("hostile-records");
    std::fs::create_dir_all(&parent).unwrap();
    let study = two_case_study(&parent);
    let out = parent.join("out");

    // Results with a metric "NaN" as text, a negative wall time, a wrong type, another
    // case's name: merge leaves them out and says why; status counts them missing; the
    // next run recomputes them, and its summary holds only true records.
    let tampers: [Tamper; 4] = [
        ("NaN as text", Box::new(|r| r["metrics"]["lowest_onset"] = "NaN".into()), "is not a finite number"),
        ("seconds = -1", Box::new(|r| r["seconds"] = (-1.0).into()), "seconds = -1"),
        ("a count as text", Box::new(|r| r["metrics"]["regions"] = "many".into()), "is not a count"),
        ("another case's name", Box::new(|r| r["name"] = "someone else".into()), "name"),
    ];
    for (what, tamper, says) in &tampers {
        bring_back(&out, &study);
        let d = case_dirs(&out);
        let path = d[0].join("result.json");
        let mut r = common::json(&path);
        tamper(&mut r);
        std::fs::write(&path, serde_json::to_string_pretty(&r).unwrap()).unwrap();
        let merged = run(&["merge"], &study, &out, &[]);
        let text = all(&merged);
        assert!(text.contains("not valid records") && text.contains(says), "{what}: {text}");
        let rows = summary(&out);
        assert_eq!(rows.len(), 1, "{what}: the tampered result is not merged: {rows:?}");
        let s = std::fs::read_to_string(out.join("summary/summary.json")).unwrap();
        assert!(!s.contains("NaN") && !s.contains("\"seconds\": -1") && !s.contains("someone else"), "{what}: {s}");
        let status = status_counts(&out);
        assert_eq!((status["done"].as_u64(), status["missing"].as_u64()), (Some(1), Some(1)), "{what}: {status}");
        let rerun = run(&["run"], &study, &out, &[]);
        assert_eq!(rerun.status.code(), Some(0), "{what}: {}", all(&rerun));
        assert!(all(&rerun).contains("(1 run, 1 skipped"), "{what}: recomputed once: {}", all(&rerun));
        assert_eq!(summary(&out).len(), 2);
        assert_ne!(common::json(&path), r, "{what}: the tampered result is replaced by a recomputed one");
        eprintln!("result with {what}: refused by merge, missing in status, recomputed by the next run");
    }

    // Locks: one of another host with fields missing is not stale for an unsharded run;
    // one of this host left by a dead run is taken over; one that is not JSON is
    // refused by an unsharded run (its host cannot be told) and noted by a sharded one.
    bring_back(&out, &study);
    let lock = out.join(".rotorshunt-study.lock");
    std::fs::write(&lock, r#"{"host":"elsewhere.invalid"}"#).unwrap();
    let o = run(&["run", "--force"], &study, &out, &[]);
    assert_eq!(o.status.code(), Some(2), "{}", all(&o));
    assert!(all(&o).contains("elsewhere.invalid") && all(&o).contains("in use"), "{}", all(&o));
    std::fs::write(&lock, "{ not json").unwrap();
    let o = run(&["run", "--force"], &study, &out, &[]);
    assert_eq!(o.status.code(), Some(2), "{}", all(&o));
    let o = run(&["run", "--shard", "0/2"], &study, &out, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", all(&o));
    assert!(all(&o).contains("whose record was not the tool's"), "{}", all(&o));
    let host = String::from_utf8(std::process::Command::new("hostname").output().unwrap().stdout).unwrap();
    let me = serde_json::json!({"pid": 999_999_999u32, "host": host.trim(), "study": "x", "started_unix_s": 0});
    std::fs::write(&lock, me.to_string()).unwrap();
    let o = run(&["run", "--force"], &study, &out, &[]);
    assert_eq!(o.status.code(), Some(0), "{}", all(&o));
    assert!(all(&o).contains("took over the lock of an earlier run (pid 999999999"), "{}", all(&o));
    assert!(!lock.exists(), "the lock is removed when the run ends");
    eprintln!("locks: a foreign host with missing fields refused, garbage refused or noted, a dead one taken over");

    // A manifest whose fields have the wrong types is not the study's record: refused.
    let manifest = out.join(".rotorshunt-study.json");
    let mut m = common::json(&manifest);
    m["created"] = 5.into();
    std::fs::write(&manifest, m.to_string()).unwrap();
    let o = run(&["run"], &study, &out, &[]);
    assert_eq!(o.status.code(), Some(2), "{}", all(&o));
    assert!(all(&o).contains("cannot be read"), "{}", all(&o));
    let o = run(&["status"], &study, &out, &[]);
    assert_eq!(o.status.code(), Some(2), "{}", all(&o));
    eprintln!("a manifest of wrong types: refused by study and status");

    // A full disk for results under --force: the earlier results stay, and the summary
    // and `study status` say the same.
    bring_back(&out, &study);
    let o = run(&["run", "--force"], &study, &out, &[("ROTORSHUNT_TEST_FULL_DISK", "result.json")]);
    let text = all(&o);
    assert_eq!(text.matches("not saved: ").count(), 2, "{text}");
    assert!(text.contains("No space left on device"), "{text}");
    let rows = summary(&out);
    let statuses: Vec<&str> = rows.iter().map(|r| r["status"].as_str().unwrap()).collect();
    let status = status_counts(&out);
    assert_eq!(statuses, ["ok", "ok"], "{rows:?}");
    assert_eq!(status["done"].as_u64(), Some(2), "{status}");
    // With no earlier result, the failure is the summary's and status's alike.
    let fresh = parent.join("fresh");
    let o = run(&["run"], &study, &fresh, &[("ROTORSHUNT_TEST_FULL_DISK", "result.json")]);
    assert_eq!(o.status.code(), Some(5), "{}", all(&o));
    let failed = summary(&fresh).iter().filter(|r| r["status"] == "failed").count();
    let status = status_counts(&fresh);
    assert_eq!(failed, 2);
    assert_eq!(status["done"].as_u64(), Some(0), "{status}");
    eprintln!("full disk: earlier results kept and summarised as status reports them; without them, 2 failed, 0 done");
    std::fs::remove_dir_all(&parent).unwrap();
}
