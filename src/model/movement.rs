//! Prescribed support movements (`voussoir settle`): a support block's whole path, a
//! translation (model units) and a rotation vector (degrees) about its centroid, followed
//! linearly from the design as drawn (fraction 0) to the end of the path (fraction 1).

use serde::{Deserialize, Serialize};

/// One support's path.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Movement {
    /// The support block (a piece name after the cut history).
    pub block: String,
    /// The whole translation, model units.
    pub translation: [f64; 3],
    /// The whole rotation about the support's centroid: axis × angle, degrees.
    #[serde(default)]
    pub rotation: [f64; 3],
}

impl Movement {
    /// Parses `NAME:dx,dy,dz[:rx,ry,rz]` (the command line's `--move`).
    pub fn parse(spec: &str) -> Result<Self, String> {
        let parts: Vec<&str> = spec.split(':').collect();
        let triple = |s: &str, what: &str| -> Result<[f64; 3], String> {
            let v: Vec<f64> = s
                .split(',')
                .map(|x| {
                    x.trim().parse::<f64>().map_err(|_| format!("--move {spec}: {what} '{s}' is not three numbers"))
                })
                .collect::<Result<_, _>>()?;
            <[f64; 3]>::try_from(v).map_err(|_| format!("--move {spec}: {what} '{s}' is not three numbers"))
        };
        match parts.as_slice() {
            [name, t] => {
                Ok(Self { block: name.to_string(), translation: triple(t, "translation")?, rotation: [0.0; 3] })
            }
            [name, t, r] => Ok(Self {
                block: name.to_string(),
                translation: triple(t, "translation")?,
                rotation: triple(r, "rotation (degrees)")?,
            }),
            _ => Err(format!("--move {spec}: give NAME:dx,dy,dz or NAME:dx,dy,dz:rx,ry,rz")),
        }
    }

    /// Whether every number is finite.
    pub fn finite(&self) -> bool {
        self.translation.iter().chain(&self.rotation).all(|v| v.is_finite())
    }
}
