//! Key numbers of a run, per model: as a JSON object for `summary.json` and the report, and
//! as a fixed list of columns for sweep CSVs.
//!
//! A report model's key numbers are read from the record's rows (impacts and rest times from
//! the velocities and impulses, contact events from the phases, extremes of gaps and speeds),
//! so that they hold for a record of every step only: [`check_thinning`] refuses a thinned
//! one. A declared mechanism's are taken from [`moreau_stepper::Record::impacts`], which lists
//! every impact whatever the thinning, and from the last row, which is the run's last step.

use moreau_models::{AnyModel, ModelKind, ModelParams, Scene};
use moreau_stepper::ContactState;
use serde::Serialize;
use serde_json::{Value, json};

use crate::analysis::{
    self, BallClosedForm, ContactEvent, ContactStateExt, Cycle, EventKind, LobeReport,
};
use crate::error::CliError;
use crate::runs::{RunResult, parameters};

/// Checks that the key numbers of `scene`'s model can be read from its record: a report
/// model's need every step's row (see the module's documentation).
///
/// # Errors
/// [`CliError::KeysNeedEveryRow`] for a report model with `record_every` > 1.
pub fn check_thinning(scene: &Scene) -> Result<(), CliError> {
    let kind = scene.kind();
    if kind != ModelKind::Declared && scene.record_every > 1 {
        return Err(CliError::KeysNeedEveryRow {
            model: kind.name().to_owned(),
            record_every: scene.record_every,
        });
    }
    Ok(())
}

/// Key numbers of a bouncing-ball run, with the closed form for comparison.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct BallKeys {
    /// The first impact as simulated.
    pub first_impact: Option<analysis::Impact>,
    /// Time after which the ball stays in contact (s).
    pub rest_time: Option<f64>,
    /// Number of impacts before the ball rests.
    pub impacts: usize,
    /// The closed-form solution (drop from rest only).
    pub closed_form: Option<BallClosedFormKeys>,
}

/// The closed-form numbers of the bouncing ball.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct BallClosedFormKeys {
    /// First impact time t1 = sqrt(2H/g) (s).
    pub t1: f64,
    /// Velocity before the first impact, −v1 = −sqrt(2gH) (m/s).
    pub v_pre: f64,
    /// Velocity after it, ε_N v1 (m/s).
    pub v_post: f64,
    /// Its impulse, (1 + ε_N) m v1 (kg m/s).
    pub impulse: f64,
    /// Accumulation (rest) time t_∞ = t1 (1 + ε_N)/(1 − ε_N) (s).
    pub t_inf: f64,
}

/// Key numbers of the ball.
pub fn ball(run: &RunResult) -> BallKeys {
    let r = run.record();
    let v = run.u(0);
    let p = run.p_n(0);
    let hits = analysis::impacts(&r.t, &v, &p);
    let rest_time = analysis::rest_time(&r.t, &p, 10);
    let closed_form = match &run.scene.params {
        ModelParams::Ball(b) if b.init.v0 == 0.0 => {
            let cf = BallClosedForm::new(b.init.y0, b.r, b.g, b.eps_n);
            Some(BallClosedFormKeys {
                t1: cf.t1,
                v_pre: -cf.v1,
                v_post: b.eps_n * cf.v1,
                impulse: (1.0 + b.eps_n) * b.m * cf.v1,
                t_inf: cf.t_inf,
            })
        }
        _ => None,
    };
    let impacts = match rest_time {
        Some(t) => hits.iter().filter(|h| h.t < t).count(),
        None => hits.len(),
    };
    BallKeys { first_impact: hits.first().copied(), rest_time, impacts, closed_form }
}

/// One contact event of the woodpecker's cycle, timed from the start of the period.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct CycleEvent {
    /// Time since the beak impact that starts the period (s).
    pub t: f64,
    /// Absolute time (s).
    pub t_abs: f64,
    /// Contact number (1 beak, 2 lower sleeve edge, 3 upper sleeve edge).
    pub contact: usize,
    /// Contact name.
    pub name: String,
    /// What happens (impact, close, open, stick, slip).
    pub what: &'static str,
    /// The contact's state afterwards (open, stick, slip).
    pub after: &'static str,
}

/// Key numbers of the woodpecker.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct WoodpeckerKeys {
    /// The limit cycle, from the beak impacts.
    pub cycle: Option<Cycle>,
    /// Mean descent speed of the sleeve over the averaged periods, −Δy/Δt (m/s, > 0 down).
    pub descent_speed: Option<f64>,
    /// The contact events of the last full period.
    pub events: Vec<CycleEvent>,
}

/// The contact events of a run (all rows).
pub fn events(run: &RunResult) -> Vec<ContactEvent> {
    analysis::contact_events(&run.record().t, &run.states(), &run.gamma_pre(), run.impact_speed())
}

/// Key numbers of the woodpecker: period from the beak (contact 1) impacts, descent speed,
/// and the event sequence of the last period.
pub fn woodpecker(run: &RunResult) -> WoodpeckerKeys {
    let all = events(run);
    let names = run.model().contact_names();
    // The beak is the first listed contact when it is switched on.
    let beak = match &run.scene.params {
        ModelParams::Woodpecker(p) if p.beak_contact => Some(1),
        _ => None,
    };
    let cycle = beak.and_then(|b| analysis::limit_cycle(&all, b));
    let r = run.record();
    let y = run.q(0);
    let descent_speed = cycle
        .as_ref()
        .and_then(|c| analysis::mean_rate(&r.t, &y, c.window_start_row, c.end_row))
        .map(|rate| -rate);
    let events = cycle
        .as_ref()
        .map(|c| {
            all.iter()
                .filter(|e| e.row >= c.start_row && e.row < c.end_row)
                .map(|e| CycleEvent {
                    t: e.t - c.start,
                    t_abs: e.t,
                    contact: e.contact,
                    name: names.get(e.contact - 1).cloned().unwrap_or_default(),
                    what: e.kind.name(),
                    after: e.after.name(),
                })
                .collect()
        })
        .unwrap_or_default();
    WoodpeckerKeys { cycle, descent_speed, events }
}

/// Key numbers of a slider-crank run (clearance joint).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct SliderKeys {
    /// Normal restitution ε_N of the corners.
    pub eps_n: f64,
    /// Crank revolutions simulated, (θ1_end − θ1_0)/2π.
    pub revolutions: f64,
    /// Time the revolutions took (s).
    pub duration: f64,
    /// Impacts of the slider on the guide (steps in which a corner is hit).
    pub impacts: usize,
    /// Impacts per crank revolution.
    pub impacts_per_revolution: f64,
    /// Most negative gap over all corners and rows, relative to the clearance c.
    pub max_penetration_over_c: f64,
    /// Smallest crank speed ω1 (rad/s).
    pub crank_speed_min: f64,
    /// Largest crank speed ω1 (rad/s).
    pub crank_speed_max: f64,
}

/// Key numbers of the slider-crank with clearance.
pub fn slider(run: &RunResult) -> SliderKeys {
    let r = run.record();
    let (eps_n, c) = match &run.scene.params {
        ModelParams::SliderCrank(p) => (p.eps_n, p.c),
        _ => (f64::NAN, f64::NAN),
    };
    let th1 = run.q(0);
    let revolutions = (th1.last().copied().unwrap_or(0.0) - th1.first().copied().unwrap_or(0.0))
        / std::f64::consts::TAU;
    let impacts = analysis::impact_steps(&run.states(), &run.gamma_pre(), run.impact_speed()).len();
    let min_gap = run.gaps().iter().flatten().copied().fold(f64::INFINITY, f64::min);
    let (lo, hi) = analysis::range(run.u(0)).unwrap_or((f64::NAN, f64::NAN));
    SliderKeys {
        eps_n,
        revolutions,
        duration: r.t.last().copied().unwrap_or(0.0),
        impacts,
        impacts_per_revolution: if revolutions > 0.0 {
            impacts as f64 / revolutions
        } else {
            f64::NAN
        },
        max_penetration_over_c: min_gap.min(0.0) / c,
        crank_speed_min: lo,
        crank_speed_max: hi,
    }
}

/// Key numbers of the ideal slider-crank.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct IdealKeys {
    /// Time of the simulated revolutions (s).
    pub duration: f64,
    /// Smallest crank speed ω1 (rad/s).
    pub crank_speed_min: f64,
    /// Largest crank speed ω1 (rad/s).
    pub crank_speed_max: f64,
}

/// Key numbers of the ideal slider-crank.
pub fn ideal(run: &RunResult) -> IdealKeys {
    let (lo, hi) = analysis::range(run.u(0)).unwrap_or((f64::NAN, f64::NAN));
    IdealKeys {
        duration: run.record().t.last().copied().unwrap_or(0.0),
        crank_speed_min: lo,
        crank_speed_max: hi,
    }
}

/// Key numbers of the cam-follower.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct CamKeys {
    /// Duration of one lobe, 2π/(N ω) (s).
    pub lobe_period: f64,
    /// Mean number of impacts per complete lobe.
    pub impacts_per_lobe: f64,
    /// Mean time from a drop to permanent contact (s).
    pub mean_time_to_contact: Option<f64>,
    /// Per lobe: impacts, rebound heights, time to permanent contact.
    pub lobes: Vec<LobeReport>,
}

/// Key numbers of the cam.
pub fn cam(run: &RunResult) -> CamKeys {
    let period = match &run.scene.params {
        ModelParams::Cam(p) => p.lobe_period(),
        _ => f64::NAN,
    };
    let r = run.record();
    let gap: Vec<f64> = run.gaps().iter().map(|g| g[0]).collect();
    let phase: Vec<_> = run.states().iter().map(|p| p[0]).collect();
    let gamma: Vec<f64> = run.gamma_pre().iter().map(|g| g[0]).collect();
    let lobes = analysis::cam_lobes(&r.t, &gap, &phase, &gamma, period, run.impact_speed());
    let impacts_per_lobe = if lobes.is_empty() {
        f64::NAN
    } else {
        lobes.iter().map(|l| l.impacts as f64).sum::<f64>() / lobes.len() as f64
    };
    let times: Vec<f64> = lobes.iter().filter_map(|l| l.time_to_contact).collect();
    let mean_time_to_contact =
        (!times.is_empty()).then(|| times.iter().sum::<f64>() / times.len() as f64);
    CamKeys { lobe_period: period, impacts_per_lobe, mean_time_to_contact, lobes }
}

/// Key numbers of the Painlevé rod.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct PainleveKeys {
    /// Final x of the centre (m).
    pub x_end: f64,
    /// Final angle φ (rad).
    pub phi_end: f64,
    /// First time the end sticks (s).
    pub first_stick_time: Option<f64>,
    /// First time the end leaves the ground after touching it (s).
    pub lift_off_time: Option<f64>,
}

/// Key numbers of the Painlevé rod.
pub fn painleve(run: &RunResult) -> PainleveKeys {
    let r = run.record();
    let phases = run.states();
    let first_stick_time = phases.iter().position(|p| p[0] == ContactState::Stick).map(|k| r.t[k]);
    let lift_off_time = (1..phases.len())
        .find(|&k| {
            analysis::classify(phases[k - 1][0], phases[k][0], 0.0, 0.0) == Some(EventKind::Open)
        })
        .map(|k| r.t[k]);
    PainleveKeys {
        x_end: r.q.last().map_or(f64::NAN, |q| q[0]),
        phi_end: r.q.last().map_or(f64::NAN, |q| q[2]),
        first_stick_time,
        lift_off_time,
    }
}

/// The first hard impact of a contact of a declared mechanism.
#[derive(Clone, Copy, Debug, Serialize, PartialEq)]
pub struct FirstImpact {
    /// Midpoint time t_M = t_E − Δt/2 of the impact step (s), the instant its impulse acts
    /// at, as the report's models give their impacts (the ball's 0.4285 s at Δt = 1e-3 s).
    pub t: f64,
    /// Normal relative velocity before the impact, γ_N⁻ < 0 (m/s).
    pub gamma_pre: f64,
    /// Normal relative velocity after it, γ_N⁺ (m/s); −ε_N γ_N⁻ for a lone frictionless
    /// contact.
    pub gamma_post: f64,
    /// Its normal impulse P_N (N s).
    pub p_n: f64,
}

/// Key numbers of one contact of a declared mechanism.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ContactKeys {
    /// The contact's name.
    pub name: String,
    /// Hard impacts: closings with γ_N⁻ below −[`RunResult::impact_speed`] (softer
    /// closings are the scheme's way of coming to rest, not impacts).
    pub impacts: usize,
    /// The first hard impact.
    pub first_impact: Option<FirstImpact>,
}

/// Key numbers of a declared mechanism: per contact, the energy at the end and the energy the
/// impulses removed, and the final state.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct DeclaredKeys {
    /// The contacts, in the order of the contact list.
    pub contacts: Vec<ContactKeys>,
    /// Total energy T + V at the last row (J).
    pub energy_end: f64,
    /// Energy removed by the impulses of contacts and joints over the run (J): the last row's
    /// `cumulative_dissipation` of the record.
    pub dissipated: f64,
    /// Energy the position projection added over the run (J): the last row's
    /// `cumulative_projection` of the record; 0 without the projection.
    pub projected: f64,
    /// The coordinates q at the last row, by name.
    pub q_end: Vec<(String, f64)>,
}

/// Key numbers of a declared mechanism.
pub fn declared(run: &RunResult) -> DeclaredKeys {
    let r = run.record();
    let model = run.model();
    let threshold = run.impact_speed();
    let contacts = model
        .contact_names()
        .into_iter()
        .enumerate()
        .map(|(i, name)| {
            let mut hard = r.impacts_at(i).filter(|h| h.gamma_n_before < -threshold);
            let first_impact = hard.next().map(|h| FirstImpact {
                t: h.t - 0.5 * run.scene.dt,
                gamma_pre: h.gamma_n_before,
                gamma_post: h.gamma_n_after,
                p_n: h.p_n,
            });
            let impacts = first_impact.map_or(0, |_| 1 + hard.count());
            ContactKeys { name, impacts, first_impact }
        })
        .collect();
    let last = r.len().saturating_sub(1);
    let energy_end = r.kinetic.get(last).copied().unwrap_or(f64::NAN)
        + r.potential.get(last).copied().unwrap_or(0.0);
    let q_end = match r.q.last() {
        Some(q) => {
            model.coordinate_names().iter().map(str::to_owned).zip(q.iter().copied()).collect()
        }
        None => Vec::new(),
    };
    DeclaredKeys {
        contacts,
        energy_end,
        dissipated: r.cumulative_dissipation.last().copied().unwrap_or(0.0),
        projected: r.cumulative_projection.last().copied().unwrap_or(0.0),
        q_end,
    }
}

/// Names of the key-number columns of a sweep over a declared mechanism: for each contact
/// `<contact>.impacts`, `<contact>.first_impact_t`, `<contact>.first_impact_gamma_pre`,
/// `<contact>.first_impact_gamma_post` and `<contact>.first_impact_p_n`; then `energy_end`,
/// `dissipated`, `projected`, and `<coordinate>.end` for each coordinate (`bob.x.end`, ...).
pub fn declared_columns(model: &AnyModel) -> Vec<String> {
    let mut out = Vec::new();
    for c in model.contact_names() {
        for k in [
            "impacts",
            "first_impact_t",
            "first_impact_gamma_pre",
            "first_impact_gamma_post",
            "first_impact_p_n",
        ] {
            out.push(format!("{c}.{k}"));
        }
    }
    out.extend(["energy_end", "dissipated", "projected"].map(str::to_owned));
    out.extend(model.coordinate_names().iter().map(|q| format!("{q}.end")));
    out
}

/// The key-number columns of a sweep over `model`: [`columns`] of its kind for a report
/// model, [`declared_columns`] for a declared mechanism.
pub fn columns_of(model: &AnyModel) -> Vec<String> {
    match model.kind() {
        ModelKind::Declared => declared_columns(model),
        kind => columns(kind).iter().map(|s| (*s).to_owned()).collect(),
    }
}

fn declared_row(run: &RunResult) -> Vec<Option<f64>> {
    let k = declared(run);
    let mut out = Vec::new();
    for c in &k.contacts {
        let f = c.first_impact;
        out.push(Some(c.impacts as f64));
        out.extend([
            f.map(|i| i.t),
            f.map(|i| i.gamma_pre),
            f.map(|i| i.gamma_post),
            f.map(|i| i.p_n),
        ]);
    }
    out.extend([Some(k.energy_end), Some(k.dissipated), Some(k.projected)]);
    out.extend(k.q_end.iter().map(|(_, x)| Some(*x)));
    out
}

/// The key numbers of a run as JSON, with the run's name, Δt and parameters.
pub fn summary(run: &RunResult) -> Value {
    let numbers = match run.spec.kind {
        ModelKind::Ball => json!(ball(run)),
        ModelKind::Woodpecker => json!(woodpecker(run)),
        ModelKind::SliderCrank => json!(slider(run)),
        ModelKind::SliderCrankIdeal => json!(ideal(run)),
        ModelKind::Cam => json!(cam(run)),
        ModelKind::Painleve => json!(painleve(run)),
        ModelKind::Declared => json!(declared(run)),
    };
    let params: serde_json::Map<String, Value> =
        parameters(&run.scene).into_iter().map(|(k, v)| (k, Value::String(v))).collect();
    json!({
        "run": run.spec.name,
        "model": run.spec.kind.name(),
        "dt": run.scene.dt,
        "solver": run.scene.solver.name(),
        "parameters": params,
        "key_numbers": numbers,
    })
}

/// Names of the key-number columns of a sweep over the report model `kind` (none for
/// [`ModelKind::Declared`], whose columns depend on the scene: see [`declared_columns`]).
pub fn columns(kind: ModelKind) -> &'static [&'static str] {
    match kind {
        ModelKind::Ball => &[
            "first_impact_t",
            "first_impact_v_pre",
            "first_impact_v_post",
            "first_impact_impulse",
            "rest_time",
            "t1_closed_form",
            "t_inf_closed_form",
        ],
        ModelKind::Woodpecker => &["period", "descent_speed", "beak_impacts_per_period"],
        ModelKind::SliderCrank => &[
            "impacts",
            "impacts_per_revolution",
            "max_penetration_over_c",
            "crank_speed_min",
            "crank_speed_max",
            "duration",
        ],
        ModelKind::SliderCrankIdeal => &["crank_speed_min", "crank_speed_max", "duration"],
        ModelKind::Cam => {
            &["impacts", "impacts_per_lobe", "first_rebound_height", "mean_time_to_contact"]
        }
        ModelKind::Painleve => &["x_end", "phi_end", "first_stick_time", "lift_off_time"],
        ModelKind::Declared => &[],
    }
}

/// The key numbers of a run in the order of [`columns_of`] its model (`None` when not
/// defined).
pub fn row(run: &RunResult) -> Vec<Option<f64>> {
    match run.spec.kind {
        ModelKind::Ball => {
            let k = ball(run);
            let fi = k.first_impact;
            vec![
                fi.map(|i| i.t),
                fi.map(|i| i.v_pre),
                fi.map(|i| i.v_post),
                fi.map(|i| i.impulse),
                k.rest_time,
                k.closed_form.as_ref().map(|c| c.t1),
                k.closed_form.as_ref().map(|c| c.t_inf),
            ]
        }
        ModelKind::Woodpecker => {
            let k = woodpecker(run);
            vec![
                k.cycle.as_ref().map(|c| c.period),
                k.descent_speed,
                k.cycle.as_ref().map(|c| c.markers_per_period as f64),
            ]
        }
        ModelKind::SliderCrank => {
            let k = slider(run);
            vec![
                Some(k.impacts as f64),
                Some(k.impacts_per_revolution),
                Some(k.max_penetration_over_c),
                Some(k.crank_speed_min),
                Some(k.crank_speed_max),
                Some(k.duration),
            ]
        }
        ModelKind::SliderCrankIdeal => {
            let k = ideal(run);
            vec![Some(k.crank_speed_min), Some(k.crank_speed_max), Some(k.duration)]
        }
        ModelKind::Cam => {
            let k = cam(run);
            let total: usize = k.lobes.iter().map(|l| l.impacts).sum();
            vec![
                Some(total as f64),
                Some(k.impacts_per_lobe),
                k.lobes.first().and_then(|l| l.rebound_heights.first().copied()),
                k.mean_time_to_contact,
            ]
        }
        ModelKind::Painleve => {
            let k = painleve(run);
            vec![Some(k.x_end), Some(k.phi_end), k.first_stick_time, k.lift_off_time]
        }
        ModelKind::Declared => declared_row(run),
    }
}
