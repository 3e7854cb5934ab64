//! glTF 2.0 binary export (.glb) of an analysis: every block as a translucent mesh (flat
//! normals) and every interface polygon coloured per vertex by a diagram mode, so any glTF
//! viewer (or Rhino) shows the forces inside the assembly. Written by hand (the format is a
//! JSON header and one binary buffer); `tests/it/gltf_export.rs` reads it back with the `gltf`
//! crate. Each node's `extras` name what it is (`{"block": i}` or `{"interface": k}`, indices
//! into the assembly's blocks and the analysis's interfaces) so a viewer can say what was
//! picked; the diagrams' colours are unlit (`KHR_materials_unlit`): shown as the legends give
//! them, not shaded. Axes: glTF is y-up, voussoir z-up: (x, y, z) → (x, z, −y), here and nowhere else in
//! the export.

use super::DiagramMode;
use super::colors::Rgb;
use crate::pipeline::Analysis;
use serde_json::{Value, json};

fn y_up(p: [f64; 3]) -> [f32; 3] {
    [p[0] as f32, p[2] as f32, -p[1] as f32]
}

/// Accumulates the binary buffer and the JSON arrays.
#[derive(Default)]
struct Builder {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
    meshes: Vec<Value>,
    nodes: Vec<Value>,
}

impl Builder {
    /// A vec3 float accessor (with the min/max glTF requires for positions).
    fn vec3(&mut self, data: &[[f32; 3]], bounds: bool) -> usize {
        let offset = self.bin.len();
        for v in data {
            for c in v {
                self.bin.extend_from_slice(&c.to_le_bytes());
            }
        }
        self.views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": data.len() * 12, "target": 34962}));
        let mut acc =
            json!({"bufferView": self.views.len() - 1, "componentType": 5126, "count": data.len(), "type": "VEC3"});
        if bounds {
            let mut min = [f32::INFINITY; 3];
            let mut max = [f32::NEG_INFINITY; 3];
            for v in data {
                for k in 0..3 {
                    min[k] = min[k].min(v[k]);
                    max[k] = max[k].max(v[k]);
                }
            }
            acc["min"] = json!(min);
            acc["max"] = json!(max);
        }
        self.accessors.push(acc);
        self.accessors.len() - 1
    }

    /// A float accessor of `kind` ("SCALAR", "VEC4") over `data`, with min/max when asked
    /// (glTF requires them on an animation's input).
    fn floats(&mut self, data: &[f32], kind: &str, bounds: bool) -> usize {
        let offset = self.bin.len();
        data.iter().for_each(|c| self.bin.extend_from_slice(&c.to_le_bytes()));
        self.views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": data.len() * 4}));
        let width = if kind == "VEC4" { 4 } else { 1 };
        let mut acc = json!({"bufferView": self.views.len() - 1, "componentType": 5126, "count": data.len() / width, "type": kind});
        if bounds {
            acc["min"] = json!([data.iter().copied().fold(f32::INFINITY, f32::min)]);
            acc["max"] = json!([data.iter().copied().fold(f32::NEG_INFINITY, f32::max)]);
        }
        self.accessors.push(acc);
        self.accessors.len() - 1
    }

    /// One mesh node of flat triangles (`positions` in threes), `extras` naming what it is.
    fn mesh(&mut self, name: &str, extras: Value, positions: Vec<[f32; 3]>, colors: Option<Vec<Rgb>>, material: usize) {
        if positions.is_empty() {
            return;
        }
        let normals: Vec<[f32; 3]> = positions
            .chunks(3)
            .flat_map(|t| {
                let a = nalgebra::Vector3::from(t[0]);
                let n = (nalgebra::Vector3::from(t[1]) - a).cross(&(nalgebra::Vector3::from(t[2]) - a));
                let n = if n.norm() > 0.0 { n.normalize() } else { nalgebra::Vector3::y() };
                [[n.x, n.y, n.z]; 3]
            })
            .collect();
        let pos = self.vec3(&positions, true);
        let nor = self.vec3(&normals, false);
        let mut attributes = json!({"POSITION": pos, "NORMAL": nor});
        if let Some(c) = colors {
            attributes["COLOR_0"] = json!(self.vec3(&c, false));
        }
        self.meshes.push(json!({"name": name, "primitives": [{"attributes": attributes, "material": material}]}));
        self.nodes.push(json!({"name": name, "mesh": self.meshes.len() - 1, "extras": extras}));
    }
}

/// The .glb bytes of `analysis` with interfaces coloured by `mode`.
pub fn glb(analysis: &Analysis, mode: DiagramMode) -> Vec<u8> {
    let mut b = Builder::default();
    for (i, block) in analysis.assembly.blocks.iter().enumerate() {
        let m = &block.mesh;
        let pos: Vec<[f32; 3]> = m
            .triangles()
            .into_iter()
            .flat_map(|(t, _)| t.map(|k| y_up([m.vertices[k].x, m.vertices[k].y, m.vertices[k].z])))
            .collect();
        b.mesh(&block.name, json!({"block": i}), pos, None, if block.support { 1 } else { 0 });
    }
    for (k, label, tris) in super::interface_triangles(analysis, mode) {
        let pos = tris.iter().flat_map(|t| t.map(|(p, _)| y_up(p))).collect();
        let col = tris.iter().flat_map(|t| t.map(|(_, c)| c)).collect();
        b.mesh(&label, json!({"interface": k}), pos, Some(col), 2);
    }
    // Materials: free blocks translucent stone, supports darker, interfaces white × vertex colour.
    let materials = json!([
        {"name": "block", "pbrMetallicRoughness": {"baseColorFactor": [0.85, 0.82, 0.76, 0.35], "metallicFactor": 0.0, "roughnessFactor": 0.9}, "alphaMode": "BLEND"},
        {"name": "support", "pbrMetallicRoughness": {"baseColorFactor": [0.35, 0.35, 0.38, 0.6], "metallicFactor": 0.0, "roughnessFactor": 0.9}, "alphaMode": "BLEND"},
        {"name": "interface", "pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0}, "doubleSided": true, "extensions": {"KHR_materials_unlit": {}}}
    ]);
    write(b, &analysis.assembly.name, materials, None)
}

/// The .glb bytes of the built nodes with `materials`, and an animation if given.
fn write(mut b: Builder, name: &str, materials: Value, animation: Option<Value>) -> Vec<u8> {
    while !b.bin.len().is_multiple_of(4) {
        b.bin.push(0);
    }
    let nodes: Vec<usize> = (0..b.nodes.len()).collect();
    let mut doc = json!({
        "asset": {"version": "2.0", "generator": concat!("voussoir ", env!("CARGO_PKG_VERSION"))},
        "scene": 0,
        "scenes": [{"name": name, "nodes": nodes}],
        "nodes": b.nodes,
        "meshes": b.meshes,
        "materials": materials,
        "accessors": b.accessors,
        "bufferViews": b.views,
        "buffers": [{"byteLength": b.bin.len()}],
    });
    if let Some(a) = animation {
        doc["animations"] = json!([a]);
    }
    if doc["materials"].to_string().contains("KHR_materials_unlit") {
        doc["extensionsUsed"] = json!(["KHR_materials_unlit"]);
    }
    let mut text = serde_json::to_vec(&doc).expect("a JSON value always serialises");
    while !text.len().is_multiple_of(4) {
        text.push(b' ');
    }
    let total = 12 + 8 + text.len() + 8 + b.bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(text.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&text);
    out.extend_from_slice(&(b.bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&b.bin);
    out
}

/// Frames per simulated second of a recorded drop test's animation (`--frames`, the report).
pub const FRAMES_PER_SECOND: f64 = 30.0;

/// Seconds a settlement's whole path plays in (its motion's clock runs over the path, 0 to 1).
pub const PATH_SECONDS: f64 = 5.0;

/// The .glb bytes of a settlement run's motion ([`crate::studies::settlement::Run::motion`],
/// clocked over the path) played in [`PATH_SECONDS`].
pub fn path_glb(assembly: &crate::model::Assembly, motion: &crate::dynamics::Trajectory) -> Vec<u8> {
    let seconds: Vec<f64> = motion.times.iter().map(|t| t * PATH_SECONDS).collect();
    animated(assembly, &seconds, &motion.poses, &format!("motion ({})", motion.engine))
}

/// The .glb bytes of a drop test's (or a settlement's) motion: every block a node at its
/// centroid (its mesh relative to it), the free blocks and any support that moves animated by
/// the recorded poses (linear translation, spherical rotation between frames), the other
/// supports still. glTF players loop it.
pub fn animation_glb(assembly: &crate::model::Assembly, motion: &crate::dynamics::Trajectory) -> Vec<u8> {
    animated(assembly, &motion.times, &motion.poses, &format!("motion ({})", motion.engine))
}

/// The .glb bytes of a collapse mechanism played out over `seconds`: from the design at rest
/// to its blocks moved by the drawn mechanism ([`super::mechanism_scale`]: the largest motion
/// [`super::EXAGGERATION`] of the model size), each moving block turned by its rotation vector
/// (a true rotation, where the mechanism's own picture is linearised) and translated along its
/// translation, uniformly in time. `None` when nothing moves.
pub fn mechanism_glb(
    assembly: &crate::model::Assembly,
    mechanism: &crate::statics::Mechanism,
    seconds: f64,
) -> Option<Vec<u8>> {
    const FRAMES: usize = 31;
    let scale = super::mechanism_scale(mechanism, assembly)?;
    let times: Vec<f64> = (0..FRAMES).map(|f| seconds * f as f64 / (FRAMES - 1) as f64).collect();
    let poses: Vec<_> = (0..FRAMES)
        .map(|f| {
            let s = scale * f as f64 / (FRAMES - 1) as f64;
            assembly
                .blocks
                .iter()
                .zip(&mechanism.motion)
                .map(|(block, m)| {
                    let c = block.mass.centroid + nalgebra::Vector3::new(m[0], m[1], m[2]) * s;
                    let q = nalgebra::UnitQuaternion::from_scaled_axis(nalgebra::Vector3::new(m[3], m[4], m[5]) * s);
                    (c, [q.w, q.i, q.j, q.k])
                })
                .collect()
        })
        .collect();
    Some(animated(assembly, &times, &poses, "mechanism"))
}

/// The .glb bytes of `poses` (per frame, per block: centroid and rotation since the start,
/// [w, x, y, z]) at `times` (s), as [`animation_glb`] describes, the animation called `name`.
fn animated(
    assembly: &crate::model::Assembly,
    times: &[f64],
    poses: &[Vec<(crate::geometry::Point3, [f64; 4])>],
    name: &str,
) -> Vec<u8> {
    let mut b = Builder::default();
    for (i, block) in assembly.blocks.iter().enumerate() {
        let m = &block.mesh;
        let c = block.mass.centroid;
        let pos: Vec<[f32; 3]> =
            m.triangles().into_iter().flat_map(|(t, _)| t.map(|k| y_up((m.vertices[k] - c).into()))).collect();
        b.mesh(&block.name, json!({"block": i}), pos, None, if block.support { 1 } else { 0 });
        if let Some(node) = b.nodes.last_mut() {
            node["translation"] = json!(y_up(c.coords.into()));
        }
    }
    let times: Vec<f32> = times.iter().map(|&t| t as f32).collect();
    let input = b.floats(&times, "SCALAR", true);
    let (mut samplers, mut channels) = (Vec::new(), Vec::new());
    // Supports are still in a drop test; a settlement's moved supports move with the blocks.
    let moves = |i: usize| poses.iter().any(|f| f.get(i) != poses.first().and_then(|f0| f0.get(i)));
    for (i, block) in assembly.blocks.iter().enumerate().filter(|&(i, b)| !b.support || moves(i)) {
        let translation: Vec<[f32; 3]> = poses.iter().map(|f| y_up(f[i].0.coords.into())).collect();
        let rotation: Vec<f32> = poses
            .iter()
            .flat_map(|f| {
                let [w, x, y, z] = f[i].1;
                let v = y_up([x, y, z]);
                [v[0], v[1], v[2], w as f32]
            })
            .collect();
        let t = b.vec3(&translation, false);
        let r = b.floats(&rotation, "VEC4", false);
        let node = b.nodes.iter().position(|n| n["name"] == json!(block.name)).unwrap_or(i);
        for (path, output) in [("translation", t), ("rotation", r)] {
            samplers.push(json!({"input": input, "output": output, "interpolation": "LINEAR"}));
            channels.push(json!({"sampler": samplers.len() - 1, "target": {"node": node, "path": path}}));
        }
    }
    let materials = json!([
        {"name": "block", "pbrMetallicRoughness": {"baseColorFactor": [0.85, 0.82, 0.76, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.9}},
        {"name": "support", "pbrMetallicRoughness": {"baseColorFactor": [0.35, 0.35, 0.38, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.9}}
    ]);
    let animation = json!({"name": name, "samplers": samplers, "channels": channels});
    write(b, &assembly.name, materials, Some(animation))
}
