//! Time per step of the report's mechanisms declared as scene files (`scenes/bodies/`) next to
//! their hand-derived models, each run as its concrete type from the same initial state, at the
//! same Δt and with the scene's options.
//!
//! `cargo bench --bench declared`; criterion's throughput gives the steps per second.

use std::hint::black_box;
use std::ops::ControlFlow;

use criterion::{BatchSize, Criterion, Throughput, criterion_group, criterion_main};
use moreau::models::{AnyModel, ModelKind, Scene};
use moreau::stepper::{Mechanism, StepReport, Stepper, StepperOptions};

/// One benchmark of a run of `model` over `t_end` seconds.
fn run_group<M: Mechanism + Clone>(
    group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    name: &str,
    model: M,
    (q0, u0): &(Vec<f64>, Vec<f64>),
    options: StepperOptions,
    t_end: f64,
) {
    group.bench_function(name, |b| {
        b.iter_batched(
            || Stepper::new(model.clone(), q0, u0, 0.0, options.clone()).unwrap(),
            |mut s| {
                s.run_until(t_end, &mut |_: &StepReport<'_>| ControlFlow::Continue(())).unwrap();
                black_box(s.q()[0]);
                s
            },
            BatchSize::LargeInput,
        );
    });
}

/// The hand-derived model of `kind` and its declared scene, both for `t_end` seconds.
fn pair(c: &mut Criterion, kind: ModelKind, text: &str, t_end: f64) {
    let hand = Scene::report(kind);
    let declared = Scene::from_toml_str(text).expect("declared scene reads");
    let steps = (t_end / hand.dt).round() as u64;
    let mut group = c.benchmark_group(format!("declared/{kind}"));
    group.throughput(Throughput::Elements(steps));
    // The declared scene as shipped and, when it projects onto the joints and contacts after
    // each step (which the hand-derived models do not), also without the projection.
    let mut unprojected = declared.clone();
    unprojected.projection = false;
    let mut runs = vec![("hand-derived", &hand), ("declared", &declared)];
    if declared.projection {
        runs.push(("declared without projection", &unprojected));
    }
    for (label, scene) in runs {
        let model = scene.build().expect("scene builds");
        let x0 = model.initial_state();
        let options = scene.stepper_options();
        let name = format!("{label}, {steps} steps, dt = {:e}", scene.dt);
        match model {
            AnyModel::Ball(m) => run_group(&mut group, &name, m, &x0, options, t_end),
            AnyModel::Woodpecker(m) => run_group(&mut group, &name, m, &x0, options, t_end),
            AnyModel::Declared(m) => run_group(&mut group, &name, m, &x0, options, t_end),
            other => run_group(&mut group, &name, other, &x0, options, t_end),
        }
    }
    group.finish();
}

fn declared(c: &mut Criterion) {
    pair(c, ModelKind::Ball, include_str!("../scenes/bodies/ball.toml"), 10.0);
    pair(c, ModelKind::Woodpecker, include_str!("../scenes/bodies/woodpecker.toml"), 1.0);
}

criterion_group!(benches, declared);
criterion_main!(benches);
