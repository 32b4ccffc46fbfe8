//! The checks of a driven body's motion at build time.
//!
//! The contacts and joints with a driven body carry the rheonomic terms ŵ = ∂g/∂t, computed
//! from the velocity and angular velocity the motion states, while the gaps come from its
//! pose. Both are right only when the pose is continuous in time and the stated rates are its
//! derivatives: a pose that jumps, or a velocity that is not the pose's rate, gives impulses
//! from a ŵ that does not describe how the gaps change.
//!
//! The closed forms (`rotate`, `oscillate`, `linear`) are continuous by construction, with
//! their rates the exact derivatives of their poses; their parameters need only be finite.
//! A closure ([`Motion::Custom`]) can be anything, so the build checks it over
//! [0, 10 s], naming the component of [`super::DrivenState`] at fault: its values finite at
//! t = 0, 0.01, ..., 10 s, and the pose's change over each interval between them equal to
//! the integral of the rate by Simpson's rule (the rate at the interval's ends and
//! midpoint). Where they differ the interval is halved, as adaptive quadrature does, until
//! they agree; an interval of 1e-8 s that still disagrees is refused when the change lies
//! outside its width times the range of those rates: a jump of the pose, or a rate that is
//! not its derivative. A kink (a rate that jumps, an impulsive drive) stays within that range
//! and passes. The closed forms are sampled for finite values only, so that parameters that
//! overflow are refused too.

use super::spec::Motion;
use crate::ModelError;
use crate::params::{finite, relation};

/// The spacing of the times at which the build samples a motion (s).
const CHECK_STEP: f64 = 0.01;

/// The last time at which the build samples a motion (s): it samples 0, 0.01, ..., 10 s.
const CHECK_END: f64 = 10.0;

/// The width (s) below which an interval whose pose's change disagrees with its rates is not
/// halved again but refused.
const MIN_WIDTH: f64 = 1e-8;

/// How far, relative to the interval's width times the largest rate sampled in it, the pose's
/// change may differ from what the sampled rates give.
const RTOL: f64 = 1e-4;

/// How far, relative to the largest magnitude of the coordinate at the sampled times (1 rad
/// at least for θ), the pose's change may differ from what the sampled rates give: the
/// round-off of the closure's arithmetic, not a jump.
const ATOL: f64 = 1e-12;

/// The most evaluations of a closure that the check of its rates makes; a motion so fast
/// that it needs more is checked up to where they run out.
const BUDGET: usize = 1_000_000;

/// A sampled state: time, pose [x, y, θ] and rates [ẋ, ẏ, θ̇].
type Sample = (f64, [f64; 3], [f64; 3]);

/// Checks a driven body's motion at the reference pose `pose0`; `field` is its `--set` path
/// (`bodies.<name>.motion`).
///
/// # Errors
/// [`ModelError::InvalidParameter`] naming `<field>.<parameter>` for a closed form's parameter
/// that is not finite, `<field>.pose.<k>`, `<field>.velocity.<k>` or `<field>.omega` for a
/// state that is not finite at a sampled time, and `<field>.velocity.<k>` or `<field>.omega`
/// for a closure whose rate disagrees with its pose (a jump, or a rate that is not the
/// pose's derivative).
pub(crate) fn check_motion(
    field: &str,
    motion: &Motion,
    pose0: [f64; 3],
) -> Result<(), ModelError> {
    let f = |s: &str| format!("{field}.{s}");
    let finite2 = |name: &str, v: [f64; 2]| {
        finite(&format!("{}.0", f(name)), v[0])?;
        finite(&format!("{}.1", f(name)), v[1])
    };
    match motion {
        Motion::Rotate { pivot, omega, phase } => {
            finite2("pivot", *pivot)?;
            finite(&f("omega"), *omega)?;
            finite(&f("phase"), *phase)?;
        }
        Motion::Oscillate { amplitude, omega, phase } => {
            finite2("amplitude", *amplitude)?;
            finite(&f("omega"), *omega)?;
            finite2("phase", *phase)?;
        }
        Motion::Linear { velocity, omega } => {
            finite2("velocity", *velocity)?;
            finite(&f("omega"), *omega)?;
        }
        Motion::Custom(_) => {}
    }
    let n = (CHECK_END / CHECK_STEP).round() as usize;
    let grid = (0..=n)
        .map(|k| sample(field, motion, pose0, k as f64 * CHECK_STEP))
        .collect::<Result<Vec<_>, _>>()?;
    if !matches!(motion, Motion::Custom(_)) {
        return Ok(());
    }
    let mut scale = [0.0, 0.0, 1.0f64];
    for (_, pose, _) in &grid {
        for (s, p) in scale.iter_mut().zip(pose) {
            *s = s.max(p.abs());
        }
    }
    let check = Check { field, motion, pose0, atol: scale.map(|s| ATOL * s) };
    let mut budget = BUDGET;
    grid.windows(2).try_for_each(|w| check.interval(w[0], w[1], &mut budget))
}

/// The state at t, refusing a value that is not finite.
fn sample(field: &str, motion: &Motion, pose0: [f64; 3], t: f64) -> Result<Sample, ModelError> {
    let s = motion.state(pose0, t);
    let rates = [s.velocity[0], s.velocity[1], s.omega];
    let names = ["pose.0", "pose.1", "pose.2", "velocity.0", "velocity.1", "omega"];
    for (name, value) in names.iter().zip(s.pose.iter().chain(&rates)) {
        if !value.is_finite() {
            return Err(relation(
                &format!("{field}.{name}"),
                *value,
                &format!("the motion's state at t = {t:e} s must be finite"),
            ));
        }
    }
    Ok((t, s.pose, rates))
}

/// The check of a closure's rates against its pose.
struct Check<'a> {
    field: &'a str,
    motion: &'a Motion,
    pose0: [f64; 3],
    /// The absolute tolerance of each coordinate's change (m, m, rad).
    atol: [f64; 3],
}

impl Check<'_> {
    /// Checks the interval from `a` to `b`: it passes where each coordinate's change agrees
    /// with Simpson's rule on the rates at its ends and midpoint; elsewhere it is halved, and
    /// below [`MIN_WIDTH`] it is refused where the change lies outside the interval's width
    /// times the range of those rates, which a kink (a rate that jumps) does not leave.
    fn interval(&self, a: Sample, b: Sample, budget: &mut usize) -> Result<(), ModelError> {
        if *budget == 0 {
            return Ok(());
        }
        *budget -= 1;
        let width = b.0 - a.0;
        let m = sample(self.field, self.motion, self.pose0, a.0 + 0.5 * width)?;
        let tolerance = |i: usize, rates: &[f64; 3]| {
            RTOL * width * rates.iter().fold(0.0f64, |r, v| r.max(v.abs())) + self.atol[i]
        };
        let agrees = (0..3).all(|i| {
            let rates = [a.2[i], m.2[i], b.2[i]];
            let simpson = width * (rates[0] + 4.0 * rates[1] + rates[2]) / 6.0;
            (b.1[i] - a.1[i] - simpson).abs() <= tolerance(i, &rates)
        });
        if agrees {
            return Ok(());
        }
        if width > MIN_WIDTH {
            self.interval(a, m, budget)?;
            return self.interval(m, b, budget);
        }
        let outside = (0..3).find_map(|i| {
            let change = b.1[i] - a.1[i];
            let rates = [a.2[i], m.2[i], b.2[i]];
            let lo = width * rates.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = width * rates.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let tol = tolerance(i, &rates);
            (change < lo - tol || change > hi + tol).then_some((i, change, lo, hi))
        });
        let Some((i, change, lo, hi)) = outside else { return Ok(()) };
        let (name, coordinate, unit) =
            [("velocity.0", "x", "m"), ("velocity.1", "y", "m"), ("omega", "θ", "rad")][i];
        Err(relation(
            &format!("{}.{name}", self.field),
            m.2[i],
            &format!(
                "from t = {:e} s to {:e} s the pose's {coordinate} changes by {change:e} \
                 {unit}, but the stated rate gives between {lo:e} and {hi:e}: the motion \
                 must be continuous with this as its pose's derivative (a jump, a wrapped \
                 angle or a rate in other units is refused)",
                a.0, b.0
            ),
        ))
    }
}
