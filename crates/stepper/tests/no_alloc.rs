//! The step loop does not touch the heap once the stepper is built and warmed up.

use std::ops::ControlFlow;

use moreau_stepper::{SolverChoice, StepReport, Stepper, StepperOptions};
use moreau_testsupport::{Ball, CountingAllocator, Rod, allocations_in};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

#[test]
fn stepping_does_not_allocate() {
    let mut ball =
        Stepper::new(Ball::new(0.9), &[1.0], &[0.0], 0.0, StepperOptions::new(1e-3)).unwrap();
    ball.run_until(0.5, &mut |_: &StepReport<'_>| ControlFlow::Continue(())).unwrap();
    let n = allocations_in(|| {
        ball.run_until(10.0, &mut |_: &StepReport<'_>| ControlFlow::Continue(())).unwrap();
    });
    assert_eq!(n, 0, "ball: {n} allocations in 9500 steps");

    // Projected Gauss-Seidel converges slowly on the redundant sticking constraints of the
    // rod lying on both ends; a looser tolerance keeps this test about allocation.
    let pgs = SolverChoice::Pgs { tolerance: 1e-6, omega: 1.0, max_iterations: 100_000 };
    for solver in [SolverChoice::Auto, SolverChoice::Lemke, pgs] {
        let opts = StepperOptions::new(1e-3).with_solver(solver);
        let (q0, u0) = ([0.0, 0.4, 0.3], [1.0, -1.0, 2.0]);
        let mut rod = Stepper::new(Rod::new(0.3, 0.4), &q0, &u0, 0.0, opts).unwrap();
        // A first run sizes every buffer: the rod bounces on one end, then on both, and
        // comes to rest. The same run again must not allocate.
        rod.run_until(3.0, &mut |_: &StepReport<'_>| ControlFlow::Continue(())).unwrap();
        rod.set_state(0.0, &q0, &u0).unwrap();
        let n = allocations_in(|| {
            rod.run_until(3.0, &mut |_: &StepReport<'_>| ControlFlow::Continue(())).unwrap();
        });
        assert_eq!(n, 0, "rod with {solver:?}: {n} allocations");
    }
}

#[test]
fn stepping_a_body_structure_whose_contacts_do_not_change_does_not_allocate() {
    use moreau_setvalued::ContactLaw;
    use moreau_testsupport::Disks;
    // A resting column of ten disks: the same ten contacts at every step.
    let law = ContactLaw::new(0.0, 0.0, 0.3).unwrap();
    let disks = Disks::new(vec![1.0; 10], vec![0.1; 10], law, true).with_walls(-0.5, 0.5);
    let centres: Vec<_> = (0..10).map(|k| (0.0, 0.1 + 0.2 * k as f64)).collect();
    let (q0, u0) = Disks::state_at(&centres);
    // The default chain and pivoting (`Lemke`: the exact LCP route on every island).
    let choices = [SolverChoice::default(), SolverChoice::Lemke];
    for (projection, solver) in [false, true].into_iter().flat_map(|p| choices.map(|c| (p, c))) {
        let opts = StepperOptions::new(1e-3)
            .with_gap_tolerance(1e-9)
            .with_projection(projection)
            .with_solver(solver);
        let mut s = Stepper::new(disks_clone(&disks), &q0, &u0, 0.0, opts).unwrap();
        let mut contacts = 0;
        s.run_until(0.2, &mut |_: &StepReport<'_>| ControlFlow::Continue(())).unwrap();
        let n = allocations_in(|| {
            s.run_until(1.0, &mut |r: &StepReport<'_>| {
                contacts = r.contacts.len();
                ControlFlow::Continue(())
            })
            .unwrap();
        });
        assert_eq!(contacts, 10);
        assert_eq!(n, 0, "projection {projection}, {solver:?}: {n} allocations in 800 steps");
    }
}

fn disks_clone(d: &moreau_testsupport::Disks) -> moreau_testsupport::Disks {
    let law = moreau_stepper::Mechanism::laws(d)[0];
    let (l, r) = d.walls.unwrap();
    moreau_testsupport::Disks::new(d.m.clone(), d.r.clone(), law, true).with_walls(l, r)
}
