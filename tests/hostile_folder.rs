//! A hostile or careless folder (issue 26) for every command with `--out`: links in
//! place of the names the tool records or uses, tampered records naming `../x` and
//! absolute paths, a user's folders named like staging folders, FIFOs and device nodes
//! where an output goes. Every file outside `--out` stays byte-identical and in place,
//! and each plant is refused (exit 2, the plant named) or ignored with a warning.
//! The study subcommands have their own test (tests/hostile_study.rs).

use crate::common;

use std::path::{Path, PathBuf};

/// A node the test makes where an output goes: what it is, and how to make it.
type Maker = (&'static str, Box<dyn Fn(&Path) -> bool>);

fn sha256_hex(bytes: &[u8]) -> String {
    use sha2::{Digest, Sha256};
    Sha256::digest(bytes).iter().map(|b| format!("{b:02x}")).collect()
}

/// A character device like /dev/null at `path`; false when this process may not make
/// one (not root).
fn mknod_null(path: &Path) -> bool {
    let c = std::ffi::CString::new(path.to_str().unwrap()).unwrap();
    // SAFETY: a valid NUL-terminated path; makedev(1, 3) is /dev/null's number.
    unsafe { libc::mknod(c.as_ptr(), libc::S_IFCHR | 0o666, libc::makedev(1, 3)) == 0 }
}

fn is_root() -> bool {
    // SAFETY: geteuid has no preconditions.
    unsafe { libc::geteuid() == 0 }
}

struct Command_ {
    name: &'static str,
    args: Vec<String>,
    /// One file the command writes.
    output: &'static str,
}

fn commands() -> Vec<Command_> {
    let p = common::problem_path;
    let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    let design = p("design-widest-band.toml");
    vec![
        Command_ {
            name: "chart",
            args: s(&["chart", &p("paper-open.toml"), "--phi", "500", "--beta", "0.1"]),
            output: "chart.json",
        },
        Command_ {
            name: "campbell",
            args: s(&["campbell", &p("paper-open.toml"), "--speeds", "0:200:100"]),
            output: "campbell.json",
        },
        Command_ {
            name: "unbalance",
            args: s(&["unbalance", &p("fig8-eta200.toml"), "--speeds", "250:500:50"]),
            output: "unbalance.json",
        },
        Command_ {
            name: "response",
            args: s(&["response", &p("fig11-closed-2000.toml"), "--phi", "1200", "--beta", "0.3", "--periods", "3"]),
            output: "response.json",
        },
        Command_ {
            name: "regions",
            args: s(&[
                "regions",
                &p("fig11-closed-2000.toml"),
                "--phi",
                "1200:1205",
                "--beta-max",
                "0.4",
                "--level",
                "0.3",
            ]),
            output: "regions.json",
        },
        Command_ {
            name: "design",
            args: s(&[
                &["design", design.as_str()][..],
                &common::COARSE_MODEL_ARGS,
                &[
                    "--set",
                    "design.starts=1",
                    "--set",
                    "design.max_iterations=2",
                    "--set",
                    "design.phi_range=[1000.0, 1500.0]",
                ],
            ]
            .concat()),
            output: "tuned.toml",
        },
    ]
}

fn run(c: &Command_, out: &Path) -> std::process::Output {
    common::bin().args(&c.args).arg("--quiet").arg("--out").arg(out).output().unwrap()
}

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Design's exit codes 3 and 4 (infeasible, not verified) still write the folder.
fn wrote(o: &std::process::Output) -> bool {
    matches!(o.status.code(), Some(0 | 3 | 4))
}

#[test]
fn every_out_command_ignores_or_refuses_each_plant_and_touches_nothing_outside() {
    let root = common::tmp("hostile-folder");
    let mut plants = 0;
    for c in commands() {
        let parent = root.join(c.name);
        std::fs::create_dir_all(parent.join("victim_dir")).unwrap();
        let out = parent.join("out");
        let victim = parent.join("victim.txt");
        std::fs::write(&victim, "the user's file outside --out\n").unwrap();
        std::fs::write(parent.join("victim_dir/inner.txt"), "inside the user's folder\n").unwrap();
        let first = run(&c, &out);
        assert!(wrote(&first), "{}: {}", c.name, stderr(&first));

        // Ignored plants: the run succeeds, says so, and leaves them all alone.
        let manifest = out.join(".rotorshunt-out.json");
        let mut m: serde_json::Value = serde_json::from_slice(&std::fs::read(&manifest).unwrap()).unwrap();
        let hash = sha256_hex(&std::fs::read(&victim).unwrap());
        m["commands"][c.name]["../victim.txt"] = hash.clone().into();
        m["commands"][c.name][victim.to_str().unwrap()] = hash.into();
        std::fs::write(&manifest, m.to_string()).unwrap();
        for user in [".rotorshunt-tmp.out.vm-999999", ".rotorshunt-tmp.out.0123456789abcdef01234567"] {
            std::fs::create_dir(parent.join(user)).unwrap();
            std::fs::write(parent.join(user).join("mine.txt"), "the user's\n").unwrap();
        }
        // A record forged with the name's token, of a process that runs (this test).
        let forged = parent.join(".rotorshunt-tmp.out.aaaaaaaaaaaaaaaaaaaaaaaa");
        std::fs::create_dir(&forged).unwrap();
        let record = serde_json::json!({"format": 1, "commands": {},
            "staged_by": {"token": "aaaaaaaaaaaaaaaaaaaaaaaa", "host": "any", "pid": std::process::id()}});
        std::fs::write(forged.join(".rotorshunt-out.json"), record.to_string()).unwrap();
        std::fs::write(forged.join("mine.txt"), "the user's\n").unwrap();
        std::os::unix::fs::symlink(
            parent.join("victim_dir"),
            parent.join(".rotorshunt-tmp.out.bbbbbbbbbbbbbbbbbbbbbbbb"),
        )
        .unwrap();
        std::fs::create_dir(out.join(".rotorshunt-tmp..rotorshunt-out.json.999997.0")).unwrap();
        std::fs::write(out.join(".rotorshunt-tmp..rotorshunt-out.json.999997.0/mine.txt"), "the user's\n").unwrap();
        let before = common::tree(&parent, &out);
        let second = run(&c, &out);
        assert!(wrote(&second), "{}: {}", c.name, stderr(&second));
        let e = stderr(&second);
        assert!(e.contains("\"../victim.txt\"") && e.contains("not a plain name"), "{}: {e}", c.name);
        assert_eq!(common::tree(&parent, &out), before, "{}: something outside --out changed", c.name);
        assert!(
            out.join(".rotorshunt-tmp..rotorshunt-out.json.999997.0/mine.txt").exists(),
            "{}: a user's folder in --out",
            c.name
        );
        plants += 6;

        // The manifest a link to a record outside: read as unreadable, never written through.
        let outside_record = parent.join("record.json");
        std::fs::write(&outside_record, m.to_string()).unwrap();
        std::fs::remove_file(&manifest).unwrap();
        std::os::unix::fs::symlink(&outside_record, &manifest).unwrap();
        let before = common::tree(&parent, &out);
        let third = run(&c, &out);
        assert!(wrote(&third), "{}: {}", c.name, stderr(&third));
        assert!(stderr(&third).contains("is ignored"), "{}: {}", c.name, stderr(&third));
        assert_eq!(common::tree(&parent, &out), before, "{}: the linked record outside changed", c.name);
        assert!(!std::fs::symlink_metadata(&manifest).unwrap().file_type().is_symlink());
        plants += 1;

        // An output name that is a link, a FIFO or a device: refused, left as it is.
        let target = out.join(c.output);
        let mut nodes: Vec<Maker> = vec![
            ("a symbolic link", Box::new(|p: &Path| std::os::unix::fs::symlink("../victim.txt", p).is_ok())),
            (
                "a FIFO",
                Box::new(|p: &Path| {
                    common::mkfifo(p);
                    true
                }),
            ),
        ];
        if is_root() {
            nodes.push(("a device", Box::new(mknod_null)));
        } else {
            eprintln!("{}: not root, so no device node is made (CI runs as root)", c.name);
        }
        for (what, make) in &nodes {
            std::fs::remove_file(&target).unwrap();
            assert!(make(&target), "{}: cannot make {what}", c.name);
            let before = common::tree(&parent, &root.join("none"));
            let refused = run(&c, &out);
            assert_eq!(refused.status.code(), Some(2), "{} with {what} at {}: {}", c.name, c.output, stderr(&refused));
            assert!(stderr(&refused).contains(what), "{}: {}", c.name, stderr(&refused));
            assert_eq!(
                common::tree(&parent, &root.join("none")),
                before,
                "{}: {what} was replaced or followed",
                c.name
            );
            plants += 1;
        }
        std::fs::remove_file(&target).unwrap();
        eprintln!("{}: every plant refused or ignored, nothing outside --out changed", c.name);
    }
    eprintln!("{plants} plants over {} commands", commands().len());
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn import_ross_refuses_links_fifos_and_devices_with_or_without_force() {
    let dir = common::tmp("hostile-import");
    std::fs::create_dir_all(&dir).unwrap();
    let rotor = common::root().join("tests/fixtures/ross/rotor_example_rayleigh.toml");
    let victim = dir.join("victim.toml");
    std::fs::write(&victim, "# the user's problem\n").unwrap();
    let mut nodes: Vec<(&str, PathBuf)> = Vec::new();
    let link = dir.join("link.toml");
    std::os::unix::fs::symlink(&victim, &link).unwrap();
    nodes.push(("a symbolic link", link));
    let fifo = dir.join("fifo.toml");
    common::mkfifo(&fifo);
    nodes.push(("a FIFO", fifo));
    if is_root() {
        let dev = dir.join("null.toml");
        assert!(mknod_null(&dev));
        nodes.push(("a device", dev));
    } else {
        eprintln!("not root: no device node is made (CI runs as root)");
    }
    let mut refused = 0;
    for (what, path) in &nodes {
        for force in [false, true] {
            let before = common::tree(&dir, &dir.join("none"));
            let mut cmd = common::bin();
            cmd.arg("import-ross").arg(&rotor).arg("--out").arg(path);
            if force {
                cmd.arg("--force");
            }
            let o = cmd.output().unwrap();
            assert_eq!(o.status.code(), Some(2), "{what} force={force}: {}", stderr(&o));
            assert!(stderr(&o).contains(what), "{what}: {}", stderr(&o));
            assert_eq!(common::tree(&dir, &dir.join("none")), before, "{what} force={force}: replaced or followed");
            refused += 1;
        }
    }
    eprintln!("import-ross: {refused} refusals, every node left as it was");
    std::fs::remove_dir_all(&dir).unwrap();
}
