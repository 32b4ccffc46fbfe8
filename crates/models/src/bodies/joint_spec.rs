//! The declared joints ([`JointSpec`]), as plain data that reads and writes TOML.

use serde::{Deserialize, Serialize};

/// One joint between body `body_a` and body `body_b`, by name; the name `ground` stands for
/// the world frame when no body has that name. Anchors and axes are in the bodies' frames (m);
/// axes need not be unit vectors. A joint's reference angle, when omitted, is the bodies'
/// relative angle θ_b − θ_a at t = 0.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum JointSpec {
    /// A pin: the anchors coincide (2 rows, g = P_b − P_a).
    Revolute {
        /// Unique joint name.
        name: String,
        /// First body.
        body_a: String,
        /// Second body.
        body_b: String,
        /// The pin on body a (m).
        anchor_a: [f64; 2],
        /// The pin on body b (m).
        anchor_b: [f64; 2],
    },
    /// A slider: body b keeps its angle relative to a and its anchor on the line through
    /// `anchor_a` along `axis` (on body a): 2 rows, θ_b − θ_a − angle and n_a · (P_b − P_a).
    Prismatic {
        /// Unique joint name.
        name: String,
        /// The body carrying the axis.
        body_a: String,
        /// The sliding body.
        body_b: String,
        /// A point of the axis on body a (m).
        anchor_a: [f64; 2],
        /// The point of body b that stays on the axis (m).
        anchor_b: [f64; 2],
        /// The axis direction on body a.
        axis: [f64; 2],
        /// Reference relative angle θ_b − θ_a (rad).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        angle: Option<f64>,
    },
    /// A rigid connection: the anchors coincide and the relative angle is fixed (3 rows).
    Weld {
        /// Unique joint name.
        name: String,
        /// First body.
        body_a: String,
        /// Second body.
        body_b: String,
        /// The connection point on body a (m).
        anchor_a: [f64; 2],
        /// The connection point on body b (m).
        anchor_b: [f64; 2],
        /// Reference relative angle θ_b − θ_a (rad).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        angle: Option<f64>,
    },
    /// A pin of body a in a slot line of body b (1 row, n_b · (P_a − P_b) = 0).
    PointOnLine {
        /// Unique joint name.
        name: String,
        /// The body carrying the pin.
        body_a: String,
        /// The body carrying the slot.
        body_b: String,
        /// The pin on body a (m).
        anchor_a: [f64; 2],
        /// A point of the slot line on body b (m).
        anchor_b: [f64; 2],
        /// The slot's direction on body b.
        axis: [f64; 2],
    },
    /// A motor: θ_b − θ_a − angle − Ω t = 0 (1 row, ŵ = −Ω).
    Motor {
        /// Unique joint name.
        name: String,
        /// The body the motor is mounted on.
        body_a: String,
        /// The driven body.
        body_b: String,
        /// Prescribed relative angular velocity Ω (rad/s).
        omega: f64,
        /// Relative angle at t = 0 (rad).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        angle: Option<f64>,
    },
    /// A revolute joint with radial clearance: a pin of radius r_p on body a in a bearing of
    /// radius r_b on body b, one unilateral contact with
    /// g_N = (r_b − r_p) − |P_pin − P_bearing| and the normal along the eccentricity.
    ///
    /// A body of reach L turning at ω about the pin pushes it outward by about L (ω Δt)² per
    /// step, and at ε_N = 0 the contact takes that velocity away: an energy loss first order
    /// in Δt whatever the play. A 1 m rod swinging from 1 rad at Δt = 1e-4 s follows the
    /// ideal joint to about 4 c rad for c = 1e-3 and 1e-4 m; below, that loss dominates. At a
    /// play as small as the projection's tolerance (1e-6 of a scene's size) the pin chatters;
    /// set `StepperOptions::projection_tolerance` to about 1e-2 c, use a smaller Δt or
    /// [`JointSpec::Revolute`] (docs/extremes.md, item 10).
    RevoluteClearance {
        /// Unique joint name (and the contact's name).
        name: String,
        /// The body carrying the pin.
        body_a: String,
        /// The body carrying the bearing.
        body_b: String,
        /// The pin's centre on body a (m).
        anchor_a: [f64; 2],
        /// The bearing's centre on body b (m).
        anchor_b: [f64; 2],
        /// Pin radius r_p (m, >= 0).
        pin_radius: f64,
        /// Bearing radius r_b (m, >= r_p).
        bearing_radius: f64,
        /// Normal restitution ε_N.
        eps_n: f64,
        /// Tangential restitution ε_T.
        eps_t: f64,
        /// Friction coefficient μ.
        mu: f64,
    },
    /// A translational joint with clearance: a block (`length` along `axis_a`, `width` across,
    /// centred at `anchor_a` on body a) between two lines parallel to `axis_b` through
    /// `anchor_b` ± `guide_width`/2 across (on body b). Four unilateral contacts: the block's
    /// two upper corners against the upper line, the two lower ones against the lower line
    /// (named `<name>.corner1` .. `<name>.corner4`: upper rear, upper front, lower rear, lower
    /// front).
    TranslationalClearance {
        /// Unique joint name.
        name: String,
        /// The block's body.
        body_a: String,
        /// The guide's body.
        body_b: String,
        /// The block's centre on body a (m).
        anchor_a: [f64; 2],
        /// The block's long axis on body a.
        axis_a: [f64; 2],
        /// Block length along its axis (m, > 0).
        length: f64,
        /// Block width across its axis (m, > 0).
        width: f64,
        /// The guide's mid-line point on body b (m).
        anchor_b: [f64; 2],
        /// The guide's direction on body b.
        axis_b: [f64; 2],
        /// Distance between the guide's lines (m, >= width).
        guide_width: f64,
        /// Normal restitution ε_N.
        eps_n: f64,
        /// Tangential restitution ε_T.
        eps_t: f64,
        /// Friction coefficient μ.
        mu: f64,
    },
}

impl JointSpec {
    /// The joint's name.
    pub fn name(&self) -> &str {
        self.parts().0
    }

    /// The joint's bodies (a, b).
    pub fn bodies(&self) -> (&str, &str) {
        let (_, a, b) = self.parts();
        (a, b)
    }

    fn parts(&self) -> (&str, &str, &str) {
        match self {
            JointSpec::Revolute { name, body_a, body_b, .. }
            | JointSpec::Prismatic { name, body_a, body_b, .. }
            | JointSpec::Weld { name, body_a, body_b, .. }
            | JointSpec::PointOnLine { name, body_a, body_b, .. }
            | JointSpec::Motor { name, body_a, body_b, .. }
            | JointSpec::RevoluteClearance { name, body_a, body_b, .. }
            | JointSpec::TranslationalClearance { name, body_a, body_b, .. } => {
                (name, body_a, body_b)
            }
        }
    }

    /// The anchors (a, b) of every joint but the motor, which has none.
    pub(crate) fn anchors(&self) -> Option<([f64; 2], [f64; 2])> {
        match *self {
            JointSpec::Revolute { anchor_a, anchor_b, .. }
            | JointSpec::Prismatic { anchor_a, anchor_b, .. }
            | JointSpec::Weld { anchor_a, anchor_b, .. }
            | JointSpec::PointOnLine { anchor_a, anchor_b, .. }
            | JointSpec::RevoluteClearance { anchor_a, anchor_b, .. }
            | JointSpec::TranslationalClearance { anchor_a, anchor_b, .. } => {
                Some((anchor_a, anchor_b))
            }
            JointSpec::Motor { .. } => None,
        }
    }

    /// The contact law's parameters (ε_N, ε_T, μ) of a clearance joint.
    pub(crate) fn clearance_law(&self) -> Option<(f64, f64, f64)> {
        match *self {
            JointSpec::RevoluteClearance { eps_n, eps_t, mu, .. }
            | JointSpec::TranslationalClearance { eps_n, eps_t, mu, .. } => {
                Some((eps_n, eps_t, mu))
            }
            _ => None,
        }
    }

    /// The joint's type as written in a scene file (`revolute`, `point_on_line`, ...).
    pub fn type_name(&self) -> &'static str {
        match self {
            JointSpec::Revolute { .. } => "revolute",
            JointSpec::Prismatic { .. } => "prismatic",
            JointSpec::Weld { .. } => "weld",
            JointSpec::PointOnLine { .. } => "point_on_line",
            JointSpec::Motor { .. } => "motor",
            JointSpec::RevoluteClearance { .. } => "revolute_clearance",
            JointSpec::TranslationalClearance { .. } => "translational_clearance",
        }
    }
}
