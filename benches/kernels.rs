//! The fast path's kernels against their straightforward forms, timed in the same run on
//! the same matrices (16×16 complex: M = 8 of problems/fig11-closed-2000.toml):
//! - a complex product by faer's complex kernel against the same product as one real
//!   product in split form ([`SplitMatrix`]);
//! - the Padé-13 `expm` (complex, with a linear solve) against the Taylor exponential in
//!   split form, at the 1-norms the per-φ tables see (0.2, 0.8 and 1.8 in balanced
//!   coordinates: a third of the table's exponentials in each Padé range).

use criterion::{criterion_group, criterion_main, Criterion};
use faer::linalg::matmul::matmul;
use faer::{c64, Accum, Mat, Par};
use rotorshunt::analysis::floquet::FloquetSystem;
use rotorshunt::analysis::Rotor;
use rotorshunt::linalg::{expm, norm1, ExpWorkspace, SplitMatrix};
use rotorshunt::problem::Problem;
use std::time::Instant;

/// τ(B0 + x·B1) of the Fig. 11 problem at φ = 3000 rad/s, x = 0.3, in the balanced
/// coordinates the per-φ table uses, rescaled to the 1-norm `norm`.
fn argument(fs: &FloquetSystem, norm: f64) -> Mat<c64> {
    let (b0, b1) = (&fs.system.b0, &fs.system.b1);
    let n = b0.nrows();
    let m = n / 2;
    let scale: Vec<f64> = (0..n).map(|i| if i < m { 1.0 } else { b0[(i - m, i)].norm().sqrt().max(1.0) }).collect();
    let a = Mat::from_fn(n, n, |i, j| (b0[(i, j)] + b1[(i, j)] * 0.3) * (scale[i] / scale[j]));
    let f = norm / norm1(a.as_ref());
    Mat::from_fn(n, n, |i, j| a[(i, j)] * f)
}

/// Seconds per call of `f`, the best of five rounds of `reps` calls.
fn per_call(reps: usize, mut f: impl FnMut()) -> f64 {
    (0..5)
        .map(|_| {
            let t = Instant::now();
            for _ in 0..reps {
                f();
            }
            t.elapsed().as_secs_f64() / reps as f64
        })
        .fold(f64::INFINITY, f64::min)
}

fn bench(c: &mut Criterion) {
    let p = Problem::from_path(format!("{}/problems/fig11-closed-2000.toml", env!("CARGO_MANIFEST_DIR")), &[]).unwrap();
    let rotor = Rotor::new(&p.model).unwrap();
    let fs = FloquetSystem::new(&rotor, &p.settings, p.model.speed).unwrap();
    let (a, b) = (argument(&fs, 0.8), argument(&fs, 1.8));
    let (sa, sb) = (SplitMatrix::from_complex(a.as_ref()), SplitMatrix::from_complex(b.as_ref()));
    let n = a.nrows();
    let mut out = Mat::<c64>::zeros(n, n);
    let mut split_out = SplitMatrix::zeros(n);
    let mut ws = ExpWorkspace::new(n);

    let mut g = c.benchmark_group("kernels");
    g.bench_function("complex product 16x16, faer complex kernel", |bch| {
        bch.iter(|| matmul(out.as_mut(), Accum::Replace, a.as_ref(), b.as_ref(), c64::new(1.0, 0.0), Par::Seq))
    });
    g.bench_function("complex product 16x16, split real form", |bch| bch.iter(|| split_out.set_product(sa.row(), &sb)));
    for norm in [0.2, 0.8, 1.8] {
        let x = argument(&fs, norm);
        let sx = SplitMatrix::from_complex(x.as_ref());
        g.bench_function(format!("exp, 1-norm {norm}: Pade expm"), |bch| bch.iter(|| expm(x.as_ref())));
        g.bench_function(format!("exp, 1-norm {norm}: Taylor, split form"), |bch| {
            bch.iter(|| {
                sx.exp_in(&mut ws);
            })
        });
    }
    g.finish();

    // Ratios in the same run, one thread, best of five rounds.
    let complex = per_call(20000, || {
        matmul(out.as_mut(), Accum::Replace, a.as_ref(), b.as_ref(), c64::new(1.0, 0.0), Par::Seq);
        std::hint::black_box(&out);
    });
    let split = per_call(20000, || {
        split_out.set_product(sa.row(), &sb);
        std::hint::black_box(&split_out);
    });
    println!(
        "same-run product: complex {:.2} us, split {:.2} us -> {:.2}x",
        complex * 1e6,
        split * 1e6,
        complex / split
    );
    for norm in [0.2, 0.8, 1.8] {
        let x = argument(&fs, norm);
        let sx = SplitMatrix::from_complex(x.as_ref());
        let pade = per_call(2000, || {
            std::hint::black_box(expm(x.as_ref()));
        });
        let taylor = per_call(2000, || {
            std::hint::black_box(sx.exp_in(&mut ws));
        });
        println!(
            "same-run exp at 1-norm {norm}: Pade {:.2} us, Taylor split {:.2} us -> {:.2}x",
            pade * 1e6,
            taylor * 1e6,
            pade / taylor
        );
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
