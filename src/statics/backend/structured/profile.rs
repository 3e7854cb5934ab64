//! Kernel timers of the structured solver, for the roofline table in docs/benchmarks.md
//! (`cargo run --release --example roofline`). Off unless [`enable`]d: a timer then costs one
//! relaxed atomic load. Times accumulate per thread (a solve moved onto rayon's pool brings
//! its own back); [`take`] returns and clears them.
//!
//! Each kernel's flops and bytes per call come from [`Dims`] ([`Kernel::cost`]): leading
//! terms counted from the loops of the kernel (a multiply–add is two flops; a division or
//! square root one), bytes as the arrays each call reads and writes once (f64, 8 bytes; the
//! per-problem constants of `shape::Shape` are a few hundred bytes and not counted).

use std::cell::RefCell;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

static ON: AtomicBool = AtomicBool::new(false);
static BLOCKS: AtomicBool = AtomicBool::new(true);

/// The timed kernels of one interior-point iteration (and of the set-up before it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kernel {
    /// The contact problem in the solver's fixed-size form, and S's pattern and symbolic
    /// analysis (once per problem).
    Setup,
    /// The iterate's residuals and measures (`measures::info`: A x, Aᵀz, norms, dots).
    Measures,
    /// The Nesterov–Todd scaling at (s, z).
    Scaling,
    /// S = E H⁻¹ Eᵀ: per point H_p and its Cholesky factor, per contact the 6×6 wrench matrix,
    /// scattered into S's values.
    FormS,
    /// faer's numeric Cholesky of S (and the load factor's extra solve).
    FactorS,
    /// The right-hand side of S: r̃x per point, H_p⁻¹ r̃x, summed into block wrenches.
    ReduceRhs,
    /// The forward and backward substitutions with S's factor.
    TriangularSolve,
    /// The points' x and z_G from z_E.
    BackSubstitute,
    /// Iterative refinement's residual: the unregularised KKT matrix times the solution.
    RefineResidual,
    /// The step to the cones' boundary.
    StepLength,
    /// One whole solve (everything above plus the vector work between them).
    Solve,
}

impl Kernel {
    /// Every kernel, in the order their times and calls are kept in a [`Profile`].
    pub const ALL: [Kernel; 11] = [
        Kernel::Setup,
        Kernel::Measures,
        Kernel::Scaling,
        Kernel::FormS,
        Kernel::FactorS,
        Kernel::ReduceRhs,
        Kernel::TriangularSolve,
        Kernel::BackSubstitute,
        Kernel::RefineResidual,
        Kernel::StepLength,
        Kernel::Solve,
    ];

    fn index(self) -> usize {
        Self::ALL.iter().position(|k| *k == self).unwrap_or(0)
    }

    /// (flops, bytes) of one call on a problem of `d` (module docs); `None` for the set-up and
    /// the whole solve, which are not single kernels.
    pub fn cost(self, d: &Dims) -> Option<(f64, f64)> {
        let (np, c, m) = (d.points as f64, d.per_point as f64, d.rows_per_point as f64);
        let (me, mg, n) = (d.m_e as f64, (d.points * d.rows_per_point) as f64, (d.points * d.per_point) as f64);
        let soc = d.soc as u8 as f64;
        let nc = d.contacts as f64;
        // A x and Aᵀz per point: N x (6C), its wrench (12), the rows (2mC), and back.
        let a_mul = np * (6.0 * c + 12.0 + 2.0 * m * c) + nc * 2.0 * 36.0;
        let at_mul = np * (6.0 * c + 12.0 + 2.0 * m * c) + nc * 2.0 * 36.0;
        let cost = match self {
            Kernel::Measures => {
                // A x, Aᵀz, P x, five dots and seven norms over x, s, z.
                (a_mul + at_mul + 2.0 * n + 10.0 * mg + 4.0 * n, 8.0 * (5.0 * n + 7.0 * mg + 3.0 * me))
            }
            Kernel::Scaling => {
                // s/z and z/s per non-negative row; ~60 flops per cone.
                let nonneg = mg - 3.0 * soc * np;
                (2.0 * nonneg + 60.0 * soc * np, 8.0 * 4.0 * mg)
            }
            Kernel::FormS => {
                // H_p (2C² per non-negative row, or the cone's ~3C² + 20C), its Cholesky
                // (C³/3), M = L⁻¹Nᵀ (3C²), Y (6·2C), T Y Tᵀ (~80); per contact Ψ K Ψᵀ twice
                // and the off-diagonal block (3·2·216).
                let nn = d.rows_per_point as f64 - 3.0 * soc;
                let per_point = nn * c * (c + 1.0)
                    + soc * (3.0 * c * c + 20.0 * c)
                    + c * c * c / 3.0
                    + 3.0 * c * c
                    + 12.0 * c
                    + 80.0;
                (np * per_point + nc * 1296.0, 8.0 * (mg + np * c * c + d.s_values as f64))
            }
            Kernel::FactorS => (d.factor_flops, 8.0 * (d.s_values + 2 * d.l_values) as f64),
            Kernel::ReduceRhs => {
                // r̃x (2mC), two triangular solves (2C²), N w (6C), the wrench (12).
                let flops = np * (2.0 * m * c + 2.0 * c * c + 6.0 * c + 12.0) + nc * 72.0;
                (flops, 8.0 * (2.0 * n + 2.0 * mg + np * c * (c + 1.0) / 2.0 + 2.0 * me))
            }
            Kernel::TriangularSolve => (4.0 * d.l_values as f64, 8.0 * (d.l_values as f64 + 4.0 * me)),
            Kernel::BackSubstitute => {
                // Motion at the point (6C + 12), two triangular solves (2C²), G x (2mC).
                let flops = np * (2.0 * m * c + 2.0 * c * c + 6.0 * c + 12.0) + nc * 72.0;
                (flops, 8.0 * (3.0 * n + 3.0 * mg + np * c * (c + 1.0) / 2.0 + me))
            }
            Kernel::RefineResidual => {
                // A x, Aᵀz, Hs z, P x and the difference with the right-hand side.
                (a_mul + at_mul + 2.0 * mg + 2.0 * n + 2.0 * (n + me + mg), 8.0 * (4.0 * n + 6.0 * mg + 3.0 * me))
            }
            Kernel::StepLength => (2.0 * 2.0 * mg, 8.0 * 4.0 * mg),
            Kernel::Setup | Kernel::Solve => return None,
        };
        Some(cost)
    }
}

/// A structured solve's sizes, for [`Kernel::cost`].
#[derive(Clone, Copy, Debug, Default)]
pub struct Dims {
    /// Force points (interface vertices) of the problem.
    pub points: usize,
    /// Variables per point (C).
    pub per_point: usize,
    /// Inequality rows per point (the cone's three counted as rows).
    pub rows_per_point: usize,
    /// Whether the friction cones are second-order (the cone model) rather than polyhedral.
    pub soc: bool,
    /// Interfaces (contacts) of the problem.
    pub contacts: usize,
    /// Free blocks (6 equality rows each).
    pub blocks: usize,
    /// Equality rows (S's order).
    pub m_e: usize,
    /// Stored entries of S's lower triangle.
    pub s_values: usize,
    /// Stored entries of S's Cholesky factor.
    pub l_values: usize,
    /// Flops of one numeric factorisation (Σ over S's factor columns of their count squared).
    pub factor_flops: f64,
}

/// Accumulated time and calls per kernel, and the last solve's sizes.
#[derive(Clone, Debug, Default)]
pub struct Profile {
    /// Accumulated wall-clock time per kernel, in the order of [`Kernel::ALL`].
    pub time: [Duration; 11],
    /// Calls per kernel, in the same order.
    pub calls: [u64; 11],
    /// The last solve's sizes.
    pub dims: Dims,
}

impl Profile {
    /// Kernel `k`'s accumulated time and number of calls.
    pub fn of(&self, k: Kernel) -> (Duration, u64) {
        (self.time[k.index()], self.calls[k.index()])
    }
}

thread_local! {
    static PROFILE: RefCell<Profile> = RefCell::new(Profile::default());
}

/// Turns the timers on or off (all threads).
pub fn enable(on: bool) {
    ON.store(on, Ordering::Relaxed);
}

/// This thread's accumulated profile, cleared.
pub fn take() -> Profile {
    PROFILE.with(|p| std::mem::take(&mut *p.borrow_mut()))
}

/// A measurement switch (all threads): S factored by faer's supernodal Cholesky even where
/// the 6×6-block one is chosen, so that benches compare both in one run. On by default.
pub fn factor_by_blocks(on: bool) {
    BLOCKS.store(on, Ordering::Relaxed);
}

pub(super) fn blocks_on() -> bool {
    BLOCKS.load(Ordering::Relaxed)
}

/// Adds `other` (another thread's, [`take`]n there) to this thread's profile: a solve run on
/// rayon's pool brings its times back to the thread that asked for it.
pub(super) fn merge(other: Profile) {
    if ON.load(Ordering::Relaxed) {
        PROFILE.with(|p| {
            let mut p = p.borrow_mut();
            for k in 0..p.time.len() {
                p.time[k] += other.time[k];
                p.calls[k] += other.calls[k];
            }
            p.dims = other.dims;
        });
    }
}

pub(super) fn record_dims(d: impl FnOnce() -> Dims) {
    if ON.load(Ordering::Relaxed) {
        let d = d();
        PROFILE.with(|p| p.borrow_mut().dims = d);
    }
}

/// Times `kernel` until dropped (nothing when the timers are off).
pub(super) struct Timer(Option<(Kernel, Instant)>);

impl Timer {
    pub fn start(kernel: Kernel) -> Self {
        Self(ON.load(Ordering::Relaxed).then(|| (kernel, Instant::now())))
    }
}

impl Drop for Timer {
    fn drop(&mut self) {
        if let Some((k, t)) = self.0 {
            let dt = t.elapsed();
            PROFILE.with(|p| {
                let mut p = p.borrow_mut();
                p.time[k.index()] += dt;
                p.calls[k.index()] += 1;
            });
        }
    }
}
