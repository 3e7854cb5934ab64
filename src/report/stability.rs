//! The JSON report of `voussoir robustness`: the analysis report ([`super::json`]) with one
//! more key, `robustness` (schema in the README, "How safe is it?"). Non-finite numbers (an
//! unlimited load factor) become `null`.

use crate::pipeline::Analysis;
use crate::stability::{DirectionSweep, Robustness};
use serde::Serialize;

#[derive(Serialize)]
struct RobustnessReport<'a> {
    /// What the live load was.
    load: &'a str,
    #[serde(flatten)]
    result: &'a Robustness,
    #[serde(skip_serializing_if = "Option::is_none")]
    directions: Option<&'a DirectionSweep>,
}

/// The analysis report with the `robustness` key.
pub fn to_json(analysis: &Analysis, result: &Robustness, sweep: Option<&DirectionSweep>, load: &str) -> String {
    let mut report: serde_json::Value =
        serde_json::from_str(&super::json::to_json(analysis)).expect("the analysis report is JSON");
    let extra = RobustnessReport { load, result, directions: sweep };
    let value = serde_json::to_value(&extra).unwrap_or_else(|e| serde_json::json!({ "error": e.to_string() }));
    if let Some(map) = report.as_object_mut() {
        map.insert("robustness".into(), value);
    }
    serde_json::to_string_pretty(&report).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
}
