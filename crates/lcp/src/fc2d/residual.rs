//! The one residual of the planar frictional-contact problem.

use serde::{Deserialize, Serialize};

use super::{Fc2dRef, chunks};

/// The units of ε times the largest term of a row of u = W r + q (and of r) in
/// [`Fc2dResidual::round_off`].
const ROUND_OFF_ULPS: f64 = 4.0;

/// The projection of `(x_N, x_T)` onto the planar Coulomb cone
/// `K = {x_N >= 0, |x_T| <= μ x_N}` (for μ = 0 the half-line x_T = 0 <= x_N), μ checked by
/// the problem's construction.
pub(crate) use moreau_setvalued::project_friction_cone as project_cone;

/// The natural map of one contact, `r - proj_K(r - (u + μ |u_T| e_N))`: zero exactly when
/// (r, u) satisfies Signorini's and Coulomb's laws (De Saxcé's bipotential form).
#[inline]
pub(crate) fn natural_map(r_n: f64, r_t: f64, u_n: f64, u_t: f64, mu: f64) -> (f64, f64) {
    moreau_setvalued::friction_natural_map((r_n, r_t), (u_n, u_t), mu, 1.0)
}

/// The residual of a candidate r for a planar frictional-contact problem: one definition
/// shared by every solver, test and report.
///
/// With u = W r + q recomputed from r, per contact i the natural map
/// `F_i = r_i - proj_K(r_i - (u_i + μ_i |u_T,i| e_N))` (K the planar Coulomb cone of
/// contact i, e_N = (1, 0); De Saxcé's modified velocity makes F_i = 0 equivalent to
/// Signorini's and Coulomb's laws), and per bilateral row b the violation `|u_b|`:
///
/// | field | definition |
/// |---|---|
/// | `absolute` | `max(max_i ‖F_i‖₂, max_b \|u_b\|)` |
/// | `natural` | `absolute / max(1, ‖q‖∞)`: the acceptance measure |
/// | `siconos` | `sqrt(Σ_i ‖F_i‖₂² + Σ_b u_b²) / max(‖r‖₂, ‖u‖₂, ‖q‖₂)` (no division when that maximum is below the machine epsilon) |
/// | `worst_group` | the contact or bilateral group where `absolute` is reached |
/// | `round_off` | `4 ε max_k ((\|W\| \|r\|)_k + \|q_k\| + \|r_k\|) / max(1, ‖q‖∞)`, ε the machine epsilon: the residual that floating point cannot resolve at r |
///
/// `siconos` is Siconos numerics' `fc2d_compute_error` with the norm of q as its `norm`
/// argument (as its NSGS passes it), extended by the bilateral rows; it is kept for
/// comparisons with Siconos' solvers.
///
/// `natural` is in the units of r and u together, scaled like the LCP residual: a problem
/// whose q is of order 1 or below is measured absolutely, a larger one relatively to q.
/// If r has a non-finite entry, every field is `+∞`.
///
/// **What a tolerance bounds.** F_i is zero exactly at a solution, but its size is not the
/// size of every violation: a contact with r_i = 0 that slides (u_T ≠ 0) while approaching
/// (u_N < 0) has `‖F_i‖ = |u_N| / sqrt(1 + μ²)` (0.89 |u_N| at μ = 0.5, |u_N| / 10 at
/// μ ≈ 10), so with a large μ such a contact passes a tolerance that its interpenetration
/// velocity exceeds: at μ = 1e9, r = 0 with u = (-1, 1) has `natural` = 1e-9. A
/// problem's `natural` is also absolute where ‖q‖∞ < 1: a problem of velocities of 1e-12
/// is solved, at any tolerance above 1e-12, by r = 0. Scale such problems (W, q and r
/// together) before solving them to a tolerance.
///
/// **Round-off.** Row k of u = W r + q sums terms as large as (|W| |r|)_k + |q_k|, and r_k
/// is itself rounded: a residual below a few units of ε times the largest of these terms is
/// not resolved by floating point at r. `round_off` is four such units, in the units of
/// `natural`. It is below 1e-14 where impulses and velocities are of order 1, and above a
/// tight tolerance where |W| |r| is large next to the velocities: in a chain whose links'
/// masses alternate between 1 and 10⁶, the reactions that carry the heavy links times W's
/// entries of the light ones reach 10³, `round_off` is about 1e-12, and nonsmooth Newton
/// asked for 1e-13 could spend its 50 iterations without reaching it. A solver reports
/// [`Status::Solved`](crate::Status) when `natural <= max(tolerance, round_off)`
/// ([`Fc2dResidual::meets`]): a tolerance below what floating point resolves at r is met at
/// round-off instead of being chased for the iterations left.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Fc2dResidual {
    /// `absolute / max(1, ‖q‖∞)`.
    pub natural: f64,
    /// Siconos' normalised error.
    pub siconos: f64,
    /// The largest per-contact natural map norm or bilateral violation.
    pub absolute: f64,
    /// Where `absolute` is reached (a group index: contacts first); 0 when all are zero.
    pub worst_group: usize,
    /// `4 ε max_k ((|W| |r|)_k + |q_k| + |r_k|) / max(1, ‖q‖∞)`: the natural residual that
    /// floating point does not resolve at r. A solver's result carries it only when `natural`
    /// exceeds the solver's tolerance, where it decides ([`Fc2dResidual::meets`]), and 0
    /// otherwise, sparing a pass over W; [`Fc2dResidual::compute`] carries it whenever
    /// `natural` > 0.
    #[serde(default)]
    pub round_off: f64,
}

impl Fc2dResidual {
    /// A residual with every field `+∞` (`worst_group` 0): the value of a solution not yet
    /// measured ([`Fc2dSolution::new`](super::Fc2dSolution::new)), which meets no tolerance.
    /// The default, all zeros, is that of a solved problem.
    pub const INFINITE: Fc2dResidual = Fc2dResidual {
        natural: f64::INFINITY,
        siconos: f64::INFINITY,
        absolute: f64::INFINITY,
        worst_group: 0,
        round_off: f64::INFINITY,
    };

    /// Whether r is a solution to `tolerance`: `natural <= max(tolerance, round_off)`, the
    /// test of every solver's [`Status::Solved`](crate::Status). A residual that is not
    /// finite (r, u or the natural map beyond f64's range, every field `+∞`) meets no
    /// tolerance, and neither does an infinite `round_off` stand in for one.
    #[inline]
    pub fn meets(&self, tolerance: f64) -> bool {
        self.natural <= tolerance || (self.natural <= self.round_off && self.round_off.is_finite())
    }

    /// Recomputes `u = W r + q` into `u` and measures r. An r or u without one entry per row
    /// of the problem gives [`Fc2dResidual::INFINITE`] (u untouched), which meets no
    /// tolerance, as [`Residual::compute`](crate::Residual::compute) does for an LCP.
    pub fn compute(problem: Fc2dRef<'_>, r: &[f64], u: &mut [f64]) -> Fc2dResidual {
        let n = problem.n_rows();
        if r.len() != n || u.len() != n {
            return Fc2dResidual::INFINITE;
        }
        problem.velocity(r, u);
        Self::of_velocity(problem, r, u, 0.0)
    }

    /// Measures r with a given `u`, which must be `W r + q` (as [`Fc2dResidual::compute`]
    /// writes it), against `tolerance`: `round_off` only when `natural` exceeds it, 0
    /// otherwise.
    pub(crate) fn of_velocity(
        problem: Fc2dRef<'_>,
        r: &[f64],
        u: &[f64],
        tolerance: f64,
    ) -> Fc2dResidual {
        let n_c = problem.n_contacts();
        let mu = problem.mu();
        let q = problem.q();
        let gs = problem.parts().group_start;
        // (largest ‖F_i‖ or |u_b|, where, Σ of squares, all finite) over a range of groups: in
        // chunks of groups on rayon's pool for a large problem, merged in group order, so that
        // the result does not depend on the pool.
        let of_groups = |groups: std::ops::Range<usize>| {
            let (mut absolute, mut worst, mut sum, mut finite) = (0.0f64, 0, 0.0, true);
            for g in groups {
                if g < n_c {
                    let (i, m) = (2 * g, mu[g]);
                    let (f_n, f_t) = natural_map(r[i], r[i + 1], u[i], u[i + 1], m);
                    let e2 = f_n * f_n + f_t * f_t;
                    finite &= e2.is_finite();
                    sum += e2;
                    let e = e2.sqrt();
                    if e > absolute {
                        absolute = e;
                        worst = g;
                    }
                } else {
                    for &v in &u[gs[g]..gs[g + 1]] {
                        finite &= v.is_finite();
                        sum += v * v;
                        if v.abs() > absolute {
                            absolute = v.abs();
                            worst = g;
                        }
                    }
                }
            }
            (absolute, worst, sum, finite)
        };
        let merge = |a: (f64, usize, f64, bool), b: (f64, usize, f64, bool)| {
            let (absolute, worst) = if b.0 > a.0 { (b.0, b.1) } else { (a.0, a.1) };
            (absolute, worst, a.2 + b.2, a.3 && b.3)
        };
        let (absolute, worst, sum, mut finite) =
            chunks::reduce(0..problem.n_groups(), &of_groups, &merge);
        let norm2 = |x: &[f64]| x.iter().map(|v| v * v).sum::<f64>().sqrt();
        finite &= r.iter().all(|v| v.is_finite()) && u.iter().all(|v| v.is_finite());
        if !finite {
            return Fc2dResidual {
                natural: f64::INFINITY,
                siconos: f64::INFINITY,
                absolute: f64::INFINITY,
                worst_group: worst,
                round_off: f64::INFINITY,
            };
        }
        let scale = norm2(r).max(norm2(u)).max(norm2(q));
        let error = sum.sqrt();
        let q_scale = problem.q_norm_inf().max(1.0);
        let natural = absolute / q_scale;
        Fc2dResidual {
            natural,
            siconos: if scale > f64::EPSILON { error / scale } else { error },
            absolute,
            worst_group: worst,
            round_off: if natural > tolerance { Self::floor(problem, r) / q_scale } else { 0.0 },
        }
    }

    /// `4 ε max_k ((|W| |r|)_k + |q_k| + |r_k|)`: [`Self::round_off`] before the division by
    /// max(1, ‖q‖∞). One more pass over W's blocks, in chunks as the residual.
    fn floor(problem: Fc2dRef<'_>, r: &[f64]) -> f64 {
        let (q, gs) = (problem.q(), problem.parts().group_start);
        let of_groups = |groups: std::ops::Range<usize>| {
            let mut largest = 0.0f64;
            for g in groups {
                let size = problem.row_magnitude(g, r);
                for (k, &s) in (gs[g]..gs[g + 1]).zip(&size) {
                    largest = largest.max(s + q[k].abs() + r[k].abs());
                }
            }
            largest
        };
        let largest = chunks::reduce(0..problem.n_groups(), &of_groups, &|a: f64, b: f64| a.max(b));
        ROUND_OFF_ULPS * f64::EPSILON * largest
    }
}
