//! Invariant: the divergence-theorem mass properties equal the closed forms for boxes,
//! tetrahedra, a non-convex L prism and a mesh with polygon faces (1e-12 relative).

use nalgebra::Matrix3;
use voussoir::geometry::{MassProperties, Mesh, Point3};

fn close(a: f64, b: f64, what: &str) {
    assert!((a - b).abs() <= 1e-12 * b.abs().max(1.0), "{what}: {a} vs {b}");
}

fn close_m(a: &Matrix3<f64>, b: &Matrix3<f64>, what: &str) {
    let scale = b.abs().max().max(1e-300);
    assert!((a - b).abs().max() <= 1e-12 * scale, "{what}:\n{a}\nvs\n{b}");
}

#[test]
fn box_volume_centroid_inertia() {
    let (a, b, c) = (2.0, 3.0, 5.0);
    let m = Mesh::cuboid(Point3::new(1.0, -2.0, 10.0), Point3::new(1.0 + a, 1.0, 15.0));
    let mp = MassProperties::of_mesh(&m);
    let v = a * b * c;
    close(mp.volume, v, "volume");
    assert!((mp.centroid - Point3::new(2.0, -0.5, 12.5)).norm() < 1e-12);
    let i = Matrix3::from_diagonal(&nalgebra::Vector3::new(
        v * (b * b + c * c) / 12.0,
        v * (a * a + c * c) / 12.0,
        v * (a * a + b * b) / 12.0,
    ));
    close_m(&mp.inertia, &i, "inertia");
}

#[test]
fn tetrahedron_far_from_origin() {
    // Corner tetrahedron with legs a, b, c: V = abc/6, centroid at (a, b, c)/4.
    let (a, b, c) = (1.0, 2.0, 3.0);
    let o = nalgebra::Vector3::new(1e3, -2e3, 5e2);
    let p = |x: f64, y: f64, z: f64| Point3::new(x, y, z) + o;
    let m = Mesh::new(
        vec![p(0., 0., 0.), p(a, 0., 0.), p(0., b, 0.), p(0., 0., c)],
        vec![vec![0, 2, 1], vec![0, 1, 3], vec![0, 3, 2], vec![1, 2, 3]],
    );
    let mp = MassProperties::of_mesh(&m);
    close(mp.volume, a * b * c / 6.0, "volume");
    assert!((mp.centroid - (Point3::new(a, b, c) / 4.0 + o)).norm() < 1e-9);
    // Closed form (density 1) about the centroid: I_xx = V/80 (3(b² + c²)) ... from the
    // covariance C = V/80 diag-form: C_ij = V/20 (Σ_k v_ki v_kj + s_i s_j) − V c_i c_j.
    let v = a * b * c / 6.0;
    let verts = [[0.0, 0.0, 0.0], [a, 0.0, 0.0], [0.0, b, 0.0], [0.0, 0.0, c]];
    let cen = [a / 4.0, b / 4.0, c / 4.0];
    let mut cov = Matrix3::zeros();
    for i in 0..3 {
        for j in 0..3 {
            let s: f64 = verts.iter().map(|q| q[i] * q[j]).sum::<f64>()
                + verts.iter().map(|q| q[i]).sum::<f64>() * verts.iter().map(|q| q[j]).sum::<f64>();
            cov[(i, j)] = v / 20.0 * s - v * cen[i] * cen[j];
        }
    }
    let inertia = Matrix3::identity() * cov.trace() - cov;
    // Hand value: I_xx about the centroid of this tetrahedron = 3V(b² + c²)/80.
    close(inertia[(0, 0)], 3.0 * v * (b * b + c * c) / 80.0, "closed-form I_xx");
    assert!((mp.inertia - inertia).abs().max() <= 1e-9 * inertia.abs().max(), "{}\n{}", mp.inertia, inertia);
}

#[test]
fn non_convex_l_prism() {
    // L = 2×1 rectangle plus a 1×1 square on its left half, extruded by h.
    let l = [[0., 0.], [2., 0.], [2., 1.], [1., 1.], [1., 2.], [0., 2.]];
    let h = 0.5;
    let mp = MassProperties::of_mesh(&Mesh::extrude_z(&l, 0.0, h));
    close(mp.volume, 3.0 * h, "volume");
    assert!((mp.centroid - Point3::new(5.0 / 6.0, 5.0 / 6.0, h / 2.0)).norm() < 1e-12);
    // I_zz by parallel axes: rectangle 2×1 at (1, .5) and square at (.5, 1.5), per unit h.
    let parts = [(2.0, 2.0, 1.0, 1.0, 0.5), (1.0, 1.0, 1.0, 0.5, 1.5)];
    let (cx, cy) = (5.0 / 6.0, 5.0 / 6.0);
    let izz: f64 = parts
        .iter()
        .map(|&(area, w, d, x, y)| {
            h * (area * (w * w + d * d) / 12.0 + area * ((x - cx) * (x - cx) + (y - cy) * (y - cy)))
        })
        .sum();
    close(mp.inertia[(2, 2)], izz, "I_zz");
}

#[test]
fn polygon_faces_hexagonal_prism() {
    // Regular hexagon of circumradius 1 (polygon caps, 6 vertices each), height 2.
    let hex: Vec<[f64; 2]> = (0..6)
        .map(|k| {
            let t = std::f64::consts::PI / 3.0 * k as f64;
            [t.cos(), t.sin()]
        })
        .collect();
    let m = Mesh::extrude_z(&hex, 1.0, 3.0);
    assert_eq!(m.faces[0].len(), 6);
    let mp = MassProperties::of_mesh(&m);
    let area = 3.0 * 3f64.sqrt() / 2.0;
    close(mp.volume, 2.0 * area, "volume");
    assert!((mp.centroid - Point3::new(0.0, 0.0, 2.0)).norm() < 1e-12);
    // Hexagon polar moment: 5√3/8 · s⁴ (s = 1) → I_zz = h · 5√3/8.
    close(mp.inertia[(2, 2)], 2.0 * 5.0 * 3f64.sqrt() / 8.0, "I_zz");
}

#[test]
fn inverted_mesh_has_negative_volume() {
    let mut m = Mesh::cuboid(Point3::origin(), Point3::new(1.0, 1.0, 1.0));
    m.faces.iter_mut().for_each(|f| f.reverse());
    close(MassProperties::of_mesh(&m).volume, -1.0, "signed volume");
}
