//! The BRG formats besides the compas 2 Assembly (issue #23): the legacy compas_rbe JSON, the
//! compas_dem `BlockModel` and compas_dem's lists of meshes with a supports file.
//! Invariants: every reference file loads with the blocks and supports its JSON holds (counted
//! here from the JSON itself), solves, and stands (the published designs all stand: they were
//! built or computed as such); a support given as one open polygon becomes a solid under that
//! polygon, clear of the blocks; bad input gets one error naming the file and the block.

use crate::common::*;
use serde_json::Value;
use voussoir::io::{IoError, load_scene, load_supports};
use voussoir::pipeline::AnalysisSettings;

fn json(rel: &str) -> Value {
    serde_json::from_str(&std::fs::read_to_string(compas_data(rel)).unwrap()).unwrap()
}

fn tmp(name: &str, content: &str) -> std::path::PathBuf {
    let p = crate::common::scratch("compas-formats").join(name);
    std::fs::write(&p, content).unwrap();
    p
}

/// The legacy compas_rbe files: blocks and supports as the JSON lists them, every design
/// stands; the single-polygon supports (simple_arch's ground, genevault's footings) are slabs
/// whose top face is the polygon.
#[test]
fn legacy_compas_rbe_files_load_and_stand() {
    for (file, blocks, supports) in [
        ("simple_arch.json", 11, 1),
        ("corbel_blocks.json", 10, 1),
        ("genevault.json", 110, 35),
        ("matthias_vault_blocks.json", 317, 56),
    ] {
        let rel = format!("compas_rbe/{file}");
        let v = json(&rel);
        let listed = v["blocks"].as_object().unwrap().len();
        let fixed = v["assembly"]["vertex"].as_object().unwrap().values().filter(|n| n["is_support"] == true).count();
        assert_eq!((listed, fixed), (blocks, supports), "{file}: the JSON's counts");
        let scene = load_scene(&compas_data(&rel)).unwrap();
        assert_eq!(scene.blocks.len(), listed, "{file}");
        assert_eq!(scene.blocks.iter().filter(|b| b.support).count(), fixed, "{file}");
        let a = run(&scene, &AnalysisSettings::default());
        assert!(a.statics.stands, "{file}: {:?}", a.statics.verdict);
        assert!(!a.interfaces.is_empty());
    }
    // simple_arch's ground is one polygon at z = 0 (normal up, towards the arch): a slab below
    // it, its top face the polygon.
    let scene = load_scene(&compas_data("compas_rbe/simple_arch.json")).unwrap();
    let ground = scene.blocks.iter().find(|b| b.name == "10").expect("block 10, the ground");
    let bb = ground.mesh.aabb();
    assert_close(bb.max.z, 0.0, 1e-12, "the slab's top is the polygon");
    assert!(bb.min.z < 0.0, "the slab lies below: {bb:?}");
    assert_close(bb.max.x - bb.min.x, 24.0, 1e-12, "the polygon's extent");
}

/// compas_dem's cross vault (a BlockModel): 38 elements, 5 supports (as the JSON flags them),
/// named by their graph node keys; it stands.
#[test]
fn compas_dem_block_model_loads_and_stands() {
    let v = json("compas_dem/dem_crossvault.json");
    let elements = v["data"]["elements"].as_object().unwrap();
    let fixed = elements.values().filter(|e| e["data"]["is_support"] == true).count();
    let scene = load_scene(&compas_data("compas_dem/dem_crossvault.json")).unwrap();
    assert_eq!(scene.blocks.len(), elements.len());
    assert_eq!(scene.blocks.iter().filter(|b| b.support).count(), fixed);
    let names: Vec<&str> = scene.blocks.iter().map(|b| b.name.as_str()).collect();
    let expected: Vec<String> = (0..elements.len()).map(|k| k.to_string()).collect();
    assert_eq!(names, expected.iter().map(String::as_str).collect::<Vec<_>>(), "graph node keys, in order");
    // Node 0's element is the one the graph names.
    let guid = v["data"]["graph"]["node"]["0"]["element"].as_str().unwrap();
    let first = &elements[guid]["data"]["geometry"]["data"]["vertex"];
    assert_eq!(scene.blocks[0].mesh.vertices.len(), first.as_object().unwrap().len());
    let a = run(&scene, &AnalysisSettings::default());
    assert!(a.statics.stands, "{:?}", a.statics.verdict);
}

/// compas_dem's pavillion vault: 377 meshes and a supports file of 10; without the supports
/// nothing holds it, with them it stands.
#[test]
fn compas_dem_mesh_lists_with_a_supports_file() {
    let blocks = compas_data("compas_dem/pavillionvault/blocks.json");
    let mut scene = load_scene(&blocks).unwrap();
    assert_eq!(scene.blocks.len(), json("compas_dem/pavillionvault/blocks.json").as_array().unwrap().len());
    assert!(scene.blocks.iter().all(|b| !b.support));
    let supports = load_supports(&compas_data("compas_dem/pavillionvault/supports.json")).unwrap();
    assert_eq!(supports.len(), 10);
    assert!(supports.iter().all(|s| s.support && s.name.starts_with("support ")));
    assert!(!run(&scene, &AnalysisSettings::default()).statics.stands, "no support");
    scene.blocks.extend(supports);
    let a = run(&scene, &AnalysisSettings::default());
    assert!(a.statics.stands, "{:?}", a.statics.verdict);
}

/// Bad input: one error naming the file and the block.
#[test]
fn bad_brg_files_name_the_file_and_the_block() {
    let square = r#"{"vertex": {"0": {"x": 0, "y": 0, "z": 1}, "1": {"x": 1, "y": 0, "z": 1}, "2": {"x": 1, "y": 1, "z": 1}, "3": {"x": 0, "y": 1, "z": 1}}, "face": {"0": [0, 1, 2, 3]}}"#;
    // A free block given as one polygon has no volume.
    let text =
        format!(r#"{{"blocks": {{"7": {square}}}, "assembly": {{"vertex": {{"7": {{"is_support": false}}}}}}}}"#);
    let p = tmp("flat_free.json", &text);
    let e = load_scene(&p).unwrap_err();
    assert!(matches!(e, IoError::Format { .. }));
    let msg = e.to_string();
    assert!(msg.contains("flat_free.json") && msg.contains("block '7'") && msg.contains("no volume"), "{msg}");
    // A block the assembly does not list.
    let text = format!(r#"{{"blocks": {{"7": {square}}}, "assembly": {{"vertex": {{"8": {{"is_support": true}}}}}}}}"#);
    let msg = load_scene(&tmp("unlisted.json", &text)).unwrap_err().to_string();
    assert!(msg.contains("block '7' is not a vertex of the assembly"), "{msg}");
    // A mesh list whose item holds two meshes.
    let mesh = format!(r#"{{"dtype": "compas.datastructures/Mesh", "data": {square}}}"#);
    let text = format!("[[{mesh}], [{mesh}, {mesh}]]");
    let msg = load_supports(&tmp("two.json", &text)).unwrap_err().to_string();
    assert!(msg.contains("two.json") && msg.contains("item 1 holds 2 meshes"), "{msg}");
}

/// `--compas-out`: the compas 2 Assembly voussoir writes, read back by the compas reader: the
/// same blocks and supports, every block–block interface with its points, and the forces in
/// compas' convention (edge u → v, normal xaxis × yaxis from u into v, v receives
/// (c_np − c_nn) n + c_u xaxis + c_v yaxis, u the opposite). Invariant (independent of how the
/// file was written): with those forces at their points every free block of the arch is in
/// equilibrium with its weight — forces and moments about its centroid, to 1e-6 of W (W·L).
#[test]
fn written_compas_assembly_reads_back_and_balances_every_block() {
    use voussoir::geometry::Vector3;
    use voussoir::io::compas::{load_stored_interfaces, stored_interfaces};
    let scene = load_scene(&compas_data("compas_assembly/arch_assembly.json")).unwrap();
    let a = run(&scene, &AnalysisSettings::default());
    assert!(a.statics.stands);
    let text = voussoir::report::compas::assembly_json(&a);
    let p = tmp("arch_out.json", &text);
    let back = load_scene(&p).unwrap();
    assert_eq!(back.blocks.len(), a.assembly.blocks.len());
    for (i, (b, orig)) in back.blocks.iter().zip(&a.assembly.blocks).enumerate() {
        assert_eq!((b.name.as_str(), b.support), (i.to_string().as_str(), orig.support));
        assert_eq!(b.mesh.vertices.len(), orig.mesh.vertices.len());
    }
    let value: Value = serde_json::from_str(&text).unwrap();
    assert_eq!(value["data"]["graph"]["data"]["node"]["0"]["name"], a.assembly.blocks[0].name.as_str());
    let stored = load_stored_interfaces(&p).unwrap();
    assert_eq!(stored.len(), stored_interfaces(&p, &value).unwrap().len());
    assert_eq!(stored.len(), a.interfaces.len(), "the arch has no ground interfaces");
    // Σ forces on each block from the file, plus its weight.
    let blocks = &a.assembly.blocks;
    let mut net = vec![(Vector3::zeros(), Vector3::zeros()); blocks.len()];
    for s in &stored {
        let forces = s.forces.as_ref().expect("forces written");
        assert_eq!(forces.len(), s.points.len());
        let n = s.normal.normalize();
        let (u, v): (usize, usize) = (s.u.parse().unwrap(), s.v.parse().unwrap());
        for (c, p) in forces.iter().zip(&s.points) {
            let f = n * (c[0] - c[1]) + s.xaxis * c[2] + s.yaxis * c[3];
            net[v].0 += f;
            net[v].1 += (p - blocks[v].mass.centroid).cross(&f);
            net[u].0 -= f;
            net[u].1 -= (p - blocks[u].mass.centroid).cross(&f);
        }
    }
    let (w, l) = (a.statics.free_weight, a.assembly.scale);
    for (i, b) in blocks.iter().enumerate().filter(|(_, b)| !b.support) {
        let force = net[i].0 + a.assembly.gravity * b.mass();
        assert!(force.norm() < 1e-6 * w, "block {i} ({}): force {force:?} of W = {w}", b.name);
        assert!(net[i].1.norm() < 1e-6 * w * l, "block {i} ({}): moment {:?}", b.name, net[i].1);
    }
}

/// `--compas-out` of a BlockModel: the BlockModel voussoir writes reads back through the
/// BlockModel reader with the same blocks (in order), supports and meshes, and analyses to the
/// same verdict and free weight; it holds one contact per block–block interface, each with one
/// force per point, and element guids that are the same on a second write (deterministic).
#[test]
fn written_block_model_reads_back() {
    let scene = load_scene(&compas_data("compas_dem/dem_crossvault.json")).unwrap();
    let a = run(&scene, &AnalysisSettings::default());
    let text = voussoir::report::compas::block_model_json(&a);
    assert_eq!(text, voussoir::report::compas::block_model_json(&a));
    let p = tmp("crossvault_out.json", &text);
    let back = load_scene(&p).unwrap();
    assert_eq!(back.blocks.len(), a.assembly.blocks.len());
    for (b, orig) in back.blocks.iter().zip(&a.assembly.blocks) {
        assert_eq!(b.support, orig.support);
        assert_eq!(b.mesh.vertices.len(), orig.mesh.vertices.len());
    }
    let again = run(&back, &AnalysisSettings::default());
    assert_eq!(again.statics.verdict, a.statics.verdict);
    assert!((again.statics.free_weight - a.statics.free_weight).abs() < 1e-9 * a.statics.free_weight);
    let value: Value = serde_json::from_str(&text).unwrap();
    let edges = value["data"]["graph"]["edge"].as_object().unwrap();
    let contacts: Vec<&Value> = edges
        .values()
        .flat_map(|row| row.as_object().unwrap().values())
        .flat_map(|e| e["contacts"].as_array().unwrap())
        .collect();
    let block_pairs = a.interfaces.iter().filter(|i| i.a.block().is_some() && i.b.block().is_some()).count();
    assert_eq!(contacts.len(), block_pairs);
    for c in contacts {
        assert_eq!(c["dtype"], "compas_dem.interactions/FrictionContact");
        assert_eq!(c["data"]["forces"].as_array().unwrap().len(), c["data"]["points"].as_array().unwrap().len());
    }
}
