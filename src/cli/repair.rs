//! `voussoir repair DESIGN -o OUT.json`: moves and turns the design's cuts (all, or `--cuts`)
//! until it stands and then stands most safely ([`synthesis::repair`](mod@crate::synthesis::repair)); prints before and
//! after, writes the repaired design (atomically, never over the input) and on request a JSON
//! report. When no placement helps, it says so and names the failing interfaces and a support
//! that holds the design. Exit codes: 0 the result stands, 1 it does not, 2 bad input.

use super::options::SolverOptions;
use super::{BadInput, load, refuse_overwrite, scene_name, write_output};
use crate::io::scene_json;
use crate::model::CutShape;
use crate::synthesis::{self, RepairOutcome, RepairReport, RepairSettings, Score};
use clap::Args;
use std::path::PathBuf;

/// The options of `voussoir repair`.
#[derive(Args, Debug, Clone, PartialEq)]
pub struct RepairArgs {
    /// The design: a scene file with a cut history, or `builtin:…`.
    pub scene: String,
    /// The solver options every evaluation uses.
    #[command(flatten)]
    pub solver: SolverOptions,
    /// The cuts that may move, by index in the history (e.g. `0,2`); default: all.
    #[arg(long, value_delimiter = ',')]
    pub cuts: Option<Vec<usize>>,
    /// Largest turn of a plane cut about each in-plane axis, degrees (0: offsets only).
    #[arg(long, default_value_t = RepairSettings::default().max_turn_degrees)]
    pub max_turn: f64,
    /// Any standing design will do: no load-factor term.
    #[arg(long)]
    pub stand_only: bool,
    /// Seed of the particle swarm (the same seed gives the same design).
    #[arg(long, default_value_t = RepairSettings::default().seed)]
    pub seed: u64,
    /// Particles and iterations of the swarm.
    #[arg(long, default_value_t = RepairSettings::default().particles)]
    pub particles: usize,
    /// Iterations of the particle swarm.
    #[arg(long, default_value_t = RepairSettings::default().iterations)]
    pub iterations: u64,
    /// The repaired design (scene JSON with its cut history, written atomically).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Write the JSON report here (atomically).
    #[arg(long)]
    pub json: Option<PathBuf>,
}

/// Runs `repair`: writes the best design; exit code 0 when it stands, 1 when not.
pub fn run(args: &RepairArgs) -> Result<i32, BadInput> {
    for out in std::iter::once(&args.output).chain(&args.json) {
        refuse_overwrite(Some(&args.scene), out, "output")?;
    }
    let name = scene_name(Some(&args.scene)).to_string();
    let scene = load(Some(&args.scene))?;
    let settings = RepairSettings {
        cuts: args.cuts.clone(),
        max_turn_degrees: args.max_turn,
        robust: !args.stand_only,
        seed: args.seed,
        particles: args.particles,
        iterations: args.iterations,
        ..Default::default()
    };
    let report = with_bar(|progress| synthesis::repair(&scene, &args.solver.settings(), &settings, progress))
        .map_err(|e| BadInput(format!("{name}: {e}")))?;
    print!("{}", text(&report));
    write_output(&args.output, scene_json::scene_to_string(&report.design).as_bytes())?;
    println!("design written to {}", args.output.display());
    if let Some(out) = &args.json {
        let json = serde_json::to_string_pretty(&report).expect("a report serialises");
        write_output(out, json.as_bytes())?;
        println!("report written to {}", out.display());
    }
    Ok(if report.after.stands() { 0 } else { 1 })
}

/// Runs the repair with a bar on stderr ([`super::LateBar`]) showing the best score so far.
fn with_bar<T>(f: impl FnOnce(&(dyn Fn(usize, usize, f64) + Sync)) -> T) -> T {
    let bar = super::LateBar::new(Some("{bar:30} {pos}/{len} evaluations, best {msg}"));
    f(&|done, total, best| bar.update(done, total, Some(format!("{best:.4}"))))
}

/// Failing interfaces listed in the text (all of them in the JSON report).
const SHOWN: usize = 6;

/// The before/after table, the moved cuts and the honest answer.
pub fn text(r: &RepairReport) -> String {
    let mut s = String::new();
    let headline = match &r.outcome {
        RepairOutcome::Repaired => "REPAIRED: it stands now".to_string(),
        RepairOutcome::AlreadyStood { improved: true } => "STOOD ALREADY: the load factor is larger now".into(),
        RepairOutcome::AlreadyStood { improved: false } => {
            "STOOD ALREADY: no placement found that stands more safely".into()
        }
        RepairOutcome::NotRepaired => "NOT REPAIRED: no placement of the cuts found makes it stand".into(),
        RepairOutcome::NothingToMove => {
            "NOTHING TO MOVE: the design has no cut (a cut only adds joints: none can help)".into()
        }
    };
    s += &format!("{headline}\n");
    s += &format!("  {:<22} {:>26} {:>26}\n", "", "before", "after");
    s += &format!("  {:<22} {:>26} {:>26}\n", "verdict", verdict(&r.before), verdict(&r.after));
    s += &format!(
        "  {:<22} {:>26.3e} {:>26.3e}\n",
        "minimum tension / W", r.before.tension_ratio, r.after.tension_ratio
    );
    s += &format!(
        "  {:<22} {:>26.3e} {:>26.3e}\n",
        "friction excess / W", r.before.friction_excess_ratio, r.after.friction_excess_ratio
    );
    s += &format!(
        "  {:<22} {:>26} {:>26}\n",
        "λ* (worst direction)",
        lambda(r.load_factor_before),
        lambda(r.load_factor_after)
    );
    s += &format!("  {:<22} {:>26} {:>26}\n", "pieces", r.before.pieces, r.after.pieces);
    for c in &r.changed {
        s += &format!("  cut {}: {} → {}\n", c.index, shape(&c.before.shape), shape(&c.after.shape));
    }
    s += &format!("  {} evaluations in {:.2} s\n", r.evaluations, r.seconds);
    if !r.failing.is_empty() {
        s += "  still failing (worst first):\n";
        for f in r.failing.iter().take(SHOWN) {
            let (t, e) = (f.tension.max(0.0), f.friction_excess.max(0.0));
            s += &format!("    {} – {}: tension {t:.3e} W, friction excess {e:.3e} W\n", f.a, f.b);
        }
        if r.failing.len() > SHOWN {
            s += &format!("    and {} more (all in --json)\n", r.failing.len() - SHOWN);
        }
    }
    match (&r.support, r.after.stands()) {
        (Some(p), _) => {
            s += &format!(
                "  a support makes it stand: a {:.3} m square column, {:.3} m high, under '{}' at ({:.3}, {:.3}, {:.3})\n",
                p.side, p.height, p.under, p.top[0], p.top[1], p.top[2]
            )
        }
        (None, false) => s += "  no single column under a failing block makes it stand\n",
        (None, true) => {}
    }
    s
}

fn verdict(score: &Score) -> String {
    match (&score.verdict, &score.invalid) {
        (_, Some(_)) => "cannot cut".into(),
        (Some(v), None) => v.words().into(),
        (None, None) => "-".into(),
    }
}

fn lambda(l: Option<f64>) -> String {
    l.map(|l| format!("{l:.4}")).unwrap_or_else(|| "-".into())
}

fn shape(s: &CutShape) -> String {
    let v = |a: &[f64; 3]| format!("({:.4}, {:.4}, {:.4})", a[0], a[1], a[2]);
    match s {
        CutShape::Plane { point, normal } => {
            let n = nalgebra::Vector3::from(*normal).normalize();
            format!("plane through {} normal {}", v(point), v(&n.into()))
        }
        CutShape::Pattern { apex, .. } => format!("pattern apex {}", v(apex)),
    }
}
