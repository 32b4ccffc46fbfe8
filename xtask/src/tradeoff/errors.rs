//! Errors of a run against its reference: closed forms, paired and nearest events, sampled
//! series.

use super::*;

/// Largest `|values[k] − reference[k]|` over the first `count` entries of `reference`.
///
/// # Errors
/// When the reference is empty or `values` has fewer entries than are compared (a missed
/// impact, say).
pub fn paired_error(values: &[f64], reference: &[f64], count: usize) -> Result<f64, String> {
    let k = count.min(reference.len());
    if k == 0 {
        return Err("nothing to compare with".to_owned());
    }
    if values.len() < k {
        return Err(format!("{} of the {k} events compared were found", values.len()));
    }
    let worst =
        values[..k].iter().zip(&reference[..k]).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    if worst.is_finite() { Ok(worst) } else { Err("non-finite value".to_owned()) }
}

/// Largest distance from each of the first `count` reference instants to the nearest instant
/// of the run (extra events of the run are not penalised; a missed one is, by its distance to
/// the next).
///
/// # Errors
/// When the reference or the run has no instants.
pub fn nearest_error(values: &[f64], reference: &[f64], count: usize) -> Result<f64, String> {
    let k = count.min(reference.len());
    if k == 0 {
        return Err("nothing to compare with".to_owned());
    }
    if values.is_empty() {
        return Err("no events in the run".to_owned());
    }
    let worst = reference[..k]
        .iter()
        .map(|r| values.iter().map(|v| (v - r).abs()).fold(f64::INFINITY, f64::min))
        .fold(0.0, f64::max);
    if worst.is_finite() { Ok(worst) } else { Err("non-finite value".to_owned()) }
}

/// Largest |pick(run) − pick(reference)| over the reference's samples.
///
/// # Errors
/// When the reference has no samples or the run ended before one of them.
pub fn sampled_error(
    run: &[Sample],
    reference: &[Sample],
    pick: impl Fn(&Sample) -> f64,
) -> Result<f64, String> {
    if reference.is_empty() {
        return Err("the reference has no samples".to_owned());
    }
    if run.len() < reference.len() {
        return Err(format!("the run ended before t = {}", reference[run.len()].t));
    }
    let worst =
        run.iter().zip(reference).map(|(a, b)| (pick(a) - pick(b)).abs()).fold(0.0, f64::max);
    if worst.is_finite() { Ok(worst) } else { Err("non-finite state".to_owned()) }
}

/// Relative error |x − x_ref|/|x_ref|.
///
/// # Errors
/// When x_ref is zero or a value is not finite.
pub fn relative_error(x: f64, x_ref: f64) -> Result<f64, String> {
    let e = ((x - x_ref) / x_ref).abs();
    if e.is_finite() { Ok(e) } else { Err(format!("cannot compare {x} with {x_ref}")) }
}

/// Apex heights R + (ε_N^k v1)²/(2g), k = 1..=count, of the closed-form ball (m).
pub fn ball_apexes(cf: &BallClosedForm, r: f64, count: usize) -> Vec<f64> {
    (1..=count).map(|k| r + (cf.eps_n.powi(k as i32) * cf.v1).powi(2) / (2.0 * cf.g)).collect()
}

/// Errors of a ball run against the closed form, one per [`metrics`] entry.
pub(super) fn ball_errors(params: &ModelParams, obs: &Observation) -> Vec<Result<f64, String>> {
    let ModelParams::Ball(p) = params else {
        return vec![Err("not a ball".to_owned()); 4];
    };
    if p.init.v0 != 0.0 {
        return vec![Err("the closed form needs a drop from rest".to_owned()); 4];
    }
    let cf = BallClosedForm::new(p.init.y0, p.r, p.g, p.eps_n);
    let impacts = obs.impact_instants(&[0], 5.0 * p.g * obs.dt);
    let times = nearest_error(&impacts, &cf.impact_times(EVENTS_COMPARED), EVENTS_COMPARED);
    let apexes =
        paired_error(&obs.apexes, &ball_apexes(&cf, p.r, EVENTS_COMPARED), EVENTS_COMPARED);
    let rest = obs
        .rest_time
        .map(|t| (t - cf.t_inf).abs())
        .ok_or_else(|| "the ball is not at rest by the end of the run".to_owned());
    let before: Vec<&Sample> = obs.samples.iter().filter(|s| s.t + obs.dt < cf.t1).collect();
    let fall = if before.is_empty() {
        Err("no sample before the first impact".to_owned())
    } else {
        Ok(before
            .iter()
            .map(|s| (s.q[0] - (p.init.y0 - 0.5 * p.g * s.t * s.t)).abs())
            .fold(0.0, f64::max))
    };
    vec![times, apexes, rest, fall]
}

/// Errors of a run against a reference run, one per [`metrics`] entry.
pub(super) fn reference_errors(
    kind: ModelKind,
    obs: &Observation,
    r: &Observation,
) -> Vec<Result<f64, String>> {
    let speed = |o: &Observation| 5.0 * o.g.abs() * o.dt;
    let stop_time = |o: &Observation, what: &str| {
        o.crossing.ok_or_else(|| format!("{what} by the end of the run"))
    };
    match kind {
        ModelKind::Woodpecker => {
            let period = |o: &Observation| {
                analysis::limit_cycle(&o.events(speed(o)), 1)
                    .map(|c| c.period)
                    .ok_or_else(|| "no limit cycle found".to_owned())
            };
            vec![
                period(obs).and_then(|t| relative_error(t, period(r)?)),
                nearest_error(
                    &obs.impact_instants(&[0], speed(obs)),
                    &r.impact_instants(&[0], speed(r)),
                    EVENTS_COMPARED,
                ),
                sampled_error(&obs.samples, &r.samples, |s| s.q[0]),
            ]
        }
        ModelKind::SliderCrank => {
            // Corners chatter at a few mm/s while the slider is pressed against the guide:
            // an impact needs at least 2 % of the largest approach speed of the run.
            let impacts = |o: &Observation| {
                let threshold = speed(o).max(0.02 * o.largest_approach());
                o.impact_instants(&[0, 1, 2, 3], threshold)
            };
            let two_revolutions = |o: &Observation| stop_time(o, "θ1 does not reach 4π");
            vec![
                sampled_error(&obs.samples, &r.samples, |s| s.u[0]),
                nearest_error(&impacts(obs), &impacts(r), EVENTS_COMPARED),
                two_revolutions(obs).and_then(|t| Ok((t - two_revolutions(r)?).abs())),
            ]
        }
        ModelKind::SliderCrankIdeal => vec![sampled_error(&obs.samples, &r.samples, |s| s.u[0])],
        ModelKind::Cam => vec![
            sampled_error(&obs.samples, &r.samples, |s| s.q[0]),
            nearest_error(
                &obs.impact_instants(&[0], speed(obs)),
                &r.impact_instants(&[0], speed(r)),
                EVENTS_COMPARED,
            ),
        ],
        ModelKind::Painleve => {
            let flat = |o: &Observation| stop_time(o, "the rod does not lie flat");
            vec![
                flat(obs).and_then(|t| Ok((t - flat(r)?).abs())),
                sampled_error(&obs.samples, &r.samples, |s| s.q[2]),
            ]
        }
        ModelKind::Ball => vec![Err("the ball is compared with its closed form".to_owned()); 4],
        // The study has no metrics for declared mechanisms.
        ModelKind::Declared => Vec::new(),
    }
}
