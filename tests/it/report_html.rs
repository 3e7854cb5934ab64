//! `voussoir report`'s page read back without a browser (tests/python/test_report_browser.py
//! opens it in Chromium). Invariants: the page is one file that names nothing outside itself;
//! its embedded designs and motions are the bytes of the glTF writers `export` and `--frames`
//! use (one writer); the numbers the page shows come from the JSON report it embeds; bad options exit 2 with one
//! message and write nothing.

use std::io::Read;
use std::path::PathBuf;
use std::process::{Command, Output};
use voussoir::pipeline::{AnalysisSettings, analyze};
use voussoir::viz::DiagramMode;

fn voussoir(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_voussoir"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("the binary runs")
}

fn tmp(name: &str) -> PathBuf {
    crate::common::scratch("report").join(name)
}

/// RFC 4648 base64, the inverse of the page's encoding (a test-side decoder, written apart).
fn unbase64(text: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => panic!("not base64: {c}"),
    } as u32;
    let bytes: Vec<u8> = text.bytes().filter(|c| !c.is_ascii_whitespace()).collect();
    let mut out = Vec::new();
    for chunk in bytes.chunks(4) {
        let pad = chunk.iter().filter(|&&c| c == b'=').count();
        let n = chunk.iter().take(4 - pad).enumerate().fold(0u32, |n, (k, &c)| n | value(c) << (18 - 6 * k));
        out.extend_from_slice(&n.to_be_bytes()[1..4 - pad]);
    }
    out
}

/// The page's assets by name, inflated.
fn assets(page: &str) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    for part in page.split("<script type=\"application/gzip+base64\" data-asset=\"").skip(1) {
        let (name, rest) = part.split_once("\">").unwrap();
        let (body, _) = rest.split_once("</script>").unwrap();
        let mut bytes = Vec::new();
        flate2::read::GzDecoder::new(&unbase64(body)[..]).read_to_end(&mut bytes).unwrap();
        out.push((name.to_string(), bytes));
    }
    out
}

/// The page's data (the JSON inside its `voussoir-data` script).
fn data(page: &str) -> serde_json::Value {
    let start = page.find("id=\"voussoir-data\">").unwrap() + "id=\"voussoir-data\">".len();
    let end = start + page[start..].find("</script>").unwrap();
    serde_json::from_str(&page[start..end]).unwrap()
}

#[test]
fn the_page_embeds_the_exports_gltf_and_three_js_and_names_nothing_outside_itself() {
    let out = tmp("arch.html");
    let r = voussoir(&["report", "builtin:arch?n=15&t=0.15", "--robustness", "-o", out.to_str().unwrap()]);
    assert_eq!(r.status.code(), Some(0), "{}", String::from_utf8_lossy(&r.stderr));
    let page = std::fs::read_to_string(&out).unwrap();
    let assets = assets(&page);
    let names: Vec<&str> = assets.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "module:three.core.js",
            "module:three",
            "module:three/addons/utils/BufferGeometryUtils.js",
            "module:three/addons/utils/SkeletonUtils.js",
            "module:three/addons/loaders/GLTFLoader.js",
            "module:three/addons/controls/OrbitControls.js",
            "design:compression",
            "design:friction",
            "motion:0",
            "report.json",
        ]
    );
    // The vendored three.js, byte for byte.
    let vendored = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/report/three/three.core.js");
    assert_eq!(assets[0].1, std::fs::read(vendored).unwrap());
    // The designs are the export's glTF (one writer).
    let scene = voussoir::model::builtin("arch?n=15&t=0.15").unwrap();
    let analysis = analyze(&scene, &AnalysisSettings::default()).unwrap();
    assert_eq!(assets[6].1, voussoir::viz::glb(&analysis, DiagramMode::Compression));
    assert_eq!(assets[7].1, voussoir::viz::glb(&analysis, DiagramMode::Friction { threshold: 0.5 }));
    assert_eq!(&assets[8].1[..4], b"glTF");
    // Outside the compressed assets, nothing is fetched from anywhere.
    let mut markup = page.clone();
    for (name, _) in &assets {
        let open = format!("data-asset=\"{name}\">");
        let start = markup.find(&open).unwrap() + open.len();
        let end = start + markup[start..].find("</script>").unwrap();
        markup.replace_range(start..end, "");
    }
    for remote in
        ["src=\"http", "href=\"http", "url(http", "from 'http", "from \"http", "import(\"http", "import('http"]
    {
        assert!(!markup.contains(remote), "the page names a remote resource: {remote}");
    }
    // The data: the verdict, both diagrams' legends, the mechanism's moving blocks.
    let d = data(&page);
    assert_eq!(d["verdict"], voussoir::report::text::headline(analysis.statics.verdict));
    let report: serde_json::Value = serde_json::from_slice(&assets[9].1).unwrap();
    assert_eq!(report["interfaces"].as_array().unwrap().len(), analysis.statics.interfaces.len());
    assert_eq!(d["diagrams"][1]["legend"][1][0], "#fff359", "yellow, sRGB of the linear [1, 0.9, 0.1]");
    assert_eq!(d["motions"][0]["title"], "mechanism");
    // The four hinges (springer_right → v0, v2 → v3, v7 → v8, v12 → v13) leave three segments
    // turning, v0–v12; v13 and v14 stay on the left springer.
    assert_eq!(d["motions"][0]["moved"].as_array().unwrap().len(), 13, "the 4-hinge mechanism's three segments");
}

#[test]
fn the_designs_gltf_names_each_block_and_interface_and_leaves_the_diagram_unlit() {
    let scene = voussoir::model::builtin("arch?n=9&t=0.15").unwrap();
    let analysis = analyze(&scene, &AnalysisSettings::default()).unwrap();
    let glb = voussoir::viz::glb(&analysis, DiagramMode::Compression);
    let len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let doc: serde_json::Value = serde_json::from_slice(&glb[20..20 + len]).unwrap();
    let nodes = doc["nodes"].as_array().unwrap();
    let blocks: Vec<u64> = nodes.iter().filter_map(|n| n["extras"]["block"].as_u64()).collect();
    let joints: Vec<u64> = nodes.iter().filter_map(|n| n["extras"]["interface"].as_u64()).collect();
    assert_eq!(blocks, (0..analysis.assembly.blocks.len() as u64).collect::<Vec<_>>());
    assert_eq!(joints, (0..analysis.statics.interfaces.len() as u64).collect::<Vec<_>>());
    for (n, &k) in nodes.iter().filter(|n| n["extras"]["interface"].is_u64()).zip(&joints) {
        let r = &analysis.statics.interfaces[k as usize];
        assert_eq!(n["name"], format!("{} | {}", r.a, r.b));
    }
    assert_eq!(doc["extensionsUsed"], serde_json::json!(["KHR_materials_unlit"]));
    assert!(doc["materials"][2]["extensions"]["KHR_materials_unlit"].is_object());
}

#[test]
fn a_settlement_report_carries_its_motion_and_its_thrust_plot() {
    let out = tmp("settle.html");
    let r = voussoir(&[
        "report",
        "builtin:arch?n=9&t=0.15",
        "--settle",
        "--move",
        "springer_left:-0.3,0,0",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(r.status.code(), Some(1), "it collapses: {}", String::from_utf8_lossy(&r.stderr));
    let page = std::fs::read_to_string(&out).unwrap();
    let d = data(&page);
    assert_eq!(d["motions"][0]["title"], "settlement");
    assert!(d["motions"][0]["caption"].as_str().unwrap().contains("collapses at"));
    assert!(d["plots"][0]["svg"].as_str().unwrap().starts_with("<svg"));
    assert!(d["panel"].as_str().unwrap().contains("SETTLE: springer_left moved"));
}

#[test]
fn bad_options_exit_2_with_one_message_and_write_nothing() {
    let out = tmp("bad.html");
    let o = out.to_str().unwrap();
    let cases: [(&[&str], &str); 4] = [
        (
            &["report", "assets/cases/fig6_dmsc.json", "--mode", "friction", "--threshold", "2", "-o", o],
            "--threshold 2",
        ),
        (&["report", "builtin:arch?n=9&t=0.15", "--move", "springer_left:-0.3,0,0", "-o", o], "--settle"),
        (&["report", "builtin:arch?n=9&t=0.15", "--settle", "-o", o], "--settle"),
        (&["report", "assets/cases/fig6_dmsc.json", "-o", "assets/cases/fig6_dmsc.json"], "fig6_dmsc.json"),
    ];
    for (args, names) in cases {
        let r = voussoir(args);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(names), "{args:?}: the message names {names}: {err}");
        assert!(!out.exists(), "{args:?} wrote a page");
    }
}
