//! Derivative-free optimisers, argmin's: the crate's one touchpoint (and rand_xoshiro's, which
//! seeds it, and gives the synthetic records their noise: [`uniform`]). A function of numbers in, the best point out; the callers own their problems
//! (the worst load direction in [`crate::stability`], cut placements in [`crate::synthesis`]).
//!
//! No units of its own: the callers' parameters and costs.

use argmin::core::{CostFunction, Error as ArgminError, Executor};
use argmin::solver::brent::BrentRoot;
use argmin::solver::particleswarm::ParticleSwarm;
use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::{RngCore, SeedableRng};

/// Uniform doubles in (0, 1) from `seed` (xoshiro256++'s 53 high bits): the same stream on
/// every machine.
pub fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    move || ((rng.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64
}

/// A root of `f` in [a, b], where f(a) and f(b) have opposite signs, by Brent's method to
/// `tolerance`, in at most `max_iters` iterations. An `Err` of `f` ends the search with it.
pub fn brent_root(
    f: &dyn Fn(f64) -> Result<f64, String>,
    a: f64,
    b: f64,
    tolerance: f64,
    max_iters: u64,
) -> Result<f64, String> {
    let problem = Scalar(f);
    let res = Executor::new(problem, BrentRoot::new(a, b, tolerance))
        .configure(|s| s.max_iters(max_iters))
        .run()
        .map_err(|e| e.to_string())?;
    res.state.best_param.ok_or_else(|| "Brent's method found no root".to_string())
}

/// The lowest point of `cost` within `bounds` (lower, upper per dimension) that a particle
/// swarm of `particles` finds in `iterations` rounds, with its cost; the random numbers come
/// from Xoshiro256++ seeded with `seed`, and the evaluations run in order, so the same seed
/// gives the same answer: particles × (iterations + 1) evaluations (`None` when nothing was
/// evaluated).
pub fn particle_swarm(
    cost: &dyn Fn(&[f64]) -> f64,
    bounds: (Vec<f64>, Vec<f64>),
    particles: usize,
    iterations: u64,
    seed: u64,
) -> Result<Option<(Vec<f64>, f64)>, String> {
    let solver = ParticleSwarm::new(bounds, particles).with_rng_generator(Xoshiro256PlusPlus::seed_from_u64(seed));
    let res = Executor::new(Vector(cost), solver)
        .configure(|state| state.max_iters(iterations))
        .run()
        .map_err(|e| e.to_string())?;
    Ok(res.state.best_individual.as_ref().map(|p| (p.position.clone(), p.cost)))
}

/// A function of one number as argmin's problem.
struct Scalar<'a>(&'a dyn Fn(f64) -> Result<f64, String>);

impl CostFunction for Scalar<'_> {
    type Param = f64;
    type Output = f64;
    fn cost(&self, x: &f64) -> Result<f64, ArgminError> {
        (self.0)(*x).map_err(ArgminError::msg)
    }
}

/// A function of a vector as argmin's problem.
struct Vector<'a>(&'a dyn Fn(&[f64]) -> f64);

impl CostFunction for Vector<'_> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, x: &Vec<f64>) -> Result<f64, ArgminError> {
        Ok((self.0)(x))
    }
}
