//! Regenerates assets/default.json: `cargo run --example make_default_scene > assets/default.json`.
fn main() {
    let mut scene = voussoir::model::builtin("arch?n=15&t=0.3&r=2&d=0.6").unwrap();
    scene.name = "default: semicircular arch, 15 voussoirs, t/R = 0.15 (R = 2 m)".into();
    print!("{}", voussoir::io::scene_json::scene_to_string(&scene));
}
