//! Cost of the region analysis on the closed-circuit Ω = 2000 rad/s problem
//! (problems/fig11-closed-2000.toml): the catalogue of φ = 100..8000 up to β_max = 1 and one
//! stable-band query, with the monodromy evaluations each used.

use criterion::{criterion_group, criterion_main, Criterion};
use rotorshunt::analysis::floquet::FloquetSystem;
use rotorshunt::analysis::modes::whirl_modes_of;
use rotorshunt::analysis::regions::{band_at, catalogue, RegionSettings};
use rotorshunt::analysis::Rotor;
use rotorshunt::problem::Problem;

fn bench(c: &mut Criterion) {
    let p = Problem::from_path(format!("{}/problems/fig11-closed-2000.toml", env!("CARGO_MANIFEST_DIR")), &[]).unwrap();
    let rotor = Rotor::new(&p.model).unwrap();
    let fs = FloquetSystem::new(&rotor, &p.settings, p.model.speed).unwrap();
    let full = whirl_modes_of(&rotor, &p.settings, p.model.speed).unwrap();
    let s = RegionSettings::default();
    let mut g = c.benchmark_group("regions");
    g.sample_size(10);
    g.bench_function("catalogue 100..8000, beta_max 1, level 0.3", |b| {
        b.iter(|| catalogue(&fs, &full, &s, (100.0, 8000.0), 1.0, 0.3, false).unwrap())
    });
    g.bench_function("band at 1000 rad/s, level 0.3", |b| {
        b.iter(|| {
            let mut n = 0;
            band_at(&fs, &s, 1000.0, 0.3, (50.0, 20000.0), &mut n)
        })
    });
    g.finish();
    let cat = catalogue(&fs, &full, &s, (100.0, 8000.0), 1.0, 0.3, false).unwrap();
    let mut n = 0;
    let band = band_at(&fs, &s, 1000.0, 0.3, (50.0, 20000.0), &mut n);
    println!(
        "catalogue: {} regions, {} monodromy evaluations; band {:?}: {} evaluations",
        cat.regions.len(),
        cat.evaluations,
        band,
        n
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);
