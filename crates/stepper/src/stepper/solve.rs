//! The contact solves of a step done without the general LCP solvers: one active frictional
//! contact in closed form, and the Gauss-Seidel choice through moreau-lcp's block
//! Gauss-Seidel on the step's frictional-contact problem.
#![allow(non_snake_case)]

use super::*;

/// Relative residual up to which a closed-form solution is accepted (that of the LCP
/// solvers' default).
pub(super) const CLOSED_FORM_TOLERANCE: f64 = 1e-9;

/// `moreau_lcp::Residual::relative` of z = P_N > 0 for the scalar LCP A z + b ≥ 0 with
/// w = A z + b: with z > 0 and the equation exact, it is |w| / max(|b|, |A z|), at most 1.
/// Written out because the general residual costs more than the rest of such a step.
#[inline(always)]
pub(super) fn closed_form_residual(a: f64, b: f64, p_n: f64) -> f64 {
    let w = a * p_n + b;
    let scale = b.abs().max((a * p_n).abs());
    if scale > 0.0 { (w.abs() / scale).min(1.0) } else { 0.0 }
}

/// The cases of one active contact's LCP (docs/theory.md section 5 with n = 1), in the order
/// they are tried.
#[derive(Clone, Copy, PartialEq)]
pub(super) enum Mode {
    /// ξ_T = 0 with |P_T| ≤ μ P_N: (P_N, P_R) from the 2 × 2 system, ξ_L = 0.
    Stick,
    /// ξ_T > 0: P_T = −μ P_N (P_R = 0, ξ_L = 0).
    SlidePositive,
    /// ξ_T < 0: P_T = +μ P_N (P_L = 0, so P_R = 2μ P_N; ξ_L = −ξ_T).
    SlideNegative,
}

/// Solves the LCP of a single active frictional contact (three rows, x = (P_N, P_R, ξ_L)) in
/// closed form, as the time-stepper's default solver does (a frictionless one takes
/// `Stepper::one_frictionless_contact`). With b_N < 0 the contact carries an impulse, and one
/// of stick, slip forwards and slip backwards holds; they are tried starting with the previous
/// step's case, the one that holds on most steps (should several hold, it is also the one
/// kept, as with Auto's warm basis). The z found is accepted only when the shared residual
/// passes [`CLOSED_FORM_TOLERANCE`]; otherwise `None`, and the caller runs the general solver.
pub(super) fn one_contact_closed_form(
    A: &[f64],
    b: &[f64],
    mu: f64,
    prev: [f64; 3],
    out: &mut Solution,
) -> Option<LcpInfo> {
    const S: usize = 3;
    let (A, b): (&[f64; S * S], &[f64; S]) = (A.try_into().ok()?, b.try_into().ok()?);
    // A is column-major: A[r + 3 c].
    let (a00, a10, a01, a11) = (A[0], A[1], A[3], A[4]);
    let [p_n, p_r, xi_l] = prev;
    let first = if p_n > 0.0 && xi_l > 0.0 {
        Mode::SlideNegative
    } else if p_n > 0.0 && p_r == 0.0 {
        Mode::SlidePositive
    } else {
        Mode::Stick
    };
    let others = [Mode::Stick, Mode::SlidePositive, Mode::SlideNegative];
    let mut order = std::iter::once(first).chain(others.into_iter().filter(|&m| m != first));
    // Comparisons with NaN are false: a singular case yields no candidate.
    let found = order.find_map(|mode| match mode {
        Mode::Stick => {
            let det = a00 * a11 - a01 * a10;
            let p_n = (a01 * b[1] - a11 * b[0]) / det;
            let p_r = (a10 * b[0] - a00 * b[1]) / det;
            (p_n >= 0.0 && p_r >= 0.0 && 2.0 * mu * p_n - p_r >= 0.0).then_some([p_n, p_r, 0.0])
        }
        Mode::SlidePositive => {
            let p_n = -b[0] / a00;
            (p_n >= 0.0 && a10 * p_n + b[1] >= 0.0).then_some([p_n, 0.0, 0.0])
        }
        Mode::SlideNegative => {
            let p_n = -b[0] / (a00 + 2.0 * mu * a01);
            let xi_l = -(a10 * p_n + 2.0 * mu * a11 * p_n + b[1]);
            (p_n >= 0.0 && xi_l >= 0.0).then_some([p_n, 2.0 * mu * p_n, xi_l])
        }
    })?;
    let (z, w) = (&mut out.z, &mut out.w);
    z.clear();
    z.extend_from_slice(&found);
    w.clear();
    for r in 0..S {
        w.push(b[r] + (0..S).map(|c| A[r + c * S] * z[c]).sum::<f64>());
    }
    let residual = moreau_lcp::Residual::compute_column_major(S, A, b, z, w);
    (residual.relative <= CLOSED_FORM_TOLERANCE).then_some(LcpInfo {
        method: Method::ClosedForm,
        status: Status::Solved,
        iterations: 0,
        residual: residual.relative,
    })
}

/// Contacts above which the default solver hands a step to the planar frictional-contact
/// solvers (the islands' chain: `Fc2dAuto`, block Gauss-Seidel with exact solves of the
/// clusters that stall, then Newton, the proximal point method and pivoting) rather than to
/// the dense LCP of eq. 7.41, whose pivoting costs O((3 n)³).
pub(super) const FC2D_ROUTE_CONTACTS: usize = 24;

/// Which solver of planar frictional contact a step uses.
#[derive(Clone, Copy, PartialEq)]
pub(super) enum Fc2dRoute {
    /// The nonsmooth Gauss-Seidel of the Gauss-Seidel choice.
    GaussSeidel,
    /// The islands' chain of the default choice, beyond [`FC2D_ROUTE_CONTACTS`] and where
    /// pivoting on eq. 7.41 fails.
    Auto,
}

/// A solver of `moreau_lcp` for planar frictional contact on the contact problem in (P_N, P_T),
/// equivalent to the LCP of eq. 7.41: W is the Delassus matrix G = [W_N W_T]ᵀ M⁻¹ [W_N W_T]
/// ordered by contact, q = (b_N, b_R) and μ per contact; a frictionless contact gets μ = 0
/// and a tangential row of its own scale coupled to nothing, which keeps its P_T at zero.
/// Warm-started from the previous step's impulses. Writes z = (P_N; P_R; ξ_L) of eq. 7.41
/// into `ws.solution.z` and checks it with the LCP's own residual.
pub(super) fn frictional_contact(
    ws: &mut Workspace,
    laws: &[moreau_setvalued::ContactLaw],
    route: Fc2dRoute,
) -> Result<LcpInfo, LcpFailure> {
    let f = ws.q_m.len();
    let na = ws.active.len();
    let nf = ws.frictional.len();
    let m = na + nf;
    let s = na + 2 * nf;
    // M⁻¹ w_N = y_N + μ x_T for frictional contacts, y_N otherwise.
    let column = |ws: &Workspace, c: usize, out: &mut [f64]| {
        if c < na {
            out.copy_from_slice(&ws.y_n[c * f..][..f]);
            if let Some(k) = ws.frictional.iter().position(|&a| a == c) {
                let mu = laws[ws.active[c]].mu();
                for (o, x) in out.iter_mut().zip(&ws.x_t[k * f..][..f]) {
                    *o += mu * x;
                }
            }
        } else {
            let k = c - na;
            out.copy_from_slice(&ws.x_t[k * f..][..f]);
        }
    };
    let row = |ws: &Workspace, r: usize| -> std::ops::Range<usize> {
        let a = if r < na { r } else { ws.frictional[r - na] };
        a * f..(a + 1) * f
    };
    let mut x = std::mem::take(&mut ws.tmp);
    for c in 0..m {
        column(ws, c, &mut x);
        for r in 0..m {
            let w = if r < na { &ws.w_n[row(ws, r)] } else { &ws.w_t[row(ws, r)] };
            ws.g[r + c * m] = dot(w, &x);
        }
    }
    ws.tmp = x;
    // The row (and column) of G of each contact's tangential impulse, if it has one.
    let g = &ws.g[..m * m];
    let tangent = |a: usize| ws.frictional.iter().position(|&c| c == a).map(|k| na + k);
    let n = 2 * na;
    let w = &mut ws.fc_w[..n * n];
    w.fill(0.0);
    for a in 0..na {
        let (ra, ta) = (a, tangent(a));
        for c in 0..na {
            let (rc, tc) = (c, tangent(c));
            w[2 * a + 2 * c * n] = g[ra + rc * m];
            if let Some(tc) = tc {
                w[2 * a + (2 * c + 1) * n] = g[ra + tc * m];
            }
            if let Some(ta) = ta {
                w[2 * a + 1 + 2 * c * n] = g[ta + rc * m];
                if let Some(tc) = tc {
                    w[2 * a + 1 + (2 * c + 1) * n] = g[ta + tc * m];
                }
            }
        }
        let law = laws[ws.active[a]];
        let [p_n, p_r, _] = ws.prev[ws.active[a]];
        ws.fc_q[2 * a] = ws.b[a];
        ws.fc_warm[2 * a] = p_n;
        match ta {
            Some(t) => {
                ws.fc_q[2 * a + 1] = ws.b[t];
                ws.fc_mu[a] = law.mu();
                ws.fc_warm[2 * a + 1] = p_r - law.mu() * p_n;
            }
            None => {
                let d = g[a + a * m];
                w[2 * a + 1 + (2 * a + 1) * n] = if d > 0.0 { d } else { 1.0 };
                ws.fc_q[2 * a + 1] = 0.0;
                ws.fc_mu[a] = 0.0;
                ws.fc_warm[2 * a + 1] = 0.0;
            }
        }
    }
    ws.fc
        .set_dense(MatRef::from_column_major_slice(w, n, n), &ws.fc_q[..n], &ws.fc_mu[..na])
        .map_err(LcpFailure::Input)?;
    let warm = &ws.fc_warm[..n];
    if route == Fc2dRoute::Auto && ws.fc_auto.is_none() {
        ws.fc_auto = Some(IslandSolver::new(&SolverChoice::Auto).map_err(LcpFailure::Solver)?);
    }
    match route {
        Fc2dRoute::GaussSeidel => {
            let nsgs = ws.nsgs.as_mut().expect("the Gauss-Seidel choice holds its solver");
            nsgs.solve_into(ws.fc.view(), Some(warm), &mut ws.fc_solution)
        }
        Fc2dRoute::Auto => {
            let chain = ws.fc_auto.as_mut().expect("built above");
            let step = Purpose::Step { inexact: 0.0 };
            chain.solve(ws.fc.view(), warm, step, &mut ws.fc_solution).map(|_| ())
        }
    }
    .map_err(LcpFailure::Solver)?;
    // z = (P_N; P_R = P_T + μ P_N; ξ_L = max(0, −ξ_T)) of eq. 7.41, and its residual.
    let (r, u) = (&ws.fc_solution.r, &ws.fc_solution.u);
    let z = &mut ws.solution.z;
    z.clear();
    z.resize(s, 0.0);
    for a in 0..na {
        z[a] = r[2 * a];
    }
    for (k, &a) in ws.frictional.iter().enumerate() {
        z[na + k] = r[2 * a + 1] + ws.fc_mu[a] * r[2 * a];
        z[na + nf + k] = (-u[2 * a + 1]).max(0.0);
    }
    let w = &mut ws.solution.w;
    w.clear();
    w.resize(s, 0.0);
    for r in 0..s {
        let mut v = ws.b[r];
        for c in 0..s {
            v += ws.a[r + c * s] * z[c];
        }
        w[r] = v;
    }
    let lcp = LcpRef::new(
        MatRef::from_column_major_slice(&ws.a[..s * s], s, s),
        ColRef::from_slice(&ws.b[..s]),
    );
    let residual = match lcp {
        Ok(lcp) => moreau_lcp::Residual::compute(lcp, z, w).relative,
        Err(_) => f64::INFINITY,
    };
    Ok(LcpInfo {
        method: ws.fc_solution.method,
        status: ws.fc_solution.status,
        iterations: ws.fc_solution.iterations,
        residual,
    })
}
