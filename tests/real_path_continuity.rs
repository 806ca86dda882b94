//! Continuity of the general path (issue 28): at zero anisotropy the real coordinates
//! (v, w) reproduce the complex path's stable bands on every problem of problems/ that
//! names an operating frequency, and the same design outcome on the paper's widest-band
//! design (a short run over a φ range around φ_op). tests/anisotropic.rs compares the
//! whirls of every problem and a Floquet chart; this file compares what the engineer
//! reads: bands and tuned values. Problems that ask the same band search of the same input
//! are compared once, and the two paths run side by side.

use crate::common;

use rayon::prelude::*;
use rotorshunt::analysis::floquet::FloquetSystem;
use rotorshunt::analysis::regions::{check_reliable, RegionSettings};
use rotorshunt::analysis::{Interval, Rotor};
use rotorshunt::problem::Problem;

/// The override that sends an isotropic problem down the general path.
const REAL: &str = "analysis.coordinates=\"real\"";

/// One fixed basis on both paths: what is compared is the coordinates, on the same
/// reduced model (the basis's sizing runs the same code on either).
const FIXED_BASIS: &str = "analysis.reduced_modes=8";

/// The two paths' monodromies differ by round-off (8.2e-12 on max|μ|, tests/anisotropic.rs),
/// so the tuned values of a short design agree far below any tolerance an engineer uses.
const VALUES_AGREE: f64 = 1e-9;

/// The stable band of `p` around φ_op at β_op at its first operating speed (rad/s): the
/// search of [`rotorshunt::analysis::regions::band`], its β = 0 check included, without
/// what only names the bounds ([`common::unnamed_band`]: the names are not compared).
fn band_edges(p: &Problem) -> Option<(f64, f64)> {
    let spec = p.design.as_ref().expect("a [design] table");
    let speed = spec.speeds[0];
    let rotor = Rotor::new(&p.model).unwrap();
    let fs = FloquetSystem::new(&rotor, &p.settings, speed).unwrap();
    let window = Interval::new(spec.phi_range.0, spec.phi_range.1);
    let phi_op = spec.phi_op().expect("an operating frequency");
    check_reliable(&fs, window).unwrap();
    let b = common::unnamed_band(&fs, &RegionSettings::default(), window, phi_op, spec.level);
    b.band.map(|i| (i.lo, i.hi))
}

/// Every problem file of problems/ (and its subfolders but `studies/`, which holds study
/// files), by name relative to it.
fn problem_names() -> Vec<String> {
    let root = common::root().join("problems");
    let mut out = Vec::new();
    let mut dirs = vec![root.clone()];
    while let Some(d) = dirs.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let path = e.unwrap().path();
            if path.is_dir() {
                if path.file_name().is_some_and(|n| n != "studies") {
                    dirs.push(path);
                }
            } else if path.extension().is_some_and(|x| x == "toml") {
                out.push(path.strip_prefix(&root).unwrap().to_string_lossy().into_owned());
            }
        }
    }
    out.sort();
    out
}

/// What [`band_edges`] reads of a problem: its model, `[analysis]` settings, first
/// operating speed, window, φ_op and β_op. Problems equal in all of these ask the same
/// band search of the same input, which gives the same result bit for bit
/// (tests/reproducibility.rs): they are compared once, as one group.
fn band_input(p: &Problem) -> impl PartialEq + '_ {
    let spec = p.design.as_ref().expect("a [design] table");
    (&p.model, &p.settings, spec.speeds[0], spec.phi_range, spec.phi_op(), spec.level)
}

#[test]
fn real_coordinates_give_the_same_band_on_every_problem_with_an_operating_frequency() {
    let mut groups: Vec<(Vec<String>, Problem)> = Vec::new();
    for name in problem_names() {
        let complex = match Problem::from_path(common::problem_path(&name), &[FIXED_BASIS.into()]) {
            Ok(p) => p,
            Err(e) => panic!("{name}: {e}"),
        };
        // Anisotropic problems already run on the general path; a design without φ_op
        // (min-peak without a band) has no band to compare.
        let has_band = complex.design.as_ref().is_some_and(|d| d.phi_op().is_some());
        if complex.model.real_coordinates() || !has_band {
            continue;
        }
        match groups.iter_mut().find(|(_, q)| band_input(q) == band_input(&complex)) {
            Some((names, _)) => names.push(name),
            None => groups.push((vec![name], complex)),
        }
    }
    let compared: usize = groups.iter().map(|(names, _)| names.len()).sum();
    // The groups in parallel, each on both paths.
    groups.par_iter().for_each(|(names, complex)| {
        let name = names.join(" = ");
        let real = common::load(&names[0], &[FIXED_BASIS, REAL]);
        assert!(real.model.real_coordinates(), "{name}: the override must select the general path");
        let (a, b) = rayon::join(|| band_edges(complex), || band_edges(&real));
        eprintln!("{name}: band complex {a:?}, real {b:?}");
        assert_eq!(a, b, "{name}");
    });
    // The catalogue's widest-band, margin, robust, clear-band and min-peak designs with φ_op.
    assert!(compared >= 5, "only {compared} problems compared");
}

#[test]
fn real_coordinates_give_the_same_design_outcome() {
    // A short design (1 start of 3 iterations), its catalogues over 900–1600 rad/s around
    // φ_op: the same request on both paths, which is what is compared.
    let short = [
        "design.starts=1",
        "design.max_iterations=3",
        "design.phi_range=[900.0, 1600.0]",
        FIXED_BASIS,
        "design.refined_check=false",
    ];
    let complex = common::load("design-widest-band.toml", &short);
    let real = common::load("design-widest-band.toml", &[short[0], short[1], short[2], short[3], short[4], REAL]);
    let silent = rotorshunt::progress::Silent;
    let run =
        |p: &rotorshunt::Problem| rotorshunt::run_design(&p.machine(), p.design.as_ref().unwrap(), &silent).unwrap();
    let (a, b) = rayon::join(|| run(&complex), || run(&real));
    let band = |o: &rotorshunt::DesignOutcome| o.after_bands()[0].band.band.map(|i| (i.lo, i.hi));
    eprintln!(
        "design: complex {:?} {:?} band {:?} ({} candidates); real {:?} {:?} band {:?} ({} candidates)",
        a.status,
        a.after,
        band(&a),
        a.candidates,
        b.status,
        b.after,
        band(&b),
        b.candidates
    );
    assert_eq!(a.status, b.status);
    assert_eq!((a.verified(), a.candidates), (b.verified(), b.candidates));
    for (x, y) in a.after.iter().zip(&b.after) {
        assert!((x - y).abs() <= VALUES_AGREE * x.abs().max(1.0), "{:?} vs {:?}", a.after, b.after);
    }
    assert_eq!(band(&a), band(&b));
}
