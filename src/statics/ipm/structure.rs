//! Presolve and block structure of a [`Problem`] for the structured interior-point method.
//!
//! The equilibrium problems have a shape a general sparse LDL does not see: every inequality
//! row touches the few variables of one force point (its *group*), and only the equality rows
//! (6 per block, plus budgets) couple groups. This module finds that shape from the plain
//! data, so that the KKT system can be reduced to the equality rows alone:
//! - equality rows with one entry fix their variable (the pinned `c_n⁻ = 0` rows): the
//!   variable leaves the problem;
//! - variables linked by inequality rows form groups (union–find, shortest rows first);
//!   a row that would make a group larger than [`MAX_GROUP`] (the budgets Σ c_n⁻ ≤ T,
//!   Σ s ≤ F) becomes an equality row with a slack variable `σ ≥ 0` of its own.
//!
//! Returns `None` when the problem does not have that shape (second-order cones, a group of
//! more than [`MAX_GROUP`] variables, an infeasible fixed row): the caller falls back to
//! clarabel.

use super::super::assemble::{Cone, Problem};

/// Inequality rows with more entries than this are coupling rows (budgets).
const MAX_LOCAL_ROW: usize = 8;
/// Largest group (variables of one force point: at most 5 in the relaxed layout).
pub const MAX_GROUP: usize = 8;

/// A sparse row: (reduced column, value).
pub type Row = Vec<(usize, f64)>;

/// The reduced problem: minimise ½ xᵀ diag(p) x + qᵀx s.t. E x = b_e, G x + s = h, s ≥ 0.
#[derive(Clone, Debug)]
pub struct Structured {
    /// Reduced variables (kept originals, then one slack per coupling row).
    pub n: usize,
    pub p: Vec<f64>,
    pub q: Vec<f64>,
    pub e_rows: Vec<Row>,
    pub b_e: Vec<f64>,
    pub g_rows: Vec<Row>,
    pub h: Vec<f64>,
    /// Groups: their variables (sorted) and their inequality rows.
    pub groups: Vec<Group>,
    /// Original column → `Ok(reduced column)` or `Err(fixed value)`.
    pub original: Vec<Result<usize, f64>>,
}

#[derive(Clone, Debug, Default)]
pub struct Group {
    pub cols: Vec<usize>,
    pub g_rows: Vec<usize>,
}

fn find(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

impl Structured {
    pub fn new(p: &Problem) -> Option<Self> {
        let m = p.m();
        let mut zero_rows = 0;
        let mut at = 0;
        for c in &p.cones {
            match *c {
                Cone::Zero(k) if at == 0 => zero_rows = k,
                Cone::Zero(0) | Cone::Nonnegative(_) => {}
                // Zero cones after the first, or second-order cones: not this solver's shape.
                _ => return None,
            }
            at += match *c {
                Cone::Zero(k) | Cone::Nonnegative(k) | Cone::SecondOrder(k) => k,
            };
        }
        if at != m {
            return None;
        }
        // Rows with duplicates summed, columns sorted.
        let mut rows: Vec<Row> = vec![Vec::new(); m];
        for &(i, j, v) in &p.a {
            rows[i].push((j, v));
        }
        for r in rows.iter_mut() {
            r.sort_unstable_by_key(|e| e.0);
            r.dedup_by(|a, b| {
                if a.0 == b.0 {
                    b.1 += a.1;
                    true
                } else {
                    false
                }
            });
            r.retain(|e| e.1 != 0.0);
        }
        // Fixed variables from singleton equality rows.
        let mut fixed: Vec<Option<f64>> = vec![None; p.n];
        let mut row_used = vec![false; m];
        for i in 0..zero_rows {
            if let [(j, a)] = rows[i][..] {
                let v = p.b[i] / a;
                match fixed[j] {
                    Some(w) if (w - v).abs() > 1e-12 * (1.0 + v.abs()) => return None,
                    _ => fixed[j] = Some(v),
                }
                row_used[i] = true;
            }
        }
        let mut original = Vec::with_capacity(p.n);
        let mut n = 0;
        for f in &fixed {
            original.push(match f {
                Some(v) => Err(*v),
                None => {
                    n += 1;
                    Ok(n - 1)
                }
            });
        }
        let reduce = |row: &Row, rhs: f64| -> (Row, f64) {
            let mut out = Vec::with_capacity(row.len());
            let mut rhs = rhs;
            for &(j, v) in row {
                match original[j] {
                    Ok(c) => out.push((c, v)),
                    Err(x) => rhs -= v * x,
                }
            }
            (out, rhs)
        };
        let mut p_diag: Vec<f64> = Vec::with_capacity(n);
        let mut q: Vec<f64> = Vec::with_capacity(n);
        for j in 0..p.n {
            if original[j].is_ok() {
                p_diag.push(p.p_diag[j]);
                q.push(p.q[j]);
            }
        }
        let (mut e_rows, mut b_e) = (Vec::new(), Vec::new());
        let mut ineq: Vec<(Row, f64)> = Vec::new();
        let tiny = 1e-12 * (1.0 + p.b.iter().fold(0.0f64, |a, v| a.max(v.abs())));
        for i in 0..m {
            if row_used[i] {
                continue;
            }
            let (row, rhs) = reduce(&rows[i], p.b[i]);
            if row.is_empty() {
                // 0 = rhs or 0 ≤ rhs: a constant row; infeasible ones are left to clarabel.
                let bad = if i < zero_rows { rhs.abs() > tiny } else { rhs < -tiny };
                if bad {
                    return None;
                }
                continue;
            }
            if i < zero_rows {
                e_rows.push(row);
                b_e.push(rhs);
            } else {
                ineq.push((row, rhs));
            }
        }
        // Groups: union–find over the inequality rows, shortest first. A row that would join
        // groups into more than MAX_GROUP variables (a budget over many points) becomes a
        // coupling row: a x ≤ rhs → a x + σ = rhs with σ ≥ 0 its own group.
        let mut order: Vec<usize> = (0..ineq.len()).collect();
        order.sort_by_key(|&k| ineq[k].0.len());
        let n0 = p_diag.len();
        let mut parent: Vec<usize> = (0..n0).collect();
        let mut size = vec![1usize; n0];
        let mut coupling = vec![false; ineq.len()];
        for &k in &order {
            let row = &ineq[k].0;
            let mut roots: Vec<usize> = row.iter().map(|&(j, _)| find(&mut parent, j)).collect();
            roots.sort_unstable();
            roots.dedup();
            let total: usize = roots.iter().map(|&r| size[r]).sum();
            if row.len() > MAX_LOCAL_ROW || total > MAX_GROUP {
                coupling[k] = true;
                continue;
            }
            for &r in &roots[1..] {
                parent[r] = roots[0];
            }
            size[roots[0]] = total;
        }
        let (mut g_rows, mut h) = (Vec::new(), Vec::new());
        for (k, (row, rhs)) in ineq.into_iter().enumerate() {
            if coupling[k] {
                let sigma = p_diag.len();
                p_diag.push(0.0);
                q.push(0.0);
                parent.push(sigma);
                let mut row = row;
                row.push((sigma, 1.0));
                e_rows.push(row);
                b_e.push(rhs);
                g_rows.push(vec![(sigma, -1.0)]);
                h.push(0.0);
            } else {
                g_rows.push(row);
                h.push(rhs);
            }
        }
        let n = p_diag.len();
        let mut group_of_root = vec![usize::MAX; n];
        let mut groups: Vec<Group> = Vec::new();
        for j in 0..n {
            let r = find(&mut parent, j);
            if group_of_root[r] == usize::MAX {
                group_of_root[r] = groups.len();
                groups.push(Group::default());
            }
            groups[group_of_root[r]].cols.push(j);
        }
        for (k, row) in g_rows.iter().enumerate() {
            let g = group_of_root[find(&mut parent, row[0].0)];
            groups[g].g_rows.push(k);
        }
        if groups.iter().any(|g| g.cols.len() > MAX_GROUP) {
            return None;
        }
        Some(Self { n, p: p_diag, q, e_rows, b_e, g_rows, h, groups, original })
    }

    /// The solution in the original variables.
    pub fn expand(&self, x: &[f64]) -> Vec<f64> {
        self.original
            .iter()
            .map(|o| match *o {
                Ok(c) => x[c],
                Err(v) => v,
            })
            .collect()
    }
}
