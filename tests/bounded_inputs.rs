//! Inputs whose size the cost of a run follows (issue 50, items 2 and 3) are bounded where
//! they are read: a coefficient table one speed over `MAX_TABLE_POINTS` is refused at its
//! key, and a ROSS rotor of more shaft elements than `MAX_ELEMENTS` before any element is
//! converted (counted by the importer's `Work`). That the work below the caps is linear
//! in the input is tests/parse_memory.rs's (its counting allocator).

use crate::common;
use rotorshunt::problem::{Problem, ProblemErrorKind, MAX_TABLE_POINTS};

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
