//! Connected components of free blocks: blocks linked by an interface where both sides are
//! free. Interfaces to supports or the ground belong to the component of their free block;
//! interfaces between two fixed bodies belong to none (they are never solved).

use crate::interfaces::{Body, Interface};
use crate::model::{Assembly, BlockId};

/// One independent equilibrium problem.
#[derive(Clone, Debug, PartialEq)]
pub struct Component {
    /// Free blocks, ascending.
    pub blocks: Vec<BlockId>,
    /// Indices into the interface list, ascending.
    pub interfaces: Vec<usize>,
}

impl Component {
    /// True when some interface of the component touches a support or the ground.
    pub fn is_supported(&self, assembly: &Assembly, interfaces: &[Interface]) -> bool {
        self.interfaces.iter().any(|&k| interfaces[k].a.is_fixed(assembly) || interfaces[k].b.is_fixed(assembly))
    }
}

fn find(parent: &mut [usize], mut x: usize) -> usize {
    while parent[x] != x {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    x
}

/// Components in order of their smallest block id. Deterministic.
pub fn components(assembly: &Assembly, interfaces: &[Interface]) -> Vec<Component> {
    let n = assembly.blocks.len();
    let mut parent: Vec<usize> = (0..n).collect();
    let free = |b: Body| b.block().filter(|&id| !assembly.block(id).support);
    for itf in interfaces {
        if let (Some(a), Some(b)) = (free(itf.a), free(itf.b)) {
            let (ra, rb) = (find(&mut parent, a.0), find(&mut parent, b.0));
            if ra != rb {
                parent[ra.max(rb)] = ra.min(rb);
            }
        }
    }
    let mut index_of_root = vec![usize::MAX; n];
    let mut comps: Vec<Component> = Vec::new();
    for i in 0..n {
        if assembly.blocks[i].support {
            continue;
        }
        let r = find(&mut parent, i);
        if index_of_root[r] == usize::MAX {
            index_of_root[r] = comps.len();
            comps.push(Component { blocks: Vec::new(), interfaces: Vec::new() });
        }
        comps[index_of_root[r]].blocks.push(BlockId(i));
    }
    for (k, itf) in interfaces.iter().enumerate() {
        if let Some(b) = free(itf.a).or(free(itf.b)) {
            let r = find(&mut parent, b.0);
            comps[index_of_root[r]].interfaces.push(k);
        }
    }
    comps
}

/// All components as one (for measuring what splitting saves).
pub fn merged(comps: Vec<Component>) -> Component {
    let mut blocks: Vec<BlockId> = comps.iter().flat_map(|c| c.blocks.iter().copied()).collect();
    let mut interfaces: Vec<usize> = comps.iter().flat_map(|c| c.interfaces.iter().copied()).collect();
    blocks.sort_unstable();
    interfaces.sort_unstable();
    Component { blocks, interfaces }
}
