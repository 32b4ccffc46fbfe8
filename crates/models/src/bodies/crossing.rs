//! Whether a step carried a body through a shape it should strike. The scheme sees the
//! contacts at each step's midpoint only: a body that moves in one step by more than its own
//! thickness can have its midpoint past a thin wall, where the gap is measured to the far face
//! and the contact pushes it on, or skip the wall altogether, without any contact sinking
//! deep. The check follows each body that moved by more than a quarter of its thickness along
//! the straight path between its poses at the step's two ends, in stations a quarter of its
//! thickness apart (the other bodies along their own), and looks for a shape it may strike
//! (its contacts' pairs, or the pairs the detection's rules allow whose boxes swept over the
//! step overlap; not a half-plane, which has no far side and whose penetration the depth
//! tells) overlapping it at a station by more than a quarter of its thickness.

use moreau_kinematics::{Aabb, BroadPhase, ManifoldPoint, Pose, Shape};

use super::multibody::Multibody;

/// Most stations along a body's path in one step.
const MAX_STATIONS: usize = 4096;

/// A body carried through another shape within one step ([`CrossingCheck::find`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Crossing {
    /// The body that moved.
    pub body: String,
    /// The body it passed through.
    pub other: String,
    /// How far the body's origin moved in the step (the mechanism's length unit).
    pub moved: f64,
    /// The body's thickness: twice the smallest half-width of its bounded shapes' boxes in its
    /// own frame.
    pub thickness: f64,
    /// The deepest overlap at a station between the step's ends (a negative gap).
    pub gap: f64,
}

/// The thickness of each dynamic body, computed once, for [`CrossingCheck::find`].
#[derive(Clone, Debug)]
pub struct CrossingCheck {
    /// Per body: its first coordinate and its thickness, for a dynamic body with a bounded
    /// shape of positive width; `None` for the others (fixed and driven bodies, bodies of
    /// half-planes or segments only), which the check leaves out.
    followed: Vec<Option<(usize, f64)>>,
    /// Per body: its first coordinate, for a dynamic body.
    coordinate: Vec<Option<usize>>,
}

impl Multibody {
    /// The check of this mechanism's bodies crossing shapes within a step.
    pub fn crossing_check(&self) -> CrossingCheck {
        let mut followed = vec![None; self.bodies.len()];
        let mut coordinate = vec![None; self.bodies.len()];
        for (k, &b) in self.dynamic.iter().enumerate() {
            coordinate[b] = Some(3 * k);
            let local = Pose::new(0.0, 0.0, 0.0);
            let widths = self.bodies[b].shapes.iter().map(|s| s.aabb(&local)).filter_map(|a| {
                let w = (a.max[0] - a.min[0]).min(a.max[1] - a.min[1]);
                (a.is_finite() && w > 0.0).then_some(w)
            });
            followed[b] = widths.reduce(f64::min).map(|w| (3 * k, w));
        }
        CrossingCheck { followed, coordinate }
    }

    /// The pairs of shapes (body a, shape, body o, shape) that a moving body (`moving[a]` or
    /// `moving[o]`) may strike within the step from (q_a, t_a) to (q_e, t_e): its contacts'
    /// pairs on a fixed contact set; on a detected one, the pairs the rules allow whose shapes'
    /// boxes, each the union of its boxes at the step's ends, overlap.
    fn moving_pairs(
        &self,
        moving: &[bool],
        (q_a, t_a): (&[f64], f64),
        (q_e, t_e): (&[f64], f64),
    ) -> Vec<(usize, usize, usize, usize)> {
        let Some(d) = &self.detector else {
            let pairs = self.pairs.iter().filter(|p| moving[p.a] || moving[p.b]);
            return pairs.map(|p| (p.a, p.shape_a, p.b, p.shape_b)).collect();
        };
        let boxes: Vec<Aabb> = d
            .colliders
            .iter()
            .map(|&(b, k)| {
                let shape = &self.bodies[b].shapes[k];
                let at = |q: &[f64], t: f64| shape.aabb_placed(&self.frame(b, q, t).placement());
                let (x, y) = (at(q_a, t_a), at(q_e, t_e));
                Aabb {
                    min: [x.min[0].min(y.min[0]), x.min[1].min(y.min[1])],
                    max: [x.max[0].max(y.max[0]), x.max[1].max(y.max[1])],
                }
            })
            .collect();
        let mut pairs = Vec::new();
        BroadPhase::new().pairs(&boxes, 0.0, &mut pairs);
        pairs
            .into_iter()
            .map(|(i, j)| (d.colliders[i], d.colliders[j]))
            .filter(|&(x, y)| moving[x.0] || moving[y.0])
            .filter(|&(x, y)| d.law(&self.bodies, x, y).is_some())
            .map(|(x, y)| (x.0, x.1, y.0, y.1))
            .collect()
    }
}

impl CrossingCheck {
    /// The first dynamic body that the step from (q_a, t_a) to (q_e, t_e) carried through a
    /// shape it may strike, if any (see the module's description). A body that bounces off a
    /// flat wall keeps both poses on the wall's side and never overlaps it on the line between
    /// them; one that rests or rolls moves too little in a step to be looked at.
    pub fn find(
        &self,
        mb: &Multibody,
        (q_a, t_a): (&[f64], f64),
        (q_e, t_e): (&[f64], f64),
    ) -> Option<Crossing> {
        let moved = |c: usize| (q_e[c] - q_a[c]).hypot(q_e[c + 1] - q_a[c + 1]);
        let moves = |f: &Option<(usize, f64)>| f.is_some_and(|(c, w)| moved(c) > 0.25 * w);
        if !self.followed.iter().any(moves) {
            return None;
        }
        // Each moving body's stations: its path in steps of at most a quarter of its thickness.
        let stations: Vec<usize> = self
            .followed
            .iter()
            .map(|f| match *f {
                Some((c, w)) if moves(f) => {
                    ((moved(c) / (0.25 * w)).ceil() as usize).clamp(2, MAX_STATIONS)
                }
                _ => 0,
            })
            .collect();
        let moving: Vec<bool> = stations.iter().map(|&n| n > 0).collect();
        let mut q = q_a.to_vec();
        let mut points: Vec<ManifoldPoint> = Vec::new();
        let mut found: Option<Crossing> = None;
        for (a, sa, o, so) in mb.moving_pairs(&moving, (q_a, t_a), (q_e, t_e)) {
            let (shape_a, shape_o): (&Shape, &Shape) =
                (&mb.bodies[a].shapes[sa], &mb.bodies[o].shapes[so]);
            // A half-plane has no far side: a body in it is caught by its depth.
            let half_plane = |s: &Shape| matches!(s, Shape::HalfPlane { .. });
            if half_plane(shape_a) || half_plane(shape_o) {
                continue;
            }
            // The pair is followed in the stations of its faster-moving body.
            let (b, other) = if stations[a] >= stations[o] { (a, o) } else { (o, a) };
            let Some((c_b, thickness)) = self.followed[b] else { continue };
            let n = stations[b];
            for j in 1..n {
                let s = j as f64 / n as f64;
                for body in [a, o] {
                    if let Some(c) = self.coordinate[body] {
                        for i in c..c + 3 {
                            q[i] = q_a[i] + s * (q_e[i] - q_a[i]);
                        }
                    }
                }
                let t = t_a + s * (t_e - t_a);
                let (pa, po) = (mb.frame(a, &q, t).placement(), mb.frame(o, &q, t).placement());
                points.clear();
                if mb.collide_shapes((a, sa, &pa), (o, so, &po), 0.0, &mut points).is_err() {
                    continue;
                }
                let Some(gap) = points.iter().map(|p| p.gap).reduce(f64::min) else { continue };
                if gap < -0.25 * thickness && found.as_ref().is_none_or(|c| gap < c.gap) {
                    found = Some(Crossing {
                        body: mb.bodies[b].name.clone(),
                        other: mb.bodies[other].name.clone(),
                        moved: moved(c_b),
                        thickness,
                        gap,
                    });
                }
            }
        }
        found
    }
}
