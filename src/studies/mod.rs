//! Studies over many analyses of one design: the threshold of a family of designs found by
//! bisection, statically and in the drop test ([`threshold`]), and the assembly sequence, every
//! prefix of a building order checked ([`sequence`]); a design on supports that move, followed
//! until it collapses ([`settlement`]); a design on a shaking ground, the static load factor
//! beside the dynamic answer, and collapse spectra ([`shake`]).

pub mod sequence;
pub mod settlement;
pub mod shake;
pub mod threshold;
