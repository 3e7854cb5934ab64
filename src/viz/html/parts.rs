//! What each study adds to a report: its lines in the panel, its motion in the motion pane,
//! its plots — the same whether the command line or Python asks.

use super::{HtmlReport, MotionPane, Plot};
use crate::dynamics::{DropResult, DropSettings, Trajectory};
use crate::report::text as text_report;
use crate::stability::Answer;
use crate::studies::settlement::{Outcome, Settlement};
use crate::viz::gltf::PATH_SECONDS;
use crate::viz::plot::{PolarPlot, ThrustPlot, svg_string};

/// Seconds a mechanism plays in.
pub const MECHANISM_SECONDS: f64 = 3.0;

impl HtmlReport<'_> {
    /// A load factor and its collapse mechanism ([`crate::stability::answer`]): the robustness
    /// text, the mechanism played from the design at rest, and a direction sweep's polar plot.
    pub fn add_mechanism(&mut self, answer: &Answer) -> Result<(), String> {
        let a = self.analysis;
        self.text.push('\n');
        self.text.push_str(&text_report::robustness(a, &answer.result, answer.sweep.as_ref(), &answer.load));
        if let Some(sweep) = &answer.sweep {
            let plot = PolarPlot { title: a.assembly.name.clone(), sweep, size: (640, 640) };
            let svg = svg_string(&plot, plot.size).map_err(|e| format!("the polar plot: {e}"))?;
            self.plots
                .push(Plot { title: "λ* of a horizontal 1 g against its direction, the worst marked".into(), svg });
        }
        self.push_mechanism(answer);
        Ok(())
    }

    /// The mechanism's motion pane, when something moves.
    fn push_mechanism(&mut self, answer: &Answer) {
        let a = self.analysis;
        let Some(mechanism) = &answer.result.mechanism else { return };
        let Some(glb) = crate::viz::gltf::mechanism_glb(&a.assembly, mechanism, MECHANISM_SECONDS) else { return };
        let moved: Vec<usize> = mechanism.moving.iter().map(|b| b.0).collect();
        let caption = format!(
            "collapse mechanism under {}: λ* = {:.4}; {} moving block(s), drawn with the largest motion {:.0} % of the model size",
            answer.load,
            answer.result.load_factor,
            moved.len(),
            100.0 * crate::viz::EXAGGERATION
        );
        self.motions.push(MotionPane { title: "mechanism".into(), caption, glb, moved });
    }

    /// A drop test ([`crate::dynamics::record`]) run with `settings`: the side-by-side text,
    /// its motion, and the JSON report's `dynamic` key.
    pub fn add_drop(&mut self, d: &DropResult, motion: &Trajectory, settings: &DropSettings) {
        let a = self.analysis;
        self.text.push('\n');
        self.text.push_str(&text_report::side_by_side(a, d));
        let extras = crate::report::json::Extras { dynamic: Some(d), ..Default::default() };
        self.json = crate::report::json::to_json_with(a, &extras);
        let caption = format!(
            "drop test ({}): {} s at dt {:.4} ms — {}",
            motion.engine,
            settings.duration,
            1e3 * settings.dt,
            if d.stands { "it stands" } else { "it falls" }
        );
        let glb = crate::viz::gltf::animation_glb(&a.assembly, motion);
        self.motions.push(MotionPane { title: "drop test".into(), caption, glb, moved: moved_blocks(a, motion) });
    }

    /// A settlement ([`crate::studies::settlement::settle`]): its runs' lines, the quasi-static
    /// run's motion (the path in [`PATH_SECONDS`] s), the thrust plot.
    pub fn add_settlement(&mut self, result: &Settlement) -> Result<(), String> {
        let a = self.analysis;
        let run = &result.quasi_static;
        self.text.push_str(&format!(
            "\nSETTLE: {} moved ({:.4e} m at the end of the path)\n",
            result.supports.join(", "),
            result.path_movement
        ));
        for r in [Some(run), result.exact.as_ref(), result.rapier.as_ref()].into_iter().flatten() {
            self.text.push_str(&format!("  {:<12} {}\n", r.method, outcome(&r.outcome)));
        }
        let caption =
            format!("settlement (quasi-static): {}; the whole path plays in {PATH_SECONDS} s", outcome(&run.outcome));
        let glb = crate::viz::gltf::path_glb(&a.assembly, &run.motion);
        self.motions.push(MotionPane { title: "settlement".into(), caption, glb, moved: moved_blocks(a, &run.motion) });
        let plot =
            ThrustPlot { title: format!("{}: reaction against support movement", a.assembly.name), settlement: result };
        let svg = svg_string(&plot, ThrustPlot::SIZE).map_err(|e| format!("the thrust plot: {e}"))?;
        self.plots.push(Plot {
            title: "The horizontal reaction on the first moved support against its movement".into(),
            svg,
        });
        Ok(())
    }
}

/// How a settlement run ended, in words.
fn outcome(o: &Outcome) -> String {
    match *o {
        Outcome::Stands => "stands to the end of the path".into(),
        Outcome::Collapses { fraction, movement, .. } => {
            format!("collapses at {:.2} % of the path ({movement:.4e} m)", 100.0 * fraction)
        }
        Outcome::Unresolved { fraction, status } => {
            format!("solver trouble at {:.2} % of the path ({status:?})", 100.0 * fraction)
        }
    }
}

/// The free blocks whose centroid moves in `motion` by more than a thousandth of the model size.
fn moved_blocks(a: &crate::pipeline::Analysis, motion: &Trajectory) -> Vec<usize> {
    let Some(first) = motion.poses.first() else { return Vec::new() };
    let still = 1e-3 * a.assembly.scale;
    let moves = |b: usize| motion.poses.iter().any(|f| (f[b].0 - first[b].0).norm() > still);
    (0..a.assembly.blocks.len()).filter(|&b| !a.assembly.blocks[b].support && moves(b)).collect()
}
