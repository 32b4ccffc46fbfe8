//! Runs one scene many times, for profilers: `cargo run --release --example profile_run --
//! MODEL|SCENE.toml REPEATS [concrete] [KEY=VALUE ...]`.
//!
//! MODEL is one of the report's built-in models; a path ending in `.toml` is read as a scene
//! file, hand-derived or declared (`scenes/bodies/ball.toml`). `concrete` steps the model as
//! its own type rather than through the models' enum; each `KEY=VALUE` is a scene override, as
//! `--set` takes it (`projection=false`, `t_end=0.5`).
use std::ops::ControlFlow;

use moreau::models::{AnyModel, Scene};
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
    let name = args.next().unwrap_or_else(|| "woodpecker".into());
    let repeats: usize = args.next().unwrap_or_else(|| "100".into()).parse()?;
    let rest: Vec<String> = args.collect();
    let concrete = rest.first().map(String::as_str) == Some("concrete");
    let mut scene = if name.ends_with(".toml") {
        Scene::from_path(std::path::Path::new(&name))?
    } else {
        Scene::report(name.parse()?)
    };
    if let Ok(t_end) = std::env::var("MOREAU_T_END") {
        scene.set("t_end", &t_end)?;
    }
    for set in &rest[usize::from(concrete)..] {
        let (key, value) = set.split_once('=').ok_or_else(|| format!("{set}: not KEY=VALUE"))?;
        scene.set(key, value)?;
    }
    let start = std::time::Instant::now();
    let mut steps = 0;
    for _ in 0..repeats {
        let summary = match (scene.build()?, concrete) {
            (AnyModel::Ball(ball), true) => run(ball, &scene)?,
            (AnyModel::Woodpecker(w), true) => run(w, &scene)?,
            (AnyModel::SliderCrank(w), true) => run(w, &scene)?,
            (AnyModel::Declared(m), true) => run(m, &scene)?,
            _ => {
                let mut stepper = scene.stepper()?;
                stepper
                    .run_until(scene.t_end, &mut |_: &StepReport<'_>| ControlFlow::Continue(()))?
            }
        };
        steps += summary.steps;
    }
    let secs = start.elapsed().as_secs_f64();
    println!("{name}: {steps} steps in {secs:.3} s, {:.1} ns per step", 1e9 * secs / steps as f64);
    Ok(())
}
