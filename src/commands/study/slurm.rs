//! `rotorshunt study slurm STUDY.toml --out DIR --tasks N`: the study as a Slurm array job
//! of N tasks, one shard each, and a merge job that runs after the array whatever its
//! tasks' states (`--dependency=afterany`). The scripts go to `DIR/slurm/`; `--submit`
//! also hands them to `sbatch`.

use super::folder::{self, StudyLock, CASES, LOCK, MANIFEST, ROOT_OUTPUTS, SLURM_DIR};
use super::shard;
use super::{load_study, Loaded, OutDir, TOOL};
use crate::Error;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The array job's script in `DIR/slurm/`.
pub(crate) const ARRAY_SCRIPT: &str = "study.sbatch";
/// The merge job's script in `DIR/slurm/`.
pub(crate) const MERGE_SCRIPT: &str = "merge.sbatch";
/// The script that submits both, for submitting by hand.
pub(crate) const SUBMIT_SCRIPT: &str = "submit.sh";
/// The folder of Slurm's job logs in `DIR/slurm/`.
pub(crate) const LOGS: &str = "logs";

/// The options of `study slurm`.
#[derive(Debug, Clone)]
pub struct SlurmOptions {
    /// Array tasks, one shard each (`--tasks`).
    pub tasks: u32,
    /// `--partition`, passed to `#SBATCH --partition`.
    pub partition: Option<String>,
    /// `--time` (Slurm's forms, e.g. `2:00:00`), passed to `#SBATCH --time`.
    pub time: Option<String>,
    /// CPUs per array task (`--cpus-per-task`): the task's threads.
    pub cpus_per_task: u32,
    /// Submit the scripts (`--submit`).
    pub submit: bool,
    /// The sbatch program (`--sbatch`).
    pub sbatch: String,
    /// Write beside entries the study did not create (`--allow-non-empty`).
    pub allow_non_empty: bool,
    /// The rotorshunt binary the jobs run (this one).
    pub binary: PathBuf,
}

fn argument(name: &str, message: impl Into<String>) -> Error {
    Error::Argument { argument: name.into(), message: message.into() }
}

/// A value that goes into an `#SBATCH` line: printable, no spaces.
fn sbatch_value(name: &str, v: &Option<String>) -> Result<(), Error> {
    match v {
        Some(v) if v.is_empty() || v.chars().any(|c| c.is_whitespace() || c.is_control() || c == '#') => {
            Err(argument(name, format!("{v:?} cannot go into an #SBATCH line: give a value without spaces")))
        }
        _ => Ok(()),
    }
}

/// `text` quoted for a POSIX shell.
fn quote(text: &str) -> String {
    format!("'{}'", text.replace('\'', "'\\''"))
}

/// The path of `program` as the shell would run it: a path with a `/` as it is, else the
/// first executable file of that name in `PATH`.
fn find_program(program: &str) -> Result<PathBuf, String> {
    use std::os::unix::fs::PermissionsExt;
    let runnable = |p: &Path| std::fs::metadata(p).is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0);
    if program.contains('/') {
        let p = PathBuf::from(program);
        return if runnable(&p) { Ok(p) } else { Err("is not an executable file".into()) };
    }
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path)
        .map(|d| d.join(program))
        .find(|p| runnable(p))
        .ok_or_else(|| "is not found in PATH (install Slurm's client tools, or give --sbatch PATH)".to_string())
}

fn sbatch_lines(o: &SlurmOptions) -> String {
    let mut s = String::new();
    if let Some(p) = &o.partition {
        s += &format!("#SBATCH --partition={p}\n");
    }
    if let Some(t) = &o.time {
        s += &format!("#SBATCH --time={t}\n");
    }
    s
}

/// Run `sbatch --parsable [extra] script` (`shown`: the script's path as the user gave
/// the folder): the job id.
fn submit(sbatch: &Path, extra: &[String], script: &Path, shown: &Path) -> Result<String, Error> {
    let failed = |status: String, stderr: String| Error::SlurmFailed {
        program: sbatch.display().to_string(),
        script: shown.display().to_string(),
        status,
        stderr,
    };
    let out = Command::new(sbatch)
        .arg("--parsable")
        .args(extra)
        .arg(script)
        .output()
        .map_err(|e| failed("not started".into(), e.to_string()))?;
    let stderr = String::from_utf8_lossy(&out.stderr);
    let first = stderr.lines().find(|l| !l.trim().is_empty()).unwrap_or("no message").trim().to_string();
    if !out.status.success() {
        return Err(failed(out.status.to_string(), first));
    }
    // `--parsable` prints `JOBID` or `JOBID;CLUSTER`.
    let stdout = String::from_utf8_lossy(&out.stdout);
    let id = stdout.trim().split(';').next().unwrap_or_default().to_string();
    if id.is_empty() || !id.bytes().all(|b| b.is_ascii_digit()) {
        return Err(failed(out.status.to_string(), format!("no job id in its output {:?}", stdout.trim())));
    }
    Ok(id)
}

/// `rotorshunt study slurm STUDY.toml --out DIR --tasks N …`: write `DIR/slurm/{study,
/// merge}.sbatch` and `submit.sh`, record N shards in the folder's manifest and, with
/// `--submit`, submit both jobs. The text for standard output.
pub fn slurm_cmd(file: &Path, out: &Path, o: &SlurmOptions) -> Result<String, Error> {
    let Loaded { plan, identity, .. } = load_study(file)?;
    shard::check_count("--tasks", o.tasks, plan.len())?;
    if o.cpus_per_task == 0 {
        return Err(argument("--cpus-per-task", "must be at least 1"));
    }
    sbatch_value("--partition", &o.partition)?;
    sbatch_value("--time", &o.time)?;
    // Before anything is written: the program that submits.
    let sbatch = if o.submit {
        Some(find_program(&o.sbatch).map_err(|reason| Error::SlurmMissing { program: o.sbatch.clone(), reason })?)
    } else {
        None
    };
    let inputs: [(&Path, &str); 2] = [(file, "the study file"), (&plan.base, "the study's base problem file")];
    let root = OutDir::planned(out, &inputs);
    let own_names: Vec<&str> = [MANIFEST, LOCK].into_iter().chain(ROOT_OUTPUTS).chain(folder::SUMMARY_FILES).collect();
    root.check_outputs(&own_names)?;
    folder::inspect_as(out, &identity, o.allow_non_empty, true)?;
    std::fs::create_dir_all(out)
        .map_err(|e| Error::Output { path: out.display().to_string(), message: e.to_string() })?;
    let lock = StudyLock::wait(out, &identity.study)?;
    let found = folder::inspect_as(out, &identity, o.allow_non_empty, true)?;
    let mut changed = None;
    let (ledger, mut notes) = folder::open_root_with(out, &identity, found, |m| {
        if m.shards.is_some_and(|n| n != o.tasks) {
            changed = m.shards;
        }
        m.shards = Some(o.tasks);
        Ok(())
    })?;
    if let Some(n) = changed {
        notes.push(format!(
            "note: the study was split into {n} shards, now {}: finished cases are kept, and tasks of the old split are refused",
            o.tasks
        ));
    }
    notes.extend(lock.taken_over.clone());
    ledger.claim(CASES, &out.join(CASES))?;
    ledger.claim(SLURM_DIR, &out.join(SLURM_DIR))?;
    let root = root.with_ledger(ledger);
    for d in [out.join(CASES), out.join(SLURM_DIR), out.join(SLURM_DIR).join(LOGS)] {
        match std::fs::create_dir(&d) {
            Ok(()) => {}
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && d.is_dir() => {}
            Err(e) => return Err(root.error(&d.display().to_string(), e)),
        }
    }
    drop(lock);
    let abs = std::fs::canonicalize(out).map_err(|e| root.error("", e))?;
    let dir = abs.join(SLURM_DIR);
    let logs = dir.join(LOGS);
    let bin = quote(&o.binary.display().to_string());
    let (study_q, out_q) = (quote(&identity.study), quote(&abs.display().to_string()));
    let n = o.tasks;
    let array = format!(
        "#!/bin/bash
# A rotorshunt study as a Slurm array job, written by `rotorshunt study slurm` ({TOOL}).
# Study {} (plan {}): {} cases in {n} shards, shard K (0-based) in array task K.
# Submit it with its merge job: sh {}
# After a failure: `rotorshunt study status {}` prints the indices to resubmit,
#   sbatch --array=LIST {}
# The shard count is written below: SLURM_ARRAY_TASK_COUNT, _MIN and _MAX describe a
# submission (a resubmission of some indices changes them); the task reads only
# SLURM_ARRAY_TASK_ID. Its threads follow SLURM_CPUS_PER_TASK (RAYON_NUM_THREADS wins).
#SBATCH --job-name=rotorshunt-study
#SBATCH --array=0-{}
#SBATCH --cpus-per-task={}
#SBATCH --output={}/study-%A_%a.out
{}set -eu
exec {bin} study {study_q} --out {out_q} --shards {n}
",
        identity.study,
        &identity.plan[..12],
        plan.len(),
        dir.join(SUBMIT_SCRIPT).display(),
        abs.display(),
        dir.join(ARRAY_SCRIPT).display(),
        n - 1,
        o.cpus_per_task,
        logs.display(),
        sbatch_lines(o),
    );
    let merge = format!(
        "#!/bin/bash
# The merge job of a rotorshunt study array (`rotorshunt study slurm`, {TOOL}): builds
# summary/summary.{{csv,json,md}} from every finished case; exit 5 if a case failed or is missing.
#SBATCH --job-name=rotorshunt-merge
#SBATCH --cpus-per-task=1
#SBATCH --output={}/merge-%j.out
{}set -eu
exec {bin} study merge {out_q}
",
        logs.display(),
        sbatch_lines(o),
    );
    let submit_text = format!(
        "#!/bin/sh
# Submit the array job and its merge job (afterany: it runs whatever the tasks' states).
set -eu
array=$(sbatch --parsable {})
array=${{array%%;*}}
merge=$(sbatch --parsable --dependency=afterany:\"$array\" {})
echo \"array job $array ({n} tasks), merge job ${{merge%%;*}}\"
",
        quote(&dir.join(ARRAY_SCRIPT).display().to_string()),
        quote(&dir.join(MERGE_SCRIPT).display().to_string()),
    );
    let scripts = OutDir::planned(&dir, &inputs);
    scripts.write(ARRAY_SCRIPT, array.as_bytes())?;
    scripts.write(MERGE_SCRIPT, merge.as_bytes())?;
    scripts.write(SUBMIT_SCRIPT, submit_text.as_bytes())?;
    let mut text = format!(
        "study slurm: {} cases in {n} shards; wrote {}, {} and {}\n",
        plan.len(),
        dir.join(ARRAY_SCRIPT).display(),
        dir.join(MERGE_SCRIPT).display(),
        dir.join(SUBMIT_SCRIPT).display()
    );
    if let Some(sbatch) = sbatch {
        let shown = out.join(SLURM_DIR);
        let job = submit(&sbatch, &[], &dir.join(ARRAY_SCRIPT), &shown.join(ARRAY_SCRIPT))?;
        let after = [format!("--dependency=afterany:{job}")];
        let merge_job = submit(&sbatch, &after, &dir.join(MERGE_SCRIPT), &shown.join(MERGE_SCRIPT))?;
        text += &format!("submitted: array job {job} ({n} tasks), merge job {merge_job} (afterany:{job})\n");
    } else {
        text += &format!("submit with: sh {}\n", dir.join(SUBMIT_SCRIPT).display());
    }
    for n in notes {
        text += &n;
        text.push('\n');
    }
    Ok(text)
}
