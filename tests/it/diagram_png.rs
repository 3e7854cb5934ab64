//! Invariant: the offscreen diagram pictures show what the statics say — blue interface pixels
//! and no red for a standing design in compression mode, red where tension is needed, yellow /
//! orange / red friction by utilisation, dark green arrows in vectors mode — asserted on the pixels of
//! the PNG read back, left of the text panel (whose legend shows every colour).

use voussoir::model::builtin;
use voussoir::pipeline::{AnalysisSettings, analyze};
use voussoir::viz::DiagramMode;
use voussoir::viz::plot::{DiagramPicture, write_diagram};

/// Pixel counts by kind in the drawing area (the panel on the right excluded).
#[derive(Debug, Default)]
struct Counts {
    blue: usize,
    red: usize,
    yellow: usize,
    orange: usize,
    arrow: usize,
}

fn render(spec: &str, mode: DiagramMode) -> Counts {
    let scene = if spec == "default" {
        voussoir::io::scene_json::scene_from_str(std::path::Path::new("default.json"), voussoir::cli::DEFAULT_SCENE)
            .unwrap()
    } else {
        builtin(spec).unwrap()
    };
    let a = analyze(&scene, &AnalysisSettings::default()).unwrap();
    let dir = crate::common::scratch("diagram");
    let path = dir.join(format!("{}.png", spec.replace(['?', '&', '='], "_")));
    let picture = DiagramPicture::new(&a, mode);
    write_diagram(&picture, &path).unwrap();
    let img = image::open(&path).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), picture.size);
    let mut c = Counts::default();
    for (x, _, p) in img.enumerate_pixels() {
        if x >= picture.size.0 - 330 {
            continue;
        }
        let [r, g, b] = p.0.map(i32::from);
        if b > r + 60 && b > g + 30 {
            c.blue += 1;
        }
        // Red and the light reds of the tension gradient (the stone's beige is r − b ≈ 23).
        if r > b + 50 && r > g + 50 {
            c.red += 1;
        }
        // Yellow (255, 243, 89) and the oranges (255, 179, 63) … (237, 115, 0): the linear
        // colours of viz::colors encoded as sRGB, as the viewer shows them.
        if r > 230 && g > 210 && b < 110 {
            c.yellow += 1;
        }
        if r > 220 && (90..190).contains(&g) && b < 80 {
            c.orange += 1;
        }
        // The arrows' dark green (0, 120, 70): no diagram colour is green.
        if g > r + 60 && g > b + 30 {
            c.arrow += 1;
        }
    }
    c
}

#[test]
fn compression_mode_blue_when_standing_red_when_tension_is_needed() {
    let standing = render("default", DiagramMode::Compression);
    assert!(standing.blue > 2000 && standing.red == 0, "{standing:?}");
    let failing = render("harmonic?n=4&s=1.3", DiagramMode::Compression);
    assert!(failing.red > 200, "{failing:?}");
}

#[test]
fn friction_mode_yellow_orange_red_by_utilisation() {
    // μ = tan 40°: utilisation tan θ / μ = 0.21 (10°), 0.83 (35°), 1.19 (45°, exceeded).
    let low = render("slope?angle=10&b=2&h=0.5", DiagramMode::Friction { threshold: 0.8 });
    assert!(low.yellow > 2000 && low.orange == 0 && low.red == 0, "{low:?}");
    let near = render("slope?angle=35&b=2&h=0.5", DiagramMode::Friction { threshold: 0.5 });
    // Orange counts as "red" under the loose rule, so compare with the strict red of 45°.
    assert!(near.orange > 2000, "{near:?}");
    let over = render("slope?angle=45&b=2&h=0.5", DiagramMode::Friction { threshold: 0.5 });
    assert!(over.red > 2000 && over.orange < near.orange / 10, "{over:?} vs {near:?}");
}

#[test]
fn vectors_mode_draws_arrows() {
    let with = render("arch?n=9&t=0.15", DiagramMode::Vectors);
    let without = render("arch?n=9&t=0.15", DiagramMode::Compression);
    assert!(with.arrow > 500 && without.arrow == 0, "{with:?} vs {without:?}");
}
