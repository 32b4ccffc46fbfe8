//! Every step of every report model obeys the set-valued laws, checked with
//! `moreau-setvalued`'s own functions rather than with the stepper's LCP.
//!
//! At each step and each contact in the active set, Newton's velocities
//! ξ_N = γ_N,E + ε_N γ_N,A and ξ_T = γ_T,E + ε_T γ_T,A must satisfy −P_N ∈ Upr(ξ_N)
//! (Signorini's law on the velocity level, which is Newton's impact law at an impact) and
//! −P_T ∈ μ P_N Sgn(ξ_T) (Coulomb's law), each within a graph distance of
//! `TOL · (1 + |γ_N,A| + |γ_T,A| + |P_N| + |P_T|)` in the units of the contact. A contact
//! outside the active set carries no impulse at all.

use std::ops::ControlFlow;

use moreau_models::{ModelKind, Scene};
use moreau_setvalued::{ContactLaw, RelativeVelocity, check_impact};
use moreau_stepper::{Mechanism, StepReport};

/// Relative tolerance of the laws: the step's LCP is accepted at a residual of 1e-9 of its
/// data, so a tenth of that margin is left for the velocities recomputed from u_E.
const TOL: f64 = 1e-8;

/// What the check of one model saw.
#[derive(Debug, Default)]
struct Seen {
    steps: usize,
    contact_steps: usize,
    impacts: usize,
    sticks: usize,
    slips: usize,
    worst: f64,
}

fn check_model(kind: ModelKind) -> Seen {
    let scene = Scene::report(kind);
    let laws: Vec<ContactLaw> = scene.build().unwrap().laws().to_vec();
    let mut seen = Seen::default();
    let mut observer = |r: &StepReport<'_>| {
        seen.steps += 1;
        for (i, c) in r.contacts.iter().enumerate() {
            if !c.active {
                assert!(
                    c.p_n == 0.0 && c.p_t == 0.0,
                    "{kind}, step {}, contact {i}: impulse without contact",
                    r.step
                );
                continue;
            }
            seen.contact_steps += 1;
            let pre = RelativeVelocity { gamma_n: c.gamma_n_a, gamma_t: c.gamma_t_a };
            let post = RelativeVelocity { gamma_n: c.gamma_n, gamma_t: c.gamma_t };
            let scale = 1.0 + c.gamma_n_a.abs() + c.gamma_t_a.abs() + c.p_n.abs() + c.p_t.abs();
            let check = check_impact(pre, post, c.p_n, c.p_t, &laws[i], TOL * scale);
            assert!(
                check.holds(),
                "{kind}, step {} (t = {}), contact {i}: {check:?}, report {c:?}",
                r.step,
                r.t
            );
            seen.worst = seen
                .worst
                .max(check.normal_residual / scale)
                .max(check.tangential_residual / scale);
            seen.impacts += usize::from(c.impact);
            if c.p_n > 0.0 && laws[i].is_frictional() {
                // Sticking needs |P_T| ≤ μ P_N; slipping puts P_T on the bound, against ξ_T.
                if check.xi_t.abs() <= TOL * scale {
                    seen.sticks += 1;
                } else {
                    seen.slips += 1;
                    let bound = laws[i].mu() * c.p_n;
                    assert!((c.p_t + bound * check.xi_t.signum()).abs() <= TOL * scale);
                }
            }
        }
        ControlFlow::Continue(())
    };
    scene.run_with(&mut observer).unwrap();
    seen
}

#[test]
fn every_step_of_every_model_obeys_newton_signorini_and_coulomb() {
    for kind in ModelKind::ALL {
        let seen = check_model(kind);
        assert!(seen.steps > 500, "{kind}: {seen:?}");
        assert!(seen.worst <= TOL, "{kind}: {seen:?}");
        // The laws were exercised where the model has contacts: impacts in every model with
        // a contact but Painlevé's rod (which starts on the ground), and stick and slip
        // where the report shows them.
        match kind {
            ModelKind::SliderCrankIdeal => assert_eq!(seen.contact_steps, 0, "{seen:?}"),
            ModelKind::Painleve => assert!(seen.slips > 100, "{kind}: {seen:?}"),
            ModelKind::Woodpecker => {
                assert!(seen.impacts > 10 && seen.sticks > 100 && seen.slips > 100, "{seen:?}")
            }
            ModelKind::SliderCrank => assert!(seen.impacts > 10 && seen.slips > 10, "{seen:?}"),
            ModelKind::Ball | ModelKind::Cam => assert!(seen.impacts > 5, "{kind}: {seen:?}"),
            ModelKind::Declared => unreachable!("not one of the report's models"),
        }
        eprintln!("{kind}: {seen:?}");
    }
}
