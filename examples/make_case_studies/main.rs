//! Regenerates the paper's case studies in assets/cases/: `cargo run --example make_case_studies`.
//! (`tests/it/case_studies.rs` fails when the files differ from what this writes.)

mod cases;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/cases");
    std::fs::create_dir_all(&dir)?;
    for (stem, scene) in cases::all() {
        let path = dir.join(format!("{stem}.json"));
        voussoir::io::write_atomic(&path, voussoir::io::scene_json::scene_to_string(&scene).as_bytes())?;
        println!("{}", path.display());
    }
    Ok(())
}
