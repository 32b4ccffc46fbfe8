//! Islands that the solvers leave above their tolerance: an error by default, taken and counted
//! within `StepperOptions::inexact_residual`.

use std::ops::ControlFlow;

use moreau_lcp::Status;
use moreau_lcp::fc2d::{Fc2dSolution, Fc2dSolver, Nsgs, NsgsOptions};
use moreau_setvalued::ContactLaw;
use moreau_stepper::{SolverChoice, StepError, StepReport, Stepper, StepperOptions};
use moreau_testsupport::Disks;

/// A column of 12 disks of masses 1, 2, ... dropped from 1 cm apart between walls, μ = 0.3.
fn column() -> (Disks, Vec<f64>, Vec<f64>) {
    let n = 12;
    let m = (1..=n).map(|k| k as f64).collect();
    let law = ContactLaw::new(0.0, 0.0, 0.3).unwrap();
    let disks = Disks::new(m, vec![0.1; n], law, true).with_walls(-0.1001, 0.1001);
    let centres: Vec<_> = (0..n).map(|k| (0.0, 0.11 + 0.21 * k as f64)).collect();
    let (q, u) = Disks::state_at(&centres);
    (disks, q, u)
}

/// Gauss-Seidel with a budget of three sweeps, far too few for its tolerance on the column's
/// impacts.
const STARVED: SolverChoice = SolverChoice::Pgs { tolerance: 1e-12, omega: 1.0, max_iterations: 3 };

fn stepper(inexact: f64) -> Stepper<Disks> {
    let (disks, q, u) = column();
    let options = StepperOptions::new(1e-3).with_solver(STARVED).with_inexact_residual(inexact);
    Stepper::new(disks, &q, &u, 0.0, options).unwrap()
}

/// Each step's (status, LCP residual) of a run to `t_end`, with the run's summary.
fn statuses(
    s: &mut Stepper<Disks>,
    t_end: f64,
) -> (Result<moreau_stepper::RunSummary, StepError>, Vec<(Status, f64)>) {
    let mut seen = Vec::new();
    let mut observe = |r: &StepReport<'_>| {
        if let Some(info) = r.lcp {
            seen.push((info.status, info.residual));
        }
        ControlFlow::Continue(())
    };
    let summary = s.run_until(t_end, &mut observe);
    (summary, seen)
}

#[test]
fn an_island_above_the_tolerance_ends_the_run_by_default() {
    let mut s = stepper(0.0);
    let (summary, seen) = statuses(&mut s, 0.5);
    let Err(StepError::IslandFailed { status, problem, .. }) = summary else {
        panic!("three sweeps to 1e-12 must leave an island unsolved: {summary:?}");
    };
    assert_eq!(status, Status::IterationLimit);
    assert!(seen.iter().all(|(s, _)| *s == Status::Solved), "{seen:?}");
    // The island's problem, solved cold with the same budget, is indeed far from 1e-12.
    let mut nsgs =
        Nsgs::new(NsgsOptions::default().with_tolerance(1e-12).with_max_sweeps(3)).unwrap();
    let mut out = Fc2dSolution::new();
    nsgs.solve_into(problem.view(), None, &mut out).unwrap();
    assert!(out.residual.natural > 1e-9, "{:?}", out.residual);
}

#[test]
fn islands_within_the_inexact_residual_are_taken_and_counted() {
    let mut s = stepper(0.5);
    let (summary, seen) = statuses(&mut s, 0.5);
    let summary = summary.unwrap();
    let inexact: Vec<f64> =
        seen.iter().filter(|(s, _)| *s != Status::Solved).map(|(_, r)| *r).collect();
    for (status, _) in &seen {
        assert!(matches!(status, Status::Solved | Status::IterationLimit), "{status:?}");
    }
    assert!(inexact.len() > 5, "{} inexact steps", inexact.len());
    assert_eq!(summary.inexact_steps, inexact.len() as u64);
    assert_eq!(summary.inexact_residual, inexact.iter().copied().fold(0.0, f64::max));
    assert!(summary.inexact_residual > 1e-12, "{}", summary.inexact_residual);
    assert_eq!(summary.steps, 500);
}

#[test]
fn a_limit_below_what_the_budget_reaches_still_ends_the_run() {
    let mut s = stepper(1e-9);
    let (summary, _) = statuses(&mut s, 0.5);
    let Err(StepError::IslandFailed { problem, .. }) = summary else {
        panic!("three sweeps cannot reach 1e-9 on every impact: {summary:?}");
    };
    assert!(problem.n_contacts() > 1);
}

#[test]
fn the_limit_changes_nothing_where_every_island_is_solved() {
    let run = |inexact: f64| {
        let (disks, q, u) = column();
        let options = StepperOptions::new(1e-3).with_inexact_residual(inexact);
        let mut s = Stepper::new(disks, &q, &u, 0.0, options).unwrap();
        let (summary, seen) = statuses(&mut s, 0.5);
        assert_eq!(summary.unwrap().inexact_steps, 0);
        assert!(seen.iter().all(|(s, _)| *s == Status::Solved));
        (s.q().to_vec(), s.u().to_vec())
    };
    assert_eq!(run(0.0), run(1e-4));
}

#[test]
fn a_limit_outside_zero_to_one_is_refused() {
    for bad in [-1e-6, 1.0, f64::NAN, f64::INFINITY] {
        let (disks, q, u) = column();
        let options = StepperOptions::new(1e-3).with_inexact_residual(bad);
        match Stepper::new(disks, &q, &u, 0.0, options) {
            Err(StepError::InvalidInexactResidual { value }) => {
                assert!(value.to_bits() == bad.to_bits())
            }
            other => panic!("{bad}: {:?}", other.err()),
        }
    }
}

#[test]
fn a_negative_or_non_finite_projection_or_joint_tolerance_is_refused() {
    for bad in [-1e-9, f64::NAN, f64::INFINITY] {
        for joints in [false, true] {
            let (disks, q, u) = column();
            let options = if joints {
                StepperOptions::new(1e-3).with_joint_tolerance(bad)
            } else {
                StepperOptions::new(1e-3).with_projection_tolerance(bad)
            };
            let expected = if joints { "joint_tolerance" } else { "projection_tolerance" };
            match Stepper::new(disks, &q, &u, 0.0, options) {
                Err(StepError::InvalidTolerance { name, value }) => {
                    assert_eq!(name, expected);
                    assert!(value.to_bits() == bad.to_bits());
                }
                other => panic!("{expected} = {bad}: {:?}", other.err()),
            }
        }
    }
}
