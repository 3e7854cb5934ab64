//! The options several commands share, as structs flattened into each command's arguments,
//! and the one place where each becomes the library's settings. Defaults are read from the
//! library's `Default`s, so `--help` prints the value the library uses.

use super::BadInput;
use super::choice::Choice;
use crate::dynamics::{ColliderForm, Coulomb, DropSettings, Engine, ExactSettings};
use crate::geometry::{Point3, Tolerances, Vector3};
use crate::model::{Load, LoadKind, Scene, SupportChoice};
use crate::pipeline::AnalysisSettings;
use crate::statics::{Backend, FrictionModel, StaticsSettings};
use crate::viz::DiagramMode;
use clap::{Args, ValueEnum};
use std::path::PathBuf;

/// How the statics run (`analyze`, `drop`, `sequence`, `export`, `view`).
#[derive(Args, Debug, Clone, PartialEq)]
pub struct SolverOptions {
    /// Friction model.
    #[arg(
        long,
        value_enum,
        value_parser = Choice::<FrictionModel>::new(),
        default_value_t = StaticsSettings::default().friction_model
    )]
    pub friction_model: FrictionModel,
    /// Interior-point solver of the statics and of the exact engine's steps: structured (the
    /// Newton system reduced to the equilibrium rows) or clarabel (its general LDL), to
    /// cross-check.
    #[arg(long, value_enum, value_parser = Choice::<Backend>::new(), default_value_t = StaticsSettings::default().backend)]
    pub solver: Backend,
    /// Friction coefficient μ (default: the scene's).
    #[arg(long)]
    pub mu: Option<f64>,
    /// Compressive strength of the stone, Pa (default: the scene's `strength`, or none: it
    /// does not crush). A design that stands by compression and friction then also needs
    /// every joint's resultant carried by a rectangular stress block within this strength.
    #[arg(long, value_name = "PA")]
    pub strength: Option<f64>,
    /// Coplanarity tolerance relative to the model size.
    #[arg(long, default_value_t = Tolerances::default().coplanar)]
    pub coplanar: f64,
    /// Angle tolerance between opposite faces, degrees.
    #[arg(long, default_value_t = Tolerances::default().angle_deg)]
    pub angle: f64,
    /// Interpenetrating blocks are an error (otherwise a warning, listed first).
    #[arg(long)]
    pub strict: bool,
}

impl SolverOptions {
    /// The analysis settings: the library's defaults with these options applied. The values
    /// are checked where the library validates its settings (an error names the setting).
    pub fn settings(&self) -> AnalysisSettings {
        let mut settings = AnalysisSettings::default();
        settings.statics.friction_model = self.friction_model;
        settings.statics.backend = self.solver;
        settings.statics.friction = self.mu;
        settings.statics.strength = self.strength;
        settings.tolerances.coplanar = self.coplanar;
        settings.tolerances.angle_deg = self.angle;
        settings.strict = self.strict;
        settings
    }
}

/// How the drop test runs (`analyze --dynamic`, `drop`, `sequence --dynamic`, `sweep`).
#[derive(Args, Debug, Clone, PartialEq)]
pub struct DropOptions {
    /// Drop test: the engine — rapier (soft contacts, the default) or exact (hard contacts,
    /// one interior-point solve per step: converges to the rigid-block answer).
    #[arg(long, value_parser = Choice::<Engine>::new(), default_value_t = DropSettings::default().engine)]
    pub engine: Engine,
    /// Exact engine: Coulomb's law by a fixed point per step (exact) or Anitescu's convex
    /// relaxation (relaxed: one solve per step, sliding contacts separate).
    #[arg(long, value_parser = Choice::<Coulomb>::new(), default_value_t = ExactSettings::default().coulomb)]
    pub coulomb: Coulomb,
    /// Drop test: simulated seconds (per evaluation in a sweep).
    #[arg(long, default_value_t = DropSettings::default().duration)]
    pub duration: f64,
    /// Drop test: time step, s.
    #[arg(long, default_value_t = DropSettings::default().dt)]
    pub dt: f64,
    /// rapier's colliders for a curved or notched block: fitted (its hull where that reaches
    /// no other block) or exact (its convex parts wherever the hull is larger).
    #[arg(long, value_parser = Choice::<ColliderForm>::new(), default_value_t = DropSettings::default().colliders)]
    pub colliders: ColliderForm,
    /// Drop test: no floor under a design with supports and no ground (by default one block
    /// size below its lowest point, so what falls lands and rests in view).
    #[arg(long)]
    pub no_floor: bool,
    /// Exact engine: take an impact at the end of its step instead of splitting the step at its
    /// instant (first order in dt: each impact loses about half a step of motion; to compare).
    #[arg(long)]
    pub no_split_impacts: bool,
    /// Exact engine: a design at rest stays where an equilibrium within Coulomb's sets holds it
    /// (the settlement's rule), instead of the kinematic check's motion from rest where the
    /// rigid-Coulomb model admits both (a bar between two posts could slide down with no force).
    #[arg(long)]
    pub rest_when_admissible: bool,
    /// Exact engine: solve every moving step by the Tresca rounds of interior-point solves,
    /// instead of first by its contacts' last states (one linear solve where they still hold;
    /// the same answer, to cross-check).
    #[arg(long)]
    pub rounds_only: bool,
}

impl DropOptions {
    /// The drop-test settings: the library's defaults with these options, the friction
    /// coefficient `friction` (`--mu`, the same as the statics'; `None`: the scene's), and the
    /// statics' friction model and solver (the exact engine's contacts and steps take them).
    pub fn settings(&self, friction: Option<f64>, friction_model: FrictionModel, backend: Backend) -> DropSettings {
        let exact = ExactSettings {
            coulomb: self.coulomb,
            friction_model,
            backend,
            split_impacts: !self.no_split_impacts,
            rest_when_admissible: self.rest_when_admissible,
            by_states: !self.rounds_only,
            ..Default::default()
        };
        DropSettings {
            engine: self.engine,
            exact,
            duration: self.duration,
            dt: self.dt,
            friction,
            colliders: self.colliders,
            floor: !self.no_floor,
            ..Default::default()
        }
    }
}

/// A diagram by name (`--mode`): the library's [`DiagramMode`] without the friction threshold.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Diagram {
    /// blue compression, red tension, grey nothing
    Compression,
    /// grey, yellow up to --threshold of μ, orange up to μ, red beyond
    Friction,
    /// force arrows over the compression colours
    Vectors,
}

impl From<DiagramMode> for Diagram {
    fn from(mode: DiagramMode) -> Self {
        match mode {
            DiagramMode::Compression => Self::Compression,
            DiagramMode::Friction { .. } => Self::Friction,
            DiagramMode::Vectors => Self::Vectors,
        }
    }
}

impl std::fmt::Display for Diagram {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&super::choice::name(self))
    }
}

/// Which diagram colours the interfaces (`export`, `view`).
#[derive(Args, Debug, Clone, PartialEq)]
pub struct DiagramOptions {
    /// Diagram colouring the interfaces (in the viewer the one at start; keys 1/2/3 switch).
    #[arg(
        long,
        value_enum,
        value_parser = Choice::<Diagram>::new(),
        default_value_t = Diagram::from(DiagramMode::default())
    )]
    pub mode: Diagram,
    /// Friction mode: the "low friction" limit as a fraction of μ · compression.
    #[arg(long, default_value_t = DiagramMode::DEFAULT_THRESHOLD)]
    pub threshold: f64,
}

impl DiagramOptions {
    /// The diagram mode; the threshold must be a fraction when the friction diagram uses it.
    pub fn mode(&self) -> Result<DiagramMode, BadInput> {
        Ok(match self.mode {
            Diagram::Compression => DiagramMode::Compression,
            Diagram::Vectors => DiagramMode::Vectors,
            Diagram::Friction if (0.0..=1.0).contains(&self.threshold) => {
                DiagramMode::Friction { threshold: self.threshold }
            }
            Diagram::Friction => return Err(BadInput(format!("--threshold {} must be within [0, 1]", self.threshold))),
        })
    }
}

/// Loads from the command line, added to the scene's (`analyze`, `drop`, `robustness`).
#[derive(Args, Debug, Clone, PartialEq, Default)]
pub struct LoadOptions {
    /// A point load BLOCK:X,Y,Z:FX,FY,FZ — point (m) on the block, force (N) — live (scaled by
    /// the load factor) unless it ends in `:dead`. Repeatable.
    #[arg(long = "load", value_name = "BLOCK:X,Y,Z:FX,FY,FZ[:dead]")]
    pub loads: Vec<String>,
    /// An acceleration AX,AY,AZ in g on every free block's mass, live unless it ends in `:dead`
    /// (e.g. `0.2,0,0:dead` is a pseudo-static seismic load). Repeatable.
    #[arg(long, value_name = "AX,AY,AZ[:dead]")]
    pub accel: Vec<String>,
}

impl LoadOptions {
    /// The loads as the library's, each option checked for its form (the library checks the
    /// rest: the block, the point, finite numbers).
    pub fn loads(&self) -> Result<Vec<Load>, BadInput> {
        let kind = |text: &str| -> (String, LoadKind) {
            match text.strip_suffix(":dead") {
                Some(rest) => (rest.to_string(), LoadKind::Dead),
                None => (text.strip_suffix(":live").unwrap_or(text).to_string(), LoadKind::Live),
            }
        };
        let mut out = Vec::new();
        for text in &self.loads {
            let (body, kind) = kind(text);
            let form = "BLOCK:X,Y,Z:FX,FY,FZ[:dead]";
            let parts: Vec<&str> = body.rsplitn(3, ':').collect();
            let [force, point, block] = parts[..] else {
                return Err(BadInput(format!("--load '{text}': expected {form}")));
            };
            if block.is_empty() {
                return Err(BadInput(format!("--load '{text}': no block named (expected {form})")));
            }
            let p = super::numbers::<3>("--load", point, "X,Y,Z (the point, m)")?;
            let f = super::numbers::<3>("--load", force, "FX,FY,FZ (the force, N)")?;
            out.push(Load::Point {
                block: block.to_string(),
                point: Point3::new(p[0], p[1], p[2]),
                force: Vector3::new(f[0], f[1], f[2]),
                kind,
            });
        }
        for text in &self.accel {
            let (body, kind) = kind(text);
            let a = super::numbers::<3>("--accel", &body, "AX,AY,AZ (in g)")?;
            out.push(Load::Acceleration { accel: Vector3::new(a[0], a[1], a[2]), kind });
        }
        Ok(out)
    }
}

/// The scene as the command line amends it: densities, supports, the ground (`analyze`,
/// `drop`, `view`).
#[derive(Args, Debug, Clone, PartialEq, Default)]
pub struct SceneOptions {
    /// Density for every block, kg/m³ (default: the scene's).
    #[arg(long)]
    pub density: Option<f64>,
    /// Supports: `lowest` (blocks at the lowest level) or a comma-separated list of block
    /// names; replaces the supports given in the scene.
    #[arg(long)]
    pub supports: Option<String>,
    /// A JSON list of compas meshes added as supports (compas_dem's `supports.json` beside its
    /// `blocks.json`).
    #[arg(long)]
    pub supports_file: Option<PathBuf>,
    /// The ground plane z = 0 supports faces lying on it.
    #[arg(long)]
    pub ground: bool,
}

impl SceneOptions {
    /// Applies the options to `scene` (supports chosen with `settings`' coplanarity tolerance).
    pub fn apply(&self, scene: &mut Scene, settings: &AnalysisSettings) -> Result<(), BadInput> {
        if let Some(file) = &self.supports_file {
            let supports = crate::io::load_supports(file).map_err(|e| BadInput(e.to_string()))?;
            if let Some(clash) = supports.iter().find(|s| scene.find(&s.name).is_some()) {
                return Err(BadInput(format!("--supports-file: the scene already has a block named '{}'", clash.name)));
            }
            scene.blocks.extend(supports);
        }
        if let Some(d) = self.density {
            scene.set_density(d);
        }
        if self.ground {
            scene.ground = true;
        }
        let choice = match self.supports.as_deref() {
            None => return Ok(()),
            Some("lowest") => SupportChoice::Lowest,
            Some(list) => SupportChoice::Named(
                list.split(',').map(str::trim).filter(|s| !s.is_empty()).map(str::to_string).collect(),
            ),
        };
        scene.choose_supports(&choice, settings.tolerances.coplanar).map_err(|e| BadInput(format!("--supports: {e}")))
    }
}
