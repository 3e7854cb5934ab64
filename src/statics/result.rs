//! Results of the statics: per interface forces and the graded global answer.
//! Forces in N, positions in m; compression positive; friction along the interface frame.

use super::assemble::ForcePoint;
use super::backend::Backend;
use super::components::Component;
use super::problem::{FrictionModel, SolverStatus};
use super::settings::StaticsSettings;
use super::stages::{ComponentOutcome, STAND_FLOOR, Verdict, verdict};
use crate::geometry::{Point3, Vector3};
use crate::interfaces::Interface;
use crate::model::Assembly;
use serde::Serialize;

/// Force at one interface vertex (N), in the interface frame.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct VertexForce {
    /// Where the vertex is, m.
    pub position: [f64; 3],
    /// Compressive normal force c_n⁺, N.
    pub compression: f64,
    /// Tensile normal force c_n⁻, N (zero when it stands).
    pub tension: f64,
    /// Friction along the interface's u axis, N.
    pub friction_u: f64,
    /// Friction along the interface's v axis, N.
    pub friction_v: f64,
    /// Friction beyond μ × compression at this vertex (the relaxed capacity used).
    pub friction_excess: f64,
}

/// Forces at one interface.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct InterfaceResult {
    /// Index in the interface list given to [`super::solve`].
    pub index: usize,
    /// The name of side a (a block, or `ground`): the normal points from a into b.
    pub a: String,
    /// The name of side b, which receives +f.
    pub b: String,
    /// Area of the contact polygon, m².
    pub area: f64,
    /// The unit normal n, from a into b.
    pub normal: [f64; 3],
    /// The frame's first in-plane axis.
    pub u: [f64; 3],
    /// The frame's second in-plane axis (u, v, n right-handed).
    pub v: [f64; 3],
    /// The forces at each vertex of the contact polygon.
    pub vertices: Vec<VertexForce>,
    /// Net normal force Σ(c_n⁺ − c_n⁻), compression positive, N.
    pub normal_force: f64,
    /// Total compression Σ c_n⁺, N.
    pub compression: f64,
    /// Total tension Σ c_n⁻, N.
    pub tension: f64,
    /// Magnitude of the resultant friction force, N.
    pub friction: f64,
    /// Total friction beyond μ × compression, N.
    pub friction_excess: f64,
    /// |friction resultant| / (μ × compression); > 1 means "exceeds". 0 with no friction,
    /// infinite when friction acts without compression ("no": below 1e-8 of the component's
    /// weight, what the solver resolves).
    pub friction_utilization: f64,
    /// Resultant force on b (on a it is the opposite), N, world axes.
    pub resultant: [f64; 3],
    /// Centre of the normal forces in the interface plane (None when they cancel).
    pub resultant_point: Option<[f64; 3]>,
}

/// What the solver did, over all components.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SolverReport {
    /// The worst status of any component.
    pub status: SolverStatus,
    /// Interior-point iterations, summed over components and stages.
    pub iterations: u32,
    /// Largest equilibrium residual ‖Σ f + W‖_∞ of any block, N (for a group that touches no
    /// support: its whole weight, since nothing balances it).
    pub residual: f64,
    /// Messages of components that did not solve, naming their blocks.
    pub messages: Vec<String>,
    /// The interior-point solver that ran: `clarabel` when any problem ran on clarabel (the
    /// `clarabel` backend, or a problem the structured solver does not take), else
    /// `structured`.
    pub backend: Backend,
}

/// The crushing check of a design that stands by compression and friction
/// ([`super::StaticsSettings::strength`]; the rectangular stress block, module docs of
/// `statics::problem`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CrushingReport {
    /// The material's compressive strength σ_c, Pa.
    pub strength: f64,
    /// The least strength any equilibrium needs (compression only, friction within μ), Pa.
    pub needed: f64,
    /// needed / strength: above 1 it crushes.
    pub utilization: f64,
    /// The interface that needs it (index, and the names of its two sides).
    pub interface: usize,
    /// The name of its side a.
    pub a: String,
    /// The name of its side b.
    pub b: String,
}

/// The answer of [`super::solve`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StaticsResult {
    /// Stands, needs tension, needs friction, both, unsupported or unresolved.
    pub verdict: Verdict,
    /// Whether it stands by compression and friction alone (and does not crush).
    pub stands: bool,
    /// Minimum total tension / total free weight.
    pub tension_ratio: f64,
    /// Minimum total friction excess / total free weight.
    pub friction_excess_ratio: f64,
    /// The largest |friction resultant| / (μ × compression) over the interfaces (> 1: exceeded).
    pub max_friction_utilization: f64,
    /// Total free weight W, N.
    pub free_weight: f64,
    /// μ the statics ran with.
    pub friction_coefficient: f64,
    /// The friction model the statics ran with.
    pub friction_model: FrictionModel,
    /// Connected components of free blocks, each solved on its own.
    pub components: usize,
    /// Forces per interface, in the interfaces' order.
    pub interfaces: Vec<InterfaceResult>,
    /// With a compressive strength, on a design that stands by compression and friction.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub crushing: Option<CrushingReport>,
    /// The solver's status, iterations and residual (the worst over components).
    pub solver: SolverReport,
    /// Seconds building the equilibrium problems and inside the interior-point solver that ran
    /// (structured by default), summed over components
    /// (CPU time: components may run on two threads).
    pub assemble_seconds: f64,
    /// Seconds inside the interior-point solver, summed over components.
    pub solver_seconds: f64,
}

pub(super) fn collect(
    assembly: &Assembly,
    interfaces: &[Interface],
    comps: &[Component],
    outcomes: Vec<ComponentOutcome>,
    mu: f64,
    settings: &StaticsSettings,
) -> StaticsResult {
    let w_total = assembly.free_weight();
    let mut results = Vec::new();
    let (mut tension, mut excess, mut residual, mut iterations) = (0.0, 0.0, 0.0f64, 0);
    let mut messages = Vec::new();
    for (comp, out) in comps.iter().zip(outcomes.iter()) {
        iterations += out.iterations;
        if let Some(m) = &out.message {
            messages.push(m.clone());
        }
        residual = residual.max(out.residual);
        if out.forces.is_empty() {
            continue;
        }
        tension += out.min_tension;
        excess += out.min_excess;
        results.extend(interface_results(assembly, interfaces, comp, out, mu));
    }
    results.sort_by_key(|r| r.index);
    // A scene without free blocks has nothing to hold up: ratios 0, not 0/0.
    let ratio = |x: f64| if w_total > 0.0 { x / w_total } else { 0.0 };
    let tension_ratio = ratio(tension);
    let friction_excess_ratio = ratio(excess);
    let (status, verdict) = verdict(&outcomes, settings);
    let max_friction_utilization = results.iter().map(|r| r.friction_utilization).fold(0.0, f64::max);
    let crushing = crushing_report(assembly, interfaces, comps, &outcomes, settings);
    StaticsResult {
        verdict,
        stands: verdict == Verdict::Stands,
        tension_ratio,
        friction_excess_ratio,
        max_friction_utilization,
        free_weight: w_total,
        friction_coefficient: mu,
        friction_model: settings.friction_model,
        components: comps.len(),
        interfaces: results,
        crushing,
        solver: SolverReport {
            status,
            iterations,
            residual,
            messages,
            backend: if outcomes.iter().any(|o| o.used_clarabel) { Backend::Clarabel } else { Backend::Structured },
        },
        assemble_seconds: outcomes.iter().map(|o| o.assemble_seconds).sum(),
        solver_seconds: outcomes.iter().map(|o| o.solver_seconds).sum(),
    }
}

/// The governing component's needed strength, when every component was checked.
fn crushing_report(
    assembly: &Assembly,
    interfaces: &[Interface],
    comps: &[Component],
    outcomes: &[ComponentOutcome],
    settings: &StaticsSettings,
) -> Option<CrushingReport> {
    let strength = settings.strength?;
    let checked: Option<Vec<(f64, usize)>> = comps
        .iter()
        .zip(outcomes)
        .filter(|(_, o)| !o.forces.is_empty())
        .map(|(c, o)| o.crushing.map(|(needed, local)| (needed, c.interfaces[local])))
        .collect();
    let (needed, interface) =
        checked?.into_iter().fold((0.0, usize::MAX), |best, c| if c.0 > best.0 { c } else { best });
    let itf = interfaces.get(interface)?;
    Some(CrushingReport {
        strength,
        needed,
        utilization: needed / strength,
        interface,
        a: itf.a.name(assembly).to_string(),
        b: itf.b.name(assembly).to_string(),
    })
}

fn arr(v: &Vector3) -> [f64; 3] {
    [v.x, v.y, v.z]
}

fn interface_results(
    assembly: &Assembly,
    interfaces: &[Interface],
    comp: &Component,
    out: &ComponentOutcome,
    mu: f64,
) -> Vec<InterfaceResult> {
    // Force points are grouped by interface in the component's interface order.
    type PointsOf<'a> = Vec<(&'a ForcePoint, &'a [f64; 5])>;
    let mut by_interface: Vec<(usize, PointsOf)> = Vec::with_capacity(comp.interfaces.len());
    for (fp, f) in out.points.iter().zip(&out.forces) {
        match by_interface.last_mut() {
            Some((k, list)) if *k == fp.interface => list.push((fp, f)),
            _ => by_interface.push((fp.interface, vec![(fp, f)])),
        }
    }
    // Below what the LPs resolve (STAND_FLOOR of the weight) an interface's forces are the
    // interior-point solution's round-off: its use and its resultant's point are not computed
    // from them.
    let noise = STAND_FLOOR * out.weight;
    by_interface
        .into_iter()
        .map(|(k, pts)| {
            let itf = &interfaces[k];
            let fr = &itf.frame;
            let mut resultant = Vector3::zeros();
            let (mut comp_sum, mut tens_sum, mut excess) = (0.0, 0.0, 0.0);
            let (mut fu, mut fv) = (0.0, 0.0);
            let mut moment_point = Vector3::zeros();
            let mut vertices = Vec::with_capacity(pts.len());
            for (fp, f) in &pts {
                let net = f[0] - f[1];
                resultant += fr.n * net + fr.u * f[2] + fr.v * f[3];
                comp_sum += f[0];
                tens_sum += f[1];
                fu += f[2];
                fv += f[3];
                excess += f[4];
                moment_point += fp.position.coords * net;
                vertices.push(VertexForce {
                    position: arr(&fp.position.coords),
                    compression: f[0],
                    tension: f[1],
                    friction_u: f[2],
                    friction_v: f[3],
                    friction_excess: f[4],
                });
            }
            let normal_force = comp_sum - tens_sum;
            let friction = (fu * fu + fv * fv).sqrt();
            let friction_utilization = if friction <= noise {
                0.0
            } else if mu * comp_sum <= noise {
                f64::INFINITY
            } else {
                friction / (mu * comp_sum)
            };
            let resultant_point =
                (normal_force.abs() > noise).then(|| arr(&Point3::from(moment_point / normal_force).coords));
            InterfaceResult {
                index: k,
                a: itf.a.name(assembly).to_string(),
                b: itf.b.name(assembly).to_string(),
                area: itf.area,
                normal: arr(&fr.n),
                u: arr(&fr.u),
                v: arr(&fr.v),
                vertices,
                normal_force,
                compression: comp_sum,
                tension: tens_sum,
                friction,
                friction_excess: excess,
                friction_utilization,
                resultant: arr(&resultant),
                resultant_point,
            }
        })
        .collect()
}
