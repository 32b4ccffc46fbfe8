//! Shapes of planar rigid bodies and the detection of their contacts.
//!
//! A body carries [`Shape`]s given in its own frame; a [`Pose`] places that frame in the world.
//! [`collide`] returns, for two shapes closing within a margin, the points of their contact
//! ([`ManifoldPoint`]): a world point on each surface, the unit normal n from A towards B and
//! the gap g_N = (p_B − p_A) · n. [`BroadPhase`] finds the pairs of bodies whose bounding boxes
//! ([`Aabb`]) come within the margin, so that [`collide`] runs only on those.
//!
//! # What the points guarantee
//! Each point is a pair of closest points, or a vertex of one shape against the line of an edge
//! of the other with that edge's normal. Either way the normal gap's rate is the normal
//! component of the relative velocity of the two material points,
//!
//! ```text
//! d g_N / dt = n · (v_B + ω_B × r_B − v_A − ω_A × r_A),   r_A = p_A − o_A,  r_B = p_B − o_B,
//! ```
//!
//! to first order, so that a time-stepper may build the force direction w_N of each point from
//! n, r_A and r_B alone. Each point carries a `feature` id that names the features in contact
//! (a vertex of one shape on an edge of the other, say) and stays the same while that contact
//! persists; it is smaller than [`max_points`] of the pair, so that a scene may give each
//! (pair, feature) a fixed slot and warm-start its impulses.
//!
//! # Pairs
//! | A \ B | disk | polygon | capsule | half-plane | polyline | profile |
//! |---|---|---|---|---|---|---|
//! | disk | 1 | 1 | 1 | 1 | per segment and vertex | per segment and vertex |
//! | polygon | | 2 (face on face), 1 (corner) | 2, 1 | per vertex | per vertex and segment | per vertex and segment |
//! | capsule | | | 2, 1 | per end | per end and segment | per end and segment |
//! | half-plane | | | | — | per local minimum and chord end | per local minimum and chord end |
//! | polyline | | | | | — | — |
//! | profile | | | | | | — |
//!
//! The table is symmetric; "—" marks the pairs that [`collide`] refuses with
//! [`KinematicsError::UnsupportedPair`](crate::KinematicsError::UnsupportedPair): two unbounded or
//! non-convex surfaces, whose contact a mechanism declares with a simpler shape on one side.
//! Points (disks of radius 0), segments (capsules of radius 0) and polylines have neither an
//! inside nor a thickness: two of them are refused with
//! [`KinematicsError::NoThickness`](crate::KinematicsError::NoThickness), since their distance
//! never changes sign and one would pass through the other between two steps.
//!
//! # Where the geometry comes from
//! The broad phase is a uniform grid written here: parry2d-f64's bounding-volume hierarchy,
//! even only refitted from call to call, was slower than a step allows for 10⁴ grains (the
//! numbers are in the crate's README). The narrow phase is written here too, for reasons
//! given where each part is computed: parry's polygon manifolds give a
//! clipped point the reference face's normal even when the faces are not parallel (which
//! breaks the rate above), keep state between calls and allocate; its polygons and polylines
//! own their vertices, so that building them from a [`Shape`] on every call would allocate;
//! its chains have no solid inside. For a disk against a disk, a capsule or a half-plane
//! parry's closest points are exact and cost the same as these (about 65 ns against 73 ns in
//! one run of the bench, parry without converting the shapes); the one closest-point routine
//! that every disk pair needs anyway serves them too, and the tests compare it with parry.
//!
//! # References
//! * Ericson, C. (2005). *Real-Time Collision Detection*. Morgan Kaufmann.
//! * Glocker, Ch. (2001). *Set-Valued Force Laws: Dynamics of Non-Smooth Systems*. Springer.

mod broad;
mod chain_index;
mod collide;
mod convex;
mod nonconvex;
mod shape;

pub use broad::BroadPhase;
pub use chain_index::ChainIndex;
pub use collide::{collide, collide_indexed, collide_placed, max_points};
pub use shape::{Placement, Shape};

use serde::{Deserialize, Serialize};

/// A body frame in the world: the position of its origin (m) and its orientation θ (rad,
/// counter-clockwise from the world's x-axis).
#[derive(Clone, Copy, Debug, PartialEq, Default, Serialize, Deserialize)]
pub struct Pose {
    /// The x coordinate of the origin (m).
    pub x: f64,
    /// The y coordinate of the origin (m).
    pub y: f64,
    /// The orientation θ (rad).
    pub theta: f64,
}

impl Pose {
    /// The pose with origin (x, y) and orientation θ.
    pub fn new(x: f64, y: f64, theta: f64) -> Self {
        Self { x, y, theta }
    }
}

/// An axis-aligned bounding box in the world (m); a half-plane's box is infinite along the
/// directions in which the half-plane extends.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Aabb {
    /// The lower corner (x, y).
    pub min: [f64; 2],
    /// The upper corner (x, y).
    pub max: [f64; 2],
}

impl Aabb {
    /// Whether this box and `other`, each grown by `margin` on every side, overlap (touching
    /// counts as overlapping).
    pub fn overlaps(&self, other: &Aabb, margin: f64) -> bool {
        let m = 2.0 * margin;
        self.min[0] <= other.max[0] + m
            && other.min[0] <= self.max[0] + m
            && self.min[1] <= other.max[1] + m
            && other.min[1] <= self.max[1] + m
    }

    /// Whether every coordinate of the box is finite.
    pub fn is_finite(&self) -> bool {
        self.min.iter().chain(&self.max).all(|v| v.is_finite())
    }
}

/// One point of a contact between shape A (on body a) and shape B (on body b).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ManifoldPoint {
    /// The id of the features in contact (a vertex of A on an edge of B, say), the same while
    /// that contact persists; smaller than [`max_points`] of the pair.
    pub feature: u32,
    /// The world point p_A on A's surface (m).
    pub point_a: [f64; 2],
    /// The world point p_B on B's surface (m).
    pub point_b: [f64; 2],
    /// The unit normal n, from A towards B.
    pub normal: [f64; 2],
    /// The normal gap g_N = (p_B − p_A) · n: positive open, negative penetration (m).
    pub gap: f64,
}
