//! The integration tests as one test binary: one compile and one link instead of one per
//! file (about a minute of a clean build on two cores), and the harness runs tests of
//! different files side by side. Each file under tests/ is a module here; run one file's
//! tests with `cargo test --release --test suite band_truth::`.
//!
//! Four files stay binaries of their own because they need a process to themselves:
//! parse_memory.rs counts the heap with its own global allocator, global_state.rs changes
//! faer's process-wide parallelism, and routes.rs and adversarial.rs bound the peak memory
//! of the children they start, which Linux reports as at least the parent's own peak at
//! the spawn (`ru_maxrss` carries the pre-exec high-water mark over `exec`): a child of
//! this binary, which holds other tests' data, would seem to use hundreds of MB
//! (Cargo.toml lists the five targets).

mod common;

mod anisotropic;
mod anisotropic_design;
mod bad_input;
mod band_names;
mod band_truth;
mod bounded_inputs;
mod campbell;
mod cancel;
mod candidates;
mod clear_bands_tolerances;
mod cli_floquet;
mod closed_form_onsets;
mod consistency;
mod convergence;
mod cost_counts;
mod criterion;
mod design;
mod early_refusal;
mod engineer_sees;
mod error_catalogue;
mod exit_codes;
mod extremes;
mod fast_modes;
mod file_layer;
mod floquet_paths;
mod fuzz;
mod general_model;
mod general_problems;
mod global_map;
mod held_out_band;
mod hostile_folder;
mod hostile_study;
mod injection;
mod interrupted;
mod invariants;
mod kill_points;
mod layers;
mod loading;
mod margins;
mod missed_f2b2_k3;
mod numerics;
mod observer;
mod out_folder;
mod overrides;
mod paper_findings;
mod paper_tables;
mod pareto;
mod peak_tolerances;
mod plausibility;
mod plots;
mod progress;
mod readme_library;
mod real_path_continuity;
mod region_settings;
mod regions;
mod report_html;
mod reproducibility;
mod response;
mod robust_design;
mod ross_aniso;
mod ross_examples;
mod ross_import;
mod ross_reference;
mod round_trip;
mod run_layer;
mod run_up;
mod sensitivity;
mod singular_mass;
mod slurm;
mod speed_range;
mod study;
mod study_safety;
mod study_shards;
mod time_limit;
mod timoshenko;
mod true_bands;
mod unbalance;
mod verification_parts;
mod vibration_design;
