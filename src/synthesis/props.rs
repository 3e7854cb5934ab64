//! A support that would make a failing design stand: one square column from the ground (or the
//! design's lowest level) up to a downward face of a failing block, where the failure
//! mechanism moves that face down the most — the paper's Fig 3b puts its pedestal under the S
//! for the same reason. Each candidate is checked by analysing the design with it; only one
//! that stands, without interpenetration, is proposed.

use crate::geometry::{Mesh, Point3};
use crate::interfaces::Body;
use crate::model::{Block, BlockId, Scene, Warning};
use crate::pipeline::{Analysis, AnalysisSettings, analyze};
use crate::stability::assess;
use serde::Serialize;

/// A column that holds the design.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SupportProposal {
    /// The block it goes under.
    pub under: String,
    /// The centre of its top face (on the block's face), m.
    pub top: [f64; 3],
    /// Its square side and height, m.
    pub side: f64,
    /// Its height, m: from the floor (the ground, else the design's lowest point) up to its top.
    pub height: f64,
    /// The support as a block of the design (named "support").
    #[serde(skip)]
    pub block: Block,
}

/// A face's candidates: at most this many faces, best first, are tried.
const CANDIDATES: usize = 8;
/// A face counts as facing down when its normal's z is below −this.
const DOWNWARD: f64 = 0.9;
/// The column's side as a fraction of √(face area): well inside a compact face.
const SIDE: f64 = 0.5;

/// The first column (in order of the failure mechanism's downward motion at the face) under
/// which `design` stands; `None` when the design stands, has no mechanism, or no column does.
pub fn propose_support(design: &Scene, analysis: &Analysis, settings: &AnalysisSettings) -> Option<SupportProposal> {
    let mechanism = assess(analysis, &settings.statics).ok()?.mechanism?;
    let assembly = &analysis.assembly;
    let tol = assembly.tolerances.coplanar;
    let floor = if assembly.ground { 0.0 } else { assembly.aabb().min.z };
    let mut faces: Vec<(f64, String, Point3, f64)> = Vec::new();
    for (i, b) in assembly.blocks.iter().enumerate().filter(|(_, b)| !b.support) {
        for f in b.faces.iter().filter(|f| f.normal.z < -DOWNWARD && f.centroid.z > floor + tol) {
            let down = -mechanism.point_motion(assembly, Body::Block(BlockId(i)), &f.centroid).z;
            if down > 0.0 {
                faces.push((down, b.name.clone(), f.centroid, f.area));
            }
        }
    }
    faces.sort_by(|a, b| b.0.total_cmp(&a.0));
    faces.into_iter().take(CANDIDATES).find_map(|(_, under, top, area)| {
        let side = SIDE * area.sqrt();
        let proposal = column(under, top, side, floor);
        holds(design, &proposal, settings).then_some(proposal)
    })
}

/// The column of side `side` from `floor` up to `top`.
fn column(under: String, top: Point3, side: f64, floor: f64) -> SupportProposal {
    let h = side / 2.0;
    let mesh = Mesh::cuboid(Point3::new(top.x - h, top.y - h, floor), Point3::new(top.x + h, top.y + h, top.z));
    let block = Block::new("support", mesh).support(true);
    SupportProposal { under, top: top.into(), side, height: top.z - floor, block }
}

/// Whether `design` with the column stands, the column touching nothing it should not.
fn holds(design: &Scene, proposal: &SupportProposal, settings: &AnalysisSettings) -> bool {
    let mut propped = design.clone();
    propped.blocks.push(proposal.block.clone());
    match analyze(&propped, settings) {
        Ok(a) => a.statics.stands && !a.assembly.warnings.iter().any(|w| matches!(w, Warning::Overlap(_))),
        Err(_) => false,
    }
}
