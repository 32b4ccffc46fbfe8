//! Runs one report scene many times, for profilers: `cargo run --release --example
//! profile_run -- MODEL REPEATS`.
use std::ops::ControlFlow;

use moreau::models::{AnyModel, ModelKind, Scene};
use moreau::stepper::{Mechanism, RunSummary, StepReport, Stepper};

/// Runs a concrete (not enum-dispatched) mechanism over the scene's horizon.
fn run<M: Mechanism + Clone>(
    m: M,
    scene: &Scene,
) -> Result<RunSummary, Box<dyn std::error::Error>> {
    let (q0, u0) = scene.build()?.initial_state();
    let mut stepper = Stepper::new(m, &q0, &u0, 0.0, scene.stepper_options())?;
    Ok(stepper.run_until(scene.t_end, &mut |_: &StepReport<'_>| ControlFlow::Continue(()))?)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let kind: ModelKind = args.next().unwrap_or_else(|| "woodpecker".into()).parse()?;
    let repeats: usize = args.next().unwrap_or_else(|| "100".into()).parse()?;
    let concrete = args.next().as_deref() == Some("concrete");
    let mut scene = Scene::report(kind);
    if let Ok(t_end) = std::env::var("MOREAU_T_END") {
        scene.set("t_end", &t_end)?;
    }
    let start = std::time::Instant::now();
    let mut steps = 0;
    for _ in 0..repeats {
        let summary = match (scene.build()?, concrete) {
            (AnyModel::Ball(ball), true) => run(ball, &scene)?,
            (AnyModel::Woodpecker(w), true) => run(w, &scene)?,
            (AnyModel::SliderCrank(w), true) => run(w, &scene)?,
            _ => {
                let mut stepper = scene.stepper()?;
                stepper
                    .run_until(scene.t_end, &mut |_: &StepReport<'_>| ControlFlow::Continue(()))?
            }
        };
        steps += summary.steps;
    }
    let secs = start.elapsed().as_secs_f64();
    println!("{kind}: {steps} steps in {secs:.3} s, {:.1} ns per step", 1e9 * secs / steps as f64);
    Ok(())
}
