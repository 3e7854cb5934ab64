use voussoir::*;
fn main() {
    for spec in std::env::args().skip(1) {
        let scene = model::builtin(&spec).unwrap();
        let asm = model::Assembly::new(&scene, &Default::default()).unwrap();
        let ifs = interfaces::detect(&asm);
        let t = std::time::Instant::now();
        let r = statics::analyze(&asm, &ifs, &Default::default()).unwrap();
        println!("{spec}: blocks {} ifaces {} warn {} -> {:?} T {:.3e} F {:.3e} util {:.3} {:?} it {} res {:.1e} {:?}", asm.blocks.len(), ifs.len(), asm.warnings.len(), r.verdict, r.tension_ratio, r.friction_excess_ratio, r.max_friction_utilization, r.solver.status, r.solver.iterations, r.solver.residual/r.free_weight, t.elapsed());
    }
}
