//! A study as a real Slurm array job (issue 19), on a single-node cluster brought up by
//! `scripts/slurm-local.sh`: `study slurm --submit --tasks 4` of the 12-case study in
//! `problems/studies`; one task cancelled with `scancel` mid-run and one task's process
//! killed with SIGKILL (a lost node); `study status` names the missing array indices,
//! resubmitting just those completes the study, and the merged summary and every case
//! file equal the single-machine run's (wall times and task ids aside).
//!
//! Needs root and Debian's Slurm packages (the script installs them). When the cluster
//! cannot be brought up the test fails, saying why, unless `ROTORSHUNT_SKIP_SLURM=1`.
//! It uses its own cluster folder and ports (`ROTORSHUNT_SLURM_DIR`, default
//! `/tmp/rotorshunt-slurm-test`; ports 6837/6838 unless `SLURM_LOCAL_CTLD_PORT` /
//! `SLURM_LOCAL_SLURMD_PORT` are set) and stops that cluster at the end.

use crate::common;

use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

struct Cluster {
    dir: PathBuf,
    conf: String,
}

impl Cluster {
    fn script(&self, what: &str) -> Output {
        Command::new(common::root().join("scripts/slurm-local.sh"))
            .args([what, self.dir.to_str().unwrap()])
            .env("SLURM_LOCAL_CTLD_PORT", std::env::var("SLURM_LOCAL_CTLD_PORT").unwrap_or("6837".into()))
            .env("SLURM_LOCAL_SLURMD_PORT", std::env::var("SLURM_LOCAL_SLURMD_PORT").unwrap_or("6838".into()))
            .output()
            .expect("run scripts/slurm-local.sh")
    }

    fn tool(&self, program: &str, args: &[&str]) -> String {
        let o = Command::new(program).args(args).env("SLURM_CONF", &self.conf).output().unwrap();
        assert!(o.status.success(), "{program} {args:?}: {}", text(&o.stderr));
        text(&o.stdout)
    }

    /// `squeue` lines `INDEX STATE` of the array tasks of `job` that Slurm still lists.
    fn tasks(&self, job: &str) -> BTreeMap<String, String> {
        self.tool("squeue", &["-h", "-r", "-t", "all", "-j", job, "-o", "%K %T"])
            .lines()
            .filter_map(|l| l.split_once(' ').map(|(k, s)| (k.to_string(), s.trim().to_string())))
            .collect()
    }

    /// The job-completion log lines of `job`'s array tasks (`ArrayJobId=job`) or of job `job`
    /// itself, as `key=value` maps.
    fn completed(&self, job: &str) -> Vec<BTreeMap<String, String>> {
        let log = std::fs::read_to_string(self.dir.join("jobcomp.log")).unwrap_or_default();
        log.lines()
            .map(|l| {
                l.split_whitespace()
                    .filter_map(|f| f.split_once('='))
                    .map(|(k, v)| (k.to_string(), v.to_string()))
                    .collect::<BTreeMap<_, _>>()
            })
            .filter(|m| {
                m.get("ArrayJobId").map(String::as_str) == Some(job)
                    || (m.get("JobId").map(String::as_str) == Some(job) && !m.contains_key("ArrayJobId"))
            })
            .collect()
    }

    /// Wait until job `job` (array or not) has left the queue.
    fn wait_gone(&self, job: &str, hang_timeout: Duration) {
        let hang_deadline = Instant::now() + hang_timeout;
        loop {
            let q = self.tool("squeue", &["-h", "-j", job, "-o", "%i %T"]);
            if q.trim().is_empty() {
                return;
            }
            assert!(Instant::now() < hang_deadline, "job {job} still queued after {hang_timeout:?}:\n{q}");
            std::thread::sleep(Duration::from_millis(200));
        }
    }
}

fn up() -> Option<Cluster> {
    let dir = PathBuf::from(std::env::var("ROTORSHUNT_SLURM_DIR").unwrap_or("/tmp/rotorshunt-slurm-test".into()));
    let mut c = Cluster { dir, conf: String::new() };
    let t = Instant::now();
    let o = c.script("up");
    let why =
        format!("scripts/slurm-local.sh up exited {:?}:\n{}{}", o.status.code(), text(&o.stdout), text(&o.stderr));
    if !o.status.success() {
        if std::env::var("ROTORSHUNT_SKIP_SLURM").as_deref() == Ok("1") {
            eprintln!("SKIPPED: the Slurm integration test (ROTORSHUNT_SKIP_SLURM=1): {why}");
            return None;
        }
        panic!(
            "the single-node Slurm cluster could not be brought up (root and Debian's slurm packages are needed; set ROTORSHUNT_SKIP_SLURM=1 to skip this test): {why}"
        );
    }
    eprintln!("cluster up in {:.1} s", t.elapsed().as_secs_f64());
    c.conf =
        text(&o.stdout).trim().strip_prefix("export SLURM_CONF=").expect("up prints the SLURM_CONF line").to_string();
    Some(c)
}

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_rotorshunt"));
    c.env_remove("SLURM_ARRAY_TASK_ID").env_remove("RAYON_NUM_THREADS");
    c
}

fn summary(out: &Path) -> Value {
    let mut v: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary/summary.json")).unwrap()).unwrap();
    for c in v["cases"].as_array_mut().unwrap() {
        c["seconds"] = Value::Null;
        c["task"] = Value::Null;
    }
    v
}

/// The pid recorded in a held case lock of a case of shard `k` (what runs it), if any.
fn running_pid(out: &Path, slugs: &[String]) -> Option<i32> {
    slugs.iter().find_map(|s| {
        let lock = std::fs::read_to_string(out.join("cases").join(s).join(".rotorshunt-case.lock")).ok()?;
        serde_json::from_str::<Value>(&lock).ok()?["pid"].as_i64().map(|p| p as i32)
    })
}

fn states_line(c: &Cluster, job: &str) -> String {
    let mut lines: Vec<String> = c
        .completed(job)
        .iter()
        .map(|m| {
            format!(
                "JobId={} ArrayJobId={} ArrayTaskId={} JobState={} ExitCode={}",
                m.get("JobId").map_or("", |s| s),
                m.get("ArrayJobId").map_or("-", |s| s),
                m.get("ArrayTaskId").map_or("-", |s| s),
                m.get("JobState").map_or("", |s| s),
                m.get("ExitCode").map_or("", |s| s)
            )
        })
        .collect();
    lines.sort();
    lines.join("\n")
}

#[test]
fn a_study_runs_as_a_slurm_array_and_recovers_from_a_cancelled_and_a_killed_task() {
    let started = Instant::now();
    let Some(cluster) = up() else { return };
    let study = common::root().join("problems/studies/resistance-speed.toml");
    let work = std::env::temp_dir().join(format!("rotorshunt-slurm-study-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&work);
    std::fs::create_dir_all(&work).unwrap();
    let (whole, out) = (work.join("whole"), work.join("array"));

    // The single-machine run.
    let o = bin().arg("study").arg(&study).arg("--out").arg(&whole).env("RAYON_NUM_THREADS", "2").output().unwrap();
    assert!(o.status.success(), "{}", text(&o.stderr));

    // The shard of every case, to find the processes of tasks 1 and 2.
    let plan: Value = serde_json::from_slice(
        &bin().args(["study", "plan"]).arg(&study).args(["--shards", "4", "--json"]).output().unwrap().stdout,
    )
    .unwrap();
    let slugs_of = |k: u64| -> Vec<String> {
        plan["list"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|c| c["shard"].as_u64() == Some(k))
            .map(|c| c["folder"].as_str().unwrap().to_string())
            .collect()
    };

    let t = Instant::now();
    let o = bin()
        .args(["study", "slurm"])
        .arg(&study)
        .arg("--out")
        .arg(&out)
        .args(["--tasks", "4", "--cpus-per-task", "1", "--submit"])
        .env("SLURM_CONF", &cluster.conf)
        .output()
        .unwrap();
    let submitted = text(&o.stdout);
    assert!(o.status.success(), "{submitted}{}", text(&o.stderr));
    eprint!("{submitted}");
    let line = submitted.lines().find(|l| l.starts_with("submitted: ")).expect("submitted line");
    let ids: Vec<&str> = line.split(|c: char| !c.is_ascii_digit()).filter(|w| !w.is_empty()).collect();
    let (job, merge_job) = (ids[0].to_string(), ids[2].to_string());

    // Task 1: scancel as soon as it runs a case. Task 2: SIGKILL its process as soon as it
    // runs a case (its node "disappears": the folder is left as it is).
    let (mut cancelled, mut killed) = (false, false);
    let hang_deadline = Instant::now() + Duration::from_secs(120);
    while !(cancelled && killed) {
        assert!(Instant::now() < hang_deadline, "tasks 1 and 2 never ran: {:?}", cluster.tasks(&job));
        if !cancelled && running_pid(&out, &slugs_of(1)).is_some() {
            cluster.tool("scancel", &[&format!("{job}_1")]);
            eprintln!("scancel {job}_1 at {:.1} s", t.elapsed().as_secs_f64());
            cancelled = true;
        }
        if !killed {
            if let Some(pid) = running_pid(&out, &slugs_of(2)) {
                // The pid the case lock records is the task's rotorshunt process.
                // SAFETY: kill(2) with a pid and a signal number has no memory effects.
                let r = unsafe { libc::kill(pid, libc::SIGKILL) };
                eprintln!("kill -9 {pid} (task {job}_2) at {:.1} s: {r}", t.elapsed().as_secs_f64());
                killed = r == 0;
            }
        }
        let states = cluster.tasks(&job);
        if !cancelled && states.get("1").is_some_and(|s| s == "COMPLETED") {
            panic!("task 1 ended before it could be cancelled: {states:?}");
        }
        if !killed && states.get("2").is_some_and(|s| s == "COMPLETED") {
            panic!("task 2 ended before it could be killed: {states:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    cluster.wait_gone(&job, Duration::from_secs(180));
    cluster.wait_gone(&merge_job, Duration::from_secs(60));
    eprintln!(
        "array and merge job ended at {:.1} s:\n{}\n{}",
        t.elapsed().as_secs_f64(),
        states_line(&cluster, &job),
        states_line(&cluster, &merge_job)
    );
    let tasks: BTreeMap<String, String> =
        cluster.completed(&job).into_iter().map(|m| (m["ArrayTaskId"].clone(), m["JobState"].clone())).collect();
    assert_eq!(tasks.get("0").map(String::as_str), Some("COMPLETED"), "{tasks:?}");
    assert_eq!(tasks.get("3").map(String::as_str), Some("COMPLETED"), "{tasks:?}");
    assert_eq!(tasks.get("1").map(String::as_str), Some("CANCELLED"), "{tasks:?}");
    assert_eq!(tasks.get("2").map(String::as_str), Some("FAILED"), "{tasks:?}");
    let merge_state = cluster.completed(&merge_job);
    assert_eq!(merge_state.len(), 1, "the merge job ran after the array (afterany)");
    assert_eq!(merge_state[0]["JobState"], "FAILED", "merge exits 5 on an incomplete study");
    assert_eq!(merge_state[0]["ExitCode"], "5:0");

    // status names the missing indices; resubmitting just those completes the study.
    let o = bin().args(["study", "status"]).arg(&out).output().unwrap();
    let status = text(&o.stdout);
    eprint!("{status}");
    assert_eq!(o.status.code(), Some(5), "{status}");
    let array = status.lines().find_map(|l| l.strip_prefix("rerun: --array=")).expect("an --array line").to_string();
    assert_eq!(array, "1-2", "{status}");
    let script = out.join("slurm/study.sbatch");
    assert!(
        status.contains(&format!("rerun: sbatch --array=1-2 {}", std::fs::canonicalize(&script).unwrap().display()))
            || status.contains("rerun: sbatch --array=1-2"),
        "{status}"
    );
    let again = cluster.tool("sbatch", &["--parsable", &format!("--array={array}"), script.to_str().unwrap()]);
    let again = again.trim().split(';').next().unwrap().to_string();
    let merge_again = cluster.tool(
        "sbatch",
        &["--parsable", &format!("--dependency=afterany:{again}"), out.join("slurm/merge.sbatch").to_str().unwrap()],
    );
    let merge_again = merge_again.trim().split(';').next().unwrap().to_string();
    cluster.wait_gone(&again, Duration::from_secs(180));
    cluster.wait_gone(&merge_again, Duration::from_secs(60));
    eprintln!(
        "resubmitted --array={array} ended at {:.1} s:\n{}\n{}",
        t.elapsed().as_secs_f64(),
        states_line(&cluster, &again),
        states_line(&cluster, &merge_again)
    );
    for m in cluster.completed(&again) {
        assert_eq!(m["JobState"], "COMPLETED", "{m:?}");
    }
    assert_eq!(cluster.completed(&merge_again)[0]["JobState"], "COMPLETED");
    let merged_log = std::fs::read_dir(out.join("slurm/logs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.file_name().unwrap().to_string_lossy() == format!("merge-{merge_again}.out"))
        .expect("the merge job's log");
    let merged = std::fs::read_to_string(merged_log).unwrap();
    eprint!("merged: {merged}");
    assert!(merged.contains("12 cases in 4 shards: 12 done, 0 failed, 0 missing, 0 running"), "{merged}");

    // The same summary and byte-identical case files as the single-machine run.
    assert_eq!(summary(&out), summary(&whole));
    assert_eq!(common::case_files(&out), common::case_files(&whole));
    // The task record names the Slurm task that ran each case.
    let s: Value = serde_json::from_str(&std::fs::read_to_string(out.join("summary/summary.json")).unwrap()).unwrap();
    for c in s["cases"].as_array().unwrap() {
        let array_job = c["task"]["slurm_array_job_id"].as_str().unwrap();
        assert!(array_job == job || array_job == again, "{c}");
        assert_eq!(
            c["task"]["shard"].as_str().unwrap(),
            format!("{}/4", c["task"]["slurm_array_task_id"].as_str().unwrap())
        );
    }
    let o = cluster.script("down");
    assert!(o.status.success(), "down: {}", text(&o.stderr));
    std::fs::remove_dir_all(&work).unwrap();
    eprintln!("slurm integration test: {:.1} s in all (cluster up and down included)", started.elapsed().as_secs_f64());
}
