//! The step of a mechanism with a [`BodyStructure`]: the same midpoint rule and impact law
//! as the path of fixed contacts (docs/theory.md sections 4-6), with M kept as one 3 × 3
//! block per body, the contacts detected at the midpoint, and their problem solved island by
//! island on sparse 2 × 2 blocks (section 10), the joints' rows in it as bilateral groups.
//!
//! The joints are not eliminated by a Schur complement as on the path of fixed contacts
//! (joints.rs), whose S = W_Bᵀ M⁻¹ W_B and rows of length f cost O(f n_B) per step and
//! couple every body: their rows stay in each island's problem, whose solution keeps
//! W_Bᵀ u_E + b_B = 0 exactly as the elimination does, and their drift is corrected by the same
//! sparse projection as the contacts' penetration.
#![allow(non_snake_case)]

use std::time::Instant;

use rayon::prelude::*;

use super::islands::{
    CHUNK_LINKS, ContactWork, IslandFailure, Islands, JointGroup, Purpose, fill, for_chunks,
    group_rows, in_parallel, link,
};
use super::joints::{PROJECTION_ITERATIONS, check_apart, check_correction, drift_tolerance};
use super::*;
use crate::bodies::{BodyBilateral, BodyContact, BodyStructure, NO_BODY};
use crate::report::{MassView, PhaseTimes};

/// Most passes of the contact projection of detected contacts (each a detection at q_E and a
/// frictionless problem over what it finds).
const CONTACT_PROJECTION_PASSES: usize = 4;

/// The state and buffers of the many-body path, sized by the bodies and by the most
/// contacts detected at once; nothing is allocated per step once they are large enough.
pub(super) struct BodyPath {
    /// Number of bodies; f = 3 × this.
    nb: usize,
    /// M_k at the midpoint and its inverse, one 3 × 3 block per body, column-major.
    mass: Vec<[f64; 9]>,
    inv: Vec<[f64; 9]>,
    /// m_k M_k⁻¹, the inverse of M_k / m_k in which every body weighs alike: the contact
    /// projection's metric (m_k the first entry of M_k, the body's mass).
    alike: Vec<[f64; 9]>,
    /// Whether `inv` holds the inverse of a constant M.
    factored: bool,
    q_m: Vec<f64>,
    /// h at the midpoint.
    h: Vec<f64>,
    /// ũ = u_A + Δt M⁻¹ h.
    u_free: Vec<f64>,
    u_e: Vec<f64>,
    q_e: Vec<f64>,
    /// q_E as the midpoint rule gave it, before the position projection moved it, and
    /// whether the last step's projection moved it.
    q_unprojected: Vec<f64>,
    projected: bool,
    /// The contacts detected at the midpoint (then at q_E, by the projection), in id order.
    detected: Vec<BodyContact>,
    /// The bilateral rows at the midpoint (then at q_E), and their groups.
    rows: Vec<BodyBilateral>,
    groups: Vec<JointGroup>,
    /// The violation γ_B,A(u_A) = w_Bᵀ u_A + ŵ_B of each row at the step's start (joints.rs).
    gamma_start: Vec<f64>,
    /// The joints' impulses Λ_B of the last step, in the mechanism's row order.
    joint_impulses: Vec<f64>,
    /// The groups at q_E during the projection, of which only g_B is used.
    end_groups: Vec<JointGroup>,
    /// Whether each body has a joint row.
    jointed: Vec<bool>,
    /// The work of the contacts, then of the joint groups.
    work: Vec<ContactWork>,
    /// The step's contacts' identities and reports.
    ids: Vec<u64>,
    reports: Vec<ContactReport>,
    /// The step's impulses (P_N, P_T) by identity, in increasing order: the next step's
    /// warm start, and what tells an impact from persistent contact.
    prev: Vec<(u64, [f64; 2])>,
    /// The joints' impulses of the step in row order, the next step's warm start.
    joint_prev: Vec<f64>,
    pub(super) islands: Islands,
    info: Option<LcpInfo>,
    lcp_size: usize,
    penetration: f64,
    /// The largest |g_B| at the midpoint.
    joint_drift: f64,
    /// The number of islands of the step's problem (the projection splits its own).
    islands_solved: usize,
    times: PhaseTimes,
}

/// The inverse of a symmetric positive definite 3 × 3 block (column-major) through its
/// Cholesky factor; the error says what fails.
fn spd_inverse3(m: &[f64; 9]) -> Result<[f64; 9], String> {
    let scale = m.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    for (i, j) in [(0, 1), (0, 2), (1, 2)] {
        if (m[i + 3 * j] - m[j + 3 * i]).abs() > 1e-12 * scale {
            return Err(format!("M[{i}][{j}] differs from M[{j}][{i}]"));
        }
    }
    // L, lower triangle.
    let l00 = m[0].sqrt();
    let l10 = m[1] / l00;
    let l20 = m[2] / l00;
    let d1 = m[4] - l10 * l10;
    let l11 = d1.sqrt();
    let l21 = (m[5] - l20 * l10) / l11;
    let d2 = m[8] - l20 * l20 - l21 * l21;
    let l22 = d2.sqrt();
    for (index, d) in [(0, m[0]), (1, d1), (2, d2)] {
        if !(d > 0.0) {
            return Err(format!("non-positive pivot in column {index}"));
        }
    }
    // L⁻¹, lower triangle, then M⁻¹ = L⁻ᵀ L⁻¹.
    let i00 = 1.0 / l00;
    let i11 = 1.0 / l11;
    let i22 = 1.0 / l22;
    let i10 = -l10 * i00 * i11;
    let i21 = -l21 * i11 * i22;
    let i20 = -(l20 * i00 + l21 * i10) * i22;
    let a00 = i00 * i00 + i10 * i10 + i20 * i20;
    let a10 = i11 * i10 + i21 * i20;
    let a20 = i22 * i20;
    let a11 = i11 * i11 + i21 * i21;
    let a21 = i22 * i21;
    let a22 = i22 * i22;
    Ok([a00, a10, a20, a10, a11, a21, a20, a21, a22])
}

#[inline(always)]
fn mul3(m: &[f64; 9], x: &[f64]) -> [f64; 3] {
    [
        m[0] * x[0] + m[3] * x[1] + m[6] * x[2],
        m[1] * x[0] + m[4] * x[1] + m[7] * x[2],
        m[2] * x[0] + m[5] * x[1] + m[8] * x[2],
    ]
}

#[inline(always)]
fn dot3(a: &[f64; 3], b: &[f64]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// w · v over the two sides of a contact (a side without coordinates contributes nothing).
#[inline(always)]
fn side_dot(bodies: [u32; 2], w: &[[f64; 3]; 2], v: &[f64]) -> f64 {
    let mut s = 0.0;
    for side in 0..2 {
        let k = bodies[side];
        if k != NO_BODY {
            s += dot3(&w[side], &v[3 * k as usize..]);
        }
    }
    s
}

/// Checks the detected contacts: finite, on existing bodies, in increasing order of identity;
/// then keeps those with g_N at most `margin` and returns the largest penetration. A large
/// list is checked in chunks on rayon's pool; the error is that of the first bad contact
/// either way.
fn check_contacts(
    contacts: &mut Vec<BodyContact>,
    nb: usize,
    margin: f64,
    t: f64,
) -> Result<f64, StepError> {
    let list = &contacts[..];
    let check = |index: usize| -> Result<(), StepError> {
        let c = &list[index];
        let p = c.point;
        let numbers = [p.g_n, p.g_t, p.w_n_hat, p.w_t_hat];
        if let Some(k) = numbers.iter().position(|v| !v.is_finite()) {
            let what = ["g_N", "g_T", "ŵ_N", "ŵ_T"][k];
            return Err(StepError::NonFinite { what, index, t });
        }
        if c.w_n.iter().chain(&c.w_t).flatten().any(|v| !v.is_finite()) {
            return Err(StepError::NonFinite { what: "w_N/w_T", index, t });
        }
        if let Some(&k) = c.bodies.iter().find(|&&k| k != NO_BODY && k as usize >= nb) {
            return Err(StepError::InvalidContact {
                index,
                id: c.id,
                reason: format!("body {k} of {nb}"),
            });
        }
        if index > 0 && c.id <= list[index - 1].id {
            return Err(StepError::InvalidContact {
                index,
                id: c.id,
                reason: "identities must increase".into(),
            });
        }
        Ok(())
    };
    // The largest penetration of the contacts kept, and whether any is dropped.
    let measure = |(depth, drop): (f64, bool), c: &BodyContact| {
        let g_n = c.point.g_n;
        if g_n <= margin { (depth.max(-g_n), drop) } else { (depth, true) }
    };
    let (depth, drop) = if in_parallel(list.len()) {
        let bad = (0..list.len())
            .into_par_iter()
            .with_min_len(CHUNK_LINKS)
            .find_first(|&i| check(i).is_err());
        if let Some(index) = bad {
            check(index)?;
        }
        list.par_iter()
            .with_min_len(CHUNK_LINKS)
            .fold(|| (0.0f64, false), measure)
            .reduce(|| (0.0, false), |a, b| (a.0.max(b.0), a.1 || b.1))
    } else {
        for index in 0..list.len() {
            check(index)?;
        }
        list.iter().fold((0.0f64, false), measure)
    };
    if drop {
        contacts.retain(|c| c.point.g_n <= margin);
    }
    Ok(depth)
}

/// M⁻¹ w_N and M⁻¹ w_T of each side of each detected contact, then M⁻¹ w_B of each side of
/// each joint group's rows, and the diagonal entry of W of the first row, into `work` (`inv`
/// the bodies' M⁻¹ blocks); in parallel for a large problem.
fn directions(
    work: &mut Vec<ContactWork>,
    inv: &[[f64; 9]],
    detected: &[BodyContact],
    groups: &[JointGroup],
) {
    let of_link = |a: usize| {
        let (bodies, w_0, w_1) = link(detected, groups, a);
        let mut w = ContactWork::default();
        for side in 0..2 {
            let k = bodies[side];
            if k != NO_BODY {
                let m = &inv[k as usize];
                w.mw_n[side] = mul3(m, &w_0[side]);
                w.mw_t[side] = mul3(m, &w_1[side]);
            }
        }
        w.diagonal = w_0.iter().zip(&w.mw_n).map(|(w_r, m_r)| dot3(w_r, m_r)).sum::<f64>();
        w
    };
    work.clear();
    let n = detected.len() + groups.len();
    if in_parallel(n) {
        // Written in place into the reserved capacity: nothing is allocated once warm.
        work.par_extend((0..n).into_par_iter().with_min_len(CHUNK_LINKS).map(of_link));
    } else {
        work.extend((0..n).map(of_link));
    }
}

impl BodyPath {
    /// The path for a mechanism of `nb` bodies and `n_bilaterals` bilateral rows.
    pub(super) fn new(nb: usize, n_bilaterals: usize) -> Self {
        let f = 3 * nb;
        BodyPath {
            nb,
            mass: vec![[0.0; 9]; nb],
            inv: vec![[0.0; 9]; nb],
            alike: vec![[0.0; 9]; nb],
            factored: false,
            q_m: vec![0.0; f],
            h: vec![0.0; f],
            u_free: vec![0.0; f],
            u_e: vec![0.0; f],
            q_e: vec![0.0; f],
            q_unprojected: Vec::new(),
            projected: false,
            detected: Vec::new(),
            rows: vec![BodyBilateral::default(); n_bilaterals],
            groups: Vec::with_capacity(n_bilaterals),
            gamma_start: vec![0.0; n_bilaterals],
            joint_impulses: Vec::with_capacity(n_bilaterals),
            end_groups: Vec::with_capacity(n_bilaterals),
            jointed: vec![false; nb],
            work: Vec::new(),
            ids: Vec::new(),
            reports: Vec::new(),
            prev: Vec::new(),
            joint_prev: Vec::with_capacity(n_bilaterals),
            islands: Islands::default(),
            info: None,
            lcp_size: 0,
            penetration: 0.0,
            joint_drift: 0.0,
            islands_solved: 0,
            times: PhaseTimes::default(),
        }
    }

    /// Forgets the impulses of the last step (the warm start and the closed contacts).
    pub(super) fn forget(&mut self) {
        self.prev.clear();
        self.joint_prev.clear();
    }

    /// Takes `impulses`, checked by the caller, as those of the last step.
    pub(super) fn set_impulses(&mut self, impulses: &crate::Impulses) {
        self.prev.clear();
        self.prev.extend(impulses.contacts.iter().map(|&(id, p_n, p_t)| (id, [p_n, p_t])));
        self.joint_prev.clear();
        self.joint_prev.extend_from_slice(&impulses.joints);
    }

    /// The rows of the contact reports of the last step.
    pub(super) fn report<'a>(&'a self, core: &'a Core) -> StepReport<'a> {
        StepReport {
            step: core.step - 1,
            t: core.t,
            q: &core.q,
            u: &core.u,
            contacts: &self.reports,
            contact_ids: &self.ids,
            lcp_size: self.lcp_size,
            lcp: self.info,
            penetration: self.penetration,
            joint_drift: self.joint_drift,
            q_unprojected: self.projected.then_some(&self.q_unprojected[..]),
            islands: self.islands_solved,
            times: self.times,
            mass: MassView::Blocks(&self.mass),
            u_free: &self.u_free,
            // The step's u_E was swapped into the state: this holds u_A.
            u_start: &self.u_e,
            joint_impulses: &self.joint_impulses,
        }
    }

    /// [`directions`] of the path's contacts and joint groups into its work.
    fn directions(&mut self) {
        directions(&mut self.work, &self.inv, &self.detected, &self.groups);
    }

    /// Evaluates and groups the bilateral rows at (q, t); returns the largest |g_B|.
    fn joints_at(
        &mut self,
        structure: &dyn BodyStructure,
        q: &[f64],
        t: f64,
    ) -> Result<f64, StepError> {
        if self.rows.is_empty() {
            return Ok(0.0);
        }
        structure.bilateral_rows(q, t, &mut self.rows);
        group_rows(&self.rows, t, &mut self.groups)?;
        Ok(self.rows.iter().fold(0.0f64, |d, r| d.max(r.point.g.abs())))
    }

    /// v += M⁻¹ (W_N P_N + W_T P_T + W_B Λ_B) with the impulses of the contacts and the joint
    /// groups of the last solve, body by body from the links of each body in link order (the
    /// sums of a scatter over the links, bit for bit), in chunks of bodies in parallel for a
    /// large problem.
    fn apply_impulses(&self, v: &mut [f64]) {
        let (islands, work) = (&self.islands, &self.work);
        let nc = islands.r.len();
        let (bodies, _) = v.as_chunks_mut::<3>();
        for_chunks(bodies, |first, chunk| {
            for (k, v) in chunk.iter_mut().enumerate() {
                for &(a, side) in islands.links_of(first + k) {
                    let a = a as usize;
                    let r = if a < nc { islands.r[a] } else { islands.r_joints[a - nc] };
                    if r[0] == 0.0 && r[1] == 0.0 {
                        continue;
                    }
                    let (w, side) = (&work[a], side as usize);
                    for j in 0..3 {
                        v[j] += w.mw_n[side][j] * r[0] + w.mw_t[side][j] * r[1];
                    }
                }
            }
        });
    }

    /// A projection's correction q_E += G⁻¹ W λ ([`BodyPath::apply_impulses`]), which first
    /// keeps q_E as the scheme gave it in `q_unprojected` when it is the step's first.
    fn correct(&mut self, q: &mut [f64]) {
        if !self.projected {
            self.q_unprojected.clear();
            self.q_unprojected.extend_from_slice(q);
            self.projected = true;
        }
        self.apply_impulses(q);
    }
}

impl Core {
    /// One step of a mechanism with a [`BodyStructure`] (docs/theory.md section 10).
    pub(super) fn advance_bodies<K: Mechanism>(&mut self, mech: &K) -> Result<(), StepError> {
        let structure = mech
            .body_structure()
            .expect("a stepper on the many-body path holds a mechanism with a body structure");
        let mut body = self.body.take().expect("the many-body path has its state");
        let result = self.step_bodies(mech, structure, &mut body);
        self.body = Some(body);
        result
    }

    fn step_bodies<K: Mechanism>(
        &mut self,
        mech: &K,
        structure: &dyn BodyStructure,
        b: &mut BodyPath,
    ) -> Result<(), StepError> {
        let start = Instant::now();
        let dt = self.options.dt;
        let half = 0.5 * dt;
        let t_m = self.t + half;
        let nb = b.nb;
        for ((q_m, q), u) in b.q_m.iter_mut().zip(&self.q).zip(&self.u) {
            *q_m = q + half * u;
        }
        if !(b.factored && mech.constant_mass_matrix()) {
            structure.mass_blocks(&b.q_m, t_m, &mut b.mass);
            let blocks = b.mass.iter().zip(b.inv.iter_mut().zip(b.alike.iter_mut()));
            for (k, (m, (inv, alike))) in blocks.enumerate() {
                if let Some(index) = m.iter().position(|v| !v.is_finite()) {
                    return Err(StepError::NonFinite { what: "M", index: 9 * k + index, t: t_m });
                }
                *inv = spd_inverse3(m).map_err(|reason| StepError::MassNotSpd {
                    t: t_m,
                    reason: format!("the block of body {k}: {reason}"),
                })?;
                *alike = inv.map(|v| v * m[0]);
            }
            b.factored = true;
        }
        b.h.fill(0.0);
        mech.forces(&b.q_m, &self.u, t_m, &mut b.h);
        check_finite("h", &b.h, t_m)?;
        for k in 0..nb {
            let y = mul3(&b.inv[k], &b.h[3 * k..]);
            for j in 0..3 {
                b.u_free[3 * k + j] = self.u[3 * k + j] + dt * y[j];
            }
        }

        if !b.rows.is_empty() {
            structure.bilateral_rows(&self.q, self.t, &mut b.rows);
            for (i, (r, gamma)) in b.rows.iter().zip(&mut b.gamma_start).enumerate() {
                *gamma = side_dot(r.bodies, &r.w, &self.u) + r.point.w_hat;
                if !gamma.is_finite() {
                    let what = "bilateral constraint";
                    return Err(StepError::NonFinite { what, index: i, t: self.t });
                }
            }
        }
        let q_m = std::mem::take(&mut b.q_m);
        let drift = b.joints_at(structure, &q_m, t_m);
        b.q_m = q_m;
        b.joint_drift = drift?;
        if !b.rows.is_empty() {
            check_apart(&self.q, self.options.joint_tolerance, b.joint_drift, t_m)?;
        }

        let detect_start = Instant::now();
        b.detected.clear();
        structure.detect(&b.q_m, t_m, self.options.gap_tolerance, &mut b.detected);
        let detect_end = Instant::now();
        b.penetration = check_contacts(&mut b.detected, nb, self.options.gap_tolerance, t_m)?;

        // A large problem's islands are split while the contacts' directions, right-hand sides
        // and warm starts are computed: neither reads what the other writes, so the bits are
        // the same in either order, and the split (sequential) runs beside the rest on a
        // second thread.
        let nc = b.detected.len();
        let BodyPath {
            islands,
            work,
            ids,
            inv,
            detected,
            groups,
            gamma_start,
            prev,
            joint_prev,
            u_free,
            ..
        } = &mut *b;
        let u = &self.u;
        let mut link_work = || {
            directions(work, inv, detected, groups);
            // γ_A, b = wᵀũ + ŵ + ε γ_A (the formulas of the path of fixed contacts), μ, and
            // the warm start from the impulses under the same identity, by a merge walk over
            // the two lists in increasing order of identity (each chunk's walk starts where
            // its first identity would be).
            for_chunks(&mut work[..nc], |start, work| {
                let contacts = &detected[start..start + work.len()];
                let mut j = contacts.first().map_or(0, |c| prev.partition_point(|p| p.0 < c.id));
                for (c, w) in contacts.iter().zip(work) {
                    let law = c.law;
                    let p = c.point;
                    let gamma_n = side_dot(c.bodies, &c.w_n, u) + p.w_n_hat;
                    let gamma_t = side_dot(c.bodies, &c.w_t, u) + p.w_t_hat;
                    w.gamma_a = [gamma_n, gamma_t];
                    w.b = [
                        side_dot(c.bodies, &c.w_n, u_free) + p.w_n_hat + law.eps_n() * gamma_n,
                        side_dot(c.bodies, &c.w_t, u_free) + p.w_t_hat + law.eps_t() * gamma_t,
                    ];
                    w.mu = law.mu();
                    while j < prev.len() && prev[j].0 < c.id {
                        j += 1;
                    }
                    w.warm = if j < prev.len() && prev[j].0 == c.id { prev[j].1 } else { [0.0; 2] };
                }
            });
            ids.clear();
            ids.extend(detected.iter().map(|c| c.id));
            // The joint groups ask γ_B,M(u_E) = −(γ_B,M(u_A) − γ_B,A(u_A)) (joints.rs):
            // q_B = w_Bᵀ ũ + ŵ_B + γ_B,M(u_A) − γ_B,A(u_A), warm-started from the step before
            // (the groups are the same at every step). A group holds consecutive rows.
            let warm_joints = joint_prev.len() == gamma_start.len();
            let mut first = 0;
            for (group, w) in groups.iter().zip(&mut work[nc..]) {
                w.warm = [0.0; 2];
                for row in 0..group.rows {
                    let (dir, w_hat) = (&group.w[row], group.w_hat[row]);
                    let change = side_dot(group.bodies, dir, u) + w_hat - gamma_start[first + row];
                    w.b[row] = side_dot(group.bodies, dir, u_free) + w_hat + change;
                    if warm_joints {
                        w.warm[row] = joint_prev[first + row];
                    }
                }
                first += group.rows;
            }
        };
        let mut split = || islands.split(nb, detected, groups);
        if in_parallel(nc + groups.len()) {
            rayon::join(split, link_work);
        } else {
            split();
            link_work();
        }
        b.islands.assemble(&b.detected, &b.groups, &b.work, &self.options.solver)?;
        b.islands_solved = b.islands.count();
        let assembled = Instant::now();

        let info = match b.islands.solve(Purpose::Step { inexact: self.options.inexact_residual }) {
            Ok(info) => info,
            Err(failure) => return Err(self.island_error(failure)),
        };
        let mut u_e = std::mem::take(&mut b.u_e);
        u_e.copy_from_slice(&b.u_free);
        b.apply_impulses(&mut u_e);
        b.u_e = u_e;
        let mut poison = 0.0;
        for ((q_e, q_m), u) in b.q_e.iter_mut().zip(&b.q_m).zip(&b.u_e) {
            *q_e = q_m + half * u;
            poison += *q_e * 0.0 + *u * 0.0;
        }
        if poison != 0.0 {
            diagnose_non_finite(&b.h, &b.u_e, &b.q_e, t_m)?;
        }
        b.lcp_size = 2 * nc;
        b.info = (nc > 0).then(|| {
            info.unwrap_or(LcpInfo {
                method: Method::Trivial,
                status: Status::Solved,
                iterations: 0,
                residual: 0.0,
            })
        });
        if nc > 0 && info.is_some() {
            self.ws.lcp_solves += 1;
        }

        // The reports, from the end velocities, each contact's closing found by the same merge
        // walk as its warm start (in chunks in parallel for a large problem); then the
        // impulses by identity for the next step.
        fill(&mut b.reports, nc, ContactReport::default());
        let (detected, work, r, prev, u_e) = (&b.detected, &b.work, &b.islands.r, &b.prev, &b.u_e);
        for_chunks(&mut b.reports, |start, reports| {
            let contacts = &detected[start..start + reports.len()];
            let mut j = contacts.first().map_or(0, |c| prev.partition_point(|p| p.0 < c.id));
            for (k, (c, report)) in contacts.iter().zip(reports).enumerate() {
                while j < prev.len() && prev[j].0 < c.id {
                    j += 1;
                }
                let closed_before = j < prev.len() && prev[j].0 == c.id && prev[j].1[0] > 0.0;
                let gamma_n = side_dot(c.bodies, &c.w_n, u_e) + c.point.w_n_hat;
                let gamma_t = side_dot(c.bodies, &c.w_t, u_e) + c.point.w_t_hat;
                let mut scale = 0.0;
                for side in 0..2 {
                    let body = c.bodies[side];
                    if body != NO_BODY {
                        let u = &u_e[3 * body as usize..][..3];
                        scale += (0..3).map(|i| (c.w_t[side][i] * u[i]).abs()).sum::<f64>();
                    }
                }
                *report = active_report(
                    r[start + k],
                    [gamma_n, gamma_t],
                    work[start + k].gamma_a,
                    closed_before,
                    scale,
                );
            }
        });
        b.prev.clear();
        b.prev.extend(b.ids.iter().zip(&b.islands.r).map(|(&id, &r)| (id, r)));
        // The groups hold consecutive rows: their impulses in row order are the mechanism's.
        b.joint_impulses.clear();
        for (group, r) in b.groups.iter().zip(&b.islands.r_joints) {
            b.joint_impulses.extend_from_slice(&r[..group.rows]);
        }
        b.joint_prev.clear();
        b.joint_prev.extend_from_slice(&b.joint_impulses);
        std::mem::swap(&mut self.u, &mut b.u_e);
        std::mem::swap(&mut self.q, &mut b.q_e);
        let solved = Instant::now();

        let t_e = self.t0 + step_count_as_f64(self.step + 1) * dt;
        if self.options.projection {
            // A correction undone leaves q_E as it was: the comparison tells it, in the steps
            // that corrected only.
            b.projected = false;
            let projected = self.project_bodies(structure, b, t_e);
            b.projected = b.projected && self.q != b.q_unprojected;
            projected?;
        }
        let end = Instant::now();
        b.times = PhaseTimes {
            detection: detect_end - detect_start,
            assembly: (detect_start - start) + (assembled - detect_end),
            solution: solved - assembled,
            projection: end - solved,
        };
        self.step += 1;
        self.t = self.t0 + step_count_as_f64(self.step) * dt;
        Ok(())
    }

    /// Moves q_E back onto the joints and the admissible set, island by island, as the path
    /// of fixed contacts does (joints.rs, then its contact projection), each correction a
    /// problem solved by the step's solver as a frictional-contact problem with μ = 0 and
    /// bilateral groups, with the midpoint's blocks of M:
    /// 1. the joints, while g_B(q_E) exceeds [`drift_tolerance`] (at most
    ///    [`PROJECTION_ITERATIONS`] times): W_Bᵀ M⁻¹ W λ + g_B(q_E) = 0 with W = [W_B W_H],
    ///    where the held contacts H, those of the step that carried an impulse and touch a
    ///    body with a joint, keep their gaps (W_Hᵀ M⁻¹ W λ = 0), so that the correction
    ///    neither opens nor closes a resting contact. W_B and W_H are the midpoint's (a
    ///    simplified Newton method, as on the other path). When that problem has no solution
    ///    (held contacts that repeat each other or a joint), the contacts are not held. The
    ///    other contacts of the bodies it moves (a pile under a chain) are not held: a
    ///    hyperstatic pile would make the problem singular; then q_E += M⁻¹ W λ;
    /// 2. the contacts, when one detected at q_E penetrates by more than the projection
    ///    tolerance (at most [`CONTACT_PROJECTION_PASSES`] times): 0 ≤ λ_N ⊥ W_Nᵀ G⁻¹ W λ +
    ///    g_N ≥ 0 with the joints' midpoint rows kept, W_Bᵀ G⁻¹ W λ = 0, and
    ///    q_E += G⁻¹ W λ, in the metric G = M_k / m_k body by body in which every body
    ///    weighs alike, as on the other path. The problem holds the contacts detected at q_E
    ///    only, and a correction can push bodies into others: one that leaves a deeper
    ///    penetration than it found is undone, and the projection ends there, as it does
    ///    after a correction that does not halve the penetration.
    ///
    /// A projection that cannot be computed leaves q_E as it is.
    fn project_bodies(
        &mut self,
        structure: &dyn BodyStructure,
        b: &mut BodyPath,
        t_e: f64,
    ) -> Result<(), StepError> {
        let gap_tolerance = self.options.gap_tolerance;
        let n_joints = b.groups.len();
        if n_joints > 0 {
            b.jointed.fill(false);
            for g in &b.groups {
                for &k in g.bodies.iter().filter(|&&k| k != NO_BODY) {
                    b.jointed[k as usize] = true;
                }
            }
            let jointed = |k: u32| k != NO_BODY && b.jointed[k as usize];
            for (c, r) in b.detected.iter().zip(&b.islands.r) {
                if r[0] > 0.0 && c.bodies.iter().any(|&k| jointed(k)) {
                    b.groups.push(JointGroup {
                        bodies: c.bodies,
                        w: [c.w_n, [[0.0; 3]; 2]],
                        g: [0.0; 2],
                        w_hat: [0.0; 2],
                        rows: 1,
                    });
                }
            }
        }
        if n_joints > 0 {
            let tolerance = drift_tolerance(&self.q, self.options.joint_tolerance);
            b.detected.clear();
            b.directions();
            let mut corrections = 0;
            let mut before = None;
            loop {
                structure.bilateral_rows(&self.q, t_e, &mut b.rows);
                group_rows(&b.rows, t_e, &mut b.end_groups)?;
                let drift = b.rows.iter().fold(0.0f64, |d, r| d.max(r.point.g.abs()));
                if drift <= tolerance {
                    break;
                }
                let before = *before.get_or_insert(drift);
                if corrections == PROJECTION_ITERATIONS {
                    if let Err(e) = check_correction(before, drift, tolerance, t_e) {
                        // The step is refused: its start, which the contacts' part below
                        // has not yet written over, comes back.
                        std::mem::swap(&mut self.q, &mut b.q_e);
                        std::mem::swap(&mut self.u, &mut b.u_e);
                        return Err(e);
                    }
                    break;
                }
                for ((w, group), end) in b.work.iter_mut().zip(&b.groups).zip(&b.end_groups) {
                    w.b = [end.g[0], if group.rows == 2 { end.g[1] } else { 0.0 }];
                }
                for w in &mut b.work[n_joints..] {
                    w.b = [0.0; 2];
                }
                b.islands.split(b.nb, &b.detected, &b.groups);
                b.islands.assemble(&b.detected, &b.groups, &b.work, &self.options.solver)?;
                if b.islands.solve(Purpose::JointCorrection).is_err() {
                    if b.groups.len() > n_joints {
                        b.groups.truncate(n_joints);
                        b.directions();
                        continue;
                    }
                    break;
                }
                b.correct(&mut self.q);
                corrections += 1;
            }
            b.groups.truncate(n_joints);
        }
        // The deepest penetration before the last correction, whose positions `b.q_e` keeps
        // (q_A's buffer, free until the next step). On a dense packing each pass pushes
        // bodies into contacts it did not pose: a correction that leaves a deeper penetration
        // than it found is undone, and one that does not halve it is the last. Keeping every
        // pass, a column of 1,000 disks reached 4.8e-2 m within 1 s against 2.8e-3 m without
        // the projection; now 2.9e-3 m.
        let tolerance = self.options.projection_tolerance;
        let mut before = f64::INFINITY;
        for pass in 0..=CONTACT_PROJECTION_PASSES {
            b.detected.clear();
            structure.detect(&self.q, t_e, gap_tolerance, &mut b.detected);
            let depth = check_contacts(&mut b.detected, b.nb, gap_tolerance, t_e)?;
            if depth <= tolerance {
                break;
            }
            if depth >= before {
                std::mem::swap(&mut self.q, &mut b.q_e);
                break;
            }
            if pass == CONTACT_PROJECTION_PASSES || depth > 0.5 * before {
                break;
            }
            b.q_e.copy_from_slice(&self.q);
            before = depth;
            for c in &mut b.detected {
                c.w_t = [[0.0; 3]; 2];
            }
            directions(&mut b.work, &b.alike, &b.detected, &b.groups);
            let nc = b.detected.len();
            for (c, w) in b.detected.iter().zip(b.work.iter_mut()) {
                w.b = [c.point.g_n, 0.0];
                w.mu = 0.0;
            }
            for w in &mut b.work[nc..] {
                w.b = [0.0; 2];
            }
            b.islands.split(b.nb, &b.detected, &b.groups);
            b.islands.assemble(&b.detected, &b.groups, &b.work, &self.options.solver)?;
            if b.islands.solve(Purpose::ContactProjection).is_err() {
                break;
            }
            b.correct(&mut self.q);
        }
        check_finite("q", &self.q, t_e)
    }

    /// The public error of a failed island solve.
    fn island_error(&self, failure: IslandFailure) -> StepError {
        let t = self.t;
        match failure {
            IslandFailure::Input(moreau_lcp::LcpError::NonFinite { .. }) => StepError::NonFinite {
                what: "contact problem: the state has diverged",
                index: 0,
                t,
            },
            IslandFailure::Input(source @ moreau_lcp::LcpError::OutOfRange { value, .. }) => {
                StepError::ProblemOutOfRange { step: self.step, t, value, source }
            }
            IslandFailure::Input(e) => StepError::Lcp(e),
            IslandFailure::Status(status, problem) => StepError::IslandFailed {
                step: self.step,
                t,
                q: self.q.clone(),
                u: self.u.clone(),
                status,
                problem,
            },
        }
    }
}
