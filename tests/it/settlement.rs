//! Support movement (`studies::settlement`).
//!
//! Invariants: a b × h block on a support that tilts slowly tips when the tilt reaches
//! atan(b/h) (μ > b/h) and slides at atan μ (μ < b/h) — quasi-statically within 0.1°, with the
//! joint hinging or sliding; the exact engine and rapier, moving the support in real time,
//! within 1.5° (their collapse is seen once the block leaves the support's pace); bad movement
//! input is one clear error each.

use crate::common::*;
use voussoir::model::{Movement, Scene};
use voussoir::pipeline::AnalysisSettings;
use voussoir::statics::JointState;
use voussoir::studies::settlement::{
    Outcome, QUASI_STATIC, SettleError, SettleSettings, Settlement, settle, settle_with_progress,
};

/// A 2 × 2 slab turning by `tilt` degrees about y under a b × 0.5 × h block, μ = `mu`.
fn tilting(b: f64, h: f64, mu: f64, tilt: f64, engines: bool) -> Settlement {
    tilting_stone(b, h, mu, tilt, engines, None)
}

/// [`tilting`] with the stone's compressive strength (Pa).
fn tilting_stone(b: f64, h: f64, mu: f64, tilt: f64, engines: bool, strength: Option<f64>) -> Settlement {
    let mut scene = Scene::new(
        "tilt",
        vec![
            cuboid("slab", [-1.0, -1.0, -0.5], [1.0, 1.0, 0.0]).support(true),
            cuboid("block", [-b / 2.0, -0.25, 0.0], [b / 2.0, 0.25, h]),
        ],
    );
    scene.material.friction = mu;
    let analysis = run(&scene, &AnalysisSettings::default());
    let turn = Movement { block: "slab".into(), translation: [0.0; 3], rotation: [0.0, tilt, 0.0] };
    settle(&analysis, &[turn], &SettleSettings { engines, strength, ..Default::default() }).unwrap()
}

fn tilt_at_collapse(outcome: Outcome, tilt: f64) -> f64 {
    match outcome {
        Outcome::Collapses { fraction, .. } => fraction * tilt,
        other => panic!("expected a collapse, got {other:?}"),
    }
}

#[test]
fn a_block_on_a_tilting_support_tips_at_atan_b_over_h_and_slides_at_atan_mu() {
    let (b, h): (f64, f64) = (0.5, 1.0);
    for (mu, expected, state) in [(0.8, (b / h).atan(), JointState::Hinging), (0.3, 0.3f64.atan(), JointState::Sliding)]
    {
        let s = tilting(b, h, mu, 60.0, true);
        let expected = expected.to_degrees();
        let quasi = tilt_at_collapse(s.quasi_static.outcome, 60.0);
        assert_close(quasi, expected, 0.1, &format!("μ {mu}: quasi-static tilt at collapse (degrees)"));
        assert_eq!(s.quasi_static.mechanism.len(), 1, "μ {mu}: {:?}", s.quasi_static.mechanism);
        assert_eq!(s.quasi_static.mechanism[0].state, state, "μ {mu}");
        for run in [s.exact.as_ref().unwrap(), s.rapier.as_ref().unwrap()] {
            let t = tilt_at_collapse(run.outcome, 60.0);
            assert!(
                t >= expected - 0.1 && t <= expected + 1.5,
                "μ {mu}: {} collapses at {t}° (expected {expected}°)",
                run.method
            );
        }
        assert_eq!(s.exact.as_ref().unwrap().mechanism[0].state, state, "μ {mu}: the exact engine's mechanism");
    }
}

/// Invariant: with a compressive strength σ the block tips before atan(b/h): turned by θ, its
/// joint carries N = W cos θ at e = (h/2) tan θ from the centre, and the stress block reaches
/// the downhill edge when N = σ d (b − 2e), i.e. h tan θ + W cos θ / (σ d) = b (θ by
/// bisection). σ is set so that W/(σ d) = 0.2 b: 22.2° against 26.6°. The quasi-static run tips
/// there within 0.1°; the report names the strength. The exact engine, the slab turning in real
/// time, is only held between that and the rigid limit + 1.5°: its joint yields slowly until
/// the uphill side opens, and an open joint pivots on its rigid edge (crushing module docs).
#[test]
fn a_block_whose_stone_crushes_tips_before_atan_b_over_h() {
    let (b, h, d): (f64, f64, f64) = (0.5, 1.0, 0.5);
    let w = 600.0 * b * d * h * 9.81;
    let sigma = w / (0.2 * b * d);
    let s = tilting_stone(b, h, 0.8, 60.0, true, Some(sigma));
    assert_eq!(s.strength, Some(sigma));
    assert!(s.quasi_static.crushed.is_some_and(|d| d >= 0.0), "{:?}", s.quasi_static.crushed);
    let crushes = |t: f64| h * t.tan() + w * t.cos() / (sigma * d) - b;
    let (mut lo, mut hi) = (0.0f64, (b / h).atan());
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if crushes(mid) < 0.0 { lo = mid } else { hi = mid }
    }
    let expected = lo.to_degrees();
    assert!(expected < (b / h).atan().to_degrees() - 4.0, "{expected}");
    let quasi = tilt_at_collapse(s.quasi_static.outcome, 60.0);
    assert_close(quasi, expected, 0.1, "quasi-static tilt at collapse with crushing (degrees)");
    let t = tilt_at_collapse(s.exact.as_ref().unwrap().outcome, 60.0);
    let rigid = (b / h).atan().to_degrees();
    assert!(
        t >= expected - 0.1 && t <= rigid + 1.5,
        "the exact engine collapses at {t}° (expected {expected}°..{rigid}°)"
    );
}

/// A tilt short of both limits: the block rides the support to the end; the support's
/// reaction is the block's weight throughout (quasi-static: no inertia), to the hold
/// criterion's 1e-4 g (a block counts as held below 1e-4 of a free fall's speed).
#[test]
fn a_short_tilt_carries_the_block_with_its_weight_on_the_support() {
    let s = tilting(0.5, 1.0, 0.8, 10.0, false);
    assert_eq!(s.quasi_static.outcome, Outcome::Stands);
    let weight = 0.5 * 0.5 * 1.0 * 600.0 * 9.81;
    for stage in &s.quasi_static.stages {
        let r = stage.reactions[0];
        let magnitude = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
        assert_close(magnitude, weight, 1e-4 * weight, "the support carries the weight");
    }
    assert_eq!(s.quasi_static.stages.len(), SettleSettings::default().increments);
}

#[test]
fn bad_movements_are_one_clear_error_each() {
    let scene = Scene::new(
        "two slabs",
        vec![
            cuboid("left", [0.0, 0.0, -1.0], [1.0, 1.0, 0.0]).support(true),
            cuboid("right", [1.5, 0.0, -1.0], [2.5, 1.0, 0.0]).support(true),
            cuboid("lintel", [0.5, 0.0, 0.0], [2.0, 1.0, 0.2]),
        ],
    );
    let analysis = run(&scene, &AnalysisSettings::default());
    let go =
        |m: Movement| settle(&analysis, &[m], &SettleSettings { engines: false, ..Default::default() }).unwrap_err();
    let mv = |block: &str, t: [f64; 3]| Movement { block: block.into(), translation: t, rotation: [0.0; 3] };
    assert_eq!(go(mv("nowhere", [0.1, 0.0, 0.0])), SettleError::UnknownBlock("nowhere".into()));
    assert_eq!(go(mv("lintel", [0.1, 0.0, 0.0])), SettleError::NotASupport("lintel".into()));
    assert_eq!(go(mv("left", [f64::NAN, 0.0, 0.0])), SettleError::NotFinite("left".into()));
    assert_eq!(go(mv("left", [1.0, 0.0, 0.0])), SettleError::Closes { moved: "left".into(), other: "right".into() });
    assert_eq!(settle(&analysis, &[], &SettleSettings::default()).unwrap_err(), SettleError::NoMovement);
    assert!(Movement::parse("left:1,2").is_err() && Movement::parse("left:1,2,3:4").is_err());
    assert_eq!(Movement::parse("left:1,2,3:0,0,5").unwrap().rotation, [0.0, 0.0, 5.0]);
}

/// Invariant: a path or a setting beyond its limit is one error naming the limit, before any
/// run (a movement of -1e30 m once overflowed the engines' step count): a support moves at most
/// 10 model sizes and turns at most 180°, a path has at most a million increments and halvings
/// within a double's 52 bits, and the engines' run at most 1e7 steps.
#[test]
fn a_path_beyond_its_limits_is_one_clear_error() {
    let analysis = run(&voussoir::model::builtin("arch?n=9&t=0.15").unwrap(), &AnalysisSettings::default());
    let size = analysis.assembly.scale;
    let go = |m: Movement, s: SettleSettings| settle(&analysis, &[m], &s).unwrap_err();
    let mv = |t: [f64; 3], r: [f64; 3]| Movement { block: "springer_left".into(), translation: t, rotation: r };
    let quasi = SettleSettings { engines: false, ..Default::default() };
    for far in [-1e30, -1e12, -10.5 * size] {
        let e = go(mv([far, 0.0, 0.0], [0.0; 3]), quasi.clone());
        assert!(matches!(e, SettleError::TooFar { limit, .. } if (limit - 10.0 * size).abs() < 1e-12 * size), "{e}");
    }
    let e = go(mv([0.0; 3], [0.0, 190.0, 0.0]), quasi.clone());
    assert!(matches!(e, SettleError::TooFar { limit: 180.0, .. }), "{e}");
    let many = SettleSettings { increments: 1_000_001, ..quasi.clone() };
    assert!(matches!(go(mv([-0.01, 0.0, 0.0], [0.0; 3]), many), SettleError::Setting(_)));
    let halvings = SettleSettings { refine: 53, ..quasi.clone() };
    assert!(matches!(go(mv([-0.01, 0.0, 0.0], [0.0; 3]), halvings), SettleError::Setting(_)));
    let fine = SettleSettings { engines: true, dt: 1e-9, ..Default::default() };
    let e = go(mv([-0.01, 0.0, 0.0], [0.0; 3]), fine);
    assert!(matches!(e, SettleError::TooManySteps { steps, .. } if steps > 1e7), "{e}");
}

/// A lintel on two piers, the right one settling by d: the lintel turns about the left pier's
/// inner edge and rests on the right pier by its end, tan θ = d / (distance from that edge to the
/// end), and stands (μ 0.84 against a slope of 2.3°).
#[test]
fn a_lintel_follows_a_settling_pier_turning_about_the_other_pier_s_edge() {
    let scene = lintel();
    let analysis = run(&scene, &AnalysisSettings::default());
    let d = 0.1;
    let settle_right = Movement { block: "right".into(), translation: [0.0, 0.0, -d], rotation: [0.0; 3] };
    let s = settle(&analysis, &[settle_right], &SettleSettings { engines: false, ..Default::default() }).unwrap();
    assert_eq!(s.quasi_static.outcome, Outcome::Stands);
    let last = s.quasi_static.stages.last().unwrap();
    let expected = (d / 2.5f64).atan().to_degrees();
    assert_close(last.rotation, expected, 1e-3 * expected, "the lintel's turn (degrees)");
    let states: Vec<(&str, &str, JointState)> =
        last.joints.iter().map(|j| (j.a.as_str(), j.b.as_str(), j.state)).collect();
    assert!(states.iter().any(|j| j.0 == "left" && j.2 == JointState::Hinging), "{states:?}");
}

/// Invariant: a settlement's motion has the start and one frame per stage, at the stages'
/// fractions of the path; in every frame the settling pier is where its path puts it (start +
/// fraction × d, 1e-9), the fixed pier has not moved, and the lintel's turn is the stage's
/// rotation. `settle --frames/--strip` write them: a glb that reads back with one channel pair
/// per moving block (the pier and the lintel), and a six-panel strip.
#[test]
fn a_settlement_records_its_motion() {
    let scene = lintel();
    let analysis = run(&scene, &AnalysisSettings::default());
    let d = 0.1;
    let settle_right = Movement { block: "right".into(), translation: [0.0, 0.0, -d], rotation: [0.0; 3] };
    let s = settle(&analysis, &[settle_right], &SettleSettings { engines: false, ..Default::default() }).unwrap();
    let run = &s.quasi_static;
    let m = &run.motion;
    assert_eq!(m.times.len(), run.stages.len() + 1);
    assert_eq!(m.times[0], 0.0);
    let asm = &analysis.assembly;
    for (k, (t, poses)) in m.times.iter().zip(&m.poses).enumerate().skip(1) {
        assert_eq!(*t, run.stages[k - 1].fraction);
        let right = asm.blocks[1].mass.centroid;
        assert!((poses[1].0 - (right - nalgebra::Vector3::z() * (t * d))).norm() < 1e-9, "{:?}", poses[1]);
        assert!(poses[0].0 == asm.blocks[0].mass.centroid && poses[0].1 == [1.0, 0.0, 0.0, 0.0]);
        let turn = 2.0 * poses[2].1[0].clamp(-1.0, 1.0).acos().to_degrees();
        assert!((turn - run.stages[k - 1].rotation).abs() < 1e-9, "{turn} vs {}", run.stages[k - 1].rotation);
    }

    let dir = crate::common::scratch("settle-motion");
    let file = dir.join("lintel.json");
    std::fs::write(&file, voussoir::io::scene_json::scene_to_string(&scene)).unwrap();
    let (glb, png) = (dir.join("lintel.glb"), dir.join("lintel.png"));
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_voussoir"))
        .arg("settle")
        .arg(&file)
        .args(["--move", "right:0,0,-0.1", "--quasi-static", "--increments", "6"])
        .arg("--frames")
        .arg(&glb)
        .arg("--strip")
        .arg(&png)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let (doc, _, _) = gltf::import(&glb).expect("a valid glb");
    assert_eq!(doc.animations().next().expect("an animation").channels().count(), 2 * 2);
    let img = image::open(&png).unwrap();
    assert_eq!((img.width(), img.height()), (6 * 360, 420));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Invariant: an arch on spreading springers (9 voussoirs, t/R 0.15, each springer 0.15 m
/// out) collapses at the same spread three ways — the exact engine moving the supports at
/// 0.005 √(g × size) sees it within [0, +3 %] of the quasi-static run (an engine sees the
/// collapse once the blocks leave the supports' pace, a little after it starts), rapier
/// within ±3 %; the quasi-static mechanism has four hinges, each also hinging in the exact
/// engine's; and from a quarter of the path to the collapse both carry the same thrust, the
/// horizontal reaction on a springer, within 1 % (before that the quasi-static run rests on
/// another hinge pattern, 7 % lower, until a snap at 16–22 % of the path).
#[test]
fn a_spreading_arch_collapses_alike_quasi_statically_and_in_both_engines() {
    let scene = voussoir::model::builtin("arch?n=9&t=0.15").unwrap();
    let analysis = run(&scene, &AnalysisSettings::default());
    let spread = |name: &str, dx: f64| Movement { block: name.into(), translation: [dx, 0.0, 0.0], rotation: [0.0; 3] };
    let moves = [spread("springer_left", -0.15), spread("springer_right", 0.15)];
    let settings = SettleSettings { increments: 50, speed: 0.005, ..Default::default() };
    let s = settle(&analysis, &moves, &settings).unwrap();
    let at = |o: Outcome| match o {
        Outcome::Collapses { fraction, .. } => fraction,
        other => panic!("expected a collapse, got {other:?}"),
    };
    let (exact, rapier) = (s.exact.as_ref().unwrap(), s.rapier.as_ref().unwrap());
    let q = at(s.quasi_static.outcome);
    let (e, r) = (at(exact.outcome), at(rapier.outcome));
    assert!(e >= q && e <= 1.03 * q, "exact {e} vs quasi-static {q}");
    assert!((r / q - 1.0).abs() <= 0.03, "rapier {r} vs quasi-static {q}");
    let hinges: Vec<(&str, &str)> = s
        .quasi_static
        .mechanism
        .iter()
        .filter(|j| j.state == JointState::Hinging)
        .map(|j| (j.a.as_str(), j.b.as_str()))
        .collect();
    assert_eq!(hinges.len(), 4, "{:?}", s.quasi_static.mechanism);
    for h in &hinges {
        assert!(
            exact.mechanism.iter().any(|j| (j.a.as_str(), j.b.as_str()) == *h && j.state == JointState::Hinging),
            "{h:?} hinges in the exact engine too: {:?}",
            exact.mechanism
        );
    }
    // From a quarter of the path on, stage by stage against the exact engine's nearest stage.
    let mut compared = 0;
    for q in s.quasi_static.stages.iter().filter(|st| st.fraction >= 0.25) {
        let near = exact
            .stages
            .iter()
            .min_by(|a, b| (a.fraction - q.fraction).abs().total_cmp(&(b.fraction - q.fraction).abs()))
            .unwrap();
        let (tq, te) = (q.reactions[0][0].abs(), near.reactions[0][0].abs());
        assert!(
            (te / tq - 1.0).abs() < 0.01,
            "thrust {te} N (exact, at {}) vs {tq} N (at {})",
            near.fraction,
            q.fraction
        );
        compared += 1;
    }
    assert!(compared >= 3, "{compared} stages compared");
}

/// Invariant: once the right pier has settled, the lintel hinges on the left pier's inner edge
/// (x = 0.5) and rests on the right pier by its end (x = 3): turned by θ, the moment about the
/// hinge puts (1.0 cos θ + 0.15 sin θ) / (2.5 cos θ) of its weight W on the settling pier (0.4
/// untilted, 0.4024 at the end). Every run's reaction on that pier at the end of the path is
/// that share of W downwards — the quasi-static run and the exact engine within 1e-3 of it,
/// rapier (soft contacts, read from its contact impulses) within 5 %. (The horizontal part is
/// not asserted: friction at the two contacts can hold any self-balanced pair.)
#[test]
fn a_settling_pier_carries_its_share_in_every_run() {
    let scene = lintel();
    let analysis = run(&scene, &AnalysisSettings::default());
    let w = analysis.assembly.blocks[2].mass() * 9.81;
    let settle_right = Movement { block: "right".into(), translation: [0.0, 0.0, -0.1], rotation: [0.0; 3] };
    let s = settle(&analysis, &[settle_right], &SettleSettings { increments: 20, ..Default::default() }).unwrap();
    for (run, tol) in [(&s.quasi_static, 1e-3), (s.exact.as_ref().unwrap(), 1e-3), (s.rapier.as_ref().unwrap(), 0.05)] {
        assert_eq!(run.outcome, Outcome::Stands, "{}", run.method);
        let last = run.stages.last().unwrap();
        // Turned by θ about the hinge, the centroid's arm is 1.0 cos θ + 0.15 sin θ, the end's 2.5 cos θ.
        let theta = (0.1 * last.fraction / 2.5f64).atan();
        let share = (theta.cos() + 0.15 * theta.sin()) / (2.5 * theta.cos());
        let r = last.reactions[0];
        assert!((r[2] / w + share).abs() < tol * share, "{}: vertical {} W, {share} expected", run.method, r[2] / w);
    }
}

/// Invariant: `settle_with_progress` reports the three runs in the report's order, each from
/// 0 to 1 of the path and never going back, the quasi-static run at each of its stages; and it
/// only listens: the report is `settle`'s, byte for byte.
#[test]
fn a_settlement_reports_each_run_s_progress_along_the_path() {
    let scene = lintel();
    let analysis = run(&scene, &AnalysisSettings::default());
    let settle_right = Movement { block: "right".into(), translation: [0.0, 0.0, -0.1], rotation: [0.0; 3] };
    let settings = SettleSettings { increments: 8, ..Default::default() };
    let heard = std::cell::RefCell::new(Vec::new());
    let s = settle_with_progress(&analysis, std::slice::from_ref(&settle_right), &settings, &|method, fraction| {
        heard.borrow_mut().push((method, fraction))
    })
    .unwrap();
    let heard = heard.into_inner();
    let mut methods: Vec<&str> = heard.iter().map(|h| h.0).collect();
    methods.dedup();
    assert_eq!(methods, [QUASI_STATIC, "exact", "rapier"]);
    for method in methods {
        let fractions: Vec<f64> = heard.iter().filter(|h| h.0 == method).map(|h| h.1).collect();
        assert_eq!((fractions[0], *fractions.last().unwrap()), (0.0, 1.0), "{method}: {fractions:?}");
        assert!(fractions.windows(2).all(|w| w[0] <= w[1]), "{method}: {fractions:?}");
    }
    for stage in &s.quasi_static.stages {
        assert!(heard.contains(&(QUASI_STATIC, stage.fraction)), "stage at {}", stage.fraction);
    }
    let quiet = settle(&analysis, &[settle_right], &settings).unwrap();
    assert_eq!(serde_json::to_string(&s).unwrap(), serde_json::to_string(&quiet).unwrap());
}

/// The least or the greatest horizontal thrust a semicircular arch of `n` radial voussoirs
/// (centre-line radius `r`, thickness `t`, depth `d`, density `rho`, friction `mu`) can carry
/// by compression and friction alone — limit analysis in the arch's plane, written out here
/// independently of voussoir's statics: at each joint j (angle πj/n) a force F_j (on the block
/// above it) and a moment M_j about the joint's mid-point, its normal part N_j ≥ 0, its shear
/// within μ N_j, its eccentricity within the thickness (|M_j| ≤ N_j t/2); each voussoir in
/// equilibrium under its weight at its sector's centroid. One LP, on clarabel directly.
/// Returns the thrust and, per joint, |M_j| / (N_j t/2) (1 at a hinge).
fn arch_thrust_lp(n: usize, r: f64, t: f64, d: f64, rho: f64, mu: f64, least: bool) -> (f64, Vec<f64>) {
    use clarabel::algebra::CscMatrix;
    use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};
    use std::f64::consts::PI;
    let (ri, ro) = (r - t / 2.0, r + t / 2.0);
    let delta = PI / n as f64;
    // A sector's weight, and its centroid's radius (annular sector of half-angle δ/2).
    let weight = rho * 9.81 * d * 0.5 * (ro * ro - ri * ri) * delta;
    let rc = 2.0 / 3.0 * (ro.powi(3) - ri.powi(3)) / (ro * ro - ri * ri) * (delta / 2.0).sin() / (delta / 2.0);
    let var = |j: usize, k: usize| 3 * j + k; // Fx, Fz, M of joint j
    let (mut rows, mut cols, mut vals) = (vec![], vec![], vec![]);
    let mut b = vec![];
    let mut push = |row: usize, col: usize, v: f64| {
        rows.push(row);
        cols.push(col);
        vals.push(v);
    };
    // Equilibrium of voussoir i between joints i (below) and i + 1 (above); moments about the
    // origin, 2-D cross product p × F = p_x F_z − p_z F_x.
    for i in 0..n {
        let mid = |j: usize| (r * (delta * j as f64).cos(), r * (delta * j as f64).sin());
        let ((x0, z0), (x1, z1)) = (mid(i), mid(i + 1));
        let gx = rc * (delta * (i as f64 + 0.5)).cos();
        for (sign, j, x, z) in [(1.0, i, x0, z0), (-1.0, i + 1, x1, z1)] {
            push(3 * i, var(j, 0), sign);
            push(3 * i + 1, var(j, 1), sign);
            push(3 * i + 2, var(j, 0), -sign * z);
            push(3 * i + 2, var(j, 1), sign * x);
            push(3 * i + 2, var(j, 2), sign);
        }
        b.extend([0.0, weight, gx * weight]);
    }
    // Per joint: −N ≤ 0, ±V − μ N ≤ 0, ±M − (t/2) N ≤ 0.
    let equalities = b.len();
    for j in 0..=n {
        let a = delta * j as f64;
        let (nx, nz) = (-a.sin(), a.cos());
        let (vx, vz) = (a.cos(), a.sin());
        let row = equalities + 5 * j;
        push(row, var(j, 0), -nx);
        push(row, var(j, 1), -nz);
        for (k, s) in [(1, 1.0), (2, -1.0)] {
            push(row + k, var(j, 0), s * vx - mu * nx);
            push(row + k, var(j, 1), s * vz - mu * nz);
        }
        for (k, s) in [(3, 1.0), (4, -1.0)] {
            push(row + k, var(j, 2), s);
            push(row + k, var(j, 0), -t / 2.0 * nx);
            push(row + k, var(j, 1), -t / 2.0 * nz);
        }
        b.extend([0.0; 5]);
    }
    let nvar = 3 * (n + 1);
    let a = CscMatrix::new_from_triplets(b.len(), nvar, rows, cols, vals);
    let p = CscMatrix::zeros((nvar, nvar));
    // The thrust is −F_x at joint 0 (the right springer pushes the arch inwards).
    let mut q = vec![0.0; nvar];
    q[var(0, 0)] = if least { -1.0 } else { 1.0 };
    let cones = [SupportedConeT::ZeroConeT(equalities), SupportedConeT::NonnegativeConeT(5 * (n + 1))];
    let settings = DefaultSettings { verbose: false, tol_gap_abs: 1e-12, tol_gap_rel: 1e-12, ..Default::default() };
    let mut solver = DefaultSolver::new(&p, &q, &a, &b, &cones, settings).unwrap();
    solver.solve();
    assert_eq!(solver.solution.status, SolverStatus::Solved);
    let x = &solver.solution.x;
    let use_of_thickness = (0..=n)
        .map(|j| {
            let a = delta * j as f64;
            let normal = -a.sin() * x[var(j, 0)] + a.cos() * x[var(j, 1)];
            x[var(j, 2)].abs() / (normal * t / 2.0)
        })
        .collect();
    (-x[var(0, 0)], use_of_thickness)
}

/// Invariant: an arch whose springers start to spread drops to the least thrust the statics
/// allow. For the 9-voussoir arch (t/R 0.15), the limit-analysis LP above gives the range of
/// thrusts [H_min, H_max] by compression and friction; voussoir's own statics answer at rest
/// lies within it (1e-6), and at the first increment of a spread (each springer out by 1.5 mm,
/// the span 0.15 % wider) the quasi-static run carries H_min of the undeformed arch within
/// 0.3 % (measured +0.08 %: the wider span's own least thrust), on both springers, hinging on
/// exactly the joints where the LP's least-thrust line touches the intrados or extrados,
/// which lie symmetrically about the crown.
#[test]
fn a_spreading_arch_drops_to_its_least_thrust() {
    let (n, t) = (9, 0.15);
    let scene = voussoir::model::builtin(&format!("arch?n={n}&t={t}")).unwrap();
    let (rho, mu) = (scene.material.density, scene.material.friction);
    let (h_min, hinges_lp) = arch_thrust_lp(n, 1.0, t, 0.5, rho, mu, true);
    let (h_max, _) = arch_thrust_lp(n, 1.0, t, 0.5, rho, mu, false);
    assert!(h_min > 0.0 && h_max > 1.2 * h_min, "range [{h_min}, {h_max}]");

    let analysis = run(&scene, &AnalysisSettings::default());
    // The statics' thrust at rest: the x force the right springer puts on the arch, inwards.
    let at_rest: f64 = analysis
        .statics
        .interfaces
        .iter()
        .map(|f| match (f.a.as_str(), f.b.as_str()) {
            ("springer_right", _) => -f.resultant[0],
            (_, "springer_right") => f.resultant[0],
            _ => 0.0,
        })
        .sum();
    assert!(at_rest >= h_min * (1.0 - 1e-6) && at_rest <= h_max * (1.0 + 1e-6), "{h_min} ≤ {at_rest} ≤ {h_max}");

    let spread = |name: &str, dx: f64| Movement { block: name.into(), translation: [dx, 0.0, 0.0], rotation: [0.0; 3] };
    let moves = [spread("springer_left", -0.0015), spread("springer_right", 0.0015)];
    let settings = SettleSettings { increments: 1, engines: false, ..Default::default() };
    let s = settle(&analysis, &moves, &settings).unwrap();
    let first = s.quasi_static.stages.first().expect("a stage");
    for reaction in &first.reactions {
        let h = reaction[0].abs();
        println!("thrust {h} N: {:+.3e} of the least", h / h_min - 1.0);
        assert!((h / h_min - 1.0).abs() < 3e-3, "thrust {h} N vs the least {h_min} N (at rest {at_rest} N)");
    }
    // Joint j lies between v(j−1) and v(j); joint 0 on the right springer, joint n on the left.
    let joint = |a: &str, b: &str| match (a, b) {
        ("springer_right", _) | (_, "springer_right") => 0,
        ("springer_left", _) | (_, "springer_left") => n,
        _ => [a, b].iter().map(|v| v[1..].parse::<usize>().unwrap()).max().unwrap(),
    };
    let mut hinging: Vec<usize> =
        first.joints.iter().filter(|j| j.state == JointState::Hinging).map(|j| joint(&j.a, &j.b)).collect();
    hinging.sort();
    let touching: Vec<usize> = (0..=n).filter(|&j| hinges_lp[j] > 1.0 - 1e-6).collect();
    println!(
        "LP: thrust [{h_min}, {h_max}], at rest {at_rest}; hinges at joints {touching:?}; quasi-static: {hinging:?}"
    );
    assert_eq!(hinging, touching, "the quasi-static hinges are the least-thrust line's");
    assert!(touching.iter().all(|&j| touching.contains(&(n - j))), "symmetric: {touching:?}");
    assert!(touching.iter().all(|&j| touching.contains(&(n - j))), "symmetric: {touching:?}");
}

/// A flat (jack) arch: two 1 × 0.5 × 0.3 m voussoirs side by side between two abutments, held
/// only by friction on the vertical abutment joints (μ 0.8: the statics' friction use 0.75).
fn flat_arch() -> Scene {
    let mut scene = Scene::new(
        "flat arch",
        vec![
            cuboid("left", [-0.5, 0.0, 0.0], [0.0, 0.5, 0.6]).support(true),
            cuboid("right", [2.0, 0.0, 0.0], [2.5, 0.5, 0.6]).support(true),
            cuboid("a", [0.0, 0.0, 0.3], [1.0, 0.5, 0.6]),
            cuboid("b", [1.0, 0.0, 0.3], [2.0, 0.5, 0.6]),
        ],
    );
    scene.material.friction = 0.8;
    scene
}

/// Invariant (rigid-block kinematics): as the abutments spread, each half (w 1, d 0.3) turns by
/// θ about its abutment joint's bottom edge, touching the other at the crown's top edge:
/// w cos θ + d sin θ = w + δ/2 for a spread δ. The crown contact sinks to the hinges' level at
/// tan θ = d/w, the largest spread the halves can bridge: δ* = 2(√(w² + d²) − w) = 0.0881 m,
/// 44.0 % of a path of 0.1 m per abutment. The quasi-static run collapses there within 0.5 %,
/// the exact engine (supports moved in real time) within 2 %; from 2 % of the path (past the
/// joints' tolerance) to the collapse both hinge at the three joints and at no other (no joint
/// read as sliding: a stage's slips are those since the last stage), and up to 80 % of it the
/// thrust is the rotated halves' moment balance about the hinge,
/// H = P (w cos θ + d sin θ) / (2 (d cos θ − w sin θ)) with P a half's weight — the
/// quasi-static run's within 0.1 %, the exact engine's within 4 % (its halves turn ever faster,
/// first as the supports start, then as the crown nears the hinges' level, and that
/// acceleration relieves the thrust: 0.97–0.99 of it). The thrust grows: friction holds ever
/// more surely. The start stands by the statics (no abutment
/// joint "sliding" at 0 %: the halves could slide down their vertical joints with no force on
/// them, but an equilibrium holds them where they are).
#[test]
fn a_flat_arch_on_spreading_abutments_turns_about_its_hinges_until_they_line_up() {
    let analysis = run(&flat_arch(), &AnalysisSettings::default());
    assert!(analysis.statics.stands);
    let (w, d, dx) = (1.0f64, 0.3f64, 0.1);
    let half = analysis.assembly.blocks[2].mass() * 9.81;
    let spread = |name: &str, x: f64| Movement { block: name.into(), translation: [x, 0.0, 0.0], rotation: [0.0; 3] };
    let s = settle(&analysis, &[spread("left", -dx), spread("right", dx)], &SettleSettings::default()).unwrap();
    let expected = ((w * w + d * d).sqrt() - w) / dx;
    let at = |run: &voussoir::studies::settlement::Run| match run.outcome {
        Outcome::Collapses { fraction, .. } => fraction,
        ref o => panic!("{}: {o:?}", run.method),
    };
    let (q, e) = (at(&s.quasi_static), at(s.exact.as_ref().unwrap()));
    assert_close(q, expected, 0.005 * expected, "quasi-static spread at collapse (fraction of the path)");
    assert_close(e, expected, 0.02 * expected, "exact engine's spread at collapse (fraction of the path)");
    for (run, tol) in [(&s.quasi_static, 0.001), (s.exact.as_ref().unwrap(), 0.04)] {
        let turning: Vec<_> = run.stages.iter().filter(|st| st.fraction > 0.02).collect();
        assert!(turning.len() >= 20, "{}: {} stages", run.method, turning.len());
        for st in &turning {
            let hinging = st.joints.iter().filter(|j| j.state == JointState::Hinging).count();
            assert_eq!((hinging, st.joints.len()), (3, 3), "{} at {}: {:?}", run.method, st.fraction, st.joints);
        }
        for st in turning.iter().filter(|st| st.fraction < 0.8 * expected) {
            let theta = st.rotation.to_radians();
            let thrust = 0.5 * half * (w * theta.cos() + d * theta.sin()) / (d * theta.cos() - w * theta.sin());
            let h = -st.reactions[0][0];
            assert_close(h, thrust, tol * thrust, &format!("{} thrust at {}", run.method, st.fraction));
        }
    }
}
