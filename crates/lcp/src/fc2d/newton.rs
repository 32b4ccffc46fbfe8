//! A nonsmooth Newton method on Alart and Curnier's function for planar frictional
//! contact, with sparse LU solves and an Armijo line search.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::linalg::lu::{NumericLu, SymbolicLu, factorize_symbolic_lu};
use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par};
use serde::{Deserialize, Serialize};

use super::residual::project_cone;
use super::solution::check_warm_start;
use super::{Fc2dRef, Fc2dResidual, Fc2dSolution, Fc2dSolver, Nsgs, NsgsOptions};
use crate::error::rules;
use crate::{LcpError, Method, Status};

/// How [`Newton`] chooses the augmentation parameters ρ of Alart and Curnier's function.
#[non_exhaustive]
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Rho {
    /// Per contact, `ρ_N = 1 / W_NN,ii` and `ρ_T = 1 / W_TT,ii` (and `1 / W_bb` for a
    /// bilateral row), so that every row of the function is in units of r and the local
    /// problem is well scaled. A zero diagonal entry gets ρ = 1.
    #[default]
    Diagonal,
    /// The same ρ > 0 for every row.
    Fixed(f64),
}

/// Options of [`Newton`]: the default, changed field by field with the `with_*` setters
/// (or by assigning the fields of a default value).
///
/// ```
/// use moreau_lcp::fc2d::{Newton, NewtonOptions};
///
/// # fn main() -> Result<(), moreau_lcp::LcpError> {
/// let options = NewtonOptions::default().with_tolerance(1e-10).with_max_iterations(20);
/// assert_eq!((options.tolerance, options.max_iterations), (1e-10, 20));
/// let solver = Newton::new(options)?;
/// # let _ = solver;
/// # Ok(())
/// # }
/// ```
///
/// The struct is `#[non_exhaustive]`, so that fields added later keep their defaults in
/// callers' code; a struct literal does not compile outside this crate:
///
/// ```compile_fail,E0639
/// let options = moreau_lcp::fc2d::NewtonOptions { tolerance: 1e-10, ..Default::default() };
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct NewtonOptions {
    /// Accept r when `natural <= max(tolerance, round_off)` ([`Fc2dResidual::meets`]).
    /// Default 1e-8.
    pub tolerance: f64,
    /// Largest number of Newton iterations (each one a sparse LU). Default 100.
    pub max_iterations: usize,
    /// The augmentation parameters ρ. Default [`Rho::Diagonal`].
    pub rho: Rho,
    /// Armijo's sufficient-decrease constant σ in (0, 1/2) (dimensionless): a step t is
    /// accepted when `ψ(r + t d) <= ψ_ref - 2 σ t ψ(r)`, ψ_ref the largest merit of the
    /// last `nonmonotone` iterates. Default 1e-4.
    pub armijo: f64,
    /// Number m >= 1 of past merits the line search compares with (Grippo, Lampariello &
    /// Lucidi's non-monotone rule; m = 1 is the monotone Armijo rule). A non-monotone
    /// search lets the full Newton step cross the kinks of Φ, where contacts at the
    /// boundary between two of their cases (r_N = u_N = 0, or |r_T| = μ r_N with
    /// u_T = 0) flip case, instead of shrinking the step towards zero. Default 1: on
    /// Siconos' FrictionContactProblem00727 the non-monotone rule (m = 10) wanders off,
    /// while on a settling column of disks it is what lets Newton converge.
    pub nonmonotone: usize,
    /// Factor β in (0, 1) by which the step shrinks after a rejected trial. Default 0.5.
    pub backtrack: f64,
    /// Trials of the line search before the fallback. Default 20.
    pub max_backtracks: usize,
    /// Gauss-Seidel sweeps of the fallback taken when the line search finds no decrease (at
    /// least one: 0 is taken as 1). Default 10.
    pub fallback_sweeps: usize,
    /// Gauss-Seidel sweeps taken after every accepted Newton step (0 for none). Newton's
    /// step fixes the long-range part of the error that Gauss-Seidel spreads only slowly
    /// (through a pile of grains with friction, tens of thousands of sweeps), and the sweeps fix
    /// the contacts whose case the step guessed wrong, which the next linearisation would
    /// otherwise see from the wrong piece of Φ. Default 0.
    pub smoothing_sweeps: usize,
    /// Smallest shift δ >= 0 added to the diagonal of the Jacobian (in the units of the
    /// ρ-scaled function, dimensionless), which keeps the linear solve defined when W is
    /// singular (indeterminate reactions of a dense packing). A failed or non-finite solve
    /// raises it a hundredfold, up to 1e-2. Default 1e-10.
    pub regularization: f64,
    /// Gain κ >= 0 of the shift that follows the residual: each iteration uses
    /// `δ = max(δ_min, min(κ ‖Φ‖∞, 1e-2))` (dimensionless, Φ in the ρ-scaled units).
    /// Default 1.
    pub regularization_gain: f64,
    /// Keep [`Fc2dResidual::natural`] after every iteration in [`Fc2dSolution::history`].
    /// Default false.
    pub keep_history: bool,
}

with_setters!(NewtonOptions {
    with_tolerance => tolerance: f64,
    with_max_iterations => max_iterations: usize,
    with_rho => rho: Rho,
    with_armijo => armijo: f64,
    with_nonmonotone => nonmonotone: usize,
    with_backtrack => backtrack: f64,
    with_max_backtracks => max_backtracks: usize,
    with_fallback_sweeps => fallback_sweeps: usize,
    with_smoothing_sweeps => smoothing_sweeps: usize,
    with_regularization => regularization: f64,
    with_regularization_gain => regularization_gain: f64,
    with_keep_history => keep_history: bool,
});

impl Default for NewtonOptions {
    fn default() -> Self {
        NewtonOptions {
            tolerance: 1e-8,
            max_iterations: 100,
            rho: Rho::Diagonal,
            armijo: 1e-4,
            backtrack: 0.5,
            max_backtracks: 20,
            nonmonotone: 1,
            fallback_sweeps: 10,
            smoothing_sweeps: 0,
            regularization: 1e-10,
            regularization_gain: 1.0,
            keep_history: false,
        }
    }
}

/// Largest diagonal shift of the Jacobian before a solve is given up for the fallback.
const MAX_REGULARIZATION: f64 = 1e-2;

/// A nonsmooth (semismooth) Newton method on Alart and Curnier's augmented Lagrangian
/// function of the planar frictional-contact problem.
///
/// With u = W r + q and, per contact i, `σ_N = r_N - ρ_N u_N`, `σ_T = r_T - ρ_T u_T`,
/// the function Φ(r) has the rows
///
/// ```text
/// Φ_N = r_N - max(0, σ_N)
/// Φ_T = r_T - proj_[-μ max(0, σ_N), μ max(0, σ_N)](σ_T)
/// Φ_b = ρ_b u_b                       (bilateral rows)
/// ```
///
/// and Φ(r) = 0 exactly when r and u satisfy Signorini's and Coulomb's laws and the
/// bilateral rows hold (Alart & Curnier 1991). Φ is piecewise linear in r; on each piece
/// its Jacobian is `J = A + B W` with A and B block diagonal (2x2 per contact: open,
/// stick or slip in either direction), so J has the block sparsity of W. Each iteration
/// solves `(J + δ I) d = -Φ` (δ a small shift that follows ‖Φ‖) by faer's sparse LU
/// with partial pivoting, and an Armijo line search on the merit `ψ = ½ ‖Φ‖²` picks the
/// step: monotone by default, non-monotone with
/// [`nonmonotone`](NewtonOptions::nonmonotone) > 1 (a step is then compared with the worst
/// of the last few merits, Grippo et al. 1986). When the line
/// search finds no decrease, a few sweeps of the nonsmooth Gauss-Seidel method ([`Nsgs`])
/// are taken from the current iterate instead, and Newton resumes from their result;
/// with `smoothing_sweeps`, such sweeps also follow every accepted step.
///
/// **Sparse LU.** The pattern of J (every entry of every stored block of W) and its
/// symbolic LU analysis (column ordering and supernodal structure) are kept and reused
/// across iterations and across solves of problems with the same block structure (same
/// groups, row pointers and block columns); only the numeric factorisation is repeated.
/// The last four structures of at most 1,024 rows are kept, so that a
/// problem whose contacts open and close between a few sets (a time-stepper's island from
/// one step to the next) reuses each one's analysis; a larger structure is kept alone.
/// A workspace (scratch memory, the matrix values, the iterates) is reused likewise, and
/// once every structure has been seen, solves do not allocate.
///
/// **Stopping.** After each iteration the shared [`Fc2dResidual`] of the iterate is
/// computed; the solve ends [`Status::Solved`] when its `natural` field is within the
/// tolerance, [`Status::IterationLimit`] after `max_iterations`, and
/// [`Status::NumericalFailure`] when the iterate stops being finite.
///
/// A warm start gives the initial r (contacts are projected onto their cone); the default
/// start is r = 0. From a start near the solution (a previous time step, or a few
/// Gauss-Seidel sweeps) Newton usually converges in a few iterations.
///
/// # References
/// - P. Alart, A. Curnier, A mixed formulation for frictional contact problems prone to
///   Newton like solution methods, Computer Methods in Applied Mechanics and Engineering
///   92 (1991) 353-375.
/// - V. Acary, B. Brogliato, Numerical Methods for Nonsmooth Dynamical Systems, Springer,
///   2008, §13.
/// - L. Grippo, F. Lampariello, S. Lucidi, A nonmonotone line search technique for
///   Newton's method, SIAM Journal on Numerical Analysis 23 (1986) 707-716.
pub struct Newton {
    options: NewtonOptions,
    work: Workspace,
    fallback: Nsgs,
    smoother: Option<Nsgs>,
    fallback_out: Fc2dSolution,
}

impl std::fmt::Debug for Newton {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Newton").field("options", &self.options).finish_non_exhaustive()
    }
}

impl Default for Newton {
    fn default() -> Self {
        Newton::new(NewtonOptions::default()).expect("the default options are valid")
    }
}

/// Number of block structures whose pattern and LU analysis [`Newton`] keeps.
const PATTERNS: usize = 4;

/// Largest number of rows of a block structure kept beside others: the analysis of a
/// larger one is kept alone, so that its memory is not held several times.
const PATTERN_ROWS: usize = 1024;

/// A block structure, the pattern of J and its symbolic LU.
#[derive(Default)]
struct Pattern {
    group_start: Vec<usize>,
    row_ptr: Vec<usize>,
    col: Vec<u32>,
    /// J in compressed sparse column form (values overwritten each iteration).
    jacobian: Option<SparseColMat<usize, f64>>,
    /// For each stored block k and entry e = 2 a + c, its position in J's values, or
    /// `usize::MAX` for the padding of a one-row group.
    position: Vec<usize>,
    /// Position of each diagonal entry J_kk.
    diagonal: Vec<usize>,
    symbolic: Option<SymbolicLu<usize>>,
    numeric: NumericLu<usize, f64>,
    scratch: Option<MemBuffer>,
}

#[derive(Default)]
struct Workspace {
    /// The patterns of the last structures solved, the latest first (see [`PATTERNS`]).
    patterns: Vec<Pattern>,
    /// ρ per row.
    rho: Vec<f64>,
    u: Vec<f64>,
    phi: Vec<f64>,
    /// The Newton direction (the right-hand side of the solve before it).
    d: Vec<f64>,
    r_trial: Vec<f64>,
    u_trial: Vec<f64>,
    phi_trial: Vec<f64>,
    /// Per group, the 2x2 coefficients of `J = A + B W` (row-major).
    a: Vec<[f64; 4]>,
    b: Vec<[f64; 4]>,
    /// The merits of the last `nonmonotone` iterates, as a ring.
    merits: Vec<f64>,
}

impl Newton {
    /// A solver with the given options.
    ///
    /// # Errors
    /// [`LcpError::InvalidOption`] unless `tolerance` is finite and > 0,
    /// `max_iterations >= 1`, `nonmonotone >= 1`, `0 < armijo < 1/2`, `0 < backtrack < 1`, a fixed ρ is
    /// finite and > 0, `regularization` is finite, >= 0 and below 1e-2, and
    /// `regularization_gain` is finite and >= 0.
    pub fn new(options: NewtonOptions) -> Result<Newton, LcpError> {
        let bad = |name: &'static str, reason: &str| Err(rules::invalid(name, reason));
        rules::tolerance(options.tolerance)?;
        rules::count("max_iterations", options.max_iterations)?;
        rules::count("nonmonotone", options.nonmonotone)?;
        if !(options.armijo > 0.0 && options.armijo < 0.5) {
            return bad("armijo", "must be in (0, 1/2)");
        }
        if !(options.backtrack > 0.0 && options.backtrack < 1.0) {
            return bad("backtrack", "must be in (0, 1)");
        }
        if let Rho::Fixed(rho) = options.rho
            && !(rho.is_finite() && rho > 0.0)
        {
            return bad("rho", "a fixed ρ must be finite and > 0");
        }
        if !(options.regularization >= 0.0 && options.regularization < MAX_REGULARIZATION) {
            return bad("regularization", "must be in [0, 1e-2)");
        }
        if !(options.regularization_gain >= 0.0 && options.regularization_gain.is_finite()) {
            return bad("regularization_gain", "must be finite and >= 0");
        }
        let fallback = Nsgs::new(NsgsOptions {
            tolerance: options.tolerance,
            max_sweeps: options.fallback_sweeps.max(1),
            ..Default::default()
        })?;
        let smoother = if options.smoothing_sweeps > 0 {
            Some(Nsgs::new(NsgsOptions {
                tolerance: options.tolerance,
                max_sweeps: options.smoothing_sweeps,
                ..Default::default()
            })?)
        } else {
            None
        };
        Ok(Newton {
            options,
            work: Workspace::default(),
            fallback,
            smoother,
            fallback_out: Fc2dSolution::new(),
        })
    }

    /// The options.
    pub fn options(&self) -> &NewtonOptions {
        &self.options
    }
}

impl Workspace {
    /// Brings the pattern of `problem`'s block structure to the front of the kept ones,
    /// building it in place of the least recently used one when it is not kept (see
    /// [`PATTERNS`] and [`PATTERN_ROWS`]).
    fn prepare(&mut self, problem: Fc2dRef<'_>) -> Result<(), LcpError> {
        let patterns = &mut self.patterns;
        if let Some(i) = patterns.iter().position(|pattern| pattern.is(problem)) {
            patterns[..=i].rotate_right(1);
            return Ok(());
        }
        let rows = |pattern: &Pattern| pattern.group_start.last().copied().unwrap_or(0);
        if problem.n_rows() > PATTERN_ROWS {
            patterns.truncate(1);
        } else {
            patterns.retain(|pattern| rows(pattern) <= PATTERN_ROWS);
        }
        if patterns.len() < PATTERNS && (patterns.is_empty() || problem.n_rows() <= PATTERN_ROWS) {
            patterns.push(Pattern::default());
        }
        patterns.rotate_right(1);
        patterns[0].build(problem)
    }
}

impl Pattern {
    /// Whether this is the pattern of `problem`'s block structure.
    fn is(&self, problem: Fc2dRef<'_>) -> bool {
        let p = problem.parts();
        self.symbolic.is_some()
            && self.group_start == p.group_start
            && self.row_ptr == p.row_ptr
            && self.col == p.col
    }

    /// Builds J's pattern and its symbolic LU for `problem`'s block structure.
    fn build(&mut self, problem: Fc2dRef<'_>) -> Result<(), LcpError> {
        let p = problem.parts();
        self.symbolic = None;
        // faer's numeric LU keeps the sizes of its last matrix: start afresh.
        self.numeric = NumericLu::new();
        self.group_start.clear();
        self.group_start.extend_from_slice(p.group_start);
        self.row_ptr.clear();
        self.row_ptr.extend_from_slice(p.row_ptr);
        self.col.clear();
        self.col.extend_from_slice(p.col);
        let n = problem.n_rows();
        let gs = p.group_start;
        // (column, row, block k, entry e) of every stored entry, sorted by column then row.
        let mut entries = Vec::with_capacity(4 * p.blocks.len());
        for g in 0..problem.n_groups() {
            let rows = gs[g + 1] - gs[g];
            for k in p.row_ptr[g]..p.row_ptr[g + 1] {
                let j = p.col[k] as usize;
                for a in 0..rows {
                    for c in 0..gs[j + 1] - gs[j] {
                        entries.push((gs[j] + c, gs[g] + a, k, 2 * a + c));
                    }
                }
            }
        }
        entries.sort_unstable();
        let mut col_ptr = vec![0usize; n + 1];
        let mut row_idx = Vec::with_capacity(entries.len());
        self.position.clear();
        self.position.resize(4 * p.blocks.len(), usize::MAX);
        self.diagonal.clear();
        self.diagonal.resize(n, usize::MAX);
        for (index, &(column, row, k, e)) in entries.iter().enumerate() {
            col_ptr[column + 1] += 1;
            row_idx.push(row);
            self.position[4 * k + e] = index;
            if row == column {
                self.diagonal[row] = index;
            }
        }
        for c in 0..n {
            col_ptr[c + 1] += col_ptr[c];
        }
        let nnz = row_idx.len();
        let symbolic = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        let lu = factorize_symbolic_lu(symbolic.as_ref(), Default::default())
            .map_err(|e| LcpError::Structure(format!("sparse LU analysis of J failed: {e:?}")))?;
        let req = StackReq::any_of(&[
            lu.factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default()),
            lu.solve_in_place_scratch::<f64>(1, Par::Seq),
        ]);
        self.scratch = Some(MemBuffer::new(req));
        self.jacobian = Some(SparseColMat::new(symbolic, vec![0.0; nnz]));
        self.symbolic = Some(lu);
        Ok(())
    }

    /// Writes `J + δ I` with `J = A + B W` into the values of the pattern's matrix,
    /// factors it and solves `(J + δ I) x = rhs` in place. Returns false when the
    /// factorisation fails or the solution is not finite.
    fn solve(
        &mut self,
        problem: Fc2dRef<'_>,
        a: &[[f64; 4]],
        b: &[[f64; 4]],
        delta: f64,
        rhs: &mut [f64],
    ) -> bool {
        let p = problem.parts();
        let (Some(jacobian), Some(symbolic), Some(scratch)) =
            (self.jacobian.as_mut(), self.symbolic.as_ref(), self.scratch.as_mut())
        else {
            return false;
        };
        let values = jacobian.val_mut();
        for g in 0..problem.n_groups() {
            let bg = &b[g];
            for k in p.row_ptr[g]..p.row_ptr[g + 1] {
                let w = &p.blocks[k];
                let own = p.col[k] as usize == g;
                for e in 0..4 {
                    let position = self.position[4 * k + e];
                    if position == usize::MAX {
                        continue;
                    }
                    let (row, column) = (e / 2, e % 2);
                    let mut v = bg[2 * row] * w[column] + bg[2 * row + 1] * w[2 + column];
                    if own {
                        v += a[g][e];
                    }
                    values[position] = v;
                }
            }
        }
        for &position in &self.diagonal {
            values[position] += delta;
        }
        let stack = MemStack::new(scratch);
        let Ok(lu) = symbolic.factorize_numeric_lu(
            &mut self.numeric,
            jacobian.as_ref(),
            Par::Seq,
            stack,
            Default::default(),
        ) else {
            return false;
        };
        let n = rhs.len();
        let rhs_mat = MatMut::from_column_major_slice_mut(rhs, n, 1);
        lu.solve_in_place_with_conj(Conj::No, rhs_mat, Par::Seq, MemStack::new(scratch));
        rhs.iter().all(|v| v.is_finite())
    }
}

/// The 2x2 blocks A and B of `J = A + B W`, one of each per group, to be written.
type Coefficients<'a> = (&'a mut [[f64; 4]], &'a mut [[f64; 4]]);

/// Evaluates Φ(r) into `phi` (u must be W r + q) and returns the merit `½ ‖Φ‖²`; with
/// `coefficients`, also writes the 2x2 blocks A and B of the Jacobian `J = A + B W` of
/// each group.
fn evaluate(
    problem: Fc2dRef<'_>,
    rho: &[f64],
    r: &[f64],
    u: &[f64],
    phi: &mut [f64],
    mut coefficients: Option<Coefficients<'_>>,
) -> f64 {
    let p = problem.parts();
    let n_c = p.n_contacts;
    let mut merit = 0.0;
    for i in 0..n_c {
        let (n, t) = (2 * i, 2 * i + 1);
        let (rho_n, rho_t, mu) = (rho[n], rho[t], p.mu[i]);
        let sigma_n = r[n] - rho_n * u[n];
        let sigma_t = r[t] - rho_t * u[t];
        let bound = mu * sigma_n.max(0.0);
        // Rows of A (coefficients of e_N, e_T) and of B (coefficients of W_N·, W_T·).
        let (a_n, b_n, phi_n) = if sigma_n > 0.0 {
            ([0.0, 0.0], [rho_n, 0.0], rho_n * u[n])
        } else {
            ([1.0, 0.0], [0.0, 0.0], r[n])
        };
        let (a_t, b_t, phi_t) = if sigma_n <= 0.0 {
            // The cone is the apex: r_T is driven to zero.
            ([0.0, 1.0], [0.0, 0.0], r[t])
        } else if sigma_t.abs() <= bound {
            ([0.0, 0.0], [0.0, rho_t], rho_t * u[t])
        } else {
            let s = sigma_t.signum();
            ([-s * mu, 1.0], [s * mu * rho_n, 0.0], r[t] - s * bound)
        };
        phi[n] = phi_n;
        phi[t] = phi_t;
        merit += phi_n * phi_n + phi_t * phi_t;
        if let Some((a, b)) = coefficients.as_mut() {
            a[i] = [a_n[0], a_n[1], a_t[0], a_t[1]];
            b[i] = [b_n[0], b_n[1], b_t[0], b_t[1]];
        }
    }
    let gs = p.group_start;
    for g in n_c..problem.n_groups() {
        for row in gs[g]..gs[g + 1] {
            phi[row] = rho[row] * u[row];
            merit += phi[row] * phi[row];
        }
        if let Some((a, b)) = coefficients.as_mut() {
            let rows = gs[g + 1] - gs[g];
            a[g] = [0.0; 4];
            b[g] = if rows == 2 {
                [rho[gs[g]], 0.0, 0.0, rho[gs[g] + 1]]
            } else {
                [rho[gs[g]], 0.0, 0.0, 0.0]
            };
        }
    }
    0.5 * merit
}

/// Fills ρ per row from the options.
fn choose_rho(problem: Fc2dRef<'_>, choice: Rho, rho: &mut [f64]) {
    let p = problem.parts();
    let gs = p.group_start;
    for g in 0..problem.n_groups() {
        let k = (p.row_ptr[g]..p.row_ptr[g + 1])
            .find(|&k| p.col[k] as usize == g)
            .expect("a validated problem stores every diagonal block");
        let diagonal = [p.blocks[k][0], p.blocks[k][3]];
        for (row, w) in (gs[g]..gs[g + 1]).zip(diagonal) {
            rho[row] = match choice {
                Rho::Fixed(value) => value,
                Rho::Diagonal => {
                    if w > 0.0 {
                        1.0 / w
                    } else {
                        1.0
                    }
                }
            };
        }
    }
}

impl Fc2dSolver for Newton {
    fn solve_into(
        &mut self,
        problem: Fc2dRef<'_>,
        warm_start: Option<&[f64]>,
        out: &mut Fc2dSolution,
    ) -> Result<(), LcpError> {
        check_warm_start(problem, warm_start)?;
        let n = problem.n_rows();
        let groups = problem.n_groups();
        let tolerance = self.options.tolerance;
        out.reset(n, Method::Newton);
        if let Some(w) = warm_start {
            out.r.copy_from_slice(w);
        }
        for (i, &mu) in problem.mu().iter().enumerate() {
            let (a, b) = project_cone(out.r[2 * i], out.r[2 * i + 1], mu);
            out.r[2 * i] = a;
            out.r[2 * i + 1] = b;
        }
        if groups == 0 {
            out.method = Method::Trivial;
            out.certify(problem, tolerance, Status::NumericalFailure);
            return Ok(());
        }
        self.work.prepare(problem)?;
        let w = &mut self.work;
        for v in [&mut w.rho, &mut w.u, &mut w.phi, &mut w.d, &mut w.r_trial, &mut w.u_trial] {
            v.clear();
            v.resize(n, 0.0);
        }
        w.phi_trial.clear();
        w.phi_trial.resize(n, 0.0);
        w.a.clear();
        w.a.resize(groups, [0.0; 4]);
        w.b.clear();
        w.b.resize(groups, [0.0; 4]);
        choose_rho(problem, self.options.rho, &mut w.rho);

        problem.velocity(&out.r, &mut w.u);
        out.residual = Fc2dResidual::of_velocity(problem, &out.r, &w.u, tolerance);
        if out.residual.meets(tolerance) {
            out.certify(problem, tolerance, Status::IterationLimit);
            return Ok(());
        }
        let mut delta = self.options.regularization;
        let sigma = self.options.armijo;
        self.work.merits.clear();
        for iteration in 1..=self.options.max_iterations {
            out.iterations = iteration;
            let w = &mut self.work;
            let merit =
                evaluate(problem, &w.rho, &out.r, &w.u, &mut w.phi, Some((&mut w.a, &mut w.b)));
            if w.merits.len() < self.options.nonmonotone {
                w.merits.push(merit);
            } else {
                w.merits[iteration % self.options.nonmonotone] = merit;
            }
            let reference = w.merits.iter().fold(merit, |m, &v| m.max(v));
            // The Newton direction, with the diagonal shift raised until the solve works.
            let mut solved = false;
            // A shift proportional to ‖Φ‖∞ keeps the step of a nearly singular J (W
            // singular on a dense packing) near the current iterate, like a proximal
            // point step, and vanishes as Φ does, which keeps fast local convergence.
            let phi_norm = w.phi.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            delta =
                delta.max((self.options.regularization_gain * phi_norm).min(MAX_REGULARIZATION));
            loop {
                for (d, phi) in w.d.iter_mut().zip(&w.phi) {
                    *d = -phi;
                }
                if w.patterns[0].solve(problem, &w.a, &w.b, delta, &mut w.d) {
                    solved = true;
                    break;
                }
                if delta >= MAX_REGULARIZATION {
                    break;
                }
                delta = (delta * 100.0).clamp(1e-8, MAX_REGULARIZATION);
            }
            let mut accepted = false;
            if solved {
                let mut t = 1.0;
                for _ in 0..=self.options.max_backtracks {
                    for ((rt, r), d) in w.r_trial.iter_mut().zip(&out.r).zip(&w.d) {
                        *rt = r + t * d;
                    }
                    problem.velocity(&w.r_trial, &mut w.u_trial);
                    let trial =
                        evaluate(problem, &w.rho, &w.r_trial, &w.u_trial, &mut w.phi_trial, None);
                    if trial <= reference - 2.0 * sigma * t * merit {
                        accepted = true;
                        break;
                    }
                    t *= self.options.backtrack;
                }
            }
            if accepted {
                std::mem::swap(&mut out.r, &mut w.r_trial);
                std::mem::swap(&mut w.u, &mut w.u_trial);
                if let Some(smoother) = self.smoother.as_mut() {
                    smoother.solve_into(problem, Some(&out.r), &mut self.fallback_out)?;
                    out.r.copy_from_slice(&self.fallback_out.r);
                    w.u.copy_from_slice(&self.fallback_out.u);
                }
                // A good step lets the shift fall back towards its floor.
                delta = (delta * 0.01).max(self.options.regularization);
            } else {
                // No decrease along d: a few Gauss-Seidel sweeps from r instead.
                self.fallback.solve_into(problem, Some(&out.r), &mut self.fallback_out)?;
                out.r.copy_from_slice(&self.fallback_out.r);
                w.u.copy_from_slice(&self.fallback_out.u);
            }
            let w = &mut self.work;
            out.residual = Fc2dResidual::of_velocity(problem, &out.r, &w.u, tolerance);
            if self.options.keep_history {
                out.history.push(out.residual.natural);
            }
            if !out.residual.natural.is_finite() {
                out.certify(problem, tolerance, Status::NumericalFailure);
                out.status = Status::NumericalFailure;
                return Ok(());
            }
            if out.residual.meets(tolerance) {
                break;
            }
        }
        out.certify(problem, tolerance, Status::IterationLimit);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_are_checked() {
        for (options, name) in [
            (NewtonOptions { tolerance: -1.0, ..Default::default() }, "tolerance"),
            (NewtonOptions { max_iterations: 0, ..Default::default() }, "max_iterations"),
            (NewtonOptions { nonmonotone: 0, ..Default::default() }, "nonmonotone"),
            (NewtonOptions { armijo: 0.5, ..Default::default() }, "armijo"),
            (NewtonOptions { backtrack: 1.0, ..Default::default() }, "backtrack"),
            (NewtonOptions { rho: Rho::Fixed(0.0), ..Default::default() }, "rho"),
            (NewtonOptions { regularization: f64::NAN, ..Default::default() }, "regularization"),
            (
                NewtonOptions { regularization_gain: -1.0, ..Default::default() },
                "regularization_gain",
            ),
        ] {
            assert!(
                matches!(Newton::new(options), Err(LcpError::InvalidOption { name: n, .. }) if n == name)
            );
        }
        let o: NewtonOptions =
            serde_json::from_str(r#"{"tolerance": 1e-6, "rho": {"fixed": 2.0}}"#).unwrap();
        assert_eq!((o.tolerance, o.rho, o.max_iterations), (1e-6, Rho::Fixed(2.0), 100));
    }
}
