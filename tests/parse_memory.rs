//! The parse-memory estimate (`TomlCost`) is an upper bound of what loading a text
//! allocates, for the TOML structures that cost the parser most per byte of text.
//!
//! Heap use is counted by this test binary's own allocator, so it is exact and independent
//! of the host; the binary holds this one test so that nothing else allocates meanwhile.

mod common;
use rotorshunt::problem::input::TomlCost;
use rotorshunt::problem::Problem;
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The system allocator, counting the bytes in use and their high-water mark.
struct Counting;

static IN_USE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

// SAFETY: every call is forwarded to the system allocator unchanged; the counters only
// observe sizes.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            let now = IN_USE.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
            PEAK.fetch_max(now, Ordering::Relaxed);
        }
        p
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) };
        IN_USE.fetch_sub(layout.size(), Ordering::Relaxed);
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            // The old and the new block may both exist during the move.
            let now = IN_USE.fetch_add(new_size, Ordering::Relaxed) + new_size;
            PEAK.fetch_max(now, Ordering::Relaxed);
            IN_USE.fetch_sub(layout.size(), Ordering::Relaxed);
        }
        p
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// Bytes allocated at the peak of loading `text`, beyond what was in use before.
fn load_peak(text: &str) -> usize {
    let before = IN_USE.load(Ordering::Relaxed);
    PEAK.store(before, Ordering::Relaxed);
    let result = Problem::from_text(text, "shape.toml", &[]);
    let peak = PEAK.load(Ordering::Relaxed) - before;
    drop(result);
    peak
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
