//! Fabrication tolerance margins (`stability::tolerance`).
//!
//! Invariants: a block whose weight acts e inside its support's edge tolerates a shrink of
//! every joint of exactly e; a joint carrying a force at angle β from its normal tolerates a
//! tilt of exactly atan μ − β; an arch's shrink margin goes to 0 as its thickness goes to the
//! least the statics let stand; a design that does not stand has no margin (an error).

use crate::common::*;
use voussoir::geometry::Vector3;
use voussoir::model::Scene;
use voussoir::pipeline::AnalysisSettings;
use voussoir::stability::tolerance::{ToleranceError, ToleranceSettings, margins};

fn margins_of(scene: &Scene) -> Result<voussoir::stability::tolerance::Margins, ToleranceError> {
    let settings = AnalysisSettings::default();
    margins(&run(scene, &settings), &settings.statics, &ToleranceSettings::default())
}

/// A 1 × 1 × 0.6 block on a pier that reaches x = 0.3: its joint spans x ∈ [0.3, 1], its weight
/// acts at x = 0.5, e = 0.2 inside the edge.
#[test]
fn an_overhanging_block_tolerates_a_shrink_of_its_weights_distance_to_the_edge() {
    let scene = Scene::new(
        "overhang",
        vec![
            cuboid("pier", [0.3, 0.0, -1.0], [2.0, 1.0, 0.0]).support(true),
            cuboid("block", [0.0; 3], [1.0, 1.0, 0.6]),
        ],
    );
    let m = margins_of(&scene).unwrap();
    let step = ToleranceSettings::default().precision * run(&scene, &AnalysisSettings::default()).assembly.scale;
    assert_close(m.shrink.value, 0.2, 2.0 * step, "shrink margin");
    let g = m.shrink.governing.as_ref().expect("a governing joint");
    assert_eq!((g.a.as_str(), g.b.as_str()), ("pier", "block"));
    // The force is normal to the joint: it tolerates a turn of the whole friction angle.
    assert_close(m.tilt.value, scene.material.friction.atan().to_degrees(), 1e-4, "tilt margin (degrees)");
    assert_close(m.tilt.relative, 1.0, 1e-6, "tilt relative to the friction angle");
}

/// A wide block on a slab under gravity turned by β = 20° (a slope of 20°): tolerates joint
/// planes turned by atan μ − β, μ = 0.8.
#[test]
fn a_block_on_a_slope_tolerates_a_tilt_of_its_friction_angle_less_the_slope() {
    let beta = 20f64.to_radians();
    let mut scene = Scene::new(
        "slope",
        vec![
            cuboid("slab", [-1.0, -1.0, -1.0], [3.0, 3.0, 0.0]).support(true),
            cuboid("block", [0.0; 3], [2.0, 2.0, 0.5]),
        ],
    );
    scene.material.friction = 0.8;
    scene.gravity = Vector3::new(beta.sin(), 0.0, -beta.cos()) * 9.81;
    let m = margins_of(&scene).unwrap();
    let expected = (0.8f64.atan() - beta).to_degrees();
    assert_close(m.tilt.value, expected, 1e-4, "tilt margin (degrees)");
    let g = m.tilt.governing.as_ref().expect("a governing joint");
    assert_eq!((g.a.as_str(), g.b.as_str()), ("slab", "block"));
}

/// The least thickness at which the 15-voussoir arch stands, by bisection on the statics.
fn least_thickness() -> f64 {
    let stands = |t: f64| {
        let scene = voussoir::model::builtin::builtin(&format!("arch?n=15&t={t}")).unwrap();
        run(&scene, &AnalysisSettings::default()).statics.stands
    };
    let (mut lo, mut hi) = (0.09, 0.12);
    while hi - lo > 1e-6 {
        let mid = 0.5 * (lo + hi);
        if stands(mid) { hi = mid } else { lo = mid }
    }
    hi
}

#[test]
fn an_arch_s_shrink_margin_vanishes_at_its_least_thickness() {
    let t_min = least_thickness();
    let mut last = f64::INFINITY;
    for excess in [2e-2, 5e-3, 1e-3, 2e-4] {
        let scene = voussoir::model::builtin::builtin(&format!("arch?n=15&t={}", t_min + excess)).unwrap();
        let m = margins_of(&scene).unwrap();
        // Shrinking both faces of every joint by δ thins the arch's bearing by 2δ.
        assert!(m.shrink.value > 0.0 && m.shrink.value < excess, "t_min + {excess}: δ* {}", m.shrink.value);
        assert!(m.shrink.value < last, "δ* shrinks with the thickness: {} after {last}", m.shrink.value);
        last = m.shrink.value;
    }
    assert!(last < 2e-4, "δ* at t_min + 2e-4: {last}");
}

#[test]
fn a_design_that_does_not_stand_has_no_margin() {
    let scene = voussoir::model::builtin::builtin("arch?n=15&t=0.09").unwrap();
    assert!(matches!(margins_of(&scene), Err(ToleranceError::DoesNotStand(_))));
    let bad = ToleranceSettings { precision: 0.0 };
    let settings = AnalysisSettings::default();
    let a = run(&voussoir::model::builtin::builtin("arch").unwrap(), &settings);
    assert_eq!(margins(&a, &settings.statics, &bad).unwrap_err(), ToleranceError::BadPrecision(0.0));
}

/// The overhanging block under a horizontal live load towards its overhang: it tips about its
/// joint's edge, at λ* = (e − δ)/(h/2) once every joint is shrunk by δ (`chipped`).
#[test]
fn a_chipped_design_s_load_factor_follows_the_shrunk_edge() {
    let h = 0.6;
    let mut scene = Scene::new(
        "overhang",
        vec![cuboid("pier", [0.3, 0.0, -1.0], [2.0, 1.0, 0.0]).support(true), cuboid("block", [0.0; 3], [1.0, 1.0, h])],
    );
    scene.loads.push(voussoir::model::Load::horizontal(std::f64::consts::PI, 1.0));
    let settings = AnalysisSettings::default();
    let analysis = run(&scene, &settings);
    for delta in [0.0, 0.05, 0.15] {
        let chipped = voussoir::stability::tolerance::chipped(&analysis, delta, &settings.statics).unwrap();
        let r = voussoir::stability::assess(&chipped, &settings.statics).unwrap();
        assert_close(r.load_factor, (0.2 - delta) / (h / 2.0), 1e-6, &format!("λ* with joints shrunk by {delta}"));
    }
    let err = voussoir::stability::tolerance::chipped(&analysis, f64::NAN, &settings.statics).unwrap_err();
    assert!(matches!(err, ToleranceError::BadShrink(_)));
}
