//! `[regions]`: the region search's settings set from the file, checked with key and line,
//! used by the searches and recorded in their output.

use crate::common;

use rotorshunt::problem::{Location, ProblemErrorKind};
use rotorshunt::{Interval, Problem};

fn with_regions(table: &str) -> String {
    let base = std::fs::read_to_string(common::problem_path("fig11-closed-2000.toml")).unwrap();
    format!("{base}\n[regions]\n{table}\n")
}

#[test]
fn regions_table_sets_the_search_and_is_recorded() {
    let text = with_regions("phi_tolerance = 0.05\nedge_step = [1.0, 1e-3]");
    let p = Problem::from_text(&text, "fig11+regions.toml", &[]).unwrap();
    assert_eq!(p.regions.phi_tolerance, 0.05);
    assert_eq!((p.regions.edge_step.absolute, p.regions.edge_step.relative), (1.0, 1e-3));
    // Keys not given keep their defaults.
    let defaults = rotorshunt::analysis::regions::RegionSettings::default();
    assert_eq!(p.regions.beta_tolerance, defaults.beta_tolerance);
    // The operating point carries them into the searches; a looser edge tolerance moves
    // the band's edges by less than the tolerances allow.
    let op = p.operating_point().unwrap();
    assert_eq!(op.regions, p.regions);
    let req = rotorshunt::BandRequest::builder()
        .range(Interval::new(100.0, 8000.0))
        .phi_op(1230.0)
        .level(0.3)
        .build()
        .unwrap();
    let fine = op.band(&req).unwrap().band.unwrap();
    let plain = Problem::from_path(common::problem_path("fig11-closed-2000.toml"), &[]).unwrap();
    let coarse = plain.operating_point().unwrap().band(&req).unwrap().band.unwrap();
    assert!((fine.lo - coarse.lo).abs() < 0.25 && (fine.hi - coarse.hi).abs() < 0.25, "{fine:?} vs {coarse:?}");
    // `regions --json` records the settings it ran with.
    let dir = std::env::temp_dir().join(format!("rotorshunt-region-settings-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("p.toml");
    std::fs::write(&file, &text).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_rotorshunt"))
        .args(["regions", file.to_str().unwrap(), "--phi", "1100:1300", "--level", "0.3", "--json"])
        .output()
        .unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["region_settings"]["phi_tolerance"], 0.05, "{}", json["region_settings"]);
}

#[test]
fn bad_regions_values_name_key_and_line() {
    for (table, key) in [
        ("phi_tolerance = -1.0", "regions.phi_tolerance"),
        ("beta_bracket = 0.0", "regions.beta_bracket"),
        ("tip_iterations = 0", "regions.tip_iterations"),
        ("edge_step = [2.0, inf]", "regions.edge_step[1]"),
    ] {
        let text = with_regions(table);
        let e = Problem::from_text(&text, "bad.toml", &[]).unwrap_err();
        assert_eq!(e.key, key, "{table}: {e}");
        assert!(!matches!(e.kind, ProblemErrorKind::Schema(_)), "a value rule, not a schema error: {e}");
        let line = text.lines().position(|l| l.starts_with(table.split(' ').next().unwrap())).unwrap() + 1;
        assert_eq!(e.location, Location::Line(line), "{table}: {e}");
    }
    let e = Problem::from_text(&with_regions("phi_tolerence = 0.1"), "typo.toml", &[]).unwrap_err();
    assert!(e.to_string().contains("phi_tolerence"), "{e}");
}
