//! `voussoir sequence`: every step of an assembly order checked (statics, the drop test with
//! `--dynamic`, the kinematic check with `--kinematic`), or an order searched, with temporary
//! supports where none stands.

use super::options::{DropOptions, SolverOptions};
use super::{BadInput, load, refuse_overwrite, write_output};
use crate::stability::kinematic::KinematicVerdict;
use crate::studies::sequence::{OrderSpec, SearchSettings, StepChecks, check, check_with_props, search};
use clap::Args;
use std::path::PathBuf;

/// The options of `voussoir sequence`.
#[derive(Args, Debug, Clone, PartialEq)]
pub struct SequenceArgs {
    /// Scene file or `builtin:…`.
    pub scene: String,
    /// `bottom-up` (by height), `from-supports` (by graph distance from the supports) or
    /// block names in placing order, comma-separated (a source shape's name stands for all its
    /// pieces, bottom-up). Default: the scene file's `order`, else bottom-up.
    #[arg(long, conflicts_with = "search", value_parser = order_spec)]
    pub order: Option<OrderSpec>,
    /// Search an order in which every step stands; when none exists, propose temporary
    /// supports (exit code 1).
    #[arg(long)]
    pub search: bool,
    /// Propose temporary supports (props) for the order wherever a step would not stand.
    #[arg(long)]
    pub props: bool,
    // The default budget is the library's, printed from its constants.
    #[arg(long, help = format!(
        "Prefixes the search may check (default {} per block + {})",
        SearchSettings::CHECKS_PER_BLOCK,
        SearchSettings::BASE_CHECKS
    ))]
    /// `--search`: prefixes it may check before giving up (default per block, printed by `--help`).
    pub max_checks: Option<usize>,
    /// Also drop-test every step.
    #[arg(long)]
    pub dynamic: bool,
    /// Also check every step kinematically (released from rest, no squeeze: does the static
    /// equilibrium arise?).
    #[arg(long)]
    pub kinematic: bool,
    /// The solver options every step is analysed with.
    #[command(flatten)]
    pub solver: SolverOptions,
    /// The drop test's engine, duration and time step, with `--dynamic`.
    #[command(flatten)]
    pub drop: DropOptions,
    /// Write the report as JSON here (atomically).
    #[arg(long)]
    pub json: Option<PathBuf>,
}

/// `--order`: one of the two named orders, else a list of names.
fn order_spec(text: &str) -> Result<OrderSpec, std::convert::Infallible> {
    Ok(match text {
        "bottom-up" => OrderSpec::BottomUp,
        "from-supports" => OrderSpec::FromSupports,
        list => OrderSpec::Given(list.split(',').map(|s| s.trim().to_string()).filter(|s| !s.is_empty()).collect()),
    })
}

/// Runs `sequence`: prints each step; exit code 0 when every step stands without props.
pub fn run(args: &SequenceArgs) -> Result<i32, BadInput> {
    if let Some(out) = &args.json {
        refuse_overwrite(Some(&args.scene), out, "--json")?;
    }
    let scene = load(Some(&args.scene))?;
    let spec = match &args.order {
        Some(spec) => spec.clone(),
        None if !scene.order.is_empty() => OrderSpec::Given(scene.order.clone()),
        None => OrderSpec::BottomUp,
    };
    let settings = args.solver.settings();
    let per_step = StepChecks {
        dynamic: args
            .dynamic
            .then(|| args.drop.settings(args.solver.mu, args.solver.friction_model, args.solver.solver)),
        kinematic: args.kinematic.then(Default::default),
    };
    let search_settings = SearchSettings { max_checks: args.max_checks, ..Default::default() };
    // The number of steps is known only after the cut history is replayed: a counting spinner.
    let bar = indicatif::ProgressBar::new_spinner();
    bar.set_style(
        indicatif::ProgressStyle::with_template("{spinner} {pos} {msg} ({elapsed})")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_spinner()),
    );
    bar.set_message(if args.search { "static checks (searching an order)" } else { "steps checked" });
    let tick = || bar.inc(1);
    let report = if args.search {
        search(&scene, &settings, &search_settings, &per_step, &tick)
    } else if args.props {
        check_with_props(&scene, &spec, &settings, &search_settings, &per_step, &tick)
    } else {
        check(&scene, &spec, &settings, &per_step, &tick)
    };
    bar.finish_and_clear();
    let r = report.map_err(|e| BadInput(format!("{}: {e}", args.scene)))?;
    print_report(&r, args.dynamic, args.kinematic);
    if let Some(out) = &args.json {
        write_output(out, serde_json::to_string_pretty(&r).unwrap_or_default().as_bytes())?;
    }
    let dyn_ok = r.steps.iter().all(|s| s.dynamic.as_ref().is_none_or(|d| d.stands));
    let kin_ok = r.steps.iter().all(|s| s.kinematic.as_ref().is_none_or(|k| k.verdict == KinematicVerdict::Stands));
    Ok(if r.stands_unpropped() && dyn_ok && kin_ok { 0 } else { 1 })
}

/// The search's outcome, one line per step, the props and the first failure.
fn print_report(r: &crate::studies::sequence::SequenceReport, dynamic: bool, kinematic: bool) {
    if let Some(info) = &r.search {
        let what = match (info.found, info.exhaustive) {
            (true, _) => "found an order in which every step stands".to_string(),
            (false, true) => "no order stands at every step (the search was exhaustive)".to_string(),
            (false, false) => "no standing order found within the budget (--max-checks)".to_string(),
        };
        println!(
            "search: {what}; {} static checks and {} of neighbourhoods, longest standing prefix {}",
            info.checks, info.local_checks, info.deepest
        );
    }
    println!(
        "step  placed                 statics  tension      friction excess{}{}  props",
        if dynamic { "  drop test" } else { "" },
        if kinematic { "  kinematic" } else { "" }
    );
    for (i, s) in r.steps.iter().enumerate() {
        let d = s.dynamic.as_ref().map(|d| if d.stands { "  stands" } else { "  falls " }).unwrap_or("");
        let k = s.kinematic.as_ref().map_or("", |k| match (k.verdict, k.agrees) {
            (KinematicVerdict::Stands, _) => "  stands   ",
            (KinematicVerdict::Fails, true) => "  falls    ",
            // Falls where the statics stands: the equilibrium needs a squeeze nothing produces.
            (KinematicVerdict::Fails, false) => "  FALLS (!)",
            (KinematicVerdict::Undecided, _) => "  undecided",
        });
        let word = if s.stands { "stands" } else { "FAILS " };
        println!(
            "{i:>4}  {:<22} {word}   {:.3e} W  {:.3e} W{d}{k}  {}",
            s.placed,
            s.tension_ratio,
            s.friction_excess_ratio,
            s.props.join(", ")
        );
    }
    for p in &r.temporary_supports {
        println!("prop '{}' from step {} until step {}", p.block, p.from, p.until);
    }
    match r.first_failure {
        None if r.temporary_supports.is_empty() => println!("every step stands"),
        None => println!("every step stands with {} temporary support(s)", r.temporary_supports.len()),
        Some(k) => {
            let s = &r.steps[k];
            println!("first failure at step {k} ({}): {:?} {}", s.placed, s.verdict, s.offending.join(", "))
        }
    }
    let not_kinematic = |s: &crate::studies::sequence::Step| {
        s.kinematic.as_ref().is_some_and(|k| k.verdict != KinematicVerdict::Stands)
    };
    if let Some(k) = r.steps.iter().position(not_kinematic) {
        let s = &r.steps[k];
        let why = if s.stands { "the statics' equilibrium does not arise from rest" } else { "the statics fails too" };
        println!("first kinematic failure at step {k} ({}): {why}", s.placed);
    }
}
