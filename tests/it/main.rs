//! The integration tests, one module per invariant, in one binary (one link of the whole
//! stack instead of one per file). The viewer's rendering test is its own binary
//! (tests/viewer_render.rs: winit wants the main thread).

mod common;

/// The fuzz targets' bodies (fuzz/bodies.rs), replayed over the kept corpora.
#[path = "../../fuzz/bodies.rs"]
mod fuzz_bodies;

/// The seed paper's case studies as built designs (examples/make_case_studies writes them).
#[path = "../../examples/make_case_studies/cases.rs"]
mod cases;

mod bad_input;
mod case_studies;
mod cli;
mod compas_formats;
mod crushing;
mod cut_history;
mod diagram_png;
#[cfg(unix)]
mod doc_examples;
mod drop_real_vault;
mod drop_test;
#[cfg(feature = "ecs")]
mod ecs_app;
mod exact_dynamics;
mod fuzz_corpora;
mod gltf_export;
mod incremental;
mod infill;
mod interfaces_synthetic;
mod kinematic_check;
mod layers;
mod load_factor;
mod mass_properties;
mod mechanism_vertex;
mod motion;
mod no_panic_inputs;
mod pattern_cut;
mod pattern_generate;
mod plane_cut;
mod readers;
mod real_data_interfaces;
mod report_html;
mod sequence;
mod settlement;
mod shake;
mod shake_cli;
mod statics_backends;
mod statics_closed_forms;
mod statics_feasible_minima;
mod statics_invariance;
mod statics_limits;
mod statics_properties;
mod statics_real_data;
mod statics_warm_start;
mod stress_numerics;
mod synthesis_generate;
mod synthesis_repair;
mod thin_blocks_regression;
mod thresholds;
mod tolerance;
