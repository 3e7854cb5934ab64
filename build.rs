//! No build step: this script exists so that the build-dependency in Cargo.toml (feature
//! alignment with the Python extension's build) takes part in the build.
fn main() {
    println!("cargo::rerun-if-changed=build.rs");
}
