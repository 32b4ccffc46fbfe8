//! Stability at the extremes: each model run at the edges of its parameters (ε_N = 0 and 1,
//! μ = 0 and 10³, Δt from 1e-7 to 5e-2 s, clearances down to 1e-6 m, mass and inertia ratios
//! of 1e-9), simultaneous impacts, Painlevé's rod and runs of a million steps.
//!
//! Every case asserts measured numbers (closed forms, momentum, energy bounds, penetration
//! bounds proportional to Δt) or a typed error. Each test prints rows of the results table of
//! `docs/extremes.md`:
//!
//! ```text
//! cargo test --test extremes -- --nocapture --test-threads=1 | grep '^|'
//! ```

use std::f64::consts::PI;
use std::ops::ControlFlow;

use moreau::kinematics::ContactKinematics;
use moreau::models::{
    AnyModel, ModelError, ModelKind, PainleveParams, Scene, SliderCrankParams, StopRule,
    WoodpeckerParams,
};
use moreau::stepper::{
    ContactState, Mechanism, Record, Recorder, RunSummary, SolverChoice, StepError, StepReport,
    Stepper, StepperOptions,
};
use moreau_testsupport::{Chain, Rod, deepest_penetration, energy_gain, record_is_finite};

const G: f64 = 9.81;

/// Prints one row of the results table of docs/extremes.md (pipes inside cells escaped).
fn row(case: &str, outcome: &str, number: &str) {
    let cell = |s: &str| s.replace('|', "\\|");
    println!("| {} | {} | {} |", cell(case), cell(outcome), cell(number));
}

/// Runs a scene like `Scene::run`, optionally with the position projection and an active-set
/// threshold, and returns the model, the record and the run summary.
fn run_with(
    scene: &Scene,
    projection: bool,
    gap_tolerance: f64,
) -> Result<(AnyModel, Record, RunSummary), ModelError> {
    let model = scene.build()?;
    let (q0, u0) = model.initial_state();
    let mut options = scene.stepper_options().with_gap_tolerance(gap_tolerance);
    options.projection = projection;
    let mut stepper = Stepper::new(model, &q0, &u0, 0.0, options)?;
    let mut recorder = Recorder::every(scene.record_every);
    recorder.push_initial(stepper.mechanism(), stepper.t(), stepper.q(), stepper.u());
    let summary = scene.drive(&mut stepper, &mut recorder)?;
    Ok((stepper.mechanism().clone(), recorder.record, summary))
}

fn run(scene: &Scene) -> (AnyModel, Record, RunSummary) {
    run_with(scene, false, 0.0).unwrap_or_else(|e| panic!("scene fails: {e}"))
}

/// A report scene with some keys set.
fn scene(kind: ModelKind, settings: &[(&str, String)]) -> Scene {
    let mut scene = Scene::report(kind);
    for (key, value) in settings {
        scene.set(key, value).unwrap_or_else(|e| panic!("{kind}: {key} = {value}: {e}"));
    }
    scene
}

/// The energy scale of a record: max(|E_0|, T_0), for relative energy errors (J).
fn energy_scale(r: &Record) -> f64 {
    r.total_energy()[0].abs().max(r.kinetic[0])
}

/// Most negative impulse dissipation of one step: energy that impulses put in (J, ≤ 0).
fn impulse_energy_input(r: &Record) -> f64 {
    let d = &r.cumulative_dissipation;
    d.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::min)
}

/// Solves the 3 × 3 system A x = b (column-major A) by Cramer's rule.
fn solve3(a: &[f64], b: [f64; 3]) -> [f64; 3] {
    let at = |i: usize, j: usize| a[i + 3 * j];
    let det3 = |c: [[f64; 3]; 3]| {
        c[0][0] * (c[1][1] * c[2][2] - c[1][2] * c[2][1])
            - c[0][1] * (c[1][0] * c[2][2] - c[1][2] * c[2][0])
            + c[0][2] * (c[1][0] * c[2][1] - c[1][1] * c[2][0])
    };
    let full = |col: Option<usize>| {
        let mut c = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                c[i][j] = if Some(j) == col { b[i] } else { at(i, j) };
            }
        }
        c
    };
    let d = det3(full(None));
    [det3(full(Some(0))) / d, det3(full(Some(1))) / d, det3(full(Some(2))) / d]
}

/// Largest stable step of the woodpecker's smooth dynamics, Δt_crit = 2/ω_max.
///
/// The scheme is explicit in h (Störmer-Verlet for the spring), stable for ω Δt < 2. The
/// torsion spring's stiffness c_φ v vᵀ, v = (0, 1, −1), has rank one, so the one non-zero
/// eigenvalue of M⁻¹K is ω² = c_φ vᵀ M⁻¹ v.
fn woodpecker_critical_step(p: &WoodpeckerParams) -> f64 {
    let model = Scene {
        params: moreau::models::ModelParams::Woodpecker(p.clone()),
        ..Scene::report(ModelKind::Woodpecker)
    }
    .build()
    .unwrap();
    let mut m = [0.0; 9];
    model.mass_matrix(&[0.0; 3], 0.0, &mut m);
    let x = solve3(&m, [0.0, 1.0, -1.0]);
    let omega = (p.c_phi * (x[1] - x[2])).sqrt();
    2.0 / omega
}

// ---------------------------------------------------------------------------------------
// ε_N = 0 and 1

#[test]
fn ball_with_eps_0_rests_from_the_first_impact() {
    let dt = 1e-3;
    let s = scene(ModelKind::Ball, &[("eps_n", "0".into()), ("t_end", "1.0".into())]);
    let (_, r, _) = run(&s);
    let v1 = (2.0 * G * 0.9f64).sqrt();
    let first = r.p_n.iter().position(|p| p[0] > 0.0).expect("an impact");
    // ξ_N = γ_N(+) = 0: the velocity is exactly zero from the impact on, the position frozen,
    // and each later step carries the weight's impulse m g Δt.
    for k in first..r.len() {
        assert_eq!(r.u[k][0], 0.0, "row {k}");
        assert_eq!(r.q[k][0], r.q[first][0]);
    }
    for k in first + 1..r.len() {
        assert!((r.p_n[k][0] - G * dt).abs() <= 1e-15, "P_N = {}", r.p_n[k][0]);
    }
    // The previous midpoint was open, so q_A > R − Δt|u_A|/2 and q_E = q_M > R − Δt|u_A|.
    let pen = 0.1 - r.q[first][0];
    let u_a = r.u[first - 1][0].abs();
    assert!(pen > 0.0 && pen <= u_a * dt * (1.0 + 1e-12), "penetration {pen}");
    row(
        "ball ε_N = 0, Δt = 1e-3",
        "rests from the first impact: u = 0 exactly, P_N = m g Δt",
        &format!("penetration {pen:.3e} m = {:.3} v₁Δt", pen / (v1 * dt)),
    );
}

#[test]
fn ball_with_eps_1_keeps_its_energy() {
    let s = scene(ModelKind::Ball, &[("eps_n", "1".into())]);
    let (m, r, summary) = run(&s);
    assert_eq!(summary.steps, 10_000);
    let e = r.total_energy();
    let drift = e.iter().map(|x| (x - e[0]).abs()).fold(0.0, f64::max) / e[0];
    // Free flight is exact for constant gravity, and the impact step reverses u and leaves
    // q_E = q_A: energy is kept to round-off.
    assert!(drift < 1e-12, "relative energy drift {drift}");
    let apexes: Vec<f64> = (1..r.len() - 1)
        .filter(|&k| r.u[k - 1][0] > 0.0 && r.u[k][0] <= 0.0)
        .map(|k| r.q[k][0])
        .collect();
    assert!(apexes.len() >= 5);
    for y in &apexes {
        assert!((y - 1.0).abs() < 1e-4, "apex {y}");
    }
    let pen = deepest_penetration(&m, &r);
    let v1 = (2.0 * G * 0.9f64).sqrt();
    assert!(pen <= 0.5 * v1 * 1e-3);
    row(
        "ball ε_N = 1, Δt = 1e-3, 10 s",
        "bounces back to y₀ every time",
        &format!(
            "|ΔE|/E₀ = {drift:.1e}, apex error {:.1e} m",
            apexes.iter().map(|y| (y - 1.0).abs()).fold(0.0, f64::max)
        ),
    );
}

#[test]
fn woodpecker_with_eps_0_and_1_gains_energy_only_through_friction() {
    let mut gains = Vec::new();
    for (eps, mu) in [(0.0, 0.3), (1.0, 0.0), (1.0, 0.3)] {
        let s = scene(ModelKind::Woodpecker, &[("eps_n", eps.to_string()), ("mu", mu.to_string())]);
        let (m, r, _) = run(&s);
        assert!(record_is_finite(&r));
        let scale = energy_scale(&r);
        let gain = energy_gain(&r) / scale;
        let pen = deepest_penetration(&m, &r);
        // The sleeve edges and the beak move at most at |v| + r_M|ω_M| + ... ≈ 1 m/s here.
        assert!(pen < 1.0 * s.dt, "penetration {pen}");
        row(
            &format!("woodpecker ε_N = {eps}, μ = {mu}"),
            "runs 1 s",
            &format!(
                "max (E − E₀)/E₀ = {gain:.2e}, impulse energy input {:.2e} J, penetration {pen:.2e} m",
                impulse_energy_input(&r)
            ),
        );
        gains.push(gain);
    }
    // ε_N = 0: energy never grows. ε_N = 1 without friction: kept to the scheme's error.
    assert!(gains[0] <= 1e-12, "eps 0 gain {}", gains[0]);
    // (The spring's energy oscillates by O((ω Δt)²) in the explicit midpoint scheme, with
    // ω Δt ≈ 0.05 here.)
    assert!(gains[1] <= 1e-3, "eps 1, mu 0 gain {}", gains[1]);
    // ε_N = 1 with friction (ε_T = 0): a sticking impact changes the kinetic energy by
    // ½ P_T γ_T(−), whose sign Newton's law does not fix; the toy is pumped up the pole.
    assert!(gains[2] > 1.0, "eps 1, mu 0.3 gain {}", gains[2]);
}

#[test]
fn slider_crank_with_eps_0_and_1_never_gains_energy() {
    let p = SliderCrankParams::report();
    for eps in [0.0, 1.0] {
        let mut s = scene(ModelKind::SliderCrank, &[("eps_n", eps.to_string())]);
        s.t_end = 0.05;
        let (m, r, _) = run(&s);
        assert!(record_is_finite(&r));
        let gain = energy_gain(&r) / energy_scale(&r);
        let pen = deepest_penetration(&m, &r);
        assert!(gain <= 1e-12, "eps {eps}: gain {gain}");
        assert!(pen <= p.l1 * p.init.w1 * s.dt, "eps {eps}: penetration {pen}");
        let e = r.total_energy();
        row(
            &format!("slider-crank ε_N = {eps}, 0.05 s"),
            "energy never grows",
            &format!(
                "E_end/E₀ = {:.4}, penetration {pen:.2e} m = {:.3} l₁ω₁Δt",
                e[e.len() - 1] / e[0],
                pen / (p.l1 * p.init.w1 * s.dt)
            ),
        );
    }
}

#[test]
fn cam_with_eps_0_and_1_penetrates_by_at_most_the_closing_speed_times_dt() {
    for eps in [0.0, 1.0] {
        let s = scene(ModelKind::Cam, &[("eps_n", eps.to_string())]);
        let (m, r, _) = run(&s);
        assert!(record_is_finite(&r));
        let AnyModel::Cam(cam) = &m else { unreachable!() };
        let p = cam.params();
        // Closing speed bound: the follower's largest speed plus the cam's largest lift rate
        // 2 H ω / β.
        let v_max = r.u.iter().map(|u| u[0].abs()).fold(0.0, f64::max);
        let bound = (v_max + 2.0 * p.stroke * p.omega / p.beta) * s.dt;
        let pen = deepest_penetration(&m, &r);
        assert!(pen <= bound, "eps {eps}: penetration {pen} > {bound}");
        row(
            &format!("cam ε_N = {eps}, Δt = 1e-4"),
            "driven; penetration within closing speed × Δt",
            &format!("penetration {pen:.2e} m = {:.2} of the bound", pen / bound),
        );
    }
}

// ---------------------------------------------------------------------------------------
// μ = 0 and 10³

#[test]
fn painleve_rod_with_mu_0_slides_freely_and_with_mu_1000_pivots_on_its_end() {
    // μ = 0: no horizontal force, x = x₀ + ẋ₀ t exactly.
    let s = scene(ModelKind::Painleve, &[("mu", "0".into())]);
    let (_, r, _) = run(&s);
    let err = (0..r.len()).map(|k| (r.q[k][0] - (-r.t[k])).abs()).fold(0.0, f64::max);
    assert!(err < 1e-12, "x error {err}");
    assert!(energy_gain(&r) <= 1e-12 * energy_scale(&r));
    row(
        "Painlevé μ = 0",
        "slides freely until flat",
        &format!("max |x − (x₀ + ẋ₀t)| = {err:.1e} m"),
    );

    // μ = 10³: the end sticks at the first step and the rod falls pivoting about it.
    for dt in [1e-3, 1e-4] {
        let mut s = scene(ModelKind::Painleve, &[("mu", "1000".into())]);
        s.dt = dt;
        let (m, r, _) = run(&s);
        let AnyModel::Painleve(rod) = &m else { unreachable!() };
        let end = |k: usize| rod.lower_end(&r.q[k])[0];
        assert_eq!(r.state[1][0], ContactState::Stick);
        // The end moves by ẋ Δt/2 in the half step before the impulse acts.
        let start = end(0);
        assert!((end(1) - (start - 0.5 * dt)).abs() < dt * dt, "end after step 1: {}", end(1));
        let drift = (1..r.len()).map(|k| (end(k) - end(1)).abs()).fold(0.0, f64::max);
        // While sticking, γ_T = w_T(q_M)ᵀ u_E = 0 at the midpoint only: the end creeps by
        // O(Δt²) per step, O(Δt) over the fall.
        assert!(drift < 2.0 * dt, "dt {dt}: end drift {drift}");
        assert!(energy_gain(&r) <= 1e-12 * energy_scale(&r));
        row(
            &format!("Painlevé μ = 10³, Δt = {dt:.0e}"),
            "end sticks at step 1, rod pivots flat",
            &format!("end drift while sticking {drift:.2e} m = {:.2} Δt·(1 m/s)", drift / dt),
        );
    }
}

#[test]
fn woodpecker_with_mu_0_falls_with_gravity_and_with_mu_1000_locks() {
    // μ = 0: the contacts' w_N have no y-component, so the vertical momentum
    // p_y = (m_S + m_M) v + m_S l_M ω_M + m_S l_G ω_S obeys dp_y/dt = −(m_S + m_M) g exactly.
    let s = scene(ModelKind::Woodpecker, &[("mu", "0".into())]);
    let (m, r, _) = run(&s);
    let AnyModel::Woodpecker(w) = &m else { unreachable!() };
    let p = w.params();
    let p_y = |u: &[f64]| (p.m_s + p.m_m) * u[0] + p.m_s * p.l_m * u[1] + p.m_s * p.l_g * u[2];
    let err = (0..r.len())
        .map(|k| (p_y(&r.u[k]) - (p_y(&r.u[0]) - (p.m_s + p.m_m) * G * r.t[k])).abs())
        .fold(0.0, f64::max);
    let scale = (p.m_s + p.m_m) * G * s.t_end;
    assert!(err < 1e-12 * scale.max(1.0) * 1e3, "p_y error {err}");
    row(
        "woodpecker μ = 0",
        "falls: p_y = p_y0 − (m_S+m_M) g t",
        &format!("max error {err:.1e} N s"),
    );

    let s = scene(ModelKind::Woodpecker, &[("mu", "1000".into())]);
    let (m, r, _) = run(&s);
    assert!(record_is_finite(&r));
    assert!(energy_gain(&r) <= 1e-12 * energy_scale(&r));
    let drop = r.q[0][0] - r.q[r.len() - 1][0];
    let pen = deepest_penetration(&m, &r);
    // With the friction report's μ = 0.3 the sleeve slides 0.14 m down in 1 s; with μ = 10³
    // it is held, and drops only in the short flights between sticking phases.
    let free_fall = 0.5 * G + 0.3411;
    assert!(drop < 0.05 * free_fall, "drop {drop}");
    row(
        "woodpecker μ = 10³",
        "sleeve mostly locked",
        &format!(
            "drop {drop:.3e} m in 1 s ({:.1}% of free fall), penetration {pen:.1e} m",
            100.0 * drop / free_fall
        ),
    );
}

#[test]
fn slider_crank_with_mu_0_and_1000() {
    for mu in [0.0, 1000.0] {
        let mut s = scene(ModelKind::SliderCrank, &[("mu", mu.to_string())]);
        s.t_end = 0.05;
        let (m, r, _) = run(&s);
        assert!(record_is_finite(&r));
        let gain = energy_gain(&r) / energy_scale(&r);
        assert!(gain <= 1e-12, "mu {mu}: gain {gain}");
        let e = r.total_energy();
        let pen = deepest_penetration(&m, &r);
        row(
            &format!("slider-crank μ = {mu}, 0.05 s"),
            if mu == 0.0 { "runs, energy never grows" } else { "jams: friction stops the crank" },
            &format!(
                "E_end/E₀ = {:.4}, penetration {pen:.2e} m, impulse energy input {:.2e} J",
                e[e.len() - 1] / e[0],
                impulse_energy_input(&r)
            ),
        );
        if mu > 1.0 {
            assert!(e[e.len() - 1] < 0.01 * e[0], "a jammed crank keeps little energy");
        }
    }
}

// ---------------------------------------------------------------------------------------
// Step sizes from 1e-7 to 5e-2 s

/// Step sizes of the sweeps, with the horizon that keeps each run within 20 000 steps.
const STEPS: [f64; 7] = [1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 5e-2];

#[test]
fn ball_at_every_step_size_hits_the_floor_on_time_and_penetrates_by_less_than_v_dt() {
    let eps = 0.9;
    for dt in STEPS {
        // Drop height H such that the first impact comes after at most 8000 steps.
        let t1_target = (8000.0 * dt).min(0.4284);
        let h = 0.5 * G * t1_target * t1_target;
        let t1 = (2.0 * h / G).sqrt();
        let v1 = G * t1;
        let s = scene(
            ModelKind::Ball,
            &[("init.y0", (0.1 + h).to_string()), ("t_end", (2.5 * t1).to_string())],
        );
        let mut s = s;
        s.dt = dt;
        let (m, r, summary) = run(&s);
        assert!(summary.steps <= 20_001);
        assert!(record_is_finite(&r));
        let k = r.p_n.iter().position(|p| p[0] > 0.0).expect("an impact");
        // The impact step is the first whose midpoint q_A + Δt/2 u_A lies at or below the
        // floor: t₁ lies within (t_E − 3Δt/2, t_E − Δt/2] up to the g Δt²/8 by which the
        // linear midpoint overshoots the true one.
        let late = (r.t[k] - t1) / dt;
        assert!((0.5 - 1e-6..=1.5 + 1e-6).contains(&late), "dt {dt}: impact at {}", r.t[k]);
        // Newton's law on the one contact: u_E = −ε_N u_A.
        let (u_a, u_e) = (r.u[k - 1][0], r.u[k][0]);
        assert!((u_e + eps * u_a).abs() <= 1e-12 * v1, "dt {dt}: {u_e} vs {}", -eps * u_a);
        // The previous midpoint was open (q_A > R − Δt|u_A|/2), so q_M > R − Δt|u_A| and
        // q_E = q_M + Δt u_E/2 > R − Δt|u_A|(1 − ε_N/2).
        let pen = deepest_penetration(&m, &r);
        let bound = u_a.abs() * dt * (1.0 - 0.5 * eps);
        assert!(pen <= bound * (1.0 + 1e-9) + 1e-15, "dt {dt}: penetration {pen}");
        row(
            &format!("ball Δt = {dt:.0e}, H = {h:.2e} m"),
            "impact within Δt of t₁; u_E = −ε_N u_A",
            &format!("t_E − t₁ = {late:.2} Δt, penetration {:.3} v₁Δt", pen / (v1 * dt)),
        );
    }
}

/// Runs `kind`'s report scene at step `dt` for `horizon` (or the scene's own stop rule),
/// returning the outcome as numbers or the error.
fn sweep_run(kind: ModelKind, dt: f64, horizon: f64) -> Result<(AnyModel, Record), ModelError> {
    let mut s = Scene::report(kind);
    s.dt = dt;
    s.t_end = horizon.min(s.t_end);
    run_with(&s, false, 0.0).map(|(m, r, _)| (m, r))
}

/// Horizon of a run at step dt: at most 10 000 steps and at most 1 s.
fn horizon(dt: f64) -> f64 {
    (1e4 * dt).min(1.0)
}

#[test]
fn woodpecker_step_sizes_stable_below_the_spring_limit_and_diverging_above() {
    let dt_crit = woodpecker_critical_step(&WoodpeckerParams::report());
    // ω = sqrt(c_φ vᵀM⁻¹v) ≈ 458 rad/s for the report's sleeve and bird: Δt_crit ≈ 4.4 ms.
    assert!((4e-3..5e-3).contains(&dt_crit), "critical step {dt_crit}");
    for dt in STEPS {
        let (m, r) = sweep_run(ModelKind::Woodpecker, dt, horizon(dt)).unwrap();
        assert!(record_is_finite(&r), "dt {dt}: NaN");
        let gain = energy_gain(&r) / energy_scale(&r);
        let pen = deepest_penetration(&m, &r);
        if dt < dt_crit {
            assert!(gain <= 1e-12, "dt {dt}: energy gain {gain}");
            // The report's initial state already penetrates by 8.8e-7 m at contact 2.
            assert!(pen <= 8.8e-7 + 1.0 * dt, "dt {dt}: penetration {pen}");
        } else {
            // Above the limit the spring mode grows by orders of magnitude each step.
            assert!(gain > 1e6, "dt {dt}: energy gain {gain}");
        }
        row(
            &format!("woodpecker Δt = {dt:.0e}"),
            if dt < dt_crit { "stable" } else { "diverges: Δt > Δt_crit = 2/ω" },
            &format!(
                "max (E − E₀)/E₀ = {gain:.2e}, penetration {pen:.2e} m (Δt_crit = {dt_crit:.2e} s)"
            ),
        );
    }
}

#[test]
fn cam_step_sizes_stable_below_the_spring_limit_and_diverging_above() {
    let p = moreau::models::CamParams::report();
    let dt_crit = 2.0 / (p.ks / p.m).sqrt();
    for dt in STEPS {
        // At least 4 ms: the follower released at the up-dead point meets the cam after 3 ms.
        let (m, r) = sweep_run(ModelKind::Cam, dt, horizon(dt).max(4e-3)).unwrap();
        assert!(record_is_finite(&r), "dt {dt}: NaN");
        let pen = deepest_penetration(&m, &r);
        let v_max = r.u.iter().map(|u| u[0].abs()).fold(0.0, f64::max);
        if dt < dt_crit {
            // The follower's speed stays below the spring's amplitude bound ω_s (H + g/ω_s²)
            // plus the cam's lift rate.
            let omega_s = (p.ks / p.m).sqrt();
            let lift_rate = 2.0 * p.stroke * p.omega / p.beta;
            assert!(
                v_max <= omega_s * (p.stroke + G / (omega_s * omega_s)) + 2.0 * lift_rate,
                "dt {dt}: v {v_max}"
            );
            assert!(pen <= (v_max + lift_rate) * dt, "dt {dt}: penetration {pen}");
        } else {
            assert!(v_max > 1e6, "dt {dt}: v {v_max}");
        }
        row(
            &format!("cam Δt = {dt:.0e}"),
            if dt < dt_crit { "stable" } else { "diverges: Δt > Δt_crit = 2/√(K_s/m)" },
            &format!(
                "max |v| = {v_max:.2e} m/s, penetration {pen:.2e} m (Δt_crit = {dt_crit:.2e} s)"
            ),
        );
    }
}

#[test]
fn painleve_step_sizes_penetrate_by_g_dt_squared() {
    for dt in STEPS {
        let (m, r) = sweep_run(ModelKind::Painleve, dt, horizon(dt)).unwrap();
        assert!(record_is_finite(&r), "dt {dt}: NaN");
        assert!(energy_gain(&r) <= 1e-12 * energy_scale(&r), "dt {dt}");
        let pen = deepest_penetration(&m, &r);
        // After the first step the rod's rotation leaves the gap positive by O(Δt²ω²) (2e-12 m
        // at Δt = 1e-3); the next midpoint is open, the rod falls freely by g Δt²/2 for one
        // step, and the following midpoint lies g Δt² deep, where γ_N = 0 then keeps it.
        assert!(pen <= G * dt * dt * (1.0 + 1e-6) + 1e-14, "dt {dt}: penetration {pen}");
        row(
            &format!("Painlevé μ = 0.3, Δt = {dt:.0e}"),
            "slides; energy never grows",
            &format!("penetration {pen:.3e} m = {:.3} g Δt²", pen / (G * dt * dt)),
        );
    }
    // The gap's second-order drift keeps growing while the contact is closed (1.6e-11 m
    // after two steps, 2.9e-10 m after five), so no fixed active-set threshold keeps the
    // contact closed; the position projection does, and removes the penetration.
    let mut s = Scene::report(ModelKind::Painleve);
    s.dt = 1e-3;
    let (m, plain, _) = run_with(&s, false, 1e-9).unwrap();
    let (_, projected, _) = run_with(&s, true, 0.0).unwrap();
    let (pen, pen_proj) = (deepest_penetration(&m, &plain), deepest_penetration(&m, &projected));
    assert!(pen > 0.9 * G * 1e-6, "threshold run penetration {pen}");
    assert!(pen_proj <= 1e-15, "projected penetration {pen_proj}");
    assert!(energy_gain(&projected) <= 1e-12 * energy_scale(&projected));
    row(
        "Painlevé μ = 0.3, Δt = 1e-3",
        "gap tolerance 1e-9 m / projection",
        &format!("penetration {pen:.2e} m / {pen_proj:.1e} m"),
    );
}

#[test]
fn slider_crank_step_sizes() {
    let p = SliderCrankParams::report();
    for dt in STEPS {
        let (m, r) = sweep_run(ModelKind::SliderCrank, dt, horizon(dt)).unwrap();
        assert!(record_is_finite(&r), "dt {dt}: NaN");
        let gain = energy_gain(&r) / energy_scale(&r);
        let pen = deepest_penetration(&m, &r);
        // The crank turns ω₁Δt per step; while that is small the run is sound.
        let turn = p.init.w1 * dt;
        if turn <= 0.15 {
            assert!(gain <= 1e-12, "dt {dt}: gain {gain}");
            assert!(pen <= p.l1 * p.init.w1 * dt, "dt {dt}: penetration {pen}");
        }
        row(
            &format!("slider-crank Δt = {dt:.0e} (ω₁Δt = {turn:.1e} rad)"),
            if turn <= 0.15 {
                "sound"
            } else {
                "finite but meaningless: the crank turns too far per step"
            },
            &format!(
                "max (E − E₀)/E₀ = {gain:.2e}, penetration {pen:.2e} m = {:.2} l₁ω₁Δt",
                pen / (p.l1 * p.init.w1 * dt)
            ),
        );
    }
}

// ---------------------------------------------------------------------------------------
// Clearance down to 1e-6 m, with and without projection

#[test]
fn slider_crank_small_clearance_drift_and_projection() {
    let p = SliderCrankParams::report();
    let mut pen_over_c = Vec::new();
    for c in [1e-3, 1e-4, 1e-5, 1e-6] {
        let mut s = scene(ModelKind::SliderCrank, &[("c", c.to_string())]);
        // One crank revolution.
        s.stop_at = Some(StopRule { coordinate: "th1".into(), value: 2.0 * PI });
        let (m, plain, _) = run_with(&s, false, 0.0).unwrap();
        let (_, projected, _) = run_with(&s, true, 0.0).unwrap();
        let AnyModel::SliderCrank(sc) = &m else { unreachable!() };
        let y_max = |r: &Record| {
            r.q.iter()
                .flat_map(|q| (0..4).map(|k| sc.normalized_corner(k, q).abs()).collect::<Vec<_>>())
                .fold(0.0, f64::max)
        };
        let pen = deepest_penetration(&m, &plain);
        let pen_proj = deepest_penetration(&m, &projected);
        let (gain, gain_proj) = (
            energy_gain(&plain) / energy_scale(&plain),
            energy_gain(&projected) / energy_scale(&projected),
        );
        // Without projection, the penetration is bounded by the speed scale times Δt, not by
        // the clearance: at c = 1e-6 m the corners sink tens of clearances deep.
        assert!(pen <= p.l1 * p.init.w1 * s.dt, "c {c}: penetration {pen}");
        // With projection, the corners stay in the guide to round-off.
        assert!(pen_proj <= 1e-15, "c {c}: projected penetration {pen_proj}");
        assert!(y_max(&projected) <= 1.0 + 1e-9, "c {c}: |Y| {}", y_max(&projected));
        // Neither run gains energy.
        assert!(gain <= 1e-12 && gain_proj <= 1e-12, "c {c}: gains {gain} {gain_proj}");
        // Both reach θ₁ = 2π at nearly the same time.
        let (t_a, t_b) = (plain.t[plain.len() - 1], projected.t[projected.len() - 1]);
        assert!((t_a - t_b).abs() < 0.01 * t_a, "c {c}: {t_a} vs {t_b}");
        row(
            &format!("slider-crank c = {c:.0e} m, Δt = 1e-5, one revolution"),
            "without / with projection",
            &format!(
                "penetration {pen:.2e} m ({:.2} c) / {pen_proj:.1e} m; max |Y| {:.2} / {:.6}; max (E − E₀)/E₀ {gain:.1e} / {gain_proj:.1e}",
                pen / c,
                y_max(&plain),
                y_max(&projected)
            ),
        );
        pen_over_c.push(pen / c);
    }
    // The drift problem: relative to the clearance, the penetration grows as c shrinks.
    assert!(pen_over_c[3] > 10.0 && pen_over_c[0] < 0.1, "{pen_over_c:?}");
}

// ---------------------------------------------------------------------------------------
// Mass and inertia ratios of 1e-9

#[test]
fn woodpecker_with_a_sleeve_1e9_lighter_than_the_bird() {
    let p = WoodpeckerParams::report();
    let mut s = scene(ModelKind::Woodpecker, &[("m_m", (1e-9 * p.m_s).to_string())]);
    s.t_end = 0.2;
    let light = match &s.params {
        moreau::models::ModelParams::Woodpecker(w) => w.clone(),
        _ => unreachable!(),
    };
    let dt_crit = woodpecker_critical_step(&light);
    assert!(dt_crit > s.dt);
    let (m, r, _) = run(&s);
    assert!(record_is_finite(&r));
    let gain = energy_gain(&r) / energy_scale(&r);
    let pen = deepest_penetration(&m, &r);
    assert!(gain <= 1e-12, "gain {gain}");
    assert!(pen <= 1.0 * s.dt, "penetration {pen}");
    row(
        "woodpecker m_M/m_S = 1e-9, Δt = 1e-4, 0.2 s",
        "runs",
        &format!("max (E − E₀)/E₀ = {gain:.1e}, penetration {pen:.2e} m"),
    );

    // J_M/J_S = 1e-9 as well: the sleeve's rotation on the torsion spring becomes a
    // 1e5 rad/s mode, Δt = 1e-4 s is far above the limit, and the run diverges until the
    // numbers overflow, which ends it with a typed error (not a NaN state, not a panic).
    let mut s = scene(
        ModelKind::Woodpecker,
        &[("m_m", (1e-9 * p.m_s).to_string()), ("j_m", (1e-9 * p.j_s).to_string())],
    );
    s.t_end = 0.2;
    let stiff = match &s.params {
        moreau::models::ModelParams::Woodpecker(w) => w.clone(),
        _ => unreachable!(),
    };
    let dt_crit = woodpecker_critical_step(&stiff);
    assert!(dt_crit < 1e-6, "critical step {dt_crit}");
    let mut stepper = s.stepper().unwrap();
    let mut steps = 0u64;
    let error = loop {
        match stepper.step() {
            Ok(report) => {
                assert!(report.q.iter().chain(report.u).all(|x| !x.is_nan()));
                steps += 1;
                assert!(steps < 2000, "no divergence");
            }
            Err(e) => break e,
        }
    };
    assert!(matches!(error, StepError::NonFinite { .. }), "{error:?}");
    row(
        "woodpecker m_M/m_S = J_M/J_S = 1e-9, Δt = 1e-4",
        "diverges (Δt ≫ Δt_crit), stops with a typed error",
        &format!("Δt_crit = {dt_crit:.2e} s; error after {steps} steps: {error}"),
    );

    // Below the limit the same mechanism runs.
    let mut s = s.clone();
    s.dt = dt_crit / 4.0;
    s.t_end = 5000.0 * s.dt;
    let (m, r, _) = run(&s);
    assert!(record_is_finite(&r));
    let gain = energy_gain(&r) / energy_scale(&r);
    let pen = deepest_penetration(&m, &r);
    assert!(gain <= 1e-9, "gain {gain}");
    row(
        "same, Δt = Δt_crit/4, 5000 steps",
        "runs",
        &format!("max (E − E₀)/E₀ = {gain:.1e}, penetration {pen:.2e} m"),
    );
}

/// Two balls, one colliding with the other at relative speed 1 m/s, one step.
fn two_ball_impact(m1: f64, m2: f64, eps: f64) -> ([f64; 2], [f64; 2]) {
    let chain = Chain::new(vec![m1, m2], 0.5, eps);
    let u0 = [1.0, 0.0];
    let mut s = Stepper::new(chain, &[0.0, 1.0], &u0, 0.0, StepperOptions::new(1e-3)).unwrap();
    let r = s.step().unwrap();
    ([r.u[0], r.u[1]], u0)
}

#[test]
fn two_balls_with_mass_ratio_1e9_follow_the_two_body_impact() {
    for (m1, m2) in [(1.0, 1e-9), (1e-9, 1.0)] {
        for eps in [0.0, 0.5, 1.0] {
            let ([v1, v2], [a1, a2]) = two_ball_impact(m1, m2, eps);
            let total = m1 + m2;
            let p = m1 * a1 + m2 * a2;
            let want1 = (p - m2 * eps * (a1 - a2)) / total;
            let want2 = (p + m1 * eps * (a1 - a2)) / total;
            assert!(
                (v1 - want1).abs() <= 1e-12 * (1.0 + want1.abs()),
                "{m1} {m2} {eps}: v1 {v1} vs {want1}"
            );
            assert!(
                (v2 - want2).abs() <= 1e-12 * (1.0 + want2.abs()),
                "{m1} {m2} {eps}: v2 {v2} vs {want2}"
            );
            let dp = (m1 * v1 + m2 * v2 - p).abs() / p.abs();
            assert!(dp <= 1e-15, "momentum {dp}");
            if eps == 1.0 {
                row(
                    &format!("two balls m₁ = {m1:.0e}, m₂ = {m2:.0e}, ε_N = 1"),
                    "two-body impact closed form",
                    &format!("v = ({v1:.12}, {v2:.12}) m/s; |Δp|/p = {dp:.0e}"),
                );
            }
        }
    }
}

// ---------------------------------------------------------------------------------------
// Simultaneous impacts

#[test]
fn newtons_cradle_of_touching_balls_is_one_simultaneous_impact() {
    // Balls of radius 1/2 at x_i = i touch exactly (g_N = 0), the first moves at v = 1.
    // At the midpoint every contact is closed (g_N ≤ 0), and the LCP acts at once: ξ_1 = 0
    // gives γ_1(+) = ε v, ξ_i = 0 for i > 1 gives γ_i(+) = 0, so balls 2..N leave together as
    // one block: V = (1 + ε) v / N and v_1 = V − ε v, the impact of m on (N − 1) m. Momentum
    // is kept exactly, and for ε = 1 the kinetic energy too, but the experiment's answer
    // (one ball leaves at v, the others rest) is not reproduced.
    for n in 2..=6 {
        for eps in [0.0, 0.5, 1.0] {
            let chain = Chain::new(vec![1.0; n], 0.5, eps);
            let q0: Vec<f64> = (0..n).map(|i| i as f64).collect();
            let mut u0 = vec![0.0; n];
            u0[0] = 1.0;
            let mut s = Stepper::new(chain, &q0, &u0, 0.0, StepperOptions::new(1e-3)).unwrap();
            let lcp_size = s.step().unwrap().lcp_size;
            assert_eq!(lcp_size, n - 1, "every contact enters the LCP");
            for _ in 0..9 {
                s.step().unwrap();
            }
            let u = s.u().to_vec();
            let big_v = (1.0 + eps) / n as f64;
            assert!((u[0] - (big_v - eps)).abs() < 1e-13, "n {n} eps {eps}: v1 {}", u[0]);
            for (i, v) in u.iter().enumerate().skip(1) {
                assert!((v - big_v).abs() < 1e-13, "n {n} eps {eps}: v{} = {v}", i + 1);
            }
            let chain = s.mechanism();
            assert!((chain.momentum(&u) - 1.0).abs() < 1e-14);
            let energy = chain.kinetic(&u) / 0.5;
            // T(+)/T(−) = 1 − (1 − ε²)(N − 1)/N.
            let want = 1.0 - (1.0 - eps * eps) * (n as f64 - 1.0) / n as f64;
            assert!((energy - want).abs() < 1e-13, "n {n} eps {eps}: energy ratio {energy}");
            if n == 5 && eps != 0.5 {
                row(
                    &format!("Newton's cradle, 5 touching balls, ε_N = {eps}"),
                    "one LCP: balls 2-5 leave as a block",
                    &format!(
                        "u = ({:.6}, {:.6} × 4); T⁺/T⁻ = {energy:.15}; |Δp| = {:.0e}",
                        u[0],
                        u[1],
                        (chain.momentum(&u) - 1.0).abs()
                    ),
                );
            }
        }
    }
}

#[test]
fn newtons_cradle_with_small_gaps_passes_the_velocity_down_the_row() {
    // With gaps of 1 mm between the balls, every impact is a two-ball impact of equal masses
    // with ε = 1, which exchanges the velocities: the last ball leaves at v.
    let n = 5;
    let gap = 1e-3;
    let chain = Chain::new(vec![1.0; n], 0.5, 1.0);
    let q0: Vec<f64> = (0..n).map(|i| i as f64 * (1.0 + gap)).collect();
    let mut u0 = vec![0.0; n];
    u0[0] = 1.0;
    let mut s = Stepper::new(chain, &q0, &u0, 0.0, StepperOptions::new(1e-5)).unwrap();
    s.run_until(0.01, &mut |_: &StepReport<'_>| ControlFlow::Continue(())).unwrap();
    let u = s.u().to_vec();
    for v in &u[..n - 1] {
        assert!(v.abs() < 1e-12, "{u:?}");
    }
    assert!((u[n - 1] - 1.0).abs() < 1e-12, "{u:?}");
    row(
        "Newton's cradle, 5 balls 1 mm apart, ε_N = 1",
        "sequential impacts: last ball leaves at v",
        &format!("u = {:?}", u.iter().map(|v| format!("{v:.1e}")).collect::<Vec<_>>()),
    );
}

#[test]
fn rod_landing_flat_on_two_contacts_bounces_without_turning() {
    for eps in [0.0, 0.5, 1.0] {
        for mu in [0.0, 0.5] {
            let rod = Rod::with(1.0, 0.5, G, eps, mu);
            let dt = 1e-3;
            let mut s = Stepper::new(
                rod,
                &[0.0, 0.01, 0.0],
                &[0.0, -1.0, 0.0],
                0.0,
                StepperOptions::new(dt),
            )
            .unwrap();
            let mut impact = None;
            let mut u_before = [0.0; 3];
            for _ in 0..2000 {
                let u_a = [s.u()[0], s.u()[1], s.u()[2]];
                let r = s.step().unwrap();
                if r.contacts.iter().any(|c| c.p_n > 0.0) {
                    impact = Some((r.contacts[0].p_n, r.contacts[1].p_n, [r.u[0], r.u[1], r.u[2]]));
                    u_before = u_a;
                    break;
                }
            }
            let (p1, p2, u) = impact.expect("the rod lands");
            // Both ends close in the same step and take equal impulses; the rod does not turn
            // and bounces with ε_N times its landing speed: u_E = −ε_N u_A.
            assert!((p1 - p2).abs() <= 1e-15 * p1, "eps {eps} mu {mu}: {p1} vs {p2}");
            assert!(u[2].abs() <= 1e-15 && u[0].abs() <= 1e-15, "eps {eps} mu {mu}: {u:?}");
            assert!(
                (u[1] + eps * u_before[1]).abs() < 1e-14,
                "eps {eps}: {} vs {}",
                u[1],
                u_before[1]
            );
            // Impulse balance: 2 P_N = m (u_E − u_A) + m g Δt.
            assert!((2.0 * p1 - (u[1] - u_before[1] + G * dt)).abs() < 1e-14);
            if mu == 0.5 {
                row(
                    &format!("rod landing flat on two contacts, ε_N = {eps}"),
                    "equal impulses, no rotation, u_E = −ε_N u_A",
                    &format!("P_N = {p1:.6} N s each, |ω| = {:.0e} rad/s", u[2].abs()),
                );
            }
        }
    }
}

// ---------------------------------------------------------------------------------------
// Painlevé's rod

#[test]
fn painleve_rod_first_step_has_a_tangential_impact_exactly_above_mu_4_3() {
    // At φ₀ = atan 2 (m = s = 1), with the end sliding at γ_T = 1 m/s, the step's Delassus
    // matrix is G = [[1.6, 1.2], [1.2, 3.4]]. Sticking (γ_N⁺ = γ_T⁺ = 0) needs
    // G P = (g Δt, −1): P_N = 0.3 + 0.85 g Δt, P_T = −0.4 − 0.3 g Δt, admissible when
    // |P_T| ≤ μ P_N, i.e. μ ≥ 4/3 as Δt → 0: an impulse that does not vanish with Δt (a
    // tangential impact without collision). Sliding (P_T = −μ P_N) gives
    // P_N = g Δt / (1.6 − 1.2 μ) = g Δt / a, the acceleration-level LCP's a > 0.
    for dt in [1e-7, 1e-5, 1e-3] {
        for mu in [0.3, 1.3, 1.4, 2.0, 1000.0] {
            let mut s = Scene::report(ModelKind::Painleve);
            s.params = moreau::models::ModelParams::Painleve(PainleveParams::report_with_mu(mu));
            s.dt = dt;
            let mut stepper = s.stepper().unwrap();
            let r = stepper.step().unwrap();
            let c = r.contacts[0];
            let (p_n_stick, p_t_stick) = (0.3 + 0.85 * G * dt, -0.4 - 0.3 * G * dt);
            if p_t_stick.abs() <= mu * p_n_stick {
                assert_eq!(c.state, ContactState::Stick, "dt {dt} mu {mu}");
                assert!((c.p_n - p_n_stick).abs() < 1e-12, "dt {dt} mu {mu}: P_N {}", c.p_n);
                assert!((c.p_t - p_t_stick).abs() < 1e-12, "dt {dt} mu {mu}: P_T {}", c.p_t);
            } else {
                let a = 1.6 - 1.2 * mu;
                assert_eq!(c.state, ContactState::Slip, "dt {dt} mu {mu}");
                assert!(
                    (c.p_n - G * dt / a).abs() < 1e-12 * (1.0 + c.p_n),
                    "dt {dt} mu {mu}: P_N {}",
                    c.p_n
                );
                assert!((c.p_t + mu * c.p_n).abs() < 1e-12, "dt {dt} mu {mu}: P_T {}", c.p_t);
            }
            if dt == 1e-3 {
                row(
                    &format!("Painlevé first step, μ = {mu}, Δt = 1e-3"),
                    if c.state == ContactState::Stick {
                        "tangential impact, end sticks"
                    } else {
                        "slides, P_N = g Δt / a"
                    },
                    &format!("P_N = {:.6} N s, P_T = {:.6} N s", c.p_n, c.p_t),
                );
            }
        }
    }
}

#[test]
fn painleve_rod_with_mu_2_runs_to_the_end() {
    let s = scene(ModelKind::Painleve, &[("mu", "2".into())]);
    let (m, r, summary) = run(&s);
    assert!(record_is_finite(&r));
    assert!(energy_gain(&r) <= 1e-12 * energy_scale(&r));
    assert!(r.q[r.len() - 1][2] <= 0.0, "lies flat at the end");
    let e = r.total_energy();
    let pen = deepest_penetration(&m, &r);
    assert!(pen <= G * s.dt * s.dt * (1.0 + 1e-9));
    row(
        "Painlevé μ = 2, Δt = 1e-3",
        "sticks at once, falls flat, no LCP failure",
        &format!(
            "{} steps; energy lost {:.3} J of {:.3} J; penetration {pen:.2e} m",
            summary.steps,
            e[0] - e[e.len() - 1],
            e[0]
        ),
    );
}

// ---------------------------------------------------------------------------------------
// A million steps

/// What a run of a million ball steps measured.
struct Million {
    /// Largest |E − E₀| (J).
    drift: f64,
    /// Largest E − E₀ (J).
    gain: f64,
    /// Largest one-step increase E_(k+1) − E_k (J).
    step_gain: f64,
    /// Largest penetration R − y (m).
    penetration: f64,
    /// Final y and v.
    y: f64,
    v: f64,
}

/// Runs the ball for 10 s at Δt = 1e-5 (10⁶ steps) with an observer that keeps no record.
fn ball_million(eps: f64) -> Million {
    let s = scene(ModelKind::Ball, &[("eps_n", eps.to_string())]);
    let model = s.build().unwrap();
    let (q0, u0) = model.initial_state();
    let mut stepper = Stepper::new(model, &q0, &u0, 0.0, StepperOptions::new(1e-5)).unwrap();
    let energy = |q: f64, v: f64| 0.5 * v * v + G * (q - 0.1);
    let e0 = energy(q0[0], u0[0]);
    let mut m = Million {
        drift: 0.0,
        gain: f64::NEG_INFINITY,
        step_gain: 0.0,
        penetration: 0.0,
        y: 0.0,
        v: 0.0,
    };
    let mut prev = e0;
    let summary = stepper
        .run_until(10.0, &mut |r: &StepReport<'_>| {
            let (q, v) = (r.q[0], r.u[0]);
            assert!(q.is_finite() && v.is_finite());
            let e = energy(q, v);
            m.drift = m.drift.max((e - e0).abs());
            m.gain = m.gain.max(e - e0);
            m.step_gain = m.step_gain.max(e - prev);
            m.penetration = m.penetration.max(0.1 - q);
            prev = e;
            ControlFlow::Continue(())
        })
        .unwrap();
    assert_eq!(summary.steps, 1_000_000);
    m.y = stepper.q()[0];
    m.v = stepper.u()[0];
    m
}

#[test]
fn ball_a_million_steps_with_eps_1() {
    let m = ball_million(1.0);
    let e0 = G * 0.9;
    assert!(m.drift < 1e-9 * e0, "drift {}", m.drift);
    assert!(m.penetration <= 0.5 * (2.0 * G * 0.9f64).sqrt() * 1e-5);
    row(
        "ball ε_N = 1, Δt = 1e-5, 10⁶ steps",
        "no NaN, energy kept",
        &format!(
            "max |E − E₀|/E₀ = {:.1e}, largest one-step gain {:.1e} J",
            m.drift / e0,
            m.step_gain
        ),
    );
}

#[test]
fn ball_a_million_steps_with_eps_0_9_comes_to_rest() {
    let eps = 0.9;
    let dt = 1e-5;
    let m = ball_million(eps);
    // Past t_∞ = t₁ (1 + ε)/(1 − ε) ≈ 8.14 s the ball rests on the floor. The energy never
    // exceeds E₀. A single step may add a little: a resting ball moving up at u_A > 0 with
    // its midpoint still in contact leaves with u_E = −ε u_A and q_E − q_A = Δt u_A (1 − ε)/2,
    // a change ½u_A²(ε² − 1) + g Δt u_A (1 − ε)/2 whose largest value, at
    // u_A = g Δt / (2(1 + ε)), is (g Δt)² (1 − ε) / (8 (1 + ε)).
    let bound = (G * dt).powi(2) * (1.0 - eps) / (8.0 * (1.0 + eps));
    // (E₀ = 8.8 J; the flight before the first impact keeps E to round-off, 1e-12 relative.)
    assert!(m.gain <= 1e-11 * G * 0.9, "energy above E0 by {}", m.gain);
    assert!(m.step_gain <= bound * (1.0 + 1e-6), "one-step gain {} > {bound}", m.step_gain);
    let v1 = (2.0 * G * 0.9f64).sqrt();
    assert!(m.penetration <= 0.5 * v1 * dt);
    // The resting position does not drift.
    assert!((m.y - 0.1).abs() <= 0.5 * v1 * dt && m.v.abs() < 1e-9, "y {}, v {}", m.y, m.v);
    row(
        "ball ε_N = 0.9, Δt = 1e-5, 10⁶ steps",
        "rests after t_∞; E ≤ E₀ throughout",
        &format!(
            "largest one-step gain {:.3e} J = {:.3} (gΔt)²(1−ε)/(8(1+ε)); final y − R = {:.2e} m, v = {:.1e} m/s",
            m.step_gain,
            m.step_gain / bound,
            m.y - 0.1,
            m.v
        ),
    );
}

// ---------------------------------------------------------------------------------------
// Drift in persistent contact, the projection, LCPs without solution, first-order energy

/// A slider-crank with a short rod (l₂ = 1.5 l₁) and a thin slider, μ = ε_N = 0, whose upper
/// corners slide along the guide for a long stretch of the crank's turn.
fn short_rod_slider_crank() -> SliderCrankParams {
    let (l1, w1) = (0.05, -161.95);
    let l2 = 1.5 * l1;
    SliderCrankParams {
        l1,
        l2,
        a: 0.0197,
        b: 0.005,
        c: 1.39e-4,
        eps_n: 0.0,
        eps_t: 0.0,
        mu: 0.0,
        init: moreau::models::SliderCrankInit {
            th1: 0.0,
            th2: 0.0,
            th3: 0.0,
            w1,
            w2: -l1 / l2 * w1,
            w3: 0.0,
        },
        ..SliderCrankParams::report()
    }
}

#[test]
fn persistent_contact_drifts_into_the_guide_in_proportion_to_dt() {
    // In persistent contact the LCP keeps γ_N = 0 at each midpoint, but the corner's path is
    // curved: each step adds O(g̈_N Δt²) of penetration, which accumulates over the contact's
    // duration to O(Δt). Nothing in the scheme as written pulls it back.
    let p = short_rod_slider_crank();
    let mut pens = Vec::new();
    for dt in [1e-4, 5e-5] {
        let mut s = Scene::report(ModelKind::SliderCrank);
        s.params = moreau::models::ModelParams::SliderCrank(p.clone());
        s.stop_at = None;
        s.dt = dt;
        s.t_end = 0.03;
        let (m, plain, _) = run_with(&s, false, 0.0).unwrap();
        let (_, projected, _) = run_with(&s, true, 0.0).unwrap();
        let (pen, pen_proj) =
            (deepest_penetration(&m, &plain), deepest_penetration(&m, &projected));
        assert!(record_is_finite(&plain) && record_is_finite(&projected));
        // Far beyond one step's worth: the largest normal speed times Δt is about 1e-4 m.
        assert!(pen > 2.0 * p.c, "dt {dt}: penetration {pen}");
        assert!(pen_proj <= 1e-15, "dt {dt}: projected penetration {pen_proj}");
        row(
            &format!("short-rod slider-crank, c = 1.39e-4 m, Δt = {dt:.0e}"),
            "upper corners slide: drift without / with projection",
            &format!("penetration {pen:.3e} m ({:.1} c) / {pen_proj:.1e} m", pen / p.c),
        );
        pens.push(pen);
    }
    let ratio = pens[0] / pens[1];
    assert!((1.6..2.4).contains(&ratio), "halving Δt divides the drift by {ratio}");
}

#[test]
fn projection_over_all_corners_frees_a_slider_turned_in_the_guide() {
    // A slider turned far beyond c/(2a) (a fuzz case). Projecting only the corner that
    // penetrates (corner 4) along M⁻¹w_N would turn the slider and push corner 3, on the same
    // face, in; the stepper therefore projects over all four corners at once, which frees
    // both.
    let (l1, rod, w1) = (0.10761667052134372, 2.675893235669823, 164.71652101770627);
    let l2 = rod * l1;
    let rep = SliderCrankParams::report();
    let p = SliderCrankParams {
        l1,
        l2,
        a: 0.04131659969911525,
        b: 0.030740557392355858,
        c: 2.7777503855992243e-5,
        m1: rep.m1 * 0.7646035050932377,
        m2: rep.m2 * 1.3402709924606528,
        m3: rep.m3 * 1.5841968000758027,
        j2: rep.j2 * 0.8239706328329293,
        eps_n: 0.0,
        eps_t: 0.0,
        mu: 1.744512096813874,
        init: moreau::models::SliderCrankInit {
            th1: 0.0,
            th2: 0.0,
            th3: 0.0,
            w1,
            w2: -l1 / l2 * w1,
            w3: 0.0,
        },
        ..rep
    };
    let model = moreau::models::ModelParams::SliderCrank(p.clone()).build().unwrap();
    let (q0, u0) = model.initial_state();
    let mut options = StepperOptions::new(1e-4);
    options.projection = true;
    let mut stepper = Stepper::new(model, &q0, &u0, 0.0, options).unwrap();
    let (mut pen, mut turn) = (0.0f64, 0.0f64);
    for _ in 0..300 {
        stepper.step().unwrap();
        let m = stepper.mechanism();
        let worst = (0..4).map(|i| -m.normal_gap(i, stepper.q(), stepper.t())).fold(0.0, f64::max);
        pen = pen.max(worst);
        turn = turn.max(stepper.q()[2].abs());
    }
    // The slider turns until it binds in the guide, at about c/(2a) (where a sin θ + b cos θ
    // = b + c/2), and no further: without projection the penetration let it turn five times
    // as far ...
    let binding = p.c / (2.0 * p.a);
    assert!(
        turn > 0.5 * binding && turn <= 1.001 * binding,
        "th3 reached {turn}, binding at {binding}"
    );
    // ... and no corner is left inside the guide at the end of any step.
    assert!(pen <= 1e-12 * p.c, "penetration {pen} after projection");
    row(
        "slider turned in the guide, projected",
        "no corner inside at step ends",
        &format!("max penetration {pen:.1e} m"),
    );
}

#[test]
fn friction_with_tangential_restitution_can_leave_the_step_lcp_without_solution() {
    // A woodpecker with a longer beak arm (a fuzz case): μ = 1.84 and ε_T = 0.69 at the
    // beak, μ = 0.76 at the lower sleeve edge. At step 142 both are closed and the LCP of
    // eq. 7.41 (size 6) has no solution: Lemke ends on a ray and complete enumeration proves
    // it. The stepper stops with a typed error that carries the instance. With ε_T = 0 the
    // same toy runs. The LCPs before it have several solutions (μ > 1): Lemke's method picks
    // the ones that lead there, while Auto's warm start keeps the previous contact mode and
    // steers clear, so the run uses Lemke.
    let f = [1.0, 1.0, 1.0, 1.473838299104488, 0.5579096273671389, 1.0, 1.8382186540343675];
    let rep = WoodpeckerParams::report();
    let make = |eps_t: f64| WoodpeckerParams {
        l_m: rep.l_m * f[3],
        l_g: rep.l_g * f[4],
        l_s: rep.l_s * f[6],
        j_s: rep.j_s * 0.9846034045927093,
        beak: moreau::models::LawParams::new(0.0, eps_t, 1.839702639234597),
        lower: moreau::models::LawParams::new(0.0, 0.0, 0.7583672515045705),
        upper: moreau::models::LawParams::new(0.0, 0.0, 0.0),
        ..rep.clone()
    };
    let mut s = Scene::report(ModelKind::Woodpecker);
    s.dt = 0.00011159184942331329;
    s.t_end = 300.0 * s.dt;
    s.solver = SolverChoice::Lemke;
    s.params = moreau::models::ModelParams::Woodpecker(make(0.6923390041536567));
    let error = s.run().unwrap_err();
    let ModelError::Step(StepError::LcpFailed { step, status, lcp, q, u, .. }) = error else {
        panic!("expected LcpFailed, got {error}");
    };
    // Lemke alone ends on a ray; Auto (down to enumeration) certifies that there is no
    // solution.
    assert_eq!(status, moreau::lcp::Status::RayTermination);
    assert_eq!(lcp.n(), 6);
    assert!(q.iter().chain(&u).all(|x| x.is_finite()));
    let all = moreau::lcp::Enumeration::default().solve_all(lcp.view()).unwrap();
    assert!(all.is_empty());
    use moreau::lcp::Solver;
    let auto = moreau::lcp::Auto::default().solve(&lcp).unwrap();
    assert_eq!(auto.status, moreau::lcp::Status::NoSolution);
    s.params = moreau::models::ModelParams::Woodpecker(make(0.0));
    let sim = s.run().unwrap();
    assert!(record_is_finite(&sim.record));
    row(
        "woodpecker variant, beak μ = 1.84, ε_T = 0.69",
        "step LCP without solution: typed error LcpFailed with the instance (Lemke: ray; Auto: NoSolution)",
        &format!(
            "step {step}, n = 6; enumeration: 0 solutions, Lemke: ray; with ε_T = 0 runs {} steps",
            sim.steps
        ),
    );
}

#[test]
fn ideal_slider_crank_energy_error_is_first_order_in_dt() {
    // Without contacts the report's ideal slider-crank is conservative. The scheme takes the
    // centrifugal terms of h at u_A, so it is first order for them: the energy error over two
    // revolutions falls linearly with Δt (by 4 for Δt / 4), and it is a loss.
    let mut losses = Vec::new();
    for dt in [4e-5, 1e-5] {
        let mut s = Scene::report(ModelKind::SliderCrankIdeal);
        s.dt = dt;
        let (_, r, _) = run(&s);
        let e = r.total_energy();
        let gain = e.iter().map(|x| x - e[0]).fold(f64::NEG_INFINITY, f64::max);
        assert!(gain <= 1e-12 * e[0], "dt {dt}: energy gain {gain}");
        let loss = (e[0] - e[e.len() - 1]) / e[0];
        row(
            &format!("ideal slider-crank, two revolutions, Δt = {dt:.0e}"),
            "energy lost by the scheme",
            &format!("(E₀ − E_end)/E₀ = {loss:.3e}"),
        );
        losses.push(loss);
    }
    let ratio = losses[0] / losses[1];
    assert!((3.0..5.5).contains(&ratio), "first order: ratio {ratio}");
}
