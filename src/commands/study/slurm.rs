//! `rotorshunt study slurm STUDY.toml --out DIR --tasks N`: the study as a Slurm array job
//! of N tasks, one shard each, and a merge job that runs after the array whatever its
//! tasks' states (`--dependency=afterany`). The scripts go to `DIR/slurm/`; `--submit`
//! also hands them to `sbatch`.

use super::folder::{self, StudyLock, CASES, LOCK, MANIFEST, ROOT_OUTPUTS, SLURM_DIR};
use super::shard;
use super::{load_study, Loaded, OutDir, TOOL};
use crate::commands::Error;
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
    /// The limits each case runs under (`--max-cost`, `--time-limit`), passed on to the
    /// array tasks.
    pub budget: rotorshunt::run::Budget,
}

fn argument(name: &str, message: impl Into<String>) -> Error {
    Error::Argument { argument: name.into(), message: message.into() }
}

/// The error of a value the scripts cannot carry: `what` names the flag or path, the value
/// is shown escaped (a control character as `\n`, `\u{1b}`), so the message is one line.
fn refused(what: &str, value: &str, message: impl Into<String>) -> Error {
    Error::SlurmValue { what: what.into(), value: format!("{value:?}"), message: message.into() }
}

/// Refuse `value` if it holds a control character (C0, DEL, C1): a newline or carriage
/// return would end an `#SBATCH` line, and so the directives sbatch reads, and a terminal
/// escape would act on whoever reads the script. Every value and path the scripts carry
/// passes here first.
fn printable(what: &str, value: &str) -> Result<(), Error> {
    match value.chars().find(|c| c.is_control()) {
        Some(c) => Err(refused(
            what,
            value,
            format!(
                "contains the control character {:?} (U+{:04X}), which a job script cannot carry (a line break ends an #SBATCH line); give a plain value",
                c, c as u32
            ),
        )),
        None => Ok(()),
    }
}

/// A path the scripts carry, as text: UTF-8 (the scripts are text) and printable.
fn script_path<'a>(what: &str, path: &'a Path) -> Result<&'a str, Error> {
    let text = path.to_str().ok_or_else(|| {
        refused(what, &path.to_string_lossy(), "is not valid UTF-8, so a job script cannot name it; give a plain path")
    })?;
    printable(what, text)?;
    Ok(text)
}

/// `--time` in one of Slurm's forms (sbatch(1)): `M`, `M:S`, `H:M:S`, `D-H`, `D-H:M`,
/// `D-H:M:S`, or `UNLIMITED`/`INFINITE` (any case). Each field is decimal digits; minutes
/// and seconds after the first field are below 60 and hours after a day count below 24;
/// the whole is at most 2^31 − 1 seconds (Slurm's limit). The value as the script writes it.
fn slurm_time(t: &str) -> Result<String, Error> {
    printable("--time", t)?;
    if t.eq_ignore_ascii_case("UNLIMITED") || t.eq_ignore_ascii_case("INFINITE") {
        return Ok(t.to_ascii_uppercase());
    }
    let bad = |why: &str| {
        refused(
            "--time",
            t,
            format!("{why}: give Slurm's forms minutes, minutes:seconds, hours:minutes:seconds, days-hours, days-hours:minutes or days-hours:minutes:seconds (e.g. 90, 2:00:00, 1-12), or UNLIMITED"),
        )
    };
    let number = |f: &str| -> Result<u64, Error> {
        if f.is_empty() || f.len() > 10 || !f.bytes().all(|b| b.is_ascii_digit()) {
            return Err(bad("not a time limit"));
        }
        f.parse::<u64>().map_err(|_| bad("not a time limit"))
    };
    let (days, rest) = match t.split_once('-') {
        Some((d, rest)) => (Some(number(d)?), rest),
        None => (None, t),
    };
    let fields = rest.split(':').map(number).collect::<Result<Vec<u64>, Error>>()?;
    let below = |x: u64, n: u64, what: &str| if x < n { Ok(x) } else { Err(bad(&format!("{what} must be below {n}"))) };
    let seconds = match (days, fields.as_slice()) {
        (None, [m]) => m * 60,
        (None, [m, s]) => m * 60 + below(*s, 60, "seconds")?,
        (None, [h, m, s]) => h * 3600 + below(*m, 60, "minutes")? * 60 + below(*s, 60, "seconds")?,
        (Some(d), [h]) => d * 86_400 + below(*h, 24, "hours")? * 3600,
        (Some(d), [h, m]) => d * 86_400 + below(*h, 24, "hours")? * 3600 + below(*m, 60, "minutes")? * 60,
        (Some(d), [h, m, s]) => {
            d * 86_400 + below(*h, 24, "hours")? * 3600 + below(*m, 60, "minutes")? * 60 + below(*s, 60, "seconds")?
        }
        _ => return Err(bad("not a time limit")),
    };
    if seconds > i32::MAX as u64 {
        return Err(bad("longer than Slurm's longest limit (2^31 - 1 seconds, about 68 years)"));
    }
    Ok(t.to_string())
}

/// `--partition`: a partition name, or a comma-separated list of them (sbatch takes the
/// first that can run the job), of letters, digits, `_`, `-` and `.`, not beginning with `-`.
fn slurm_partition(p: &str) -> Result<String, Error> {
    printable("--partition", p)?;
    let name_ok = |n: &str| {
        !n.is_empty()
            && n.len() <= 64
            && !n.starts_with('-')
            && n.bytes().all(|b| b.is_ascii_alphanumeric() || matches!(b, b'_' | b'-' | b'.'))
    };
    if p.split(',').all(name_ok) {
        Ok(p.to_string())
    } else {
        Err(refused(
            "--partition",
            p,
            "is not a partition name: give one name, or several separated by commas, of letters, digits, '_', '-' and '.' (at most 64 characters each, not beginning with '-')",
        ))
    }
}

/// The value of an `#SBATCH --output=` line naming `dir/file`: sbatch reads a directive
/// line as words, not through a shell (no variables, no globs, no `~`): a word may be
/// quoted with `"` or `'`, a backslash escapes the next character, even inside quotes,
/// and an unquoted `#` starts a comment (Slurm's `get_argument`, src/sbatch/opt.c). So
/// the value is written in double quotes with `"` escaped, which carries spaces, `'`, `#`,
/// `$` and any non-ASCII text. `%` is doubled, as Slurm expands `%A`, `%j` and the like
/// in the name (`%%` is a `%`). A backslash is refused: one anywhere in the name turns off
/// Slurm's `%` replacements, so the logs would not be per task. `file` is ours, `%`
/// patterns included.
fn output_value(what: &str, dir: &str, file: &str) -> Result<String, Error> {
    printable(what, dir)?;
    if dir.contains('\\') {
        return Err(refused(
            what,
            dir,
            "contains a backslash, which Slurm's --output cannot carry (a backslash turns off its %A/%a/%j patterns, so every task would write one log); give a path without backslashes",
        ));
    }
    Ok(format!("\"{}/{file}\"", dir.replace('%', "%%").replace('"', "\\\"")))
}

/// The `#SBATCH` lines of a job, one `--option=value` each, the values checked or built
/// above (names and numbers are plain words).
fn directives(options: &[(&str, String)]) -> String {
    options.iter().map(|(k, v)| format!("#SBATCH --{k}={v}\n")).collect()
}

/// `text` quoted for a POSIX shell.
fn quote(text: &str) -> String {
    format!("'{}'", text.replace('\'', "'\\''"))
}

/// The absolute path `out` will have once created: its longest existing ancestor resolved
/// as `canonicalize` resolves it (links followed), the rest appended with `.` and `..`
/// resolved by name (those folders are created as written).
fn planned_absolute(out: &Path) -> std::io::Result<PathBuf> {
    use std::path::Component;
    let abs = if out.is_absolute() { out.to_path_buf() } else { std::env::current_dir()?.join(out) };
    let mut base = abs.as_path();
    let mut rest = Vec::new();
    loop {
        match std::fs::canonicalize(base) {
            Ok(mut p) => {
                for c in rest.iter().rev() {
                    match c {
                        Component::ParentDir => {
                            p.pop();
                        }
                        Component::Normal(name) => p.push(name),
                        _ => {}
                    }
                }
                return Ok(p);
            }
            Err(e) => match (base.components().next_back(), base.parent()) {
                (Some(last), Some(parent)) => {
                    rest.push(last);
                    base = parent;
                }
                _ => return Err(e),
            },
        }
    }
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
    // Before anything is written: every value and path the scripts carry.
    let mut options = Vec::new();
    if let Some(p) = &o.partition {
        options.push(("partition", slurm_partition(p)?));
    }
    if let Some(t) = &o.time {
        options.push(("time", slurm_time(t)?));
    }
    let study_path = std::fs::canonicalize(file).unwrap_or_else(|_| file.to_path_buf());
    let study = script_path("the study file", &study_path)?.to_string();
    let binary = script_path("this program's path", &o.binary)?.to_string();
    let planned =
        planned_absolute(out).map_err(|e| Error::Output { path: out.display().to_string(), message: e.to_string() })?;
    output_value("--out", script_path("--out", &planned)?, "")?;
    // The program that submits.
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
        // A link, file or special file there is refused, never followed.
        rotorshunt::files::ensure_dir(&d).map_err(|e| Error::io(&d, &e))?;
    }
    drop(lock);
    let abs = std::fs::canonicalize(out).map_err(|e| root.error("", e))?;
    // The folder as created (a link made meanwhile could differ from the plan).
    let abs_text = script_path("--out", &abs)?;
    let dir = abs.join(SLURM_DIR);
    let logs = format!("{abs_text}/{SLURM_DIR}/{LOGS}");
    let (array_script, merge_script, submit_script) =
        (dir.join(ARRAY_SCRIPT), dir.join(MERGE_SCRIPT), dir.join(SUBMIT_SCRIPT));
    // Every path below is printable UTF-8 (checked above), joined to names of ours.
    let shown = |p: &Path| quote(&p.display().to_string());
    let (bin, study_q, out_q) = (quote(&binary), quote(&study), quote(abs_text));
    let n = o.tasks;
    // Numbers the tool wrote (digits, `.`, `e`, `-`): nothing for the shell to expand.
    let limits: String = o.budget.flags().iter().map(|f| format!(" {f}")).collect();
    let mut array_options = vec![
        ("job-name", "rotorshunt-study".to_string()),
        ("array", format!("0-{}", n - 1)),
        ("cpus-per-task", o.cpus_per_task.to_string()),
        ("output", output_value("--out", &logs, "study-%A_%a.out")?),
    ];
    array_options.extend(options.iter().cloned());
    let mut merge_options = vec![
        ("job-name", "rotorshunt-merge".to_string()),
        ("cpus-per-task", "1".to_string()),
        ("output", output_value("--out", &logs, "merge-%j.out")?),
    ];
    merge_options.extend(options.iter().cloned());
    // The comments quote every path as the commands they show would need it.
    let array = format!(
        "#!/bin/bash
# A rotorshunt study as a Slurm array job, written by `rotorshunt study slurm` ({TOOL}).
# Study {study_q} (plan {}): {} cases in {n} shards, shard K (0-based) in array task K.
# Submit it with its merge job: sh {}
# After a failure: `rotorshunt study status {out_q}` prints the indices to resubmit,
#   sbatch --array=LIST {}
# The shard count is written below: SLURM_ARRAY_TASK_COUNT, _MIN and _MAX describe a
# submission (a resubmission of some indices changes them); the task reads only
# SLURM_ARRAY_TASK_ID. Its threads follow SLURM_CPUS_PER_TASK (RAYON_NUM_THREADS wins).
{}set -eu
exec {bin}{limits} study {study_q} --out {out_q} --shards {n}
",
        &identity.plan[..12],
        plan.len(),
        shown(&submit_script),
        shown(&array_script),
        directives(&array_options),
    );
    let merge = format!(
        "#!/bin/bash
# The merge job of a rotorshunt study array (`rotorshunt study slurm`, {TOOL}): builds
# summary/summary.{{csv,json,md}} from every finished case; exit 5 if a case failed or is missing.
{}set -eu
exec {bin} study merge {out_q}
",
        directives(&merge_options),
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
        shown(&array_script),
        shown(&merge_script),
    );
    let scripts = OutDir::planned(&dir, &inputs);
    scripts.write(ARRAY_SCRIPT, array.as_bytes())?;
    scripts.write(MERGE_SCRIPT, merge.as_bytes())?;
    scripts.write(SUBMIT_SCRIPT, submit_text.as_bytes())?;
    let mut text = format!(
        "study slurm: {} cases in {n} shards; wrote {}, {} and {}\n",
        plan.len(),
        array_script.display(),
        merge_script.display(),
        submit_script.display()
    );
    if let Some(sbatch) = sbatch {
        let shown = out.join(SLURM_DIR);
        let job = submit(&sbatch, &[], &array_script, &shown.join(ARRAY_SCRIPT))?;
        let after = [format!("--dependency=afterany:{job}")];
        let merge_job = submit(&sbatch, &after, &merge_script, &shown.join(MERGE_SCRIPT))?;
        text += &format!("submitted: array job {job} ({n} tasks), merge job {merge_job} (afterany:{job})\n");
    } else {
        text += &format!("submit with: sh {}\n", shown(&submit_script));
    }
    for n in notes {
        text += &n;
        text.push('\n');
    }
    Ok(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slurms_time_forms_and_no_others() {
        for t in ["0", "90", "90:30", "2:00:00", "48:00:00", "1-12", "1-12:30", "7-23:59:59", "365-0"] {
            assert_eq!(slurm_time(t).unwrap(), t);
        }
        assert_eq!(slurm_time("unlimited").unwrap(), "UNLIMITED");
        assert_eq!(slurm_time("Infinite").unwrap(), "INFINITE");
        for t in [
            "",
            "abc",
            "$(reboot)",
            "`id`",
            "2h",
            "1:60",
            "1:00:60",
            "1:60:00",
            "1-24",
            "1-1:60",
            "1-1:1:60",
            "1:2:3:4",
            "-1",
            "1-",
            "-",
            "1--2",
            "1-2-3",
            " 90",
            "90 ",
            "9 0",
            "１２",
            "99999999999",
            "1:",
            ":1",
            "+5",
            "1.5",
            "1\n",
            "35791395",
            "24856-0",
        ] {
            let e = slurm_time(t).unwrap_err().to_string();
            assert!(e.starts_with(&format!("--time {t:?}: ")) && !e.contains('\n'), "{t:?}: {e}");
        }
        // The longest: 2^31 - 1 seconds.
        assert!(slurm_time("35791394").is_ok() && slurm_time("24855-0").is_ok());
    }

    #[test]
    fn partitions_are_plain_names() {
        for p in ["debug", "gpu-a100", "p1,p2", "a.b_c"] {
            assert_eq!(slurm_partition(p).unwrap(), p);
        }
        for p in ["", "-x", "a,,b", ",a", "a,", "a b", "a\"b", "a'b", "a#b", "a;b", "a/b", "é", "a\nb", &"x".repeat(65)]
        {
            assert!(slurm_partition(p).unwrap_err().to_string().starts_with(&format!("--partition {p:?}: ")), "{p:?}");
        }
    }

    #[test]
    fn an_output_path_is_written_as_sbatch_reads_it() {
        assert_eq!(output_value("--out", "/a b/c", "x-%j.out").unwrap(), "\"/a b/c/x-%j.out\"");
        assert_eq!(
            output_value("--out", "/it's \"q\" #h $HOME 100%", "f").unwrap(),
            "\"/it's \\\"q\\\" #h $HOME 100%%/f\""
        );
        let e = output_value("--out", "/a\\b", "f").unwrap_err().to_string();
        assert!(e.contains("backslash") && e.starts_with("--out \"/a\\\\b\": "), "{e}");
        let e = output_value("--out", "/a\nb", "f").unwrap_err().to_string();
        assert!(e.contains("'\\n' (U+000A)") && !e.contains('\n'), "{e}");
        let e = printable("--time", "\u{1b}[31m").unwrap_err().to_string();
        assert!(e.contains("'\\u{1b}' (U+001B)") && !e.contains('\u{1b}'), "{e}");
        assert_eq!(directives(&[("array", "0-3".into())]), "#SBATCH --array=0-3\n");
    }

    #[test]
    fn the_planned_folder_is_what_creating_it_gives() {
        let base = std::env::temp_dir().join(format!("rotorshunt-planned-{}", std::process::id()));
        std::fs::create_dir_all(base.join("there")).unwrap();
        let base = std::fs::canonicalize(&base).unwrap();
        for rel in ["there", "new", "new/deeper", "there/../x", "a/./b", "n/../m/../o", "there/.."] {
            let planned = planned_absolute(&base.join(rel)).unwrap();
            std::fs::create_dir_all(base.join(rel)).unwrap();
            assert_eq!(planned, std::fs::canonicalize(base.join(rel)).unwrap(), "{rel}");
        }
        let _ = std::fs::remove_dir_all(&base);
    }
}
