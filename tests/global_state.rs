//! The library leaves a caller's process-wide state alone: faer's global parallelism is
//! neither changed nor read by any analysis. Every faer kernel the library calls takes its
//! parallelism explicitly (`Par::Seq`; `linalg::seq`), so the results are the same to the
//! bit whatever the caller's global setting and rayon pool.
//!
//! One test function: the global setting is process-wide, and the phases below must not
//! run at the same time as each other.

mod common;
use common::load;
use faer::Par;
use rotorshunt::analysis::campbell::campbell;
use rotorshunt::analysis::chart::chart;
use rotorshunt::analysis::floquet::dstm::monodromy_rk4;
use rotorshunt::analysis::floquet::FloquetSystem;
use rotorshunt::analysis::modes::whirl_modes_of;
use rotorshunt::analysis::regions::{band, catalogue, CatalogueRequest, RegionSettings};
use rotorshunt::analysis::response::response;
use rotorshunt::analysis::{Interval, Rotor};

/// Every analysis of the library that reaches faer, on small ranges, as one text: `{:?}`
/// writes each f64 as the shortest text that reads back to the same bits, so equal texts
/// are bit-identical results.
fn analyses() -> String {
    let mut out = Vec::new();
    // Fig. 11 (closed circuit, undamped: the Hermitian first-order form of the whirls):
    // buckling load, reduced model, chart, catalogue with tracking, band, responses, the
    // DSTM (Padé exponential, LU) and RK4 (products) paths.
    let p = load("fig11-closed-2000.toml", &[]);
    let rotor = Rotor::new(&p.model).unwrap();
    let fs = FloquetSystem::new(&rotor, &p.settings, p.model.speed).unwrap();
    out.push(format!("{fs:?}"));
    let full = whirl_modes_of(&rotor, &fs.settings, fs.speed).unwrap();
    out.push(format!("{full:?}"));
    let phis: Vec<f64> = (0..12).map(|i| 1100.0 + 15.0 * i as f64).collect();
    let betas: Vec<f64> = (0..6).map(|i| 0.1 * i as f64).collect();
    out.push(format!("{:?}", chart(&fs, &phis, &betas, &|| {})));
    let settings = RegionSettings::default();
    let req = CatalogueRequest { range: Interval::new(1150.0, 1250.0), beta_max: 0.5, level: 0.3, track: true };
    out.push(format!("{:?}", catalogue(&fs, &full, &settings, &req).unwrap()));
    out.push(format!("{:?}", band(&fs, &full, &settings, Interval::new(1000.0, 1500.0), 1230.0, 0.3).unwrap()));
    out.push(format!("{:?}", response(&fs, 1180.0, 0.3, 4)));
    out.push(format!("{:?}", fs.point_dstm(1180.0, 0.5, 256)));
    out.push(format!("{:?}", monodromy_rk4(&fs.system, 1180.0, 0.5, 256).matrix));
    // Fig. 13 with R = 10 Ω: a damped model, the general eigensolver of the first-order form.
    let p = load("fig13-r10.toml", &[]);
    let rotor = Rotor::new(&p.model).unwrap();
    out.push(format!("{:?}", whirl_modes_of(&rotor, &p.settings, 1500.0).unwrap()));
    // L = 0 on branch 1: a massless charge with R = 0, condensed statically.
    let mut zero = load("paper-closed.toml", &[]).model;
    for r in &mut zero.rings {
        r.circuit.branches[0].inductance = 0.0;
    }
    let p = load("paper-closed.toml", &[]);
    let rotor = Rotor::new(&zero).unwrap();
    out.push(format!("{:?}", whirl_modes_of(&rotor, &p.settings, 2000.0).unwrap()));
    // L = 0 and R > 0: the shift-invert solver of Eq. (18–21).
    for r in &mut zero.rings {
        r.circuit.branches[0].resistance = 5.0;
    }
    let rotor = Rotor::new(&zero).unwrap();
    out.push(format!("{:?}", whirl_modes_of(&rotor, &p.settings, 2000.0).unwrap()));
    // A Campbell diagram (rayon over speeds) of the paper's closed circuit.
    let rotor = Rotor::new(&p.model).unwrap();
    let speeds: Vec<f64> = (0..5).map(|i| 500.0 * i as f64).collect();
    out.push(format!("{:?}", campbell(&rotor, &p.settings, &speeds, 4, &|| {}).unwrap()));
    out.join("\n")
}

fn in_pool(threads: usize) -> String {
    rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("thread pool").install(analyses)
}

#[test]
fn analyses_neither_change_nor_read_faer_global_parallelism() {
    // Disabled, faer panics ("Global parallelism is disabled.") in any call that reads the
    // setting: the analyses must not make one.
    faer::disable_global_parallelism();
    let reference = analyses();
    // A caller's own setting is what it was after the analyses, and does not change them.
    for global in [Par::rayon(2), Par::Seq] {
        faer::set_global_parallelism(global);
        let again = analyses();
        assert_eq!(faer::get_global_parallelism(), global, "the analyses changed the global setting");
        assert!(again == reference, "results differ with the global parallelism {global:?}");
    }
    faer::set_global_parallelism(Par::rayon(2));
    for threads in [1, 2] {
        let again = in_pool(threads);
        assert_eq!(faer::get_global_parallelism(), Par::rayon(2), "the analyses changed the global setting");
        assert!(again == reference, "results differ in a pool of {threads} threads");
    }
}
