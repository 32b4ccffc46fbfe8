//! The default solver (one contact in closed form, several by the warm-started basis, then
//! Lemke) against Lemke alone on the report's scenes: the same trajectories to round-off,
//! with most LCPs settled without pivoting.

use std::ops::ControlFlow;

use moreau_lcp::Method;
use moreau_models::{ModelKind, Scene};
use moreau_stepper::{SolverChoice, StepReport};

/// Runs `scene` and returns the final (q, u), the number of LCP solves and how many of them
/// were settled without pivoting (closed form or warm basis).
fn run(scene: &Scene) -> (Vec<f64>, Vec<f64>, usize, usize) {
    let mut stepper = scene.stepper().unwrap();
    let (mut solves, mut warm) = (0, 0);
    stepper
        .run_until(scene.t_end, &mut |r: &StepReport<'_>| {
            if let Some(l) = r.lcp.filter(|l| l.method != Method::Trivial) {
                solves += 1;
                warm += usize::from(matches!(l.method, Method::WarmBasis | Method::ClosedForm));
            }
            ControlFlow::Continue(())
        })
        .unwrap();
    (stepper.q().to_vec(), stepper.u().to_vec(), solves, warm)
}

#[test]
fn auto_and_lemke_give_the_same_trajectories_on_the_report_scenes() {
    // Measured: all of the woodpecker's and Painlevé's LCPs are settled without pivoting, 89 %
    // of the slider-crank's. The ball's and the cam's single frictionless contact takes the
    // stepper's scalar path.
    for (kind, t_end) in [
        (ModelKind::Ball, 10.0),
        (ModelKind::Cam, 1.0),
        (ModelKind::Woodpecker, 0.3),
        (ModelKind::SliderCrank, 0.137),
        (ModelKind::Painleve, 1.0),
    ] {
        let mut scene = Scene::report(kind);
        scene.t_end = t_end;
        let (q_auto, u_auto, solves, warm) = run(&scene);
        scene.solver = SolverChoice::Lemke;
        let (q_lemke, u_lemke, lemke_solves, _) = run(&scene);
        assert_eq!(solves, lemke_solves, "{kind}: LCP solves");
        let u_scale = u_lemke.iter().fold(1.0f64, |a, v| a.max(v.abs()));
        for k in 0..q_auto.len() {
            assert!(
                (q_auto[k] - q_lemke[k]).abs() < 1e-10,
                "{kind}: q[{k}] {q_auto:?} vs {q_lemke:?}"
            );
            assert!(
                (u_auto[k] - u_lemke[k]).abs() < 1e-8 * u_scale,
                "{kind}: u[{k}] {u_auto:?} vs {u_lemke:?}"
            );
        }
        assert!(solves > 100, "{kind}: {solves} LCP solves");
        assert!(warm as f64 > 0.8 * solves as f64, "{kind}: warm basis {warm} of {solves}");
        println!("{kind}: {warm} of {solves} LCPs settled without pivoting");
    }
}
