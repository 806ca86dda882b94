//! One name for what bounds a band (issue 27, point 7), in the design report: page one,
//! the region table, report.json and `rotorshunt band` on tuned.toml give each finite
//! bound of the widest-band design's band the same name, that of the lowest-order counted
//! tongue of the report's own catalogue with that edge (computed here from the catalogue
//! in report.json). The design runs with one start and three iterations.
//!
//! That `band` names every finite edge by the lowest-order catalogued tongue on every
//! problem in problems/ at every φ_op and β_op of the band tests is checked in
//! tests/band_truth.rs, beside the band's truth, on the catalogue it already computes.

use crate::common;

use common::{bin, json, problem_path, run_ok, tmp};
use serde_json::Value;

const WINDOW: &str = "100:8000";
/// Two routes to the same lattice-refined edge give the same number; only round-off may
/// separate them (rad/s).
const SAME_EDGE: f64 = 1e-9;

/// (label, order, left, right) of every counted region of a catalogue JSON object.
fn tongues(cat: &Value) -> Vec<(String, u64, f64, f64)> {
    cat["regions"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|r| r["counted"].as_bool() == Some(true))
        .filter_map(|r| {
            Some((r["label"].as_str()?.to_string(), r["order"].as_u64()?, r["left"].as_f64()?, r["right"].as_f64()?))
        })
        .collect()
}

/// The expected name of a bound: `below` the band (tongue's right edge = band's lower
/// edge) or above it.
fn expected(tongues: &[(String, u64, f64, f64)], edge: f64, below: bool) -> Option<String> {
    let mut same: Vec<&(String, u64, f64, f64)> =
        tongues.iter().filter(|t| ((if below { t.3 } else { t.2 }) - edge).abs() <= SAME_EDGE).collect();
    same.sort_by(|a, b| a.1.cmp(&b.1).then_with(|| a.0.cmp(&b.0)));
    same.first().map(|t| format!("{} (k = {})", t.0, t.1))
}

/// The cells of the page-one band table's "after" row: (below, above) names.
fn page_one_bounds(md: &str) -> Vec<(String, String)> {
    md.lines()
        .skip_while(|l| !l.contains("after: bounded below by"))
        .skip(2)
        .take_while(|l| l.starts_with('|'))
        .map(|l| {
            let cells: Vec<&str> = l.split('|').map(str::trim).collect();
            (cells[4].to_string(), cells[5].to_string())
        })
        .collect()
}

#[test]
fn design_report_names_the_bounds_as_band_does() {
    let dir = tmp("band-names-design");
    let input = problem_path("design-widest-band.toml");
    run_ok(
        bin()
            .arg("design")
            .arg(&input)
            .args(["--set", "design.starts=1", "--set", "design.max_iterations=3"])
            // What is compared is the names on the design's own basis: its refined check
            // and its sizing by convergence (tests/design.rs) are not needed here.
            .args(common::QUICK_BASIS_ARGS)
            .args(common::COARSE_CHART_ARGS)
            .arg("--out")
            .arg(&dir)
            .arg("--quiet"),
    );
    let report = json(&dir.join("report.json"));
    let outcome = &report["outcome"];
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    let rows = page_one_bounds(&md);
    assert_eq!(rows.len(), 1, "{md}");
    let band = &outcome["after_bands"][0]["band"];
    let tongues = tongues(&outcome["after_speeds"][0]["catalogue"]);
    // `band` on tuned.toml over the design's range, at its φ_op and β_op, on the basis the
    // design judged every candidate on (the same model: what is compared is the names).
    let modes = format!("analysis.reduced_modes={}", outcome["basis"]["modes"].as_u64().unwrap());
    let b: Value = serde_json::from_str(&run_ok(
        bin()
            .arg("band")
            .arg(dir.join("tuned.toml"))
            .args(["--set", &modes])
            .args(["--phi-op", "1230", "--level", "0.3", "--phi", WINDOW, "--json"]),
    ))
    .unwrap();
    let mut checked = 0;
    for ((side, below), cell) in [("left", true), ("right", false)].into_iter().zip([&rows[0].0, &rows[0].1]) {
        let bound = &band[side];
        if bound["kind"] != "tongue" {
            continue;
        }
        checked += 1;
        let edge = bound["edge"].as_f64().unwrap();
        let want = expected(&tongues, edge, below).unwrap_or_else(|| "unlabelled".into());
        eprintln!("design band {side}: edge {edge}, page one `{cell}`, catalogue {want}, band {}", b[side]["label"]);
        assert_eq!(bound["label"], want.as_str(), "report.json {side}");
        assert!(cell.starts_with(&format!("{want} at {edge:.2}")), "page one `{cell}` vs {want}");
        assert_eq!(b[side]["label"], want.as_str(), "`band` on tuned.toml, {side}");
        assert_eq!(b[side]["edge"].as_f64(), Some(edge), "`band` edge, {side}");
        // The region table lists that tongue under the same label and order.
        if let Some((label, k)) = want.strip_suffix(')').and_then(|w| w.split_once(" (k = ")) {
            let row = format!("| {label} | {k} |");
            assert!(md.lines().any(|l| l.starts_with(&row) && l.contains(&format!("{edge:.2}"))), "no row {row}");
        }
    }
    assert!(checked >= 1, "the design's band has no finite edge");
    std::fs::remove_dir_all(&dir).unwrap();
}
