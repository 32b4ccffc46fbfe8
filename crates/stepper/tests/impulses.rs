//! A stepper restarted from a step's end state with that step's impulses goes on as the run
//! that did not stop; without them it starts cold.

use moreau_setvalued::ContactLaw;
use moreau_stepper::{Impulses, StepError, Stepper, StepperOptions};
use moreau_testsupport::Disks;

/// A column of n disks of masses 1, 2, ... a little above each other and above the floor,
/// between walls: it lands and settles in the first few hundred steps.
fn column(n: usize, structured: bool) -> (Disks, Vec<f64>, Vec<f64>) {
    let m = (1..=n).map(|k| k as f64).collect();
    let law = ContactLaw::new(0.0, 0.0, 0.3).unwrap();
    let disks = Disks::new(m, vec![0.1; n], law, structured).with_walls(-0.5, 0.5);
    let centres: Vec<_> = (0..n).map(|k| (0.0, 0.11 + 0.201 * k as f64)).collect();
    let (q, u) = Disks::state_at(&centres);
    (disks, q, u)
}

/// One step's q, u, impulses and contacts reported as impacts.
type Step = (Vec<f64>, Vec<f64>, Impulses, Vec<bool>);

/// The steps of a run, and the most sweeps or pivots of a step.
struct Run {
    steps: Vec<Step>,
    most_iterations: usize,
}

fn run(s: &mut Stepper<Disks>, steps: usize) -> Run {
    let mut most_iterations = 0;
    let steps = (0..steps)
        .map(|_| {
            let r = s.step().unwrap();
            most_iterations = most_iterations.max(r.lcp.map_or(0, |i| i.iterations));
            let impacts = r.contacts.iter().map(|c| c.impact).collect();
            (r.q.to_vec(), r.u.to_vec(), Impulses::of(&r), impacts)
        })
        .collect();
    Run { steps, most_iterations }
}

/// Runs 400 steps, then 40 more on the same stepper and on a new one started from the state
/// after 400 with (`warm`) or without the impulses of that step.
fn restarted(structured: bool, warm: bool) -> (Run, Run) {
    let (disks, q, u) = column(12, structured);
    let options = StepperOptions::new(1e-3);
    let mut whole = Stepper::new(disks, &q, &u, 0.0, options.clone()).unwrap();
    let before = run(&mut whole, 400);
    let last = before.steps.last().unwrap().2.clone();
    assert!(last.contacts.len() >= 12, "the column rests on the floor and on each other: {last:?}");
    let (disks, _, _) = column(12, structured);
    let mut again = Stepper::new(disks, whole.q(), whole.u(), whole.t(), options).unwrap();
    if warm {
        again.set_impulses(&last).unwrap();
    }
    (run(&mut whole, 40), run(&mut again, 40))
}

#[test]
fn a_pile_restarted_with_its_impulses_goes_on_bit_for_bit() {
    let (whole, again) = restarted(true, true);
    for (k, (a, b)) in whole.steps.iter().zip(&again.steps).enumerate() {
        assert_eq!(a, b, "step {k} after the restart");
    }
    assert!(again.most_iterations <= 3, "warm: {} sweeps", again.most_iterations);
    assert!(again.steps.iter().all(|s| s.3.iter().all(|&i| !i)), "a resting column has no impacts");
}

#[test]
fn a_pile_restarted_cold_needs_more_sweeps_and_reports_its_contacts_as_impacts() {
    let (whole, again) = restarted(true, false);
    assert!(whole.most_iterations <= 3, "warm: {} sweeps", whole.most_iterations);
    assert!(again.most_iterations >= 20, "cold: {} sweeps", again.most_iterations);
    let first = &again.steps[0];
    assert!(first.3.iter().filter(|&&i| i).count() >= 3, "impacts: {:?}", first.3);
    assert_ne!(whole.steps[0].0, first.0, "the cold start finds other bits");
}

#[test]
fn the_path_of_fixed_contacts_takes_the_impulses_too() {
    let (whole, again) = restarted(false, true);
    for (k, (a, b)) in whole.steps.iter().zip(&again.steps).enumerate() {
        for (x, y) in a.0.iter().chain(&a.1).zip(b.0.iter().chain(&b.1)) {
            assert!((x - y).abs() <= 1e-12, "step {k}: {x} against {y}");
        }
        assert_eq!(a.3, b.3, "step {k}: the same impacts");
    }
    let (_, cold) = restarted(false, false);
    assert!(cold.steps[0].3.iter().filter(|&&i| i).count() >= 3, "cold: {:?}", cold.steps[0].3);
}

#[test]
fn impulses_a_stepper_cannot_take_are_typed_errors() {
    for structured in [true, false] {
        let (disks, q, u) = column(3, structured);
        let mut s = Stepper::new(disks, &q, &u, 0.0, StepperOptions::new(1e-3)).unwrap();
        let bad = [
            (Impulses { contacts: vec![(3, 0.1, 0.0), (0, 0.1, 0.0)], joints: vec![] }, "follows"),
            (Impulses { contacts: vec![(0, -0.1, 0.0)], joints: vec![] }, "negative P_N"),
            (Impulses { contacts: vec![(0, 0.1, f64::NAN)], joints: vec![] }, "NaN"),
            (Impulses { contacts: vec![], joints: vec![1.0] }, "1 joint impulses for 0"),
        ];
        for (impulses, says) in bad {
            match s.set_impulses(&impulses) {
                Err(StepError::InvalidImpulses { reason }) => {
                    assert!(reason.contains(says), "{reason}")
                }
                other => panic!("{impulses:?}: {other:?}"),
            }
        }
        let beyond = Impulses { contacts: vec![(1_000_000, 0.1, 0.0)], joints: vec![] };
        assert_eq!(s.set_impulses(&beyond).is_err(), !structured, "an index beyond the contacts");
    }
}
