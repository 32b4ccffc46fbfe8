//! One run of a study: the probe that observes it step by step, and what it measured.

use super::*;

/// The state at one sample time, interpolated linearly between the ends of the step that
/// contains it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Sample {
    /// Sample time (s).
    pub t: f64,
    /// Coordinates q.
    pub q: Vec<f64>,
    /// Velocities u.
    pub u: Vec<f64>,
}

/// A change of a contact's state at the end of a step.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Transition {
    /// Step number, from 1 (the row of a full record).
    pub row: usize,
    /// End time of the step (s).
    pub t: f64,
    /// Contact index, from 0.
    pub contact: usize,
    /// State before the step.
    pub from: ContactState,
    /// State after the step.
    pub to: ContactState,
    /// Normal relative velocity γ_N⁻ = w_Nᵀ u_A + ŵ_N at the start of the step (m/s); only
    /// computed when the contact closes, zero otherwise.
    pub gamma_pre: f64,
}

/// What a run leaves for the error measures.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Observation {
    /// Step Δt (s).
    pub dt: f64,
    /// The scene's gravitational acceleration g (m/s²), for the impact threshold 5 g Δt.
    pub g: f64,
    /// Time reached (s).
    pub t_end: f64,
    /// Whether the scene's stop rule ended the run before its end time.
    pub stopped_early: bool,
    /// States at the sample times reached.
    pub samples: Vec<Sample>,
    /// Contact state changes.
    pub transitions: Vec<Transition>,
    /// Largest `q[0]` in each flight between closings of contact 0 (the ball's apexes).
    pub apexes: Vec<f64>,
    /// Midpoint time of the first step of the final run of steps with P_N > 0 at contact 0,
    /// if that run lasts at least 10 steps to the end (the ball's rest time, s).
    pub rest_time: Option<f64>,
    /// When the scene's stop rule was met: the time at which its coordinate crosses the
    /// stop value, interpolated linearly within the step (s).
    pub crossing: Option<f64>,
    /// Largest |q_i| or |u_i| over the run.
    pub max_state: f64,
}

impl Observation {
    /// Contact events (analysis' classification): a closing is an impact when
    /// γ_N⁻ < −`impact_speed`.
    pub fn events(&self, impact_speed: f64) -> Vec<ContactEvent> {
        self.transitions
            .iter()
            .filter_map(|tr| {
                let kind = analysis::classify(tr.from, tr.to, tr.gamma_pre, impact_speed)?;
                Some(ContactEvent {
                    row: tr.row,
                    t: tr.t,
                    contact: tr.contact + 1,
                    kind,
                    after: tr.to,
                })
            })
            .collect()
    }

    /// Midpoint times of the steps in which one of `contacts` closes with γ_N⁻ <
    /// −`impact_speed` (several contacts hit in one step count once).
    pub fn impact_instants(&self, contacts: &[usize], impact_speed: f64) -> Vec<f64> {
        let mut rows: Vec<(usize, f64)> = self
            .transitions
            .iter()
            .filter(|tr| {
                contacts.contains(&tr.contact)
                    && analysis::classify(tr.from, tr.to, tr.gamma_pre, impact_speed)
                        == Some(EventKind::Impact)
            })
            .map(|tr| (tr.row, tr.t - 0.5 * self.dt))
            .collect();
        rows.dedup_by_key(|r| r.0);
        rows.into_iter().map(|r| r.1).collect()
    }

    /// Whether the state left every physical bound (|q| or |u| above 1e6).
    pub fn diverged(&self) -> bool {
        !(self.max_state <= DIVERGED)
    }

    /// Largest approach speed −γ_N⁻ of any closing (m/s).
    pub fn largest_approach(&self) -> f64 {
        self.transitions
            .iter()
            .filter(|tr| !tr.from.is_closed() && tr.to.is_closed())
            .map(|tr| -tr.gamma_pre)
            .fold(0.0, f64::max)
    }
}

/// The streaming observer of a run.
struct Probe {
    dt: f64,
    sample_times: Vec<f64>,
    track_apexes: bool,
    obs: Observation,
    steps: u64,
    lcp_solves: u64,
    prev_t: f64,
    prev_q: Vec<f64>,
    prev_u: Vec<f64>,
    prev_phase: Vec<ContactState>,
    w_n: Vec<f64>,
    w_t: Vec<f64>,
    flight_top: Option<f64>,
    closed_run: Option<(f64, usize)>,
    stop: Option<(usize, f64)>,
}

impl Probe {
    fn new(scene: &Scene, model: &AnyModel, sample_times: &[f64]) -> Self {
        let (q, u) = model.initial_state();
        let dt = scene.dt;
        let stop = scene.stop_at.as_ref().and_then(|s| {
            let index = scene.kind().coordinate_names().iter().position(|n| *n == s.coordinate)?;
            Some((index, s.value))
        });
        let f = q.len();
        Self {
            dt,
            sample_times: sample_times.to_vec(),
            track_apexes: scene.kind() == ModelKind::Ball,
            obs: Observation { dt, g: crate::runs::gravity(scene), ..Observation::default() },
            steps: 0,
            lcp_solves: 0,
            prev_t: 0.0,
            prev_q: q,
            prev_u: u,
            prev_phase: vec![ContactState::Open; model.num_contacts()],
            w_n: vec![0.0; f],
            w_t: vec![0.0; f],
            flight_top: None,
            closed_run: None,
            stop,
        }
    }

    fn finish(mut self, t_end: f64, stopped_early: bool) -> Observation {
        self.obs.t_end = t_end;
        self.obs.stopped_early = stopped_early;
        self.obs.rest_time = self.closed_run.filter(|(_, n)| *n >= 10).map(|(t, _)| t);
        if !stopped_early {
            self.obs.crossing = None;
        }
        self.obs
    }
}

impl Observer<AnyModel> for Probe {
    fn observe(&mut self, model: &AnyModel, r: &StepReport<'_>) -> ControlFlow<()> {
        self.steps += 1;
        if r.lcp.is_some_and(|l| l.method != Method::Trivial) {
            self.lcp_solves += 1;
        }
        let row = self.steps as usize;
        for x in r.q.iter().chain(r.u) {
            self.obs.max_state = self.obs.max_state.max(x.abs());
        }
        if let Some((i, value)) = self.stop {
            let (a, b) = (self.prev_q[i] - value, r.q[i] - value);
            if self.obs.crossing.is_none() && a != 0.0 && (a < 0.0) != (b < 0.0) {
                self.obs.crossing = Some(self.prev_t + (r.t - self.prev_t) * a / (a - b));
            }
        }
        while let Some(&ts) = self.sample_times.get(self.obs.samples.len()) {
            if ts > r.t {
                break;
            }
            let span = r.t - self.prev_t;
            let w = if span > 0.0 { ((ts - self.prev_t) / span).clamp(0.0, 1.0) } else { 1.0 };
            let mix = |a: &[f64], b: &[f64]| -> Vec<f64> {
                a.iter().zip(b).map(|(a, b)| a + w * (b - a)).collect()
            };
            let sample = Sample { t: ts, q: mix(&self.prev_q, r.q), u: mix(&self.prev_u, r.u) };
            self.obs.samples.push(sample);
        }
        for (i, c) in r.contacts.iter().enumerate() {
            let phase = c.state;
            let before = self.prev_phase[i];
            if phase == before {
                continue;
            }
            let gamma_pre = if !before.is_closed() && phase.is_closed() {
                let point =
                    model.contact(i, &self.prev_q, self.prev_t, &mut self.w_n, &mut self.w_t);
                self.w_n.iter().zip(&self.prev_u).map(|(a, b)| a * b).sum::<f64>() + point.w_n_hat
            } else {
                0.0
            };
            self.obs.transitions.push(Transition {
                row,
                t: r.t,
                contact: i,
                from: before,
                to: phase,
                gamma_pre,
            });
            self.prev_phase[i] = phase;
            if i == 0
                && self.track_apexes
                && !before.is_closed()
                && let Some(top) = self.flight_top.take()
            {
                self.obs.apexes.push(top);
            }
        }
        if let Some(c) = r.contacts.first() {
            if self.track_apexes && c.state == ContactState::Open && !r.q.is_empty() {
                if let Some(top) = self.flight_top.as_mut() {
                    *top = top.max(r.q[0]);
                } else if !self.obs.transitions.is_empty() {
                    self.flight_top = Some(r.q[0]);
                }
            }
            self.closed_run = if c.p_n > 0.0 {
                match self.closed_run {
                    Some((t, n)) => Some((t, n + 1)),
                    None => Some((r.t - 0.5 * self.dt, 1)),
                }
            } else {
                None
            };
        }
        self.prev_t = r.t;
        self.prev_q.copy_from_slice(r.q);
        self.prev_u.copy_from_slice(r.u);
        ControlFlow::Continue(())
    }
}

/// One run of the study: its cost and what it observed, or why it failed.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Measurement {
    /// The LCP solver.
    pub solver: Solver,
    /// Step h (s).
    pub dt: f64,
    /// Steps taken (up to the failure, if any).
    pub steps: u64,
    /// Steps whose LCP needed a solver.
    pub lcp_solves: u64,
    /// Measured wall time of the run (s).
    pub wall_seconds: f64,
    /// What the run observed, or the typed error that stopped it.
    pub outcome: Result<Observation, String>,
}

impl Measurement {
    /// Whether the run finished with a state beyond every physical bound.
    pub fn diverged(&self) -> bool {
        self.outcome.as_ref().is_ok_and(Observation::diverged)
    }

    /// Steps per second of wall time.
    pub fn steps_per_second(&self) -> f64 {
        self.steps as f64 / self.wall_seconds.max(1e-9)
    }

    /// LCP solves per second of wall time.
    pub fn lcp_solves_per_second(&self) -> f64 {
        self.lcp_solves as f64 / self.wall_seconds.max(1e-9)
    }
}

/// Runs `study` at step `dt` with `solver`.
pub fn measure(study: &Study, dt: f64, solver: Solver) -> Measurement {
    let failed = |reason: String| Measurement {
        solver,
        dt,
        steps: 0,
        lcp_solves: 0,
        wall_seconds: 0.0,
        outcome: Err(reason),
    };
    let scene = match study.scene(dt, solver) {
        Ok(s) => s,
        Err(e) => return failed(format!("{e:#}")),
    };
    let model = match scene.build() {
        Ok(m) => m,
        Err(e) => return failed(e.to_string()),
    };
    let mut probe = Probe::new(&scene, &model, &study.sample_times);
    let start = Instant::now();
    let result = scene.run_with(&mut probe);
    let mut wall_seconds = start.elapsed().as_secs_f64();
    let (steps, lcp_solves) = (probe.steps, probe.lcp_solves);
    let mut spent = wall_seconds;
    for _ in 1..REPEATS {
        if result.is_err() || spent >= SHORT_RUN {
            break;
        }
        let mut again = Probe::new(&scene, &model, &study.sample_times);
        let start = Instant::now();
        let repeat = scene.run_with(&mut again);
        let wall = start.elapsed().as_secs_f64();
        if repeat.is_err() {
            break;
        }
        wall_seconds = wall_seconds.min(wall);
        spent += wall;
    }
    let outcome = match result {
        Ok(summary) => Ok(probe.finish(summary.t_end, summary.stopped_early)),
        Err(e) => Err(format!("{:#}", anyhow::Error::from(e))),
    };
    Measurement { solver, dt, steps, lcp_solves, wall_seconds, outcome }
}
