//! Joints: the bilateral rows g_B(q, t) = 0 of the ideal joints, and the unilateral contacts of
//! the clearance joints, each with its force directions w = (∂g/∂q)ᵀ and rheonomic term
//! ŵ = ∂g/∂t written analytically.
//!
//! A row that constrains a world direction e between the body points P_a and P_b,
//! g = e · (P_b − P_a), has w = (e, (P_b − p_b) × e) in body b's coordinates and
//! −(e, (P_a − p_a) × e) in body a's, and ŵ = e · (v_b(P_b) − v_a(P_a)) with the driven
//! bodies' velocities ([`Frame::add_row`]). When e turns with a body (the normal of a
//! prismatic joint's axis), the derivative of e adds e^⊥ · (P_b − P_a) to that body's θ entry.

use moreau_kinematics::ContactPoint;
use moreau_stepper::BilateralPoint;

use super::body::{Frame, add, dot, perp, scale, sub};

/// A built joint between bodies `a` and `b` (indices into the body list).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Joint {
    pub name: String,
    pub a: usize,
    pub b: usize,
    pub kind: JointKind,
}

/// The geometry of a built joint; vectors in the bodies' frames, directions made unit.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum JointKind {
    Revolute {
        ra: [f64; 2],
        rb: [f64; 2],
    },
    Prismatic {
        ra: [f64; 2],
        rb: [f64; 2],
        normal_a: [f64; 2],
        angle: f64,
    },
    Weld {
        ra: [f64; 2],
        rb: [f64; 2],
        angle: f64,
    },
    PointOnLine {
        ra: [f64; 2],
        rb: [f64; 2],
        normal_b: [f64; 2],
    },
    Motor {
        omega: f64,
        angle: f64,
    },
    RevoluteClearance {
        ra: [f64; 2],
        rb: [f64; 2],
        pin_radius: f64,
        bearing_radius: f64,
    },
    TranslationalClearance {
        ra: [f64; 2],
        axis_a: [f64; 2],
        half_length: f64,
        half_width: f64,
        rb: [f64; 2],
        axis_b: [f64; 2],
        half_guide: f64,
    },
}

/// One contact point between body a's surface and body b's at (q, t).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SlotGeometry {
    /// The point on body a's surface (m, world frame).
    pub point_a: [f64; 2],
    /// The point on body b's surface (m, world frame).
    pub point_b: [f64; 2],
    /// The unit normal n from a towards b.
    pub normal: [f64; 2],
    /// The gap (P_b − P_a) · n (m): > 0 open, < 0 penetration.
    pub gap: f64,
}

impl SlotGeometry {
    /// The force directions of the contact: w_N with the normal n and w_T with the tangent
    /// t = n^⊥ = (−n_y, n_x), each the direction's part on body b at `point_b` minus its part
    /// on body a at `point_a`, and ŵ_N, ŵ_T from the driven bodies' velocities. `w_n` and `w_t`
    /// must be zero on entry. g_T is reported as 0: only its rate w_Tᵀ u + ŵ_T, the tangential
    /// relative velocity of the two surface points, enters the dynamics.
    #[inline]
    pub(crate) fn rows(
        &self,
        fa: &Frame,
        fb: &Frame,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) -> ContactPoint {
        let n = self.normal;
        let t = perp(n);
        let w_n_hat =
            fb.add_row(w_n, 1.0, n, self.point_b) + fa.add_row(w_n, -1.0, n, self.point_a);
        let w_t_hat =
            fb.add_row(w_t, 1.0, t, self.point_b) + fa.add_row(w_t, -1.0, t, self.point_a);
        ContactPoint { g_n: self.gap, g_t: 0.0, w_n_hat, w_t_hat }
    }
}

/// The corners of a translational clearance joint's block, as (along, across) signs: upper
/// rear, upper front, lower rear, lower front.
const CORNERS: [(f64, f64); 4] = [(-1.0, 1.0), (1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)];

/// A corner of a translational clearance joint's block in body a's frame: `ra` the block's
/// centre, `axis_a` its unit long axis, and `along`, `across` the corner's signs (±1) along
/// and across that axis.
pub(crate) fn block_corner(
    ra: [f64; 2],
    axis_a: [f64; 2],
    half_length: f64,
    half_width: f64,
    along: f64,
    across: f64,
) -> [f64; 2] {
    add(ra, add(scale(axis_a, along * half_length), scale(perp(axis_a), across * half_width)))
}

/// g = n_L · (P_P − P_L) for a direction n_L that turns with body L (an axis' normal), the
/// line point P_L on body L and the point P_P on body P.
#[allow(clippy::too_many_arguments)]
fn offset_row(
    fl: &Frame,
    rl: [f64; 2],
    normal_l: [f64; 2],
    fp: &Frame,
    rp: [f64; 2],
    w: &mut [f64],
) -> BilateralPoint {
    let n = fl.rotate(normal_l);
    let pl = fl.point(rl);
    let pp = fp.point(rp);
    let d = sub(pp, pl);
    // The turning of n with body L: ∂n/∂θ_L = n^⊥.
    let turn = dot(perp(n), d);
    if let Some(dof) = fl.dof {
        w[dof + 2] += turn;
    }
    let w_hat = fp.add_row(w, 1.0, n, pp) + fl.add_row(w, -1.0, n, pl) + fl.omega * turn;
    BilateralPoint { g: dot(n, d), w_hat }
}

/// g = e · (P_b − P_a) for a fixed world direction e.
fn point_row(
    fa: &Frame,
    ra: [f64; 2],
    fb: &Frame,
    rb: [f64; 2],
    e: [f64; 2],
    w: &mut [f64],
) -> BilateralPoint {
    let (pa, pb) = (fa.point(ra), fb.point(rb));
    let w_hat = fb.add_row(w, 1.0, e, pb) + fa.add_row(w, -1.0, e, pa);
    BilateralPoint { g: dot(e, sub(pb, pa)), w_hat }
}

/// g = θ_b − θ_a − angle.
fn angle_row(fa: &Frame, fb: &Frame, angle: f64, w: &mut [f64]) -> BilateralPoint {
    let w_hat = fb.add_angle(w, 1.0) + fa.add_angle(w, -1.0);
    BilateralPoint { g: fb.theta - fa.theta - angle, w_hat }
}

impl JointKind {
    /// The number of bilateral rows.
    pub fn num_rows(&self) -> usize {
        match self {
            JointKind::Revolute { .. } | JointKind::Prismatic { .. } => 2,
            JointKind::Weld { .. } => 3,
            JointKind::PointOnLine { .. } | JointKind::Motor { .. } => 1,
            JointKind::RevoluteClearance { .. } | JointKind::TranslationalClearance { .. } => 0,
        }
    }

    /// The name of row `k`'s impulse: `Lx`, `Ly` for the world components of a point
    /// constraint (revolute, weld), `Ltheta` for an angle (weld, prismatic, motor), `Ln` for
    /// a distance across a line (prismatic, point on line).
    pub fn row_name(&self, k: usize) -> &'static str {
        match (self, k) {
            (JointKind::Revolute { .. } | JointKind::Weld { .. }, 0) => "Lx",
            (JointKind::Revolute { .. } | JointKind::Weld { .. }, 1) => "Ly",
            (JointKind::Prismatic { .. }, 1) | (JointKind::PointOnLine { .. }, _) => "Ln",
            _ => "Ltheta",
        }
    }

    /// The number of unilateral contacts.
    pub fn num_contacts(&self) -> usize {
        match self {
            JointKind::RevoluteClearance { .. } => 1,
            JointKind::TranslationalClearance { .. } => 4,
            _ => 0,
        }
    }

    /// Bilateral row `k` at the bodies' frames and time t: adds w_B into `w` (zero on entry)
    /// and returns g_B and ŵ_B.
    pub fn row(&self, k: usize, fa: &Frame, fb: &Frame, t: f64, w: &mut [f64]) -> BilateralPoint {
        const AXES: [[f64; 2]; 2] = [[1.0, 0.0], [0.0, 1.0]];
        match *self {
            JointKind::Revolute { ra, rb } => point_row(fa, ra, fb, rb, AXES[k], w),
            JointKind::Weld { ra, rb, angle } => match k {
                0 | 1 => point_row(fa, ra, fb, rb, AXES[k], w),
                _ => angle_row(fa, fb, angle, w),
            },
            JointKind::Prismatic { ra, rb, normal_a, angle } => match k {
                0 => angle_row(fa, fb, angle, w),
                _ => offset_row(fa, ra, normal_a, fb, rb, w),
            },
            JointKind::PointOnLine { ra, rb, normal_b } => offset_row(fb, rb, normal_b, fa, ra, w),
            JointKind::Motor { omega, angle } => {
                let p = angle_row(fa, fb, angle + omega * t, w);
                BilateralPoint { g: p.g, w_hat: p.w_hat - omega }
            }
            JointKind::RevoluteClearance { .. } | JointKind::TranslationalClearance { .. } => {
                BilateralPoint { g: f64::NAN, w_hat: f64::NAN }
            }
        }
    }

    /// Contact `k` of a clearance joint at the bodies' frames (a: pin or block, b: bearing or
    /// guide).
    pub fn contact(&self, k: usize, fa: &Frame, fb: &Frame) -> SlotGeometry {
        match *self {
            JointKind::RevoluteClearance { ra, rb, pin_radius, bearing_radius } => {
                let (pa, pb) = (fa.point(ra), fb.point(rb));
                // The eccentricity e = P_pin − P_bearing; the normal points along it, from the
                // pin's surface to the bearing's.
                let e = sub(pa, pb);
                let d = e[0].hypot(e[1]);
                // A centred pin has no contact direction; any will do, since its gap is the
                // full clearance r_b − r_p, positive unless the joint is ideal.
                let n = if d > 0.0 { scale(e, 1.0 / d) } else { fb.rotate([1.0, 0.0]) };
                SlotGeometry {
                    point_a: add(pa, scale(n, pin_radius)),
                    point_b: add(pb, scale(n, bearing_radius)),
                    normal: n,
                    gap: bearing_radius - pin_radius - d,
                }
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
                let (along, across) = CORNERS[k];
                let corner =
                    fa.point(block_corner(ra, axis_a, half_length, half_width, along, across));
                // The guide line on the corner's side, and the normal from the corner to it.
                let n = scale(fb.rotate(perp(axis_b)), across);
                let line = add(fb.point(rb), scale(n, half_guide));
                let gap = dot(n, sub(line, corner));
                SlotGeometry {
                    point_a: corner,
                    point_b: add(corner, scale(n, gap)),
                    normal: n,
                    gap,
                }
            }
            _ => SlotGeometry { gap: f64::NAN, ..SlotGeometry::default() },
        }
    }
}
