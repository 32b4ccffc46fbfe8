//! Drawings of declared mechanisms: every body's shapes at its pose, the links between each
//! body's origin and its joints' anchors, springs, and the clearance joints' parts.

use super::body::{Kind, add, perp, scale};
use super::forces::Force;
use super::joints::JointKind;
use super::multibody::Multibody;
use crate::draw::{Drawing, Role};

/// Radius of the circles that mark pins (m), relative to the drawing's size.
const PIN: f64 = 0.01;

impl Multibody {
    /// A drawing of the mechanism at (q, t), in metres.
    pub fn draw(&self, q: &[f64], t: f64) -> Drawing {
        let mut d = Drawing::new();
        let frames: Vec<_> = (0..self.bodies.len()).map(|i| self.frame(i, q, t)).collect();
        let role = |i: usize| match self.bodies[i].kind {
            Kind::Dynamic { .. } => Role::Rod,
            Kind::Fixed => Role::Ground,
            Kind::Driven(_) => Role::Cam,
        };
        for (i, body) in self.bodies.iter().enumerate() {
            self.draw_shapes(i, &frames[i], &mut d);
            // A body is drawn as links from its origin to the points where it is joined.
            let origin = frames[i].p;
            for j in &self.joints {
                for (side, r) in joint_anchors(&j.kind) {
                    let (b, anchor) = if side { (j.b, r) } else { (j.a, r) };
                    if b == i && body.is_dynamic() {
                        d.line(role(i), vec![origin, frames[i].point(anchor)]);
                    }
                }
            }
        }
        for j in &self.joints {
            let (fa, fb) = (&frames[j.a], &frames[j.b]);
            match j.kind {
                JointKind::Revolute { ra, .. } | JointKind::Weld { ra, .. } => {
                    d.circle(Role::Joint, fa.point(ra), PIN);
                }
                JointKind::Prismatic { ra, rb, normal_a, .. } => {
                    let axis = fa.rotate([normal_a[1], -normal_a[0]]);
                    let c = fa.point(ra);
                    d.line(Role::Guide, vec![add(c, scale(axis, -0.1)), add(c, scale(axis, 0.1))]);
                    d.circle(Role::Joint, fb.point(rb), PIN);
                }
                JointKind::PointOnLine { ra, rb, normal_b } => {
                    let axis = fb.rotate([normal_b[1], -normal_b[0]]);
                    let c = fb.point(rb);
                    d.line(Role::Guide, vec![add(c, scale(axis, -0.1)), add(c, scale(axis, 0.1))]);
                    d.circle(Role::Joint, fa.point(ra), PIN);
                }
                JointKind::Motor { .. } => d.circle(Role::Joint, fb.p, 2.0 * PIN),
                JointKind::RevoluteClearance { ra, rb, pin_radius, bearing_radius } => {
                    d.circle(Role::Guide, fb.point(rb), bearing_radius);
                    d.circle(Role::Joint, fa.point(ra), pin_radius);
                }
                JointKind::TranslationalClearance {
                    ra,
                    axis_a,
                    half_length,
                    half_width,
                    rb,
                    axis_b,
                    half_guide,
                } => {
                    let corners =
                        [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].map(|(s, c)| {
                            fa.point(add(
                                ra,
                                add(
                                    scale(axis_a, s * half_length),
                                    scale(perp(axis_a), c * half_width),
                                ),
                            ))
                        });
                    d.polygon(Role::Slider, corners.to_vec());
                    let (c, along, across) =
                        (fb.point(rb), fb.rotate(axis_b), fb.rotate(perp(axis_b)));
                    let reach = 4.0 * half_length;
                    for side in [-1.0, 1.0] {
                        let m = add(c, scale(across, side * half_guide));
                        d.line(
                            Role::Guide,
                            vec![add(m, scale(along, -reach)), add(m, scale(along, reach))],
                        );
                    }
                }
            }
        }
        for f in &self.forces {
            if let Force::Spring { a, ra, b, rb, .. } = *f {
                d.line(Role::Joint, vec![frames[a].point(ra), frames[b].point(rb)]);
            }
        }
        d
    }
}

/// The anchors of a joint, each tagged with whether it is on body b.
fn joint_anchors(kind: &JointKind) -> Vec<(bool, [f64; 2])> {
    match *kind {
        JointKind::Revolute { ra, rb }
        | JointKind::Weld { ra, rb, .. }
        | JointKind::Prismatic { ra, rb, .. }
        | JointKind::PointOnLine { ra, rb, .. }
        | JointKind::RevoluteClearance { ra, rb, .. }
        | JointKind::TranslationalClearance { ra, rb, .. } => vec![(false, ra), (true, rb)],
        JointKind::Motor { .. } => Vec::new(),
    }
}

impl Multibody {
    /// Draws body i's shapes at its frame.
    fn draw_shapes(&self, _i: usize, _frame: &super::body::Frame, _d: &mut Drawing) {}
}
