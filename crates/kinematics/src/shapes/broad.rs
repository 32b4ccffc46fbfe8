//! The broad phase: the pairs of boxes that come within a margin, from a uniform grid rebuilt
//! at every call by a counting sort.
//!
//! # Why a grid and not parry's hierarchy
//! A time-stepper asks for the pairs of all bodies at every step: 10⁴ grains should cost well
//! under the 10 ms of a step. parry2d-f64's bounding-volume hierarchy, built once and then only
//! refitted (`Bvh::insert_or_update_partially`, `Bvh::refit`) before its self-traversal, the
//! cheapest incremental use it offers, takes 2.4 to 4 ms for 10⁴ disks of radius 5 mm, at
//! random in 1 m² (28 484 pairs) or in a column 20 disks wide (38 442 pairs), on this shared
//! 2-core machine; rebuilding it is slower, and its incremental optimisation allocates. Grains
//! are of one size within a small factor, the case a uniform grid serves best: cells the size
//! of the largest grain, one pass to place the boxes and one to collect the pairs, O(n + pairs)
//! with no tree to keep. Measured in the same runs (`cargo bench -p moreau-kinematics --bench
//! collide -- broad`, load average 4.5 to 6), the grid takes 0.2 times parry's time on the
//! column (0.83 ms against 3.97 ms), about half on 10³ disks at random (89 µs against 187 µs),
//! and 0.7 to 0.9 times on 10⁴ disks numbered at random over the square (3.0 ms against
//! 3.5 ms), where its reads of the neighbouring cells miss the cache: bodies numbered in space
//! order (a lattice, a column that settles) are its fast case.
//!
//! # How
//! The cell size h is the largest extent (grown by the margin) of the ORDINARY boxes, those no
//! larger than four times the mean extent of the finite boxes. Each ordinary box goes, by a
//! counting sort, into the cell of its lower grown corner, copied in cell order; two boxes that
//! overlap then lie in the same or neighbouring cells. Box i then reads the 3 × 3 cells around
//! its own (three runs of memory, one per row) and keeps the boxes j > i that overlap it
//! exactly ([`Aabb::overlaps`]), so that the pairs come out in (i, j) order after sorting each
//! box's few partners. A grid that would need more than about four cells per box (bodies
//! scattered far apart) is made coarser. The few other boxes (half-planes with an infinite
//! side, long walls) are tested against every box directly, and so is every box when no grid
//! can hold them (an infinite margin, boxes spread wider than f64's range). Every buffer is
//! kept, so that once warm a call allocates nothing. The grid is built once
//! ([`BroadPhase::build`]) and searched by ranges of boxes ([`BroadPhase::pairs_of`]), whose
//! lists follow each other in the order of the whole: ranges can be searched on several
//! threads and their lists concatenated.

use std::ops::Range;

use super::Aabb;

/// The cells are this fraction larger than the largest ordinary box, so that round-off can
/// never put two overlapping boxes' corners two cells apart.
const SLACK: f64 = 1e-9;

/// An ordinary box is no larger than this many times the mean extent of the finite boxes.
const LARGE: f64 = 4.0;

/// A box in the grid, copied in cell order so that the sweep over cells reads memory in order.
#[derive(Clone, Copy, Debug)]
struct Item {
    aabb: Aabb,
    index: u32,
}

/// The pairs (i, j), i < j, of boxes that overlap when each is grown by a margin.
#[derive(Clone, Debug, Default)]
pub struct BroadPhase {
    /// The boxes tested directly against all others: unbounded or much larger than most.
    direct: Vec<usize>,
    /// Whether each box is in the grid.
    ordinary: Vec<bool>,
    /// Each ordinary box's cell, row-major.
    cell: Vec<u32>,
    /// The ordinary boxes sorted by cell: cell c holds `items[start[c]..start[c + 1]]`.
    items: Vec<Item>,
    start: Vec<u32>,
    /// The grid's columns and rows, and the margin of the last build.
    nx: usize,
    ny: usize,
    margin: f64,
}

/// Whether a box has a NaN coordinate.
fn nan(b: &Aabb) -> bool {
    b.min.iter().chain(&b.max).any(|v| v.is_nan())
}

impl BroadPhase {
    /// An empty broad phase.
    pub fn new() -> Self {
        Self::default()
    }

    /// Writes into `out` (cleared first) the pairs (i, j), i < j, of `boxes` that overlap when
    /// each is grown by `margin` (m) on every side, touching included, in increasing (i, j)
    /// order. A box with a NaN coordinate overlaps nothing; an infinite margin makes every two
    /// other boxes overlap, a NaN margin none. It is [`Self::build`] then
    /// [`Self::pairs_of`] over all boxes.
    pub fn pairs(&mut self, boxes: &[Aabb], margin: f64, out: &mut Vec<(usize, usize)>) {
        out.clear();
        self.build(boxes, margin);
        self.pairs_of(boxes, 0..boxes.len(), out);
    }

    /// Sorts `boxes`, grown by `margin` (m) on every side, into the grid that
    /// [`Self::pairs_of`] reads.
    pub fn build(&mut self, boxes: &[Aabb], margin: f64) {
        let n = boxes.len();
        let extent = |b: &Aabb| (b.max[0] - b.min[0]).max(b.max[1] - b.min[1]) + 2.0 * margin;
        let (mut sum, mut finite) = (0.0, 0usize);
        for b in boxes.iter().filter(|b| b.is_finite()) {
            sum += extent(b);
            finite += 1;
        }
        let mean = if finite > 0 { sum / finite as f64 } else { 0.0 };
        self.direct.clear();
        self.ordinary.clear();
        let (mut h, mut lo, mut hi) = (0.0f64, [f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        let mut nans = 0;
        for (i, b) in boxes.iter().enumerate() {
            let ordinary = !nan(b) && b.is_finite() && extent(b) <= LARGE * mean;
            self.ordinary.push(ordinary);
            if ordinary {
                h = h.max(extent(b));
                for k in 0..2 {
                    lo[k] = lo[k].min(b.min[k] - margin);
                    hi[k] = hi[k].max(b.min[k] - margin);
                }
            } else if !nan(b) {
                self.direct.push(i);
            } else {
                nans += 1;
            }
        }
        // An infinite margin, or boxes spread wider than f64's range, leave no finite cell size
        // or grid span: every box is then tested against every other directly.
        if !(h.is_finite() && (hi[0] - lo[0]).is_finite() && (hi[1] - lo[1]).is_finite()) {
            self.direct.clear();
            self.direct.extend((0..n).filter(|&i| !nan(&boxes[i])));
            self.ordinary.fill(false);
        }
        let ordinary_count = n - self.direct.len() - nans;
        (self.nx, self.ny) = if ordinary_count > 0 {
            self.grid(boxes, margin, h, lo, hi, ordinary_count)
        } else {
            (0, 0)
        };
        self.margin = margin;
    }

    /// Appends to `out` the pairs (i, j), i < j, i in `range`, of the boxes that the last
    /// [`Self::build`] sorted, in increasing (i, j) order: consecutive ranges give
    /// consecutive runs of [`Self::pairs`]' list, so that ranges can be searched in parallel.
    ///
    /// # Panics
    /// When `boxes` is not the slice of the last [`Self::build`] (a different length), or
    /// `range` ends past it.
    pub fn pairs_of(&self, boxes: &[Aabb], range: Range<usize>, out: &mut Vec<(usize, usize)>) {
        assert_eq!(
            boxes.len(),
            self.ordinary.len(),
            "the boxes of a search are those of the last build"
        );
        let (nx, ny, margin) = (self.nx, self.ny, self.margin);
        // Box by box in index order, so that the pairs come out sorted by i; each box's few
        // partners j > i are then sorted in place.
        for i in range {
            let first = out.len();
            if self.ordinary[i] {
                let c = self.cell[i] as usize;
                let (x, y) = (c % nx, c / nx);
                let (x0, x1) = (x.saturating_sub(1), (x + 1).min(nx - 1));
                for row in y.saturating_sub(1)..=(y + 1).min(ny - 1) {
                    let cells =
                        self.start[row * nx + x0] as usize..self.start[row * nx + x1 + 1] as usize;
                    for item in &self.items[cells] {
                        let j = item.index as usize;
                        if j > i && boxes[i].overlaps(&item.aabb, margin) {
                            out.push((i, j));
                        }
                    }
                }
                for &u in &self.direct {
                    if u > i && boxes[i].overlaps(&boxes[u], margin) {
                        out.push((i, u));
                    }
                }
            } else if !nan(&boxes[i]) {
                for (j, b) in boxes.iter().enumerate().skip(i + 1) {
                    if !nan(b) && boxes[i].overlaps(b, margin) {
                        out.push((i, j));
                    }
                }
            }
            for k in first + 1..out.len() {
                let mut m = k;
                while m > first && out[m - 1].1 > out[m].1 {
                    out.swap(m - 1, m);
                    m -= 1;
                }
            }
        }
    }

    /// Puts the ordinary boxes, whose lower grown corners lie in [lo, hi] and whose grown
    /// extents are at most h, each in the cell of its lower corner, so that two overlapping
    /// boxes lie in the same or neighbouring cells; returns the grid's columns and rows.
    fn grid(
        &mut self,
        boxes: &[Aabb],
        margin: f64,
        h: f64,
        lo: [f64; 2],
        hi: [f64; 2],
        count: usize,
    ) -> (usize, usize) {
        // Cells of the largest ordinary box, made coarser if the region would need more than
        // about four cells per box (bodies scattered far apart), so that memory stays O(n).
        let cap = (4 * count + 64) as f64;
        let span = (hi[0] - lo[0]).max(hi[1] - lo[1]);
        // Boxes of zero size and margin still get cells of a finite, non-zero size.
        let mut size = if h > 0.0 { h * (1.0 + SLACK) } else { 1.0 };
        size = size.max(span / cap);
        let dims = |size: f64| {
            let d = [(hi[0] - lo[0]) / size, (hi[1] - lo[1]) / size];
            [d[0].floor() + 1.0, d[1].floor() + 1.0]
        };
        let mut d = dims(size);
        while d[0] * d[1] > cap {
            size *= (d[0] * d[1] / cap).sqrt().max(1.0 + 1e-3);
            d = dims(size);
        }
        let (nx, ny) = (d[0] as usize, d[1] as usize);
        let cells = nx * ny;
        let inverse = 1.0 / size;
        let place = |v: f64, k: usize, len: usize| (((v - lo[k]) * inverse) as usize).min(len - 1);
        self.cell.clear();
        self.start.clear();
        // Room for the largest grid these boxes can have, so that moving them never regrows it.
        self.start.reserve(cap as usize + 1);
        self.start.resize(cells + 1, 0);
        for (b, &ordinary) in boxes.iter().zip(&self.ordinary) {
            let c = if ordinary {
                let c = place(b.min[1] - margin, 1, ny) * nx + place(b.min[0] - margin, 0, nx);
                self.start[c + 1] += 1;
                c as u32
            } else {
                u32::MAX
            };
            self.cell.push(c);
        }
        for c in 0..cells {
            self.start[c + 1] += self.start[c];
        }
        self.items.clear();
        let empty = Item { aabb: Aabb { min: [0.0; 2], max: [0.0; 2] }, index: 0 };
        self.items.resize(count, empty);
        for (i, &c) in self.cell.iter().enumerate() {
            if c != u32::MAX {
                let slot = &mut self.start[c as usize];
                self.items[*slot as usize] = Item { aabb: boxes[i], index: i as u32 };
                *slot += 1;
            }
        }
        for c in (1..=cells).rev() {
            self.start[c] = self.start[c - 1];
        }
        self.start[0] = 0;
        (nx, ny)
    }
}
