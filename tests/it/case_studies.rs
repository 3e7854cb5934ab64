//! Invariant: the seed paper's case studies (assets/cases, density 600 kg/m³, μ = tan 40°)
//! give the paper's qualitative outcomes, measured on the forces.

use crate::cases;
use crate::common::*;
use voussoir::model::Scene;
use voussoir::pipeline::{Analysis, AnalysisSettings};
use voussoir::statics::{FrictionModel, InterfaceResult};

/// The stored asset `stem`, checked to be what `make_case_studies` writes today.
fn case(stem: &str) -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("assets/cases/{stem}.json"));
    let stored = voussoir::io::load_scene(&path).expect("the case study asset loads");
    let (_, built) = cases::all().into_iter().find(|(s, _)| s == stem).expect("a known case");
    assert_eq!(stored, built, "{stem}: the asset is stale; run `cargo run --example make_case_studies`");
    stored
}

fn analysis(stem: &str) -> Analysis {
    run(&case(stem), &AnalysisSettings::default())
}

fn internal(a: &Analysis) -> impl Iterator<Item = &InterfaceResult> {
    a.statics.interfaces.iter().filter(|r| r.a != "ground" && r.b != "ground")
}

/// |resultant point − polygon centroid| / √area.
fn eccentricity(a: &Analysis, r: &InterfaceResult) -> f64 {
    let p = nalgebra::Point3::from(r.resultant_point.expect("a loaded interface"));
    (p - a.interfaces[r.index].centroid()).norm() / r.area.sqrt()
}

#[test]
fn every_case_is_stored_and_current() {
    let stems: Vec<String> = cases::all().into_iter().map(|(s, _)| s).collect();
    assert_eq!(stems.len(), 17);
    for stem in stems {
        case(&stem);
    }
}

#[test]
fn fig3_sc_needs_tension_until_supported_or_reshaped() {
    let a = analysis("fig3a_sc");
    assert!(!a.statics.stands);
    // One block on the C's foot with its centre of mass outside: the ground interface pulls.
    let ground = &a.statics.interfaces[0];
    assert_eq!((ground.a.as_str(), ground.b.as_str()), ("ground", "SC"));
    assert!(ground.tension > 0.2 * a.statics.free_weight, "tension {}", ground.tension);
    assert!(a.statics.tension_ratio > 0.2);
    let b = analysis("fig3b_sc");
    assert!(b.statics.stands && b.statics.interfaces.iter().any(|r| r.a == "pedestal" || r.b == "pedestal"));
    assert!(analysis("fig3c_sc").statics.stands);
}

#[test]
fn fig4_m_cut_through_the_v_hangs_lower_cuts_stand_more_evenly() {
    let a = analysis("fig4a_m_cut");
    assert!(!a.statics.stands);
    // The tension is at a cut interface (the V's tip hangs from the top piece), not the ground.
    let pulled: Vec<_> = a.statics.interfaces.iter().filter(|r| r.tension > 1e-6 * a.statics.free_weight).collect();
    assert!(!pulled.is_empty() && pulled.iter().all(|r| r.a != "ground"), "{pulled:?}");
    let spread = |stem: &str| {
        let a = analysis(stem);
        assert!(a.statics.stands, "{stem}");
        internal(&a).map(|r| eccentricity(&a, r)).fold(0.0, f64::max)
    };
    let (b, c) = (spread("fig4b_m_cut"), spread("fig4c_m_cut"));
    assert!(c < 0.7 * b, "eccentricity (c) {c} should be clearly below (b) {b}");
}

#[test]
fn fig5_m_inclined_cut_friction_follows_the_angle() {
    let mut settings = AnalysisSettings::default();
    settings.statics.friction_model = FrictionModel::Cone; // exact Coulomb: utilisation = tan θ / μ
    let mu = 40f64.to_radians().tan();
    for (stem, deg, stands) in
        [("fig5a_m_inclined", 50.0, false), ("fig5b_m_inclined", 30.0, true), ("fig5c_m_inclined", 10.0, true)]
    {
        let a = run(&case(stem), &settings);
        assert_eq!(a.statics.stands, stands, "{stem}");
        let need = f64::to_radians(deg).tan() / mu;
        let worst = internal(&a).map(|r| r.friction_utilization).fold(0.0, f64::max);
        if stands {
            assert_close(worst, need, 0.02 * need, stem);
        } else {
            assert!(worst > 1.0 && a.statics.friction_excess_ratio > 0.1, "{stem}: {worst}");
        }
    }
}

#[test]
fn fig6_dmsc_stands_on_compression_and_friction_without_ground_friction() {
    let a = analysis("fig6_dmsc");
    let w = a.statics.free_weight;
    assert!(a.statics.stands);
    assert!(a.assembly.blocks.len() >= 10);
    assert!(internal(&a).all(|r| r.compression > 1e-3 * w && r.tension <= 1e-9 * w));
    assert!(internal(&a).any(|r| r.friction_utilization > 0.2), "some interfaces need friction");
    let ground_friction: f64 = a.statics.interfaces.iter().filter(|r| r.a == "ground").map(|r| r.friction).sum();
    assert!(ground_friction < 1e-9 * w, "ground friction {ground_friction}");
}

#[test]
fn fig7_loop_compression_only_until_the_cuts_are_inclined() {
    let a = analysis("fig7a_loop");
    assert!(a.statics.stands && a.statics.interfaces.iter().all(|r| r.a == "ground"));
    // The loop's foot is five coplanar faces (one per grid cell), each a ground interface.
    let c: Vec<f64> = a.statics.interfaces.iter().flat_map(|r| r.vertices.iter().map(|v| v.compression)).collect();
    assert_eq!(c.len(), 20);
    let (lo, hi) = c.iter().fold((f64::MAX, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
    assert!(hi - lo < 1e-6 * hi, "even compression at the support: {c:?}");

    let b = analysis("fig7b_loop");
    let w = b.statics.free_weight;
    assert!(b.statics.stands && internal(&b).count() == 4);
    assert!(internal(&b).all(|r| r.compression > 0.1 * w && r.friction < 1e-6 * w));

    let c = analysis("fig7c_loop");
    assert!(c.statics.stands);
    let vertical: Vec<_> = internal(&c).filter(|r| r.normal[2].abs() < 1e-9).collect();
    assert_eq!(vertical.len(), 2);
    for r in vertical {
        // Zero up to the distribution QP's resolution: its objective is flat at the optimum, so
        // a solver gap of 1e-8 leaves forces of order √1e-8 of the mean (measured 4e-5 W).
        assert!(r.compression + r.friction < 1e-3 * w, "{} | {}: {} N", r.a, r.b, r.compression);
    }

    let d = analysis("fig7d_loop");
    assert!(d.statics.stands);
    assert!(internal(&d).all(|r| r.friction_utilization > 0.15 && r.friction_utilization <= 1.0));
}

#[test]
fn fig9_pattern_box_stands_also_with_parts_removed() {
    let a = analysis("fig9a_box");
    assert!(a.statics.stands);
    assert_eq!(a.assembly.blocks.len(), 10);
    // Every cut interface lies in a plane through the apex.
    let apex = nalgebra::Point3::new(0.0, 0.0, -1.0);
    for r in internal(&a) {
        let n = nalgebra::Vector3::from(r.normal);
        let d = n.dot(&(apex - a.interfaces[r.index].centroid()));
        assert!(d.abs() < 1e-9, "{} | {} misses the apex by {d}", r.a, r.b);
    }
    let b = analysis("fig9b_box");
    assert!(b.statics.stands);
    assert_eq!(b.assembly.blocks.len(), 8);
    for name in cases::FIG9B_REMOVED {
        assert!(b.assembly.blocks.iter().all(|blk| blk.name != name));
    }
}
