//! Floquet performance on the Fig. 11 configuration (problems/fig11-closed-2000.toml:
//! closed circuit, Ω = 2000 rad/s, M = 8) and the fast path's speed-up over the reference
//! DSTM, measured in the same run on the same points.

use criterion::{criterion_group, criterion_main, Criterion};
use rotorshunt::analysis::chart::chart;
use rotorshunt::analysis::floquet::FloquetSystem;
use rotorshunt::analysis::Interval;
use rotorshunt::analysis::Rotor;
use rotorshunt::problem::Problem;
use std::time::Instant;

fn system() -> FloquetSystem {
    let p = Problem::from_path(format!("{}/problems/fig11-closed-2000.toml", env!("CARGO_MANIFEST_DIR")), &[]).unwrap();
    let rotor = Rotor::new(&p.model).unwrap();
    FloquetSystem::new(&rotor, &p.settings, p.model.speed).unwrap()
}

fn bench(c: &mut Criterion) {
    let fs = system();
    let phis = Interval::new(100.0, 14000.0).stepped(25.0, 1000).unwrap();
    let betas = Interval::new(0.0, 1.0).stepped(0.025, 1000).unwrap();
    let mut g = c.benchmark_group("floquet");
    g.sample_size(10);
    g.bench_function("fig11 chart 22837 points, fast", |b| b.iter(|| chart(&fs, &phis, &betas, &|| {})));
    g.bench_function("one point fast (1180, 0.5)", |b| b.iter(|| fs.point_fast(&fs.table(1180.0, 0.5), 0.5)));
    g.bench_function("one point DSTM 4096 steps (1180, 0.5)", |b| b.iter(|| fs.point_dstm(1180.0, 0.5, 4096)));
    g.finish();

    // Speed-up in the same run: 24 points spread over the grid, each computed on its own
    // (a fresh per-φ table per point, no sharing across β) by both paths, one thread.
    let points: Vec<(f64, f64)> = (0..24).map(|i| (300.0 + 550.0 * i as f64, 0.1 + 0.035 * i as f64)).collect();
    let time = |f: &dyn Fn(f64, f64)| {
        let t = Instant::now();
        for &(phi, beta) in &points {
            f(phi, beta);
        }
        t.elapsed().as_secs_f64() / points.len() as f64
    };
    let fast = time(&|phi, beta| {
        std::hint::black_box(fs.point_fast(&fs.table(phi, beta), beta));
    });
    let dstm_fine = time(&|phi, beta| {
        std::hint::black_box(fs.point_dstm(phi, beta, 4096));
    });
    let dstm_512 = time(&|phi, beta| {
        std::hint::black_box(fs.point_dstm(phi, beta, 512));
    });
    let t = Instant::now();
    let c = chart(&fs, &phis, &betas, &|| {});
    let grid = t.elapsed().as_secs_f64();
    println!(
        "same-run per point: fast {:.1} us, DSTM(4096) {:.1} us, DSTM(512) {:.1} us",
        fast * 1e6,
        dstm_fine * 1e6,
        dstm_512 * 1e6
    );
    println!(
        "speed-up of the fast path: {:.0}x over DSTM(4096, ~1e-8), {:.0}x over DSTM(512, ~5e-7, similar accuracy)",
        dstm_fine / fast,
        dstm_512 / fast
    );
    println!(
        "fig11 grid: {} points in {:.2} s wall with the fast chart (per-phi sharing, {} threads); DSTM(512) estimate {:.0} s -> {:.0}x",
        c.points.len(),
        grid,
        rayon::current_num_threads(),
        dstm_512 * c.points.len() as f64 / rayon::current_num_threads() as f64,
        dstm_512 * c.points.len() as f64 / rayon::current_num_threads() as f64 / grid
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);
