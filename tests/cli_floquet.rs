//! The Floquet commands end to end through the binary.

use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rotorshunt"))
}

fn problem(name: &str) -> String {
    format!("{}/problems/{name}", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn floquet_json_has_the_documented_shape() {
    let out = bin()
        .args(["floquet", &problem("fig9-open-2000.toml"), "--phi", "704", "--beta", "0.25", "--json"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["phi"], 704.0);
    assert_eq!(v["beta"], 0.25);
    assert_eq!(v["stable"], false);
    let m = v["max_multiplier"].as_f64().unwrap();
    assert!(m > 1.0001);
    assert!((v["growth_rate"].as_f64().unwrap() - m.ln() * 704.0 / (2.0 * std::f64::consts::PI)).abs() < 1e-9);
    let mult = v["multipliers"].as_array().unwrap();
    assert_eq!(mult.len(), 8, "M = 4 → 8 multipliers");
    assert!(mult.iter().all(|p| p.as_array().unwrap().len() == 2));
}

#[test]
fn chart_with_compare_and_timing_writes_all_outputs() {
    let dir = std::env::temp_dir().join(format!("rotorshunt-chart-{}", std::process::id()));
    let out = bin()
        .args(["chart", &problem("fig11-closed-2000.toml"), "--phi", "600:1400:20", "--beta", "0:1:0.25"])
        .args(["--compare-set", "circuit.state=open", "--timing", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(text.contains("timing: 205 points"), "{text}");
    for f in
        ["chart.json", "chart.csv", "chart.svg", "chart.png", "growth.svg", "growth.png", "compare.json", "compare.csv"]
    {
        assert!(dir.join(f).exists(), "{f} missing");
    }
    let csv = std::fs::read_to_string(dir.join("chart.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 41 * 5);
    assert!(!csv.contains("NaN"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_point_arguments_are_refused() {
    for args in [["--phi", "0", "--beta", "0.1"], ["--phi", "700", "--beta", "-1"], ["--phi", "nan", "--beta", "0.1"]] {
        let out = bin().args(["floquet", &problem("fig9-open-2000.toml")]).args(args).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(!String::from_utf8_lossy(&out.stderr).contains("panicked"));
    }
    let out = bin()
        .args([
            "floquet",
            &problem("fig9-open-2000.toml"),
            "--phi",
            "700",
            "--beta",
            "0.1",
            "--set",
            "analysis.reduced_modes=500",
        ])
        .output()
        .unwrap();
    assert_ne!(out.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&out.stderr).contains("reduced_modes"));
}

#[test]
fn oversized_grids_and_zero_counts_are_refused_at_once() {
    let dir = std::env::temp_dir().join(format!("rotorshunt-guard-{}", std::process::id()));
    let out = bin()
        .args(["chart", &problem("fig9-open-2000.toml"), "--phi", "1:10000000:1", "--beta", "0:1:0.001", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("more than the 2000000"));
    let out = bin()
        .args(["campbell", &problem("paper-open.toml"), "--speeds", "0:100:50", "--count", "0", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let _ = std::fs::remove_dir_all(&dir);
}
