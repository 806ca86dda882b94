//! Inputs whose size the cost of a run follows (issue 50, items 2 and 3) are bounded where
//! they are read: a coefficient table one speed over `MAX_TABLE_POINTS` is refused at its
//! key, and a ROSS rotor of more shaft elements than `MAX_ELEMENTS` before any element is
//! converted (counted by the importer's `Work`). That the work below the caps is linear
//! in the input is tests/parse_memory.rs's (its counting allocator).

use crate::common;
use rotorshunt::import::ross::{self, Options, Refusal, RossErrorKind, Work};
use rotorshunt::problem::{Problem, ProblemErrorKind, MAX_ELEMENTS, MAX_TABLE_POINTS};

#[test]
fn a_speed_table_one_point_over_the_cap_is_refused_at_its_key() {
    let cap = MAX_TABLE_POINTS;
    let e = Problem::from_text(&common::tabulated_jeffcott(cap + 1), "long.toml", &[]).unwrap_err();
    assert_eq!(e.key, "bearings[0].speeds", "{e}");
    assert_eq!(e.kind, ProblemErrorKind::TableTooLong { points: cap + 1, limit: cap }, "{e}");
    // The same table as a seal's.
    let seal = common::tabulated_jeffcott(cap + 1).replacen("[[bearings]]", "[[seals]]", 1);
    let e = Problem::from_text(&seal, "long.toml", &[]).unwrap_err();
    assert_eq!((e.key.as_str(), e.kind.name()), ("seals[0].speeds", "TableTooLong"), "{e}");
    // At the cap the table loads and is evaluated.
    let p = Problem::from_text(&common::tabulated_jeffcott(cap), "cap.toml", &[]).expect("a table at the cap loads");
    let b = &p.model.bearings[0];
    assert_eq!(b.speeds.len(), cap);
    let k = b.matrices_at(1234.5).k[0][0];
    assert!((9e6..=1.1e7).contains(&k), "kxx = {k}");
    // The command line: exit 2, the file's line and the key.
    let path = common::long_table_file();
    let out = common::bin().arg("check").arg(&path).output().expect("run rotorshunt");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("key `bearings[0].speeds`: the table has 1001 speeds, more than the 1000"), "{stderr}");
}

#[test]
fn twenty_thousand_shaft_elements_are_refused_before_any_is_converted() {
    for format in ["toml", "json"] {
        let text = common::ross_rotor(20_000, format);
        let before = Work::this_thread();
        let e = ross::import_text(&text, &format!("long.{format}"), Options::default()).unwrap_err();
        let work = Work::this_thread().since(&before);
        println!("{format}: {} bytes: {work:?}", text.len());
        match e.kind {
            RossErrorKind::Refused { element: None, reason, more } => {
                assert_eq!(*reason, Refusal::TooManyElements { count: 20_000, limit: MAX_ELEMENTS as usize });
                assert!(more.is_empty());
            }
            other => panic!("{format}: {other}"),
        }
        assert_eq!(work.shaft_elements_converted, 0, "{format}: converted before the refusal");
        assert_eq!(work.lines_scanned, 0, "{format}: lines scanned before the refusal");
    }
    // At the cap the rotor is imported, each element converted once (the count is live).
    let cap = MAX_ELEMENTS as usize;
    let before = Work::this_thread();
    let import = ross::import_text(&common::ross_rotor(cap, "json"), "cap.json", Options::default()).expect("imports");
    let work = Work::this_thread().since(&before);
    assert_eq!(work.shaft_elements_converted, cap as u64);
    assert_eq!(import.rotor.sections.iter().map(|s| s.elements).sum::<usize>(), cap);
}

#[test]
fn a_ross_table_one_frequency_over_the_cap_is_refused() {
    // Bearing 0 of a small rotor tabulated over `points` frequencies (kxx varies).
    let with_table = |points: usize| -> String {
        let mut doc: serde_json::Value = serde_json::from_str(&common::ross_rotor(4, "json")).expect("JSON");
        let b = &mut doc["BearingElement_Bearing 0"];
        for key in ["kxy", "kyx", "cxx", "cxy", "cyx", "cyy", "mxx", "mxy", "myx", "myy", "kzz", "czz", "mzz"] {
            b[key] = serde_json::json!(vec![0.0; points]);
        }
        b["kxx"] = serde_json::json!((0..points).map(|i| 1e6 + i as f64).collect::<Vec<_>>());
        b["kyy"] = serde_json::json!(vec![1e6; points]);
        b["frequency"] = serde_json::json!((0..points).map(|i| i as f64).collect::<Vec<_>>());
        doc.to_string()
    };
    let cap = MAX_TABLE_POINTS;
    let e = ross::import_text(&with_table(cap + 1), "table.json", Options::default()).unwrap_err();
    match e.kind {
        RossErrorKind::Refused { element: Some(element), reason, .. } => {
            assert_eq!((element.class.as_str(), element.tag.as_str()), ("BearingElement", "Bearing 0"));
            assert!(
                matches!(&*reason, Refusal::Value { key, value, .. } if key == "frequency" && *value == (cap + 1) as f64),
                "{reason}"
            );
        }
        other => panic!("{other}"),
    }
    let import = ross::import_text(&with_table(cap), "table.json", Options::default()).expect("a table at the cap");
    assert_eq!(import.rotor.bearings[0].speeds.len(), cap);
    // What it writes loads.
    Problem::from_text(&import.text, "imported.toml", &[]).expect("the imported table loads");
}

/// Issue 50, point 1: a robust design is counted by its plan, every build at every speed
/// it is judged at, and one plainly beyond the limit is refused before it starts (exit 2,
/// no folder) with the count of its builds; the bundled robust files, inside it, are
/// admitted (a limit of 1e-9 s then stops them at their first step, exit 7).
#[test]
fn a_robust_design_plainly_beyond_the_limit_is_refused_before_it_starts() {
    // The case: every part of the circuit toleranced (L, R, C_f, C_p^T: 2^4
    // corners and the nominal), tongues up to order 32 and φ_op = 150 rad/s.
    let heavy = [
        "design.tolerances.c_f=0.1",
        "design.tolerances.cp_t=0.1",
        "design.phi_op=150",
        "analysis.max_tongue_order=32",
    ];
    let dir = common::tmp("robust-refused");
    for (file, searches) in [("design-robust.toml", 17), ("design-robust-speed-range.toml", 5)] {
        let out_dir = dir.join(file);
        // A limit of time too, so that a design admitted by mistake fails the test (exit 7)
        // rather than running for long.
        let mut cmd = common::bin();
        cmd.args(["--time-limit", "60", "design", &common::problem_path(file)]);
        for s in heavy {
            cmd.args(["--set", s]);
        }
        let out = cmd.arg("--out").arg(&out_dir).output().expect("run rotorshunt");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{file}: {stderr}");
        assert!(stderr.starts_with("error: the design would need about "), "{file}: {stderr}");
        // The nominal build at the 5 speeds with 4 refinements and 16 corners at the worst
        // speed is 25 searches over 5 speeds; at one speed, 17 builds.
        assert!(
            stderr.contains(&format!("each: {searches} searches per speed (builds, refinements)")),
            "{file}: {stderr}"
        );
        assert!(stderr.contains("`[design.tolerances]`"), "{file}: {stderr}");
        assert!(!out_dir.exists(), "{file}: a refused design made its folder");
        // As bundled, admitted: stopped at its first step, not refused.
        let out = common::bin()
            .args(["--time-limit", "1e-9", "--quiet", "design", &common::problem_path(file), "--out"])
            .arg(&out_dir)
            .output()
            .expect("run rotorshunt");
        assert_eq!(out.status.code(), Some(7), "{file}: {}", String::from_utf8_lossy(&out.stderr));
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// Every bundled design problem (the top level of problems/ and its rotor folders
/// `ross/` and `families/`) is admitted by its estimate as shipped: a user who runs
/// `rotorshunt design FILE` on it starts the design (stopped here by a limit of 1e-9 s at
/// its first step, exit 7), never meets a refusal (exit 2).
#[test]
fn every_bundled_design_problem_is_admitted_as_shipped() {
    let root = common::root().join("problems");
    let mut files = Vec::new();
    for dir in [root.clone(), root.join("ross"), root.join("families")] {
        for name in common::toml_names(&dir) {
            let path = dir.join(&name);
            if Problem::from_path(&path, &[]).is_ok_and(|p| p.design.is_some()) {
                files.push(path);
            }
        }
    }
    assert!(files.len() >= 12, "the bundled design problems: {files:?}");
    let dir = common::tmp("bundled-admitted");
    for (k, file) in files.iter().enumerate() {
        let out_dir = dir.join(k.to_string());
        let out = common::bin()
            .args(["--time-limit", "1e-9", "--quiet", "design"])
            .arg(file)
            .arg("--out")
            .arg(&out_dir)
            .output()
            .expect("run rotorshunt");
        assert_eq!(out.status.code(), Some(7), "{}: {}", file.display(), String::from_utf8_lossy(&out.stderr));
    }
    eprintln!("{} bundled design problems admitted as shipped", files.len());
    std::fs::remove_dir_all(&dir).ok();
}
