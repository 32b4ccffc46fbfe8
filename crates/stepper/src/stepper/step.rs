//! One step of the midpoint rule on the stepper's state: the midpoint, the free velocity,
//! the assembly of the step's contact problem, its solution, the velocity update and the
//! per-contact report.
#![allow(non_snake_case)]

use super::joints::check_apart;
use super::*;

impl Core {
    /// The report of the step just taken.
    pub(super) fn report(&self) -> StepReport<'_> {
        match &self.body {
            Some(body) => body.report(self),
            None => self.dense_report(),
        }
    }

    /// The report of the step just taken on the path of fixed contacts. Inlined, so that
    /// the fields an observer does not read are never written.
    #[inline(always)]
    pub(super) fn dense_report(&self) -> StepReport<'_> {
        StepReport {
            step: self.step - 1,
            t: self.t,
            q: &self.q,
            u: &self.u,
            contacts: &self.contacts,
            contact_ids: &self.contact_ids,
            lcp_size: self.ws.lcp_size,
            // Set only by steps with contacts.
            lcp: if self.ws.lcp_size > 0 { self.ws.lcp_info } else { None },
            penetration: self.ws.penetration,
            joint_drift: self.ws.joint_drift,
            q_unprojected: self.ws.projected.then_some(&self.ws.q_unprojected[..]),
            islands: 0,
            times: crate::report::PhaseTimes::default(),
            mass: crate::report::MassView::Dense(&self.ws.mass),
            u_free: if self.ws.joints.n > 0 { &self.ws.u_unconstrained } else { &self.ws.u_free },
            u_start: &self.ws.u_start,
            joint_impulses: &self.ws.joint_impulses,
        }
    }

    /// The body of [`Stepper::step`]: updates (t, q, u) and the contact reports.
    pub(super) fn advance<K: Mechanism>(&mut self, mech: &K) -> Result<(), StepError> {
        match self.q.len() {
            1 => self.advance_n::<K, 1>(mech),
            2 => self.advance_n::<K, 2>(mech),
            3 => self.advance_n::<K, 3>(mech),
            4 => self.advance_n::<K, 4>(mech),
            _ => self.advance_n::<K, 0>(mech),
        }
    }

    /// [`Self::advance`] for f = N coordinates (`N > 0`: the small mechanisms, whose loops over
    /// the coordinates then have constant bounds) or any f (`N = 0`).
    #[inline(always)]
    pub(super) fn advance_n<K: Mechanism, const N: usize>(
        &mut self,
        mech: &K,
    ) -> Result<(), StepError> {
        let f = order::<N>(self.q.len());
        let dt = self.options.dt;
        let half = 0.5 * dt;
        let t_m = self.t + half;
        let ws = &mut self.ws;

        for ((q_m, q), u) in ws.q_m[..f].iter_mut().zip(&self.q[..f]).zip(&self.u[..f]) {
            *q_m = q + half * u;
        }
        if ws.joints.n > 0 && self.options.projection {
            ws.q_start[..f].copy_from_slice(&self.q[..f]);
        }
        let new_mass = !(ws.factored && mech.constant_mass_matrix());
        let mass = new_mass.then_some(&mut ws.mass[..f * f]);
        crate::mechanism::evaluate(
            mech,
            &ws.q_m[..f],
            &self.u[..f],
            t_m,
            mass,
            &mut ws.h[..f],
            &mut ws.gaps,
            &mut ws.memo,
        );
        if new_mass {
            check_finite("M", &ws.mass[..f * f], t_m)?;
            ws.chol
                .factor::<N>(&ws.mass)
                .map_err(|e| StepError::MassNotSpd { t: t_m, reason: e.to_string() })?;
            ws.factored = true;
        }
        // A non-finite h gives a non-finite ũ, which the check of u_E below reports as h.
        ws.chol.solve_scaled_add::<N>(&mut ws.h[..f], dt, &self.u[..f], &mut ws.u_free[..f]);
        if ws.joints.n > 0 {
            // ũ becomes ũ', which satisfies the bilateral constraints; every M⁻¹ w below
            // becomes M̂⁻¹ w (joints.rs). ũ is kept for the report's work of the impulses.
            ws.u_unconstrained[..f].copy_from_slice(&ws.u_free[..f]);
            let start = (&self.q[..f], &self.u[..f], self.t);
            let midpoint = (&ws.q_m[..f], t_m, &ws.memo[..]);
            ws.joints.assemble(mech, start, midpoint, &ws.chol)?;
            ws.joints.constrain(&mut ws.u_free[..f], true);
            ws.joints.check_kept(&ws.u_free[..f], t_m)?;
            ws.joint_drift = ws.joints.drift();
            check_apart(&self.q[..f], self.options.joint_tolerance, ws.joint_drift, t_m)?;
        }

        ws.last_size = 0;
        ws.active.clear();
        let mut poison = 0.0;
        let mut lowest = 0.0f64;
        for (i, &g) in ws.gaps.iter().enumerate() {
            // x · 0 is 0 for a finite x and NaN otherwise: one test after the loop.
            poison += g * 0.0;
            lowest = lowest.min(g);
            if g <= self.options.gap_tolerance {
                ws.active.push(i);
            }
        }
        ws.penetration = -lowest;
        if poison != 0.0 {
            check_finite("h", &ws.h, t_m)?;
            check_finite("g_N", &ws.gaps, t_m)?;
        }

        // Steps without contacts, closed now or in the step before, skip what follows out of
        // line.
        let contacts = !(ws.active.is_empty() && ws.reported.is_empty());
        if contacts {
            self.solve_contacts::<K, N>(mech, t_m)?;
        } else {
            self.ws.lcp_size = 0;
        }
        let ws = &mut self.ws;
        let lcp_size = ws.lcp_size;
        let u_new = if lcp_size > 0 { &mut ws.tmp } else { &mut ws.u_free };
        // q_E and u_E, with one test for non-finite values in both; the cold path names the
        // culprit. A non-finite h gives a non-finite ũ, so it is caught here too.
        let mut poison = 0.0;
        for ((q_e, q_m), u) in ws.q_e[..f].iter_mut().zip(&ws.q_m[..f]).zip(&u_new[..f]) {
            *q_e = q_m + half * u;
            poison += *q_e * 0.0 + *u * 0.0;
        }
        if poison != 0.0 {
            diagnose_non_finite(&ws.h, u_new, &ws.q_e, t_m)?;
        }
        if lcp_size > 0 || ws.joints.n > 0 {
            // u_A, for the report's work of the impulses.
            ws.u_start[..f].copy_from_slice(&self.u[..f]);
        }
        if N == 0 {
            // q_A and u_A are not needed any more: swap the buffers rather than copy.
            std::mem::swap(&mut self.u, u_new);
            std::mem::swap(&mut self.q, &mut ws.q_e);
        } else {
            // A few entries cost less to copy than the buffers do to swap.
            self.u[..f].copy_from_slice(&u_new[..f]);
            self.q[..f].copy_from_slice(&ws.q_e[..f]);
        }

        if contacts {
            self.report_contacts::<K, N>(mech);
        }
        if self.ws.joints.n > 0 {
            self.joint_impulses(f);
        }

        if self.options.projection {
            let t_e = self.t0 + step_count_as_f64(self.step + 1) * dt;
            self.ws.q_unprojected[..f].copy_from_slice(&self.q[..f]);
            let projected = self.project(mech, t_e);
            self.ws.projected = self.q[..f] != self.ws.q_unprojected[..f];
            if let Err(e) = projected {
                // The joints' evaluation at the end is not that of the next step's start.
                self.ws.joints.moved();
                return Err(e);
            }
        }

        self.step += 1;
        self.t = self.t0 + step_count_as_f64(self.step) * dt;
        Ok(())
    }

    /// The contact part of a step before u_E: clears the previous step's contact reports
    /// and, when contacts are closed, solves their LCP (u_E into `ws.tmp`). Sets the step's
    /// LCP size and information.
    #[inline(never)]
    pub(super) fn solve_contacts<K: Mechanism, const N: usize>(
        &mut self,
        mech: &K,
        t_m: f64,
    ) -> Result<(), StepError> {
        let ws = &mut self.ws;
        for &i in &ws.reported {
            self.contacts[i] = ContactReport::default();
        }
        ws.reported.clear();
        ws.lcp_size = 0;
        ws.lcp_info = None;
        if !ws.active.is_empty() {
            check_finite("h", &ws.h[..order::<N>(ws.h.len())], t_m)?;
            // The previous step's impulses are overwritten by this step's solve.
            for (closed, &i) in ws.closed_before.iter_mut().zip(&ws.active) {
                *closed = ws.prev[i][0] > 0.0;
            }
            let (size, solved) =
                Self::contact_step::<K, N>(mech, &self.options, &mut self.solver, ws, &self.u, t_m)
                    .map_err(|e| self.lcp_error(e, t_m))?;
            let ws = &mut self.ws;
            ws.lcp_size = size;
            ws.lcp_info = Some(solved);
            if solved.method != Method::Trivial {
                ws.lcp_solves += 1;
            }
        }
        Ok(())
    }

    /// The joints' impulses Λ_B of the step just taken, from ũ before the joints and the
    /// active contacts' impulses at q_M (see `Joints::impulses`).
    #[inline(never)]
    fn joint_impulses(&mut self, f: usize) {
        let ws = &mut self.ws;
        let wcp = &mut ws.tmp[..f];
        wcp.fill(0.0);
        for (a, &i) in ws.active.iter().enumerate() {
            let (p_n, p_t) = (self.contacts[i].p_n, self.contacts[i].p_t);
            let (w_n, w_t) = (&ws.w_n[a * f..][..f], &ws.w_t[a * f..][..f]);
            for ((x, n), t) in wcp.iter_mut().zip(w_n).zip(w_t) {
                *x += n * p_n + t * p_t;
            }
        }
        ws.joints.impulses(&ws.u_unconstrained[..f], &ws.tmp[..f], &mut ws.joint_impulses);
    }

    /// The contact reports of a step from its end velocities; forgets the impulses of the
    /// contacts that have opened.
    #[inline(never)]
    pub(super) fn report_contacts<K: Mechanism, const N: usize>(&mut self, mech: &K) {
        let f = order::<N>(self.q.len());
        let ws = &mut self.ws;
        let laws = mech.laws();
        let u = &self.u[..f];
        for (a, &i) in ws.active.iter().enumerate() {
            let w_n = &ws.w_n[a * f..][..f];
            let w_t = &ws.w_t[a * f..][..f];
            let gamma_n = dot(w_n, u) + ws.w_n_hat[a];
            let gamma_t = dot(w_t, u) + ws.w_t_hat[a];
            let [p_n, p_r, _] = ws.prev[i];
            let mu = laws[i].mu();
            // P_T = P_R − μ P_N (section 5); P_R is zero for a contact without friction rows.
            let p_t = p_r - mu * p_n;
            let scale: f64 = w_t.iter().zip(u).map(|(w, u)| (w * u).abs()).sum();
            self.contacts[i] = active_report(
                [p_n, p_t],
                [gamma_n, gamma_t],
                [ws.gamma_na[a], ws.gamma_ta[a]],
                ws.closed_before[a],
                scale,
            );
            ws.reported.push(i);
        }
        for (i, c) in self.contacts.iter().enumerate() {
            if !c.active {
                ws.prev[i] = [0.0; 3];
            }
        }
    }

    /// Moves q_E back onto the admissible set g_N(q, t_E) ≥ 0 along M⁻¹ W_N:
    /// q_E ← q_E + M⁻¹ W_N λ with 0 ≤ λ ⊥ W_Nᵀ M⁻¹ W_N λ + g_N ≥ 0 over all contacts, when
    /// one penetrates by more than `projection_tolerance`, repeated (at most four times) while the linearisation leaves some
    /// penetration. Velocities are not changed, so kinetic energy is not changed.
    ///
    /// For bodies in maximal coordinates (`Mechanism::maximal_coordinates`), G = M_k / m_k
    /// body by body takes M's place here, joints kept included, so that every body weighs
    /// alike: in M, a body a million times lighter than its neighbours is a million times
    /// cheaper to move, and a light box pinched between two heavy ones was pushed out
    /// sideways along their faces, tilted by a thousandth, by tens of centimetres per step.
    pub(super) fn project<K: Mechanism>(&mut self, mech: &K, t_e: f64) -> Result<(), StepError> {
        let f = self.q.len();
        let ws = &mut self.ws;
        if ws.joints.n > 0 {
            // The contacts that carried an impulse in this step rest or press: the joints'
            // correction keeps their gaps, which it would otherwise open or close (joints.rs).
            let mut closed = 0;
            for (a, &i) in ws.active.iter().enumerate() {
                if ws.prev[i][0] > 0.0 {
                    ws.proj_w[closed * f..][..f].copy_from_slice(&ws.w_n[a * f..][..f]);
                    closed += 1;
                }
            }
            let held = &ws.proj_w[..closed * f];
            let tolerance = self.options.joint_tolerance;
            if let Err(e) = ws.joints.project(mech, &mut self.q, t_e, &ws.chol, held, tolerance) {
                // The step is refused: its start comes back (u_A is kept for joints).
                self.q.copy_from_slice(&ws.q_start[..f]);
                self.u.copy_from_slice(&ws.u_start[..f]);
                return Err(e);
            }
        }
        // Bodies in maximal coordinates are moved in the metric in which they weigh alike.
        let alike = mech.maximal_coordinates();
        let mut weighed = false;
        for _ in 0..4 {
            // Every contact enters the projection LCP once one penetrates: pushing a corner
            // out can push its neighbour on the same face in, and complementarity keeps the
            // open ones (g_N > 0) free of impulse. Penetrations within the tolerance are left
            // alone, so that resting contacts stay closed.
            ws.proj_active.clear();
            let mut penetrating = false;
            mech.normal_gaps(&self.q, t_e, &mut ws.proj_b);
            for (i, &g) in ws.proj_b.iter().enumerate() {
                if !g.is_finite() {
                    return Err(StepError::NonFinite { what: "g_N", index: i, t: t_e });
                }
                penetrating |= g < -self.options.projection_tolerance;
                ws.proj_active.push(i);
            }
            let k = ws.proj_active.len();
            if !penetrating {
                break;
            }
            if alike && !weighed && ws.joints.n > 0 {
                ws.joints.weigh_bodies_alike(&ws.mass[..f * f], t_e)?;
                weighed = true;
            }
            for (a, &i) in ws.proj_active.iter().enumerate() {
                let (w_n, x) = (&mut ws.proj_w[a * f..][..f], &mut ws.proj_x[a * f..][..f]);
                mech.contact(i, &self.q, t_e, w_n, &mut ws.tmp);
                x.copy_from_slice(w_n);
                ws.chol.solve(x);
                if alike {
                    weigh_bodies_alike(x, &ws.mass[..f * f]);
                }
                ws.joints.constrain(x, false);
            }
            for c in 0..k {
                for r in 0..k {
                    ws.proj_a[r + c * k] = dot(&ws.proj_w[r * f..][..f], &ws.proj_x[c * f..][..f]);
                }
            }
            let lcp = LcpRef::new(
                MatRef::from_column_major_slice(&ws.proj_a[..k * k], k, k),
                ColRef::from_slice(&ws.proj_b[..k]),
            )?;
            ws.proj_solver.solve_into(lcp, None, &mut ws.proj_solution)?;
            let tolerance = self.options.projection_tolerance;
            if ws.proj_solution.status != Status::Solved
                && !projects_within(&ws.proj_solution, tolerance)
            {
                // A projection that cannot be computed leaves q_E as the scheme gave it.
                break;
            }
            ws.joints.moved();
            for (c, lambda) in ws.proj_solution.z.iter().enumerate() {
                for (q, x) in self.q.iter_mut().zip(&ws.proj_x[c * f..][..f]) {
                    *q += x * lambda.max(0.0);
                }
            }
        }
        check_finite("q", &self.q, t_e)
    }

    /// Assembles and solves the LCP of the active contacts; writes u_E into `ws.tmp` and the
    /// impulses (P_N, P_R, ξ_L) into `ws.prev`. Returns the LCP size and how it was solved.
    pub(super) fn contact_step<K: Mechanism, const N: usize>(
        mech: &K,
        options: &StepperOptions,
        solver: &mut SolverImpl,
        ws: &mut Workspace,
        u_a: &[f64],
        t_m: f64,
    ) -> Result<(usize, LcpInfo), LcpFailure> {
        let f = order::<N>(u_a.len());
        let u_a = &u_a[..f];
        let laws = mech.laws();
        if let [i] = ws.active[..]
            && !(laws[i].is_frictional() || options.friction_rows_when_frictionless)
            && matches!(options.solver, SolverChoice::Auto)
            && let Some(done) = Self::one_frictionless_contact::<K, N>(mech, ws, u_a, t_m, i)?
        {
            return Ok(done);
        }
        ws.frictional.clear();
        let na = ws.active.len();
        mark_unwritten(&mut ws.w_n[..na * f], &mut ws.w_t[..na * f]);
        crate::mechanism::midpoint_contacts(
            mech,
            &ws.active,
            &ws.q_m,
            t_m,
            &ws.memo,
            &mut ws.w_n[..na * f],
            &mut ws.w_t[..na * f],
            &mut ws.points[..na],
        );
        // γ_A, and b = W' ũ + ŵ + ε γ_A (eq. 7.41 with W' M⁻¹ h Δt + γ_A = W' ũ + ŵ): rows N
        // of all contacts, rows R of the frictional ones; rows L are zero.
        let u_free = &ws.u_free[..f];
        let mut all_separating = true;
        let mut poison = 0.0;
        for (a, &i) in ws.active.iter().enumerate() {
            let law = laws[i];
            let (w_n, w_t) = (&ws.w_n[a * f..][..f], &ws.w_t[a * f..][..f]);
            // x · 0 is 0 for a finite x and NaN otherwise: one test after the loop.
            for (n_j, t_j) in w_n.iter().zip(w_t) {
                poison += n_j * 0.0 + t_j * 0.0;
            }
            let point = ws.points[a];
            poison += point.w_n_hat * 0.0 + point.w_t_hat * 0.0;
            ws.w_n_hat[a] = point.w_n_hat;
            ws.w_t_hat[a] = point.w_t_hat;
            let gamma_n = dot(w_n, u_a) + point.w_n_hat;
            let gamma_t = dot(w_t, u_a) + point.w_t_hat;
            ws.gamma_na[a] = gamma_n;
            ws.gamma_ta[a] = gamma_t;
            let b_n = dot(w_n, u_free) + point.w_n_hat + law.eps_n() * gamma_n;
            ws.b[a] = b_n;
            all_separating &= b_n >= 0.0;
            if law.is_frictional() || options.friction_rows_when_frictionless {
                let k = ws.frictional.len();
                ws.b[na + k] = dot(w_t, u_free) + point.w_t_hat + law.eps_t() * gamma_t;
                ws.mu_f[k] = law.mu();
                ws.frictional.push(a);
            }
        }
        if poison != 0.0 {
            for (a, &i) in ws.active.iter().enumerate() {
                check_directions(i, &ws.w_n[a * f..][..f], &ws.w_t[a * f..][..f])?;
            }
            check_rheonomic(&ws.active, &ws.points[..na])?;
        }
        let nf = ws.frictional.len();
        let s = na + 2 * nf;
        ws.b[na + nf..s].fill(0.0);

        if all_separating {
            // The zero-impulse solution: P_N = P_R = 0, ξ_L = max(0, −b_R).
            ws.tmp.copy_from_slice(&ws.u_free);
            for &i in ws.active.iter() {
                ws.prev[i] = [0.0; 3];
            }
            for (k, &a) in ws.frictional.iter().enumerate() {
                ws.prev[ws.active[a]][2] = (-ws.b[na + k]).max(0.0);
            }
            let info = LcpInfo {
                method: Method::Trivial,
                status: Status::Solved,
                iterations: 0,
                residual: 0.0,
            };
            return Ok((s, info));
        }

        // Columns M⁻¹ w_T of the frictional contacts and M⁻¹ (w_N − μ w_T) of all.
        for (k, &a) in ws.frictional.iter().enumerate() {
            let x = &mut ws.x_t[k * f..][..f];
            ws.chol.solve_into::<N>(&ws.w_t[a * f..][..f], x);
            ws.joints.constrain(x, false);
        }
        let mut k = 0;
        for a in 0..na {
            let y = &mut ws.y_n[a * f..][..f];
            ws.chol.solve_into::<N>(&ws.w_n[a * f..][..f], y);
            ws.joints.constrain(y, false);
            if k < nf && ws.frictional[k] == a {
                let mu = ws.mu_f[k];
                for (yj, xj) in y.iter_mut().zip(&ws.x_t[k * f..][..f]) {
                    *yj -= mu * xj;
                }
                k += 1;
            }
        }

        // A of eq. 7.41, column-major, rows (N; R; L), columns (P_N; P_R; ξ_L).
        let A = &mut ws.a[..s * s];
        A.fill(0.0);
        for c in 0..na {
            let y = &ws.y_n[c * f..][..f];
            for r in 0..na {
                A[r + c * s] = dot(&ws.w_n[r * f..][..f], y);
            }
            for (k, &r) in ws.frictional.iter().enumerate() {
                A[na + k + c * s] = dot(&ws.w_t[r * f..][..f], y);
            }
        }
        for (l, &c) in ws.frictional.iter().enumerate() {
            let x = &ws.x_t[l * f..][..f];
            let col = na + l;
            for r in 0..na {
                A[r + col * s] = dot(&ws.w_n[r * f..][..f], x);
            }
            for (k, &r) in ws.frictional.iter().enumerate() {
                A[na + k + col * s] = dot(&ws.w_t[r * f..][..f], x);
            }
            A[na + nf + l + col * s] = -1.0;
            A[na + l + (na + nf + l) * s] = 1.0;
            A[na + nf + l + c * s] = 2.0 * ws.mu_f[l];
        }

        ws.last_size = s;
        let one_contact = na == 1 && nf == 1 && matches!(options.solver, SolverChoice::Auto);
        let solved = if one_contact
            && let Some(info) = one_contact_closed_form(
                &ws.a[..s * s],
                &ws.b[..s],
                laws[ws.active[0]].mu(),
                ws.prev[ws.active[0]],
                &mut ws.solution,
            ) {
            info
        } else if let Some(route) = match options.solver {
            // The LCP of eq. 7.41 has zeros on the diagonal of its ξ_L block, where projected
            // Gauss-Seidel cannot pivot; it is run on the equivalent contact problem instead.
            SolverChoice::Pgs { .. } if nf > 0 => Some(Fc2dRoute::GaussSeidel),
            SolverChoice::Auto if na > FC2D_ROUTE_CONTACTS => Some(Fc2dRoute::Auto),
            _ => None,
        } {
            let info = frictional_contact(ws, laws, route)?;
            if info.status != Status::Solved {
                return Err(LcpFailure::Status(info.status));
            }
            info
        } else {
            let lcp = LcpRef::from_column_major(s, &ws.a[..s * s], &ws.b[..s])
                .map_err(LcpFailure::Input)?;
            // The previous step's (P_N, P_R, ξ_L) of each contact: PGS starts from them and
            // Auto first tries the complementary basis they name.
            let warm = if matches!(options.solver, SolverChoice::Pgs { .. } | SolverChoice::Auto) {
                for (a, &i) in ws.active.iter().enumerate() {
                    ws.warm[a] = ws.prev[i][0];
                }
                for (k, &a) in ws.frictional.iter().enumerate() {
                    let [_, p_r, xi_l] = ws.prev[ws.active[a]];
                    ws.warm[na + k] = p_r;
                    ws.warm[na + nf + k] = xi_l;
                }
                Some(&ws.warm[..s])
            } else {
                None
            };
            solver.solve(lcp, warm, &mut ws.solution).map_err(LcpFailure::Solver)?;
            if ws.solution.status == Status::Solved {
                LcpInfo {
                    method: ws.solution.method,
                    status: ws.solution.status,
                    iterations: ws.solution.iterations,
                    residual: ws.solution.residual.relative,
                }
            } else if matches!(options.solver, SolverChoice::Auto)
                && ws.solution.status != Status::NoSolution
            {
                // Pivoting on eq. 7.41 fails where the bodies' masses differ by orders of
                // magnitude (a stack of boxes of densities 1 and 10⁻⁶: every covering ends in
                // a ray or a basis that round-off spoils); the solvers of the equivalent
                // contact problem, which does not mix P_N with P_R, solve it. An LCP that
                // enumeration proved to have no solution is not tried again, and a failure
                // reports the LCP's status.
                let status = ws.solution.status;
                let info = frictional_contact(ws, laws, Fc2dRoute::Auto)?;
                if info.status != Status::Solved {
                    return Err(LcpFailure::Status(status));
                }
                info
            } else {
                return Err(LcpFailure::Status(ws.solution.status));
            }
        };

        // u_E = ũ + M⁻¹(w_N − μ w_T) P_N + M⁻¹ w_T P_R (eq. 7.36).
        let z = &ws.solution.z;
        ws.tmp.copy_from_slice(&ws.u_free);
        for a in 0..na {
            let p_n = z[a].max(0.0);
            ws.prev[ws.active[a]] = [p_n, 0.0, 0.0];
            if p_n != 0.0 {
                for (u, y) in ws.tmp.iter_mut().zip(&ws.y_n[a * f..][..f]) {
                    *u += y * p_n;
                }
            }
        }
        for (k, &a) in ws.frictional.iter().enumerate() {
            let p_r = z[na + k].max(0.0);
            let i = ws.active[a];
            ws.prev[i][1] = p_r;
            ws.prev[i][2] = z[na + nf + k].max(0.0);
            if p_r != 0.0 {
                for (u, x) in ws.tmp.iter_mut().zip(&ws.x_t[k * f..][..f]) {
                    *u += x * p_r;
                }
            }
        }
        Ok((s, solved))
    }

    /// [`Self::contact_step`] for one active frictionless contact i with the default solver,
    /// without the general assembly: the LCP is the scalar A P_N + b ≥ 0, P_N ≥ 0 with
    /// A = w_Nᵀ M⁻¹ w_N and b = w_Nᵀ ũ + ŵ_N + ε_N γ_NA, so P_N = 0 when b ≥ 0 and
    /// P_N = −b/A otherwise; u_E = ũ + M⁻¹ w_N P_N. `None` (nothing written that the general
    /// path needs) when A is not positive or −b/A is not finite.
    #[inline(always)]
    pub(super) fn one_frictionless_contact<K: Mechanism, const N: usize>(
        mech: &K,
        ws: &mut Workspace,
        u_a: &[f64],
        t_m: f64,
        i: usize,
    ) -> Result<Option<(usize, LcpInfo)>, LcpFailure> {
        let f = order::<N>(u_a.len());
        let u_a = &u_a[..f];
        let (w_n, w_t) = (&mut ws.w_n[..f], &mut ws.w_t[..f]);
        mark_unwritten(w_n, w_t);
        // A mechanism that shares work keeps the contact's geometry from the gaps.
        let point = match mech.shared_work() {
            Some(shared) => {
                let mut point = [ContactPoint::default()];
                shared.midpoint_contacts(&[i], &ws.q_m, t_m, &ws.memo, w_n, w_t, &mut point);
                point[0]
            }
            None => mech.contact(i, &ws.q_m, t_m, w_n, w_t),
        };
        check_directions(i, w_n, w_t)?;
        if !(point.w_n_hat.is_finite() && point.w_t_hat.is_finite()) {
            check_rheonomic(&[i], std::slice::from_ref(&point))?;
        }
        ws.w_n_hat[0] = point.w_n_hat;
        ws.w_t_hat[0] = point.w_t_hat;
        let gamma_na = dot(w_n, u_a) + point.w_n_hat;
        ws.gamma_na[0] = gamma_na;
        ws.gamma_ta[0] = dot(w_t, u_a) + point.w_t_hat;
        let u_free = &ws.u_free[..f];
        let b = dot(w_n, u_free) + point.w_n_hat + mech.laws()[i].eps_n() * gamma_na;
        ws.b[0] = b;
        let u_e = &mut ws.tmp[..f];
        if b >= 0.0 {
            u_e.copy_from_slice(u_free);
            ws.prev[i] = [0.0; 3];
            let info = LcpInfo {
                method: Method::Trivial,
                status: Status::Solved,
                iterations: 0,
                residual: 0.0,
            };
            return Ok(Some((1, info)));
        }
        let y = &mut ws.y_n[..f];
        ws.chol.solve_into::<N>(w_n, y);
        ws.joints.constrain(y, false);
        let a = dot(w_n, y);
        let p_n = -b / a;
        if !(a > 0.0 && p_n.is_finite()) {
            return Ok(None);
        }
        ws.a[0] = a;
        ws.last_size = 1;
        for ((u_e, u), y) in u_e.iter_mut().zip(u_free).zip(y.iter()) {
            *u_e = u + y * p_n;
        }
        ws.prev[i] = [p_n, 0.0, 0.0];
        let info = LcpInfo {
            method: Method::ClosedForm,
            status: Status::Solved,
            iterations: 0,
            residual: closed_form_residual(a, b, p_n),
        };
        Ok(Some((1, info)))
    }

    /// Turns a failure of the contact step into the public error, with the LCP instance. A
    /// non-finite number, found in what was evaluated at the midpoint, is reported at t_M
    /// (`t_m`), as M, h and g_N are; the other errors name the step by its start t_A.
    pub(super) fn lcp_error(&self, failure: LcpFailure, t_m: f64) -> StepError {
        let t = self.t;
        match failure {
            LcpFailure::NonFinite { what, index } => StepError::NonFinite { what, index, t: t_m },
            LcpFailure::Unwritten { what, contact, entry } => {
                StepError::Unwritten { what, contact, entry, t: t_m }
            }
            // Finite M, h and W give a finite LCP unless the state has grown past the range
            // of f64 in between: report that as the state it is.
            LcpFailure::Input(moreau_lcp::LcpError::NonFinite { .. }) => StepError::NonFinite {
                what: "LCP (A, b): the state has diverged",
                index: 0,
                t: t_m,
            },
            LcpFailure::Input(source @ moreau_lcp::LcpError::OutOfRange { value, .. }) => {
                StepError::ProblemOutOfRange { step: self.step, t, value, source }
            }
            LcpFailure::Input(e) | LcpFailure::Solver(e) => StepError::Lcp(e),
            LcpFailure::Status(status) => {
                let na = self.ws.active.len();
                let s = na + 2 * self.ws.frictional.len();
                let lcp =
                    Lcp::from_column_major(s, &self.ws.a[..s * s], &self.ws.b[..s]).map(Box::new);
                match lcp {
                    Ok(lcp) => StepError::LcpFailed {
                        step: self.step,
                        t,
                        q: self.q.clone(),
                        u: self.u.clone(),
                        status,
                        lcp,
                    },
                    Err(e) => StepError::Lcp(e),
                }
            }
        }
    }
}

/// Whether the solution of a projection's LCP (A z + g_N = w, 0 ≤ z ⊥ w ≥ 0, w the gaps after
/// the correction to first order, in m) that its solver does not call solved still puts the
/// contacts within `tolerance` of their surfaces: z finite and non-negative, every w at least
/// −`tolerance`, and the w of each contact it pushes (z > 0) at most `tolerance`. The
/// projection needs the positions to its tolerance, not the LCP to the solvers' relative
/// residual: with joints, A = W_Nᵀ Ĝ⁻¹ W_N is singular, and Lemke can end at a natural residual
/// of 1e-13 m whose relative residual of 1e-7 it reports as a numerical failure.
fn projects_within(solution: &Solution, tolerance: f64) -> bool {
    solution.z.iter().zip(&solution.w).all(|(&z, &w)| {
        z.is_finite() && z >= 0.0 && w >= -tolerance && (z == 0.0 || w <= tolerance)
    })
}
