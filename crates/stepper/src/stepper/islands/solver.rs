//! The solver chain of an island's problem, from the stepper's [`SolverChoice`].

use moreau_lcp::LcpError;
use moreau_lcp::fc2d::{
    Fc2dAuto, Fc2dAutoOptions, Fc2dRef, Fc2dSolution, Fc2dSolver, LcpRoute, LcpRouteOptions,
    LcpRouteSolver, Newton, NewtonOptions, Nsgs, NsgsOptions, Proximal, ProximalOptions,
};

use super::Purpose;
use crate::SolverChoice;
use crate::stepper::FC2D_TOLERANCE;

/// Islands of at most this many contacts are small: the default choice solves them with
/// unrelaxed Gauss-Seidel (whose exact local solution answers a one-contact island in one
/// sweep) to [`SMALL_TOLERANCE`], and by pivoting if that stalls; an island that both leave
/// above it goes through the large islands' chain, to their tolerance.
const SMALL_ISLAND: usize = 8;

/// The Gauss-Seidel sweeps (cluster solves included) that the default choice gives a large
/// island before nonsmooth Newton takes over.
const LARGE_ISLAND_SWEEPS: usize = 5_000;

/// The Gauss-Seidel sweeps (cluster solves included) between two looks at a large island's
/// progress when the step has an inexact residual. A dense packing arrested by impacts brings
/// Gauss-Seidel's residual down only as the inverse of its sweeps (cold, an island of 517
/// contacts of the settling column reaches 1e-3 in 284 sweeps, 1e-4 in 2,015, 1e-5 in
/// 23,735): such an island, once within the limit, would spend the rest of the budget of
/// [`LARGE_ISLAND_SWEEPS`] to gain one digit and still miss the tolerance. It is taken as soon
/// as it is within the limit and the reduction of its last chunk of sweeps, kept up over the
/// chunks left, would not reach the tolerance.
const INEXACT_CHUNK_SWEEPS: usize = 250;

/// The Gauss-Seidel sweeps that follow each accepted Newton step of a large island: the step
/// carries the long-range correction, the sweeps settle the contacts whose case (stick or
/// slip, open or closed) it guessed wrong. On the settling disk column (N = 1000, islands
/// of 388 and 631 contacts) cold Newton with them needs 23 and 31 iterations to 1e-10.
const NEWTON_SMOOTHING_SWEEPS: usize = 20;

/// The past merits that the line search of a large island's Newton compares with: the
/// monotone rule stalls near 5e-5 on the settling column, where contacts at the boundary
/// of two cases flip from one iteration to the next.
const NEWTON_NONMONOTONE: usize = 10;

/// The Newton iterations the default choice gives a large island before the proximal
/// point method takes over: Newton either converges in a few dozen or cycles.
const NEWTON_ITERATIONS: usize = 50;

/// The Newton iterations that the default choice gives the step's problem of an island with
/// joints and 1 to [`SMALL_JOINTS_CONTACTS`] contacts before the large islands' chain takes
/// over, where [`Fc2dAuto`] pivots after a window of sweeps. Started from the step before's
/// impulses with the contacts' right cases, Newton solves such an island in a few iterations
/// (at most three in 99 % of the test suite's solves that succeed); where the warm start guesses
/// them wrong, as on a chain resting at ε_N = 0.5 whose contacts open and close from step to
/// step, it spent its 50 iterations (1.7 ms on 19 contacts) where pivoting solves the island
/// in 0.1 ms, about three iterations. Islands of joints alone keep their 50: pivoting has
/// nothing to solve there, and a chain whose masses alternate between 1 and 10⁶ needs up to
/// 21.
const SMALL_JOINTS_NEWTON_ITERATIONS: usize = 8;

/// The largest island whose step Newton ends after [`SMALL_JOINTS_NEWTON_ITERATIONS`]:
/// beyond it pivoting, whose cost grows as n_c³, takes longer than the iterations saved.
const SMALL_JOINTS_CONTACTS: usize = 32;

/// The largest island the default choice hands to pivoting (a dense solve of 3 n_c rows)
/// when Gauss-Seidel and Newton leave it unsolved.
const PIVOTING_ISLAND: usize = 300;

/// The Gauss-Seidel sweeps (cluster solves included) that the default choice gives a small
/// island, after its first window and pivoting, before the large islands' chain takes over.
const SMALL_ISLAND_SWEEPS: usize = 2_000;

/// The natural-map tolerance of small islands, where it costs a few sweeps more.
const SMALL_TOLERANCE: f64 = 1e-13;

/// The stages of the default choice (see [`IslandSolver::Auto`]).
pub(in crate::stepper) struct AutoChain {
    /// Small islands, large islands, Gauss-Seidel resumed, and the large islands' first chunk
    /// and later chunks (these without the pivoting that the first has tried).
    auto: [Fc2dAuto; 5],
    /// Large islands cold, islands with joints for the step (the small ones' ending after
    /// [`SMALL_JOINTS_NEWTON_ITERATIONS`]), and for the joints' correction.
    newton: [Newton; 4],
    proximal: Proximal,
    lcp: LcpRoute,
    /// The iterate a later stage starts from.
    start: Vec<f64>,
}

/// The solver of the islands' problems, from the stepper's [`SolverChoice`].
pub(in crate::stepper) enum IslandSolver {
    /// The default choice: one `Fc2dAuto` for small islands and one for large ones, then,
    /// for the islands that Gauss-Seidel and its cluster solves leave unsolved,
    /// nonsmooth Newton, the proximal point method, Gauss-Seidel resumed with the full
    /// budget from the proximal iterate, and pivoting (whose candidate Newton finishes when
    /// it falls short: `LcpRoute`'s polish); with an inexact residual, a large island's
    /// Gauss-Seidel runs in chunks.
    Auto(Box<AutoChain>),
    Nsgs(Nsgs),
    Lcp(Box<LcpRoute>),
}

impl IslandSolver {
    pub(in crate::stepper) fn new(choice: &SolverChoice) -> Result<Self, LcpError> {
        Ok(match *choice {
            SolverChoice::Auto => Self::Auto(Box::new(AutoChain {
                auto: [
                    Fc2dAuto::new(
                        Fc2dAutoOptions::default()
                            .with_tolerance(SMALL_TOLERANCE)
                            .with_omega(1.0)
                            .with_max_sweeps(SMALL_ISLAND_SWEEPS),
                    )?,
                    Fc2dAuto::new(
                        Fc2dAutoOptions::default()
                            .with_tolerance(FC2D_TOLERANCE)
                            .with_max_sweeps(LARGE_ISLAND_SWEEPS),
                    )?,
                    Fc2dAuto::new(Fc2dAutoOptions::default().with_tolerance(FC2D_TOLERANCE))?,
                    Fc2dAuto::new(
                        Fc2dAutoOptions::default()
                            .with_tolerance(FC2D_TOLERANCE)
                            .with_max_sweeps(INEXACT_CHUNK_SWEEPS),
                    )?,
                    Fc2dAuto::new(
                        Fc2dAutoOptions::default()
                            .with_tolerance(FC2D_TOLERANCE)
                            .with_max_sweeps(INEXACT_CHUNK_SWEEPS)
                            .with_lcp_max_contacts(0),
                    )?,
                ],
                newton: {
                    let newton = |tolerance, iterations| {
                        Newton::new(
                            NewtonOptions::default()
                                .with_tolerance(tolerance)
                                .with_max_iterations(iterations)
                                .with_smoothing_sweeps(NEWTON_SMOOTHING_SWEEPS)
                                .with_nonmonotone(NEWTON_NONMONOTONE),
                        )
                    };
                    [
                        newton(FC2D_TOLERANCE, NEWTON_ITERATIONS)?,
                        newton(SMALL_TOLERANCE, NEWTON_ITERATIONS)?,
                        newton(SMALL_TOLERANCE, SMALL_JOINTS_NEWTON_ITERATIONS)?,
                        newton(SMALL_TOLERANCE, NEWTON_ITERATIONS)?,
                    ]
                },
                proximal: Proximal::new(
                    ProximalOptions::default()
                        .with_tolerance(FC2D_TOLERANCE)
                        .with_smoothing_sweeps(NEWTON_SMOOTHING_SWEEPS),
                )?,
                lcp: LcpRoute::new(
                    LcpRouteOptions::default()
                        .with_tolerance(FC2D_TOLERANCE)
                        .with_max_contacts(PIVOTING_ISLAND),
                )?,
                start: Vec::new(),
            })),
            SolverChoice::Pgs { tolerance, omega, max_iterations } => Self::Nsgs(Nsgs::new(
                NsgsOptions::default()
                    .with_tolerance(tolerance)
                    .with_omega(omega)
                    .with_max_sweeps(max_iterations),
            )?),
            SolverChoice::Lemke | SolverChoice::Enumeration => {
                let solver = if matches!(choice, SolverChoice::Lemke) {
                    LcpRouteSolver::Lemke
                } else {
                    LcpRouteSolver::Enumeration
                };
                Self::Lcp(Box::new(LcpRoute::new(
                    LcpRouteOptions::default().with_tolerance(FC2D_TOLERANCE).with_solver(solver),
                )?))
            }
        })
    }

    /// Solves `problem` from `warm` for `purpose` and tells whether `out` is to be taken:
    /// solved, or with a natural residual at most the purpose's inexact residual. The default
    /// choice starts an island with joint groups by Newton for the step and the joints'
    /// correction (each with its own Newton, whose factorisation pattern then carries over
    /// from one step to the next), and ends a large island's chain at an iterate within the
    /// inexact residual once Gauss-Seidel's progress shows that its budget would not reach the
    /// tolerance (see [`INEXACT_CHUNK_SWEEPS`]).
    pub(in crate::stepper) fn solve(
        &mut self,
        problem: Fc2dRef<'_>,
        warm: &[f64],
        purpose: Purpose,
        out: &mut Fc2dSolution,
    ) -> Result<bool, LcpError> {
        let inexact = purpose.inexact();
        let acceptable = |out: &Fc2dSolution| out.is_solved() || out.residual.natural <= inexact;
        match self {
            Self::Auto(s) => {
                let AutoChain {
                    auto,
                    newton: [newton, step_joints, small_step_joints, correction],
                    proximal,
                    lcp,
                    start,
                } = &mut **s;
                let small = (1..=SMALL_JOINTS_CONTACTS).contains(&problem.n_contacts());
                let joints = match purpose {
                    Purpose::Step { .. } if small => Some(small_step_joints),
                    Purpose::Step { .. } => Some(step_joints),
                    Purpose::JointCorrection => Some(correction),
                    Purpose::ContactProjection => None,
                };
                if let Some(joints) = joints.filter(|_| problem.n_groups() > problem.n_contacts()) {
                    // Joints couple their bodies stiffly (a chain's rows form a path whose W
                    // has a condition number growing as the square of its length), where
                    // Gauss-Seidel crawls; Newton solves the joints' rows exactly once it has
                    // the contacts' cases, and from the step before's impulses it usually has
                    // them. A cold start in a hyperstatic pile (the contact projection's) is
                    // better left to Gauss-Seidel, where Newton cycles. Its tolerance is that of
                    // small islands: the joints' correction asks for their drift to round-off.
                    joints.solve_into(problem, Some(warm), out)?;
                    if out.is_solved() {
                        return Ok(true);
                    }
                }
                let large = problem.n_groups() > SMALL_ISLAND;
                if large && inexact > 0.0 {
                    start.clear();
                    start.extend_from_slice(warm);
                    let (mut sweeps, mut before) = (0, f64::INFINITY);
                    while sweeps < LARGE_ISLAND_SWEEPS {
                        let chunk = if sweeps == 0 { &mut auto[3] } else { &mut auto[4] };
                        chunk.solve_into(problem, Some(start), out)?;
                        sweeps += out.iterations.max(1);
                        let now = out.residual.natural;
                        let chunks_left = (LARGE_ISLAND_SWEEPS - sweeps.min(LARGE_ISLAND_SWEEPS))
                            / INEXACT_CHUNK_SWEEPS;
                        let reachable = now * (now / before).min(1.0).powi(chunks_left as i32)
                            <= FC2D_TOLERANCE;
                        if out.is_solved() || (now <= inexact && !reachable) {
                            out.iterations = sweeps;
                            return Ok(true);
                        }
                        before = now;
                        std::mem::swap(start, &mut out.r);
                    }
                    out.iterations = sweeps;
                } else {
                    auto[usize::from(large)].solve_into(problem, Some(warm), out)?;
                }
                if !acceptable(out) {
                    // A small island gets here when pivoting's exact solution still misses
                    // SMALL_TOLERANCE by its round-off: a hyperstatic pile of boxes, a capsule
                    // and a disk of 31 to 240 kg without the projection had an island of 6
                    // contacts that pivoting solved to 1.26e-13 only, and the run stopped.
                    //
                    // Dense packings make W singular and their reactions indeterminate, where
                    // Gauss-Seidel can crawl; Newton's regularised steps, started cold and
                    // each followed by a few sweeps, then usually solve the island. Where
                    // Newton cycles between the cases of contacts at the boundary of two,
                    // the proximal point method's positive definite sub-problems do not;
                    // pivoting is the last resort of islands small enough for it.
                    //
                    // A frictionless island with joint groups (a contact projection through
                    // a chain) is a positive semidefinite LCP, which pivoting solves or proves
                    // infeasible: a chain hanging straight from its pivot onto a pile in a box
                    // jams, and its projection has no solution. The stages for friction
                    // would spend 0.6 s to find nothing there (a chain of 8 links on 30 disks).
                    // So would they on any frictionless island small enough for pivoting: the
                    // contact projection of a stack of five boxes spent 50 Newton iterations
                    // on 47 of 2,000 steps before pivoting solved it. A larger one, with joints
                    // or not, has no pivoting to go to and takes the stages below.
                    let frictionless = problem.parts().mu.iter().all(|&mu| mu == 0.0);
                    let pivot_at_once = frictionless && problem.n_groups() <= PIVOTING_ISLAND;
                    if !pivot_at_once {
                        newton.solve_into(problem, None, out)?;
                        if !out.is_solved() {
                            proximal.solve_into(problem, None, out)?;
                        }
                        if !out.is_solved() {
                            // The proximal iterate is close (1e-6 on an island of 986 contacts
                            // of the settling column, which Gauss-Seidel alone finishes in
                            // 37,800 sweeps): Gauss-Seidel with the full budget finishes from it.
                            std::mem::swap(start, &mut out.r);
                            auto[2].solve_into(problem, Some(start), out)?;
                        }
                    }
                    if !acceptable(out) && problem.n_groups() <= PIVOTING_ISLAND {
                        lcp.solve_into(problem, None, out)?;
                    }
                }
            }
            Self::Nsgs(s) => s.solve_into(problem, Some(warm), out)?,
            Self::Lcp(s) => s.solve_into(problem, None, out)?,
        }
        Ok(acceptable(out))
    }
}
