//! Cost of the region analysis on the closed-circuit Ω = 2000 rad/s problem
//! (problems/fig11-closed-2000.toml): the catalogue of φ = 100..8000 up to β_max = 1 and the
//! stable band around φ_op = 1000 and 1230 rad/s at β_op = 0.3 (the seeds and the model
//! prepared once, as a design candidate's are), with the monodromy evaluations each used.

use criterion::{criterion_group, criterion_main, Criterion};
use rotorshunt::analysis::floquet::FloquetSystem;
use rotorshunt::analysis::modes::whirl_modes_of;
use rotorshunt::analysis::regions::{
    band_around, catalogue, seeds_for, CatalogueRequest, Level, Probe, RegionSettings,
};
use rotorshunt::analysis::{Criterion as Rule, Interval, Rotor};
use rotorshunt::problem::Problem;

const RANGE: Interval = Interval::new(100.0, 8000.0);

fn bench(c: &mut Criterion) {
    let p = Problem::from_path(format!("{}/problems/fig11-closed-2000.toml", env!("CARGO_MANIFEST_DIR")), &[]).unwrap();
    let rotor = Rotor::new(&p.model).unwrap();
    let fs = FloquetSystem::new(&rotor, &p.settings, p.model.speed).unwrap();
    let full = whirl_modes_of(&rotor, &p.settings, p.model.speed).unwrap();
    let s = RegionSettings::default();
    let rule = Rule::of(&p.settings);
    let seeds = seeds_for(&fs, Some(&full), RANGE, rule.max_order).unwrap();
    let req = CatalogueRequest { range: RANGE, beta_max: 1.0, level: 0.3, track: false };
    let band = |phi_op: f64| {
        let probe = Probe::new(&fs, &s);
        band_around(&Level::new(&probe, rule, 0.3, RANGE), &seeds, phi_op)
    };
    let mut g = c.benchmark_group("regions");
    g.sample_size(10);
    g.bench_function("catalogue 100..8000, beta_max 1, level 0.3", |b| {
        b.iter(|| catalogue(&fs, &full, &s, &req).unwrap())
    });
    for phi_op in [1000.0, 1230.0] {
        g.bench_function(format!("band at {phi_op} rad/s, level 0.3"), |b| b.iter(|| band(phi_op)));
    }
    g.finish();
    let cat = catalogue(&fs, &full, &s, &req).unwrap();
    println!("catalogue: {} regions, {} monodromy evaluations", cat.regions.len(), cat.evaluations);
    for phi_op in [1000.0, 1230.0] {
        let b = band(phi_op);
        println!("band at {phi_op}: {:?}, {} evaluations", b.band, b.evaluations);
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
