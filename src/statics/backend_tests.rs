//! The structured solver against clarabel on the same plain-data problems, for every shape a
//! stage produces: 1, 3, 4 and 5 variables per point, budgets (their slacks σ), the pyramid,
//! box and cone rows, standing and failing designs.

use super::assemble::{Stage, System, contact_problem};
use super::backend::structured::{Warm, solve};
use super::backend::{Backend, run};
use super::components::components;
use super::problem::{Accuracy, FrictionModel, SolverStatus, Var};
use super::settings::StaticsSettings;
use crate::interfaces::detect;
use crate::model::{Assembly, builtin};

/// The accuracy the stages ask of their LPs.
const LP: Accuracy = Accuracy { feas: 1e-10, gap_abs: 1e-10, gap_rel: 1e-8, pure_relative: true };

fn system(spec: &str, mu: f64, model: FrictionModel, relaxed: bool) -> System {
    let asm = Assembly::new(&builtin(spec).unwrap(), &Default::default()).unwrap();
    let ifs = detect(&asm);
    let comps = components(&asm, &ifs);
    System::new(&asm, &ifs, &comps[0], mu, model, relaxed)
}

/// Solves `stage` of `sys` on both backends to the stages' LP accuracy; returns the status
/// (both solved, to full or reduced accuracy, or both infeasible) and the two objectives.
fn both(sys: &System, stage: Stage) -> (SolverStatus, f64, f64) {
    let settings = StaticsSettings::default();
    let cp = contact_problem(sys, stage, &settings);
    let s = solve(&cp, LP, 200, Warm::Off).expect("the structured solver takes every stage");
    let c = run(&cp, Backend::Clarabel, LP, settings.max_iterations);
    let solved = SolverStatus::solved;
    let status = match (s.status, c.status) {
        (a, b) if solved(a) && solved(b) => SolverStatus::Solved,
        (a, b) if a == b => a,
        (a, b) => panic!("{stage:?}: structured {a:?}, clarabel {b:?}"),
    };
    (status, s.objective, c.objective)
}

#[test]
fn every_stage_shape_meets_clarabel() {
    for model in [FrictionModel::Pyramid8, FrictionModel::Box4, FrictionModel::Cone] {
        // A 7-voussoir arch too thin to stand: tension is needed, and friction beyond μ once the
        // tension is held at its minimum.
        let strict = system("arch?n=7&t=0.06", 0.6, model, false);
        let (status, _, _) = both(&strict, Stage::Strict);
        assert_eq!(status, SolverStatus::Infeasible, "{model}: the thin arch has no strict equilibrium");
        let sys = system("arch?n=7&t=0.06", 0.6, model, true);
        let (status, t, tc) = both(&sys, Stage::Tension);
        assert_eq!(status, SolverStatus::Solved);
        assert!(t > 1e-4 && (t - tc).abs() <= 1e-8, "{model}: minimum tension {t} vs clarabel {tc}");
        for penalty in [0.0, 1e3] {
            let (_, f, fc) = both(&sys, Stage::FrictionExcess { tension: t, penalty });
            assert!((f - fc).abs() <= 1e-7 * (1.0 + fc.abs()), "{model} M {penalty}: {f} vs {fc}");
        }
        // The distribution QP (weights 1e6 on tension and slack): clarabel ends it only at its
        // reduced accuracy on the pyramid, hence 1e-4.
        let (_, d, dc) = both(&sys, Stage::Distribution { tension: t, excess: 1.0 });
        assert!((d - dc).abs() <= 1e-4 * (1.0 + dc.abs()), "{model}: distribution {d} vs {dc}");
        // Zero tension: the pinned layout of 4 variables per point.
        let slope = system("slope?angle=35", 0.5, model, true);
        let (_, f, fc) = both(&slope, Stage::FrictionExcess { tension: 0.0, penalty: 0.0 });
        assert!(f > 0.1 && (f - fc).abs() <= 1e-8, "{model}: slope excess {f} vs {fc}");
        // A standing wall: the strict QP of 3 variables per point.
        let wall = system("wall?courses=3&bricks=3", 0.6, model, false);
        let (status, q, qc) = both(&wall, Stage::Strict);
        assert_eq!(status, SolverStatus::Solved);
        assert!((q - qc).abs() <= 1e-7 * (1.0 + qc.abs()), "{model}: wall {q} vs {qc}");
    }
    // μ = 0: one variable per point (c_n⁺) in the strict layout.
    let stack = system("stack?n=3", 0.0, FrictionModel::Pyramid8, false);
    let (status, q, qc) = both(&stack, Stage::Strict);
    assert_eq!(status, SolverStatus::Solved);
    assert!((q - qc).abs() <= 1e-8 * (1.0 + qc.abs()), "frictionless stack {q} vs {qc}");
}

#[test]
fn the_cone_slope_excess_is_sin_minus_mu_cos() {
    // One block on a 35° slope, μ = 0.5: the exact cone needs W (sin θ − μ cos θ) more
    // friction, in the problem's units (forces / W).
    let sys = system("slope?angle=35", 0.5, FrictionModel::Cone, true);
    let cp = contact_problem(&sys, Stage::FrictionExcess { tension: 0.0, penalty: 1e3 }, &StaticsSettings::default());
    let o = solve(&cp, LP, 200, Warm::Off).unwrap();
    assert_eq!(o.status, SolverStatus::Solved);
    let th = 35f64.to_radians();
    // The closed form to 1e-9; clarabel, at the same tolerances, ends further from it, so the
    // cross-check allows clarabel's own accuracy.
    assert!((o.objective - (th.sin() - 0.5 * th.cos())).abs() < 1e-9, "{}", o.objective);
    let c = run(&cp, Backend::Clarabel, LP, 200);
    assert!((o.objective - c.objective).abs() < 5e-8, "{} vs clarabel {}", o.objective, c.objective);
}

/// Invariant: the factorisation on two threads (faer's supernodal kernels on rayon, forced here
/// on a problem below the size where it is used) solves the same problem to the same answer as
/// the serial one: same status, the objectives within 1e-10 relative, the forces within 1e-8
/// of the largest.
#[test]
fn two_thread_factorisation_gives_the_serial_answer() {
    use super::backend::structured::{FactorPlan, solve_from};
    // faer's factorisation, parallel from its first entry.
    let plan = FactorPlan { blocks_up_to: 0, parallel_from: 0 };
    let settings = StaticsSettings::default();
    let sys = system("wall?courses=10&bricks=10", 0.6, FrictionModel::Pyramid8, false);
    let mut cp = contact_problem(&sys, Stage::Strict, &settings);
    cp.threads = 1;
    let serial = solve_from(&cp, LP, 200, plan, Warm::Off).expect("the structured solver takes the strict QP");
    cp.threads = 2;
    let parallel = solve_from(&cp, LP, 200, plan, Warm::Off).expect("the structured solver takes the strict QP");
    assert_eq!(serial.status, SolverStatus::Solved);
    assert_eq!(parallel.status, serial.status);
    let scale = serial.objective.abs().max(1e-300);
    assert!(
        (parallel.objective - serial.objective).abs() <= 1e-10 * scale,
        "{} vs {}",
        parallel.objective,
        serial.objective
    );
    let largest = serial.x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let worst = serial.x.iter().zip(&parallel.x).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(worst <= 1e-8 * largest, "forces differ by {worst} (largest {largest})");
}

/// Invariant: S factored by 6×6 blocks (AMD on the block graph, the default on problems of
/// this size) and by faer's supernodal Cholesky (AMD on the scalar pattern) solve the same
/// problem to the same answer — a wall (pyramid8) and a dome (cone, tilted frames): same
/// status, objectives within 1e-9 relative, forces within 1e-7 of the largest.
#[test]
fn block_factorisation_gives_faers_answer() {
    use super::backend::structured::{FactorPlan, solve_from};
    let settings = StaticsSettings::default();
    let faer = FactorPlan { blocks_up_to: 0, ..FactorPlan::default() };
    let blocks = FactorPlan { blocks_up_to: usize::MAX, ..FactorPlan::default() };
    for (spec, model) in [("wall?courses=10&bricks=10", FrictionModel::Pyramid8), ("dome", FrictionModel::Cone)] {
        let sys = system(spec, 0.6, model, false);
        let cp = contact_problem(&sys, Stage::Strict, &settings);
        let a = solve_from(&cp, LP, 200, blocks, Warm::Off).expect("the structured solver takes the strict QP");
        let b = solve_from(&cp, LP, 200, faer, Warm::Off).expect("the structured solver takes the strict QP");
        assert_eq!(a.status, SolverStatus::Solved, "{spec}");
        assert_eq!(b.status, a.status, "{spec}");
        let scale = a.objective.abs().max(1e-300);
        assert!((a.objective - b.objective).abs() <= 1e-9 * scale, "{spec}: {} vs {}", a.objective, b.objective);
        let largest = a.x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let worst = a.x.iter().zip(&b.x).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(worst <= 1e-7 * largest, "{spec}: forces differ by {worst} (largest {largest})");
    }
}

/// Invariant: the equilibrium operator applied from the contact form (`System::a_mul`,
/// `at_mul`, `eq_triplets`) is the textbook one — each point force f (c_n⁺ n − c_n⁻ n + c_u u +
/// c_v v) acts on b as +f with moment (p − c_b) × f about b's centroid and on a as −f, lengths
/// by the model size — built here independently from the positions and centroids: the
/// products agree to 1e-12 on an arch and a dome (tilted frames), strict and relaxed layouts.
#[test]
fn equilibrium_operator_from_the_contact_form_is_the_textbook_one() {
    use crate::interfaces::Body;
    for spec in ["arch?n=15&t=0.15", "dome"] {
        for relaxed in [false, true] {
            let asm = Assembly::new(&builtin(spec).unwrap(), &Default::default()).unwrap();
            let ifs = detect(&asm);
            let comps = components(&asm, &ifs);
            let comp = &comps[0];
            let sys = System::new(&asm, &ifs, comp, 0.6, FrictionModel::Pyramid8, relaxed);
            let local: std::collections::HashMap<_, _> = comp.blocks.iter().enumerate().map(|(i, &b)| (b, i)).collect();
            let (n, m) = (sys.n(), sys.eq_rhs.len());
            let mut textbook: std::collections::BTreeMap<(usize, usize), f64> = Default::default();
            for (i, fp) in sys.points.iter().enumerate() {
                let f = &ifs[fp.interface].frame;
                for (var, d) in [(Var::CnPos, f.n), (Var::CnNeg, -f.n), (Var::Cu, f.u), (Var::Cv, f.v)] {
                    let Some(col) = sys.col(i, var) else { continue };
                    for (body, sign) in [(ifs[fp.interface].b, 1.0), (ifs[fp.interface].a, -1.0)] {
                        let Body::Block(id) = body else { continue };
                        let Some(&blk) = local.get(&id) else { continue };
                        let r = (fp.position - asm.block(id).mass.centroid) / asm.scale;
                        let (d, mo) = (d * sign, r.cross(&(d * sign)));
                        for k in 0..3 {
                            *textbook.entry((6 * blk + k, col)).or_default() += d[k];
                            *textbook.entry((6 * blk + 3 + k, col)).or_default() += mo[k];
                        }
                    }
                }
            }
            // Deterministic test vectors.
            let x: Vec<f64> = (0..n).map(|j| ((j * 7919) % 1000) as f64 / 1000.0 - 0.3).collect();
            let y: Vec<f64> = (0..m).map(|i| ((i * 104_729) % 997) as f64 / 997.0 - 0.5).collect();
            let mut ax = vec![0.0; m];
            sys.a_mul(&x, &mut ax);
            let mut aty = vec![0.0; n];
            sys.at_mul(&y, &mut aty);
            let (mut want_ax, mut want_aty) = (vec![0.0; m], vec![0.0; n]);
            for (&(i, j), &v) in &textbook {
                want_ax[i] += v * x[j];
                want_aty[j] += v * y[i];
            }
            for i in 0..m {
                let want = want_ax[i];
                assert!(
                    (ax[i] - want).abs() <= 1e-12 * (1.0 + want.abs()),
                    "{spec} relaxed {relaxed}: row {i}: {} vs {want}",
                    ax[i]
                );
            }
            for j in 0..n {
                let want = want_aty[j];
                assert!((aty[j] - want).abs() <= 1e-12 * (1.0 + want.abs()), "{spec} relaxed {relaxed}: column {j}");
            }
            let mut from_triplets: std::collections::BTreeMap<(usize, usize), f64> = Default::default();
            for (i, j, v) in sys.eq_triplets() {
                *from_triplets.entry((i, j)).or_default() += v;
            }
            for (key, &v) in textbook.iter().chain(&from_triplets) {
                let (a, b) =
                    (textbook.get(key).copied().unwrap_or(0.0), from_triplets.get(key).copied().unwrap_or(0.0));
                assert!((a - b).abs() <= 1e-12, "{spec}: triplet {key:?}: {a} vs {b} ({v})");
            }
        }
    }
}

/// The strict problem of `scene` (its first component, pyramid8, μ 0.6).
fn strict_system(scene: &crate::model::Scene) -> System {
    let asm = Assembly::new(scene, &Default::default()).unwrap();
    let ifs = detect(&asm);
    let comps = components(&asm, &ifs);
    System::new(&asm, &ifs, &comps[0], 0.6, FrictionModel::Pyramid8, false)
}

/// Invariant: a warm start is only a starting point. From the iterate a solve of a wall kept,
/// the same wall with one brick 10 % heavier (same rows and columns) is solved to the cold
/// solve's optimum (objective within 5e-8 relative: both within the gap tolerance 1e-8 of it,
/// and feasible to 1e-8; forces, in units of the weight, within 1e-5: a gap of 1e-8 allows
/// √(2·1e-8) ≈ 1.4e-4 for an objective of unit curvature, and the cold solve is far nearer a
/// solve to 1e-10 — tests/it/statics_warm_start.rs) in fewer iterations, reusing the start's
/// symbolic factorisation (the same pattern); a warm run cut
/// short (capped at one iteration) is replaced by the cold solve itself, bit for bit, its
/// iteration spent counted; a start of another size is not used (the cold solve, bit for bit,
/// with its own symbolic factorisation).
#[test]
fn a_warm_start_is_only_a_starting_point() {
    let settings = StaticsSettings::default();
    let wall = builtin("wall?courses=6&bricks=6").unwrap();
    let mut heavier = wall.clone();
    heavier.blocks[20].density = Some((heavier.material.density * 1.1).into());
    let (base, edited) = (strict_system(&wall), strict_system(&heavier));
    let (cp_base, cp) =
        (contact_problem(&base, Stage::Strict, &settings), contact_problem(&edited, Stage::Strict, &settings));
    let acc = Accuracy::uniform(settings.solver_tolerance);
    let kept = solve(&cp_base, acc, 200, Warm::Keep).unwrap().kept.expect("a solved problem keeps an iterate");
    let cold = solve(&cp, acc, 200, Warm::Off).unwrap();
    assert_eq!(cold.status, SolverStatus::Solved);

    let warm = solve(&cp, acc, 200, Warm::From(&kept)).unwrap();
    assert_eq!(warm.status, SolverStatus::Solved);
    assert!(warm.iterations < cold.iterations, "warm {} vs cold {}", warm.iterations, cold.iterations);
    assert!(
        (warm.objective - cold.objective).abs() <= 5e-8 * cold.objective.abs(),
        "{} vs {}",
        warm.objective,
        cold.objective
    );
    let worst = cold.x.iter().zip(&warm.x).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(worst <= 1e-5, "forces differ by {worst} W");
    assert!(warm.kept.as_ref().expect("a warm solve keeps an iterate").shares_pattern(&kept));

    let cut_short = solve(&cp, acc, 200, Warm::From(&kept.clone().capped(1))).unwrap();
    assert_eq!(cut_short.status, cold.status);
    assert_eq!(cut_short.x, cold.x);
    assert_eq!(cut_short.iterations, cold.iterations + 1);

    let other = strict_system(&builtin("wall?courses=6&bricks=5").unwrap());
    let cp_other = contact_problem(&other, Stage::Strict, &settings);
    let other_cold = solve(&cp_other, acc, 200, Warm::Off).unwrap();
    let other_warm = solve(&cp_other, acc, 200, Warm::From(&kept)).unwrap();
    assert!(!other_warm.kept.as_ref().expect("a solved problem keeps an iterate").shares_pattern(&kept));
    assert_eq!((other_warm.x, other_warm.iterations), (other_cold.x, other_cold.iterations));
}
