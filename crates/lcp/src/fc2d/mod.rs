//! Planar frictional contact (FC2D): the problem, its residual and its solvers.
//!
//! # The problem
//!
//! For n_c contacts, find reactions r_i = (r_N,i, r_T,i) (impulses, in a time step) and
//! relative velocities u_i = (u_N,i, u_T,i) with
//!
//! ```text
//! u = W r + q,
//! 0 <= r_N,i ⊥ u_N,i >= 0                                  (Signorini)
//! |r_T,i| <= μ_i r_N,i,  r_T,i = -μ_i r_N,i sign(u_T,i) if u_T,i != 0   (Coulomb)
//! ```
//!
//! W (the Delassus matrix) is symmetric positive semidefinite and stored by 2x2 blocks (a
//! problem is checked for what its solvers rely on: finite entries, blocks in range, and
//! diagonal blocks that are symmetric positive semidefinite; the symmetry of the
//! off-diagonal blocks, W_ji = W_ijᵀ, is the caller's to keep, as a Delassus matrix
//! W = H M⁻¹ Hᵀ has it by construction):
//! block (i, j) is nonzero only when contacts i and j share a body, so a granular problem
//! of thousands of contacts stores a few blocks per contact ([`Fc2d`], [`Fc2dRef`],
//! [`Fc2dBuilder`]). Bilateral (equality) rows with free multipliers, for joints, live in
//! the same storage as groups of one or two rows after the contacts: `u_b = 0`, r_b free.
//! In Moreau's midpoint step with Newton's impact law, u is the step's ξ
//! (ξ_N = γ_N,E + ε_N γ_N,A) and r the impulses (P_N, P_T).
//!
//! Signorini's and Coulomb's laws together say that r_i lies in the cone
//! K_i = {|r_T| <= μ_i r_N} and that De Saxcé's modified velocity
//! `û_i = u_i + μ_i |u_T,i| e_N` lies in its polar's opposite, complementary to r_i; that
//! is, `r_i = proj_K(r_i - û_i)` (De Saxcé & Feng 1998).
//!
//! # The residual
//!
//! [`Fc2dResidual`] is the one measure of all solvers, tests and reports: per contact the
//! natural map `F_i = r_i - proj_K(r_i - û_i)`, per bilateral row `|u_b|`, their maximum
//! scaled by `max(1, ‖q‖∞)` (`natural`, the acceptance measure), and Siconos' normalised
//! error (`siconos`) for comparisons, and the floor that floating point cannot resolve at r
//! (`round_off`, `4 ε` times the largest term of u = W r + q). A solver reports
//! [`Status::Solved`](crate::Status) only when `natural <= max(tolerance, round_off)`: the
//! tolerance, or round-off where the tolerance asks for more than floating point resolves.
//!
//! **Large problems on rayon's pool.** A problem of more than 1,024 groups is checked
//! ([`Fc2dRef::from_parts`]), multiplied ([`Fc2dRef::velocity`]) and measured
//! ([`Fc2dResidual`]) in chunks of 1,024 groups on rayon's current pool. The chunks and the
//! order in which their sums are combined depend on the number of groups only, so every
//! result is the same, bit for bit, on a pool of any size (one thread included).
//!
//! # The solvers
//!
//! | solver | for |
//! |---|---|
//! | [`Nsgs`] | any size: block Gauss-Seidel with the exact local solution per contact, ω, warm start, no allocation on repeated solves |
//! | [`LcpRoute`] | small problems (up to about 100 contacts): the exact LCP reformulation solved by pivoting, the certified answer |
//! | [`Newton`] | nonsmooth Newton on Alart and Curnier's function with sparse LU and an Armijo line search (monotone by default, non-monotone on request), optionally smoothed by Gauss-Seidel sweeps: fast local convergence from a good start; can cycle on dense packings whose W is singular |
//! | [`Proximal`] | the proximal point method, each sub-problem (W + η, positive definite) solved by Newton: slower, but finishes the dense packings where Newton cycles |
//! | [`Fc2dAuto`] | the default: Gauss-Seidel, the LCP route for small problems it does not finish, exact solves of the clusters where it stalls |
//!
//! **The local problem of NSGS.** With the others' reactions fixed, contact i sees
//! `u_i = W_ii r_i + v_i` and its solution is one of four cases, tried in turn:
//!
//! | case | r_i | valid when |
//! |---|---|---|
//! | open | 0 | v_N >= 0 |
//! | stick | -W_ii⁻¹ v_i (u_i = 0) | \|r_T\| <= μ r_N |
//! | slip, u_T > 0 | r_N = -v_N / (W_NN - μ W_NT), r_T = -μ r_N | u_T >= 0 |
//! | slip, u_T < 0 | r_N = -v_N / (W_NN + μ W_NT), r_T = μ r_N | u_T <= 0 |
//!
//! μ = 0 is the slip case; a singular or (by rounding) slightly unsymmetric block is
//! handled by taking the candidate with the smallest local natural map when rounding leaves
//! none exactly valid. A bilateral group solves `W_bb r_b = -v_b`.
//!
//! **The LCP route.** With `r_R = r_T + μ r_N`, `r_L = μ r_N - r_T` and
//! `u_T = ξ_R - ξ_L`, the problem is the LCP in `z = (r_N; r_R; ξ_L)` of Moreau's midpoint
//! step (see [`LcpRoute`]); it is exact, not a faceted approximation of the cone, because
//! the planar cone has only two edges (Glocker 2001; Acary & Brogliato 2008, §12).
//!
//! # Files
//!
//! Siconos numerics' FC2D and GFC2D files are read by [`Fc2d::read_siconos`] and
//! [`Gfc2d::read_siconos`] (W in dense, sparse-block or CSparse storage) and written by
//! [`Fc2d::write_siconos`]; [`Gfc2d::reduce`] forms `W = Hᵀ M⁻¹ H` sparsely.
//!
//! # Notation
//!
//! | symbol | identifier | meaning |
//! |---|---|---|
//! | n_c | `n_contacts()` | number of contacts |
//! | n_b | `n_bilateral()` | number of bilateral rows |
//! | W | `Fc2dParts::blocks` | Delassus matrix, 2x2 blocks `[W_NN, W_NT, W_TN, W_TT]` |
//! | q | `q()` | free velocity |
//! | μ | `mu()` | friction coefficient per contact |
//! | r = (r_N, r_T) | `Fc2dSolution::r` | reactions (impulses P_N, P_T in a step) |
//! | u = (u_N, u_T) | `Fc2dSolution::u` | velocities u = W r + q (ξ in a step) |
//! | K | | Coulomb cone {\|r_T\| <= μ r_N} |
//! | ω | `NsgsOptions::omega` | relaxation factor |
//! | η, α | `ProximalOptions::initial_weight` | proximal weights η_i = α W_NN,ii |
//! | ρ_N, ρ_T | `NewtonOptions::rho` | Alart and Curnier's augmentation parameters |
//! | Φ, J | | Alart and Curnier's function and its generalised Jacobian |
//! | M, H, b | `Gfc2d` | global form: M v = q + H r, u = Hᵀ v + b |
//!
//! # Example
//!
//! ```
//! use moreau_lcp::Status;
//! use moreau_lcp::fc2d::{Fc2d, Fc2dSolver, LcpRoute, Nsgs};
//!
//! # fn main() -> Result<(), moreau_lcp::LcpError> {
//! // One contact pushed into the ground (q_N = -1) and sideways (q_T = 2), W = I, μ = 0.5:
//! // it slips, r = (1, -0.5), u = (0, 1.5).
//! let w = moreau_lcp::faer::Mat::<f64>::identity(2, 2);
//! let problem = Fc2d::from_dense(w.as_ref(), &[-1.0, 2.0], &[0.5])?;
//! for solution in [Nsgs::default().solve(&problem)?, LcpRoute::default().solve(&problem)?] {
//!     assert_eq!(solution.status, Status::Solved);
//!     assert!((solution.r[0] - 1.0).abs() < 1e-12 && (solution.r[1] + 0.5).abs() < 1e-12);
//!     assert!((solution.u[1] - 1.5).abs() < 1e-12);
//! }
//! # Ok(())
//! # }
//! ```
//!
//! # References
//! - J. J. Moreau, Unilateral contact and dry friction in finite freedom dynamics, CISM
//!   Courses and Lectures 302, Springer, 1988.
//! - M. Jean, The non-smooth contact dynamics method, Computer Methods in Applied
//!   Mechanics and Engineering 177 (1999) 235-257.
//! - P. Alart, A. Curnier, A mixed formulation for frictional contact problems prone to
//!   Newton like solution methods, Computer Methods in Applied Mechanics and Engineering
//!   92 (1991) 353-375.
//! - G. De Saxcé, Z.-Q. Feng, The bipotential method: a constructive approach to design
//!   the complete contact law with friction and improved numerical algorithms,
//!   Mathematical and Computer Modelling 28 (1998) 225-245.
//! - V. Acary, B. Brogliato, Numerical Methods for Nonsmooth Dynamical Systems, Springer,
//!   2008.
//! - C. Glocker, Set-Valued Force Laws: Dynamics of Non-Smooth Systems, Springer, 2001.

mod auto;
mod chunks;
mod lcp_route;
mod local;
mod newton;
mod nsgs;
mod problem;
mod proximal;
mod residual;
mod solution;

pub use crate::io::{Gfc2d, Reduced, SiconosStorage};
pub use auto::{Fc2dAuto, Fc2dAutoOptions};
pub use lcp_route::{LcpRoute, LcpRouteOptions, LcpRouteSolver};
pub use newton::{Newton, NewtonOptions, Rho};
pub use nsgs::{Nsgs, NsgsOptions};
pub use problem::{Fc2d, Fc2dBuilder, Fc2dParts, Fc2dRef, PSD_TOLERANCE};
pub use proximal::{Proximal, ProximalOptions};
pub use residual::Fc2dResidual;
pub use solution::{Fc2dSolution, Fc2dSolver};
