//! Solvers for the linear complementarity problem (LCP) and for planar frictional contact
//! (FC2D) on faer.
//!
//! Given a dense square matrix M (n x n, n from 1 to a few hundred) and a vector q, the
//! LCP(M, q) asks for z in R^n with
//!
//! ```text
//! w = M z + q,    z >= 0,    w >= 0,    z'w = 0        (written 0 <= z ⊥ w >= 0)
//! ```
//!
//! Complementarity means that in each component either z_i = 0 or w_i = 0. In Moreau's
//! midpoint time-stepping the LCP of one step has z = (P_N; P_R; ξ_L) (impulses and an
//! auxiliary tangential velocity) and w = (ξ_N; ξ_R; P_L), with M built from W_N, W_T,
//! the mass matrix and μ; this crate only sees (M, q).
//!
//! The [`fc2d`] module solves the planar frictional-contact problem itself, sparse by 2x2
//! blocks, at any size: find reactions r and velocities u = W r + q with Signorini's and
//! Coulomb's laws per contact (and bilateral rows for joints), by nonsmooth block
//! Gauss-Seidel or, for small problems, by its exact LCP reformulation; it reads and
//! writes Siconos numerics' FC2D and GFC2D files.
//!
//! **What it is for:** accurate, allocation-free solves of small dense LCPs in a time
//! stepper's hot loop, certified residuals, and hard cases (degenerate, infeasible,
//! exponential) handled with an honest [`Status`]; planar frictional contact from one
//! contact to tens of thousands ([`fc2d`]).
//! **What it is not for:** large sparse LCPs, nonlinear complementarity, spatial (3D)
//! friction cones, or mechanics: building M and q (or W and q) from a model is the
//! stepper's job.
//!
//! # Principal types
//!
//! | type | role |
//! |---|---|
//! | [`Lcp`], [`LcpRef`] | a validated problem (owned / borrowed, the solvers take [`LcpRef`]) |
//! | [`Solver`] | `solve_into(lcp, warm_start, &mut solution)`: one trait for all solvers |
//! | [`Lemke`] ([`LemkeOptions`], [`Covering`]) | complementary pivoting, lexicographic, checked tableau solution (LU re-solve as fallback) |
//! | [`Pgs`] ([`PgsOptions`]) | projected Gauss-Seidel with over-relaxation and warm start |
//! | [`Enumeration`] ([`EnumerationOptions`]) | all complementary bases; every solution; certified "no solution" |
//! | [`Auto`] ([`AutoOptions`]) | trivial, warm-start basis, Lemke, other covering vectors, enumeration: the robust default |
//! | [`Solution`], [`Status`], [`Method`], [`Residual`] | result, how it ended, who produced it, how good it is |
//! | [`LcpError`] | invalid input only; not converging is a [`Status`] |
//! | [`fc2d::Fc2d`], [`fc2d::Fc2dRef`], [`fc2d::Fc2dBuilder`] | a planar frictional-contact problem, W by 2x2 blocks, with bilateral rows |
//! | [`fc2d::Nsgs`], [`fc2d::LcpRoute`] ([`fc2d::Fc2dSolver`]) | nonsmooth Gauss-Seidel; the exact LCP reformulation |
//! | [`fc2d::Newton`], [`fc2d::Fc2dAuto`] | nonsmooth Newton with sparse LU; the robust FC2D default |
//! | [`fc2d::Fc2dSolution`], [`fc2d::Fc2dResidual`] | r, u, status and the one FC2D residual |
//! | [`fc2d::Gfc2d`] | Siconos' global form M v = q + H r, u = Hᵀ v + b, reduced to W = Hᵀ M⁻¹ H |
//!
//! # The methods
//!
//! **Lemke's method** (Lemke 1965) adds an artificial variable z_0 with a covering vector
//! d > 0, `w = q + M z + d z_0`, starts from the almost complementary basis {w} with
//! z_0 = max(-q_i / d_i), and pivots: the complement of the variable that left enters,
//! the ratio test picks who leaves. It ends when z_0 leaves (a solution), on a secondary
//! ray, or at a pivot limit. A lexicographic ratio test prevents cycling on degenerate
//! problems. It finds a solution for every P-matrix and every positive semidefinite M
//! whose LCP is feasible (Cottle, Pang & Stone 1992, §4.4).
//!
//! **Projected Gauss-Seidel** sweeps `z_i <- max(0, z_i - ω (M z + q)_i / M_ii)`. It is
//! cheap per sweep, takes warm starts, converges for symmetric positive definite M with
//! 0 < ω < 2 (Moreau 1988), and needs M_ii > 0.
//!
//! **Enumeration** solves `M_αα z_α = -q_α` for all 2^n index sets α (plus a vertex
//! search when some `M_αα` is singular) and returns every solution, or proves there is
//! none, for small n (Glocker 2001 uses it for the contact LCP).
//!
//! Every solver recomputes w = M z + q from its final z and reports the shared
//! [`Residual`]; [`Status::Solved`] is returned only when [`Residual::relative`] is at or
//! below the solver's tolerance. `relative` measures each w_i against the magnitude of
//! the terms that make it up, so it is unchanged by a positive scaling of a row of
//! (M, q) (which does not change the solutions either).
//!
//! # Allocation
//!
//! Each solver keeps a workspace. `solve_into` with an [`LcpRef`] and a reused
//! [`Solution`] allocates nothing once a problem of that size has been solved (checked by
//! a counting-allocator test); [`Enumeration::solve_all`] allocates its result.
//!
//! # Notation
//!
//! | symbol | identifier | meaning |
//! |---|---|---|
//! | n | `n()` | problem size |
//! | M | `m()`, `M` in kernels | n x n matrix |
//! | q | `q()` | vector of length n |
//! | z | `Solution::z` | unknown, z >= 0 (impulses P_N, P_R and ξ_L in the step LCP) |
//! | w | `Solution::w` | w = M z + q >= 0 (ξ_N, ξ_R and P_L in the step LCP) |
//! | d | `Covering` | Lemke's covering vector, d > 0 |
//! | z_0 | | Lemke's artificial variable |
//! | ω | `PgsOptions::omega` | PGS relaxation factor |
//! | α | | index set of basic z (z_i > 0 allowed) |
//! | W, r, u, μ | [`fc2d`] | Delassus matrix, reactions, velocities, friction coefficients of FC2D |
//!
//! # Example
//!
//! ```
//! use moreau_lcp::{Auto, Lcp, Solver, Status};
//!
//! # fn main() -> Result<(), moreau_lcp::LcpError> {
//! // w1 = 2 z1 + z2 - 5, w2 = z1 + 2 z2 - 6: the solution is z = (4/3, 7/3), w = 0.
//! let lcp = Lcp::from_rows(&[vec![2.0, 1.0], vec![1.0, 2.0]], &[-5.0, -6.0])?;
//! let solution = Auto::default().solve(&lcp)?;
//! assert_eq!(solution.status, Status::Solved);
//! assert!((solution.z[0] - 4.0 / 3.0).abs() < 1e-12);
//! assert!((solution.z[1] - 7.0 / 3.0).abs() < 1e-12);
//! assert!(solution.residual.relative <= 1e-9);
//! # Ok(())
//! # }
//! ```
//!
//! # Planar frictional contact
//!
//! See the [`fc2d`] module: the problem and its laws, the cases of NSGS's local solver
//! (open, stick, slip either way), the natural-map residual with De Saxcé's modified
//! velocity and Siconos' normalised error, and an example.
//!
//! ```
//! use moreau_lcp::fc2d::{Fc2d, Fc2dSolver, Nsgs};
//!
//! # fn main() -> Result<(), moreau_lcp::LcpError> {
//! // Two contacts of W = 2 I coupled by 0.5 in their normal rows, both pushed in.
//! let w = moreau_lcp::faer::Mat::from_fn(4, 4, |i, j| match (i, j) {
//!     _ if i == j => 2.0,
//!     (0, 2) | (2, 0) => 0.5,
//!     _ => 0.0,
//! });
//! let problem = Fc2d::from_dense(w.as_ref(), &[-1.0, 0.1, -1.0, -0.1], &[0.3, 0.3])?;
//! let solution = Nsgs::default().solve(&problem)?;
//! assert!(solution.is_solved() && solution.residual.natural <= 1e-8);
//! // Both press with r_N = 1 / 2.5 and stick (|q_T| is small).
//! assert!((solution.r[0] - 0.4).abs() < 1e-8 && (solution.r[2] - 0.4).abs() < 1e-8);
//! assert!(solution.u.iter().all(|u| u.abs() < 1e-8));
//! # Ok(())
//! # }
//! ```
//!
//! # References
//! - C. E. Lemke, Bimatrix equilibrium points and mathematical programming, Management
//!   Science 11 (1965) 681-689.
//! - R. W. Cottle, J.-S. Pang, R. E. Stone, The Linear Complementarity Problem, Academic
//!   Press, 1992.
//! - J. J. Moreau, Unilateral contact and dry friction in finite freedom dynamics, in
//!   Nonsmooth Mechanics and Applications, CISM Courses and Lectures 302, Springer, 1988.
//! - C. Glocker, Set-Valued Force Laws: Dynamics of Non-Smooth Systems, Springer, 2001.
//! - M. Jean, The non-smooth contact dynamics method, Computer Methods in Applied
//!   Mechanics and Engineering 177 (1999) 235-257 (NSGS).
//! - P. Alart, A. Curnier, A mixed formulation for frictional contact problems prone to
//!   Newton like solution methods, CMAME 92 (1991) 353-375.
//! - G. De Saxcé, Z.-Q. Feng, The bipotential method, Mathematical and Computer Modelling
//!   28 (1998) 225-245.
//! - V. Acary, B. Brogliato, Numerical Methods for Nonsmooth Dynamical Systems, Springer,
//!   2008.
//! - P. Flores, Kinematics and Dynamics of Multibody Systems with Imperfect Joints,
//!   Springer, 2008; Flores et al., Nonlinear Dynamics, 2010 (clearance joints via LCP).
#![deny(missing_docs)]

#[macro_use]
mod setters;

mod auto;
mod dense;
mod enumeration;
mod error;
pub mod fc2d;
mod io;
mod lemke;
mod pgs;
mod problem;
mod solution;

/// The dense and sparse matrices that [`Lcp::new`], [`Lcp::m`] and
/// [`fc2d::Fc2d::from_dense`] take and give are faer's, re-exported here so that a user of this
/// crate (or of the `moreau` package, as `moreau::lcp::faer`) needs no faer dependency of a
/// matching version.
pub use faer;

pub use auto::{Auto, AutoOptions};
pub use enumeration::{Enumeration, EnumerationOptions};
pub use error::LcpError;
pub use lemke::{Covering, Lemke, LemkeOptions};
pub use pgs::{Pgs, PgsOptions};
pub use problem::{Lcp, LcpRef, MAX_ENTRY};
pub use solution::{Method, Residual, ResidualRows, Solution, Solver, Status};
