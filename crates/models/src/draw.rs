//! Drawings of the mechanisms: polylines and circles in metres, for animation strips.

use serde::{Deserialize, Serialize};

/// The part of a mechanism a drawing element belongs to, so that a renderer can colour it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum Role {
    /// The fixed ground or floor.
    Ground,
    /// The woodpecker's pole.
    Pole,
    /// The woodpecker's sleeve.
    Sleeve,
    /// The woodpecker's body.
    Bird,
    /// The woodpecker's beak.
    Beak,
    /// A spring or a joint between bodies.
    Joint,
    /// The slider-crank's crank.
    Crank,
    /// A connecting rod or the Painlevé rod.
    Rod,
    /// The slider of the slider-crank.
    Slider,
    /// The slider-crank's guide surfaces or the follower's guide.
    Guide,
    /// The cam.
    Cam,
    /// The cam's follower.
    Follower,
    /// The bouncing ball.
    Ball,
    /// A closed contact (g_N ≤ 0 up to round-off).
    ContactPoint,
}

/// A chain of line segments.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Polyline {
    /// Vertices `[x, y]` (m).
    pub points: Vec<[f64; 2]>,
    /// Whether the last vertex joins the first (a polygon).
    pub closed: bool,
    /// The part drawn.
    pub role: Role,
}

/// A circle.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Circle {
    /// Centre `[x, y]` (m).
    pub center: [f64; 2],
    /// Radius (m).
    pub radius: f64,
    /// The part drawn.
    pub role: Role,
}

/// An axis-aligned box `[min, max]` (m).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Bounds {
    /// Lower-left corner `[x, y]`.
    pub min: [f64; 2],
    /// Upper-right corner `[x, y]`.
    pub max: [f64; 2],
}

impl Bounds {
    /// Width `max_x − min_x` (m).
    pub fn width(&self) -> f64 {
        self.max[0] - self.min[0]
    }

    /// Height `max_y − min_y` (m).
    pub fn height(&self) -> f64 {
        self.max[1] - self.min[1]
    }

    /// The smallest box holding both boxes.
    pub fn union(&self, other: &Bounds) -> Bounds {
        Bounds {
            min: [self.min[0].min(other.min[0]), self.min[1].min(other.min[1])],
            max: [self.max[0].max(other.max[0]), self.max[1].max(other.max[1])],
        }
    }

    /// Whether the point lies inside or on the box.
    pub fn contains(&self, p: [f64; 2]) -> bool {
        (self.min[0]..=self.max[0]).contains(&p[0]) && (self.min[1]..=self.max[1]).contains(&p[1])
    }
}

/// A drawing of a mechanism at one instant, in metres, in the model's fixed frame
/// (x to the right, y up).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Drawing {
    /// Lines and polygons.
    pub polylines: Vec<Polyline>,
    /// Circles (balls, joints, contact markers).
    pub circles: Vec<Circle>,
}

impl Drawing {
    /// An empty drawing.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds an open polyline.
    pub fn line(&mut self, role: Role, points: Vec<[f64; 2]>) {
        self.polylines.push(Polyline { points, closed: false, role });
    }

    /// Adds a closed polygon.
    pub fn polygon(&mut self, role: Role, points: Vec<[f64; 2]>) {
        self.polylines.push(Polyline { points, closed: true, role });
    }

    /// Adds a circle.
    pub fn circle(&mut self, role: Role, center: [f64; 2], radius: f64) {
        self.circles.push(Circle { center, radius, role });
    }

    /// The elements of one role, as (polylines, circles) counts; handy for checks.
    pub fn count(&self, role: Role) -> (usize, usize) {
        (
            self.polylines.iter().filter(|p| p.role == role).count(),
            self.circles.iter().filter(|c| c.role == role).count(),
        )
    }

    /// The smallest box holding every vertex and every circle, or `None` for an empty drawing.
    pub fn bounds(&self) -> Option<Bounds> {
        let mut b: Option<Bounds> = None;
        let mut add = |lo: [f64; 2], hi: [f64; 2]| {
            let nb = Bounds { min: lo, max: hi };
            b = Some(match b {
                Some(old) => old.union(&nb),
                None => nb,
            });
        };
        for p in &self.polylines {
            for &v in &p.points {
                add(v, v);
            }
        }
        for c in &self.circles {
            let r = c.radius.abs();
            add([c.center[0] - r, c.center[1] - r], [c.center[0] + r, c.center[1] + r]);
        }
        b
    }
}
