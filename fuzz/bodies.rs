//! The fuzz targets' bodies, shared by the libFuzzer binaries (`fuzz/fuzz_targets/`) and the
//! corpus replay test (`tests/it/fuzz_corpora.rs`): bytes in, how deep the input reached out.
//! Whatever the bytes, a body returns; a panic is the bug the fuzzer looks for.

use std::path::Path;
use voussoir::geometry::{Mesh, Point3, Vector3};
use voussoir::model::{Assembly, Block, Scene};
use voussoir::pipeline::{AnalysisSettings, analyze};
use voussoir::statics::{Backend, FrictionModel, StaticsSettings};

/// How far an input got: each stage is reached only by inputs that passed the one before.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Reached {
    /// The reader (or the assembly's checks) refused it with this error.
    Refused(String),
    /// Read, then refused by validation, detection or the statics' settings with this error.
    Rejected(String),
    /// Detection ran (the mesh target stops there; the record target: the record was read).
    Detected,
    /// The equilibrium was solved.
    Solved,
    /// Solved, then the load factor and the kinematic check ran.
    Assessed,
}

/// The targets by name, as `fuzz/Cargo.toml` lists them (the replay test walks them; each
/// fuzz binary runs one).
#[allow(dead_code)]
pub const TARGETS: [&str; 8] = ["scene_json", "compas", "obj", "stl", "mesh", "perturbed", "motion", "record"];

/// Runs the body of `target` on `data`.
pub fn run(target: &str, data: &[u8]) -> Reached {
    match target {
        "scene_json" | "compas" => scene_file("fuzz.json", data),
        "obj" => scene_file("fuzz.obj", data),
        "stl" => scene_file("fuzz.stl", data),
        "mesh" => mesh(data),
        "perturbed" => perturbed(data),
        "motion" => motion(data),
        "record" => record(data),
        other => panic!("no fuzz target '{other}'"),
    }
}

/// A scene file (the format from `name`'s extension) through reading and the whole analysis;
/// a scene without supports stands on the ground.
pub fn scene_file(name: &str, data: &[u8]) -> Reached {
    match voussoir::io::scene_from_bytes(Path::new(name), data) {
        Err(e) => Reached::Refused(e.to_string()),
        Ok(mut scene) => {
            if !scene.blocks.iter().any(|b| b.support) {
                scene.ground = true;
            }
            analysed(&scene, &AnalysisSettings::default())
        }
    }
}

fn analysed(scene: &Scene, settings: &AnalysisSettings) -> Reached {
    match analyze(scene, settings) {
        Err(e) => Reached::Rejected(e.to_string()),
        Ok(_) => Reached::Solved,
    }
}

/// A mesh from raw bytes (vertex coordinates as f64, faces as small indices) through
/// validation, repair, mass properties and interface detection.
pub fn mesh(data: &[u8]) -> Reached {
    let Some((&head, rest)) = data.split_first() else { return Reached::Refused("empty".into()) };
    let nv = (head % 16) as usize;
    let (coords, rest) = rest.split_at((nv * 24).min(rest.len()));
    let vertices: Vec<Point3> = coords
        .chunks_exact(24)
        .map(|c| {
            let f = |k: usize| f64::from_le_bytes(c[8 * k..8 * k + 8].try_into().expect("8 bytes"));
            Point3::new(f(0), f(1), f(2))
        })
        .collect();
    // Faces: a length byte then that many index bytes, repeatedly.
    let mut faces = Vec::new();
    let mut i = 0;
    while i < rest.len() {
        let len = (rest[i] % 8) as usize;
        let end = (i + 1 + len).min(rest.len());
        faces.push(rest[i + 1..end].iter().map(|&b| (b % 20) as usize).collect());
        i = end;
    }
    let scene = Scene::new("fuzz", vec![Block::new("m", Mesh::new(vertices, faces))]);
    match Assembly::new(&scene, &Default::default()) {
        Err(e) => Reached::Rejected(e.to_string()),
        Ok(a) => {
            voussoir::interfaces::detect(&a);
            Reached::Detected
        }
    }
}

/// A built-in design, then from the bytes either a support movement — any support or none by
/// that name, translations and rotations from 0 to ±1e30, NaN and ∞, increments, halvings and
/// the engines' dt at and beyond their limits — through `settle`'s checks and its quasi-static
/// run, or a short drop test in either engine with dt, duration and an initial speed from
/// sensible to absurd. A path or setting beyond its limits must be one error; one within them
/// runs (bounded: at most 20 increments, 0.25 s of motion).
pub fn motion(data: &[u8]) -> Reached {
    use voussoir::dynamics::{DropSettings, Engine, drop_test};
    use voussoir::model::Movement;
    use voussoir::studies::settlement::{SettleSettings, settle};
    let mut bytes = Bytes(data);
    let scene = base_scene(bytes.byte());
    let analysis = match analyze(&scene, &AnalysisSettings::default()) {
        Err(e) => return Reached::Rejected(e.to_string()),
        Ok(a) => a,
    };
    let size = analysis.assembly.scale;
    let value = |bytes: &mut Bytes| {
        let v = [0.0, 1e-6, 0.01, 0.05, 0.3, 20.0, 1e12, 1e30, f64::NAN, f64::INFINITY][usize::from(bytes.byte() % 10)];
        if bytes.byte().is_multiple_of(2) { v * size } else { -v * size }
    };
    let outcome = if bytes.byte().is_multiple_of(2) {
        let supports: Vec<String> =
            analysis.assembly.blocks.iter().filter(|b| b.support).map(|b| b.name.clone()).collect();
        let block = match bytes.byte() % 8 {
            0 => "no such block".to_owned(),
            _ => supports.get(bytes.index(supports.len())).cloned().unwrap_or_default(),
        };
        let translation = [value(&mut bytes), value(&mut bytes), value(&mut bytes)];
        let rotation = [0.0, 0.0, [0.0, 5.0, 90.0, 200.0][usize::from(bytes.byte() % 4)]];
        let settings = SettleSettings {
            increments: [1, 5, 20, 0, 2_000_000][usize::from(bytes.byte() % 5)],
            refine: [0, 3, 53][usize::from(bytes.byte() % 3)],
            // The engines only where their dt is beyond the limit (one error, no run).
            engines: bytes.byte().is_multiple_of(4),
            dt: 1e-12,
            ..Default::default()
        };
        let settings = if settings.engines { settings } else { SettleSettings { dt: 1.0 / 240.0, ..settings } };
        settle(&analysis, &[Movement { block, translation, rotation }], &settings)
            .map(|_| ())
            .map_err(|e| e.to_string())
    } else {
        let settings = DropSettings {
            engine: if bytes.byte().is_multiple_of(2) { Engine::Exact } else { Engine::Rapier },
            dt: [1.0 / 240.0, 1.0 / 60.0, 0.0, -1.0, 1e-12, f64::NAN][usize::from(bytes.byte() % 6)],
            duration: [0.05, 0.25, 0.0, 1e9, f64::INFINITY][usize::from(bytes.byte() % 5)],
            perturbation: [0.0, 0.05, 0.5, -1.0, f64::NAN][usize::from(bytes.byte() % 5)],
            ..Default::default()
        };
        drop_test(&analysis.assembly, &settings).map(|_| ()).map_err(|e| e.to_string())
    };
    match outcome {
        Err(e) => Reached::Rejected(e),
        Ok(()) => Reached::Assessed,
    }
}

/// A ground-motion record through its reader: an `.AT2` file when the first byte is even, else a
/// CSV, the rest of the bytes its text. A record read is as deep as this target goes.
pub fn record(data: &[u8]) -> Reached {
    let (name, text) = match data.split_first() {
        Some((b, rest)) if b.is_multiple_of(2) => ("fuzz.at2", rest),
        Some((_, rest)) => ("fuzz.csv", rest),
        None => ("fuzz.at2", data),
    };
    match voussoir::io::accelerogram::parse_accelerogram(Path::new(name), &String::from_utf8_lossy(text)) {
        Err(e) => Reached::Refused(e.to_string()),
        Ok(_) => Reached::Detected,
    }
}

/// Reads bytes as small numbers, then zeros once they run out.
struct Bytes<'a>(&'a [u8]);

impl Bytes<'_> {
    fn byte(&mut self) -> u8 {
        let Some((&b, rest)) = self.0.split_first() else { return 0 };
        self.0 = rest;
        b
    }

    fn index(&mut self, n: usize) -> usize {
        if n == 0 { 0 } else { (usize::from(self.byte()) << 8 | usize::from(self.byte())) % n }
    }

    /// A signed fraction in [-1, 1].
    fn unit(&mut self) -> f64 {
        f64::from(self.byte() as i8) / 127.0
    }

    fn done(&self) -> bool {
        self.0.is_empty()
    }
}

/// A valid built-in assembly, perturbed as a designer's or a converter's mistakes would
/// (vertices moved by 1e-9 to 0.3 of the model, faces flipped, near-duplicate vertices,
/// densities, μ, tolerances and the friction model changed), then the whole pipeline: the
/// analysis, the load factor of a horizontal field and the kinematic check.
pub fn perturbed(data: &[u8]) -> Reached {
    let mut bytes = Bytes(data);
    let mut scene = base_scene(bytes.byte());
    let mut settings = AnalysisSettings::default();
    let mut edits = 0;
    while !bytes.done() && edits < 16 {
        perturb(&mut scene, &mut settings, &mut bytes);
        edits += 1;
    }
    let analysis = match analyze(&scene, &settings) {
        Err(e) => return Reached::Rejected(e.to_string()),
        Ok(a) => a,
    };
    assess(&analysis, &settings.statics);
    Reached::Assessed
}

fn base_scene(pick: u8) -> Scene {
    let spec = match pick % 6 {
        0 => "stack?n=3",
        1 => "arch?n=7&t=0.2",
        2 => "wall?courses=2&bricks=3",
        3 => "dome?courses=2&blocks=5",
        4 => "slope?angle=25&mu=0.6",
        _ => "harmonic?n=4",
    };
    voussoir::model::builtin(spec).expect("the built-in specs are valid")
}

/// One edit chosen by the next byte.
fn perturb(scene: &mut Scene, settings: &mut AnalysisSettings, bytes: &mut Bytes) {
    let size = scene.scale();
    let b = bytes.index(scene.blocks.len());
    let kind = bytes.byte();
    let block = &mut scene.blocks[b];
    match kind % 9 {
        0 | 1 => {
            // A vertex moved by up to 1e-9, 1e-5, 1e-3 or 0.3 of the model size.
            let v = bytes.index(block.mesh.vertices.len());
            let reach = [1e-9, 1e-5, 1e-3, 0.3][usize::from(bytes.byte() % 4)] * size;
            let d = Vector3::new(bytes.unit(), bytes.unit(), bytes.unit()) * reach;
            if let Some(p) = block.mesh.vertices.get_mut(v) {
                *p += d;
            }
        }
        2 => {
            let f = bytes.index(block.mesh.faces.len());
            if let Some(face) = block.mesh.faces.get_mut(f) {
                face.reverse();
            }
        }
        3 => {
            // A near-duplicate of a vertex, used by one face in its place.
            let v = bytes.index(block.mesh.vertices.len());
            let f = bytes.index(block.mesh.faces.len());
            let eps = [0.0, 1e-12, 1e-8, 1e-6][usize::from(bytes.byte() % 4)] * size;
            if let Some(&p) = block.mesh.vertices.get(v) {
                block.mesh.vertices.push(p + Vector3::new(eps, -eps, eps));
                let new = block.mesh.vertices.len() - 1;
                if let Some(face) = block.mesh.faces.get_mut(f) {
                    face.iter_mut().filter(|i| **i == v).for_each(|i| *i = new);
                }
            }
        }
        4 => block.density = Some([1.0, 2400.0, 1e-6, 1e9, 0.0, -5.0][usize::from(bytes.byte() % 6)].into()),
        5 => block.support = !block.support,
        6 => scene.material.friction = [0.0, 0.2, 0.5, 0.84, 1.5, f64::NAN][usize::from(bytes.byte() % 6)],
        7 => {
            settings.statics.friction_model =
                [FrictionModel::Pyramid8, FrictionModel::Cone, FrictionModel::Box4][usize::from(bytes.byte() % 3)];
            settings.statics.backend =
                if bytes.byte().is_multiple_of(2) { Backend::Structured } else { Backend::Clarabel };
        }
        _ => {
            let t = &mut settings.tolerances;
            match bytes.byte() % 3 {
                0 => t.coplanar = [1e-6, 3e-3, 0.05, 0.0][usize::from(bytes.byte() % 4)],
                1 => t.angle_deg = [0.5, 6.0, 30.0, 90.0][usize::from(bytes.byte() % 4)],
                _ => t.weld = [1e-12, 1e-7, 1e-3, -1.0][usize::from(bytes.byte() % 4)],
            }
        }
    }
}

/// The load factor of a horizontal 1 g field along x and the kinematic check, each ending in a
/// value or an error.
fn assess(analysis: &voussoir::pipeline::Analysis, statics: &StaticsSettings) {
    let field = voussoir::stability::directions::with_horizontal_field(&analysis.assembly, 0.0);
    let _ = voussoir::stability::assess_parts(&field, &analysis.interfaces, analysis.statics.stands, statics);
    let _ = voussoir::stability::kinematic::check(analysis, statics, &Default::default());
}
