//! Drawings of declared mechanisms: every body's shapes at its pose, the links between each
//! body's origin and its joints' anchors, springs, and the clearance joints' parts.

use super::body::{Kind, add, perp, scale};
use super::forces::Force;
use super::joints::{JointKind, block_corner};
use super::multibody::Multibody;
use crate::draw::{Drawing, Role};

/// Radius of the circles that mark pins, relative to the mechanism's size
/// ([`Multibody::size`]).
const PIN: f64 = 0.01;

/// Half the length of the line drawn along a prismatic or point-on-line joint's axis, relative
/// to the mechanism's size.
const GUIDE: f64 = 0.1;

impl Multibody {
    /// A drawing of the mechanism at (q, t), in the length unit of its declaration; the
    /// marks of pins and joint axes are sized after the mechanism ([`Multibody::size`]).
    pub fn draw(&self, q: &[f64], t: f64) -> Drawing {
        let mut d = Drawing::new();
        let (pin, guide) = (PIN * self.size, GUIDE * self.size);
        let frames: Vec<_> = (0..self.bodies.len()).map(|i| self.frame(i, q, t)).collect();
        let role = |i: usize| match self.bodies[i].kind {
            Kind::Dynamic { .. } => Role::Rod,
            Kind::Fixed(_) => Role::Ground,
            Kind::Driven(_) => Role::Cam,
        };
        // A dynamic body is drawn as links from its origin to the points where it is joined,
        // in the order of the joints: each body's anchors, gathered in one pass over them.
        let mut anchors: Vec<Vec<[f64; 2]>> = vec![Vec::new(); self.bodies.len()];
        for j in &self.joints {
            for (side, anchor) in joint_anchors(&j.kind) {
                let b = if side { j.b } else { j.a };
                if self.bodies[b].is_dynamic() {
                    anchors[b].push(anchor);
                }
            }
        }
        for (i, anchors) in anchors.iter().enumerate() {
            self.draw_shapes(i, &frames[i], &mut d);
            for &anchor in anchors {
                d.line(role(i), vec![frames[i].p, frames[i].point(anchor)]);
            }
        }
        for j in &self.joints {
            let (fa, fb) = (&frames[j.a], &frames[j.b]);
            match j.kind {
                JointKind::Revolute { ra, .. } | JointKind::Weld { ra, .. } => {
                    d.circle(Role::Joint, fa.point(ra), pin);
                }
                JointKind::Prismatic { ra, rb, normal_a, .. } => {
                    let axis = fa.rotate([normal_a[1], -normal_a[0]]);
                    let c = fa.point(ra);
                    d.line(
                        Role::Guide,
                        vec![add(c, scale(axis, -guide)), add(c, scale(axis, guide))],
                    );
                    d.circle(Role::Joint, fb.point(rb), pin);
                }
                JointKind::PointOnLine { ra, rb, normal_b } => {
                    let axis = fb.rotate([normal_b[1], -normal_b[0]]);
                    let c = fb.point(rb);
                    d.line(
                        Role::Guide,
                        vec![add(c, scale(axis, -guide)), add(c, scale(axis, guide))],
                    );
                    d.circle(Role::Joint, fa.point(ra), pin);
                }
                JointKind::Motor { .. } => d.circle(Role::Joint, fb.p, 2.0 * pin),
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
                    // Counter-clockwise, for the polygon's outline.
                    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].map(
                        |(along, across)| {
                            fa.point(block_corner(
                                ra,
                                axis_a,
                                half_length,
                                half_width,
                                along,
                                across,
                            ))
                        },
                    );
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
    /// Draws body i's shapes at its frame; a half-plane as its boundary across the region the
    /// finite shapes and the joints occupy at t = 0.
    fn draw_shapes(&self, i: usize, frame: &super::body::Frame, d: &mut Drawing) {
        use moreau_kinematics::Shape;
        let role = match self.bodies[i].kind {
            Kind::Dynamic { .. } => Role::Slider,
            Kind::Fixed(_) => Role::Ground,
            Kind::Driven(_) => Role::Cam,
        };
        let points = |v: &[[f64; 2]]| v.iter().map(|p| frame.point(*p)).collect::<Vec<_>>();
        for shape in &self.bodies[i].shapes {
            match shape {
                Shape::Disk { center, radius } => {
                    let c = frame.point(*center);
                    let ball = if role == Role::Slider { Role::Ball } else { role };
                    d.circle(ball, c, *radius);
                    // A radius shows the disk's rotation.
                    d.line(role, vec![c, frame.point(add(*center, [*radius, 0.0]))]);
                }
                Shape::Polygon { vertices } => d.polygon(role, points(vertices)),
                Shape::Profile { points: p } => d.polygon(role, points(p)),
                Shape::Polyline { points: p } => d.line(role, points(p)),
                Shape::Capsule { a, b, radius } => {
                    let axis = [b[0] - a[0], b[1] - a[1]];
                    let length = axis[0].hypot(axis[1]);
                    let angle = axis[1].atan2(axis[0]);
                    let mut outline = Vec::with_capacity(34);
                    for (end, start) in [
                        (*b, angle - std::f64::consts::FRAC_PI_2),
                        (*a, angle + std::f64::consts::FRAC_PI_2),
                    ] {
                        for k in 0..=16 {
                            let phi = start + std::f64::consts::PI * k as f64 / 16.0;
                            outline.push(
                                frame.point(add(end, scale([phi.cos(), phi.sin()], *radius))),
                            );
                        }
                    }
                    if *radius == 0.0 || length == 0.0 {
                        d.line(role, points(&[*a, *b]));
                    } else {
                        d.polygon(role, outline);
                    }
                }
                Shape::HalfPlane { point, normal } => {
                    let n = frame.rotate(*normal);
                    let along = scale(perp(n), 1.0 / n[0].hypot(n[1]));
                    let p = frame.point(*point);
                    // The boundary through the point nearest the scene's centre.
                    let (c, reach) = self.extent;
                    let s = (c[0] - p[0]) * along[0] + (c[1] - p[1]) * along[1];
                    let m = add(p, scale(along, s));
                    d.line(
                        Role::Ground,
                        vec![add(m, scale(along, -reach)), add(m, scale(along, reach))],
                    );
                }
            }
        }
    }
}
