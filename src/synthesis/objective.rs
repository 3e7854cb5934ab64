//! What an optimiser minimises: one number per design, standing designs below failing ones.
//!
//! - a design that fails scores its minimum tension + minimum friction excess, as fractions of
//!   its free weight (> 0; 0 would be standing);
//! - a design that stands scores −λ, λ the smallest horizontal load factor over a few evenly
//!   spaced azimuths (capped: an unlimited one counts as [`LAMBDA_CAP`]), or 0 when robustness
//!   is not asked for;
//! - a design that cannot be cut as asked (a cut that no longer splits anything, a piece below
//!   the minimum volume, a cut the replay refuses), that falls apart, or that the solver cannot
//!   decide scores a penalty above every failing design.
//!
//! Evaluations go through one [`Pipeline`], so each re-cuts only the pieces downstream of a
//! moved cut and re-solves only the components whose blocks or interfaces changed.

use crate::history::made_by;
use crate::model::Scene;
use crate::pipeline::{Analysis, AnalysisSettings, Pipeline};
use crate::stability::{DirectionSettings, worst_direction};
use crate::statics::Verdict;
use serde::Serialize;
use std::sync::Mutex;

/// λ above this counts as this much (an unlimited load factor is no better than a huge one).
pub const LAMBDA_CAP: f64 = 100.0;
/// The score of a design that falls apart (a piece touching nothing).
pub const UNSUPPORTED: f64 = 1e3;
/// The score of a design that cannot be cut as asked, or that the solver cannot decide.
pub const INVALID: f64 = 1e6;

/// One design's score and what it is made of.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Score {
    /// The design's verdict (`None` when it cannot be cut as asked).
    pub verdict: Option<Verdict>,
    /// Minimum tension and friction excess, fractions of the free weight.
    pub tension_ratio: f64,
    /// Minimum friction excess, a fraction of the free weight.
    pub friction_excess_ratio: f64,
    /// The smallest horizontal load factor over the azimuths (when it stands and it was asked).
    pub load_factor: Option<f64>,
    /// The number of free pieces.
    pub pieces: usize,
    /// Why the design cannot be cut as asked.
    pub invalid: Option<String>,
    /// The number the optimiser minimises (see the module docs).
    pub cost: f64,
}

impl Score {
    /// Whether the design stands.
    pub fn stands(&self) -> bool {
        self.verdict == Some(Verdict::Stands)
    }

    fn invalid(why: String) -> Self {
        Self {
            verdict: None,
            tension_ratio: f64::NAN,
            friction_excess_ratio: f64::NAN,
            load_factor: None,
            pieces: 0,
            invalid: Some(why),
            cost: INVALID,
        }
    }
}

/// Scores designs (one pipeline kept between evaluations).
pub struct Evaluator {
    pipeline: Mutex<Pipeline>,
    settings: AnalysisSettings,
    /// Azimuths of the robustness term; `None`: no robustness term.
    directions: Option<usize>,
    /// Cuts (indices in the history) that must still split a piece.
    must_cut: Vec<usize>,
    /// Smallest volume of a free piece, m³.
    min_volume: f64,
}

impl Evaluator {
    /// Scores with `settings` less the force distribution of a failing design (the QP after
    /// its minimum-tension and friction-excess LPs): the score needs only their optimum, and
    /// the QP is half of a failing design's solve.
    pub fn new(settings: &AnalysisSettings, directions: Option<usize>, must_cut: Vec<usize>, min_volume: f64) -> Self {
        let mut settings = settings.clone();
        settings.statics.distribution = false;
        Self { pipeline: Mutex::new(Pipeline::new()), settings, directions, must_cut, min_volume }
    }

    /// The score of `scene` and its analysis (when it could be analysed).
    pub fn score(&self, scene: &Scene) -> (Score, Option<Analysis>) {
        let run = self.pipeline.lock().expect("not poisoned").run(scene, &self.settings);
        match run {
            Ok(analysis) => (self.judge(&analysis), Some(analysis)),
            Err(e) => (Score::invalid(e.to_string()), None),
        }
    }

    /// The score of a design already analysed (with this evaluator's settings).
    pub fn judge(&self, analysis: &Analysis) -> Score {
        if let Some(why) = self.cannot_cut(analysis) {
            return Score::invalid(why);
        }
        let s = &analysis.statics;
        let pieces = analysis.assembly.blocks.iter().filter(|b| !b.support).count();
        let load_factor = (s.stands && self.directions.is_some()).then(|| self.load_factor(analysis));
        let cost = match s.verdict {
            Verdict::Stands => -load_factor.unwrap_or(0.0).min(LAMBDA_CAP),
            Verdict::NeedsTension | Verdict::NeedsFriction | Verdict::NeedsTensionAndFriction => {
                (s.tension_ratio + s.friction_excess_ratio).max(f64::MIN_POSITIVE)
            }
            // How far beyond its strength the stone is asked: a gradient towards standing.
            Verdict::Crushes => s.crushing.as_ref().map_or(INVALID, |c| (c.utilization - 1.0).max(f64::MIN_POSITIVE)),
            Verdict::Unsupported => UNSUPPORTED,
            Verdict::Unresolved => INVALID,
        };
        Score {
            verdict: Some(s.verdict),
            tension_ratio: s.tension_ratio,
            friction_excess_ratio: s.friction_excess_ratio,
            load_factor,
            pieces,
            invalid: None,
            cost,
        }
    }

    /// Why `analysis` is not the design the cuts were meant to make.
    fn cannot_cut(&self, analysis: &Analysis) -> Option<String> {
        let names: Vec<&str> = analysis.assembly.blocks.iter().map(|b| b.name.as_str()).collect();
        if let Some(i) = self.must_cut.iter().find(|&&i| !names.iter().any(|n| made_by(n, i))) {
            return Some(format!("cut {i} no longer splits any piece"));
        }
        let small = analysis.assembly.blocks.iter().find(|b| !b.support && b.mass.volume < self.min_volume)?;
        Some(format!(
            "piece '{}' ({:.3e} m³) is below the minimum volume {:.3e} m³",
            small.name, small.mass.volume, self.min_volume
        ))
    }

    /// The smallest λ over the azimuths (0 when a direction's solve fails: no credit for it).
    fn load_factor(&self, analysis: &Analysis) -> f64 {
        let sweep = DirectionSettings { directions: self.directions.unwrap_or(8), refine: 0 };
        // Only λ counts here: no mechanism is shown, so none is recovered.
        let statics = crate::statics::StaticsSettings { one_mechanism: false, ..self.settings.statics.clone() };
        worst_direction(&analysis.assembly, &analysis.interfaces, &statics, &sweep, &|_, _| {})
            .map(|s| s.worst_load_factor)
            .unwrap_or(0.0)
    }
}
