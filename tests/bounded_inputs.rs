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
