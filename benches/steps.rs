//! Cost of one Moreau step and of whole simulations of the report's mechanisms.
//!
//! `cargo bench --bench steps` reports, per model, the time of a whole run; dividing by the
//! number of steps (printed in the group names) gives the time per step. The ball, the
//! woodpecker and the slider-crank are also run as their concrete types, without the enum
//! dispatch of scene-built models.

use std::hint::black_box;
use std::ops::ControlFlow;

use criterion::{BatchSize, Criterion, Throughput, criterion_group, criterion_main};
use moreau::models::{AnyModel, ModelKind, Scene};
use moreau::stepper::{Mechanism, StepReport, Stepper, StepperOptions};

/// Runs `kind`'s report scene for `t_end` seconds at step `dt` with a no-op observer, as a
/// scene runs it (`Scene::run_with`: the model built and its own type stepped) and, where
/// given, as a stepper of its concrete type built beforehand (what a user's own `Mechanism`
/// gets).
fn bench_model(c: &mut Criterion, kind: ModelKind, dt: f64, t_end: f64) {
    let mut scene = Scene::report(kind);
    scene.dt = dt;
    scene.t_end = t_end;
    scene.stop_at = None;
    let model = scene.build().expect("report scene builds");
    let steps = (t_end / dt).round() as u64;
    let mut group = c.benchmark_group(format!("simulate/{kind}"));
    group.throughput(Throughput::Elements(steps));
    let name = format!("{steps} steps, dt = {dt:e}");
    let x0 = model.initial_state();
    group.bench_function(&name, |b| {
        b.iter(|| {
            let summary = scene
                .run_with(&mut |_: &StepReport<'_>| ControlFlow::Continue(()))
                .expect("the report scene runs");
            black_box(summary.t_end)
        });
    });
    let concrete = format!("{name}, concrete");
    match model {
        AnyModel::Ball(m) => run_group(&mut group, &concrete, m, &x0, dt, t_end),
        AnyModel::Woodpecker(m) => run_group(&mut group, &concrete, m, &x0, dt, t_end),
        AnyModel::SliderCrank(m) => run_group(&mut group, &concrete, m, &x0, dt, t_end),
        _ => {}
    }
    group.finish();
}

/// One benchmark of a whole run of `model` from its initial state.
fn run_group<M: Mechanism + Clone>(
    group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    name: &str,
    model: M,
    (q0, u0): &(Vec<f64>, Vec<f64>),
    dt: f64,
    t_end: f64,
) {
    group.bench_function(name, |b| {
        b.iter_batched(
            || Stepper::new(model.clone(), q0, u0, 0.0, StepperOptions::new(dt)).unwrap(),
            // The stepper is returned so that it is dropped outside the timed part, as it is
            // built outside it.
            |mut s| {
                s.run_until(t_end, &mut |_: &StepReport<'_>| ControlFlow::Continue(())).unwrap();
                black_box(s.q()[0]);
                s
            },
            BatchSize::LargeInput,
        );
    });
}

/// The bouncing ball written out by hand for this one mechanism: the floor below which a
/// general library should stay within a small factor.
fn specialised_ball(steps: usize, dt: f64) -> f64 {
    let (m, r, g, eps) = (1.0, 0.1, 9.81, 0.9);
    let (mut y, mut v) = (1.0f64, 0.0f64);
    for _ in 0..steps {
        let y_m = y + 0.5 * dt * v;
        let v_free = v - g * dt;
        if y_m - r <= 0.0 {
            let b = v_free + eps * v;
            v = if b < 0.0 { v_free - b * m / m } else { v_free };
        } else {
            v = v_free;
        }
        y = y_m + 0.5 * dt * v;
    }
    y
}

fn steps(c: &mut Criterion) {
    bench_model(c, ModelKind::Ball, 1e-3, 10.0);
    bench_model(c, ModelKind::Woodpecker, 1e-4, 1.0);
    bench_model(c, ModelKind::Cam, 1e-4, 1.0);
    bench_model(c, ModelKind::Painleve, 1e-3, 2.0);
    // Two crank revolutions at 150 rad/s take about 0.13725 s.
    bench_model(c, ModelKind::SliderCrank, 1e-5, 0.13725);
    let mut group = c.benchmark_group("simulate/ball-specialised");
    group.throughput(Throughput::Elements(10_000));
    group.bench_function("10000 steps, dt = 1e-3", |b| {
        b.iter(|| specialised_ball(black_box(10_000), 1e-3))
    });
    group.finish();
}

criterion_group!(benches, steps);
criterion_main!(benches);
