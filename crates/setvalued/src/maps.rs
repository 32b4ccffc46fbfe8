//! The unilateral primitive Upr and the set-valued sign Sgn, their inverses, proximal maps and
//! sampled graphs.
//!
//! ```text
//! Upr(x) = {0} (x > 0),  (−∞, 0] (x = 0),  ∅ (x < 0)
//! b Sgn(x) = {+b} (x > 0),  [−b, +b] (x = 0),  {−b} (x < 0)        (b ≥ 0)
//! ```
//!
//! Membership with a tolerance is measured on the graph: y ∈ F(x) within `tol` when the point
//! (x, y) lies within `tol` of the graph of F in the max-norm. For Upr this distance is exactly
//! the natural-map residual |min(x, −y)| of the complementarity 0 ≤ x ⊥ −y ≥ 0.
//!
//! # References
//! * Moreau, J. J. (1988). Unilateral contact and dry friction in finite freedom dynamics. In
//!   *Non-Smooth Mechanics and Applications*, CISM 302, Springer.
//! * Glocker, Ch. (2001). *Set-Valued Force Laws: Dynamics of Non-Smooth Systems*. Springer.
//! * Flores, P. (2010). *Application of the non-smooth dynamics approach to model and analyze
//!   contact-impact events in rigid multibody systems using the linear complementarity problem
//!   formulation*. Universidade do Minho.

use serde::{Deserialize, Serialize};

use crate::{SetValuedError, ValueSet, checked_mu};

/// A maximal monotone set-valued map F: ℝ ⇉ ℝ with a piecewise-linear graph.
pub trait SetValuedMap {
    /// The value set F(x).
    fn value(&self, x: f64) -> ValueSet;

    /// The inverse graph F⁻¹(y) = {x : y ∈ F(x)}.
    fn inverse(&self, y: f64) -> ValueSet;

    /// The max-norm distance from the point (x, y) to the graph of F; NaN for a NaN input.
    fn graph_distance(&self, x: f64, y: f64) -> f64;

    /// The abscissae at which F is set-valued (the vertical segments of the graph).
    fn breakpoints(&self) -> &[f64];

    /// Whether y ∈ F(x) within `tol`: the point (x, y) is at most `tol` from the graph.
    /// Exact membership for `tol = 0`; false for NaN inputs.
    fn contains(&self, x: f64, y: f64, tol: f64) -> bool {
        self.graph_distance(x, y) <= tol
    }

    /// The graph of F sampled as a polyline in `window`: see [`sample_graph`].
    ///
    /// # Errors
    /// As [`sample_graph`].
    fn graph(&self, window: &GraphWindow, points: usize) -> Result<Vec<(f64, f64)>, SetValuedError>
    where
        Self: Sized,
    {
        sample_graph(self, window, points)
    }
}

/// The unilateral primitive Upr, the subdifferential of the indicator of ℝ₊:
/// −y ∈ Upr(x) ⇔ 0 ≤ x ⊥ y ≥ 0 (Signorini's law with x = g_N, y = λ_N; Newton's impact law
/// with x = ξ_N, y = P_N).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Upr;

impl Upr {
    /// The proximal map of Upr's potential: the projection onto ℝ₊, max(x, 0); NaN stays NaN.
    ///
    /// −y ∈ Upr(x) holds if and only if x = prox(x − r y) for any r > 0.
    pub fn prox(x: f64) -> f64 {
        if x < 0.0 { 0.0 } else { x }
    }
}

impl SetValuedMap for Upr {
    fn value(&self, x: f64) -> ValueSet {
        if x > 0.0 {
            ValueSet::Point(0.0)
        } else if x == 0.0 {
            ValueSet::Interval { lo: f64::NEG_INFINITY, hi: 0.0 }
        } else {
            ValueSet::Empty
        }
    }

    fn inverse(&self, y: f64) -> ValueSet {
        if y < 0.0 {
            ValueSet::Point(0.0)
        } else if y == 0.0 {
            ValueSet::Interval { lo: 0.0, hi: f64::INFINITY }
        } else {
            ValueSet::Empty
        }
    }

    fn graph_distance(&self, x: f64, y: f64) -> f64 {
        if x.is_nan() || y.is_nan() {
            return f64::NAN;
        }
        // The graph is the vertical ray {0} × (−∞, 0] and the horizontal ray [0, ∞) × {0}.
        let vertical = x.abs().max(y.max(0.0));
        let horizontal = (-x).max(0.0).max(y.abs());
        vertical.min(horizontal)
    }

    fn breakpoints(&self) -> &[f64] {
        &[0.0]
    }
}

/// The set-valued sign scaled by a bound b ≥ 0, b Sgn(x) (the filled-in relay): Coulomb's law
/// reads −λ_T ∈ μλ_N Sgn(γ_T), i.e. −λ_T ∈ F(γ_T) with b = μλ_N.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sgn {
    bound: f64,
}

impl Default for Sgn {
    fn default() -> Self {
        Self::unit()
    }
}

impl Sgn {
    /// The set-valued sign itself, b = 1.
    pub fn unit() -> Self {
        Self { bound: 1.0 }
    }

    /// The relay b Sgn(x) with bound b (e.g. b = μλ_N, in N, or μP_N, in N s).
    ///
    /// # Errors
    /// [`SetValuedError::Bound`] when b is negative or not finite.
    pub fn scaled(bound: f64) -> Result<Self, SetValuedError> {
        if bound >= 0.0 && bound.is_finite() {
            Ok(Self { bound })
        } else {
            Err(SetValuedError::Bound { value: bound })
        }
    }

    /// The relay μλ_N Sgn of Coulomb's law.
    ///
    /// # Errors
    /// [`SetValuedError::Friction`] when μ is negative or not finite (also when λ_N < 0 would
    /// make μλ_N positive), [`SetValuedError::Bound`] when μλ_N is negative or not finite.
    pub fn coulomb(mu: f64, lambda_n: f64) -> Result<Self, SetValuedError> {
        checked_mu(mu)?;
        Self::scaled(mu * lambda_n)
    }

    /// The bound b.
    pub fn bound(&self) -> f64 {
        self.bound
    }

    /// The proximal map of the relay's dual: the projection of λ onto [−b, b]; NaN stays NaN.
    ///
    /// −λ_T ∈ b Sgn(γ_T) holds if and only if λ_T = prox(λ_T − r γ_T) for any r > 0.
    pub fn prox(&self, lambda: f64) -> f64 {
        lambda.clamp(-self.bound, self.bound)
    }
}

impl SetValuedMap for Sgn {
    fn value(&self, x: f64) -> ValueSet {
        let b = self.bound;
        if x > 0.0 {
            ValueSet::Point(b)
        } else if x < 0.0 {
            ValueSet::Point(-b)
        } else if x == 0.0 {
            ValueSet::interval(-b, b)
        } else {
            ValueSet::Empty
        }
    }

    fn inverse(&self, y: f64) -> ValueSet {
        let b = self.bound;
        if b == 0.0 {
            return if y == 0.0 { ValueSet::real_line() } else { ValueSet::Empty };
        }
        if y == b {
            ValueSet::Interval { lo: 0.0, hi: f64::INFINITY }
        } else if y == -b {
            ValueSet::Interval { lo: f64::NEG_INFINITY, hi: 0.0 }
        } else if y.abs() < b {
            ValueSet::Point(0.0)
        } else {
            ValueSet::Empty
        }
    }

    fn graph_distance(&self, x: f64, y: f64) -> f64 {
        if x.is_nan() || y.is_nan() {
            return f64::NAN;
        }
        let b = self.bound;
        // The graph is (−∞, 0] × {−b}, {0} × [−b, b] and [0, ∞) × {b}.
        let left = x.max(0.0).max((y + b).abs());
        let vertical = x.abs().max(ValueSet::interval(-b, b).distance(y));
        let right = (-x).max(0.0).max((y - b).abs());
        left.min(vertical).min(right)
    }

    fn breakpoints(&self) -> &[f64] {
        &[0.0]
    }
}

/// The complementarity 0 ≤ x ⊥ y ≥ 0 within `tol`: |min(x, y)| ≤ tol (the natural-map
/// residual). Equivalent to −y ∈ Upr(x) within `tol` ([`Upr`]'s `contains(x, −y, tol)`);
/// false for NaN inputs.
pub fn complementarity(x: f64, y: f64, tol: f64) -> bool {
    complementarity_residual(x, y) <= tol
}

/// The natural-map residual |min(x, y)| of 0 ≤ x ⊥ y ≥ 0; NaN for NaN inputs.
pub fn complementarity_residual(x: f64, y: f64) -> f64 {
    if x.is_nan() || y.is_nan() { f64::NAN } else { x.min(y).abs() }
}

/// A rectangle of the (x, y) plane in which a graph is sampled.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GraphWindow {
    /// Left edge (units of x). Default `-1.0`.
    pub x_min: f64,
    /// Right edge (units of x), `> x_min`, with a finite width `x_max − x_min`. Default `1.0`.
    pub x_max: f64,
    /// Bottom edge (units of y); the vertical segments of the graph are cut here. Default `-1.0`.
    pub y_min: f64,
    /// Top edge (units of y), `>= y_min`. Default `1.0`.
    pub y_max: f64,
}

impl Default for GraphWindow {
    fn default() -> Self {
        Self { x_min: -1.0, x_max: 1.0, y_min: -1.0, y_max: 1.0 }
    }
}

impl GraphWindow {
    fn validate(&self) -> Result<(), SetValuedError> {
        let edges = [
            ("x_min", self.x_min),
            ("x_max", self.x_max),
            ("y_min", self.y_min),
            ("y_max", self.y_max),
        ];
        for (name, value) in edges {
            if !value.is_finite() {
                return Err(SetValuedError::Window { name, value });
            }
        }
        // The abscissae are x_min + (x_max − x_min) k/(n − 1): the width must be finite too.
        if self.x_max <= self.x_min || !(self.x_max - self.x_min).is_finite() {
            return Err(SetValuedError::Window { name: "x_max", value: self.x_max });
        }
        if self.y_max < self.y_min {
            return Err(SetValuedError::Window { name: "y_max", value: self.y_max });
        }
        Ok(())
    }
}

/// The graph of `map` in `window` as a polyline of points (x, y) for plotting.
///
/// The abscissae are `points` equally spaced values from `x_min` to `x_max` together with the
/// map's breakpoints inside the window. At each abscissa the value set F(x), cut to
/// [`y_min`, `y_max`], adds one point, or both ends of a vertical segment, ordered so that the
/// polyline runs continuously along the graph. Abscissae with an empty value set (Upr for x < 0)
/// add nothing.
///
/// # Errors
/// [`SetValuedError::Window`] for a non-finite or empty window, [`SetValuedError::Samples`]
/// when `points < 2`, [`SetValuedError::TooManySamples`] when the graph of `points` samples
/// cannot be allocated.
pub fn sample_graph<M: SetValuedMap + ?Sized>(
    map: &M,
    window: &GraphWindow,
    points: usize,
) -> Result<Vec<(f64, f64)>, SetValuedError> {
    window.validate()?;
    if points < 2 {
        return Err(SetValuedError::Samples { points });
    }
    let GraphWindow { x_min, x_max, y_min, y_max } = *window;
    let breaks = map.breakpoints().len();
    // The abscissae, the value sets and the polyline, reserved before they are written so that
    // a count beyond memory is an error, not an abort.
    let too_many = || SetValuedError::TooManySamples { points };
    let mut xs: Vec<f64> = Vec::new();
    xs.try_reserve_exact(points.checked_add(breaks).ok_or_else(too_many)?)
        .map_err(|_| too_many())?;
    xs.extend((0..points).map(|k| x_min + (x_max - x_min) * (k as f64) / ((points - 1) as f64)));
    xs.extend(map.breakpoints().iter().copied().filter(|b| (x_min..=x_max).contains(b)));
    xs.sort_by(f64::total_cmp);
    xs.dedup();

    // The value sets cut to the window, as (lo, hi) pairs.
    let mut cut: Vec<Option<(f64, f64)>> = Vec::new();
    cut.try_reserve_exact(xs.len()).map_err(|_| too_many())?;
    cut.extend(xs.iter().map(|&x| {
        let set = map.value(x);
        let (lo, hi) = (set.lower()?.max(y_min), set.upper()?.min(y_max));
        (lo <= hi).then_some((lo, hi))
    }));

    let mut polyline: Vec<(f64, f64)> = Vec::new();
    polyline.try_reserve_exact(xs.len() + 2 * breaks).map_err(|_| too_many())?;
    for (k, (&x, range)) in xs.iter().zip(&cut).enumerate() {
        let Some((lo, hi)) = *range else { continue };
        if lo == hi {
            polyline.push((x, lo));
            continue;
        }
        // Start the vertical segment at the end nearer the previous point, or, for the first
        // point, end it at the end nearer the next one.
        let start_low = match polyline.last() {
            Some(&(_, y_prev)) => (y_prev - lo).abs() <= (y_prev - hi).abs(),
            None => match cut.get(k + 1).copied().flatten() {
                Some((next_lo, next_hi)) => {
                    let y_next = 0.5 * (next_lo + next_hi);
                    (y_next - hi).abs() <= (y_next - lo).abs()
                }
                None => true,
            },
        };
        if start_low {
            polyline.extend([(x, lo), (x, hi)]);
        } else {
            polyline.extend([(x, hi), (x, lo)]);
        }
    }
    Ok(polyline)
}

/// The graph of Signorini's law g_N ≥ 0, λ_N ≥ 0, g_N λ_N = 0 (the corner of the report's
/// Fig 3.2a) as points (g_N, λ_N), sampled from −λ_N ∈ Upr(g_N) for g_N in [−g_max, g_max]
/// and λ_N up to `lambda_max`.
///
/// # Errors
/// [`SetValuedError::Window`] when `g_max` or `lambda_max` is not positive and finite,
/// [`SetValuedError::Samples`] when `points < 2`, [`SetValuedError::TooManySamples`] beyond
/// memory.
pub fn signorini_graph(
    g_max: f64,
    lambda_max: f64,
    points: usize,
) -> Result<Vec<(f64, f64)>, SetValuedError> {
    for (name, value) in [("g_max", g_max), ("lambda_max", lambda_max)] {
        if !(value > 0.0 && value.is_finite()) {
            return Err(SetValuedError::Window { name, value });
        }
    }
    let window = GraphWindow { x_min: -g_max, x_max: g_max, y_min: -lambda_max, y_max: lambda_max };
    Ok(sample_graph(&Upr, &window, points)?.into_iter().map(|(g, y)| (g, 0.0 - y)).collect())
}

/// The graph of Coulomb's law −λ_T ∈ μλ_N Sgn(γ_T) (the filled-in relay of the report's
/// Fig 3.2b) as points (γ_T, λ_T) for γ_T in [`gamma_min`, `gamma_max`]: λ_T = −μλ_N for
/// γ_T > 0, +μλ_N for γ_T < 0 and the vertical step at γ_T = 0.
///
/// # Errors
/// [`SetValuedError::Friction`] when μ is negative or not finite, [`SetValuedError::Bound`]
/// when μλ_N is negative or not finite, [`SetValuedError::Window`] for an empty or non-finite
/// γ_T range, [`SetValuedError::Samples`] when `points < 2`, [`SetValuedError::TooManySamples`]
/// beyond memory.
pub fn coulomb_graph(
    mu: f64,
    lambda_n: f64,
    gamma_min: f64,
    gamma_max: f64,
    points: usize,
) -> Result<Vec<(f64, f64)>, SetValuedError> {
    let relay = Sgn::coulomb(mu, lambda_n)?;
    let b = relay.bound();
    let window = GraphWindow { x_min: gamma_min, x_max: gamma_max, y_min: -b, y_max: b };
    Ok(sample_graph(&relay, &window, points)?.into_iter().map(|(g, y)| (g, 0.0 - y)).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn upr_values_and_inverse() {
        assert_eq!(Upr.value(2.0), ValueSet::Point(0.0));
        assert_eq!(Upr.value(0.0), ValueSet::interval(f64::NEG_INFINITY, 0.0));
        assert_eq!(Upr.value(-1e-300), ValueSet::Empty);
        assert_eq!(Upr.value(f64::NAN), ValueSet::Empty);
        assert_eq!(Upr.inverse(-3.0), ValueSet::Point(0.0));
        assert_eq!(Upr.inverse(0.0), ValueSet::interval(0.0, f64::INFINITY));
        assert_eq!(Upr.inverse(1.0), ValueSet::Empty);
        assert!(Upr.contains(0.0, -5.0, 0.0) && Upr.contains(3.0, 0.0, 0.0));
        assert!(!Upr.contains(3.0, -1.0, 0.5) && Upr.contains(3.0, -1.0, 1.0));
        assert!(!Upr.contains(-0.1, 0.0, 0.05) && Upr.contains(-0.1, 0.0, 0.1));
        assert!(!Upr.contains(f64::NAN, 0.0, 1.0));
        assert_eq!(Upr.graph_distance(3.0, 1.0), 1.0);
        assert_eq!(Upr.graph_distance(1.0, 2.0), 2.0);
        assert_eq!(Upr.graph_distance(-2.0, -3.0), 2.0);
        assert_eq!((Upr::prox(-2.0), Upr::prox(1.5), Upr::prox(0.0)), (0.0, 1.5, 0.0));
        assert!(Upr::prox(f64::NAN).is_nan());
    }

    #[test]
    fn sgn_values_inverse_and_prox() {
        let s = Sgn::scaled(0.6).unwrap();
        assert_eq!(s.value(1.0), ValueSet::Point(0.6));
        assert_eq!(s.value(-1e-9), ValueSet::Point(-0.6));
        assert_eq!(s.value(0.0), ValueSet::interval(-0.6, 0.6));
        assert_eq!(s.inverse(0.6), ValueSet::interval(0.0, f64::INFINITY));
        assert_eq!(s.inverse(-0.6), ValueSet::interval(f64::NEG_INFINITY, 0.0));
        assert_eq!(s.inverse(0.3), ValueSet::Point(0.0));
        assert_eq!(s.inverse(0.7), ValueSet::Empty);
        assert_eq!(Sgn::scaled(0.0).unwrap().inverse(0.0), ValueSet::real_line());
        assert_eq!(Sgn::scaled(0.0).unwrap().value(0.0), ValueSet::Point(0.0));
        assert_eq!(Sgn::unit().value(0.0), ValueSet::interval(-1.0, 1.0));
        assert_eq!((s.prox(2.0), s.prox(-2.0), s.prox(0.25)), (0.6, -0.6, 0.25));
        assert!(
            s.contains(0.0, 0.6, 0.0) && s.contains(2.0, 0.6, 0.0) && !s.contains(2.0, 0.5, 0.05)
        );
        assert_eq!(s.graph_distance(0.1, 0.0), 0.1);
        assert_eq!(s.graph_distance(0.0, 1.0), 0.4);
        assert_eq!(Sgn::scaled(-0.1), Err(SetValuedError::Bound { value: -0.1 }));
        assert!(Sgn::scaled(f64::NAN).is_err() && Sgn::coulomb(0.3, f64::INFINITY).is_err());
        assert_eq!(Sgn::coulomb(0.3, 2.0).unwrap().bound(), 0.3 * 2.0);
    }

    #[test]
    fn a_negative_friction_coefficient_is_refused_whatever_the_normal_force() {
        // μ = −0.3 with λ_N = −2 made the bound μλ_N = 0.6 look valid.
        assert_eq!(Sgn::coulomb(-0.3, -2.0), Err(SetValuedError::Friction { value: -0.3 }));
        assert!(matches!(Sgn::coulomb(f64::NAN, 1.0), Err(SetValuedError::Friction { .. })));
        assert_eq!(Sgn::coulomb(0.3, -2.0), Err(SetValuedError::Bound { value: 0.3 * -2.0 }));
        assert!(!crate::coulomb_holds(-0.3, -2.0, -0.6, 1.0, 0.0));
        assert_eq!(
            coulomb_graph(-0.3, -2.0, -1.0, 1.0, 3),
            Err(SetValuedError::Friction { value: -0.3 })
        );
        // μ = 0 takes any finite λ_N: the bound is zero.
        assert_eq!(Sgn::coulomb(0.0, -2.0).map(|s| s.bound() == 0.0), Ok(true));
    }

    #[test]
    fn complementarity_is_the_natural_map() {
        assert!(complementarity(0.0, 3.0, 0.0) && complementarity(2.0, 0.0, 0.0));
        assert!(!complementarity(1.0, 1.0, 0.5) && !complementarity(-1.0, 0.0, 0.5));
        assert!(complementarity(1e-9, 2.0, 1e-8));
        assert_eq!(complementarity_residual(-0.5, 3.0), 0.5);
        assert!(!complementarity(f64::NAN, 0.0, 1.0));
    }

    #[test]
    fn signorini_graph_is_the_corner() {
        let g = signorini_graph(0.5, 2.0, 5).unwrap();
        // x = −0.5, −0.25 have empty Upr; the corner is (0, 2) → (0, 0), then the gap axis.
        assert_eq!(g, vec![(0.0, 2.0), (0.0, 0.0), (0.25, 0.0), (0.5, 0.0)]);
        assert!(g.iter().all(|p| p.1.is_sign_positive()));
        assert!(g.iter().all(|&(gn, ln)| gn >= 0.0 && ln >= 0.0 && gn * ln == 0.0));
    }

    #[test]
    fn coulomb_graph_has_steps_at_the_friction_bound() {
        // μλ_N = 0.3 · 10 N = 3 N.
        let g = coulomb_graph(0.3, 10.0, -1.0, 1.0, 3).unwrap();
        assert_eq!(g.len(), 4);
        assert_eq!(g[0], (-1.0, 3.0));
        assert_eq!((g[1].0, g[2].0), (0.0, 0.0));
        assert!((g[1].1 - 3.0).abs() < 1e-15 && (g[2].1 + 3.0).abs() < 1e-15);
        assert_eq!(g[3], (1.0, -3.0));
        // A window that does not contain γ_T = 0 gives a constant branch.
        assert_eq!(coulomb_graph(0.3, 10.0, 0.5, 1.0, 2).unwrap(), vec![(0.5, -3.0), (1.0, -3.0)]);
        // The frictionless relay is the γ_T axis.
        assert!(coulomb_graph(0.0, 10.0, -1.0, 1.0, 4).unwrap().iter().all(|p| p.1 == 0.0));
    }

    #[test]
    fn graph_sampling_orders_vertical_segments_continuously() {
        let window = GraphWindow { x_min: -2.0, x_max: 2.0, y_min: -1.5, y_max: 1.5 };
        let g = Sgn::unit().graph(&window, 4).unwrap();
        // Abscissae −2, −2/3, 0, 2/3, 2: the step runs from −1 up to +1.
        let ys: Vec<f64> = g.iter().map(|p| p.1).collect();
        assert_eq!(ys, vec![-1.0, -1.0, -1.0, 1.0, 1.0, 1.0]);
        // Every sampled point lies on the graph.
        assert!(g.iter().all(|&(x, y)| Sgn::unit().contains(x, y, 0.0)));
        // Starting at the breakpoint, Upr's segment ends at 0 where the next point is.
        let g =
            Upr.graph(&GraphWindow { x_min: 0.0, x_max: 1.0, y_min: -1.0, y_max: 1.0 }, 2).unwrap();
        assert_eq!(g, vec![(0.0, -1.0), (0.0, 0.0), (1.0, 0.0)]);
        assert!(matches!(
            Upr.graph(&GraphWindow { x_max: -3.0, ..window }, 4),
            Err(SetValuedError::Window { .. })
        ));
        assert!(matches!(
            Upr.graph(&GraphWindow { y_min: f64::NAN, ..window }, 4),
            Err(SetValuedError::Window { .. })
        ));
        assert_eq!(Upr.graph(&window, 1), Err(SetValuedError::Samples { points: 1 }));
        // A count beyond memory is refused, where collecting it aborted on a capacity overflow.
        assert_eq!(
            Upr.graph(&window, usize::MAX),
            Err(SetValuedError::TooManySamples { points: usize::MAX })
        );
        assert_eq!(
            signorini_graph(1.0, 1.0, usize::MAX / 2),
            Err(SetValuedError::TooManySamples { points: usize::MAX / 2 })
        );
        // A window wider than f64's range: its width overflowed and the abscissae were NaN
        // and +∞.
        let wide = GraphWindow { x_min: -1e308, x_max: 1e308, ..window };
        assert_eq!(
            Upr.graph(&wide, 3),
            Err(SetValuedError::Window { name: "x_max", value: 1e308 })
        );
        let g = Upr.graph(&GraphWindow { x_min: -1e307, x_max: 1e307, ..window }, 3).unwrap();
        assert_eq!(g, vec![(0.0, -1.5), (0.0, 0.0), (1e307, 0.0)]);
        assert!(signorini_graph(0.0, 1.0, 3).is_err());
    }

    #[test]
    fn a_nan_coordinate_has_no_distance_to_the_relay() {
        // One NaN coordinate is enough: f64::max would otherwise drop it and measure the
        // other coordinate alone.
        let s = Sgn::scaled(0.6).unwrap();
        assert!(s.graph_distance(0.0, f64::NAN).is_nan());
        assert!(s.graph_distance(f64::NAN, 0.6).is_nan());
        assert!(!s.contains(0.0, f64::NAN, 1.0) && !s.contains(f64::NAN, 0.6, 1.0));
        assert!(Upr.graph_distance(0.0, f64::NAN).is_nan());
    }

    #[test]
    fn upr_has_its_breakpoint_sampled_between_the_grid_points() {
        assert_eq!(Upr.breakpoints(), &[0.0]);
        // Four points −1, −1/3, 1/3, 1 miss x = 0: the corner comes from the breakpoint.
        let window = GraphWindow { x_min: -1.0, x_max: 1.0, y_min: -2.0, y_max: 2.0 };
        let g = Upr.graph(&window, 4).unwrap();
        let third = -1.0 + 2.0 * 2.0 / 3.0; // x_min + width · k/(n − 1), as sampled
        assert_eq!(g, vec![(0.0, -2.0), (0.0, 0.0), (third, 0.0), (1.0, 0.0)]);
    }

    #[test]
    fn signorini_graph_names_the_rejected_bound() {
        for g_max in [0.0, -1.0, f64::INFINITY, f64::NAN] {
            let err = signorini_graph(g_max, 1.0, 3).unwrap_err();
            assert!(matches!(err, SetValuedError::Window { name: "g_max", .. }), "{err:?}");
        }
        // λ_max = 0 would leave a window of zero height, which sample_graph accepts.
        for lambda_max in [0.0, f64::INFINITY] {
            let err = signorini_graph(1.0, lambda_max, 3).unwrap_err();
            assert_eq!(err, SetValuedError::Window { name: "lambda_max", value: lambda_max });
        }
    }

    /// A maximal monotone map with one step: lo + slope·x for x < 0, [lo, hi] at 0 and
    /// hi + slope·x for x > 0 (slope ≥ 0).
    struct Ramp {
        lo: f64,
        hi: f64,
        slope: f64,
    }

    impl SetValuedMap for Ramp {
        fn value(&self, x: f64) -> ValueSet {
            if x < 0.0 {
                ValueSet::Point(self.lo + self.slope * x)
            } else if x > 0.0 {
                ValueSet::Point(self.hi + self.slope * x)
            } else {
                ValueSet::interval(self.lo, self.hi)
            }
        }

        fn inverse(&self, y: f64) -> ValueSet {
            // Below lo the left branch, above hi the right one (none where a branch is flat);
            // between them the step at 0, reaching along a flat branch at its level.
            let flat = self.slope == 0.0;
            if y < self.lo || y > self.hi {
                let base = if y < self.lo { self.lo } else { self.hi };
                return if flat {
                    ValueSet::Empty
                } else {
                    ValueSet::Point((y - base) / self.slope)
                };
            }
            let left = if flat && y == self.lo { f64::NEG_INFINITY } else { 0.0 };
            let right = if flat && y == self.hi { f64::INFINITY } else { 0.0 };
            ValueSet::interval(left, right)
        }

        fn graph_distance(&self, x: f64, y: f64) -> f64 {
            // The nearest of the two branches (rays from (0, lo) and (0, hi) along
            // (∓1, ∓slope)) and the vertical segment between them.
            let ray = |base: f64, dir: f64| {
                let n = (1.0 + self.slope * self.slope).sqrt();
                let (dx, dy) = (dir / n, dir * self.slope / n);
                let s = (x * dx + (y - base) * dy).max(0.0);
                (x - s * dx).hypot(y - base - s * dy)
            };
            let segment = x.hypot(y - y.clamp(self.lo, self.hi));
            ray(self.lo, -1.0).min(ray(self.hi, 1.0)).min(segment)
        }

        fn breakpoints(&self) -> &[f64] {
            &[0.0]
        }
    }

    #[test]
    fn the_ramp_s_inverse_and_distance_agree_with_its_graph() {
        // The fixture below: the ends of value(x) lie in the graph, so x ∈ inverse(y) and
        // their distance to it is 0; off the graph, distances and inverses in closed form.
        for (lo, hi, slope) in [(-1.0, 0.5, 1.0), (0.9, 1.0, 0.0)] {
            let r = Ramp { lo, hi, slope };
            for x in [-2.0, -0.5, 0.0, 0.5, 2.0] {
                for y in [r.value(x).lower().unwrap(), r.value(x).upper().unwrap()] {
                    assert!(r.inverse(y).contains(x, 0.0), "{lo} {hi} {slope}: {x} {y}");
                    // Zero up to the round-off of projecting onto a sloped branch.
                    let d = r.graph_distance(x, y);
                    assert!(d <= 4.0 * f64::EPSILON * (1.0 + x.abs() + y.abs()), "{x} {y}: {d:e}");
                }
            }
        }
        let r = Ramp { lo: -1.0, hi: 0.5, slope: 1.0 };
        // (0, −3) lies below the step: the nearest point of the graph is (−1, −2) on the left
        // branch y = −1 + x, at √2 (the step's foot (0, −1) is 2 away).
        assert!((r.graph_distance(0.0, -3.0) - 2f64.sqrt()).abs() < 1e-15);
        assert_eq!(r.inverse(-3.0), ValueSet::Point(-2.0));
        let flat = Ramp { lo: 0.9, hi: 1.0, slope: 0.0 };
        assert_eq!(flat.inverse(0.9), ValueSet::interval(f64::NEG_INFINITY, 0.0));
        assert_eq!(flat.inverse(2.0), ValueSet::Empty);
        assert_eq!(flat.graph_distance(0.5, 3.0), 2.0);
    }

    #[test]
    fn vertical_segments_of_steps_and_ramps_run_from_the_lower_end() {
        // Steps above, below and across zero, flat and sloped: after a point on the left
        // branch, and as the first point of a window starting at the step, the segment runs
        // from lo up to hi, where the right branch continues.
        let ramps = [
            (0.9, 1.0, 0.0),
            (-7.0, -5.0, 0.0),
            (2.0, 4.0, 0.0),
            (-1.0, 0.5, 1.0),
            (-10.0, 0.0, 1.0),
            (0.0, 1.0, 1.0),
            (0.0, 4.0, 1.0),
        ];
        for (lo, hi, slope) in ramps {
            let map = Ramp { lo, hi, slope };
            let tall = |x_min| GraphWindow { x_min, x_max: 1.0, y_min: -20.0, y_max: 20.0 };
            assert_eq!(
                sample_graph(&map, &tall(-1.0), 3).unwrap(),
                vec![(-1.0, lo - slope), (0.0, lo), (0.0, hi), (1.0, hi + slope)],
                "{lo} {hi} {slope} from x = -1"
            );
            assert_eq!(
                sample_graph(&map, &tall(0.0), 2).unwrap(),
                vec![(0.0, lo), (0.0, hi), (1.0, hi + slope)],
                "{lo} {hi} {slope} from x = 0"
            );
        }
    }
}
