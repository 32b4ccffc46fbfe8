//! The boxes of runs of consecutive segments of a long polyline or profile, so that the narrow
//! phase against it visits the runs near the other shape instead of every segment.
//!
//! A disk on a polyline of n segments costs about 2.5 ns a segment without them (25 µs at
//! 10,000 points, for each grain on a measured floor): a chain's narrow phase passes over each
//! segment whose box misses the other shape's, but it still places every point in the world to
//! find out. With runs of about √n segments, it places the corners of √n run boxes and the
//! points of the few runs that pass the same test, and finds the same points bit for bit: each
//! run box holds its segments in the world (with room for round-off), so a run is passed over
//! only when every segment in it would have been.

use std::ops::Range;

use super::Aabb;
use super::shape::{Placement, Shape, V};

/// Chains of at most this many segments are not indexed: a pass over them costs less than the
/// index's boxes.
const SHORT_CHAIN: usize = 64;

/// The boxes of runs of consecutive segments of a polyline or profile, in the shape's own
/// frame: built once per shape ([`ChainIndex::new`]), passed to [`crate::collide_indexed`] with
/// that shape.
///
/// ```
/// use moreau_kinematics::{ChainIndex, ManifoldPoint, Placement, Pose, Shape};
/// use moreau_kinematics::{collide_indexed, collide_placed};
///
/// # fn main() -> Result<(), moreau_kinematics::KinematicsError> {
/// // A wavy floor of 10,000 segments and a disk resting on it.
/// let points = (0..=10_000)
///     .map(|k| { let x = k as f64 * 1e-3; [x, 0.05 * (3.0 * x).sin()] })
///     .collect();
/// let floor = Shape::Polyline { points };
/// let index = ChainIndex::new(&floor).expect("a long chain is indexed");
/// let disk = Shape::Disk { center: [0.0, 0.0], radius: 0.01 };
/// let at = Placement::new(&Pose::new(5.0, 0.05 * 15f64.sin() + 0.0099, 0.0));
/// let origin = Placement::new(&Pose::new(0.0, 0.0, 0.0));
/// let (mut fast, mut plain) = (Vec::<ManifoldPoint>::new(), Vec::new());
/// collide_indexed(&disk, &at, &floor, &origin, Some(&index), 1e-3, &mut fast)?;
/// collide_placed(&disk, &at, &floor, &origin, 1e-3, &mut plain)?;
/// assert_eq!(fast, plain);
/// assert_eq!(fast.len(), 1);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct ChainIndex {
    /// The chain's number of points and whether it is closed: an index is used only with a
    /// chain of the same kind and length.
    points: usize,
    closed: bool,
    /// Segments per run (the last run may have fewer).
    run: usize,
    /// Per run: the centre and half-widths of its segments' box in the shape's frame.
    boxes: Vec<([f64; 2], [f64; 2])>,
}

impl ChainIndex {
    /// The index of `shape`: `Some` for a polyline or a profile of more than 64 segments,
    /// `None` for any other shape, whose narrow phase does not need one.
    pub fn new(shape: &Shape) -> Option<Self> {
        let (points, closed) = match shape {
            Shape::Polyline { points } => (points, false),
            Shape::Profile { points } => (points, true),
            _ => return None,
        };
        let p = points.len();
        let m = if closed { p } else { p.saturating_sub(1) };
        if m <= SHORT_CHAIN {
            return None;
        }
        let run = (m as f64).sqrt().ceil() as usize;
        let boxes = (0..m.div_ceil(run))
            .map(|r| {
                let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
                for v in r * run..=((r + 1) * run).min(m) {
                    let q = points[v % p];
                    for i in 0..2 {
                        lo[i] = lo[i].min(q[i]);
                        hi[i] = hi[i].max(q[i]);
                    }
                }
                let c = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
                (c, [0.5 * (hi[0] - lo[0]), 0.5 * (hi[1] - lo[1])])
            })
            .collect();
        Some(Self { points: p, closed, run, boxes })
    }

    /// Whether the index was built for a chain of `points` points, closed or not.
    pub(crate) fn fits(&self, points: &[[f64; 2]], closed: bool) -> bool {
        self.points == points.len() && self.closed == closed
    }

    /// The runs of segments (segment k from point k to point k + 1, the last of a profile back
    /// to point 0) whose box at `frame`, in the world, `keep` accepts, in increasing order. The
    /// box holds the run's points as [`Placement::point`] places them, grown for round-off.
    pub(crate) fn runs<'a>(
        &'a self,
        frame: &'a Placement,
        keep: impl Fn(&Aabb) -> bool + 'a,
    ) -> impl Iterator<Item = Range<usize>> + 'a {
        let m = if self.closed { self.points } else { self.points - 1 };
        let (c, s) = (frame.cos.abs(), frame.sin.abs());
        self.boxes.iter().enumerate().filter_map(move |(r, &(centre, half))| {
            let o: V = frame.point(centre);
            let w = [c * half[0] + s * half[1], s * half[0] + c * half[1]];
            // A placed point differs from the exact one by a few units in the last place of
            // the magnitudes it adds; this is a million of them.
            let size = o.x.abs().max(o.y.abs()) + half[0].abs().max(half[1].abs());
            let slack = 1e-10 * (size + f64::MIN_POSITIVE);
            let placed = Aabb {
                min: [o.x - w[0] - slack, o.y - w[1] - slack],
                max: [o.x + w[0] + slack, o.y + w[1] + slack],
            };
            keep(&placed).then(|| r * self.run..((r + 1) * self.run).min(m))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_chains_and_other_shapes_have_no_index() {
        let line =
            |n: usize| Shape::Polyline { points: (0..=n).map(|k| [k as f64, 0.0]).collect() };
        assert!(ChainIndex::new(&line(64)).is_none());
        let index = ChainIndex::new(&line(65)).expect("65 segments");
        // 65 segments in runs of 9: 8 runs of 9 and one of 2.
        assert_eq!((index.run, index.boxes.len()), (9, 8));
        let frame = Placement::new(&super::super::Pose::new(0.0, 0.0, 0.0));
        let runs: Vec<Range<usize>> = index.runs(&frame, |_| true).collect();
        assert_eq!(runs.first(), Some(&(0..9)));
        assert_eq!(runs.last(), Some(&(63..65)));
        assert!(ChainIndex::new(&Shape::Disk { center: [0.0; 2], radius: 1.0 }).is_none());
    }

    #[test]
    fn every_placed_point_lies_in_its_runs_box() {
        // A spiral profile of 1,000 points far from the origin, turned by 0.7 rad and moved.
        let points: Vec<[f64; 2]> = (0..1000)
            .map(|k| {
                let a = k as f64 * 0.0063;
                let r = 1.0 + 0.3 * (7.0 * a).sin();
                [1e3 + r * a.cos(), -2e3 + r * a.sin()]
            })
            .collect();
        let index = ChainIndex::new(&Shape::Profile { points: points.clone() }).expect("indexed");
        let frame = Placement::new(&super::super::Pose::new(-4e3, 7e2, 0.7));
        let mut seen = 0;
        let boxes: Vec<(Range<usize>, Aabb)> = {
            let placed = std::cell::RefCell::new(Vec::new());
            let runs: Vec<Range<usize>> = index
                .runs(&frame, |b| {
                    placed.borrow_mut().push(*b);
                    true
                })
                .collect();
            runs.into_iter().zip(placed.into_inner()).collect()
        };
        for (run, b) in &boxes {
            for k in run.start..=run.end {
                let v = frame.point(points[k % points.len()]);
                assert!(
                    b.min[0] <= v.x && v.x <= b.max[0] && b.min[1] <= v.y && v.y <= b.max[1],
                    "point {k} at {v:?} outside {b:?}"
                );
                seen += 1;
            }
        }
        assert_eq!(seen, 1000 + boxes.len());
    }
}
