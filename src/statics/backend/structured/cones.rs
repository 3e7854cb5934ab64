//! The inequality rows' cones and their Nesterov–Todd scaling, as in clarabel: the
//! non-negative rows (scaling s/z) and one three-row second-order cone per force point for
//! the cone model (scaling W = η(2wwᵀ − J) applied in ECOS' fast product form, Hs = WᵀW).
//!
//! Row layout: `per_point` rows per point (the first `nonneg` non-negative, then the cone's
//! three), then `tail` non-negative rows (the budgets' σ ≥ 0).

/// Where the cones sit in the inequality vectors.
#[derive(Clone, Copy, Debug)]
pub struct Layout {
    pub points: usize,
    pub per_point: usize,
    pub nonneg: usize,
    pub soc: bool,
    pub tail: usize,
}

impl Layout {
    pub fn len(&self) -> usize {
        self.points * self.per_point + self.tail
    }

    /// Barrier degree: one per non-negative row, one per second-order cone.
    pub fn degree(&self) -> usize {
        self.points * (self.nonneg + self.soc as usize) + self.tail
    }

    /// Calls `f(range)` for every run of non-negative rows.
    fn for_nonneg(&self, mut f: impl FnMut(std::ops::Range<usize>)) {
        if self.soc {
            for p in 0..self.points {
                let at = p * self.per_point;
                f(at..at + self.nonneg);
            }
        } else {
            f(0..self.points * self.per_point);
        }
        let end = self.points * self.per_point;
        f(end..end + self.tail);
    }

    /// Start of point p's cone rows.
    fn soc_at(&self, p: usize) -> usize {
        p * self.per_point + self.nonneg
    }
}

fn soc_residual(v: &[f64]) -> f64 {
    let n1 = (v[1] * v[1] + v[2] * v[2]).sqrt();
    (v[0] - n1) * (v[0] + n1)
}

fn sqrt_soc_residual(v: &[f64]) -> f64 {
    let r = soc_residual(v);
    if r > 0.0 { r.sqrt() } else { 0.0 }
}

/// The scaling of the current iterate.
pub struct Scaling {
    pub layout: Layout,
    /// s/z and z/s for the non-negative rows (entries at cone rows unused).
    pub d: Vec<f64>,
    pub dinv: Vec<f64>,
    /// Per point (cone model): w and η of W = η[w₀ w₁ᵀ; w₁ I + w₁w₁ᵀ/(1 + w₀)], λ = Wz.
    /// Hs = WᵀW is never formed: with a scaling point far from the cone's axis its explicit
    /// form η²(2wwᵀ − J) cancels catastrophically.
    w: Vec<[f64; 3]>,
    eta: Vec<f64>,
    lambda: Vec<[f64; 3]>,
}

impl Scaling {
    /// Identity scaling (Hs = I), for the initial point.
    pub fn identity(layout: Layout) -> Self {
        let m = layout.len();
        let k = if layout.soc { layout.points } else { 0 };
        Self {
            layout,
            d: vec![1.0; m],
            dinv: vec![1.0; m],
            w: vec![[1.0, 0.0, 0.0]; k],
            eta: vec![1.0; k],
            lambda: vec![[0.0; 3]; k],
        }
    }

    /// Nesterov–Todd scaling at (s, z); false when either is not strictly inside its cone.
    pub fn update(&mut self, s: &[f64], z: &[f64]) -> bool {
        let mut ok = true;
        let (d, dinv) = (&mut self.d, &mut self.dinv);
        self.layout.for_nonneg(|r| {
            // The divisions in one loop without branches (vectorised), the check in another.
            let pairs = s[r.clone()].iter().zip(&z[r.clone()]);
            for ((di, vi), (si, zi)) in d[r.clone()].iter_mut().zip(&mut dinv[r.clone()]).zip(pairs) {
                *di = si / zi;
                *vi = zi / si;
            }
            ok &= r.into_iter().all(|i| s[i] > 0.0 && z[i] > 0.0);
        });
        if !ok {
            return false;
        }
        if !self.layout.soc {
            return true;
        }
        for p in 0..self.layout.points {
            let at = self.layout.soc_at(p);
            let (sp, zp) = (&s[at..at + 3], &z[at..at + 3]);
            let zscale = sqrt_soc_residual(zp);
            let sscale = sqrt_soc_residual(sp);
            if zscale == 0.0 || sscale == 0.0 {
                return false;
            }
            let eta = (sscale / zscale).sqrt();
            let mut w = [0.0; 3];
            for i in 0..3 {
                w[i] = sp[i] / sscale;
            }
            w[0] += zp[0] / zscale;
            for i in 1..3 {
                w[i] -= zp[i] / zscale;
            }
            let wscale = sqrt_soc_residual(&w);
            if wscale == 0.0 {
                return false;
            }
            for v in w.iter_mut() {
                *v /= wscale;
            }
            w[0] = (1.0 + w[1] * w[1] + w[2] * w[2]).sqrt();
            let gamma = 0.5 * wscale;
            let mut lam = [gamma, 0.0, 0.0];
            let a = (gamma + zp[0] / zscale) / sscale;
            let b = (gamma + sp[0] / sscale) / zscale;
            let den = sp[0] / sscale + zp[0] / zscale + 2.0 * gamma;
            for i in 1..3 {
                lam[i] = (a * sp[i] + b * zp[i]) / den;
            }
            let f = (sscale * zscale).sqrt();
            for v in lam.iter_mut() {
                *v *= f;
            }
            self.w[p] = w;
            self.eta[p] = eta;
            self.lambda[p] = lam;
        }
        true
    }

    /// `W x` for point p's cone (ECOS' fast product).
    pub fn w_mul(&self, p: usize, x: &[f64; 3]) -> [f64; 3] {
        let (w, eta) = (&self.w[p], self.eta[p]);
        let zeta = w[1] * x[1] + w[2] * x[2];
        let c = x[0] + zeta / (1.0 + w[0]);
        [eta * (w[0] * x[0] + zeta), eta * (c * w[1] + x[1]), eta * (c * w[2] + x[2])]
    }

    /// `W⁻¹ x` for point p's cone.
    pub fn winv_mul(&self, p: usize, x: &[f64; 3]) -> [f64; 3] {
        let (w, eta) = (&self.w[p], self.eta[p]);
        let zeta = w[1] * x[1] + w[2] * x[2];
        let c = -x[0] + zeta / (1.0 + w[0]);
        [(w[0] * x[0] - zeta) / eta, (c * w[1] + x[1]) / eta, (c * w[2] + x[2]) / eta]
    }

    /// `Hs x = W W x` for point p's cone.
    pub fn hs_mul(&self, p: usize, x: &[f64; 3]) -> [f64; 3] {
        self.w_mul(p, &self.w_mul(p, x))
    }

    /// `Hs⁻¹ x = W⁻¹ W⁻¹ x` for point p's cone.
    pub fn hs_inv_mul(&self, p: usize, x: &[f64; 3]) -> [f64; 3] {
        self.winv_mul(p, &self.winv_mul(p, x))
    }

    /// `Δs = −(Hs Δz + c)`.
    pub fn ds_from_dz(&self, dz: &[f64], c: &[f64], ds: &mut [f64]) {
        let d = &self.d;
        self.layout.for_nonneg(|r| {
            for i in r {
                ds[i] = -c[i] - d[i] * dz[i];
            }
        });
        if self.layout.soc {
            for p in 0..self.layout.points {
                let at = self.layout.soc_at(p);
                let hz = self.hs_mul(p, &[dz[at], dz[at + 1], dz[at + 2]]);
                for r in 0..3 {
                    ds[at + r] = -c[at + r] - hz[r];
                }
            }
        }
    }

    /// The Δs constant term of the combined step, `Wᵀ(λ \ ds)` with
    /// `ds = λ∘λ + (W⁻¹Δs_a)∘(W m Δz_a) − σμe` (the Mehrotra correction of the affine step).
    #[allow(clippy::too_many_arguments)]
    pub fn combined_const(
        &self,
        s: &[f64],
        z: &[f64],
        ds_a: &[f64],
        dz_a: &[f64],
        m: f64,
        sigma_mu: f64,
        out: &mut [f64],
    ) {
        self.layout.for_nonneg(|r| {
            for i in r {
                out[i] = (s[i] * z[i] + m * ds_a[i] * dz_a[i] - sigma_mu) / z[i];
            }
        });
        if !self.layout.soc {
            return;
        }
        for p in 0..self.layout.points {
            let at = self.layout.soc_at(p);
            let (w, eta, lam) = (&self.w[p], self.eta[p], &self.lambda[p]);
            let wdz = self.w_mul(p, &[m * dz_a[at], m * dz_a[at + 1], m * dz_a[at + 2]]);
            let wids = self.winv_mul(p, &[ds_a[at], ds_a[at + 1], ds_a[at + 2]]);
            // ds = λ∘λ + W⁻¹Δs ∘ WΔz − σμe.
            let circ = |a: &[f64; 3], b: &[f64; 3]| -> [f64; 3] {
                [a[0] * b[0] + a[1] * b[1] + a[2] * b[2], a[0] * b[1] + b[0] * a[1], a[0] * b[2] + b[0] * a[2]]
            };
            let ll = circ(lam, lam);
            let sh = circ(&wids, &wdz);
            let ds = [ll[0] + sh[0] - sigma_mu, ll[1] + sh[1], ll[2] + sh[2]];
            // out = Wᵀ(λ \ ds), clarabel's stable form.
            let zp = &z[at..at + 3];
            let resz = soc_residual(zp);
            let l1ds1 = lam[1] * ds[1] + lam[2] * ds[2];
            let w1ds1 = w[1] * ds[1] + w[2] * ds[2];
            let cc = (lam[0] * ds[0] - l1ds1) / resz;
            let mut o = [zp[0] * cc, -zp[1] * cc, -zp[2] * cc];
            o[0] += eta * w1ds1;
            for i in 1..3 {
                o[i] += eta * (ds[i] + w1ds1 / (1.0 + w[0]) * w[i]);
            }
            for i in 0..3 {
                out[at + i] = o[i] / lam[0];
            }
        }
    }

    /// Largest step in (0, cap] keeping `v + α dv` in the cones.
    pub fn step_length(&self, v: &[f64], dv: &[f64], cap: f64) -> f64 {
        let mut a = cap;
        self.layout.for_nonneg(|r| a = nonneg_step(&v[r.clone()], &dv[r], a));
        if self.layout.soc {
            for p in 0..self.layout.points {
                let at = self.layout.soc_at(p);
                a = soc_step(&v[at..at + 3], &dv[at..at + 3], a);
            }
        }
        a
    }
}

/// Largest step in (0, cap] keeping `v + α dv ≥ 0`: the least −v/dv over dv < 0, in four
/// lanes without branches so that the compiler vectorises it (the minimum of the same set,
/// so the same bits as a scalar loop).
fn nonneg_step(v: &[f64], dv: &[f64], cap: f64) -> f64 {
    let mut lanes = [cap; 4];
    let (vc, dc) = (v.chunks_exact(4), dv.chunks_exact(4));
    let (v_rest, d_rest) = (vc.remainder(), dc.remainder());
    for (v4, d4) in vc.zip(dc) {
        // Every lane divided, then selected: a branch per row keeps the compiler from
        // vectorising the divisions.
        let q: [f64; 4] = std::array::from_fn(|k| -v4[k] / d4[k]);
        for k in 0..4 {
            let r = if d4[k] < 0.0 { q[k] } else { f64::INFINITY };
            lanes[k] = if r < lanes[k] { r } else { lanes[k] };
        }
    }
    for (vi, di) in v_rest.iter().zip(d_rest) {
        let r = if *di < 0.0 { -vi / di } else { f64::INFINITY };
        lanes[0] = if r < lanes[0] { r } else { lanes[0] };
    }
    lanes.iter().fold(cap, |a, l| if *l < a { *l } else { a })
}

/// clarabel's step to the boundary of one second-order cone.
fn soc_step(x: &[f64], y: &[f64], cap: f64) -> f64 {
    let mut amax = cap;
    if x[0] >= 0.0 && y[0] < 0.0 {
        amax = amax.min(-x[0] / y[0]);
    }
    let a = soc_residual(y);
    let b = 2.0 * (x[0] * y[0] - x[1] * y[1] - x[2] * y[2]);
    let c = soc_residual(x).max(0.0);
    let d = b * b - 4.0 * a * c;
    if (a > 0.0 && b > 0.0) || d < 0.0 || a == 0.0 {
        return amax;
    }
    if c == 0.0 {
        return if a >= 0.0 { amax } else { 0.0 };
    }
    let t = if b >= 0.0 { -b - d.sqrt() } else { -b + d.sqrt() };
    let r1 = (2.0 * c) / t;
    let r2 = t / (2.0 * a);
    let r1 = if r1 < 0.0 { f64::INFINITY } else { r1 };
    let r2 = if r2 < 0.0 { f64::INFINITY } else { r2 };
    amax.min(r1).min(r2)
}

/// Shifts `v` into the interior of the cones (clarabel's symmetric initialisation).
pub fn shift_to_interior(layout: &Layout, v: &mut [f64]) {
    if layout.len() == 0 {
        return;
    }
    let mut min = f64::INFINITY;
    let mut pos = 0.0;
    layout.for_nonneg(|r| {
        for i in r {
            min = min.min(v[i]);
            pos += v[i].max(0.0);
        }
    });
    if layout.soc {
        for p in 0..layout.points {
            let at = layout.soc_at(p);
            let margin = v[at] - (v[at + 1] * v[at + 1] + v[at + 2] * v[at + 2]).sqrt();
            min = min.min(margin);
            pos += margin.max(0.0);
        }
    }
    let target = (0.1 * pos / layout.degree() as f64).max(1.0);
    let shift = if min <= 0.0 {
        -min + target
    } else if min < target {
        target - min
    } else {
        return;
    };
    let mut add = |i: usize| v[i] += shift;
    layout.for_nonneg(|r| r.for_each(&mut add));
    if layout.soc {
        for p in 0..layout.points {
            v[layout.soc_at(p)] += shift;
        }
    }
}
