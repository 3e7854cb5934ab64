//! The seed paper's case studies as designs with cut histories (our own models: letters drawn
//! on a grid of `U` = 0.1 m, `T` = 0.1 m thick along y, standing on the ground z = 0; density
//! 600 kg/m³ and μ = tan 40° as in the paper). `cargo run --example make_case_studies`
//! writes them to `assets/cases/`; `tests/it/case_studies.rs` asserts the paper's outcomes.
//!
//! Letters are drawn in the xz-plane (x right, z up) in grid units and swept along +y.

use voussoir::geometry::{Mesh, Point3, Vector3};
use voussoir::model::{Block, Cut, Scene};

/// Grid unit and letter thickness (m).
pub const U: f64 = 0.1;
pub const T: f64 = 0.1;

fn at(x0: f64, outline: &[[f64; 2]]) -> Vec<Point3> {
    outline.iter().map(|p| Point3::new((x0 + p[0]) * U, 0.0, p[1] * U)).collect()
}

/// A letter without a counter: the outline (grid units) shifted by `x0`, swept along y.
fn letter(name: &str, x0: f64, outline: &[[f64; 2]]) -> Block {
    Block::new(name, Mesh::prism(&at(x0, outline), Vector3::new(0.0, T, 0.0)))
}

/// A letter with a counter (D, a loop): outer and inner outlines.
fn ring(name: &str, x0: f64, outer: &[[f64; 2]], inner: &[[f64; 2]]) -> Block {
    Block::new(name, Mesh::prism_with_hole(&at(x0, outer), &at(x0, inner), Vector3::new(0.0, T, 0.0)))
}

fn design(name: &str, blocks: Vec<Block>, cuts: Vec<Cut>) -> Scene {
    let mut s = Scene::new(name, blocks);
    s.ground = true;
    s.cuts = cuts;
    s
}

/// Horizontal plane z = h (grid units).
fn level(h: f64) -> Cut {
    Cut::plane([0.0, 0.0, h * U], [0.0, 0.0, 1.0])
}

/// Plane through height `h` at x = `x` (grid units), tilted by `deg` in the xz-plane.
fn tilted_xz(x: f64, h: f64, deg: f64) -> Cut {
    let a = deg.to_radians();
    Cut::plane([x * U, 0.0, h * U], [a.sin(), 0.0, a.cos()])
}

/// Plane through height `h` (grid units) tilted by `deg` about the x-axis (across the letter's
/// thickness).
fn tilted_yz(h: f64, deg: f64) -> Cut {
    let a = deg.to_radians();
    Cut::plane([0.0, T / 2.0, h * U], [0.0, -a.sin(), a.cos()])
}

/// "S" and "C" joined by a bridge, one solid; the S raised by `lift` (grid units) above the
/// ground.
fn sc(lift: f64) -> Block {
    let l = lift;
    let outline = [
        [0.0, l],
        [3.0, l],
        [3.0, 2.0 + l],
        [4.0, 2.0 + l],
        [4.0, 0.0],
        [7.0, 0.0],
        [7.0, 1.0],
        [5.0, 1.0],
        [5.0, 4.0],
        [7.0, 4.0],
        [7.0, 5.0],
        [4.0, 5.0],
        [4.0, 3.0 + l],
        [1.0, 3.0 + l],
        [1.0, 4.0 + l],
        [3.0, 4.0 + l],
        [3.0, 5.0 + l],
        [0.0, 5.0 + l],
        [0.0, 2.0 + l],
        [2.0, 2.0 + l],
        [2.0, 1.0 + l],
        [0.0, 1.0 + l],
    ];
    letter("SC", 0.0, &outline)
}

/// Fig. 3: "SC" as one solid. (a) the S hangs half a unit above the ground: the solid stands
/// on the C's foot only, its centre of mass outside it, so it needs tension at the support;
/// (b) a support block under the S: stands; (c) the S lowered onto the ground: stands.
pub fn fig3() -> [Scene; 3] {
    let pedestal = Block::new("pedestal", Mesh::cuboid(Point3::new(0.0, 0.0, 0.0), Point3::new(3.0 * U, T, 0.5 * U)))
        .support(true);
    [
        design("fig3a: SC on the C's foot", vec![sc(0.5)], vec![]),
        design("fig3b: SC with an added support under the S", vec![sc(0.5), pedestal], vec![]),
        design("fig3c: SC with the S on the ground", vec![sc(0.0)], vec![]),
    ]
}

/// An "M" (grid units, 5 tall): a straight right leg, a left leg flared at its foot by
/// `flare`, and a V between them reaching down to z = 1.5.
fn m_letter(x0: f64, flare: f64) -> Block {
    letter("M", x0, &m_outline(flare, 0.0))
}

/// The M's outline (grid units): left foot flared by `flare`, right leg starting at height
/// `right_foot` (0: on the ground).
fn m_outline(flare: f64, right_foot: f64) -> [[f64; 2]; 12] {
    [
        [-flare, 0.0],
        [1.0, 0.0],
        [1.0, 3.0],
        [2.5, 1.5],
        [4.0, 3.0],
        [4.0, right_foot],
        [5.0, right_foot],
        [5.0, 5.0],
        [4.0, 5.0],
        [2.5, 3.5],
        [1.0, 5.0],
        [0.0, 5.0],
    ]
}

/// The S's outline (grid units), its lower bar drawn out to the left from x = `bar_from`.
fn s_outline(bar_from: f64) -> [[f64; 2]; 12] {
    [
        [bar_from, 0.0],
        [3.0, 0.0],
        [3.0, 3.0],
        [1.0, 3.0],
        [1.0, 4.0],
        [3.0, 4.0],
        [3.0, 5.0],
        [0.0, 5.0],
        [0.0, 2.0],
        [2.0, 2.0],
        [2.0, 1.0],
        [bar_from, 1.0],
    ]
}

/// Flare of the M's left foot (grid units) in figs. 4 and 5.
pub const M_FLARE: f64 = 1.0;

/// Fig. 4: "M" cut into a top and a bottom piece at heights `h` (grid units): (a) 2.0 cuts
/// through the V, leaving its tip hanging from the top piece: tension; (b) 1.2 and (c) 0.4
/// cut the legs only: stands, (c) with the more even distribution.
pub fn fig4() -> [Scene; 3] {
    [(2.0, 'a'), (1.2, 'b'), (0.4, 'c')]
        .map(|(h, k)| design(&format!("fig4{k}: M cut at z = {h} U"), vec![m_letter(0.0, M_FLARE)], vec![level(h)]))
}

/// Fig. 5: "M" cut at z = 0.8 U by a plane inclined across the thickness: (a) 50°, friction
/// exceeded (tan 50° > μ = tan 40°); (b) rotated to 30°, within the limit; (c) rotated to
/// 10°, the lowest friction.
pub fn fig5() -> [Scene; 3] {
    [(50.0, 'a'), (30.0, 'b'), (10.0, 'c')].map(|(deg, k)| {
        design(
            &format!("fig5{k}: M with a cut inclined {deg}°"),
            vec![m_letter(0.0, M_FLARE)],
            vec![tilted_yz(0.8, deg)],
        )
    })
}

/// Fig. 6: "DMSC" decomposed into many pieces by inclined and horizontal cuts (each letter's
/// cuts target it and its pieces).
pub fn fig6() -> Scene {
    let d = ring(
        "D",
        0.0,
        &[[0.0, 0.0], [2.0, 0.0], [3.0, 1.0], [3.0, 4.0], [2.0, 5.0], [0.0, 5.0]],
        &[[1.0, 1.0], [1.6, 1.0], [2.0, 1.4], [2.0, 3.6], [1.6, 4.0], [1.0, 4.0]],
    );
    let m = m_letter(4.0, 0.0);
    let s = letter("S", 10.0, &s_outline(0.0));
    let c = letter(
        "C",
        14.0,
        &[[0.0, 0.0], [3.0, 0.0], [3.0, 1.0], [1.0, 1.0], [1.0, 4.0], [2.0, 4.0], [2.0, 5.0], [0.0, 5.0]],
    );
    let cuts = vec![
        tilted_xz(1.5, 2.5, 15.0).on("D"),
        level(0.8).on("M"),
        level(2.5).on("S"),
        tilted_xz(10.5, 4.5, 10.0).on("S.2+"),
        tilted_xz(14.5, 2.5, 15.0).on("C"),
        Cut::plane([1.5 * U, 0.0, 0.0], [1.0, 0.0, 0.0]).on("D.0+"),
    ];
    design("fig6: DMSC in many pieces", vec![d, m, s, c], cuts)
}

/// Fig. 6 as the paper's sequence study: the same letters set as a ligature — the M's right
/// leg stops one unit above the ground and rests on the S's lower bar, drawn out under it — so
/// that, as the paper reports of its DMSC, "D" and "M" cannot stand alone: placed in the order
/// D, M, S, C (the scene's `order`), the M's upper piece tips over its left foot until the S
/// is there.
pub fn fig6_sequence() -> Scene {
    let mut scene = fig6();
    scene.name = "fig6 (sequence): DMSC with the M's right foot on the S".into();
    scene.blocks[1] = letter("M", 4.0, &m_outline(0.0, 1.0));
    scene.blocks[2] = letter("S", 10.0, &s_outline(-2.2));
    scene.order = ["D", "M", "S", "C"].map(String::from).to_vec();
    scene
}

/// Prism (along +y, thickness `T`) of a union of grid cells `[x0, z0, x1, z1]` (grid units)
/// whose corners lie on common grid lines: the cap is one quad per cell and the sides are
/// split at every grid line, so the mesh is closed however the cells touch (a loop's hole
/// edges may be collinear with its outline, which ear clipping cannot triangulate).
fn cells(name: &str, cells: &[[f64; 4]]) -> Block {
    let grid = |k: usize| {
        let mut v: Vec<f64> = cells.iter().flat_map(|c| [c[k], c[k + 2]]).collect();
        v.sort_by(f64::total_cmp);
        v.dedup();
        v
    };
    let (xs, zs) = (grid(0), grid(1));
    let at = |v: &[f64], x: f64| v.iter().position(|&g| g == x).expect("a grid line");
    let (nx, nz) = (xs.len(), zs.len());
    let mut filled = vec![false; nx * nz];
    for c in cells {
        for i in at(&xs, c[0])..at(&xs, c[2]) {
            for j in at(&zs, c[1])..at(&zs, c[3]) {
                filled[i * nz + j] = true;
            }
        }
    }
    let full = |i: isize, j: isize| {
        i >= 0 && j >= 0 && (i as usize) < nx - 1 && (j as usize) < nz - 1 && filled[i as usize * nz + j as usize]
    };
    let vid = |i: usize, j: usize, back: bool| (i * nz + j) * 2 + back as usize;
    let vertices: Vec<Point3> = (0..nx * nz * 2)
        .map(|k| Point3::new(xs[k / 2 / nz] * U, if k % 2 == 1 { T } else { 0.0 }, zs[k / 2 % nz] * U))
        .collect();
    let mut faces = vec![];
    for i in 0..nx - 1 {
        for j in 0..nz - 1 {
            if !full(i as isize, j as isize) {
                continue;
            }
            // Front cap (y = 0) faces −y, back cap +y; counter-clockwise seen from outside.
            faces.push(vec![vid(i, j, false), vid(i + 1, j, false), vid(i + 1, j + 1, false), vid(i, j + 1, false)]);
            faces.push(vec![vid(i, j, true), vid(i, j + 1, true), vid(i + 1, j + 1, true), vid(i + 1, j, true)]);
            let (ii, jj) = (i as isize, j as isize);
            let mut side = |a: (usize, usize), b: (usize, usize)| {
                faces.push(vec![vid(a.0, a.1, false), vid(a.0, a.1, true), vid(b.0, b.1, true), vid(b.0, b.1, false)])
            };
            if !full(ii, jj - 1) {
                side((i + 1, j), (i, j)); // bottom
            }
            if !full(ii, jj + 1) {
                side((i, j + 1), (i + 1, j + 1)); // top
            }
            if !full(ii - 1, jj) {
                side((i, j), (i, j + 1)); // left
            }
            if !full(ii + 1, jj) {
                side((i + 1, j + 1), (i + 1, j)); // right
            }
        }
    }
    // Drop the vertices no face uses, keeping the order.
    let mut used = vec![usize::MAX; vertices.len()];
    let mut kept = vec![];
    for f in &mut faces {
        for v in f.iter_mut() {
            if used[*v] == usize::MAX {
                used[*v] = kept.len();
                kept.push(vertices[*v]);
            }
            *v = used[*v];
        }
    }
    let mut mesh = Mesh::new(kept, faces);
    if voussoir::geometry::MassProperties::of_mesh(&mesh).volume < 0.0 {
        mesh.faces.iter_mut().for_each(|f| f.reverse());
    }
    Block::new(name, mesh)
}

/// A square loop on feet: bars kinked out one unit past the legs at top and bottom.
fn kinked_loop() -> Block {
    cells("loop", &[[-1.0, 0.0, 5.0, 1.0], [0.0, 1.0, 1.0, 3.0], [3.0, 1.0, 4.0, 3.0], [-1.0, 3.0, 5.0, 4.0]])
}

/// Fig. 7: a square loop whose top and bottom bars kink out one unit past the legs (so each
/// corner piece balances over its leg) standing on the ground: (a) uncut; (b) cut by two horizontal planes
/// through both legs (four cut interfaces); (c) plus a vertical cut splitting the two U pieces
/// into L pieces; (d) the two planes inclined 10° instead of horizontal.
pub fn fig7() -> [Scene; 4] {
    let vertical = Cut::plane([2.0 * U, 0.0, 0.0], [1.0, 0.0, 0.0]);
    [
        design("fig7a: loop, uncut", vec![kinked_loop()], vec![]),
        design("fig7b: loop, four horizontal cuts", vec![kinked_loop()], vec![level(1.6), level(2.4)]),
        design(
            "fig7c: loop, horizontal and vertical cuts",
            vec![kinked_loop()],
            vec![level(1.6), level(2.4), vertical],
        ),
        design(
            "fig7d: loop, inclined cuts",
            vec![kinked_loop()],
            vec![tilted_xz(2.0, 1.6, 10.0), tilted_xz(2.0, 2.4, 10.0)],
        ),
    ]
}

/// An open-bottom box: outer half-width `a`, height `h`, walls and lid `w` thick (m).
fn open_box(a: f64, h: f64, w: f64) -> Block {
    let (b, c) = (a - w, h - w);
    let p = Point3::new;
    let vertices = vec![
        p(-a, -a, 0.0),
        p(a, -a, 0.0),
        p(a, a, 0.0),
        p(-a, a, 0.0),
        p(-a, -a, h),
        p(a, -a, h),
        p(a, a, h),
        p(-a, a, h),
        p(-b, -b, 0.0),
        p(b, -b, 0.0),
        p(b, b, 0.0),
        p(-b, b, 0.0),
        p(-b, -b, c),
        p(b, -b, c),
        p(b, b, c),
        p(-b, b, c),
    ];
    let mut faces = vec![vec![4, 5, 6, 7], vec![12, 15, 14, 13]];
    for i in 0..4 {
        let j = (i + 1) % 4;
        faces.push(vec![i, j, 4 + j, 4 + i]); // outer wall
        faces.push(vec![8 + j, 8 + i, 12 + i, 12 + j]); // inner wall
        faces.push(vec![j, i, 8 + i, 8 + j]); // wall foot
    }
    Block::new("box", Mesh::new(vertices, faces))
}

/// The pattern of fig. 9 on the lid z = 0.5 of a 1 m box: three lines across, then staggered
/// joints between them; the apex 1 m below the ground.
fn box_pattern() -> Cut {
    let z = 0.5;
    let mut segments = vec![];
    for x in [-0.25, 0.0, 0.25] {
        segments.push([[x, -0.5, z], [x, 0.5, z]]);
    }
    for (x0, x1, ys) in [
        (-0.5, -0.25, &[-0.2, 0.2][..]),
        (-0.25, 0.0, &[0.0][..]),
        (0.0, 0.25, &[-0.2, 0.2][..]),
        (0.25, 0.5, &[0.0][..]),
    ] {
        for &y in ys {
            segments.push([[x0, y, z], [x1, y, z]]);
        }
    }
    Cut::pattern([0.0, 0.0, -1.0], segments)
}

/// Fig. 9: (a) an open-bottom box cut by a pattern converging on an apex below it: stands;
/// (b) with two pieces of the lid removed: still stands.
pub fn fig9() -> [Scene; 2] {
    let a = design("fig9a: box with a pattern cut to an apex", vec![open_box(0.5, 0.5, 0.08)], vec![box_pattern()]);
    let mut b = design("fig9b: the box with two lid pieces removed", a.blocks.clone(), a.cuts.clone());
    b.removed = FIG9B_REMOVED.map(String::from).to_vec();
    [a, b]
}

/// Names of the pieces removed in fig. 9b (they exist after the pattern cut).
pub const FIG9B_REMOVED: [&str; 2] = ["box.0/0-.0/1-.0/2+.0/6+.0/7-", "box.0/0-.0/1+.0/5+"];

/// Every case with the file stem it is stored under in `assets/cases/`.
pub fn all() -> Vec<(String, Scene)> {
    let mut out = vec![];
    for (k, s) in ["a", "b", "c"].iter().zip(fig3()) {
        out.push((format!("fig3{k}_sc"), s));
    }
    for (k, s) in ["a", "b", "c"].iter().zip(fig4()) {
        out.push((format!("fig4{k}_m_cut"), s));
    }
    for (k, s) in ["a", "b", "c"].iter().zip(fig5()) {
        out.push((format!("fig5{k}_m_inclined"), s));
    }
    out.push(("fig6_dmsc".into(), fig6()));
    out.push(("fig6_dmsc_sequence".into(), fig6_sequence()));
    for (k, s) in ["a", "b", "c", "d"].iter().zip(fig7()) {
        out.push((format!("fig7{k}_loop"), s));
    }
    for (k, s) in ["a", "b"].iter().zip(fig9()) {
        out.push((format!("fig9{k}_box"), s));
    }
    out
}
