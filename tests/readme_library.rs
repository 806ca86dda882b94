//! The "Using the library" section of `docs/library.md` (the library guide the README links
//! to) is the program `examples/library_tour.rs`, word for word, and the program prints what
//! the guide says it prints.

use crate::common;
use common::pins;

/// The first ```rust block after the heading "## Using the library" of `docs/library.md`.
fn readme_block() -> String {
    let readme = std::fs::read_to_string(common::root().join("docs/library.md")).unwrap();
    let section = &readme[readme.find("## Using the library").expect("docs/library.md has the library section")..];
    let start = section.find("```rust\n").expect("a rust block") + "```rust\n".len();
    let end = start + section[start..].find("```").expect("the block ends");
    section[start..end].to_string()
}

#[test]
fn the_readme_shows_the_example_exactly() {
    let example = std::fs::read_to_string(common::root().join("examples/library_tour.rs")).unwrap();
    // The example is its module doc followed by the guide's code, unchanged.
    let code: String =
        example.lines().skip_while(|l| l.starts_with("//!") || l.is_empty()).map(|l| format!("{l}\n")).collect();
    assert_eq!(code, readme_block(), "examples/library_tour.rs differs from the library section of docs/library.md");
}

#[test]
fn the_example_prints_what_the_readme_says() {
    // `cargo test` builds the examples beside the test binaries: target/<profile>/examples.
    let exe = std::env::current_exe().unwrap();
    let profile = exe.parent().and_then(|d| d.parent()).unwrap();
    let tour = profile.join("examples").join(format!("library_tour{}", std::env::consts::EXE_SUFFIX));
    assert!(tour.exists(), "{} not built: run through `cargo test`", tour.display());
    let out = std::process::Command::new(&tour).current_dir(common::root()).output().unwrap();
    assert!(out.status.success(), "library_tour failed: {}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    println!("{text}");
    // The figures the guide's paragraph after the program quotes: regression pins
    // (tests/common/pins.rs, each with its origin) and a property.
    let claims =
        pins::TOUR_WHIRLS.iter().chain([&pins::TOUR_CHART]).chain(&pins::TOUR_REGIONS).chain([&pins::TOUR_BAND]);
    for claim in claims.chain([&"(verified: true)"]) {
        assert!(text.contains(claim), "docs/library.md says the tour prints `{claim}`:\n{text}");
    }
    // Independently of any earlier output: the whirls the tour prints are the paper's
    // Table 3 (closed circuit, Ω = 2000 rad/s) within its 0.1 % (tests/paper_tables.rs).
    for (tag, paper) in [("f1", 398.5), ("b1", 300.1)] {
        let printed: f64 = text
            .lines()
            .find_map(|l| {
                let mut words = l.split_whitespace();
                (words.next() == Some(tag)).then(|| words.next()?.parse().ok()).flatten()
            })
            .unwrap_or_else(|| panic!("the tour prints no {tag} line:\n{text}"));
        assert!(common::rel(printed, paper) < 1e-3, "{tag}: the tour prints {printed} rad/s, Table 3 has {paper}");
    }
    // The unbalance peak is a critical speed: the forward whirl at that speed, by the
    // modal solve (a second computation), equals it within the 1 rad/s grid's half step
    // and the peak refinement.
    let peak: f64 = text
        .lines()
        .find_map(|l| l.strip_prefix("unbalance at node 16: unbounded at ")?.strip_suffix(" rad/s")?.parse().ok())
        .unwrap_or_else(|| panic!("the tour prints no unbounded unbalance peak:\n{text}"));
    let p = rotorshunt::Problem::from_path(common::problem_path("fig11-closed-2000.toml"), &[]).unwrap();
    let f1 = p.operating_point_at(peak).unwrap().modes.forward().next().unwrap().frequency;
    assert!((f1 - peak).abs() < 0.6, "unbalance peak at {peak} rad/s, f1 there {f1} rad/s");
}
