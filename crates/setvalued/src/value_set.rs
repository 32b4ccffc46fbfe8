//! Closed convex subsets of the real line: the values of the set-valued maps.

/// A closed convex subset of ℝ: empty, a point, or an interval whose bounds may be ±∞.
///
/// Built through [`ValueSet::interval`], an interval always has `lo < hi`; a degenerate interval
/// is a [`ValueSet::Point`]. A set written through the variants with a NaN bound or `lo > hi`
/// holds nothing: every method treats it as [`ValueSet::Empty`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ValueSet {
    /// The empty set ∅ (e.g. Upr(x) for x < 0).
    Empty,
    /// A single value {v}.
    Point(f64),
    /// The interval [lo, hi], with lo = −∞ or hi = +∞ for an unbounded side.
    Interval {
        /// Lower bound (may be −∞).
        lo: f64,
        /// Upper bound (may be +∞).
        hi: f64,
    },
}

impl ValueSet {
    /// The set [lo, hi]: a point when lo = hi, empty when lo > hi or a bound is NaN.
    pub fn interval(lo: f64, hi: f64) -> Self {
        if lo < hi {
            Self::Interval { lo, hi }
        } else if lo == hi && lo.is_finite() {
            Self::Point(lo)
        } else {
            Self::Empty
        }
    }

    /// The whole real line (−∞, +∞).
    pub fn real_line() -> Self {
        Self::Interval { lo: f64::NEG_INFINITY, hi: f64::INFINITY }
    }

    /// The bounds (lo, hi) with lo ≤ hi, `None` for the empty set (or one written with a NaN
    /// bound or lo > hi).
    fn bounds(&self) -> Option<(f64, f64)> {
        let (lo, hi) = match *self {
            Self::Empty => return None,
            Self::Point(v) => (v, v),
            Self::Interval { lo, hi } => (lo, hi),
        };
        (lo <= hi).then_some((lo, hi))
    }

    /// Whether the set is empty.
    pub fn is_empty(&self) -> bool {
        self.bounds().is_none()
    }

    /// The lower bound, `None` for the empty set.
    pub fn lower(&self) -> Option<f64> {
        self.bounds().map(|(lo, _)| lo)
    }

    /// The upper bound, `None` for the empty set.
    pub fn upper(&self) -> Option<f64> {
        self.bounds().map(|(_, hi)| hi)
    }

    /// The distance from `y` to the set: zero inside, +∞ for the empty set, NaN for a NaN `y`.
    pub fn distance(&self, y: f64) -> f64 {
        match self.bounds() {
            Some((lo, hi)) => {
                if y.is_nan() {
                    f64::NAN
                } else if y < lo {
                    lo - y
                } else if y > hi {
                    y - hi
                } else {
                    0.0
                }
            }
            None => f64::INFINITY,
        }
    }

    /// Whether `y` lies in the set within `tol` (distance at most `tol`); false for a NaN `y`.
    pub fn contains(&self, y: f64, tol: f64) -> bool {
        self.distance(y) <= tol
    }

    /// The projection of `y` onto the set (the nearest element), `None` for the empty set.
    pub fn project(&self, y: f64) -> Option<f64> {
        self.bounds().map(|(lo, hi)| y.clamp(lo, hi))
    }

    /// The set a·S = {a s : s ∈ S}; 0·S = {0} for a non-empty S, also when S is unbounded.
    /// Empty for a NaN factor, and for ±∞·{0} or a point sent to infinity, which are no reals.
    pub fn scale(&self, a: f64) -> Self {
        if self.is_empty() || a.is_nan() {
            return Self::Empty;
        }
        match *self {
            Self::Empty => Self::Empty,
            _ if a == 0.0 => Self::Point(0.0),
            Self::Point(v) => Self::interval(a * v, a * v),
            Self::Interval { lo, hi } if a > 0.0 => Self::interval(a * lo, a * hi),
            Self::Interval { lo, hi } => Self::interval(a * hi, a * lo),
        }
    }

    /// The set −S.
    pub fn negate(&self) -> Self {
        self.scale(-1.0)
    }

    /// The Minkowski sum S + R = {s + r : s ∈ S, r ∈ R}.
    pub fn sum(&self, other: &Self) -> Self {
        match (self.lower(), self.upper(), other.lower(), other.upper()) {
            (Some(a), Some(b), Some(c), Some(d)) => Self::interval(a + c, b + d),
            _ => Self::Empty,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn construction_normalises_degenerate_intervals() {
        assert_eq!(ValueSet::interval(1.0, 1.0), ValueSet::Point(1.0));
        assert_eq!(ValueSet::interval(2.0, 1.0), ValueSet::Empty);
        assert_eq!(ValueSet::interval(f64::NAN, 1.0), ValueSet::Empty);
        assert_eq!(
            ValueSet::interval(f64::NEG_INFINITY, 0.0),
            ValueSet::Interval { lo: f64::NEG_INFINITY, hi: 0.0 }
        );
        assert_eq!(ValueSet::interval(f64::INFINITY, f64::INFINITY), ValueSet::Empty);
    }

    #[test]
    fn distance_contains_and_projection() {
        let s = ValueSet::interval(-1.0, 2.0);
        assert_eq!((s.distance(-3.0), s.distance(0.5), s.distance(2.5)), (2.0, 0.0, 0.5));
        assert!(s.contains(2.1, 0.1 + 1e-15) && !s.contains(2.1, 0.09));
        assert!(!s.contains(f64::NAN, 1.0));
        assert_eq!(ValueSet::Empty.distance(0.0), f64::INFINITY);
        assert!(!ValueSet::Empty.contains(0.0, 1e300));
        assert_eq!(ValueSet::Point(3.0).distance(1.0), 2.0);
        assert_eq!(s.project(5.0), Some(2.0));
        assert_eq!(ValueSet::interval(f64::NEG_INFINITY, 0.0).project(-7.0), Some(-7.0));
        assert_eq!(ValueSet::Empty.project(1.0), None);
    }

    #[test]
    fn malformed_sets_and_nan_factors_behave_as_empty_without_panicking() {
        // A NaN factor leaves no set, where it made the point {NaN} that every y was 0 from.
        let nan_point = ValueSet::Point(1.0).scale(f64::NAN);
        assert_eq!(nan_point, ValueSet::Empty);
        assert_eq!(ValueSet::interval(-1.0, 2.0).scale(f64::NAN), ValueSet::Empty);
        // ∞ · {0} is no number; ∞ · [−1, 2] is the real line.
        assert_eq!(ValueSet::Point(0.0).scale(f64::INFINITY), ValueSet::Empty);
        assert_eq!(ValueSet::interval(-1.0, 2.0).scale(f64::INFINITY), ValueSet::real_line());
        // Sets written through the variants with a NaN bound or lo > hi hold nothing: no
        // bounds, infinitely far from every y, no projection (the clamp panicked before).
        for set in [
            ValueSet::Point(f64::NAN),
            ValueSet::Interval { lo: 2.0, hi: 1.0 },
            ValueSet::Interval { lo: f64::NAN, hi: 1.0 },
            ValueSet::Interval { lo: 0.0, hi: f64::NAN },
        ] {
            assert!(set.is_empty(), "{set:?}");
            assert_eq!((set.lower(), set.upper()), (None, None), "{set:?}");
            assert_eq!(set.distance(0.5), f64::INFINITY, "{set:?}");
            assert!(!set.contains(0.5, 1e300), "{set:?}");
            assert_eq!(set.project(0.5), None, "{set:?}");
            assert_eq!(set.sum(&ValueSet::Point(1.0)), ValueSet::Empty, "{set:?}");
        }
    }

    #[test]
    fn scaling_and_minkowski_sum() {
        let ray = ValueSet::interval(f64::NEG_INFINITY, 0.0);
        assert_eq!(ray.scale(3.0), ray);
        assert_eq!(ray.negate(), ValueSet::interval(0.0, f64::INFINITY));
        assert_eq!(ray.scale(0.0), ValueSet::Point(0.0));
        assert_eq!(ValueSet::interval(-1.0, 2.0).scale(-2.0), ValueSet::interval(-4.0, 2.0));
        assert_eq!(
            ValueSet::Point(1.5).sum(&ValueSet::interval(-1.0, 1.0)),
            ValueSet::interval(0.5, 2.5)
        );
        assert_eq!(ray.sum(&ray.negate()), ValueSet::real_line());
        assert_eq!(ray.sum(&ValueSet::Empty), ValueSet::Empty);
    }
}
