//! Studies over many analyses of one design: the threshold of a family of designs found by
//! bisection, statically and in the drop test ([`threshold`]), and the assembly sequence, every
//! prefix of a building order checked ([`sequence`]).

pub mod sequence;
pub mod threshold;
