//! Force networks: a picture of the contacts of one step of a many-body scene, each drawn as
//! a line whose width grows with its normal impulse, over the bodies.
//!
//! A contact between two bodies with coordinates is drawn from one centre of mass to the
//! other; a contact with a fixed or driven body (a floor, a wall) from the moving body's
//! centre of mass to the contact point. The contacts are those the step solved, found again
//! at its midpoint q_M = q_A + Δt/2 u_A ([`moreau_models::bodies::Multibody::locate_contact`]).

use anyhow::{Result, bail};
use moreau_models::bodies::Multibody;
use moreau_models::{AnyModel, Drawing, Role};
use moreau_stepper::ContactReport;

use crate::contacts;
use crate::frames::{Frame, Paint, Shape, bounds, shapes};

/// Width classes of the lines, in pixels: 1 for the weakest contacts to this for the
/// strongest.
const WIDEST: f64 = 6.0;

/// The frame of the force network of the step that starts at (q_A, u_A, t_A) with step `dt`,
/// whose contacts carried the impulses `reports` under the identities `ids`, found again with
/// the active-set `margin` the step used; `caption` under it, its window its own.
///
/// # Errors
/// A scene that does not declare its bodies; a contact with an impulse that is not found again
/// at the midpoint.
#[allow(clippy::too_many_arguments)]
pub fn frame(
    model: &AnyModel,
    (q_a, u_a, t_a): (&[f64], &[f64], f64),
    dt: f64,
    margin: f64,
    ids: &[u64],
    reports: &[ContactReport],
    caption: Vec<String>,
) -> Result<Frame> {
    let AnyModel::Declared(m) = model else {
        bail!("a force network needs a scene of declared bodies");
    };
    let mut q_m = Vec::new();
    let t_m = contacts::midpoint(q_a, u_a, t_a, dt, &mut q_m);
    let centres = centres(m, &q_m, t_m);
    let strongest = reports.iter().map(|c| c.p_n).fold(0.0, f64::max);
    let mut links = Vec::new();
    for (&id, c) in ids.iter().zip(reports).filter(|(_, c)| c.p_n > 0.0) {
        let l = contacts::locate(m, id, (&q_m, t_m), margin, t_a + dt)?;
        let [a, b] = l.bodies.map(|k| centres[k]);
        let (from, to) = match (a, b) {
            (Some(a), Some(b)) => (a, b),
            (None, Some(b)) => (l.geometry.point_a, b),
            (Some(a), None) => (a, l.geometry.point_b),
            (None, None) => continue,
        };
        let width = 1.0 + ((WIDEST - 1.0) * c.p_n / strongest).round();
        let paint = Paint { stroke: (180, 20, 20), width: width as u32, fill: None };
        links.push(Shape::Poly { points: vec![from, to], closed: false, paint });
    }
    // The bodies in light grey under the links; the window is the moving bodies', so that
    // walls drawn to the scene's first extent do not shrink a settled pile.
    let grey = |s: Shape| match s {
        Shape::Poly { points, closed, .. } => Shape::Poly { points, closed, paint: GREY },
        Shape::Circle { center, radius, .. } => Shape::Circle { center, radius, paint: GREY },
    };
    let drawing = model.draw(&q_m, t_m);
    let moving = shapes(&moving_only(drawing.clone()));
    let window = bounds([&Frame { t: t_m, shapes: moving, caption: Vec::new(), window: None }]);
    let mut drawn: Vec<Shape> = shapes(&drawing).into_iter().map(grey).collect();
    drawn.extend(links);
    Ok(Frame { t: t_m, shapes: drawn, caption, window: Some(window) })
}

/// The outline of the bodies under a force network.
const GREY: Paint = Paint { stroke: (170, 170, 170), width: 1, fill: Some((240, 240, 240)) };

/// The centre of mass of every body at (q, t), `None` for a body without coordinates.
fn centres(m: &Multibody, q: &[f64], t: f64) -> Vec<Option<[f64; 2]>> {
    m.body_poses(q, t)
        .iter()
        .enumerate()
        .map(|(k, &[x, y, theta])| {
            let (_, _, com) = m.mass_properties(k)?;
            let (s, c) = theta.sin_cos();
            Some([x + c * com[0] - s * com[1], y + s * com[0] + c * com[1]])
        })
        .collect()
}

/// A drawing without its fixed and driven bodies' elements (role `Ground`).
fn moving_only(mut d: Drawing) -> Drawing {
    d.polylines.retain(|l| l.role != Role::Ground);
    d.circles.retain(|c| c.role != Role::Ground);
    d
}
