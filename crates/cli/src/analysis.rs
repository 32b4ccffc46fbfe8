//! Key numbers from recorded runs: impacts, rest times, limit-cycle periods, contact events.
//!
//! The functions take plain per-row arrays (row k = state at `t[k]`; the impulses of row k are
//! those of the step that ends at `t[k]`; row 0 is the initial state), so they can be checked on
//! synthetic records as well as on the stepper's [`moreau_stepper::Record`].
//!
//! # References
//! - Flores, P. (2010). Application of the non-smooth dynamics approach to model and analyze
//!   contact-impact events in rigid multibody systems using the LCP formulation.

use moreau_stepper::ContactState;
use serde::Serialize;

/// What the analysis asks of the stepper's [`ContactState`]: whether the contact carries a
/// normal impulse, and its lower-case name. The stepper's state is the one classification of
/// a contact after a step; the events below are built on it alone.
pub trait ContactStateExt {
    /// Whether the contact carries a normal impulse (stick or slip).
    fn is_closed(&self) -> bool;
    /// Lower-case name: `open`, `stick` or `slip`.
    fn name(&self) -> &'static str;
}

impl ContactStateExt for ContactState {
    fn is_closed(&self) -> bool {
        *self != ContactState::Open
    }

    fn name(&self) -> &'static str {
        match self {
            ContactState::Open => "open",
            ContactState::Stick => "stick",
            ContactState::Slip => "slip",
        }
    }
}

/// What happens at a contact at an event.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EventKind {
    /// The contact closes with an approach velocity γ_N⁻ below −(impact speed): an impact.
    Impact,
    /// The contact closes without a noticeable approach velocity.
    Close,
    /// The contact opens (P_N drops to zero).
    Open,
    /// A closed, slipping contact starts to stick.
    Stick,
    /// A closed, sticking contact starts to slip.
    Slip,
}

impl EventKind {
    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Impact => "impact",
            Self::Close => "close",
            Self::Open => "open",
            Self::Stick => "stick",
            Self::Slip => "slip",
        }
    }
}

/// One contact event.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ContactEvent {
    /// Row of the record at which the event is seen (the end of the step in which it happens).
    pub row: usize,
    /// Time t of that row (s).
    pub t: f64,
    /// Contact number, 1-based as in the report.
    pub contact: usize,
    /// What happens.
    pub kind: EventKind,
    /// The contact's state after the step.
    pub after: ContactState,
}

/// The event, if any, at a contact whose state goes from `before` to `after` in one step
/// that it approached with normal relative velocity γ_N⁻ = `gamma_pre`: an impact when it
/// closes with γ_N⁻ < −`impact_speed`, a soft closing otherwise; opening; stick after slip;
/// slip after stick. This is the one classification of contact events; every analysis uses it.
pub fn classify(
    before: ContactState,
    after: ContactState,
    gamma_pre: f64,
    impact_speed: f64,
) -> Option<EventKind> {
    use ContactState::{Open, Slip, Stick};
    match (before, after) {
        (Open, Open) => None,
        (Open, _) if gamma_pre < -impact_speed => Some(EventKind::Impact),
        (Open, _) => Some(EventKind::Close),
        (_, Open) => Some(EventKind::Open),
        (Slip, Stick) => Some(EventKind::Stick),
        (Stick, Slip) => Some(EventKind::Slip),
        _ => None,
    }
}

/// The contact events of a record.
///
/// `state[k][i]` is contact i's state at row k; `gamma_pre[k][i]` is its normal relative
/// velocity γ_N⁻ at the start of the step that ends at row k (used to tell an impact from a
/// soft closing, see [`classify`]).
pub fn contact_events(
    t: &[f64],
    state: &[Vec<ContactState>],
    gamma_pre: &[Vec<f64>],
    impact_speed: f64,
) -> Vec<ContactEvent> {
    let mut events = Vec::new();
    for k in 1..t.len().min(state.len()) {
        for (i, (&prev, &cur)) in state[k - 1].iter().zip(&state[k]).enumerate() {
            let g = gamma_pre.get(k).and_then(|g| g.get(i)).copied().unwrap_or(0.0);
            if let Some(kind) = classify(prev, cur, g, impact_speed) {
                events.push(ContactEvent { row: k, t: t[k], contact: i + 1, kind, after: cur });
            }
        }
    }
    events
}

/// One impact of the bouncing ball.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Impact {
    /// Row k of the impact step (the step from `t[k−1]` to `t[k]`).
    pub row: usize,
    /// Midpoint time t_M of the impact step (s).
    pub t: f64,
    /// Velocity before the step, v_A (m/s).
    pub v_pre: f64,
    /// Velocity after the step, v_E (m/s).
    pub v_post: f64,
    /// Normal impulse Λ_N of the step (kg m/s).
    pub impulse: f64,
}

/// Impacts of a single-contact record: the first step of every run of steps with P_N > 0.
pub fn impacts(t: &[f64], v: &[f64], p_n: &[f64]) -> Vec<Impact> {
    let n = t.len().min(v.len()).min(p_n.len());
    (1..n)
        .filter(|&k| p_n[k] > 0.0 && p_n[k - 1] <= 0.0)
        .map(|k| Impact {
            row: k,
            t: 0.5 * (t[k - 1] + t[k]),
            v_pre: v[k - 1],
            v_post: v[k],
            impulse: p_n[k],
        })
        .collect()
}

/// The time after which a contact stays closed: the midpoint time of the first step of the
/// final run of steps with P_N > 0, if that run lasts to the end of the record and is at least
/// `min_steps` long; `None` otherwise.
pub fn rest_time(t: &[f64], p_n: &[f64], min_steps: usize) -> Option<f64> {
    let n = t.len().min(p_n.len());
    if n < 2 || p_n[n - 1] <= 0.0 {
        return None;
    }
    let mut k = n - 1;
    while k > 1 && p_n[k - 1] > 0.0 {
        k -= 1;
    }
    if n - k < min_steps.max(1) {
        return None;
    }
    Some(0.5 * (t[k - 1] + t[k]))
}

/// The closed-form bouncing ball (docs/theory.md, section 7.1): impacts at y = R of a ball dropped from
/// y0 at rest, with restitution ε_N.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BallClosedForm {
    /// Drop height H = y0 − R (m).
    pub height: f64,
    /// First impact time t1 = sqrt(2H/g) (s).
    pub t1: f64,
    /// Impact speed v1 = sqrt(2gH) (m/s).
    pub v1: f64,
    /// Accumulation time t_∞ = t1 (1 + ε_N)/(1 − ε_N) (s); infinite for ε_N = 1.
    pub t_inf: f64,
    /// Restitution ε_N.
    pub eps_n: f64,
    /// Gravity g (m/s²).
    pub g: f64,
}

impl BallClosedForm {
    /// The closed form for drop height y0, radius R, gravity g and restitution ε_N.
    pub fn new(y0: f64, r: f64, g: f64, eps_n: f64) -> Self {
        let height = y0 - r;
        let t1 = (2.0 * height / g).sqrt();
        let v1 = (2.0 * g * height).sqrt();
        let t_inf = if eps_n < 1.0 { t1 * (1.0 + eps_n) / (1.0 - eps_n) } else { f64::INFINITY };
        Self { height, t1, v1, t_inf, eps_n, g }
    }

    /// The first `count` impact times t_1, t_2 = t_1 + 2 ε_N v1/g, ... (s).
    pub fn impact_times(&self, count: usize) -> Vec<f64> {
        let mut times = Vec::with_capacity(count);
        let mut t = self.t1;
        let mut speed = self.v1;
        for _ in 0..count {
            times.push(t);
            speed *= self.eps_n;
            t += 2.0 * speed / self.g;
        }
        times
    }
}

/// A periodic pattern of contact events found in a record.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Cycle {
    /// Period T (s), averaged over the periods of the repeating tail.
    pub period: f64,
    /// Marker impacts per period.
    pub markers_per_period: usize,
    /// Number of periods averaged.
    pub periods_averaged: usize,
    /// Whether the event pattern between marker impacts repeats exactly; when `false` the
    /// period is the best-fitting average of marker intervals.
    pub pattern_repeats: bool,
    /// Row and time of the marker impact that starts the last full period.
    pub start_row: usize,
    /// Start time of the last full period (s).
    pub start: f64,
    /// Row of the marker impact that ends the last full period.
    pub end_row: usize,
    /// End time of the last full period (s).
    pub end: f64,
    /// Start time of the averaging window (s).
    pub window_start: f64,
    /// Row at which the averaging window starts.
    pub window_start_row: usize,
}

/// Finds the limit cycle from the impacts of contact `marker` (1-based): the period is the time
/// between marker impacts that start the same pattern of events, averaged over the repeating
/// tail of the record. Tries 1 to 4 marker impacts per period and takes the smallest that
/// repeats at least twice; when none repeats exactly, takes the grouping whose period sums
/// spread least over the last half of the record. `None` with fewer than three marker impacts.
pub fn limit_cycle(events: &[ContactEvent], marker: usize) -> Option<Cycle> {
    let markers: Vec<&ContactEvent> =
        events.iter().filter(|e| e.contact == marker && e.kind == EventKind::Impact).collect();
    let n = markers.len();
    if n < 3 {
        return None;
    }
    // Signature of interval j: the (contact, kind) sequence from marker j up to marker j + 1.
    let signatures: Vec<Vec<(usize, EventKind)>> = (0..n - 1)
        .map(|j| {
            events
                .iter()
                .filter(|e| e.row >= markers[j].row && e.row < markers[j + 1].row)
                .map(|e| (e.contact, e.kind))
                .collect()
        })
        .collect();
    let last = n - 1; // index of the last marker
    let make = |p: usize, periods: usize, repeats: bool| {
        let first = last - p * periods;
        Cycle {
            period: (markers[last].t - markers[first].t) / periods as f64,
            markers_per_period: p,
            periods_averaged: periods,
            pattern_repeats: repeats,
            start_row: markers[last - p].row,
            start: markers[last - p].t,
            end_row: markers[last].row,
            end: markers[last].t,
            window_start: markers[first].t,
            window_start_row: markers[first].row,
        }
    };
    for p in 1..=4usize {
        if signatures.len() < 2 * p {
            break;
        }
        // Smallest j0 with signatures[j] == signatures[j - p] for all j in j0..len.
        let mut j0 = signatures.len();
        while j0 > p && signatures[j0 - 1] == signatures[j0 - 1 - p] {
            j0 -= 1;
        }
        if signatures.len() - j0 >= p {
            // Markers j0 - p ..= last repeat with period p.
            let periods = (last - (j0 - p)) / p;
            return Some(make(p, periods, true));
        }
    }
    // No exact repetition: choose p whose period sums spread least over the last half.
    let mut best: Option<(f64, usize, usize)> = None;
    for p in 1..=4usize {
        let periods = (n - 1) / 2 / p;
        if periods < 2 {
            continue;
        }
        let sums: Vec<f64> =
            (0..periods).map(|k| markers[last - k * p].t - markers[last - (k + 1) * p].t).collect();
        let mean = sums.iter().sum::<f64>() / periods as f64;
        let spread = sums.iter().map(|s| (s - mean).abs()).fold(0.0, f64::max) / mean;
        if best.is_none_or(|(b, _, _)| spread < b - 1e-9) {
            best = Some((spread, p, periods));
        }
    }
    let (_, p, periods) = best.unwrap_or((0.0, 1, n - 1));
    Some(make(p, periods, false))
}

/// Mean rate of change `(y[k1] − y[k0])/(t[k1] − t[k0])` between two rows.
pub fn mean_rate(t: &[f64], y: &[f64], k0: usize, k1: usize) -> Option<f64> {
    let dt = t.get(k1)? - t.get(k0)?;
    (dt != 0.0).then(|| (y[k1] - y[k0]) / dt)
}

/// Rows k (at least 1) in which contact `i` (0-based) is hit: it was open before the step,
/// carries an impulse in it, and approached with γ_N⁻ < −`impact_speed`.
pub fn impact_rows(
    state: &[Vec<ContactState>],
    gamma_pre: &[Vec<f64>],
    i: usize,
    impact_speed: f64,
) -> Vec<usize> {
    (1..state.len())
        .filter(|&k| {
            let g = gamma_pre.get(k).and_then(|g| g.get(i)).copied().unwrap_or(0.0);
            classify(state[k - 1][i], state[k][i], g, impact_speed) == Some(EventKind::Impact)
        })
        .collect()
}

/// Impacts of the slider on the guide counted per step: a step in which one or more corners
/// are hit counts once (corners of one face hit together when the slider is parallel).
pub fn impact_steps(
    state: &[Vec<ContactState>],
    gamma_pre: &[Vec<f64>],
    impact_speed: f64,
) -> Vec<usize> {
    let contacts = state.first().map_or(0, Vec::len);
    let mut rows: Vec<usize> =
        (0..contacts).flat_map(|i| impact_rows(state, gamma_pre, i, impact_speed)).collect();
    rows.sort_unstable();
    rows.dedup();
    rows
}

/// Smallest and largest value of a series (NaN-free input assumed; `None` when empty).
pub fn range(values: impl IntoIterator<Item = f64>) -> Option<(f64, f64)> {
    values.into_iter().fold(None, |acc, v| match acc {
        None => Some((v, v)),
        Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
    })
}

/// What one lobe of the cam does to the follower.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LobeReport {
    /// Lobe number, from 0.
    pub lobe: usize,
    /// Time of the drop that starts the lobe (s).
    pub drop_time: f64,
    /// Impacts in the lobe.
    pub impacts: usize,
    /// Times of the impacts (s).
    pub impact_times: Vec<f64>,
    /// Largest gap g_N after each impact, before the next closing (m).
    pub rebound_heights: Vec<f64>,
    /// Time from the drop to the start of permanent contact (s); `None` if the contact does
    /// not stay closed up to the end of the lobe.
    pub time_to_contact: Option<f64>,
}

/// Splits a single-contact record into lobes of length `period` starting at t = 0 and reports
/// impacts, rebound heights and the time to permanent contact of each complete lobe.
///
/// `gap[k]` is g_N at row k, `gamma_pre[k]` the normal relative velocity before step k.
pub fn cam_lobes(
    t: &[f64],
    gap: &[f64],
    phase: &[ContactState],
    gamma_pre: &[f64],
    period: f64,
    impact_speed: f64,
) -> Vec<LobeReport> {
    let n = t.len().min(gap.len()).min(phase.len()).min(gamma_pre.len());
    if n < 2 || !(period > 0.0) {
        return Vec::new();
    }
    let t_end = t[n - 1];
    let lobes = ((t_end - t[0]) / period + 1e-9).floor() as usize;
    let mid = |k: usize| 0.5 * (t[k - 1] + t[k]);
    let start_of = |lobe: usize| t[0] + lobe as f64 * period;
    let holds =
        |lobe: usize, k: usize| mid(k) >= start_of(lobe) && mid(k) < start_of(lobe) + period;
    // The rows of each lobe that has any, found from each row's own lobe (and its neighbours,
    // for a midpoint on a lobe's boundary up to rounding): the lobes without rows, which a cam
    // turning fast past the record's rows has by the million, are never visited.
    let mut rows_of: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
    for k in 1..n {
        let near = ((mid(k) - t[0]) / period).floor();
        if !(near >= 0.0) {
            continue;
        }
        let near = near as usize;
        for lobe in near.saturating_sub(1)..=near.saturating_add(1) {
            if lobe < lobes && holds(lobe, k) {
                rows_of.entry(lobe).or_default().push(k);
            }
        }
    }
    let mut out = Vec::new();
    for (lobe, rows) in rows_of {
        let start = start_of(lobe);
        let (Some(&first), Some(&last)) = (rows.first(), rows.last()) else { continue };
        let hits: Vec<usize> = rows
            .iter()
            .copied()
            .filter(|&k| {
                classify(phase[k - 1], phase[k], gamma_pre[k], impact_speed)
                    == Some(EventKind::Impact)
            })
            .collect();
        let mut rebound_heights = Vec::new();
        for &h in &hits {
            // Flight after the impact: rows after h until the contact closes again.
            let mut k = h + 1;
            let mut top: f64 = 0.0;
            let mut flew = false;
            while k <= last && !phase[k].is_closed() {
                top = top.max(gap[k]);
                flew = true;
                k += 1;
            }
            if flew {
                rebound_heights.push(top);
            }
        }
        let time_to_contact = if phase[last].is_closed() {
            let mut k = last;
            while k > first && phase[k - 1].is_closed() {
                k -= 1;
            }
            Some(mid(k) - start)
        } else {
            None
        };
        out.push(LobeReport {
            lobe,
            drop_time: start,
            impacts: hits.len(),
            impact_times: hits.iter().map(|&k| mid(k)).collect(),
            rebound_heights,
            time_to_contact,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Exact event-driven bouncing ball sampled on a grid: P_N in the step that contains an
    /// impact, v jumps from −v to ε v.
    fn synthetic_ball(
        dt: f64,
        t_end: f64,
        eps: f64,
    ) -> (Vec<f64>, Vec<f64>, Vec<f64>, BallClosedForm) {
        let cf = BallClosedForm::new(1.0, 0.1, 9.81, eps);
        let times = cf.impact_times(200);
        let steps = (t_end / dt).round() as usize;
        let t: Vec<f64> = (0..=steps).map(|k| k as f64 * dt).collect();
        let mut v = vec![0.0; t.len()];
        let mut p = vec![0.0; t.len()];
        for k in 1..t.len() {
            let (a, b) = (t[k - 1], t[k]);
            if b >= cf.t_inf {
                p[k] = 9.81 * dt;
                v[k] = 0.0;
                continue;
            }
            // Velocity at b: after the last impact before b.
            let last = times.iter().rposition(|&ti| ti <= b);
            v[k] = match last {
                None => -9.81 * b,
                Some(j) => cf.v1 * eps.powi(j as i32 + 1) - 9.81 * (b - times[j]),
            };
            if times.iter().any(|&ti| ti > a && ti <= b) {
                p[k] = v[k] - v[k - 1] + 9.81 * dt;
            }
        }
        (t, v, p, cf)
    }

    #[test]
    fn ball_first_impact_matches_closed_form() {
        let (t, v, p, cf) = synthetic_ball(1e-3, 3.0, 0.7);
        let hits = impacts(&t, &v, &p);
        assert!((hits[0].t - cf.t1).abs() <= 1e-3, "{} vs {}", hits[0].t, cf.t1);
        assert!((hits[0].v_pre + cf.v1).abs() < 0.02);
        assert!((hits[0].v_post - 0.7 * cf.v1).abs() < 0.02);
        assert!((hits[0].impulse - 1.7 * cf.v1).abs() < 0.03);
        let t2 = cf.impact_times(2)[1];
        assert!((hits[1].t - t2).abs() <= 1e-3);
    }

    #[test]
    fn rest_time_is_the_start_of_the_final_closed_run() {
        let (t, _, p, cf) = synthetic_ball(1e-3, 3.0, 0.7);
        let rest = rest_time(&t, &p, 10).expect("rests");
        // Once the flights are shorter than one step every step carries an impulse; the
        // remaining flights then add up to at most dt/(1 − ε_N).
        let bound = 1e-3 / (1.0 - 0.7) + 1e-3;
        assert!(rest <= cf.t_inf + 1e-3 && rest >= cf.t_inf - bound, "{rest} vs {}", cf.t_inf);
        // A record that ends in flight has no rest time.
        assert_eq!(rest_time(&[0.0, 1.0, 2.0], &[0.0, 1.0, 0.0], 1), None);
        // Too short a final run.
        assert_eq!(rest_time(&[0.0, 1.0, 2.0], &[0.0, 0.0, 1.0], 2), None);
    }

    #[test]
    fn closed_form_accumulation_time() {
        let cf = BallClosedForm::new(1.0, 0.1, 9.81, 0.9);
        assert!((cf.t1 - (1.8f64 / 9.81).sqrt()).abs() < 1e-15);
        assert!((cf.t_inf - cf.t1 * 19.0).abs() < 1e-12);
        // The sum of the impact-time series tends to t_inf.
        let times = cf.impact_times(400);
        assert!((times[399] - cf.t_inf).abs() < 1e-9);
        assert!(BallClosedForm::new(1.0, 0.1, 9.81, 1.0).t_inf.is_infinite());
    }

    use ContactState::{Open as O, Slip as L, Stick as S};

    #[test]
    fn events_classify_impacts_and_transitions() {
        let t = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0];
        let phase = vec![vec![O, O], vec![L, O], vec![S, S], vec![L, S], vec![O, O], vec![O, O]];
        let gamma = vec![
            vec![0.0, 0.0],
            vec![-1.0, 0.0],
            vec![0.0, -1e-6],
            vec![0.0; 2],
            vec![0.0; 2],
            vec![0.0; 2],
        ];
        let ev = contact_events(&t, &phase, &gamma, 1e-3);
        let got: Vec<(usize, usize, EventKind)> =
            ev.iter().map(|e| (e.row, e.contact, e.kind)).collect();
        assert_eq!(
            got,
            vec![
                (1, 1, EventKind::Impact),
                (2, 1, EventKind::Stick),
                (2, 2, EventKind::Close),
                (3, 1, EventKind::Slip),
                (4, 1, EventKind::Open),
                (4, 2, EventKind::Open),
            ]
        );
    }

    /// Events of a periodic pattern: every period, contact 1 is hit at offset 0.0, contact 2
    /// closes at 0.3 and opens at 0.6; contact 1 opens at 0.1. An initial transient of
    /// irregular impacts comes first.
    fn periodic_events(period: f64, cycles: usize, doubled: bool) -> Vec<ContactEvent> {
        let mut ev = Vec::new();
        let mut row = 0;
        let mut push = |t: f64, contact: usize, kind: EventKind, ev: &mut Vec<ContactEvent>| {
            row += 1;
            ev.push(ContactEvent { row, t, contact, kind, after: ContactState::Slip });
        };
        push(0.05, 1, EventKind::Impact, &mut ev);
        push(0.07, 3, EventKind::Impact, &mut ev);
        let t0 = 0.2;
        for c in 0..cycles {
            let s = t0 + c as f64 * period;
            push(s, 1, EventKind::Impact, &mut ev);
            push(s + 0.1 * period, 1, EventKind::Open, &mut ev);
            if doubled {
                push(s + 0.2 * period, 1, EventKind::Impact, &mut ev);
                push(s + 0.25 * period, 1, EventKind::Open, &mut ev);
            }
            push(s + 0.3 * period, 2, EventKind::Close, &mut ev);
            push(s + 0.6 * period, 2, EventKind::Open, &mut ev);
        }
        push(t0 + cycles as f64 * period, 1, EventKind::Impact, &mut ev);
        ev
    }

    #[test]
    fn limit_cycle_finds_the_period() {
        let ev = periodic_events(0.11, 8, false);
        let c = limit_cycle(&ev, 1).expect("cycle");
        assert!(c.pattern_repeats);
        assert_eq!(c.markers_per_period, 1);
        assert!((c.period - 0.11).abs() < 1e-12, "{}", c.period);
        assert_eq!(c.periods_averaged, 8);
        assert!((c.end - c.start - 0.11).abs() < 1e-12);
    }

    #[test]
    fn limit_cycle_groups_two_beak_impacts_per_period() {
        let ev = periodic_events(0.1, 6, true);
        let c = limit_cycle(&ev, 1).expect("cycle");
        assert!(c.pattern_repeats);
        assert_eq!(c.markers_per_period, 2);
        assert!((c.period - 0.1).abs() < 1e-12, "{}", c.period);
    }

    #[test]
    fn limit_cycle_needs_three_markers() {
        let ev = periodic_events(0.1, 0, false);
        assert!(limit_cycle(&ev, 1).is_none());
    }

    #[test]
    fn mean_rate_and_range() {
        let t = [0.0, 1.0, 2.0];
        let y = [0.0, -0.5, -1.0];
        assert_eq!(mean_rate(&t, &y, 0, 2), Some(-0.5));
        assert_eq!(mean_rate(&t, &y, 1, 1), None);
        assert_eq!(range([3.0, -1.0, 2.0]), Some((-1.0, 3.0)));
        assert_eq!(range(std::iter::empty()), None);
    }

    #[test]
    fn impact_steps_merge_simultaneous_corners() {
        let phase = vec![vec![O, O], vec![L, L], vec![O, O], vec![O, L]];
        let gamma = vec![vec![0.0; 2], vec![-1.0, -1.0], vec![0.0; 2], vec![0.0, -2.0]];
        assert_eq!(impact_steps(&phase, &gamma, 1e-3), vec![1, 3]);
        assert_eq!(impact_rows(&phase, &gamma, 1, 1e-3), vec![1, 3]);
    }

    #[test]
    fn cam_lobes_count_impacts_and_rebounds() {
        // Lobe period 1 s, dt 0.1 s: contact open until 0.3, impact at row 3 (rebound to gap
        // 0.02), impact at row 6, closed from then on to the end of the lobe.
        let t: Vec<f64> = (0..=10).map(|k| k as f64 * 0.1).collect();
        let phase = vec![O, O, O, S, O, O, S, S, S, S, S];
        let gap = vec![0.1, 0.05, 0.01, 0.0, 0.01, 0.02, 0.0, 0.0, 0.0, 0.0, 0.0];
        let mut gamma = vec![0.0; 11];
        gamma[3] = -2.0;
        gamma[6] = -0.5;
        let lobes = cam_lobes(&t, &gap, &phase, &gamma, 1.0, 1e-3);
        assert_eq!(lobes.len(), 1);
        let l = &lobes[0];
        assert_eq!(l.impacts, 2);
        assert_eq!(l.rebound_heights, vec![0.02]);
        assert!((l.time_to_contact.expect("closes") - 0.55).abs() < 1e-12);
        assert!((l.impact_times[0] - 0.25).abs() < 1e-12);
    }
}
