//! Refusals early and at the right key (issue 26, point 5): each bad value is refused with
//! exit code 2 and a one-line message naming the key (and the line, when the key is in
//! the file) or the flag, and `check` refuses what a command would, at the same key and
//! line. The expected keys and lines come from the edited texts written here, never from
//! the code under test.

use crate::common;
use common::root;
use std::path::PathBuf;
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_rotorshunt");

/// The folder of this test's files, in the system's temporary folder.
fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("rotorshunt-early-refusal-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap_or_else(|e| panic!("{}: {e}", d.display()));
    d
}

fn run(args: &[&str]) -> Output {
    Command::new(BIN).args(args).current_dir(root()).output().expect("run rotorshunt")
}

/// A copy of `problems/<base>` with the line starting `from` (the first one) replaced by
/// `to`, written as `<name>` in [`dir`]: its path and the 1-based line of
/// the replacement.
fn edited(base: &str, name: &str, from: &str, to: &str) -> (String, usize) {
    let text = std::fs::read_to_string(root().join("problems").join(base)).expect("read problem");
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let i = lines.iter().position(|l| l.starts_with(from)).unwrap_or_else(|| panic!("{base} has no line `{from}`"));
    lines[i] = to.to_string();
    let path = dir().join(name);
    std::fs::write(&path, lines.join("\n") + "\n").expect("write problem");
    (path.display().to_string(), i + 1)
}

/// A copy of `problems/<base>` with `line` inserted after the first line starting `after`.
fn inserted(base: &str, name: &str, after: &str, line: &str) -> (String, usize) {
    let text = std::fs::read_to_string(root().join("problems").join(base)).expect("read problem");
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let i = lines.iter().position(|l| l.starts_with(after)).unwrap_or_else(|| panic!("{base} has no line `{after}`"));
    lines.insert(i + 1, line.to_string());
    let path = dir().join(name);
    std::fs::write(&path, lines.join("\n") + "\n").expect("write problem");
    (path.display().to_string(), i + 2)
}

/// Exit code 2 and the one line of standard error (which must be all of it).
fn refused(args: &[&str]) -> String {
    let out = run(args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(2), "{args:?}: expected exit 2\n{stderr}");
    let lines: Vec<&str> = stderr.lines().filter(|l| !l.starts_with("warning: ")).collect();
    assert_eq!(lines.len(), 1, "{args:?}: expected one line of error\n{stderr}");
    assert!(lines[0].starts_with("error: "), "{stderr}");
    lines[0].to_string()
}

/// The error names `file`, `line` and `key`.
fn at_key(message: &str, file: &str, line: usize, key: &str) {
    let prefix = format!("error: {file}, line {line}: key `{key}`: ");
    assert!(message.starts_with(&prefix), "expected `{prefix}…`, found\n{message}");
}

/// `check` and `command` (with its further arguments) refuse `file` with the same message.
fn same_as_check(file: &str, command: &[&str]) -> String {
    let check = refused(&["check", file]);
    let mut args = vec![command[0], file];
    args.extend_from_slice(&command[1..]);
    assert_eq!(refused(&args), check, "{command:?} and check differ");
    check
}

#[test]
fn a_set_takes_exactly_one_value() {
    let file = "problems/paper-closed.toml";
    for bad in ["speed=1000\nspeed=5", "speed=1000\n[x]\ny = 1", "circuit.state=open\nclosed", "speed=1000\r\nz=2"] {
        let e = refused(&["check", file, "--set", bad]);
        let key = bad.split('=').next().unwrap();
        assert!(e.starts_with(&format!("error: {file}, --set: key `{key}`: cannot apply --set ")), "{bad:?}: {e}");
        assert!(e.contains("one TOML value"), "{bad:?}: {e}");
        // The message shows the argument on its one line, the line break escaped.
        assert!(e.contains("\\n"), "{bad:?}: {e}");
        // Another command refuses it the same way.
        assert_eq!(refused(&["modes", file, "--set", bad]), e);
    }
    // One value, with a comment or an inline table, is still one value.
    for good in ["speed=1000 # rad/s", "speed = 1000", "circuit.state=open"] {
        let out = run(&["check", file, "--set", good]);
        assert_eq!(out.status.code(), Some(0), "{good:?}: {}", String::from_utf8_lossy(&out.stderr));
    }
}

#[test]
fn check_refuses_a_response_speed_range_design_cannot_run() {
    let out = dir().join("design-out");
    let out = out.to_str().unwrap();
    for (name, to, key) in [
        ("resp-hi-1e300.toml", "speeds = [0, 1e300]", "design.response.speeds[1]"),
        ("resp-lo-1e300.toml", "speeds = [1e300, 2e300]", "design.response.speeds[0]"),
        ("resp-hi-1e9.toml", "speeds = [250.0, 1e9]", "design.response.speeds[1]"),
        ("resp-rpm-1e308.toml", "speeds_rpm = [0, 1e308]", "design.response.speeds_rpm[1]"),
        ("resp-rpm-1e12.toml", "speeds_rpm = [0, 1e12]", "design.response.speeds_rpm[1]"),
    ] {
        let (file, line) = edited("design-min-peak-at-speed.toml", name, "speeds = [250.0, 500.0]", to);
        let e = same_as_check(&file, &["design", "--out", out]);
        at_key(&e, &file, line, key);
        assert!(e.contains("must be at most"), "{e}");
    }
    // The bound admits every real rotor: 1e6 rad/s (9.5 million rpm) is checked valid.
    let (file, _) =
        edited("design-min-peak-at-speed.toml", "resp-1e6.toml", "speeds = [250.0, 500.0]", "speeds = [0, 1e6]");
    let ok = run(&["check", &file]);
    assert_eq!(ok.status.code(), Some(0), "{}", String::from_utf8_lossy(&ok.stderr));
    // The unbalance command's speeds follow the same rule, named by the flag.
    let e = refused(&["unbalance", "problems/paper-closed.toml", "--speeds", "0:1e300:1e299", "--out", out]);
    assert!(e.starts_with("error: argument `--speeds`: must be at most"), "{e}");
}

#[test]
fn overflowing_shaft_quantities_are_bad_input_at_their_key() {
    let cases = [
        (
            "stepped-bearing-ring.toml",
            "sec-od.toml",
            "outer_diameter = 0.04",
            "outer_diameter = 1e300",
            "sections[0].outer_diameter",
        ),
        ("stepped-bearing-ring.toml", "sec-len.toml", "length = 0.1 ", "length = 1e300", "sections[0].length"),
        ("paper-closed.toml", "shaft-radius.toml", "radius = 0.015", "radius = 1e300", "shaft.radius"),
        (
            "paper-closed.toml",
            "shaft-e.toml",
            "youngs_modulus = 206e9",
            "youngs_modulus = 1e305",
            "shaft.youngs_modulus",
        ),
        ("paper-closed.toml", "shaft-tiny-radius.toml", "radius = 0.015", "radius = 1e-100", "shaft.radius"),
    ];
    for (base, name, from, to, key) in cases {
        let (file, line) = edited(base, name, from, to);
        let e = same_as_check(&file, &["modes"]);
        at_key(&e, &file, line, key);
        assert!(e.contains("between 1e-150 and 1e150 (SI units; here "), "{e}");
    }
}

#[test]
fn an_overflowing_disk_or_material_names_its_own_key() {
    let base = "stepped-bearing-ring.toml";
    let cases = [
        ("disk-width.toml", "width = 0.03", "width = 1e300", "disks[0].width"),
        ("disk-od.toml", "outer_diameter = 0.16", "outer_diameter = 1e300", "disks[0].outer_diameter"),
        ("disk-width-150.toml", "width = 0.03", "width = 1e150", "disks[0].width"),
        ("mat-density.toml", "density = 7810.0", "density = 1e308", "materials[0].density"),
        ("mat-e.toml", "youngs_modulus = 2.11e11", "youngs_modulus = 1e307", "materials[0].youngs_modulus"),
    ];
    for (name, from, to, key) in cases {
        let (file, line) = edited(base, name, from, to);
        let e = same_as_check(&file, &["modes"]);
        at_key(&e, &file, line, key);
    }
    // A disk's own density (no material) is blamed at the disk.
    let text = std::fs::read_to_string(root().join("problems").join(base)).unwrap();
    let disk = text.find("[[disks]]").unwrap();
    let material = disk + text[disk..].find("material = \"steel\"").unwrap();
    let edited_text =
        format!("{}density = 1e308{}", &text[..material], &text[material + "material = \"steel\"".len()..]);
    let path = dir().join("disk-own-density.toml");
    std::fs::write(&path, &edited_text).unwrap();
    let line = edited_text[..material].matches('\n').count() + 1;
    let file = path.display().to_string();
    let e = same_as_check(&file, &["modes"]);
    at_key(&e, &file, line, "disks[0].density");
}

#[test]
fn huge_values_print_short() {
    let cases = [
        ("paper-closed.toml", "pos-1e300.toml", "node = 16", "position = 1e300", "disks[0].position"),
        (
            "stepped-bearing-ring.toml",
            "inner-1e300.toml",
            "inner_diameter = 0.025",
            "inner_diameter = 1e300",
            "sections[1].inner_diameter",
        ),
        (
            "design-min-peak-at-speed.toml",
            "resp-empty-1e300.toml",
            "speeds = [250.0, 500.0]",
            "speeds = [1e300, 5]",
            "design.response.speeds[0]",
        ),
    ];
    for (base, name, from, to, key) in cases {
        let (file, line) = edited(base, name, from, to);
        let e = refused(&["check", &file]);
        at_key(&e, &file, line, key);
        assert!(e.contains("1e300"), "{e}");
        assert!(!e.contains("00000000000"), "{e}");
        assert!(e.len() < file.len() + key.len() + 250, "{} chars: {e}", e.len());
    }
    // An empty range whose low end is huge, within the bound: the low end prints short.
    let (file, line) = edited(
        "design-min-peak-at-speed.toml",
        "resp-empty-big.toml",
        "speeds = [250.0, 500.0]",
        "speeds = [9.5e6, 5]",
    );
    let e = refused(&["check", &file]);
    at_key(&e, &file, line, "design.response.speeds[1]");
    assert!(e.contains("9.5e6 rad/s") || e.contains("9500000 rad/s"), "{e}");
}

#[test]
fn empty_list_entries_in_flags_are_refused() {
    let out = dir().join("unbalance-out");
    let out = out.to_str().unwrap();
    let file = "problems/paper-closed.toml";
    for nodes in ["3,,4", ",", "3,", ",3"] {
        let e = refused(&["unbalance", file, "--speeds", "0:200:100", "--nodes", nodes, "--out", out]);
        assert!(e.starts_with("error: argument `--nodes`: "), "{nodes}: {e}");
        assert!(e.contains("empty"), "{e}");
    }
    for modes in [",", "f1,,b1", "f1,"] {
        let e = refused(&["damping", file, "--speeds", "0:200:100", "--modes", modes]);
        assert!(e.starts_with("error: argument `--modes`: "), "{modes}: {e}");
    }
    // Well-formed lists still run.
    let ok = run(&["damping", file, "--speeds", "0:200:100", "--modes", "f1, b1"]);
    assert_eq!(ok.status.code(), Some(0), "{}", String::from_utf8_lossy(&ok.stderr));
}

/// `rotor_example_rayleigh.toml` with element `n`'s material given `name`, `rho`, `E`.
fn with_material(text: &str, n: usize, name: &str, rho: f64, e: f64) -> String {
    let header = format!("[\"ShaftElement_Shaft Element {n}\".material]\n");
    let start = text.find(&header).expect("material table") + header.len();
    let end = start + text[start..].find("G_s").expect("G_s");
    format!("{}name = \"{name}\"\nrho = {rho:?}\nE = {e:?}\n{}", &text[..start], &text[end..])
}

#[test]
fn ross_material_names_never_collide() {
    let text = std::fs::read_to_string(root().join("tests/fixtures/ross/rotor_example_rayleigh.toml")).unwrap();
    // Steel (the file's), a second Steel with other values, and a real Steel-2; in both
    // orders of the variant and the real name.
    let orders = [
        [(2, "Steel", 7800.0, 2.0e11), (4, "Steel-2", 7700.0, 1.9e11)],
        [(2, "Steel-2", 7700.0, 1.9e11), (4, "Steel", 7800.0, 2.0e11)],
    ];
    for (k, order) in orders.iter().enumerate() {
        let mut t = text.clone();
        for &(n, name, rho, e) in order {
            t = with_material(&t, n, name, rho, e);
        }
        let source = dir().join(format!("ross-names-{k}.toml"));
        std::fs::write(&source, &t).unwrap();
        let problem = dir().join(format!("ross-names-{k}.problem.toml"));
        let (src, dst) = (source.to_str().unwrap(), problem.to_str().unwrap());
        let out = run(&["import-ross", src, "--out", dst, "--force"]);
        assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
        let check = run(&["check", dst]);
        assert_eq!(check.status.code(), Some(0), "{}", String::from_utf8_lossy(&check.stderr));
        let written: toml::Table = toml::from_str(&std::fs::read_to_string(&problem).unwrap()).unwrap();
        let materials = written["materials"].as_array().unwrap();
        let props: Vec<(String, f64, f64)> = materials
            .iter()
            .map(|m| {
                (
                    m["name"].as_str().unwrap().to_string(),
                    m["density"].as_float().unwrap(),
                    m["youngs_modulus"].as_float().unwrap(),
                )
            })
            .collect();
        assert_eq!(props.len(), 3, "{props:?}");
        let names: std::collections::BTreeSet<&str> = props.iter().map(|p| p.0.as_str()).collect();
        assert_eq!(names.len(), 3, "{props:?}");
        // The file's own names keep their values: Steel is the first Steel, Steel-2 the
        // real Steel-2.
        let of = |name: &str| props.iter().find(|p| p.0 == name).map(|p| (p.1, p.2));
        assert_eq!(of("Steel"), Some((7810.0, 211000000000.0)), "{props:?}");
        assert_eq!(of("Steel-2"), Some((7700.0, 1.9e11)), "{props:?}");
        assert!(
            props.iter().any(|p| (p.1, p.2) == (7800.0, 2.0e11) && p.0 != "Steel" && p.0 != "Steel-2"),
            "{props:?}"
        );
    }
}

#[test]
fn a_study_syntax_error_is_one_paragraph() {
    let text = std::fs::read_to_string(root().join("problems/studies/resistance-speed.toml")).unwrap();
    let cases = [("beta_max = 0.5", "beta_max = "), ("[sweep]", "[sweep"), ("phi_op = 1230.0", "phi_op = 1230.0 1")];
    for (k, (from, to)) in cases.iter().enumerate() {
        let start = text.find(from).unwrap();
        let broken = format!("{}{to}{}", &text[..start], &text[start + from.len()..]);
        let line = broken[..start].matches('\n').count() + 1;
        let path = dir().join(format!("study-syntax-{k}.toml"));
        std::fs::write(&path, &broken).unwrap();
        let file = path.display().to_string();
        let out_dir = dir().join(format!("study-syntax-{k}-out"));
        let out = run(&["study", &file, "--out", out_dir.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(2));
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(stderr.lines().count(), 1, "not one line:\n{stderr}");
        let prefix = format!("error: {file}, line {line}: TOML syntax error: ");
        assert!(stderr.starts_with(&prefix), "expected `{prefix}…`, found\n{stderr}");
        assert!(stderr.trim_end().ends_with(')') && stderr.contains("(column "), "{stderr}");
        assert!(!out_dir.exists(), "nothing is written");
    }
}

/// The problem file's syntax errors have the same form, with the column.
#[test]
fn a_problem_syntax_error_gives_line_and_column() {
    let (file, line) = inserted("paper-closed.toml", "syntax.toml", "radius = 0.015", "elements = = 3");
    let e = refused(&["check", &file]);
    assert!(e.starts_with(&format!("error: {file}, line {line}: TOML syntax error: ")), "{e}");
    assert!(e.ends_with("(column 12)"), "{e}");
}
