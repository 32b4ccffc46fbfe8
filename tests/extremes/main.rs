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

mod clearance_and_ratios;
mod drift;
mod impacts;
mod laws;
mod million;
mod step_sizes;

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
