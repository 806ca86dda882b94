//! Data flows one way: file → problem → model → assembly → analysis → design → run →
//! report → CLI. The code's dependencies follow the types: the file layer (`problem`, `import`)
//! reads a text and builds the model, the analysis settings and the design spec, so it
//! comes after the layers whose types it builds and before the report and the command
//! line, which read a problem. A module may use its own layer and the layers before it
//! ([`rank`]); every layer is checked, the file layer included, and the only exceptions
//! are in [`EXCEPTIONS`], each with its reason. This test reads every `crate::…` path in
//! src/ (comments aside) and fails on one that runs back up the chain.

use crate::common;

/// The place of a top-level module in the dependency order; `None` for modules outside
/// it (the binary's `main`, `cli` and `reporter` are not in src/ of the library's tree
/// scanned here, but would be ranked last).
fn rank(module: &str) -> Option<u32> {
    Some(match module {
        // Numerical kernels, the file-system layer (the only writer) and the message form
        // of numbers, which any layer may use.
        "linalg" | "files" | "numbers" => 0,
        "model" => 1,
        "assembly" => 2,
        // The analyses, and the progress trait through which they report.
        "analysis" | "progress" => 3,
        "design" => 4,
        // The file layer: builds the types of every layer above from a text.
        "problem" | "import" => 5,
        // The application layer: runs a problem's jobs under their limits.
        "run" => 6,
        "report" => 7,
        // The crate's composed error, the command layer and the Python bindings.
        "error" | "Error" | "commands" | "python" => 8,
        _ => return None,
    })
}

/// Uses that run back up the chain on purpose: (file, the module it names, why). Empty:
/// every layer keeps the order.
const EXCEPTIONS: &[(&str, &str, &str)] = &[];

/// The `crate::name` paths of one line of code (its comment cut off), and its
/// `rotorshunt::name` paths: the command layer is compiled into the binary too, and
/// names the library by the crate's name there.
fn crate_paths(line: &str) -> Vec<String> {
    let code = line.split("//").next().unwrap_or("");
    let mut paths: Vec<(usize, String)> = Vec::new();
    for prefix in ["crate::", "rotorshunt::"] {
        paths.extend(code.match_indices(prefix).map(|(i, _)| {
            let name = code[i + prefix.len()..].chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_');
            (i, name.collect())
        }));
    }
    paths.sort();
    paths.into_iter().map(|(_, name)| name).collect()
}

#[test]
fn no_import_runs_back_up_the_chain() {
    let src = common::root().join("src");
    let files = common::rust_files(&src);
    let mut back = Vec::new();
    let mut checked = 0;
    for f in &files {
        let rel = f.strip_prefix(&src).unwrap();
        let top = rel.components().next().unwrap().as_os_str().to_string_lossy().trim_end_matches(".rs").to_string();
        let Some(own) = rank(&top) else { continue };
        let file = format!("src/{}", rel.display());
        for (n, line) in std::fs::read_to_string(f).unwrap().lines().enumerate() {
            // Grouped paths would hide their modules from the scan: the code names each.
            let code = line.split("//").next().unwrap_or("");
            assert!(
                !code.contains("crate::{") && !code.contains("rotorshunt::{"),
                "src/{}:{}: a grouped path",
                rel.display(),
                n + 1
            );
            for target in crate_paths(line) {
                checked += 1;
                let excepted = EXCEPTIONS.iter().any(|(f, m, _)| *f == file && *m == target);
                if rank(&target).is_some_and(|r| r > own) && !excepted {
                    back.push(format!("src/{}:{}: {top} uses crate::{target}", rel.display(), n + 1));
                }
            }
        }
    }
    eprintln!("{} files, {checked} crate:: paths checked", files.len());
    assert!(checked > 100, "the scan found only {checked} paths");
    assert!(back.is_empty(), "imports that run back up the chain:\n{}", back.join("\n"));
}

#[test]
fn the_scan_sees_a_path_back_up() {
    // The check itself: a design module naming the report layer is caught, and so is
    // an analysis module naming the file layer.
    assert_eq!(crate_paths("use crate::report::design::x; // crate::commands"), vec!["report".to_string()]);
    assert_eq!(crate_paths("use rotorshunt::report::x; crate::design::y"), vec!["report", "design"]);
    assert!(rank("report") > rank("design"));
    assert!(rank("problem") > rank("analysis"));
    assert!(rank("model") < rank("problem") && rank("problem") < rank("report"));
    for (file, module, why) in EXCEPTIONS {
        assert!(common::root().join(file).is_file() && rank(module).is_some() && !why.is_empty());
    }
}

#[test]
fn the_command_layer_is_not_part_of_the_library() {
    // The binary and the Python bindings compile src/commands/; the library declares it
    // only for the bindings, privately (docs/development.md).
    let lib = std::fs::read_to_string(common::root().join("src/lib.rs")).unwrap();
    let declared: Vec<(usize, &str)> =
        lib.lines().enumerate().filter(|(_, l)| l.trim_start().ends_with("mod commands;")).collect();
    assert_eq!(declared.len(), 1, "{declared:?}");
    let (at, line) = declared[0];
    assert_eq!(line.trim(), "mod commands;", "declared public: {line}");
    let lines: Vec<&str> = lib.lines().collect();
    let attributes: Vec<&str> = lines[..at].iter().rev().take_while(|l| l.starts_with("#[")).copied().collect();
    assert!(attributes.contains(&"#[cfg(feature = \"python\")]"), "{attributes:?}");
    // Nor are its items re-exported.
    let exported: Vec<&str> =
        lines.iter().filter(|l| l.contains("pub use") && l.contains("commands")).copied().collect();
    assert!(exported.is_empty(), "{exported:?}");
    let main = std::fs::read_to_string(common::root().join("src/main.rs")).unwrap();
    assert!(main.lines().any(|l| l == "mod commands;"), "the binary compiles the layer");
}
