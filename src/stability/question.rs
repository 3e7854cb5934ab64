//! Which load factor a caller asks for, answered in one place (`voussoir robustness` and the
//! Python `load_factor` both go through [`answer`]).

use super::{DirectionSettings, DirectionSweep, Robustness, RobustnessError, assess, assess_parts, directions};
use crate::pipeline::Analysis;
use crate::statics::StaticsSettings;

/// What the load factor scales.
#[derive(Clone, Debug, PartialEq)]
pub enum Question {
    /// The scene's live loads.
    LiveLoads,
    /// A horizontal 1 g along this azimuth, degrees from +x towards +y.
    Direction(f64),
    /// A horizontal 1 g in the worst direction of a sweep.
    Worst(DirectionSettings),
}

impl Question {
    /// The default question: the live loads when the design has any, else the worst direction
    /// over `directions` azimuths (the sweep's default when `None`); `direction` asks for one.
    pub fn choose(analysis: &Analysis, direction: Option<f64>, directions: Option<usize>) -> Self {
        match (direction, directions) {
            (Some(d), _) => Question::Direction(d),
            (None, Some(n)) => Question::Worst(DirectionSettings { directions: n, ..Default::default() }),
            (None, None) if analysis.assembly.has_live_loads() => Question::LiveLoads,
            (None, None) => Question::Worst(DirectionSettings::default()),
        }
    }
}

/// A load factor, the sweep behind it (for [`Question::Worst`] on a design that stands) and a
/// phrase naming the load.
#[derive(Clone, Debug)]
pub struct Answer {
    /// The load factor and its mechanism.
    pub result: Robustness,
    /// λ* per direction, when the question was the worst horizontal direction.
    pub sweep: Option<DirectionSweep>,
    /// The load in words, as the text report names it (`1 g horizontal at 30°`, or the live loads named).
    pub load: String,
}

/// Answers `question` for an analysed design. A design that does not stand under its dead
/// load has no worst direction: its failure mechanism, and the load factor of its live loads
/// if it has any. `progress` is called with (done, total) during a sweep.
pub fn answer(
    analysis: &Analysis,
    settings: &StaticsSettings,
    question: &Question,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Answer, RobustnessError> {
    let stands = analysis.statics.stands;
    match question {
        Question::Worst(sweep_settings) if stands => {
            let s = directions::worst_direction(
                &analysis.assembly,
                &analysis.interfaces,
                settings,
                sweep_settings,
                progress,
            )?;
            let load = format!("1 g horizontal at {:.1}° (worst of {})", s.worst_azimuth, sweep_settings.directions);
            Ok(Answer { result: s.worst.clone(), sweep: Some(s), load })
        }
        Question::Direction(d) => {
            let field = directions::with_horizontal_field(&analysis.assembly, *d);
            let result = assess_parts(&field, &analysis.interfaces, stands, settings)?;
            Ok(Answer { result, sweep: None, load: format!("1 g horizontal at {d}°") })
        }
        Question::LiveLoads | Question::Worst(_) => {
            let result = assess(analysis, settings)?;
            let load = if analysis.assembly.has_live_loads() { "the live loads" } else { "no live load" };
            Ok(Answer { result, sweep: None, load: load.into() })
        }
    }
}
