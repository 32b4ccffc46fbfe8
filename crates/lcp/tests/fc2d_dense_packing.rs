//! Newton, the proximal point method and pivoting on a step problem of a settling column of
//! disks, whose W is singular (more contact rows than degrees of freedom): the reactions r
//! are not unique there, the velocities u = W r + q are.

use moreau_lcp::Status;
use moreau_lcp::fc2d::{
    Fc2d, Fc2dSolution, Fc2dSolver, LcpRoute, LcpRouteOptions, Newton, NewtonOptions, Proximal,
    ProximalOptions,
};

const TOLERANCE: f64 = 1e-10;

fn column() -> Fc2d {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/moreau/column1000_388.dat");
    Fc2d::read_siconos(std::fs::File::open(path).unwrap()).unwrap()
}

/// The certified pivoting solution: the reference for u.
fn pivoting(problem: &Fc2d) -> Fc2dSolution {
    let options =
        LcpRouteOptions::default().with_tolerance(TOLERANCE).with_max_contacts(usize::MAX);
    let s = LcpRoute::new(options).unwrap().solve(problem).unwrap();
    assert_eq!(s.status, Status::Solved, "{:?}", s.residual);
    s
}

fn max_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

/// Checks a solution against pivoting's: the residual within the tolerance, and the same
/// velocities (r differs where W is singular, u = W r + q does not).
fn assert_agrees(name: &str, s: &Fc2dSolution, reference: &Fc2dSolution) {
    assert_eq!(s.status, Status::Solved, "{name}: {:?}", s.residual);
    assert!(s.residual.natural <= TOLERANCE, "{name}: {:?}", s.residual);
    let du = max_difference(&s.u, &reference.u);
    assert!(du < 1e-8, "{name}: u differs from pivoting's by {du:e}");
}

#[test]
fn the_column_is_solved_by_newton_smoothed_and_by_the_proximal_method() {
    let problem = column();
    assert_eq!(problem.n_contacts(), 388);
    let reference = pivoting(&problem);
    // The reactions are indeterminate: some other r gives the same u.
    let smoothed = Newton::new(
        NewtonOptions::default()
            .with_tolerance(TOLERANCE)
            .with_smoothing_sweeps(20)
            .with_nonmonotone(10),
    )
    .unwrap()
    .solve(&problem)
    .unwrap();
    assert_agrees("newton, smoothed", &smoothed, &reference);
    let proximal = Proximal::new(ProximalOptions::default().with_tolerance(TOLERANCE))
        .unwrap()
        .solve(&problem)
        .unwrap();
    assert_agrees("proximal", &proximal, &reference);
    assert!(proximal.iterations > 0);
}

#[test]
fn monotone_newton_stalls_on_the_column() {
    // The monotone Armijo rule shrinks the step to nothing where contacts at the boundary
    // of two cases flip: the reason for the non-monotone rule and the smoothing sweeps.
    let problem = column();
    let s = Newton::new(
        NewtonOptions::default()
            .with_tolerance(TOLERANCE)
            .with_nonmonotone(1)
            .with_max_iterations(40),
    )
    .unwrap()
    .solve(&problem)
    .unwrap();
    assert_eq!(s.status, Status::IterationLimit);
    assert!(s.residual.natural > 1e-6, "{:?}", s.residual);
}

#[test]
fn proximal_options_are_checked() {
    use moreau_lcp::LcpError;
    for (options, name) in [
        (ProximalOptions::default().with_tolerance(0.0), "tolerance"),
        (ProximalOptions::default().with_max_outer(0), "max_outer"),
        (ProximalOptions::default().with_inner_iterations(0), "inner_iterations"),
        (ProximalOptions::default().with_nonmonotone(0), "nonmonotone"),
        (ProximalOptions::default().with_initial_weight(0.0), "initial_weight"),
        (ProximalOptions::default().with_shrink(1.0), "shrink"),
        (ProximalOptions::default().with_grow(1.0), "grow"),
    ] {
        assert!(
            matches!(Proximal::new(options), Err(LcpError::InvalidOption { name: n, .. }) if n == name)
        );
    }
}
