//! Complete enumeration of complementary bases.
#![allow(non_snake_case)]

use std::cell::Cell;

use serde::{Deserialize, Serialize};

use crate::dense::{Lu, refine};
use crate::error::rules;

/// Above this relative residual a candidate gets a step of iterative refinement.
const REFINE_ABOVE: f64 = 1e-14;
use crate::solution::{check_warm_start, finish_row_major};
use crate::{LcpError, LcpRef, Method, Residual, Solution, Solver, Status};

/// Largest `max_n` accepted: 2^26 bases is already hours of work.
const MAX_N_LIMIT: usize = 26;

/// Largest `max_n_degenerate` accepted: C(28, 14) = 4e7 systems.
const MAX_N_DEGENERATE_LIMIT: usize = 14;

/// Two solutions whose z differ by at most this fraction of `max(1, ‖z‖∞)` are the same.
const DEDUP_RELATIVE: f64 = 1e-7;

/// Options of [`Enumeration`]: the default, changed field by field with the `with_*` setters
/// (or by assigning the fields of a default value).
///
/// ```
/// use moreau_lcp::{Enumeration, EnumerationOptions};
///
/// # fn main() -> Result<(), moreau_lcp::LcpError> {
/// let options = EnumerationOptions::default().with_max_n(14).with_tolerance(1e-10);
/// assert_eq!((options.max_n, options.tolerance), (14, 1e-10));
/// let solver = Enumeration::new(options)?;
/// # let _ = solver;
/// # Ok(())
/// # }
/// ```
///
/// The struct is `#[non_exhaustive]`, so that fields added later keep their defaults in
/// callers' code; a struct literal does not compile outside this crate:
///
/// ```compile_fail,E0639
/// let options = moreau_lcp::EnumerationOptions { max_n: 14, ..Default::default() };
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct EnumerationOptions {
    /// Size guard: problems with n > `max_n` return [`LcpError::TooLarge`]. The work is
    /// 2^n LU factorisations of size up to n. Default 20 (about a million bases, around a
    /// second); at most 26.
    pub max_n: usize,
    /// Acceptance tolerance on [`Residual::relative`] (dimensionless), in (0, 1). Default
    /// 1e-9.
    pub tolerance: f64,
    /// Largest n for the second, complete vertex search that runs when some principal
    /// submatrix `M_αα` is singular: sum over k of C(n, k)^2 = C(2n, n) square systems
    /// `M_SK` (C(24, 12) = 2.7 million for n = 12, about a second). Default 12; at most
    /// 14 and at most `max_n`.
    pub max_n_degenerate: usize,
}

with_setters!(EnumerationOptions {
    with_max_n => max_n: usize,
    with_tolerance => tolerance: f64,
    with_max_n_degenerate => max_n_degenerate: usize,
});

impl Default for EnumerationOptions {
    fn default() -> Self {
        EnumerationOptions { max_n: 20, tolerance: 1e-9, max_n_degenerate: 12 }
    }
}

impl EnumerationOptions {
    pub(crate) fn validate(&self) -> Result<(), LcpError> {
        let bad =
            |name: &'static str, reason: String| Err(LcpError::InvalidOption { name, reason });
        if self.max_n == 0 || self.max_n > MAX_N_LIMIT {
            return bad("max_n", format!("must be in 1..={MAX_N_LIMIT}"));
        }
        if self.max_n_degenerate > self.max_n.min(MAX_N_DEGENERATE_LIMIT) {
            return bad(
                "max_n_degenerate",
                format!("must not exceed max_n nor {MAX_N_DEGENERATE_LIMIT}"),
            );
        }
        rules::relative_tolerance(self.tolerance)
    }
}

/// Complete enumeration of the complementary bases of LCP(M, q).
///
/// **Principal pass.** For every index set α ⊆ {1..n} (2^n of them) it solves
/// `M_αα z_α = -q_α` with an LU factorisation, sets `z_i = 0` for i ∉ α and
/// `w = M z + q`, and keeps z when [`Residual::relative`] `<= tolerance`. When every
/// `M_αα` is nonsingular (M nondegenerate) every solution is found this way: a solution
/// with support α has `w_α = 0`, so `z_α` is the unique solution of that system.
///
/// **Vertex pass.** If some `M_αα` was singular (as in the friction LCP, whose last
/// diagonal block is zero) solutions can hide from the principal pass (for example
/// M = [[0, 0], [1, 0]], q = (0, -1), solved by z = (1, 0)). Every nonempty solution face
/// of the polyhedron {z >= 0, M z + q >= 0} contains one of its vertices, and the
/// vertices are the solutions of `M_SK z_K = -q_S`, `z_i = 0` for i ∉ K, over pairs
/// |S| = |K| with `M_SK` nonsingular. For n <= `max_n_degenerate` these are all tried
/// too, so the search stays complete.
///
/// The status is [`Status::Solved`] for the first solution found, [`Status::NoSolution`]
/// when the search was complete and found none (a certificate, up to the numerical rank
/// decisions of the LU pivots), and [`Status::TooLarge`] when the principal pass found
/// nothing, some `M_αα` was singular and n > `max_n_degenerate`.
/// [`Enumeration::solve_all`] returns every solution found, deduplicated. Problems with
/// n > `max_n` are refused with [`LcpError::TooLarge`].
///
/// # References
/// - R. W. Cottle, J.-S. Pang, R. E. Stone, The Linear Complementarity Problem, Academic
///   Press, 1992, §1.3 and §3.
/// - F. Pfeiffer, C. Glocker, Multibody Dynamics with Unilateral Contacts, Wiley, 1996;
///   C. Glocker, Set-Valued Force Laws, Springer, 2001.
pub struct Enumeration {
    options: EnumerationOptions,
    m_rows: Vec<f64>,
    q: Vec<f64>,
    rows: Vec<usize>,
    cols: Vec<usize>,
    rhs: Vec<f64>,
    scratch: Vec<f64>,
    by_count: Vec<u32>,
    by_count_n: usize,
    lu: Lu,
    /// Whether a basis of the current search gave a z or a w = M z + q beyond f64's range:
    /// a solution may then exist that no f64 candidate represents, so the search proves
    /// nothing.
    overflowed: bool,
}

impl Default for Enumeration {
    fn default() -> Self {
        Enumeration {
            options: EnumerationOptions::default(),
            m_rows: Vec::new(),
            q: Vec::new(),
            rows: Vec::new(),
            cols: Vec::new(),
            rhs: Vec::new(),
            scratch: Vec::new(),
            by_count: Vec::new(),
            by_count_n: usize::MAX,
            lu: Lu::default(),
            overflowed: false,
        }
    }
}

/// What a visitor wants after seeing a solution.
#[derive(PartialEq)]
enum Next {
    Stop,
    Continue,
}

impl Enumeration {
    /// A solver with the given options.
    ///
    /// # Errors
    /// [`LcpError::InvalidOption`] for out-of-range options.
    pub fn new(options: EnumerationOptions) -> Result<Enumeration, LcpError> {
        options.validate()?;
        Ok(Enumeration { options, ..Enumeration::default() })
    }

    /// The options in use.
    pub fn options(&self) -> &EnumerationOptions {
        &self.options
    }

    /// Every solution found by the complete search, deduplicated (z within 1e-7 of
    /// `max(1, ‖z‖∞)`), each with status [`Status::Solved`]. An empty vector means no
    /// solution.
    ///
    /// # Errors
    /// [`LcpError::TooLarge`] when n > `max_n`, or when some `M_αα` is singular and
    /// n > `max_n_degenerate` (`max` is then `max_n_degenerate`): the vertex pass that a
    /// complete search needs is beyond the size guard, so the list may miss solutions, as
    /// [`Status::TooLarge`] says for [`Solver::solve_into`]; [`LcpError::Overflow`] when
    /// some basis gave a z or a w = M z + q beyond f64's range, so that the list may miss
    /// solutions.
    pub fn solve_all(&mut self, lcp: LcpRef<'_>) -> Result<Vec<Solution>, LcpError> {
        let n = self.prepare(lcp)?;
        let mut found: Vec<Solution> = Vec::new();
        let mut z = vec![0.0; n];
        let mut w = vec![0.0; n];
        let mut examined = 0;
        let mut keep = |z: &[f64], w: &[f64], r: Residual, examined: usize| {
            let scale = z.iter().fold(1.0f64, |a, v| a.max(v.abs()));
            let duplicate = found.iter().any(|s| {
                let s_scale = s.z.iter().fold(scale, |a, v| a.max(v.abs()));
                s.z.iter().zip(z).all(|(a, b)| (a - b).abs() <= DEDUP_RELATIVE * s_scale)
            });
            if !duplicate {
                found.push(Solution {
                    status: Status::Solved,
                    method: Method::Enumeration,
                    z: z.to_vec(),
                    w: w.to_vec(),
                    iterations: examined,
                    residual: r,
                });
            }
            Next::Continue
        };
        let singular = self.principal_pass(n, &mut z, &mut w, &mut examined, &mut keep);
        let max = self.options.max_n_degenerate;
        let complete = singular == 0 || n <= max;
        if !complete {
            return Err(LcpError::TooLarge { n, max });
        }
        if singular > 0 {
            self.vertex_pass(n, &mut z, &mut w, &mut examined, &mut keep);
        }
        if self.overflowed {
            return Err(LcpError::Overflow);
        }
        Ok(found)
    }

    fn prepare(&mut self, lcp: LcpRef<'_>) -> Result<usize, LcpError> {
        let n = lcp.n();
        if n > self.options.max_n {
            return Err(LcpError::TooLarge { n, max: self.options.max_n });
        }
        self.m_rows.resize(n * n, 0.0);
        self.q.resize(n, 0.0);
        self.rhs.resize(n, 0.0);
        self.scratch.resize(n, 0.0);
        if self.rows.capacity() < n {
            self.rows.reserve(n);
            self.cols.reserve(n);
        }
        self.lu.reserve(n);
        lcp.copy_m_row_major(&mut self.m_rows);
        lcp.copy_q(&mut self.q);
        self.overflowed = false;
        Ok(n)
    }

    /// Solves `M_{rows, cols} z_cols = -q_rows` into z (zero elsewhere, clamped at 0);
    /// returns the residual, or `None` if the system is singular.
    fn candidate(&mut self, n: usize, z: &mut [f64], w: &mut [f64]) -> Option<Residual> {
        let k = self.cols.len();
        let (m, rows, cols) = (&self.m_rows, &self.rows, &self.cols);
        if !self.lu.factor_with(k, |i, j| m[rows[i] * n + cols[j]]) {
            return None;
        }
        for (t, &i) in self.rows.iter().enumerate() {
            self.rhs[t] = -self.q[i];
        }
        self.lu.solve(&mut self.rhs);
        if self.rhs[..k].iter().any(|v| !v.is_finite()) {
            self.overflowed = true;
            return Some(Residual::INFINITE);
        }
        // Cheap rejection before the O(n^2) residual: a clearly negative z_j.
        let zmax = self.rhs[..k].iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if self.rhs[..k].iter().any(|&v| v < -1e-6 * zmax) {
            return Some(Residual::INFINITE);
        }
        let mut r = self.scatter(n, z, w);
        if r.relative > REFINE_ABOVE {
            refine(
                &mut self.lu,
                &self.m_rows,
                n,
                &self.rows,
                &self.cols,
                &self.q,
                &mut self.rhs,
                &mut self.scratch,
            );
            let r2 = self.scatter(n, z, w);
            if r2.relative < r.relative {
                r = r2;
            } else {
                for (t, &i) in self.rows.iter().enumerate() {
                    self.rhs[t] = -self.q[i];
                }
                self.lu.solve(&mut self.rhs);
                r = self.scatter(n, z, w);
            }
        }
        Some(r)
    }

    /// z = the solution in `rhs` on `cols` (clamped at 0, zero elsewhere), w = M z + q.
    fn scatter(&mut self, n: usize, z: &mut [f64], w: &mut [f64]) -> Residual {
        z.fill(0.0);
        for (t, &j) in self.cols.iter().enumerate() {
            z[j] = self.rhs[t].max(0.0);
        }
        let r = finish_row_major(&self.m_rows, n, &self.q, z, w);
        if w.iter().any(|v| !v.is_finite()) {
            self.overflowed = true;
        }
        r
    }

    /// Tries every principal basis; returns the number of singular `M_αα`.
    fn principal_pass(
        &mut self,
        n: usize,
        z: &mut [f64],
        w: &mut [f64],
        examined: &mut usize,
        visit: &mut impl FnMut(&[f64], &[f64], Residual, usize) -> Next,
    ) -> usize {
        let mut singular = 0;
        for mask in 0u32..(1u32 << n) {
            self.cols.clear();
            self.cols.extend((0..n).filter(|&i| mask & (1 << i) != 0));
            self.rows.clear();
            self.rows.extend_from_slice(&self.cols);
            *examined += 1;
            match self.candidate(n, z, w) {
                None => singular += 1,
                Some(r) if r.relative <= self.options.tolerance => {
                    if visit(z, w, r, *examined) == Next::Stop {
                        return singular;
                    }
                }
                Some(_) => {}
            }
        }
        singular
    }

    /// Tries every vertex `M_SK z_K = -q_S` with |S| = |K| and S != K; returns `true` if
    /// the visitor stopped the search.
    fn vertex_pass(
        &mut self,
        n: usize,
        z: &mut [f64],
        w: &mut [f64],
        examined: &mut usize,
        visit: &mut impl FnMut(&[f64], &[f64], Residual, usize) -> Next,
    ) -> bool {
        if self.by_count_n != n {
            self.by_count.clear();
            self.by_count.extend(0u32..(1u32 << n));
            self.by_count.sort_by_key(|m| (m.count_ones(), *m));
            self.by_count_n = n;
        }
        let mut start = 0;
        while start < self.by_count.len() {
            let k = self.by_count[start].count_ones();
            let end =
                start + self.by_count[start..].iter().take_while(|m| m.count_ones() == k).count();
            for a in start..end {
                for b in start..end {
                    let (kmask, smask) = (self.by_count[a], self.by_count[b]);
                    if kmask == smask {
                        continue;
                    }
                    self.cols.clear();
                    self.cols.extend((0..n).filter(|&i| kmask & (1 << i) != 0));
                    self.rows.clear();
                    self.rows.extend((0..n).filter(|&i| smask & (1 << i) != 0));
                    *examined += 1;
                    if let Some(r) = self.candidate(n, z, w)
                        && r.relative <= self.options.tolerance
                        && visit(z, w, r, *examined) == Next::Stop
                    {
                        return true;
                    }
                }
            }
            start = end;
        }
        false
    }
}

impl Solver for Enumeration {
    fn solve_into(
        &mut self,
        lcp: LcpRef<'_>,
        warm_start: Option<&[f64]>,
        out: &mut Solution,
    ) -> Result<(), LcpError> {
        check_warm_start(lcp.n(), warm_start)?;
        let n = self.prepare(lcp)?;
        out.reset(n, Method::Enumeration);
        let mut examined = 0;
        let best: Cell<Option<Residual>> = Cell::new(None);
        let mut stop = |_: &[f64], _: &[f64], r: Residual, _: usize| {
            best.set(Some(r));
            Next::Stop
        };
        let mut z = std::mem::take(&mut out.z);
        let mut w = std::mem::take(&mut out.w);
        let singular = self.principal_pass(n, &mut z, &mut w, &mut examined, &mut stop);
        let complete = if best.get().is_none() && singular > 0 {
            if n <= self.options.max_n_degenerate {
                self.vertex_pass(n, &mut z, &mut w, &mut examined, &mut stop);
                true
            } else {
                false
            }
        } else {
            true
        };
        out.z = z;
        out.w = w;
        out.iterations = examined;
        match best.get() {
            Some(r) => {
                out.residual = r;
                out.status = Status::Solved;
            }
            None => {
                out.z.fill(0.0);
                out.residual = finish_row_major(&self.m_rows, n, &self.q, &out.z, &mut out.w);
                // A basis whose z or w overflowed may hold a solution that f64 cannot
                // represent: the search then proves nothing.
                out.status = if self.overflowed {
                    Status::NumericalFailure
                } else if complete {
                    Status::NoSolution
                } else {
                    Status::TooLarge
                };
            }
        }
        Ok(())
    }
}
