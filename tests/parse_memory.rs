//! The parse-memory estimate (`TomlCost`) is an upper bound of what loading a text
//! allocates, for the TOML structures that cost the parser most per byte of text; and the
//! paths whose cost follows an input's size are linear in it (issue 50): a bearing's
//! speed table (loading and evaluating it) and the ROSS importer.
//!
//! Heap use is counted by this test binary's own allocator, per thread, so it is exact,
//! independent of the host and of the tests that run beside it (each test runs on a
//! thread of its own, and the paths measured start no threads).

mod common;
use rotorshunt::import::ross::{self, Options, Work};
use rotorshunt::problem::input::TomlCost;
use rotorshunt::problem::{Problem, MAX_ELEMENTS, MAX_TABLE_POINTS};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

/// The system allocator, counting on each thread the bytes in use, their high-water
/// mark, and the allocations made and their bytes.
struct Counting;

/// One thread's heap counters. In use may go below zero on a thread that frees what
/// another allocated.
#[derive(Clone, Copy)]
struct Heap {
    in_use: isize,
    peak: isize,
    allocations: u64,
    allocated: u64,
}

thread_local! {
    static HEAP: Cell<Heap> = const { Cell::new(Heap { in_use: 0, peak: 0, allocations: 0, allocated: 0 }) };
}

/// Count `grow` bytes allocated on this thread (a new block or a grown one), then `shrink`
/// bytes freed. `try_with`: nothing is counted while the thread's storage is torn down.
fn count(grow: usize, shrink: usize) {
    let _ = HEAP.try_with(|h| {
        let mut c = h.get();
        if grow > 0 {
            c.in_use += grow as isize;
            c.peak = c.peak.max(c.in_use);
            c.allocations += 1;
            c.allocated += grow as u64;
        }
        c.in_use -= shrink as isize;
        h.set(c);
    });
}

// SAFETY: every call is forwarded to the system allocator unchanged; the counters only
// observe sizes (thread-local cells of plain integers, which never allocate).
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            count(layout.size(), 0);
        }
        p
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) };
        count(0, layout.size());
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            // The old and the new block may both exist during the move.
            count(new_size, layout.size());
        }
        p
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// What `f` cost on this thread: its heap peak beyond what was in use before, the
/// allocations it made and their bytes, and its wall time (s).
#[derive(Debug, Clone, Copy)]
struct Cost {
    peak: usize,
    allocations: u64,
    allocated: u64,
    seconds: f64,
}

fn measure<T>(f: impl FnOnce() -> T) -> (T, Cost) {
    let before = HEAP.with(|h| {
        let mut c = h.get();
        c.peak = c.in_use;
        h.set(c);
        c
    });
    let start = std::time::Instant::now();
    let out = f();
    let seconds = start.elapsed().as_secs_f64();
    let after = HEAP.with(Cell::get);
    let cost = Cost {
        peak: (after.peak - before.in_use).max(0) as usize,
        allocations: after.allocations - before.allocations,
        allocated: after.allocated - before.allocated,
        seconds,
    };
    (out, cost)
}

/// Bytes allocated at the peak of loading `text`, beyond what was in use before.
fn load_peak(text: &str) -> usize {
    let (result, cost) = measure(|| Problem::from_text(text, "shape.toml", &[]));
    drop(result);
    cost.peak
}

/// The ratios of `large`'s counts to `small`'s (for an input 4× as large), printed; a
/// failure for each above `most`.
fn ratios(what: &str, small: Cost, large: Cost, most: f64, failures: &mut Vec<String>) {
    let pairs = [
        ("heap peak", small.peak as f64, large.peak as f64),
        ("allocations", small.allocations as f64, large.allocations as f64),
        ("bytes allocated", small.allocated as f64, large.allocated as f64),
    ];
    for (name, a, b) in pairs {
        let r = b / a.max(1.0);
        println!("{what}: {name} {a:.0} → {b:.0} ({r:.2}×)");
        if r > most {
            failures.push(format!("{what}: {name} grew {r:.2}× for 4× the input ({a:.0} → {b:.0})"));
        }
    }
    println!("{what}: time {:.4} s → {:.4} s (measured, not checked)", small.seconds, large.seconds);
}

/// Loading a problem whose bearing tabulates kxx, kyy and cxx over `points` speeds, and
/// evaluating its matrices at 100 speeds across the table: (load, evaluations).
fn table_costs(points: usize) -> (Cost, Cost) {
    let text = common::tabulated_jeffcott(points);
    let (problem, load) = measure(|| Problem::from_text(&text, "table.toml", &[]).expect("loads"));
    let bearing = &problem.model.bearings[0];
    let top = 10.0 * (points - 1) as f64;
    let (sum, evaluate) = measure(|| (0..100).map(|i| bearing.matrices_at(top * i as f64 / 99.0).k[0][0]).sum::<f64>());
    assert!(sum.is_finite());
    (load, evaluate)
}

#[test]
fn a_speed_table_costs_time_and_memory_linear_in_its_length() {
    // At the cap: under 100 MB (and a second) to load and evaluate.
    let cap = MAX_TABLE_POINTS;
    let (small_load, small_eval) = table_costs(cap / 4);
    let (load, evaluate) = table_costs(cap);
    println!(
        "a table of {cap} speeds: loaded in {:.4} s, heap peak {:.2} MB; 100 evaluations (8 coefficients each) in {:.4} s, heap peak {:.3} MB",
        load.seconds,
        load.peak as f64 / 1e6,
        evaluate.seconds,
        evaluate.peak as f64 / 1e6
    );
    let mut failures = Vec::new();
    if load.peak + evaluate.peak > 100_000_000 {
        failures.push(format!("a table at the cap takes {} bytes", load.peak + evaluate.peak));
    }
    // 4× the table: at most 6× the memory and the work (allocations and their bytes:
    // a dense solve allocates n² per evaluation).
    ratios("loading a table", small_load, load, 6.0, &mut failures);
    ratios("evaluating a table", small_eval, evaluate, 6.0, &mut failures);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn the_ross_importer_costs_time_and_memory_linear_in_the_elements() {
    // The most work per element (each its own material variant and section), at a
    // quarter of the cap and at the cap: heap, allocations and the importer's own counts.
    let cap = MAX_ELEMENTS as usize;
    let mut failures = Vec::new();
    for format in ["toml", "json"] {
        let import = |n: usize| {
            let text = common::ross_rotor(n, format);
            let before = Work::this_thread();
            let (result, cost) = measure(|| ross::import_text(&text, &format!("rotor.{format}"), Options::default()));
            let import = result.expect("imports");
            assert_eq!(import.rotor.materials.len(), n, "every element its own material");
            (cost, Work::this_thread().since(&before))
        };
        let (small, small_work) = import(cap / 4);
        let (large, work) = import(cap);
        println!(
            "{format}: {cap} elements: {:.4} s, heap peak {:.1} MB; {work:?}",
            large.seconds,
            large.peak as f64 / 1e6
        );
        ratios(&format!("{format} import"), small, large, 6.0, &mut failures);
        let counts = [
            ("lines scanned", small_work.lines_scanned, work.lines_scanned),
            ("elements converted", small_work.shaft_elements_converted, work.shaft_elements_converted),
            ("material names tried", small_work.material_names_tried, work.material_names_tried),
        ];
        for (name, a, b) in counts {
            let r = b as f64 / a.max(1) as f64;
            println!("{format} import: {name} {a} → {b} ({r:.2}×)");
            if r > 6.0 {
                failures.push(format!("{format} import: {name} grew {r:.2}× for 4× the elements ({a} → {b})"));
            }
        }
        assert_eq!(work.shaft_elements_converted, cap as u64);
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn the_estimate_bounds_what_loading_allocates() {
    let size = 256 * 1024;
    let repeat = |unit: &str, n: usize| vec![unit; n].join(",");
    let escaped: String =
        format!("{{{}}}", (0..12).map(|i| format!("\"\\u00{:02x}{i}\"=1", 0x61 + i)).collect::<Vec<_>>().join(","));
    let keys: String = format!("{{{}}}", (0..12).map(|i| format!("k{i}=1")).collect::<Vec<_>>().join(","));
    let shapes: Vec<(&str, String)> = vec![
        ("dotted keys", common::dotted_keys_text(size)),
        ("dotted headers", (0..size / 150).map(|i| format!("[h{i}.{}]\n", vec!["a"; 70].join("."))).collect()),
        ("integers", format!("x = [{}]\n", repeat("1", size / 2))),
        ("empty arrays", format!("x = [{}]\n", repeat("[]", size / 3))),
        ("one-element arrays", format!("x = [{}]\n", repeat("[1]", size / 4))),
        ("one-key inline tables", format!("x = [{}]\n", repeat("{a=1}", size / 6))),
        ("12-key inline tables", format!("x = [{}]\n", repeat(&keys, size / keys.len()))),
        ("12 escaped keys per table", format!("x = [{}]\n", repeat(&escaped, size / escaped.len()))),
        ("escaped strings", format!("x = [{}]\n", repeat("\"\\u0041\"", size / 9))),
        ("keys", format!("[t]\n{}", (0..size / 10).map(|i| format!("k{i}=1\n")).collect::<String>())),
        ("array tables", "[[a]]\nb=1\n".repeat(size / 10)),
        ("10^4 disks", common::many_disks_text(10_000)),
    ];
    let mut failures = Vec::new();
    for (name, text) in &shapes {
        let cost = TomlCost::of(text);
        let peak = load_peak(text);
        println!(
            "{name}: {} bytes, {} tokens, {} tables, {} arrays, {} keys: estimate {:.1} MB, allocated {:.1} MB ({:.2})",
            text.len(),
            cost.tokens,
            cost.tables,
            cost.arrays,
            cost.keys,
            cost.estimate() as f64 / 1e6,
            peak as f64 / 1e6,
            peak as f64 / cost.estimate() as f64
        );
        if peak as u64 > cost.estimate() {
            failures.push(format!("{name}: {peak} bytes allocated, above the estimate {}", cost.estimate()));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
