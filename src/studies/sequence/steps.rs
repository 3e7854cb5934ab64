//! One step's analysis: the blocks placed so far (and the props, as supports) through a
//! [`Pipeline`] that keeps its work between steps, so a step costs about the component the new
//! block joins. A sequence check runs the steps on two threads (each prefix is independent).

use super::{SequenceError, Step, StepChecks};
use crate::dynamics::drop_test;
use crate::model::{Load, Scene};
use crate::pipeline::{Analysis, AnalysisSettings, Pipeline};
use crate::statics::{FirstStage, InterfaceResult};
use std::collections::HashSet;

/// `settings` for the prefixes of `resolved`: every prefix takes its tolerances (and the
/// statics its length unit) from the complete design's size, not from its own bounding box —
/// the same absolute tolerances at every step, so the prefix has the design's interfaces and
/// the pipeline finds the pairs and components of earlier steps in its memory.
pub(crate) fn prefix_settings(resolved: &Scene, settings: &AnalysisSettings) -> AnalysisSettings {
    let mut settings = settings.clone();
    let t = &mut settings.tolerances;
    t.reference_length = Some(t.scale(resolved.scale()));
    settings
}

/// Analyses prefixes of one resolved design.
pub(crate) struct Stepper<'a> {
    resolved: &'a Scene,
    /// The resolved design without blocks: every other field of a prefix comes from it.
    empty: Scene,
    settings: AnalysisSettings,
    pipeline: Pipeline,
    /// Static checks run so far.
    pub checks: usize,
    /// Whether the last check failed: steps that fail come in runs (a partial vault fails
    /// until it closes), so the next check then starts with the exact LPs instead of the
    /// strict QP (`FirstStage::Relaxed`: the same answer, one solve fewer when it fails).
    last_failed: bool,
}

impl<'a> Stepper<'a> {
    /// Only the graded numbers are reported per step, so the distribution QP is skipped (the
    /// minimum tension and friction excess are exact either way).
    pub fn new(resolved: &'a Scene, settings: &AnalysisSettings) -> Self {
        let mut settings = prefix_settings(resolved, settings);
        settings.statics.distribution = false;
        let empty = Scene { blocks: Vec::new(), ..resolved.clone() };
        Self { resolved, empty, settings, pipeline: Pipeline::new(), checks: 0, last_failed: false }
    }

    /// A stepper of the same design and settings with its own pipeline, whose statics keeps
    /// `keep` component outcomes of earlier runs ([`Pipeline::keeping_components`]).
    pub fn twin(&self, keep: usize) -> Stepper<'a> {
        let (settings, empty) = (self.settings.clone(), self.empty.clone());
        let pipeline = Pipeline::keeping_components(keep);
        Stepper { resolved: self.resolved, empty, settings, pipeline, checks: 0, last_failed: false }
    }

    /// Whether the last analysis found its prefix failing.
    pub fn last_failed(&self) -> bool {
        self.last_failed
    }

    /// The settings every prefix is analysed with.
    pub fn settings(&self) -> &AnalysisSettings {
        &self.settings
    }

    /// The design with only the `placed` free blocks, the `props` among them fixed.
    pub(crate) fn prefix(&self, placed: &HashSet<&str>, props: &HashSet<&str>) -> Scene {
        let mut scene = self.empty.clone();
        scene.blocks = self
            .resolved
            .blocks
            .iter()
            .filter(|b| b.support || placed.contains(b.name.as_str()))
            .map(|b| {
                let mut b = b.clone();
                b.support |= props.contains(b.name.as_str());
                b
            })
            .collect();
        // A point load acts once its block is placed (by name, or a piece of the source shape it names).
        let placed_block = |name: &str| {
            let prefix = format!("{name}.");
            scene.blocks.iter().any(|b| b.name == name || b.name.starts_with(&prefix))
        };
        let loads = std::mem::take(&mut scene.loads);
        let loads = loads
            .into_iter()
            .filter(|l| match l {
                Load::Point { block, .. } => placed_block(block),
                Load::Acceleration { .. } => true,
            })
            .collect();
        scene.loads = loads;
        scene
    }

    /// The prefix's analysis, starting with the strict QP unless the last check failed.
    pub fn analyse(&mut self, placed: &HashSet<&str>, props: &HashSet<&str>) -> Result<Analysis, SequenceError> {
        let first = if self.last_failed { FirstStage::Relaxed } else { FirstStage::Strict };
        self.analyse_from(placed, props, first)
    }

    /// The prefix's analysis starting with `first`: the caller knows which answer to expect.
    pub fn analyse_from(
        &mut self,
        placed: &HashSet<&str>,
        props: &HashSet<&str>,
        first: FirstStage,
    ) -> Result<Analysis, SequenceError> {
        self.checks += 1;
        let prefix = self.prefix(placed, props);
        self.settings.statics.first_stage = first;
        let a = self.pipeline.run(&prefix, &self.settings)?;
        self.last_failed = !a.statics.stands;
        Ok(a)
    }

    /// The step that placed `name`, with the drop test and the kinematic check when asked.
    pub fn step(
        &mut self,
        name: &str,
        placed: &HashSet<&str>,
        props: &HashSet<&str>,
        per_step: &StepChecks,
    ) -> Result<Step, SequenceError> {
        let a = self.analyse(placed, props)?;
        self.step_from(name, &a, props, per_step)
    }

    /// The step that placed `name`, from the analysis `a` of its prefix with `props`.
    pub fn step_from(
        &self,
        name: &str,
        a: &Analysis,
        props: &HashSet<&str>,
        per_step: &StepChecks,
    ) -> Result<Step, SequenceError> {
        let s = &a.statics;
        let offending = offending(a).map(|r| format!("{} | {}", r.a, r.b)).collect();
        let dynamic = match &per_step.dynamic {
            Some(ds) => Some(drop_test(&a.assembly, ds).map_err(|e| SequenceError::Drop(e.to_string()))?),
            None => None,
        };
        let kinematic = match &per_step.kinematic {
            Some(ks) => Some(
                crate::stability::kinematic::check(a, &self.settings.statics, ks)
                    .map_err(|e| SequenceError::Kinematic(e.to_string()))?,
            ),
            None => None,
        };
        let props = sorted(props);
        Ok(Step {
            placed: name.to_string(),
            stands: s.stands,
            verdict: s.verdict,
            tension_ratio: s.tension_ratio,
            friction_excess_ratio: s.friction_excess_ratio,
            offending,
            props,
            dynamic,
            kinematic,
        })
    }
}

/// Every prefix of `order` (no props), on two threads: thread t takes the steps k ≡ t (mod 2)
/// with its own pipeline (steps k and k + 2 share most components). Each step depends only on
/// its prefix, so the result does not depend on the split.
pub(crate) fn check_order(
    resolved: &Scene,
    order: &[String],
    settings: &AnalysisSettings,
    per_step: &StepChecks,
    tick: &(dyn Fn() + Sync),
) -> Result<Vec<Step>, SequenceError> {
    let mut settings = settings.clone();
    // The two step threads already use both cores.
    settings.statics.parallel = false;
    let lane = |t: usize| -> Result<Vec<(usize, Step)>, SequenceError> {
        let mut stepper = Stepper::new(resolved, &settings);
        let none = HashSet::new();
        let mut placed: HashSet<&str> = HashSet::new();
        let mut out = Vec::new();
        for (k, name) in order.iter().enumerate() {
            placed.insert(name);
            if k % 2 == t {
                out.push((k, stepper.step(name, &placed, &none, per_step)?));
                tick();
            }
        }
        Ok(out)
    };
    let (a, b) = if order.len() < 8 {
        (lane(0), lane(1))
    } else {
        std::thread::scope(|s| {
            let other = s.spawn(|| lane(1));
            let mine = lane(0);
            // A panic in the other lane: run its steps here instead.
            (mine, other.join().unwrap_or_else(|_| lane(1)))
        })
    };
    let (a, b) = (a?, b?);
    let mut steps: Vec<(usize, Step)> = a.into_iter().chain(b).collect();
    steps.sort_by_key(|s| s.0);
    Ok(steps.into_iter().map(|s| s.1).collect())
}

/// The props' names in order, as a step reports them.
pub(crate) fn sorted(props: &HashSet<&str>) -> Vec<String> {
    let mut props: Vec<String> = props.iter().map(|p| p.to_string()).collect();
    props.sort();
    props
}

/// The interfaces of an analysis that need tension or friction beyond μ (above 1e-6 of W).
pub(crate) fn offending(a: &Analysis) -> impl Iterator<Item = &InterfaceResult> {
    let s = &a.statics;
    s.interfaces.iter().filter(|r| r.tension > 1e-6 * s.free_weight || r.friction_excess > 1e-6 * s.free_weight)
}
