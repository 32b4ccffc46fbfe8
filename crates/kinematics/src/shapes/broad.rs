//! The broad phase: the pairs of boxes that come within a margin, from parry2d-f64's
//! bounding-volume hierarchy, kept and refitted from call to call.

use parry2d_f64::bounding_volume::Aabb as ParryAabb;
use parry2d_f64::math::Vector as ParryVector;
use parry2d_f64::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace};

use super::Aabb;

/// The pairs (i, j), i < j, of boxes that overlap when each is grown by a margin.
///
/// Finite boxes go into a bounding-volume hierarchy that is built once and refitted on later
/// calls with the same boxes (so that, once warm, a call allocates nothing); it is rebuilt
/// when the set of finite boxes changes. Boxes with an infinite side (half-planes) are few and
/// are tested against every box directly, since a hierarchy cannot split an infinite box. A box
/// with a NaN coordinate overlaps nothing.
#[derive(Clone, Default)]
pub struct BroadPhase {
    tree: Bvh,
    workspace: BvhWorkspace,
    /// The indices of the boxes in the tree at the last call, in increasing order.
    in_tree: Vec<usize>,
    /// The indices of the boxes in the tree at this call, being gathered.
    scratch: Vec<usize>,
    /// The indices of the boxes with an infinite side.
    unbounded: Vec<usize>,
    /// The tree's leaves (grown by the margin) when it is built afresh.
    leaves: Vec<ParryAabb>,
}

impl std::fmt::Debug for BroadPhase {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("BroadPhase").field("boxes_in_tree", &self.in_tree.len()).finish()
    }
}

impl BroadPhase {
    /// An empty broad phase; its first call builds the hierarchy.
    pub fn new() -> Self {
        Self::default()
    }

    /// Writes into `out` (cleared first) the pairs (i, j), i < j, of `boxes` that overlap when
    /// each is grown by `margin` (m) on every side, touching included, in increasing (i, j)
    /// order.
    pub fn pairs(&mut self, boxes: &[Aabb], margin: f64, out: &mut Vec<(usize, usize)>) {
        out.clear();
        self.scratch.clear();
        self.unbounded.clear();
        for (i, b) in boxes.iter().enumerate() {
            let values = [b.min[0], b.min[1], b.max[0], b.max[1]];
            if values.iter().any(|v| v.is_nan()) {
                continue;
            }
            if values.iter().all(|v| v.is_finite()) {
                self.scratch.push(i);
            } else {
                self.unbounded.push(i);
            }
        }
        let grown = |b: &Aabb| {
            ParryAabb::new(
                ParryVector::new(b.min[0] - margin, b.min[1] - margin),
                ParryVector::new(b.max[0] + margin, b.max[1] + margin),
            )
        };
        if self.scratch != self.in_tree {
            std::mem::swap(&mut self.scratch, &mut self.in_tree);
            self.leaves.clear();
            self.leaves.extend(self.in_tree.iter().map(|&i| grown(&boxes[i])));
            let ids = self.in_tree.iter().copied();
            self.tree =
                Bvh::from_iter(BvhBuildStrategy::Binned, ids.zip(self.leaves.iter().copied()));
        } else {
            for &i in &self.in_tree {
                self.tree.insert_or_update_partially(grown(&boxes[i]), i as u32, 0.0);
            }
            self.tree.refit(&mut self.workspace);
        }
        self.tree.traverse_bvtt_single_tree::<false>(&mut self.workspace, &mut |i, j| {
            let (i, j) = (i as usize, j as usize);
            // The tree reports pairs whose nodes' boxes meet; the leaves' boxes are tested
            // again here so that the answer is exactly the overlap test.
            if boxes[i].overlaps(&boxes[j], margin) {
                out.push((i.min(j), i.max(j)));
            }
        });
        for &u in &self.unbounded {
            for (j, b) in boxes.iter().enumerate() {
                let counted = self.unbounded.contains(&j) && j < u;
                if j != u && !counted && boxes[u].overlaps(b, margin) {
                    out.push((u.min(j), u.max(j)));
                }
            }
        }
        out.sort_unstable();
    }
}
