use std::collections::BTreeSet;
use voussoir::*;
fn main() {
    for f in std::env::args().skip(1) {
        let p = std::path::Path::new(&f);
        let mut scene = io::load_scene(p).unwrap();
        if !scene.blocks.iter().any(|b| b.support) { scene.mark_lowest_as_supports(1e-3); }
        let t0 = std::time::Instant::now();
        let asm = match model::Assembly::new(&scene, &Default::default()) { Ok(a) => a, Err(e) => { println!("{f}: {e}"); continue } };
        let t1 = std::time::Instant::now();
        let ifs = interfaces::detect(&asm);
        let t2 = std::time::Instant::now();
        let pairs: BTreeSet<(String,String)> = ifs.iter().map(|i| { let (a,b)=(i.a.name(&asm).to_string(), i.b.name(&asm).to_string()); if a<b {(a,b)} else {(b,a)} }).collect();
        let stored = io::compas::load_stored_interfaces(p).unwrap();
        let spairs: BTreeSet<(String,String)> = stored.iter().map(|s| if s.u<s.v {(s.u.clone(),s.v.clone())} else {(s.v.clone(),s.u.clone())}).collect();
        let area: f64 = ifs.iter().map(|i| i.area).sum();
        println!("{f}: blocks {} warn {} ifaces {} pairs {} | stored {} pairs {} | missing {} extra {} | area {area:.4} scale {:.3} | valid {:?} detect {:?}",
          asm.blocks.len(), asm.warnings.len(), ifs.len(), pairs.len(), stored.len(), spairs.len(),
          spairs.difference(&pairs).count(), pairs.difference(&spairs).count(), asm.scale, t1-t0, t2-t1);
        for model in [statics::FrictionModel::Pyramid8, statics::FrictionModel::Cone, statics::FrictionModel::Box4] {
            let t3 = std::time::Instant::now();
            let r = statics::analyze(&asm, &ifs, &statics::StaticsSettings { friction_model: model, friction: Some(0.84), ..Default::default() }).unwrap();
            println!("   {model}: {:?} T {:.3e} F {:.3e} util {:.3} status {:?} it {} res {:.2e} comps {} time {:?} msgs {:?}", r.verdict, r.tension_ratio, r.friction_excess_ratio, r.max_friction_utilization, r.solver.status, r.solver.iterations, r.solver.residual / r.free_weight, r.components, t3.elapsed(), r.solver.messages.iter().take(2).collect::<Vec<_>>());
        }
        for w in asm.warnings.iter().take(3) { println!("   {w}"); }
        for m in spairs.difference(&pairs).take(3) { println!("   missing {m:?}"); }
        for m in pairs.difference(&spairs).take(3) { println!("   extra {m:?}"); }
    }
}
#[allow(dead_code)]
fn unused() {}
