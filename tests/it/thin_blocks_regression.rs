//! Invariant: thin blocks do not reach past their neighbour — the gap tolerance is capped at a
//! fraction of the thinner block's thickness, not only relative to the model, so a 1000-voussoir
//! arch (voussoirs 3 mm thick at the springing) has exactly one interface per joint.

use crate::common::*;
use voussoir::interfaces::detect;
use voussoir::model::builtin;

#[test]
fn thousand_voussoir_arch_has_one_interface_per_joint() {
    let asm = assembly(&builtin("arch?n=1000&t=0.15").unwrap());
    let ifs = detect(&asm);
    assert_eq!(ifs.len(), 1001, "999 joints + 2 springings");
    for i in &ifs {
        let (a, b) = (i.a.block().unwrap().0, i.b.block().unwrap().0);
        // Blocks 0, 1 are the supports; voussoir k is block k + 2.
        let neighbours = match (a.min(b), a.max(b)) {
            (0, 2) | (1, 1001) => true,
            (x, y) => x >= 2 && y == x + 1,
        };
        assert!(neighbours, "{} – {}", i.a.name(&asm), i.b.name(&asm));
        assert_close(i.area, 0.15 * 0.5, 1e-9, "joint area t × d");
    }
}
