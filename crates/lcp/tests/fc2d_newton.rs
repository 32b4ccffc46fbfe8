//! The FC2D Newton and Auto solvers on Siconos' collection, on planted problems with
//! bilateral rows, and against the LCP route.

mod common;

use common::{Rng, fc2d_collection, planted_fc2d, uniqueness_margin};
use faer::Mat;
use faer::linalg::solvers::Solve;
use moreau_lcp::fc2d::{
    Fc2d, Fc2dAuto, Fc2dAutoOptions, Fc2dBuilder, Fc2dResidual, Fc2dSolution, Fc2dSolver, LcpRoute,
    Newton, NewtonOptions, Proximal, Rho,
};
use moreau_lcp::{Method, Status};

/// Files on which Newton from r = 0 does not reach 1e-8, and why.
const NEWTON_FAILURES: &[(&str, &str)] = &[
    (
        "fc2d_granularflowonwall_02020_00213.dat",
        "dense packing: W (printed with six digits) is nearly singular, the Newton steps of \
         the stick contacts leave the region where they are valid and the line search stalls \
         (1.6e-5 after 50 iterations)",
    ),
    (
        "fc2d_granularflowonwall_07002_00801.dat",
        "dense packing: as on 2,020 contacts (5e-4 after 50 iterations)",
    ),
];

/// Iterations Newton is given on the files it solves (the most used: 45, on 367
/// contacts) and on the listed failures (enough to show the stall, few enough for a debug
/// build).
const NEWTON_ITERATIONS: usize = 100;
const NEWTON_FAILURE_ITERATIONS: usize = 8;

fn assert_honest(name: &str, s: &Fc2dSolution, tolerance: f64) {
    assert_eq!(s.status == Status::Solved, s.residual.meets(tolerance), "{name}: {s:?}");
}

#[test]
fn newton_solves_the_collection_or_says_why() {
    for (name, problem) in fc2d_collection() {
        let failure = NEWTON_FAILURES.iter().find(|f| f.0 == name.as_str());
        let max_iterations =
            if failure.is_some() { NEWTON_FAILURE_ITERATIONS } else { NEWTON_ITERATIONS };
        let mut newton =
            Newton::new(NewtonOptions::default().with_max_iterations(max_iterations)).unwrap();
        let s = newton.solve(problem).unwrap();
        assert_honest(name, &s, 1e-8);
        let mut u = vec![0.0; problem.n_rows()];
        let residual = Fc2dResidual::compute(problem.view(), &s.r, &mut u);
        // The reported residual is the residual of r; its round-off is measured only when
        // the tolerance is not met.
        let round_off = if s.residual.natural > 1e-8 { residual.round_off } else { 0.0 };
        assert_eq!(Fc2dResidual { round_off, ..residual }, s.residual, "{name}");
        match failure {
            Some((_, why)) => {
                assert_eq!(s.status, Status::IterationLimit, "{name} ({why})");
                assert!(s.residual.natural > 1e-8, "{name}: {:?}", s.residual);
            }
            None => {
                assert_eq!(s.status, Status::Solved, "{name}: {:?}", s.residual);
                assert!(s.residual.natural <= 1e-8);
                if problem.n_contacts() > 0 && s.iterations > 0 {
                    assert_eq!(s.method, Method::Newton);
                }
            }
        }
    }
}

#[test]
fn auto_reaches_1e_8_on_every_file() {
    let mut auto = Fc2dAuto::default();
    let mut out = Fc2dSolution::new();
    for (name, problem) in fc2d_collection() {
        auto.solve_into(problem.view(), None, &mut out).unwrap();
        assert_eq!(out.status, Status::Solved, "{name}: {:?} by {}", out.residual, out.method);
        assert!(out.residual.natural <= 1e-8, "{name}");
        assert_honest(name, &out, 1e-8);
        let expected = if problem.n_contacts() == 0 {
            Method::Trivial
        } else if name.starts_with("FC2D_SliderCrank") {
            // Gauss-Seidel needs hundreds of sweeps on these two contacts: pivoting is
            // quicker.
            Method::LcpRoute
        } else if name.contains("02020") || name.contains("07002") {
            // Gauss-Seidel alone stalls there: the cluster solves are needed.
            Method::NsgsClusters
        } else {
            Method::Nsgs
        };
        assert_eq!(out.method, expected, "{name}");
        if out.method == Method::NsgsClusters {
            assert!(out.lcp_method.is_some(), "{name}: a cluster was solved by pivoting");
        }
    }
}

#[test]
fn auto_at_a_loose_tolerance_solves_every_file() {
    let mut auto = Fc2dAuto::new(Fc2dAutoOptions::default().with_tolerance(1e-4)).unwrap();
    for (name, problem) in fc2d_collection() {
        let s = auto.solve(problem).unwrap();
        assert_eq!(s.status, Status::Solved, "{name}: {:?}", s.residual);
        assert_honest(name, &s, 1e-4);
    }
}

#[test]
fn newton_agrees_with_the_lcp_route_on_the_small_files() {
    let mut compared = 0;
    for (name, problem) in fc2d_collection() {
        if problem.n_contacts() == 0 || problem.n_contacts() > 100 {
            continue;
        }
        let lcp = LcpRoute::default().solve(problem).unwrap();
        let newton = Newton::new(NewtonOptions::default().with_tolerance(1e-12))
            .unwrap()
            .solve(problem)
            .unwrap();
        assert_eq!(lcp.status, Status::Solved, "{name}");
        assert_eq!(newton.status, Status::Solved, "{name}: {:?}", newton.residual);
        let scale = lcp.r.iter().fold(1e-300f64, |m, v| m.max(v.abs()));
        let diff = lcp.r.iter().zip(&newton.r).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        // These problems have unique reactions: both methods find the same ones.
        assert!(diff <= 1e-6 * scale + 1e-12, "{name}: reactions differ by {diff:e} of {scale:e}");
        compared += 1;
    }
    assert_eq!(compared, 7);
}

#[test]
fn planted_solutions_with_a_joint_are_found() {
    let mut rng = Rng::new(41);
    let mut newton = Newton::new(NewtonOptions::default().with_tolerance(1e-12)).unwrap();
    let mut fixed =
        Newton::new(NewtonOptions::default().with_tolerance(1e-12).with_rho(Rho::Fixed(1.0)))
            .unwrap();
    let mut out = Fc2dSolution::new();
    let mut compared = 0;
    for case in 0..30 {
        let n_c = 1 + case % 10;
        let p = planted_fc2d(n_c, 0.6, true, &mut rng);
        let mut u = vec![0.0; p.r.len()];
        assert!(Fc2dResidual::compute(p.problem.view(), &p.r, &mut u).natural < 1e-13);
        // The planted reactions are the only solution where the certificate holds; elsewhere
        // Newton may find another one, which the residual and the joint rows check.
        let unique = uniqueness_margin(&p.problem) > 0.0;
        for solver in [&mut newton, &mut fixed] {
            solver.solve_into(p.problem.view(), None, &mut out).unwrap();
            assert_eq!(out.status, Status::Solved, "case {case}: {:?}", out.residual);
            assert_eq!(out.method, Method::Newton);
            assert!(out.residual.natural <= 1e-12, "case {case}: {:?}", out.residual);
            let bound = 1e-12 * p.problem.view().q_norm_inf().max(1.0);
            let joint = out.u[2 * n_c].abs().max(out.u[2 * n_c + 1].abs());
            assert!(joint <= bound, "case {case}: joint velocity {joint:e}");
            if unique {
                let diff = out.r.iter().zip(&p.r).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
                assert!(diff < 1e-9, "case {case}: {:?} vs {:?}", out.r, p.r);
                compared += 1;
            }
        }
        let auto = Fc2dAuto::default().solve(&p.problem).unwrap();
        assert_eq!(auto.status, Status::Solved, "case {case}");
    }
    // The certificate holds in 28 of the 30 cases.
    assert_eq!(compared, 2 * 28);
}

#[test]
fn a_newton_solve_does_not_depend_on_the_structures_solved_before() {
    // Twelve block structures (1 to 6 contacts, with and without a joint), more than Newton
    // keeps, cycled three times: each solve gives the bits of a fresh solver's, whether its
    // structure's analysis was kept, rebuilt in place of another's or new.
    let mut rng = Rng::new(43);
    let problems: Vec<Fc2d> =
        (0..12).map(|k| planted_fc2d(1 + k % 6, 0.6, k >= 6, &mut rng).problem).collect();
    let options = NewtonOptions::default().with_tolerance(1e-12);
    let fresh: Vec<Fc2dSolution> =
        problems.iter().map(|p| Newton::new(options.clone()).unwrap().solve(p).unwrap()).collect();
    let mut newton = Newton::new(options).unwrap();
    let mut out = Fc2dSolution::new();
    for round in 0..3 {
        for (k, (p, expected)) in problems.iter().zip(&fresh).enumerate() {
            newton.solve_into(p.view(), None, &mut out).unwrap();
            assert_eq!(out.status, Status::Solved, "round {round}, problem {k}");
            let bits = |r: &[f64]| r.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&out.r), bits(&expected.r), "round {round}, problem {k}");
            assert_eq!(out.iterations, expected.iterations);
        }
    }
}

#[test]
fn newton_from_the_solution_takes_no_iteration_and_keeps_its_history() {
    let mut rng = Rng::new(43);
    let p = planted_fc2d(8, 0.5, true, &mut rng);
    let mut newton =
        Newton::new(NewtonOptions::default().with_tolerance(1e-12).with_keep_history(true))
            .unwrap();
    let mut out = Fc2dSolution::new();
    newton.solve_into(p.problem.view(), None, &mut out).unwrap();
    assert_eq!(out.status, Status::Solved);
    assert_eq!(out.history.len(), out.iterations);
    assert_eq!(*out.history.last().unwrap(), out.residual.natural);
    // Semismooth Newton converges fast once the contact modes are right: the last step
    // gains many digits at once.
    let n = out.history.len();
    assert!(n >= 2 && out.history[n - 1] < 1e-3 * out.history[n - 2], "{:?}", out.history);
    let r = out.r.clone();
    newton.solve_into(p.problem.view(), Some(&r), &mut out).unwrap();
    assert_eq!((out.status, out.iterations), (Status::Solved, 0));
    // A wrong warm start is an error.
    assert!(newton.solve_into(p.problem.view(), Some(&r[1..]), &mut out).is_err());
}

#[test]
fn an_iteration_limit_is_an_honest_status() {
    let mut rng = Rng::new(47);
    let p = planted_fc2d(10, 0.8, true, &mut rng);
    let s = Newton::new(NewtonOptions::default().with_max_iterations(1).with_tolerance(1e-14))
        .unwrap()
        .solve(&p.problem)
        .unwrap();
    assert_eq!((s.status, s.iterations), (Status::IterationLimit, 1));
    assert!(s.residual.natural > 1e-14);
    // A zero W with an approaching contact has no solution: never reported solved.
    let problem = Fc2d::from_dense(Mat::<f64>::zeros(2, 2).as_ref(), &[-1.0, 0.0], &[0.5]).unwrap();
    let s = Newton::new(NewtonOptions::default().with_max_iterations(20))
        .unwrap()
        .solve(&problem)
        .unwrap();
    assert_ne!(s.status, Status::Solved);
    let s = Fc2dAuto::new(Fc2dAutoOptions::default().with_max_sweeps(200))
        .unwrap()
        .solve(&problem)
        .unwrap();
    assert_ne!(s.status, Status::Solved);
}

#[test]
fn auto_options_are_checked() {
    for (options, name) in [
        (Fc2dAutoOptions::default().with_tolerance(0.0), "tolerance"),
        (Fc2dAutoOptions::default().with_window(0), "window"),
        (Fc2dAutoOptions::default().with_max_sweeps(0), "max_sweeps"),
        (Fc2dAutoOptions::default().with_stall_factor(1.0), "stall_factor"),
        (Fc2dAutoOptions::default().with_omega(2.0), "omega"),
    ] {
        let result = Fc2dAuto::new(options);
        assert!(
            matches!(result, Err(moreau_lcp::LcpError::InvalidOption { name: n, .. }) if n == name),
            "{name}: {result:?}"
        );
    }
}

/// Six links of 0.5 m hinged end to end from the ground and lying along x, their masses
/// alternating between 1 kg and `ratio` (so that the last link weighs `ratio`): six revolute
/// joints of two rows each, and q such that every joint transmits the pull Λ = (`pull`, 0)
/// with u = W Λ + q = 0. The pull cancels on every link but the last, so that q is of
/// order `pull / ratio` while W Λ sums terms of order `pull`.
fn pulled_chain(ratio: f64, pull: f64) -> Fc2d {
    let (links, half) = (6, 0.25);
    let rows = 2 * links;
    // H: joint k ties link k - 1's end (+half, 0) to link k's start (-half, 0); joint 0 ties
    // link 0 to the ground at the origin. For a link along x, the velocity of a point at
    // (a, 0) of it is (v_x, v_y + a ω).
    let mut h = Mat::<f64>::zeros(rows, 3 * links);
    for k in 0..links {
        h[(2 * k, 3 * k)] = 1.0;
        h[(2 * k + 1, 3 * k + 1)] = 1.0;
        h[(2 * k + 1, 3 * k + 2)] = -half;
        if k > 0 {
            h[(2 * k, 3 * (k - 1))] = -1.0;
            h[(2 * k + 1, 3 * (k - 1) + 1)] = -1.0;
            h[(2 * k + 1, 3 * (k - 1) + 2)] = -half;
        }
    }
    let inverse_mass: Vec<f64> = (0..links)
        .flat_map(|k| {
            let m = if k % 2 == 0 { 1.0 } else { ratio };
            [1.0 / m, 1.0 / m, 12.0 / (m * 4.0 * half * half)]
        })
        .collect();
    let w = Mat::from_fn(rows, rows, |i, j| {
        (0..3 * links).map(|c| h[(i, c)] * inverse_mass[c] * h[(j, c)]).sum::<f64>()
    });
    let lambda: Vec<f64> = (0..rows).map(|i| if i % 2 == 0 { pull } else { 0.0 }).collect();
    let q: Vec<f64> =
        (0..rows).map(|i| -(0..rows).map(|j| w[(i, j)] * lambda[j]).sum::<f64>()).collect();
    let mut builder = Fc2dBuilder::new(0);
    for _ in 0..links {
        builder.bilateral_group(2);
    }
    for i in 0..rows {
        for j in 0..rows {
            if w[(i, j)] != 0.0 {
                builder.add_entry(i, j, w[(i, j)]);
            }
        }
    }
    builder.build(&q, &[]).unwrap()
}

#[test]
fn a_tolerance_below_round_off_is_met_at_round_off() {
    // Links of 10⁶ kg pulled by 10³ N s, which W's entries of order 1 (the light links) turn
    // into velocities of 10³ that must cancel to 1e-15: far below what floating point
    // resolves. A time-stepper's chain of such links used to spend Newton's 50 iterations
    // there at most steps. Started, as a step is, from reactions 1 % off.
    let problem = pulled_chain(1e6, 1e3);
    let warm: Vec<f64> = problem
        .view()
        .q()
        .iter()
        .enumerate()
        .map(|(i, _)| if i % 2 == 0 { 990.0 } else { 0.0 })
        .collect();
    let n = problem.n_rows();
    let dense = problem.view().to_dense();
    let w = Mat::from_fn(n, n, |i, j| dense[i + j * n]);
    let minus_q = Mat::from_fn(n, 1, |i, _| -problem.view().q()[i]);
    let exact = w.full_piv_lu().solve(&minus_q);
    let mut newton = Newton::new(
        NewtonOptions::default()
            .with_tolerance(1e-15)
            .with_max_iterations(50)
            .with_smoothing_sweeps(20)
            .with_nonmonotone(10),
    )
    .unwrap();
    let mut s = Fc2dSolution::new();
    newton.solve_into(problem.view(), Some(&warm), &mut s).unwrap();
    assert_eq!(s.status, Status::Solved, "{s:?}");
    assert!(s.iterations < 50, "{} iterations", s.iterations);
    // Met at round-off, not at the tolerance: 4 ε times the terms of 10³.
    let res = s.residual;
    assert!(res.natural > 1e-15 && res.natural <= res.round_off, "{res:?}");
    assert!(res.round_off > 4.0 * f64::EPSILON * 1e3 && res.round_off < 1e-11, "{res:?}");
    // And the reactions are those of the linear solve, to the conditioning of W.
    for i in 0..n {
        let e = (s.r[i] - exact[(i, 0)]).abs();
        assert!(e <= 1e-6, "row {i}: {} vs {}", s.r[i], exact[(i, 0)]);
    }
    // Reactions and velocities of order 1 have a round-off far below any tolerance: a tight
    // tolerance is met as asked.
    let light = pulled_chain(1.0, 1.0);
    let s =
        Newton::new(NewtonOptions::default().with_tolerance(1e-14)).unwrap().solve(&light).unwrap();
    assert_eq!(s.status, Status::Solved);
    let mut u = vec![0.0; n];
    let measured = Fc2dResidual::compute(light.view(), &s.r, &mut u);
    assert!(measured.natural <= 1e-14 && measured.round_off < 1e-14, "{measured:?}");
}

/// The residual of a candidate off the solution in closed form. One contact, μ = 0.5,
/// W = [2 −1; −1 3], q = (−1, 4), r = (1, 0.5): u = W r + q = (0.5, 4.5), De Saxcé's point
/// r − (u + μ |u_T| e_N) = (−1.75, −4) projects onto the cone's edge (1, −μ) at (0.2, −0.1),
/// so F = (0.8, 0.6) and ‖F‖ = 1. The rows' terms |W| |r| + |q| + |r| are 2.5 + 1 + 1 and
/// 2.5 + 4 + 0.5: round-off is 4 ε · 7 / ‖q‖∞.
#[test]
fn the_residual_of_a_candidate_off_the_solution_is_its_closed_form() {
    let w = Mat::from_fn(2, 2, |i, j| [[2.0, -1.0], [-1.0, 3.0]][i][j]);
    let problem = Fc2d::from_dense(w.as_ref(), &[-1.0, 4.0], &[0.5]).expect("valid problem");
    let mut u = vec![0.0; 2];
    let res = Fc2dResidual::compute(problem.view(), &[1.0, 0.5], &mut u);
    assert_eq!(u, [0.5, 4.5]);
    assert!((res.absolute - 1.0).abs() <= 1e-15, "{res:?}");
    assert!((res.natural - 0.25).abs() <= 1e-15, "{res:?}");
    // Siconos' error divides by the largest of ‖r‖₂ = 1.12, ‖u‖₂ = 4.53 and ‖q‖₂ = 4.12.
    assert!((res.siconos - 1.0 / 20.5f64.sqrt()).abs() <= 1e-15, "{res:?}");
    assert_eq!(res.worst_group, 0);
    assert_eq!(res.round_off, 4.0 * f64::EPSILON * 7.0 / 4.0);
    assert!(res.meets(0.3) && !res.meets(0.2));
    // r = 0, with u = q, is no solution either (u_N < 0): its round-off is that of q alone.
    let res = Fc2dResidual::compute(problem.view(), &[0.0, 0.0], &mut u);
    assert!(res.natural > 0.0);
    assert_eq!(res.round_off, 4.0 * f64::EPSILON * 4.0 / 4.0);
}

#[test]
fn a_residual_beyond_the_range_of_f64_meets_no_tolerance() {
    // One contact pressed into the ground, W = I, μ = 0.5: r = (1, 0), u = 0. Started from
    // r = (1e300, 0), a point of the cone whose natural map squares beyond f64's range.
    let problem = Fc2d::from_dense(Mat::<f64>::identity(2, 2).as_ref(), &[-1.0, 0.0], &[0.5])
        .expect("valid problem");
    let warm = [1e300, 0.0];
    let mut u = vec![0.0; 2];
    let measured = Fc2dResidual::compute(problem.view(), &warm, &mut u);
    assert!(measured.natural.is_infinite() && measured.round_off.is_infinite(), "{measured:?}");
    assert!(!measured.meets(1e-8) && !measured.meets(f64::MAX));
    // Newton and the proximal method start from it: they end on the solution or say that
    // they did not, never `Solved` at r = 1e300.
    let solvers: [(&str, Box<dyn Fc2dSolver>); 2] =
        [("newton", Box::new(Newton::default())), ("proximal", Box::new(Proximal::default()))];
    for (name, mut solver) in solvers {
        let mut s = Fc2dSolution::new();
        solver.solve_into(problem.view(), Some(&warm), &mut s).unwrap();
        assert_honest(name, &s, 1e-8);
        if s.is_solved() {
            assert!((s.r[0] - 1.0).abs() <= 1e-8 && s.r[1].abs() <= 1e-8, "{name}: {s:?}");
        } else {
            assert!(s.status == Status::NumericalFailure, "{name}: {s:?}");
        }
    }
    // A round-off that is not finite does not stand in for the tolerance either.
    let r = Fc2dResidual { natural: 1.0, round_off: f64::INFINITY, ..Fc2dResidual::default() };
    assert!(!r.meets(1e-8) && r.meets(1.0));
}
