//! Invariant: the minimum tension and friction excess of a design that fails are those of a
//! force state that exists — with the force-distribution QP off, the reported forces are the
//! last LP's, and they hold every block (residual ≤ 1e-12 W), have c_n⁺ ≥ 0 and c_n⁻ ≥ 0 at
//! every vertex, a friction excess at each vertex equal to the friction its forces need beyond
//! μ c_n⁺ (pyramid rows, 1e-12 W), a friction excess summing to the reported minimum (1e-12
//! relative) and a tension within its budget.
//!
//! The case is step 360 of the Armadillo's bottom-up sequence at μ 0.84 (361 of its 399
//! blocks, 4 924 force points: it needs tension and friction). Its two LPs were also solved by
//! HiGHS (scipy 1.17.1's `linprog(method="highs-ipm")`, crossover to a vertex: primal and dual
//! objectives equal to 10 digits, rows met to 1e-12): T* = 2.0223693157e-3 W and, from the
//! exact-penalty LP's optimum M T* + F* = 2.0250672212 (M = 1000), F* = 2.6979054e-3 W. The
//! reported minima, a feasible state's, are upper bounds of these: T* to 1e-6 and F* to 2e-4
//! relative.

use crate::common::*;
use voussoir::pipeline::AnalysisSettings;
use voussoir::statics::Verdict;
use voussoir::studies::sequence::{OrderSpec, SequenceReport, order, step_analysis};

#[test]
fn the_minima_of_a_failing_armadillo_prefix_are_those_of_a_feasible_force_state() {
    let scene = voussoir::io::load_scene(&compas_data("compas_cra/armadillo_cra.json")).unwrap();
    let mut settings = AnalysisSettings::default();
    settings.statics.friction = Some(0.84);
    settings.statics.distribution = false;
    let order = order(&scene, &OrderSpec::BottomUp, &settings).unwrap();
    let report =
        SequenceReport { order, steps: Vec::new(), first_failure: None, temporary_supports: Vec::new(), search: None };
    let r = step_analysis(&scene, &report, 360, &settings).unwrap().statics;
    assert_eq!(r.verdict, Verdict::NeedsTensionAndFriction);
    assert_eq!(r.components, 1, "one shell: the ratios are its LPs' optima");
    let w = r.free_weight;
    assert!(r.solver.residual <= 1e-12 * w, "residual {:e} W", r.solver.residual / w);

    let mu = r.friction_coefficient;
    let (mut tension, mut excess) = (0.0, 0.0);
    for f in r.interfaces.iter().flat_map(|i| &i.vertices) {
        assert!(f.compression >= 0.0 && f.tension >= 0.0, "c_n⁺ {:e}, c_n⁻ {:e} W", f.compression, f.tension);
        let (u, v) = (f.friction_u.abs(), f.friction_v.abs());
        let need = u.max(v).max((u + v) / std::f64::consts::SQRT_2);
        let beyond = (need - mu * f.compression).max(0.0);
        assert!(
            (f.friction_excess - beyond).abs() <= 1e-12 * w,
            "slack {:e} for {:e} W beyond",
            f.friction_excess,
            beyond
        );
        tension += f.tension;
        excess += f.friction_excess;
    }
    // The forces are the friction-excess LP's, whose tension is held to the budget T*(1 + 1e-6)
    // + 1e-9 W (statics::assemble::tension_budget).
    let budget = r.tension_ratio * (1.0 + 1e-6) + 1e-9;
    assert!(tension / w <= budget, "Σ c_n⁻ {:e} W above the budget {budget:e} W", tension / w);
    assert_close(
        excess / w,
        r.friction_excess_ratio,
        1e-12 * r.friction_excess_ratio,
        "Σ s = the minimum friction excess",
    );

    // Against HiGHS (module docs): a feasible state's minima are upper bounds.
    assert_close(r.tension_ratio, 2.0223693157e-3, 1e-6 * 2.0223693157e-3, "T* / W");
    assert_close(r.friction_excess_ratio, 2.6979054e-3, 2e-4 * 2.6979054e-3, "F* / W");
    assert!(r.tension_ratio >= 2.0223693157e-3 * (1.0 - 1e-9), "the tension of a feasible state is at least T*");
}
