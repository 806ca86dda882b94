//! Plots: axis labels with units, legends that cover no data, titles from the actual
//! configuration, and Campbell tracks that keep a mode's identity when another mode
//! enters the window.

use crate::common;
use common::load;
use rotorshunt::analysis::campbell::{campbell, CampbellResult};
use rotorshunt::analysis::modes::{whirl_modes_of, Whirl};
use rotorshunt::analysis::Interval;
use rotorshunt::analysis::Rotor;
use rotorshunt::numbers::SpeedUnit;
use rotorshunt::progress::Silent as Quiet;
use rotorshunt::report::campbell::campbell_plot;
use rotorshunt::report::plot::{CurvePlot, Drawing, Figure, Layout};

/// The case: the tuned widest-band circuit, whose b3 comes down into the lowest
/// six backward whirls and veers with an electrical mode.
const TUNED: [&str; 2] = ["circuit.branches[0].tuning_frequency=733.75", "circuit.branches[0].resistance=13.708"];

fn diagram(count: usize) -> (CampbellResult, Rotor, rotorshunt::problem::Problem) {
    let p = load("design-widest-band.toml", &TUNED);
    let rotor = Rotor::new(&p.model).unwrap();
    let speeds = Interval::new(0.0, 3000.0).stepped(100.0, 1000).unwrap();
    let r = campbell(&rotor, &p.settings, &speeds, count, &|| {}).unwrap();
    (r, rotor, p)
}

/// Every data point of `plot` inside its plotting area, and the legend outside it.
fn legend_covers_no_data(plot: &CurvePlot, layout: &Layout) {
    assert!(layout.legend.is_some(), "a legend is drawn");
    assert!(!layout.legend_overlaps_plot(), "legend {:?} overlaps the plot {:?}", layout.legend, layout.plot);
    let legend = layout.legend.unwrap();
    let [(x0, y0), (x1, y1)] = layout.plot;
    for c in &plot.curves {
        for &p in &c.points {
            let inside =
                p.0 >= plot.x_range.0 && p.0 <= plot.x_range.1 && p.1 >= plot.y_range.0 && p.1 <= plot.y_range.1;
            if !inside {
                continue;
            }
            let (px, py) = plot.to_pixel(layout, p);
            assert!(px >= x0 as f64 - 1.0 && px <= x1 as f64 + 1.0 && py >= y0 as f64 - 1.0 && py <= y1 as f64 + 1.0);
            let covered = px >= legend[0].0 as f64
                && px <= legend[1].0 as f64
                && py >= legend[0].1 as f64
                && py <= legend[1].1 as f64;
            assert!(!covered, "{} at {p:?} is under the legend", c.name);
        }
    }
}

#[test]
fn campbell_legend_covers_no_curve_and_axes_carry_units() {
    let (r, _, _) = diagram(6);
    let plot = campbell_plot(
        &r,
        "Campbell diagram: a title long enough to need fitting into the width of the image, and then some more words",
        SpeedUnit::RadPerS,
        &[],
    );
    let layout = plot.layout().unwrap();
    legend_covers_no_data(&plot, &layout);
    let svg = plot.svg().unwrap();
    assert!(svg.contains("speed Ω (rad/s)") && svg.contains("whirl frequency ω (rad/s)"));
    assert!(svg.contains("1× (ω = Ω)"), "the synchronous line is labelled");
    assert!(!svg.contains("500.0"), "ticks without spurious decimals");
    // Every track has its own colour-and-marker style, and forward/backward differ in dash.
    // (The curves after the tracks are the 1× line and the critical speeds' markers.)
    let tracks = &plot.curves[..r.tracks.len()];
    let styles: std::collections::HashSet<_> = tracks.iter().map(|c| (c.color, format!("{:?}", c.marker))).collect();
    assert_eq!(styles.len(), tracks.len());
    for (c, t) in plot.curves.iter().zip(&r.tracks) {
        assert_eq!(c.dash == rotorshunt::report::style::Dash::Dashed, t.whirl == Whirl::Backward, "{}", c.name);
    }
}

#[test]
fn campbell_tracks_keep_their_identity_when_a_mode_enters_the_window() {
    let (six, rotor, p) = diagram(6);
    let (seven, _, _) = diagram(7);
    // Unique labels, and each label's curve continuous in frequency across Ω.
    let tags: std::collections::HashSet<_> =
        six.tracks.iter().map(|t| (t.tag.clone(), t.whirl == Whirl::Forward)).collect();
    assert_eq!(tags.len(), six.tracks.len());
    for t in &six.tracks {
        for w in t.points.windows(2) {
            let jump = (w[1].frequency - w[0].frequency).abs();
            assert!(jump < 0.05 * w[0].frequency, "{} jumps {jump} rad/s at {} rad/s", t.tag, w[1].speed);
        }
    }
    // Every mode among the lowest six of its direction, at every speed, is on exactly one
    // track: none is lost and none is shared.
    for (s, &w) in six.speeds.iter().enumerate() {
        let modes = whirl_modes_of(&rotor, &p.settings, w).unwrap();
        for whirl in [Whirl::Forward, Whirl::Backward] {
            for m in modes.modes.iter().filter(|m| m.whirl == whirl).take(6) {
                let holders = six
                    .tracks
                    .iter()
                    .filter(|t| t.whirl == whirl && t.points.iter().any(|q| q.speed == w && q.frequency == m.frequency))
                    .count();
                assert_eq!(holders, 1, "{} at speed index {s}", m.tag());
            }
        }
    }
    // Identity, not rank: a seventh mode in the window (b3 from the first speed) gets its
    // own track and takes no other track's label or points.
    assert!(seven.tracks.len() > six.tracks.len());
    for t in &six.tracks {
        let same = seven.tracks.iter().find(|u| u.tag == t.tag && u.whirl == t.whirl).unwrap();
        assert_eq!(same.points, t.points, "{}", t.tag);
    }
    let b3 = seven.tracks.iter().find(|t| t.tag == "b3").expect("b3 tracked with --count 7");
    assert!(b3.points.first().unwrap().frequency > 3000.0);
    // The veering is named on the curve that changes character.
    assert!(six.tracks.iter().any(|t| t.tag == "bs1" && t.last_tag == "b3"));
}

#[test]
fn set_overrides_and_compare_labels_appear_in_titles_and_legends() {
    let dir = common::tmp("titles");
    let flags = "--set circuit.state=open --phi 600:800:50 --beta 0:0.4:0.2 --compare-set circuit.state=closed";
    let mut chart = common::bin();
    chart.args(["chart", &common::problem_path("fig9-open-2000.toml")]).args(flags.split(' '));
    common::run_ok(chart.arg("--out").arg(&dir));
    for f in ["chart.svg", "growth.svg"] {
        let svg = std::fs::read_to_string(dir.join(f)).unwrap();
        assert!(svg.contains("[circuit.state=open]"), "{f} title names the override");
        assert!(svg.contains("excitation frequency φ (rad/s)") && svg.contains("dynamic load β (−)"), "{f}");
    }
    let svg = std::fs::read_to_string(dir.join("chart.svg")).unwrap();
    assert!(svg.contains("unstable: open circuit") && svg.contains("unstable: closed circuit"), "both layers by state");
    std::fs::remove_dir_all(&dir).unwrap();

    let dir = common::tmp("campbell-title");
    let flags = "--set load.alpha=0.25 --speeds 0:2000:1000 --count 2";
    let mut campbell = common::bin();
    campbell.args(["campbell", &common::problem_path("paper-open.toml")]).args(flags.split(' '));
    common::run_ok(campbell.arg("--out").arg(&dir));
    let svg = std::fs::read_to_string(dir.join("campbell.svg")).unwrap();
    assert!(svg.contains("[load.alpha=0.25]"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn stability_and_bode_legends_sit_beside_the_plot() {
    use rotorshunt::analysis::chart::chart;
    use rotorshunt::analysis::floquet::FloquetSystem;
    use rotorshunt::analysis::unbalance::{probes, unbalance_response};
    use rotorshunt::report::chart::{Layer, Span, StabilityPlot};
    use rotorshunt::report::unbalance::{plot_pareto, BodeLayer, BodePlot};
    let p = load("fig9-open-2000.toml", &[]);
    let rotor = Rotor::new(&p.model).unwrap();
    let fs = FloquetSystem::new(&rotor, &p.settings, p.model.speed).unwrap();
    let c = chart(&fs, &[600.0, 700.0, 800.0], &[0.0, 0.2, 0.4], &Quiet);
    let plot =
        StabilityPlot::new("chart", vec![Layer { name: "open circuit".into(), color: (31, 119, 180), chart: c }])
            .with_spans(vec![Span {
                lo: 650.0,
                hi: 700.0,
                beta: None,
                name: "operating band".into(),
                color: (0, 150, 0),
            }])
            .with_levels(vec![(0.3, "β_op = 0.3".into())]);
    let layout = plot.layout().unwrap();
    assert!(layout.legend.is_some() && !layout.legend_overlaps_plot(), "{layout:?}");
    let svg = plot.svg().unwrap();
    assert!(svg.contains("operating band") && svg.contains("β_op = 0.3"));

    let speeds: Vec<f64> = (0..50).map(|i| 300.0 + 4.0 * i as f64).collect();
    let r = unbalance_response(&rotor, &speeds, &probes(&rotor, &[]).unwrap(), &rotorshunt::progress::Silent).unwrap();
    let bode = BodePlot {
        title: "bode".into(),
        layers: vec![BodeLayer { name: String::new(), dashed: false, result: &r }],
        unit: SpeedUnit::RadPerS,
    };
    let layout = bode.layout().unwrap();
    assert!(layout.legend.is_some() && !layout.legend_overlaps_plot(), "{layout:?}");
    let svg = bode.svg().unwrap();
    assert!(svg.contains("amplitude |U| (m)") && svg.contains("phase arg U (deg)") && svg.contains("speed Ω (rad/s)"));

    let pareto = plot_pareto(&[(1e-3, 100.0), (5e-4, 50.0)], &["a".into(), "b".into()], "designs");
    let layout = pareto.layout().unwrap();
    legend_covers_no_data(&pareto, &layout);
    let svg = pareto.svg().unwrap();
    assert!(svg.contains("peak response (m)") && svg.contains("stable band width (rad/s)"));
}
