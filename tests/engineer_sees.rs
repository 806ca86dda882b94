//! What the engineer sees (issue 29): the plots show the result (Bode curves through
//! every refined peak, design charts spanning every band, compare legends that tell two
//! same-title files apart), speeds come back in the unit given (rpm), progress moves,
//! studies are tables (a column per swept key, folder names keeping every value), and
//! every `src/…` path the README and docs cite exists. Small problems only: the whole
//! file runs in seconds.

use crate::common;

use rotorshunt::analysis::unbalance::{probes, unbalance_response};
use rotorshunt::analysis::Interval;
use rotorshunt::design::content::{chart_window, drawn_window};
use rotorshunt::numbers::SpeedUnit;
use rotorshunt::problem::tuned::tuned_file;
use rotorshunt::report::unbalance::{BodeLayer, BodePlot};
use std::path::Path;

/// A speed grid of 97 rad/s steps from 100 rad/s: coarse enough to miss the sharp first
/// peak of the compressor-class rotor (AF ≈ 3300 at 832 rad/s).
fn coarse_grid() -> Vec<f64> {
    (0..30).map(|i| 100.0 + 97.0 * i as f64).collect()
}

#[test]
fn bode_curve_passes_through_every_refined_peak_the_grid_misses() {
    let p = common::load("design-compressor.toml", &[]);
    let rotor = p.rotor().unwrap();
    let speeds = coarse_grid();
    let r = unbalance_response(&rotor, &speeds, &probes(&rotor, &[]).unwrap(), &rotorshunt::progress::Silent).unwrap();
    let plot = BodePlot {
        title: "bode".into(),
        layers: vec![BodeLayer { name: String::new(), dashed: false, result: &r }],
        unit: SpeedUnit::RadPerS,
    };
    let drawn = plot.drawn();
    let ((lo, hi), _) = plot.amplitude_axis();
    let grid_max = r.probes.iter().flat_map(|p| p.amplitude.iter().copied()).fold(0.0, f64::max);
    let peak_max = r.probes.iter().flat_map(|p| p.peaks.iter().map(|k| k.amplitude)).fold(0.0, f64::max);
    eprintln!("largest grid amplitude {grid_max:.4e} m, largest refined peak {peak_max:.4e} m, y-range [{lo:.3e}, {hi:.3e}] m");
    assert!(grid_max < 0.9 * peak_max, "the grid misses the largest peak: {grid_max:e} vs {peak_max:e}");
    let mut checked = 0;
    for (curve, probe) in drawn.iter().zip(&r.probes) {
        let top = curve.iter().map(|p| p.1).fold(0.0, f64::max);
        for k in &probe.peaks {
            // On the curve: a drawn point at the peak, and the curve's maximum is no lower.
            let nearest = curve.iter().map(|p| (p.1 - k.amplitude).abs() / k.amplitude).fold(f64::INFINITY, f64::min);
            assert!(
                nearest <= 0.01,
                "{} peak at {} rad/s: nearest drawn point {nearest:.3e} off",
                probe.probe.name,
                k.speed
            );
            assert!(
                k.amplitude <= 1.01 * top,
                "{}: peak {:e} above the curve's maximum {top:e}",
                probe.probe.name,
                k.amplitude
            );
            assert!(
                k.amplitude >= lo && k.amplitude <= hi,
                "peak {:e} outside the y-range [{lo:e}, {hi:e}]",
                k.amplitude
            );
            checked += 1;
        }
    }
    eprintln!("{checked} refined peaks on their curves and inside the y-range");
    assert!(checked >= 2, "{checked} peaks");
}

#[test]
fn design_charts_span_every_band_they_draw() {
    // The whole φ range of the catalogue, so that a found band can be wider than the chart.
    let p = common::load("design-clear-bands.toml", &["design.phi_range=[100, 8000]"]);
    let spec = p.design.as_ref().unwrap();
    let base = chart_window(spec);
    // The operating bands with their clearances, and a found band wider than the window
    // on both sides (as a design's band of [500, 4051.75] beside a 1000–3000 window).
    let mut bands: Vec<Interval> = spec.kept_clear().iter().map(|b| b.guarded()).collect();
    let wide = Interval::new(
        (base.lo - 0.3 * base.width()).max(spec.phi_range.0),
        (base.hi + 0.3 * base.width()).min(spec.phi_range.1),
    );
    bands.push(wide);
    let w = drawn_window(spec, &bands);
    eprintln!("chart window [{}, {}], drawn [{}, {}], {} bands", base.lo, base.hi, w.lo, w.hi, bands.len());
    assert!(wide.lo < base.lo || wide.hi > base.hi, "the test band leaves the base window");
    for b in &bands {
        assert!(w.lo <= b.lo && w.hi >= b.hi, "band [{}, {}] outside the drawn [{}, {}]", b.lo, b.hi, w.lo, w.hi);
    }
}

#[test]
fn compare_legends_of_two_files_with_one_title_differ() {
    let dir = common::scratch("compare-legends");
    let text = std::fs::read_to_string(common::problem_path("fig11-closed-2000.toml")).unwrap();
    let (a, b) = (dir.join("reference.toml"), dir.join("tuned.toml"));
    std::fs::write(&a, &text).unwrap();
    std::fs::write(&b, text.replace("resistance = 0.0", "resistance = 10.0")).unwrap();
    let out = dir.join("out");
    common::run_ok(
        common::bin()
            .args(["chart", a.to_str().unwrap(), "--phi", "1200:1260:30", "--beta", "0:0.3:0.3", "--out"])
            .arg(&out)
            .args(["--compare", b.to_str().unwrap(), "--quiet"]),
    );
    let svg = std::fs::read_to_string(out.join("chart.svg")).unwrap();
    let entries: Vec<&str> = ["reference.toml", "tuned.toml"].into_iter().filter(|n| svg.contains(n)).collect();
    eprintln!("legend names the layers {entries:?}");
    assert_eq!(entries.len(), 2, "both files named in the legend");
}

/// fig11-closed-2000.toml with its speed in rpm: 19098.593171027442 rpm is 2000 rad/s.
fn rpm_problem(dir: &Path) -> std::path::PathBuf {
    let text = std::fs::read_to_string(common::problem_path("fig11-closed-2000.toml")).unwrap();
    let changed = text.replacen("\nspeed = 2000.0", "\nspeed_rpm = 19100.0", 1);
    assert_ne!(changed, text, "the speed key was found");
    let file = dir.join("rpm.toml");
    std::fs::write(&file, changed).unwrap();
    file
}

#[test]
fn speeds_given_in_rpm_come_back_in_rpm() {
    let dir = common::scratch("rpm-echo");
    let file = rpm_problem(&dir);
    let out = dir.join("campbell");
    let text = common::run_ok(
        common::bin().args(["campbell", file.to_str().unwrap(), "--speeds", "0:24000:2000rpm", "--out"]).arg(&out),
    );
    eprintln!("{text}");
    assert!(text.contains("(0 to 24000 rpm (0 to 2513.3 rad/s))"), "{text}");
    assert!(text.contains("operating speed: 19100 rpm (2000.1 rad/s)"), "{text}");
    assert!(text.contains("critical speeds (crossings with 1x):"), "{text}");
    let svg = std::fs::read_to_string(out.join("campbell.svg")).unwrap();
    assert!(
        svg.contains("speed n (rpm)") && svg.contains("operating speed 19100 rpm"),
        "Campbell axis and marker in rpm"
    );
    let json = common::json(&out.join("campbell.json"));
    assert!(json["critical_speeds"].as_array().is_some_and(|c| !c.is_empty()), "critical speeds in campbell.json");
    let bode = dir.join("bode");
    let text = common::run_ok(
        common::bin()
            .args(["unbalance", file.to_str().unwrap(), "--speeds", "6000:24000:3000rpm", "--out"])
            .arg(&bode)
            .arg("--quiet"),
    );
    assert!(text.contains("6000 to 24000 rpm") && text.contains(" rpm ("), "{text}");
    assert!(std::fs::read_to_string(bode.join("bode.svg")).unwrap().contains("speed n (rpm)"));
    // A tuned file keeps the user's key and value.
    let p = rotorshunt::problem::Problem::from_path(&file, &[]).unwrap();
    let tuned = tuned_file(&p.data, &[], &p.rpm).unwrap();
    assert!(tuned.lines().any(|l| l == "speed_rpm = 19100.0"), "{tuned}");
    assert!(!tuned.lines().any(|l| l.starts_with("speed = ")), "{tuned}");
}

#[test]
fn a_two_key_sweep_is_a_table_with_a_column_per_key_and_readable_folders() {
    let dir = common::scratch("sweep-table");
    let study = common::coarse_study(
        &dir,
        "study.toml",
        "[sweep]\n\"circuit.branches[0].tuning_frequency\" = [900.0, 1000.0]\n\"circuit.branches[0].resistance\" = [0.0, 50.0]\n",
    );
    let out = dir.join("out");
    common::run_ok(common::bin().args(["study", study.to_str().unwrap(), "--out"]).arg(&out).arg("--quiet"));
    let csv = std::fs::read_to_string(out.join("summary/summary.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    eprintln!("{csv}");
    assert_eq!(
        &header[..3],
        ["case", "circuit.branches[0].tuning_frequency", "circuit.branches[0].resistance"],
        "a column per swept key, in the study file's order"
    );
    let at = |name: &str| header.iter().position(|h| *h == name).unwrap();
    assert!(at("band_lo") < at("band_hi") && header.contains(&"clipped"), "{header:?}");
    let mut folders: Vec<String> = std::fs::read_dir(out.join("cases"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    folders.sort();
    assert_eq!(
        folders,
        [
            "resistance=0.0,tuning_frequency=1000.0",
            "resistance=0.0,tuning_frequency=900.0",
            "resistance=50.0,tuning_frequency=1000.0",
            "resistance=50.0,tuning_frequency=900.0"
        ]
    );
    assert!(out.join("summary/figure.png").exists());
    let md = std::fs::read_to_string(out.join("summary/summary.md")).unwrap();
    assert!(md.contains("![Study: band_width against circuit.branches[0].tuning_frequency](figure.png)"), "{md}");
}

#[test]
fn progress_never_shows_a_total_of_0_and_a_long_phase_counts_up() {
    // A slow load: one period of φ = 1 rad/s is 6.3 s of rotor time, some 4e5 RK4 steps.
    let dir = common::scratch("progress-moves");
    let out = common::bin()
        .env("ROTORSHUNT_TEST_PROGRESS_EVERY", "10")
        .args(["response", &common::problem_path("fig11-closed-2000.toml"), "--phi", "1", "--beta", "0.1"])
        .args(["--periods", "1", "--out"])
        .arg(dir.join("out"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let stderr = String::from_utf8_lossy(&out.stderr);
    let lines: Vec<&str> = stderr.lines().filter(|l| l.starts_with("progress: ")).collect();
    assert!(!lines.iter().any(|l| l.contains("/0 steps")), "{stderr}");
    let done: Vec<u64> = lines
        .iter()
        .filter_map(|l| l.strip_prefix("progress: response: response (phase 2 of 3): "))
        .filter_map(|r| r.split_once('/')?.0.parse().ok())
        .collect();
    eprintln!("response phase done counts: {done:?}");
    assert!(done.len() >= 5 && done.windows(2).all(|w| w[0] < w[1]), "{stderr}");
}

#[test]
fn every_source_path_the_docs_cite_exists() {
    let root = common::root();
    let mut files = vec![root.join("README.md")];
    for e in std::fs::read_dir(root.join("docs")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "md") {
            files.push(p);
        }
    }
    let mut cited = 0;
    let mut missing = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        for (i, _) in text.match_indices("src/") {
            if i > 0 && text[..i].ends_with(|c: char| c.is_ascii_alphanumeric() || c == '_' || c == '/') {
                continue;
            }
            let path: String = text[i..]
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '.' | '/' | '-'))
                .collect();
            let path = path.trim_end_matches('.');
            cited += 1;
            if !root.join(path).exists() {
                missing.push(format!("{}: {path}", f.display()));
            }
        }
    }
    eprintln!("{cited} src/ paths cited in {} files", files.len());
    assert!(cited > 10, "{cited}");
    assert!(missing.is_empty(), "{missing:?}");
}

#[test]
fn the_readme_stays_short() {
    let lines = std::fs::read_to_string(common::root().join("README.md")).unwrap().lines().count();
    eprintln!("README.md: {lines} lines");
    assert!(lines <= 250, "{lines}");
}
