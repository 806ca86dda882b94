//! Scripts and markup are built by escaping, not by pasting (issue 26, "Injection").
//!
//! `study slurm`: 30 hostile strings (line breaks, quotes, `$(…)`, backticks, `;`, `&&`,
//! `|`, spaces, tabs, globs, `~`, a leading `-`, `#`, `%`, a backslash, Unicode, `$HOME`,
//! `..`, very long names, a terminal escape) as the study file's path, as `--out`, as the
//! path of the binary the scripts run, as the `--sbatch` program's path and as the value
//! of every value flag (`--time`, `--partition`, `--tasks`, `--cpus-per-task`). Each run
//! either exits 2 with one error line naming the flag or path and the value (escaped),
//! having written nothing, or writes scripts that pass `bash -n` and, run with stubs for
//! `sbatch` and for the binary (each records its argv, NUL-separated, and `sbatch` the
//! script it was given), run exactly the intended commands: every path arrives as one
//! argument, byte for byte, and no `touch` hidden in a name leaves its marker anywhere.
//! The `#SBATCH` lines are read as sbatch reads them (a port of Slurm's `get_argument`,
//! src/sbatch/opt.c, 22.05): all before the first command, with `--array` and an
//! `--output` that names the folder's log once Slurm's `%` patterns are expanded.
//!
//! `report.html`: a design report whose title is full of markup and a terminal escape,
//! opened in headless Chromium (`--dump-dom`): no element from the title, the title as
//! text in `<title>` and `<h1>`; and no raw escape byte on the terminal.

use crate::common;

use std::collections::BTreeSet;
use std::ffi::OsStr;
use std::os::unix::ffi::OsStrExt;
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// The marker every injected command would create (in the folder it runs in).
const MARK: &str = "INJECTED";

/// The hostile strings: names of one path component (no `/`), but `..` and the deep path.
fn hostile() -> Vec<(&'static str, String)> {
    let long = "L".repeat(200);
    let deep = vec!["D".repeat(100); 15].join("/");
    vec![
        ("newline", "new\nline".into()),
        ("cr", "carriage\rreturn".into()),
        ("single quote", "it's'".into()),
        ("double quote", "say \"hi\"".into()),
        ("command substitution", format!("$(touch {MARK}-cs)")),
        ("backticks", format!("`touch {MARK}-bt`")),
        ("semicolon", format!("a;touch {MARK}-semi")),
        ("and", format!("a&&touch {MARK}-and")),
        ("pipe", format!("a|touch {MARK}-pipe")),
        ("spaces", "two  spaces ".into()),
        ("tab", "tab\there".into()),
        ("glob", "star*?[a]".into()),
        ("tilde", "~tilde".into()),
        ("leading dash", "-rf --help".into()),
        ("hash", "#not a comment".into()),
        ("percent", "100%A_%a%j%%".into()),
        ("backslash", "back\\slash\\n".into()),
        ("accent", "café é".into()),
        ("cjk", "中文路径".into()),
        ("rtl mark", "rtl\u{200f}mark\u{202e}over".into()),
        ("emoji", "emoji🙂🚀".into()),
        ("home", "$HOME${HOME}".into()),
        ("dotdot", "sub/../up".into()),
        ("very long", long),
        ("deep", deep),
        ("quote mix", format!("'\"$(touch {MARK}-mix)\"'")),
        ("double-quoted command", format!("\"; touch {MARK}-dq; \"")),
        ("terminal escape", "esc\u{1b}[31mred\u{1b}]0;title\u{7}".into()),
        ("sbatch directive", format!("x\n#SBATCH --output=/tmp/evil\ntouch {MARK}-nl")),
        ("redirections", format!("a>{MARK}-gt<b {{a,b}} !bang")),
    ]
}

/// Whether the scripts cannot carry `s` (a control character; a backslash in `--out`).
fn has_control(s: &str) -> bool {
    s.chars().any(char::is_control)
}

/// `s` as the error message shows it (Rust's `{:?}`: quoted, control characters escaped).
fn shown(s: &str) -> String {
    format!("{s:?}")
}

struct Setup {
    root: PathBuf,
    /// The copy of the binary the generating runs use, under a hostile folder name (the
    /// scripts call it by this path).
    binary: PathBuf,
    /// A stub `sbatch` in this folder (put first in PATH).
    sbatch_dir: PathBuf,
    /// The stubs record here: `N.argv` (NUL-separated) and, for sbatch, `N.script`.
    records: PathBuf,
}

/// A stub that records its arguments; `sbatch` also its last argument's file, and prints
/// a job id.
fn stub(path: &Path, sbatch: bool) {
    let extra = if sbatch {
        "for a in \"$@\"; do last=$a; done\ncat -- \"$last\" > \"$RECORDS/$n.script\"\necho '4242;cluster'\n"
    } else {
        ""
    };
    let body = format!(
        "#!/bin/sh\nn=$(ls \"$RECORDS\" | grep -c argv)\nfor a in \"$@\"; do printf '%s\\0' \"$a\"; done > \"$RECORDS/$n.argv\"\n{extra}"
    );
    std::fs::write(path, body).unwrap();
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o755)).unwrap();
}

/// The recorded calls, in order: (argv, the script given to sbatch if any).
/// One recorded call of a stub: its arguments, and the script it was given (if any).
type Call = (Vec<Vec<u8>>, Option<Vec<u8>>);

fn calls(records: &Path) -> Vec<Call> {
    let mut n = 0;
    let mut out = Vec::new();
    while let Ok(argv) = std::fs::read(records.join(format!("{n}.argv"))) {
        let args = argv.split(|b| *b == 0).map(<[u8]>::to_vec).collect::<Vec<_>>();
        let args = args[..args.len() - 1].to_vec(); // the last NUL ends the last argument
        out.push((args, std::fs::read(records.join(format!("{n}.script"))).ok()));
        n += 1;
    }
    out
}

fn clear(records: &Path) {
    let _ = std::fs::remove_dir_all(records);
    std::fs::create_dir_all(records).unwrap();
}

fn setup(name: &str) -> Setup {
    let root = common::scratch(&format!("injection-{name}"));
    let root = std::fs::canonicalize(&root).unwrap();
    let bin_dir = root.join(format!("bin $(touch {MARK}-bin) 'q' \"d\" `x` ;"));
    std::fs::create_dir_all(&bin_dir).unwrap();
    let binary = bin_dir.join("rotorshunt");
    std::fs::copy(env!("CARGO_BIN_EXE_rotorshunt"), &binary).unwrap();
    let sbatch_dir = root.join("stub-bin");
    std::fs::create_dir_all(&sbatch_dir).unwrap();
    stub(&sbatch_dir.join("sbatch"), true);
    let records = root.join("records");
    clear(&records);
    Setup { root, binary, sbatch_dir, records }
}

/// A study file of 12 cases at `path` (its folders created).
fn study_file(path: &Path) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(
        path,
        format!(
            "base = \"{}\"\nphi = [1150.0, 1350.0]\nbeta_max = 0.5\nlevel = 0.3\nphi_op = 1230.0\n\n[sweep]\nspeed = [1000.0, 2000.0, 3000.0]\n\"circuit.branches[0].resistance\" = [0.0, 10.0, 50.0, 100.0]\n",
            common::problem_path("design-widest-band.toml")
        ),
    )
    .unwrap();
}

fn run(s: &Setup, cwd: &Path, args: &[&OsStr]) -> Output {
    output(
        Command::new(&s.binary)
            .args(args)
            .current_dir(cwd)
            .env_remove("SLURM_ARRAY_TASK_ID")
            .env("RAYON_NUM_THREADS", "1"),
    )
}

/// `cmd`'s output, retried while its program is "busy": a binary copy (or a stub script)
/// just written is busy for a moment, as a child spawned by another test thread while it
/// was open for writing holds that descriptor until it execs.
fn output(cmd: &mut Command) -> Output {
    let mut attempts = 0;
    loop {
        match cmd.output() {
            Err(e) if e.kind() == std::io::ErrorKind::ExecutableFileBusy && attempts < 100 => {
                attempts += 1;
                std::thread::sleep(std::time::Duration::from_millis(20));
            }
            other => return other.unwrap(),
        }
    }
}

/// A refused run: exit 2, an `error: ` line naming `what` and the value as shown (the
/// whole message on one line: the scripts' own refusals escape a line break), and `out`
/// not created.
fn assert_refused(o: &Output, what: &str, value: &str, out: &Path, label: &str) {
    let e = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{label}: {e}");
    assert!(e.starts_with("error: ") && e.lines().count() == 1, "{label}: one error line: {e:?}");
    assert_refused_as(o, what, value, out, label);
}

/// A refusal by another layer (clap, the shard count): exit 2 and an `error: ` message
/// naming `what`, no raw escape or carriage return, `out` not created.
fn assert_refused_as(o: &Output, what: &str, value: &str, out: &Path, label: &str) {
    let e = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{label}: {e}");
    assert!(e.starts_with("error: "), "{label}: {e:?}");
    assert!(e.contains(what), "{label}: {what} not named: {e}");
    assert!(e.contains(value), "{label}: value {value} not shown: {e}");
    assert!(!e.contains('\u{1b}') && !e.contains('\r'), "{label}: raw control character in {e:?}");
    assert!(!out.exists(), "{label}: {} was created", out.display());
}

/// sbatch's reading of a directive line (after `#SBATCH`): Slurm 22.05's `get_argument`
/// (src/sbatch/opt.c) applied until the line ends: words split at unquoted whitespace,
/// `"`/`'` quote, a backslash escapes the next character (inside quotes too), an
/// unquoted `#` ends the line.
fn sbatch_words(line: &[u8]) -> Vec<Vec<u8>> {
    let mut words = Vec::new();
    let mut i = 0;
    loop {
        while i < line.len() && line[i].is_ascii_whitespace() {
            i += 1;
        }
        if i >= line.len() {
            return words;
        }
        let (mut word, mut quoted, mut q, mut escape, mut any) = (Vec::new(), false, 0u8, false, false);
        while i < line.len() && (quoted || !line[i].is_ascii_whitespace()) && line[i] != b'\n' {
            let c = line[i];
            if escape {
                escape = false;
            } else if c == b'\\' {
                escape = true;
                i += 1;
                continue;
            } else if quoted {
                if c == q {
                    quoted = false;
                    i += 1;
                    continue;
                }
            } else if c == b'"' || c == b'\'' {
                quoted = true;
                q = c;
                i += 1;
                continue;
            } else if c == b'#' {
                i = line.len();
                break;
            }
            word.push(c);
            any = true;
            i += 1;
        }
        assert!(!quoted, "sbatch: unmatched quote in {:?}", text(line));
        if any {
            words.push(word);
        }
    }
}

/// The options sbatch reads from a script: the words of every `#SBATCH` line before the
/// first line that is a command (sbatch stops there), and whether an `#SBATCH` line comes
/// after it.
fn sbatch_options(script: &[u8]) -> (Vec<Vec<u8>>, bool) {
    let mut words = Vec::new();
    let mut header = true;
    let mut late = false;
    for line in script.split(|b| *b == b'\n') {
        if let Some(rest) = line.strip_prefix(b"#SBATCH") {
            if header {
                words.extend(sbatch_words(rest));
            } else {
                late = true;
            }
        } else if line.iter().find(|b| !b.is_ascii_whitespace()).is_some_and(|b| *b != b'#') {
            header = false;
        }
    }
    (words, late)
}

/// Slurm's expansion of a batch job's output name (src/slurmd/common/fname.c): `%%` is
/// `%`, `%A` the array job, `%a` the task, `%j` the job; a backslash turns it off.
fn expand_output(name: &[u8], job: &str, task: &str) -> Vec<u8> {
    assert!(!name.contains(&b'\\'), "a backslash in the output name turns off its patterns");
    let mut out = Vec::new();
    let mut i = 0;
    while i < name.len() {
        if name[i] == b'%' && i + 1 < name.len() {
            match name[i + 1] {
                b'%' => out.push(b'%'),
                b'A' | b'j' => out.extend(job.as_bytes()),
                b'a' => out.extend(task.as_bytes()),
                other => panic!("unexpected pattern %{}", other as char),
            }
            i += 2;
        } else {
            out.push(name[i]);
            i += 1;
        }
    }
    out
}

/// Every entry below `dir` named like a marker.
fn markers(dir: &Path, found: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for e in entries.flatten() {
        let p = e.path();
        if e.file_name().as_bytes().starts_with(MARK.as_bytes()) {
            found.push(p.clone());
        }
        if e.file_type().is_ok_and(|t| t.is_dir()) {
            markers(&p, found);
        }
    }
}

fn bash_n(script: &Path) {
    let o = Command::new("bash").arg("-n").arg(script).output().unwrap();
    assert!(o.status.success(), "bash -n {}: {}", script.display(), text(&o.stderr));
}

/// The scripts written for the study `study` (canonical) into `out` (canonical): they
/// pass `bash -n`, sbatch reads the intended options from them, and run with the stubs
/// they run exactly the intended commands, each path one argument, byte for byte.
fn check_scripts(s: &Setup, study: &Path, out: &Path, tasks: u32, extra: &[(&str, &str)], label: &str) {
    let dir = out.join("slurm");
    let (array, merge, submit) = (dir.join("study.sbatch"), dir.join("merge.sbatch"), dir.join("submit.sh"));
    for p in [&array, &merge, &submit] {
        bash_n(p);
    }
    let bytes = |p: &Path| p.as_os_str().as_bytes().to_vec();
    let logs = bytes(&dir.join("logs"));
    for (script, name, fixed) in [
        (&array, "study-4242_0.out", vec![format!("--job-name=rotorshunt-study"), format!("--array=0-{}", tasks - 1)]),
        (&merge, "merge-4242.out", vec!["--job-name=rotorshunt-merge".to_string()]),
    ] {
        let body = std::fs::read(script).unwrap();
        let (words, late) = sbatch_options(&body);
        assert!(!late, "{label}: an #SBATCH line after the first command in {}", text(&body));
        let mut want: BTreeSet<Vec<u8>> = fixed.iter().map(|w| w.as_bytes().to_vec()).collect();
        for (k, v) in extra {
            want.insert(format!("--{k}={v}").into_bytes());
        }
        let mut output = None;
        for w in &words {
            if let Some(v) = w.strip_prefix(b"--output=") {
                output = Some(expand_output(v, "4242", "0"));
            } else if !w.starts_with(b"--cpus-per-task=") {
                assert!(want.remove(w), "{label}: unexpected sbatch option {:?} in {}", text(w), text(&body));
            }
        }
        assert!(want.is_empty(), "{label}: sbatch options missing: {want:?} in {}", text(&body));
        let mut expected = logs.clone();
        expected.extend(format!("/{name}").as_bytes());
        assert_eq!(output.as_deref().map(text), Some(text(&expected)), "{label}: --output in {}", text(&body));
        assert_eq!(output.unwrap(), expected, "{label}: --output bytes");
        // No raw input in a comment: every line is an #SBATCH line, a command, or a
        // comment without a control character.
        assert!(!body.iter().any(|b| *b == b'\r' || *b == 0x1b), "{label}: raw control bytes");
    }
    // Run them: the array task, the merge job and submit.sh, from a folder of their own.
    let cwd = s.root.join("run");
    std::fs::create_dir_all(&cwd).unwrap();
    let path = format!("{}:{}", s.sbatch_dir.display(), std::env::var("PATH").unwrap_or_default());
    let exe = |program: &str, script: &Path, task: Option<&str>| {
        clear(&s.records);
        let mut c = Command::new(program);
        c.arg(script).current_dir(&cwd).env("PATH", &path).env("RECORDS", &s.records);
        match task {
            Some(t) => c.env("SLURM_ARRAY_TASK_ID", t),
            None => c.env_remove("SLURM_ARRAY_TASK_ID"),
        };
        let o = c.output().unwrap();
        assert!(o.status.success(), "{label}: {program} {}: {}", script.display(), text(&o.stderr));
        (calls(&s.records), o)
    };
    let arg = |x: &str| x.as_bytes().to_vec();
    let (c, _) = exe("bash", &array, Some("0"));
    let want = vec![arg("study"), bytes(study), arg("--out"), bytes(out), arg("--shards"), arg(&tasks.to_string())];
    assert_eq!(c.len(), 1, "{label}: the array task ran {} commands", c.len());
    assert_eq!(c[0].0, want, "{label}: the array task's command");
    let (c, _) = exe("bash", &merge, None);
    assert_eq!(c.len(), 1, "{label}");
    assert_eq!(c[0].0, vec![arg("study"), arg("merge"), bytes(out)], "{label}: the merge job's command");
    let (c, o) = exe("sh", &submit, None);
    assert_eq!(c.len(), 2, "{label}: submit.sh ran sbatch {} times", c.len());
    assert_eq!(c[0].0, vec![arg("--parsable"), bytes(&array)], "{label}: submit.sh's first sbatch");
    assert_eq!(c[1].0, vec![arg("--parsable"), arg("--dependency=afterany:4242"), bytes(&merge)], "{label}");
    assert_eq!(c[0].1.as_deref(), Some(&std::fs::read(&array).unwrap()[..]), "{label}: the script sbatch got");
    assert_eq!(c[1].1.as_deref(), Some(&std::fs::read(&merge).unwrap()[..]), "{label}");
    assert_eq!(text(&o.stdout), format!("array job 4242 ({tasks} tasks), merge job 4242\n"), "{label}");
}

/// Swap the binary copy for a recording stub while `f` runs the scripts.
fn with_stub_binary(s: &Setup, f: impl FnOnce()) {
    let real = s.binary.with_extension("real");
    std::fs::rename(&s.binary, &real).unwrap();
    stub(&s.binary, false);
    let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f));
    std::fs::remove_file(&s.binary).unwrap();
    std::fs::rename(&real, &s.binary).unwrap();
    if let Err(e) = r {
        std::panic::resume_unwind(e);
    }
}

fn no_markers(s: &Setup) {
    let mut found = Vec::new();
    markers(&s.root, &mut found);
    for e in std::fs::read_dir(common::root()).unwrap().flatten() {
        if e.file_name().as_bytes().starts_with(MARK.as_bytes()) {
            found.push(e.path());
        }
    }
    assert!(found.is_empty(), "injected commands ran: {found:?}");
}

#[test]
fn hostile_paths_are_quoted_or_refused() {
    let s = setup("paths");
    // Generated first (with the real binary), run afterwards (with the stub in its place).
    let mut written: Vec<(PathBuf, PathBuf, String)> = Vec::new();
    for (i, (label, h)) in hostile().into_iter().enumerate() {
        // As the study file's path: a folder of that name, given relative (after `--`).
        let cwd = s.root.join(format!("study-{i}"));
        std::fs::create_dir_all(&cwd).unwrap();
        let rel = PathBuf::from(&h).join("study.toml");
        study_file(&cwd.join(&rel));
        let out = cwd.join("out");
        let o = run(
            &s,
            &cwd,
            &[
                "study".as_ref(),
                "slurm".as_ref(),
                "--out=out".as_ref(),
                "--tasks".as_ref(),
                "3".as_ref(),
                "--".as_ref(),
                rel.as_os_str(),
            ],
        );
        let study = std::fs::canonicalize(cwd.join(&rel)).unwrap();
        let label_s = format!("study file {label}");
        if has_control(&h) {
            assert_refused(&o, "the study file", &shown(study.to_str().unwrap()), &out, &label_s);
        } else {
            assert!(o.status.success(), "{label_s}: {}", text(&o.stderr));
            written.push((study, std::fs::canonicalize(&out).unwrap(), label_s));
        }

        // As --out: a folder of that name (created by the run), given relative.
        let cwd = s.root.join(format!("out-{i}"));
        let study = cwd.join("study.toml");
        study_file(&study);
        let mut flag = std::ffi::OsString::from("--out=");
        flag.push(&h);
        let o = run(
            &s,
            &cwd,
            &[
                "study".as_ref(),
                "slurm".as_ref(),
                "study.toml".as_ref(),
                flag.as_os_str(),
                "--tasks".as_ref(),
                "3".as_ref(),
            ],
        );
        let label_o = format!("--out {label}");
        let planned = if label == "dotdot" { cwd.join("up") } else { cwd.join(&h) };
        if has_control(&h) || h.contains('\\') {
            assert_refused(
                &o,
                "--out",
                &shown(planned.to_str().unwrap()),
                &cwd.join(h.split('/').next().unwrap()),
                &label_o,
            );
        } else {
            assert!(o.status.success(), "{label_o}: {}", text(&o.stderr));
            let stdout = text(&o.stdout);
            assert!(!stdout.contains('\u{1b}'), "{label_o}: {stdout:?}");
            let out = std::fs::canonicalize(&planned).unwrap();
            written.push((std::fs::canonicalize(&study).unwrap(), out, label_o));
        }
    }
    assert!(written.len() >= 40, "only {} runs wrote scripts", written.len());
    with_stub_binary(&s, || {
        for (study, out, label) in &written {
            check_scripts(&s, study, out, 3, &[], label);
        }
    });
    no_markers(&s);
}

#[test]
fn hostile_values_are_refused_and_slurms_forms_written() {
    let s = setup("values");
    let cwd = s.root.join("w");
    let study = cwd.join("study.toml");
    study_file(&study);
    let fresh = cwd.join("never");
    fn base<'a>(extra: &[&'a OsStr]) -> Vec<&'a OsStr> {
        let mut a: Vec<&OsStr> =
            vec!["study".as_ref(), "slurm".as_ref(), "study.toml".as_ref(), "--out".as_ref(), "never".as_ref()];
        a.extend_from_slice(extra);
        a
    }
    for (label, h) in hostile() {
        let value = |flag: &str| format!("{flag}={h}");
        for flag in ["--time", "--partition"] {
            let v = value(flag);
            let o = run(&s, &cwd, &base(&["--tasks=2".as_ref(), v.as_ref()]));
            assert_refused(&o, flag, &shown(&h), &fresh, &format!("{flag} {label}"));
        }
        let v = value("--tasks");
        let o = run(&s, &cwd, &base(&[v.as_ref()]));
        assert_refused_as(&o, "--tasks", "", &fresh, &format!("--tasks {label}"));
        let v = value("--cpus-per-task");
        let o = run(&s, &cwd, &base(&["--tasks=2".as_ref(), v.as_ref()]));
        assert_refused_as(&o, "--cpus-per-task", "", &fresh, &format!("--cpus-per-task {label}"));
        // --sbatch names a program run without a shell: a missing one is refused by name.
        let v = value("--sbatch");
        let o = run(&s, &cwd, &base(&["--tasks=2".as_ref(), "--submit".as_ref(), v.as_ref()]));
        assert_refused_as(&o, "cannot submit: the program", "", &fresh, &format!("--sbatch {label}"));
    }
    // Slurm's time forms, and forms that are not.
    for t in [
        "abc",
        "$(touch INJECTED-t)",
        "1:60",
        "1:00:60",
        "1:60:00",
        "1-24",
        "1-1:60",
        "",
        "2h",
        "1:2:3:4",
        "-1",
        "1-",
        "1--2",
        "1-2-3",
        " 90",
        "90 ",
        "１２",
        "99999999999",
        "1-2:3:4:5",
        ":30",
        "1:",
        "+5",
        "0x10",
        "1.5",
    ] {
        let v = format!("--time={t}");
        let o = run(&s, &cwd, &base(&["--tasks=2".as_ref(), v.as_ref()]));
        assert_refused(&o, "--time", &shown(t), &fresh, &format!("--time {t:?}"));
    }
    for p in ["", "-x", "a,,b", "a b", ",a", "a,", "p\"q", "p'q", "p;q", "p/q", "é"] {
        let v = format!("--partition={p}");
        let o = run(&s, &cwd, &base(&["--tasks=2".as_ref(), v.as_ref()]));
        assert_refused(&o, "--partition", &shown(p), &fresh, &format!("--partition {p:?}"));
    }
    let mut written = Vec::new();
    let good = [
        ("90", "debug"),
        ("90:30", "gpu-a100"),
        ("2:00:00", "p1,p2"),
        ("1-12", "a.b_c"),
        ("1-12:30", "X"),
        ("7-23:59:59", "long"),
        ("UNLIMITED", "short"),
        ("0", "q"),
    ];
    for (k, (t, p)) in good.iter().enumerate() {
        let out = format!("good-{k}");
        let o = run(
            &s,
            &cwd,
            &[
                "study".as_ref(),
                "slurm".as_ref(),
                "study.toml".as_ref(),
                "--out".as_ref(),
                out.as_ref(),
                "--tasks".as_ref(),
                "4".as_ref(),
                "--time".as_ref(),
                t.as_ref(),
                "--partition".as_ref(),
                p.as_ref(),
            ],
        );
        assert!(o.status.success(), "--time {t} --partition {p}: {}", text(&o.stderr));
        written.push((cwd.join(&out), *t, *p));
    }
    let o = run(
        &s,
        &cwd,
        &[
            "study".as_ref(),
            "slurm".as_ref(),
            "study.toml".as_ref(),
            "--out".as_ref(),
            "inf".as_ref(),
            "--tasks".as_ref(),
            "1".as_ref(),
            "--time".as_ref(),
            "infinite".as_ref(),
        ],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let inf = std::fs::read_to_string(cwd.join("inf/slurm/study.sbatch")).unwrap();
    assert!(inf.contains("\n#SBATCH --time=INFINITE\n"), "{inf}");
    let study = std::fs::canonicalize(&study).unwrap();
    with_stub_binary(&s, || {
        for (out, t, p) in &written {
            let out = std::fs::canonicalize(out).unwrap();
            check_scripts(
                &s,
                &study,
                &out,
                4,
                &[("time", t), ("partition", p)],
                &format!("--time {t} --partition {p}"),
            );
        }
    });
    no_markers(&s);
}

#[test]
fn submit_runs_the_sbatch_it_names_with_the_scripts_as_one_argument() {
    let s = setup("submit");
    for (i, (label, h)) in hostile().into_iter().enumerate() {
        let cwd = s.root.join(format!("w-{i}"));
        study_file(&cwd.join("study.toml"));
        let program = cwd.join(&h).join("sbatch");
        std::fs::create_dir_all(program.parent().unwrap()).unwrap();
        stub(&program, true);
        clear(&s.records);
        let o = output(
            Command::new(&s.binary)
                .args(["study", "slurm", "study.toml", "--out", "o", "--tasks", "2", "--submit", "--sbatch"])
                .arg(&program)
                .current_dir(&cwd)
                .env("RECORDS", &s.records),
        );
        assert!(o.status.success(), "--sbatch {label}: {}", text(&o.stderr));
        let stdout = text(&o.stdout);
        assert!(stdout.contains("submitted: array job 4242 (2 tasks), merge job 4242 (afterany:4242)"), "{stdout}");
        let dir = std::fs::canonicalize(cwd.join("o/slurm")).unwrap();
        let b = |p: PathBuf| p.into_os_string().into_vec();
        let c = calls(&s.records);
        assert_eq!(c.len(), 2, "--sbatch {label}");
        assert_eq!(c[0].0, vec![b"--parsable".to_vec(), b(dir.join("study.sbatch"))], "--sbatch {label}");
        assert_eq!(
            c[1].0,
            vec![b"--parsable".to_vec(), b"--dependency=afterany:4242".to_vec(), b(dir.join("merge.sbatch"))],
            "--sbatch {label}"
        );
    }
    no_markers(&s);
}

use std::os::unix::ffi::OsStringExt;

fn chromium() -> Option<PathBuf> {
    ["/usr/bin/chromium", "/usr/bin/chromium-browser"].iter().map(PathBuf::from).find(|p| p.exists())
}

/// The title of the report test: markup that would close `<title>`, run a script, load an
/// image and set bold, and a terminal escape (as TOML escapes, for `--set`).
const TITLE_TOML: &str = r#"title="</title><script>alert(1)</script><img src=x onerror=alert(2)><b>bold</b> *em* [l](javascript:alert(3)) \u001b[31mred""#;

#[test]
fn a_title_full_of_markup_is_text_in_the_report_and_on_the_terminal() {
    let dir = common::scratch("injection-report");
    let out = dir.join("design");
    let problem = common::problem_path("design-widest-band.toml");
    // A small model, so the design takes seconds.
    let small = ["shaft.elements=8", "disks[0].node=2", "analysis.reduced_modes=4"];
    let mut c = Command::new(env!("CARGO_BIN_EXE_rotorshunt"));
    c.args(["design", &problem, "--out", out.to_str().unwrap(), "--set", TITLE_TOML]);
    for o in small {
        c.args(["--set", o]);
    }
    let run = c.output().unwrap();
    assert!(run.status.code().is_some_and(|c| c == 0 || c == 3 || c == 4), "{}", text(&run.stderr));
    for (name, stream) in [("stdout", &run.stdout), ("stderr", &run.stderr)] {
        assert!(!stream.contains(&0x1b), "raw escape on {name}: {:?}", text(stream));
    }
    // `check` prints the title: shown, not acted on.
    let mut c = Command::new(env!("CARGO_BIN_EXE_rotorshunt"));
    c.args(["check", &problem, "--set", TITLE_TOML]);
    let check = c.output().unwrap();
    assert!(check.status.success(), "{}", text(&check.stderr));
    let stdout = text(&check.stdout);
    assert!(!check.stdout.contains(&0x1b) && !check.stderr.contains(&0x1b), "{stdout:?}");
    assert!(stdout.contains("\\u{1b}[31mred"), "the escape shown as text: {stdout}");

    let page = std::fs::read_to_string(out.join("report.html")).expect("report.html written");
    assert!(!page.contains('\u{1b}'), "raw escape in report.html");
    for bad in ["<script", "<b>", "href=\"javascript", "<img src=\"x\"", "<img src=x"] {
        assert!(!page.contains(bad), "report.html contains {bad}");
    }
    let Some(bin) = chromium() else {
        if std::env::var("ROTORSHUNT_SKIP_BROWSER").as_deref() == Ok("1") {
            eprintln!("SKIPPED: no chromium (ROTORSHUNT_SKIP_BROWSER=1)");
            return;
        }
        panic!("no chromium at /usr/bin/chromium: `apt-get install chromium` (.ci/run does), or set ROTORSHUNT_SKIP_BROWSER=1");
    };
    let url = format!("file://{}", out.join("report.html").display());
    let dom = Command::new("timeout")
        .arg("60")
        .arg(&bin)
        .args(["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking", "--no-first-run"])
        .arg("--host-resolver-rules=MAP * ~NOTFOUND")
        .args(["--virtual-time-budget=5000", "--dump-dom", &url])
        .output()
        .unwrap();
    assert!(dom.status.success(), "chromium failed: {}", text(&dom.stderr));
    let dom = text(&dom.stdout);
    for bad in ["<script", "<b>", "onerror=\"", "src=\"x\"", "href=\"javascript", "<em>em</em>"] {
        assert!(!dom.contains(bad), "the DOM holds {bad} from the title");
    }
    let escaped = "&lt;/title&gt;&lt;script&gt;alert(1)&lt;/script&gt;&lt;img src=x onerror=alert(2)&gt;&lt;b&gt;bold&lt;/b&gt; *em* [l](javascript:alert(3)) \\u{1b}[31mred";
    let title = &dom[dom.find("<title>").expect("a title") + 7..dom.find("</title>").unwrap()];
    assert_eq!(title, escaped, "the <title> is the text");
    let h1 = &dom[dom.find("<h1>").expect("a heading") + 4..dom.find("</h1>").unwrap()];
    assert_eq!(h1, format!("Shunt design report: {escaped}"), "the <h1> is the text");
}
