//! Assembly of a declaration's initial positions onto its joints: q₀ moved onto the position
//! constraints g_B(q, t₀) = 0 at the start time t₀, and refused when a joint contradicts the declared positions or
//! when driven joints ask for velocities that no motion has.

use moreau_kinematics::ContactKinematics;
use moreau_stepper::Mechanism;
use nalgebra::{DMatrix, DVector};

use super::build::bad;
use super::joints::JointKind;
use super::multibody::Multibody;
use crate::ModelError;
use crate::params::relation;
/// The largest move of a body's origin that assembling the initial positions onto the joints
/// may make, as a fraction of the mechanism's length (the larger of its
/// [size](Multibody::size) and the span of its dynamic bodies' declared origins and joints'
/// anchors), before the declaration is refused as wrong rather than merely inexact.
pub const MAX_ASSEMBLY_MOVE: f64 = 0.1;

/// q₀ moved onto the joints' position constraints g_B(q, t₀) = 0 by Gauss-Newton steps
/// q ← q − W (WᵀW)⁺ g (the smallest change in the Euclidean norm).
pub(crate) fn assemble(mb: &Multibody) -> Result<Vec<f64>, ModelError> {
    let (f, nb) = (mb.num_coordinates(), mb.num_bilaterals());
    let mut q = mb.q0.clone();
    if nb == 0 {
        return Ok(q);
    }
    let scale = 1.0 + q.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut w = DMatrix::zeros(f, nb);
    let mut g = DVector::zeros(nb);
    let mut w_hat = DVector::zeros(nb);
    let mut column = vec![0.0; f];
    for _ in 0..50 {
        for i in 0..nb {
            let p = mb.bilateral(i, &q, mb.t0, &mut column);
            (g[i], w_hat[i]) = (p.g, p.w_hat);
            w.column_mut(i).copy_from_slice(&column);
        }
        let (worst, size) = g
            .iter()
            .enumerate()
            .fold((0, 0.0f64), |(k, m), (i, v)| if v.abs() > m { (i, v.abs()) } else { (k, m) });
        if !size.is_finite() {
            return Err(relation(
                &format!("joints.{}", mb.joints[mb.rows[worst].0].name),
                size,
                "the constraint is not finite at the start time",
            ));
        }
        if size <= 1e-13 * scale {
            let q = checked_moves(mb, q)?;
            consistent_drives(mb, &w, &w_hat)?;
            return Ok(q);
        }
        let normal = w.transpose() * &w;
        let lambda = normal
            .svd(true, true)
            .solve(&g, 1e-12 * scale)
            .map_err(|e| relation("joints", size, e))?;
        let dq = &w * lambda;
        for (qi, d) in q.iter_mut().zip(dq.iter()) {
            *qi -= d;
        }
    }
    let (worst, size) = (0..nb)
        .map(|i| (i, mb.bilateral(i, &q, mb.t0, &mut column).g.abs()))
        .fold((0, 0.0f64), |(k, m), (i, v)| if v > m { (i, v) } else { (k, m) });
    Err(relation(
        &format!("joints.{}", mb.joints[mb.rows[worst].0].name),
        size,
        "the joints cannot all be closed at the start time (incompatible anchors or positions)",
    ))
}

/// The length against which assembly's moves are measured: the larger of the mechanism's
/// [size](Multibody::size) and 0.6 times the diagonal of the box around the dynamic bodies'
/// declared origins and every joint's anchors as declared, so that a pendulum's length counts
/// as well as its bob's.
fn assembly_length(mb: &Multibody) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    let mut grow = |p: [f64; 2]| {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    };
    for k in 0..mb.dynamic.len() {
        grow([mb.q0[3 * k], mb.q0[3 * k + 1]]);
    }
    for j in &mb.joints {
        let (ra, rb) = match j.kind {
            JointKind::Revolute { ra, rb }
            | JointKind::Prismatic { ra, rb, .. }
            | JointKind::Weld { ra, rb, .. }
            | JointKind::PointOnLine { ra, rb, .. }
            | JointKind::RevoluteClearance { ra, rb, .. }
            | JointKind::TranslationalClearance { ra, rb, .. } => (ra, rb),
            JointKind::Motor { .. } => continue,
        };
        grow(mb.bodies[j.a].frame(&mb.q0, mb.t0).point(ra));
        grow(mb.bodies[j.b].frame(&mb.q0, mb.t0).point(rb));
    }
    let span = if lo[0].is_finite() { 0.6 * (hi[0] - lo[0]).hypot(hi[1] - lo[1]) } else { 0.0 };
    mb.size.max(span)
}

/// The assembled q₀, unless it moves a body's origin from its declared position by more than
/// [`MAX_ASSEMBLY_MOVE`] of the mechanism's length (the larger of its
/// [size](Multibody::size) and the span of its dynamic bodies' origins and joints' anchors):
/// a joint then contradicts the declaration (a wrong anchor or position), and the error names
/// the body, the joint of its own whose constraint was furthest from closed as declared, and
/// where the joints put it.
fn checked_moves(mb: &Multibody, q: Vec<f64>) -> Result<Vec<f64>, ModelError> {
    let length = assembly_length(mb);
    let limit = MAX_ASSEMBLY_MOVE * length;
    let moved = |k: usize| (q[3 * k] - mb.q0[3 * k]).hypot(q[3 * k + 1] - mb.q0[3 * k + 1]);
    let Some((k, far)) = (0..mb.dynamic.len())
        .map(|k| (k, moved(k)))
        .filter(|&(_, d)| d > limit)
        .fold(None, |m: Option<(usize, f64)>, (k, d)| match m {
            Some((_, e)) if e >= d => m,
            _ => Some((k, d)),
        })
    else {
        return Ok(q);
    };
    let body = mb.dynamic[k];
    let mut column = vec![0.0; mb.num_coordinates()];
    let joint = (0..mb.num_bilaterals())
        .filter(|&i| {
            let j = &mb.joints[mb.rows[i].0];
            j.a == body || j.b == body
        })
        .map(|i| (mb.rows[i].0, mb.bilateral(i, &mb.q0, mb.t0, &mut column).g.abs()))
        .fold(None, |m: Option<(usize, f64)>, (j, g)| match m {
            Some((_, h)) if h >= g => m,
            _ => Some((j, g)),
        })
        .map_or("(none)", |(j, _)| mb.joints[j].name.as_str());
    let name = &mb.bodies[body].name;
    let [x0, y0] = [mb.q0[3 * k], mb.q0[3 * k + 1]];
    Err(bad(
        format!("bodies.{name}.position"),
        &format!("[{x0}, {y0}]"),
        format!(
            "the joints (`{joint}` the furthest from closed) put the body at [{x}, {y}], {far:.3e} \
             from its declared position: more than {pct} % of the mechanism's length {length:.3e}, \
             so the declaration is wrong, not merely inexact; correct the position or the \
             joint's anchors",
            x = q[3 * k],
            y = q[3 * k + 1],
            pct = 100.0 * MAX_ASSEMBLY_MOVE,
        ),
    ))
}

/// Refuses joints whose velocity constraints W_Bᵀ u + ŵ_B = 0 no velocity u satisfies at
/// the start time t₀: rows that depend on one another (W_B's columns not independent) with rheonomic terms
/// that contradict each other, such as a motor turning a body that a weld holds, or two motors
/// at different speeds on one pair of bodies. Their position constraints then part as soon as
/// t > t₀ and every step would fail. The least-squares velocity leaves a residual on exactly the
/// rows in conflict, and the error names their joints. Without a rheonomic term (no motor, no
/// joint to a driven body) u = 0 satisfies every row and nothing is computed.
fn consistent_drives(
    mb: &Multibody,
    w: &DMatrix<f64>,
    w_hat: &DVector<f64>,
) -> Result<(), ModelError> {
    let drive = w_hat.amax();
    if drive == 0.0 || !drive.is_finite() {
        return Ok(());
    }
    let wt = w.transpose();
    let svd = wt.clone().svd(true, true);
    let sigma = svd.singular_values.max();
    let u = svd.solve(&(-w_hat), 1e-10 * sigma).map_err(|e| relation("joints", drive, e))?;
    let residual = &wt * u + w_hat;
    let tolerance = 1e-8 * drive;
    if residual.amax() <= tolerance {
        return Ok(());
    }
    let mut names: Vec<&str> = Vec::new();
    for (i, r) in residual.iter().enumerate() {
        let name = mb.joints[mb.rows[i].0].name.as_str();
        if r.abs() > tolerance && !names.contains(&name) {
            names.push(name);
        }
    }
    let list = names.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", ");
    Err(relation(
        &format!("joints.{}", names[0]),
        residual.amax(),
        &format!(
            "the joints {list} ask for velocities that no motion has at the start time (their rows \
             depend on one another and their drives differ: a motor on a welded pair, two \
             motors on one pair, a joint to a driven body that another joint holds still); \
             the value is the least-squares residual of their velocity constraints; remove \
             or change one of them"
        ),
    ))
}
