//! The JSON report of an analysis (schema documented in the README, "Report JSON").

use crate::dynamics::DropResult;
use crate::pipeline::{Analysis, Timings};
use crate::stability::kinematic::Kinematic;
use crate::stability::tolerance::Margins;
use crate::statics::{CrushingReport, InterfaceResult, SolverReport, Verdict};
use serde::Serialize;

/// Report schema version.
pub const REPORT_VERSION: u32 = 1;

#[derive(Serialize)]
struct BlockReport<'a> {
    name: &'a str,
    support: bool,
    volume: f64,
    mass: f64,
    centroid: [f64; 3],
}

#[derive(Serialize)]
struct Report<'a> {
    schema: u32,
    scene: &'a str,
    stands: bool,
    verdict: Verdict,
    tension_ratio: f64,
    friction_excess_ratio: f64,
    max_friction_utilization: f64,
    free_weight: f64,
    friction_coefficient: f64,
    friction_model: String,
    components: usize,
    blocks: Vec<BlockReport<'a>>,
    supports: Vec<&'a str>,
    ground: bool,
    interfaces: &'a [InterfaceResult],
    /// With a compressive strength, on a design that stands by compression and friction.
    #[serde(skip_serializing_if = "Option::is_none")]
    crushing: Option<&'a CrushingReport>,
    solver: &'a SolverReport,
    timings: Timings,
    warnings: Vec<String>,
    /// With a drop test: the statics' verdict fields, the drop test's, and whether they agree.
    #[serde(rename = "static", skip_serializing_if = "Option::is_none")]
    static_verdict: Option<StaticVerdict>,
    #[serde(skip_serializing_if = "Option::is_none")]
    dynamic: Option<&'a DropResult>,
    #[serde(skip_serializing_if = "Option::is_none")]
    agree: Option<bool>,
    /// With the kinematic check: its verdict, whether it agrees with the statics, its
    /// mechanism (initial accelerations).
    #[serde(skip_serializing_if = "Option::is_none")]
    kinematic: Option<&'a Kinematic>,
    /// With `--tolerance`: the fabrication tolerance margins.
    #[serde(skip_serializing_if = "Option::is_none")]
    tolerance: Option<&'a Margins>,
}

/// What ran beside the statics, each reported when present.
#[derive(Clone, Copy, Default)]
pub struct Extras<'a> {
    /// The drop test's result (`drop`, `analyze --dynamic`): the report's `dynamic` and `agree` keys.
    pub dynamic: Option<&'a DropResult>,
    /// The kinematic check's result (`--kinematic`): the report's `kinematic` key.
    pub kinematic: Option<&'a Kinematic>,
    /// The fabrication tolerance margins (`--tolerance`): the report's `tolerance` key.
    pub tolerance: Option<&'a Margins>,
}

#[derive(Serialize)]
struct StaticVerdict {
    stands: bool,
    verdict: Verdict,
    tension_ratio: f64,
    friction_excess_ratio: f64,
    max_friction_utilization: f64,
}

/// The report as pretty JSON. Non-finite numbers (an infinite utilisation) become `null`.
pub fn to_json(analysis: &Analysis) -> String {
    to_json_with(analysis, &Extras::default())
}

/// The report with a drop test beside the statics (keys `static`, `dynamic`, `agree`), the
/// kinematic check (key `kinematic`) and the tolerance margins (key `tolerance`), each when it
/// ran.
pub fn to_json_with(analysis: &Analysis, extras: &Extras) -> String {
    let Extras { dynamic, kinematic, tolerance } = *extras;
    let a = &analysis.assembly;
    let s = &analysis.statics;
    let report = Report {
        schema: REPORT_VERSION,
        scene: &a.name,
        stands: s.stands,
        verdict: s.verdict,
        tension_ratio: s.tension_ratio,
        friction_excess_ratio: s.friction_excess_ratio,
        max_friction_utilization: s.max_friction_utilization,
        free_weight: s.free_weight,
        friction_coefficient: s.friction_coefficient,
        friction_model: s.friction_model.to_string(),
        components: s.components,
        blocks: a
            .blocks
            .iter()
            .map(|b| BlockReport {
                name: &b.name,
                support: b.support,
                volume: b.mass.volume,
                mass: b.mass(),
                centroid: [b.mass.centroid.x, b.mass.centroid.y, b.mass.centroid.z],
            })
            .collect(),
        supports: a.blocks.iter().filter(|b| b.support).map(|b| b.name.as_str()).collect(),
        ground: a.ground,
        interfaces: &s.interfaces,
        crushing: s.crushing.as_ref(),
        solver: &s.solver,
        timings: analysis.timings,
        warnings: a.warnings.iter().map(|w| w.to_string()).collect(),
        static_verdict: dynamic.map(|_| StaticVerdict {
            stands: s.stands,
            verdict: s.verdict,
            tension_ratio: s.tension_ratio,
            friction_excess_ratio: s.friction_excess_ratio,
            max_friction_utilization: s.max_friction_utilization,
        }),
        dynamic,
        agree: dynamic.map(|d| d.stands == s.stands),
        kinematic,
        tolerance,
    };
    serde_json::to_string_pretty(&report).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
}
