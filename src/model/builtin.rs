//! Built-in parametric scenes, named like `arch?n=21&t=0.12` (the CLI takes
//! `builtin:arch?n=21&t=0.12`). All use the default material unless `density` / `mu` are given,
//! z up, metres. Every scene rests on support blocks (or the ground plane for the dome).
//!
//! | scene | parameters (defaults) |
//! |---|---|
//! | `stack` | `n` cubes (5) of edge `a` (1) on a support slab |
//! | `stacks` | `k` independent stacks (10) of `n` cubes (5) side by side on one slab |
//! | `harmonic` | `n` blocks (10) 1 × 1 × `h` (0.25), overhang scale `s` (1: the limit H_n/2) |
//! | `arch` | `n` voussoirs (21), centre-line radius `r` (1), thickness `t` (0.15), depth `d` (0.5) |
//! | `wall` | `courses` (10) × `bricks` (10), brick `l` × `d` × `h` (0.4 × 0.2 × 0.1), running bond |
//! | `slope` | block `b` × `h` (0.5 × 0.5) on a slab tilted by `angle` degrees (20) |
//! | `dome` | `courses` (8) × `blocks` (16), radius `r` (5), thickness `t` (0.3), `oculus` (10°) |

use super::{Block, Material, Scene};
use crate::geometry::{Mesh, Point3, Vector3};
use std::collections::BTreeMap;
use std::f64::consts::PI;
use thiserror::Error;

/// Why a built-in scene name cannot be built.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum BuiltinError {
    /// No built-in scene has that name.
    #[error("unknown built-in scene '{0}' (stack, stacks, harmonic, arch, wall, slope, dome)")]
    Unknown(String),
    /// A parameter the scene does not take.
    #[error("built-in '{scene}': unknown parameter '{param}' (known: {known})")]
    UnknownParam {
        /// The scene's name (`arch`, `stack`, …).
        scene: String,
        /// The parameter as written.
        param: String,
        /// The parameters the scene takes.
        known: String,
    },
    /// A parameter's value is out of range or not a number.
    #[error("built-in '{scene}': parameter '{param}' = '{value}' is not valid: {why}")]
    BadValue {
        /// The scene's name.
        scene: String,
        /// The parameter.
        param: String,
        /// The value as written.
        value: String,
        /// What it must be.
        why: &'static str,
    },
}

struct Params {
    scene: String,
    values: BTreeMap<String, String>,
    known: Vec<&'static str>,
}

impl Params {
    fn parse(spec: &str) -> Self {
        let (scene, query) = spec.split_once('?').unwrap_or((spec, ""));
        let values = query
            .split('&')
            .filter(|kv| !kv.is_empty())
            .map(|kv| {
                let (k, v) = kv.split_once('=').unwrap_or((kv, ""));
                (k.trim().to_string(), v.trim().to_string())
            })
            .collect();
        Self { scene: scene.trim().to_string(), values, known: vec!["mu"] }
    }

    fn bad(&self, param: &str, value: &str, why: &'static str) -> BuiltinError {
        BuiltinError::BadValue { scene: self.scene.clone(), param: param.into(), value: value.into(), why }
    }

    /// A positive finite number.
    fn num(&mut self, key: &'static str, default: f64) -> Result<f64, BuiltinError> {
        self.known.push(key);
        match self.values.get(key) {
            None => Ok(default),
            Some(v) => match v.parse::<f64>() {
                Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
                _ => Err(self.bad(key, v, "expected a positive number")),
            },
        }
    }

    /// A finite number, any sign.
    fn signed(&mut self, key: &'static str, default: f64) -> Result<f64, BuiltinError> {
        self.known.push(key);
        match self.values.get(key) {
            None => Ok(default),
            Some(v) => {
                v.parse::<f64>().ok().filter(|x| x.is_finite()).ok_or_else(|| self.bad(key, v, "expected a number"))
            }
        }
    }

    fn count(&mut self, key: &'static str, default: usize, min: usize) -> Result<usize, BuiltinError> {
        self.known.push(key);
        match self.values.get(key) {
            None => Ok(default),
            Some(v) => match v.parse::<usize>() {
                Ok(x) if x >= min && x <= 1_000_000 => Ok(x),
                _ => Err(self.bad(key, v, "expected a whole number in range")),
            },
        }
    }

    fn finish(&self) -> Result<(), BuiltinError> {
        if let Some(k) = self.values.keys().find(|k| !self.known.contains(&k.as_str())) {
            return Err(BuiltinError::UnknownParam {
                scene: self.scene.clone(),
                param: k.clone(),
                known: self.known.join(", "),
            });
        }
        Ok(())
    }
}

/// Builds the scene named by `spec` (`name?key=value&...`).
pub fn builtin(spec: &str) -> Result<Scene, BuiltinError> {
    let mut p = Params::parse(spec);
    let mut scene = match p.scene.as_str() {
        "stack" => {
            let (n, a) = (p.count("n", 5, 1)?, p.num("a", 1.0)?);
            box_stack(n, a)
        }
        "stacks" => {
            let (k, n) = (p.count("k", 10, 1)?, p.count("n", 5, 1)?);
            stacks(k, n)
        }
        "harmonic" => {
            let (n, s, h) = (p.count("n", 10, 1)?, p.num("s", 1.0)?, p.num("h", 0.25)?);
            harmonic_stack(n, s, h)
        }
        "arch" => {
            let (n, r, t, d) = (p.count("n", 21, 1)?, p.num("r", 1.0)?, p.num("t", 0.15)?, p.num("d", 0.5)?);
            if t >= 2.0 * r {
                return Err(p.bad("t", &t.to_string(), "thickness must be below twice the radius"));
            }
            arch(n, r, t, d)
        }
        "wall" => {
            let (c, m) = (p.count("courses", 10, 1)?, p.count("bricks", 10, 1)?);
            let (l, d, h) = (p.num("l", 0.4)?, p.num("d", 0.2)?, p.num("h", 0.1)?);
            wall(c, m, l, d, h)
        }
        "slope" => {
            let angle = p.signed("angle", 20.0)?;
            if angle.abs() >= 90.0 {
                return Err(p.bad("angle", &angle.to_string(), "the slope must be within ±90°"));
            }
            let (b, h) = (p.num("b", 0.5)?, p.num("h", 0.5)?);
            slope(angle, b, h)
        }
        "dome" => {
            let (c, m) = (p.count("courses", 8, 1)?, p.count("blocks", 16, 3)?);
            let (r, t, oc) = (p.num("r", 5.0)?, p.num("t", 0.3)?, p.signed("oculus", 10.0)?);
            if t >= 2.0 * r || !(0.0..90.0).contains(&oc) {
                return Err(p.bad("t", &t.to_string(), "need t < 2r and 0 ≤ oculus < 90°"));
            }
            dome(c, m, r, t, oc)
        }
        other => return Err(BuiltinError::Unknown(other.to_string())),
    };
    let defaults = Material::default();
    scene.material = Material { density: p.num("density", defaults.density)?, ..defaults };
    if p.values.contains_key("mu") {
        let v = p.values["mu"].clone();
        scene.material.friction = v
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite() && *x >= 0.0)
            .ok_or_else(|| p.bad("mu", &v, "expected μ ≥ 0"))?;
    }
    p.finish()?;
    scene.name = spec.to_string();
    Ok(scene)
}

fn cuboid(x0: f64, y0: f64, z0: f64, x1: f64, y1: f64, z1: f64) -> Mesh {
    Mesh::cuboid(Point3::new(x0, y0, z0), Point3::new(x1, y1, z1))
}

/// `n` cubes of edge `a` stacked on a support slab.
pub fn box_stack(n: usize, a: f64) -> Scene {
    let mut blocks = vec![Block::new("base", cuboid(-a, -a, -a, a, a, 0.0)).support(true)];
    for k in 0..n {
        let z = k as f64 * a;
        blocks.push(Block::new(format!("box{k}"), cuboid(-a / 2.0, -a / 2.0, z, a / 2.0, a / 2.0, z + a)));
    }
    Scene::new("stack", blocks)
}

/// `k` stacks of `n` unit cubes, 0.5 apart, on one support slab: `k` independent components.
pub fn stacks(k: usize, n: usize) -> Scene {
    let len = 1.5 * k as f64;
    let mut blocks = vec![Block::new("base", cuboid(-0.5, -0.5, -1.0, len, 1.5, 0.0)).support(true)];
    for s in 0..k {
        let x = 1.5 * s as f64;
        for j in 0..n {
            let z = j as f64;
            blocks.push(Block::new(format!("s{s}b{j}"), cuboid(x, 0.0, z, x + 1.0, 1.0, z + 1.0)));
        }
    }
    Scene::new("stacks", blocks)
}

/// Harmonic stack of `n` blocks 1 × 1 × h over a table edge at x = 0; block k from the top
/// overhangs the one below by s/(2k). At s = 1 every partial stack's centroid is exactly over
/// the edge below it: total overhang s·H_n/2.
pub fn harmonic_stack(n: usize, s: f64, h: f64) -> Scene {
    let mut blocks = vec![Block::new("table", cuboid(-2.0, -0.5, -h, 0.0, 0.5, 0.0)).support(true)];
    let mut right = 0.0;
    let mut rights = vec![0.0; n + 1];
    for k in (1..=n).rev() {
        right += s / (2.0 * k as f64);
        rights[k] = right;
    }
    for k in (1..=n).rev() {
        let level = (n - k) as f64;
        let x1 = rights[k];
        blocks.push(Block::new(format!("h{k}"), cuboid(x1 - 1.0, -0.5, level * h, x1, 0.5, (level + 1.0) * h)));
    }
    Scene::new("harmonic", blocks)
}

/// Semicircular arch of `n` radial voussoirs in the xz-plane, centre-line radius `r`,
/// thickness `t`, depth `d` (along y), on two support blocks under the springings.
pub fn arch(n: usize, r: f64, t: f64, d: f64) -> Scene {
    let (ri, ro) = (r - t / 2.0, r + t / 2.0);
    let at = |rad: f64, a: f64, y: f64| Point3::new(rad * a.cos(), y, rad * a.sin());
    let mut blocks = vec![
        Block::new("springer_right", cuboid(ri, -d / 2.0, -t, ro, d / 2.0, 0.0)).support(true),
        Block::new("springer_left", cuboid(-ro, -d / 2.0, -t, -ri, d / 2.0, 0.0)).support(true),
    ];
    for i in 0..n {
        let (a0, a1) = (PI * i as f64 / n as f64, PI * (i + 1) as f64 / n as f64);
        let base = [at(ri, a0, -d / 2.0), at(ro, a0, -d / 2.0), at(ro, a1, -d / 2.0), at(ri, a1, -d / 2.0)];
        blocks.push(Block::new(format!("v{i}"), Mesh::prism(&base, Vector3::new(0.0, d, 0.0))));
    }
    Scene::new("arch", blocks)
}

/// Running-bond wall: `courses` courses of `bricks` bricks l × d × h; odd courses start and end
/// with half bricks. On a support slab under the whole length.
pub fn wall(courses: usize, bricks: usize, l: f64, d: f64, h: f64) -> Scene {
    let len = bricks as f64 * l;
    let mut blocks = vec![Block::new("base", cuboid(0.0, -d / 2.0, -h, len, d / 2.0, 0.0)).support(true)];
    for c in 0..courses {
        let z = c as f64 * h;
        let mut edges: Vec<f64> = if c % 2 == 0 {
            (0..=bricks).map(|i| i as f64 * l).collect()
        } else {
            let mut e = vec![0.0];
            e.extend((0..bricks).map(|i| (i as f64 + 0.5) * l));
            e.push(len);
            e
        };
        edges.dedup();
        for (k, w) in edges.windows(2).enumerate() {
            blocks.push(Block::new(format!("c{c}b{k}"), cuboid(w[0], -d / 2.0, z, w[1], d / 2.0, z + h)));
        }
    }
    Scene::new("wall", blocks)
}

/// Block b × b × h (b along the slope) on a support slab tilted by `angle_deg` about y; the
/// block tends to slide towards +x.
pub fn slope(angle_deg: f64, b: f64, h: f64) -> Scene {
    let th = angle_deg.to_radians();
    let (c, s) = (th.cos(), th.sin());
    let rot = |p: &Point3| Point3::new(p.x * c + p.z * s, p.y, -p.x * s + p.z * c);
    let slab = cuboid(-2.0 * b, -b, -0.5 * b, 2.0 * b, b, 0.0).map_points(rot);
    let block = cuboid(-b / 2.0, -b / 2.0, 0.0, b / 2.0, b / 2.0, h).map_points(rot);
    Scene::new("slope", vec![Block::new("slab", slab).support(true), Block::new("block", block)])
}

/// Hemispherical dome on the ground plane: `courses` × `blocks` voussoirs between radii r ± t/2,
/// from the ground to an oculus of half-angle `oculus_deg` at the top.
pub fn dome(courses: usize, blocks: usize, r: f64, t: f64, oculus_deg: f64) -> Scene {
    let (ri, ro) = (r - t / 2.0, r + t / 2.0);
    let top = PI / 2.0 - oculus_deg.to_radians();
    let sph = |rad: f64, phi: f64, th: f64| {
        Point3::new(rad * phi.cos() * th.cos(), rad * phi.cos() * th.sin(), rad * phi.sin())
    };
    let mut out = Vec::with_capacity(courses * blocks);
    for c in 0..courses {
        let (p0, p1) = (top * c as f64 / courses as f64, top * (c + 1) as f64 / courses as f64);
        // Head joints stay aligned from course to course: a bed face is planar only over its
        // own azimuth range, so staggered courses would not meet face to face.
        for k in 0..blocks {
            let (t0, t1) = (2.0 * PI * k as f64 / blocks as f64, 2.0 * PI * (k + 1) as f64 / blocks as f64);
            let v = [
                sph(ri, p0, t0),
                sph(ro, p0, t0),
                sph(ro, p0, t1),
                sph(ri, p0, t1),
                sph(ri, p1, t0),
                sph(ro, p1, t0),
                sph(ro, p1, t1),
                sph(ri, p1, t1),
            ];
            out.push(Block::new(format!("d{c}_{k}"), Mesh::hexahedron(v)));
        }
    }
    let mut scene = Scene::new("dome", out);
    scene.ground = true;
    scene
}
