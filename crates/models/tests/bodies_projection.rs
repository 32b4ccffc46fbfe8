//! The projection of a declared mechanism keeps resting contacts closed: the woodpecker's
//! sleeve, pressed against the pole by the bird, closes its bore's edges about as often in
//! 1.5 s as the hand-derived model's do, and its joints stay assembled.

use std::ops::ControlFlow;

use moreau_kinematics::ContactKinematics;
use moreau_models::{ModelKind, Scene};
use moreau_stepper::StepReport;

const WOODPECKER: &str = include_str!("../../../scenes/bodies/woodpecker.toml");

/// Contact onsets (a normal impulse after a step without one) of each contact over 1.5 s, and
/// the largest joint drift.
fn onsets(scene: &Scene) -> (Vec<usize>, f64) {
    let mut stepper = scene.stepper().expect("scene steps");
    let n = stepper.mechanism().num_contacts();
    let (mut count, mut closed, mut drift) = (vec![0; n], vec![false; n], 0.0f64);
    stepper
        .run_until(1.5, &mut |s: &StepReport<'_>| {
            for (i, c) in s.contacts.iter().enumerate() {
                let now = c.p_n > 0.0;
                count[i] += usize::from(now && !closed[i]);
                closed[i] = now;
            }
            drift = drift.max(s.joint_drift);
            ControlFlow::Continue(())
        })
        .expect("run");
    (count, drift)
}

#[test]
fn the_projected_sleeve_rests_as_the_hand_models_does() {
    let declared = Scene::from_toml_str(WOODPECKER).expect("scene reads");
    assert!(declared.projection, "the scene ships with the projection");
    let (declared_onsets, drift) = onsets(&declared);
    let (hand_onsets, _) = onsets(&Scene::report(ModelKind::Woodpecker));
    // Contacts 2 and 3 of both are the sleeve's lower and upper edges. With the joints'
    // projection opening the resting edge, the lower edge closed 313 times in 1.5 s against
    // the hand model's 21.
    let sleeve = |c: &[usize]| c[1] + c[2];
    let (d, h) = (sleeve(&declared_onsets), sleeve(&hand_onsets));
    assert!(h > 0, "the hand model's sleeve touches the pole");
    assert!(d <= 2 * h, "declared sleeve onsets {declared_onsets:?}, hand {hand_onsets:?}");
    // The drift at each midpoint, after the previous step's projection, stays far below the
    // bore's clearance of 6e-4 m.
    assert!(drift < 1e-7, "joint drift {drift:e}");
}
