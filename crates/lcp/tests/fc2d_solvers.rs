//! The FC2D solvers on Siconos' collection, on planted solutions and on random problems.

mod common;

use common::{Rng, chain_w, fc2d_collection, planted_fc2d, uniqueness_margin};
use faer::Mat;
use moreau_lcp::fc2d::{
    Fc2d, Fc2dAuto, Fc2dAutoOptions, Fc2dBuilder, Fc2dResidual, Fc2dSolution, Fc2dSolver, LcpRoute,
    LcpRouteOptions, LcpRouteSolver, Newton, Nsgs, NsgsOptions, SiconosStorage,
};
use moreau_lcp::{LcpError, MAX_ENTRY, Method, Status};

/// Sweep limit within which NSGS reaches 1e-4 on every file (the most measured: 628
/// sweeps, on 7,002 contacts).
const LOOSE_SWEEPS: usize = 2_000;

/// Files on which NSGS does not reach 1e-8 within `TIGHT_SWEEPS`, and why.
const NSGS_TIGHT_FAILURES: &[(&str, &str)] = &[
    (
        "fc2d_granularflowonwall_02020_00213.dat",
        "Gauss-Seidel stalls near 5e-7 on a few clusters of contacts (still 5.5e-7 after 100,000 sweeps)",
    ),
    (
        "fc2d_granularflowonwall_07002_00801.dat",
        "Gauss-Seidel stalls near 5e-8 on a few clusters of contacts (still 4.7e-8 after 100,000 sweeps)",
    ),
];
const TIGHT_SWEEPS: usize = 2_000;

/// The LCP route is run on files with at most this many contacts (a dense LCP of 3 n_c
/// rows: 0.05 s at 89 contacts, about (3 n_c)³ beyond).
const LCP_MAX_CONTACTS: usize = 100;

fn nsgs(tolerance: f64, max_sweeps: usize) -> Nsgs {
    Nsgs::new(NsgsOptions::default().with_tolerance(tolerance).with_max_sweeps(max_sweeps)).unwrap()
}

fn assert_honest(name: &str, s: &Fc2dSolution, tolerance: f64) {
    assert_eq!(s.status == Status::Solved, s.residual.meets(tolerance), "{name}: {s:?}");
}

/// Every contact's r lies in its Coulomb cone exactly: r_N >= 0 and |r_T| <= μ r_N.
fn assert_in_cones(name: &str, problem: &Fc2d, s: &Fc2dSolution) {
    for (i, &mu) in problem.view().mu().iter().enumerate() {
        let (n, t) = (s.r[2 * i], s.r[2 * i + 1]);
        assert!(n >= 0.0 && t.abs() <= mu * n, "{name}: contact {i}: r = ({n:e}, {t:e}), μ = {mu}");
    }
}

#[test]
fn nsgs_reaches_a_loose_tolerance_on_every_file() {
    for (name, problem) in fc2d_collection() {
        let s = nsgs(1e-4, LOOSE_SWEEPS).solve(problem).unwrap();
        assert_eq!(s.status, Status::Solved, "{name}: {:?} after {}", s.residual, s.iterations);
        assert!(s.residual.natural <= 1e-4);
        assert_honest(name, &s, 1e-4);
    }
}

#[test]
fn nsgs_at_a_tight_tolerance_fails_only_where_listed() {
    for (name, problem) in fc2d_collection() {
        let s = nsgs(1e-8, TIGHT_SWEEPS).solve(problem).unwrap();
        assert_honest(name, &s, 1e-8);
        match NSGS_TIGHT_FAILURES.iter().find(|f| f.0 == name.as_str()) {
            Some((_, why)) => {
                assert_eq!(s.status, Status::IterationLimit, "{name} ({why})");
                assert!(s.residual.natural < 1e-5, "{name}: {:?}", s.residual);
            }
            None => assert_eq!(s.status, Status::Solved, "{name}: {:?}", s.residual),
        }
    }
}

#[test]
fn lcp_route_solves_the_small_files_and_agrees_with_nsgs() {
    let mut compared = 0;
    for (name, problem) in fc2d_collection() {
        if problem.n_contacts() > LCP_MAX_CONTACTS {
            continue;
        }
        let lcp = LcpRoute::default().solve(problem).unwrap();
        assert_eq!(lcp.status, Status::Solved, "{name}: {:?}", lcp.residual);
        assert_eq!(lcp.method, Method::LcpRoute);
        assert_honest(name, &lcp, 1e-8);
        assert_in_cones(name, problem, &lcp);
        let gs = nsgs(1e-10, 100_000).solve(problem).unwrap();
        assert_in_cones(name, problem, &gs);
        assert_eq!(gs.status, Status::Solved, "{name}");
        let scale = lcp.r.iter().fold(1e-300f64, |m, v| m.max(v.abs()));
        let diff = lcp.r.iter().zip(&gs.r).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        println!(
            "{name}: {} contacts, reactions differ by {:.1e} of {scale:.1e}",
            problem.n_contacts(),
            diff
        );
        // On every file small enough the two find the same reactions.
        assert!(diff <= 1e-6 * scale, "{name}: {diff:e} of {scale:e}");
        compared += 1;
    }
    assert_eq!(compared, 8);
}

#[test]
fn planted_solutions_are_found() {
    let mut rng = Rng::new(7);
    let mut compared = 0;
    for case in 0..40 {
        let n_c = 1 + case % 12;
        let p = planted_fc2d(n_c, 0.5, false, &mut rng);
        let mut u = vec![0.0; 2 * n_c];
        assert!(Fc2dResidual::compute(p.problem.view(), &p.r, &mut u).natural < 1e-14);
        // The planted r is the only solution where the certificate holds (all but one case,
        // whose margin is −0.038); elsewhere a solver may find another one, so r is checked
        // only for being a solution.
        let unique = uniqueness_margin(&p.problem) > 0.0;
        for solver in [&mut nsgs(1e-10, 100_000) as &mut dyn Fc2dSolver, &mut LcpRoute::default()] {
            let s = solver.solve(&p.problem).unwrap();
            assert_eq!(s.status, Status::Solved, "case {case}: {:?}", s.residual);
            assert_honest("planted", &s, if s.method == Method::Nsgs { 1e-10 } else { 1e-8 });
            assert_in_cones("planted", &p.problem, &s);
            if unique {
                // Pivoting finds r to round-off (1.6e-15 at most), NSGS at its tolerance
                // 1e-10 to 3.3e-10.
                let bound = if s.method == Method::Nsgs { 1e-9 } else { 1e-12 };
                let diff = s.r.iter().zip(&p.r).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
                assert!(diff < bound, "case {case}, {:?}: {:?} vs {:?}", s.method, s.r, p.r);
                compared += 1;
            }
        }
    }
    assert_eq!(compared, 2 * 39);
}

#[test]
fn frictionless_contacts_are_the_normal_lcp() {
    // With μ = 0 the normal reactions solve LCP(W_NN, q_N) and r_T = 0.
    let mut rng = Rng::new(11);
    for _ in 0..10 {
        let n_c = 5;
        let w = chain_w(n_c, false, &mut rng);
        let q: Vec<f64> = (0..2 * n_c).map(|_| rng.uniform(-1.0, 1.0)).collect();
        let problem = Fc2d::from_dense(w.as_ref(), &q, &vec![0.0; n_c]).unwrap();
        let s = nsgs(1e-12, 100_000).solve(&problem).unwrap();
        assert_eq!(s.status, Status::Solved);
        let wnn = Mat::from_fn(n_c, n_c, |i, j| w[(2 * i, 2 * j)]);
        let lcp = moreau_lcp::Lcp::new(wnn, faer::Col::from_fn(n_c, |i| q[2 * i])).unwrap();
        let z = moreau_lcp::Solver::solve(&mut moreau_lcp::Auto::default(), &lcp).unwrap().z;
        for i in 0..n_c {
            assert!((s.r[2 * i] - z[i]).abs() < 1e-9, "{} vs {}", s.r[2 * i], z[i]);
            assert_eq!(s.r[2 * i + 1], 0.0);
        }
    }
}

#[test]
fn frictionless_contacts_without_tangential_rows_are_the_normal_lcp() {
    // The contact projection's problems: μ = 0, W_T = 0 and q_T = 0, so that u_T = 0
    // exactly. The cone of μ = 0 is the half-line r_T = 0 <= r_N, and an open contact
    // (r_N = 0 < u_N) meets the law. The projection onto the cone took (x_N, 0) with
    // x_N < 0 for a point of it (|0| <= 0 · x_N), so that every open contact counted u_N
    // in the natural residual and Gauss-Seidel could leave r_N < 0.
    let mut rng = Rng::new(12);
    let mut open = 0;
    for _ in 0..10 {
        let n_c = 5;
        let chain = chain_w(n_c, false, &mut rng);
        let normal = |i: usize, j: usize| i.is_multiple_of(2) && j.is_multiple_of(2);
        let w =
            Mat::from_fn(2 * n_c, 2 * n_c, |i, j| if normal(i, j) { chain[(i, j)] } else { 0.0 });
        let q: Vec<f64> = (0..2 * n_c)
            .map(|k| if k.is_multiple_of(2) { rng.uniform(-1.0, 1.0) } else { 0.0 })
            .collect();
        let problem = Fc2d::from_dense(w.as_ref(), &q, &vec![0.0; n_c]).unwrap();
        let wnn = Mat::from_fn(n_c, n_c, |i, j| w[(2 * i, 2 * j)]);
        let lcp = moreau_lcp::Lcp::new(wnn, faer::Col::from_fn(n_c, |i| q[2 * i])).unwrap();
        let z = moreau_lcp::Solver::solve(&mut moreau_lcp::Auto::default(), &lcp).unwrap().z;
        let exact: Vec<f64> =
            (0..2 * n_c).map(|k| if k % 2 == 0 { z[k / 2] } else { 0.0 }).collect();
        let mut u = vec![0.0; 2 * n_c];
        let residual = Fc2dResidual::compute(problem.view(), &exact, &mut u);
        open += (0..n_c).filter(|&i| exact[2 * i] == 0.0 && u[2 * i] > 1e-3).count();
        assert!(residual.natural <= 1e-14, "{residual:?}");
        let route = LcpRoute::default().solve(&problem).unwrap();
        let gs = nsgs(1e-12, 100_000).solve(&problem).unwrap();
        for (name, s) in [("lcp route", &route), ("nsgs", &gs)] {
            assert_eq!(s.status, Status::Solved, "{name}: {s:?}");
            assert_in_cones(name, &problem, s);
            for i in 0..n_c {
                assert!((s.r[2 * i] - z[i]).abs() < 1e-9, "{name}: {} vs {}", s.r[2 * i], z[i]);
            }
        }
    }
    assert!(open >= 10, "only {open} open contacts");
}

#[test]
fn bilateral_rows_hold_and_both_solvers_agree() {
    // Two contacts and a two-row joint sharing bodies, built from a random Jacobian.
    let mut rng = Rng::new(23);
    for _ in 0..20 {
        let rows = 6;
        let h = Mat::from_fn(rows, 6, |_, _| rng.uniform(-1.0, 1.0));
        let mut w = &h * h.transpose();
        for i in 0..rows {
            w[(i, i)] += 0.1;
        }
        let mut b = Fc2dBuilder::new(2);
        b.bilateral_group(2);
        for i in 0..rows {
            for j in 0..rows {
                b.add_entry(i, j, w[(i, j)]);
            }
        }
        let q: Vec<f64> = (0..rows).map(|_| rng.uniform(-1.0, 1.0)).collect();
        let problem = b.build(&q, &[0.3, 0.6]).unwrap();
        let gs = nsgs(1e-11, 100_000).solve(&problem).unwrap();
        let lcp = LcpRoute::new(LcpRouteOptions::default().with_tolerance(1e-9))
            .unwrap()
            .solve(&problem)
            .unwrap();
        assert_eq!(gs.status, Status::Solved);
        assert_eq!(lcp.status, Status::Solved);
        assert!(gs.u[4].abs() < 1e-10 && gs.u[5].abs() < 1e-10);
        let diff = gs.r.iter().zip(&lcp.r).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(diff < 1e-6, "{:?} vs {:?}", gs.r, lcp.r);
        // The contacts alone, the joint eliminated: the same contact reactions, by
        // Gauss-Seidel on the reduced problem, which Siconos' format can hold.
        let reduced = problem.view().without_bilateral().unwrap();
        assert_eq!((reduced.n_contacts(), reduced.n_rows()), (2, 4));
        let mut text = Vec::new();
        reduced.write_siconos(&mut text, SiconosStorage::SparseBlock).unwrap();
        assert_eq!(Fc2d::read_siconos(&text[..]).unwrap(), reduced);
        let alone = nsgs(1e-11, 100_000).solve(&reduced).unwrap();
        assert_eq!(alone.status, Status::Solved);
        for (a, b) in alone.r.iter().zip(&gs.r[..4]) {
            assert!((a - b).abs() < 1e-6, "{:?} vs {:?}", alone.r, gs.r);
        }
    }
}

#[test]
fn redundant_bilateral_rows_end_the_lcp_route_as_a_numerical_failure() {
    // A two-row joint whose rows repeat each other: W_bb is singular, its multipliers are
    // undetermined, and the route says so instead of returning one of them.
    let mut rng = Rng::new(29);
    let mut h = Mat::from_fn(6, 6, |_, _| rng.uniform(-1.0, 1.0));
    for k in 0..6 {
        h[(5, k)] = h[(4, k)];
    }
    let mut w = &h * h.transpose();
    for i in 0..4 {
        w[(i, i)] += 0.1;
    }
    let mut b = Fc2dBuilder::new(2);
    b.bilateral_group(2);
    for i in 0..6 {
        for j in 0..6 {
            b.add_entry(i, j, w[(i, j)]);
        }
    }
    let q: Vec<f64> = (0..6).map(|_| rng.uniform(-1.0, 1.0)).collect();
    let problem = b.build(&q, &[0.3, 0.6]).unwrap();
    let s = LcpRoute::default().solve(&problem).unwrap();
    assert_eq!(s.status, Status::NumericalFailure);
    assert!(matches!(problem.view().without_bilateral(), Err(LcpError::Structure(_))));
    // With the repeated row dropped the same problem is regular and solved.
    w[(5, 5)] += 0.1;
    let mut b = Fc2dBuilder::new(2);
    b.bilateral_group(2);
    for i in 0..6 {
        for j in 0..6 {
            b.add_entry(i, j, w[(i, j)]);
        }
    }
    let s = LcpRoute::default().solve(&b.build(&q, &[0.3, 0.6]).unwrap()).unwrap();
    assert_eq!(s.status, Status::Solved);
}

#[test]
fn warm_start_from_a_solution_takes_one_sweep_and_history_is_kept() {
    let mut rng = Rng::new(3);
    let p = planted_fc2d(8, 0.4, false, &mut rng);
    let mut solver = Nsgs::new(
        NsgsOptions::default()
            .with_tolerance(1e-12)
            .with_max_sweeps(100_000)
            .with_keep_history(true),
    )
    .unwrap();
    let mut out = Fc2dSolution::new();
    solver.solve_into(p.problem.view(), None, &mut out).unwrap();
    assert_eq!(out.status, Status::Solved);
    assert_eq!(out.history.len(), out.iterations);
    assert_eq!(*out.history.last().unwrap(), out.residual.natural);
    let r = out.r.clone();
    solver.solve_into(p.problem.view(), Some(&r), &mut out).unwrap();
    assert_eq!((out.status, out.iterations), (Status::Solved, 1));
    // Over-relaxation changes the path, not the answer.
    let mut relaxed = Nsgs::new(
        NsgsOptions::default().with_tolerance(1e-12).with_max_sweeps(100_000).with_omega(1.3),
    )
    .unwrap();
    let s = relaxed.solve(&p.problem).unwrap();
    assert_eq!(s.status, Status::Solved);
}

#[test]
fn a_sweep_limit_is_an_honest_status() {
    let mut rng = Rng::new(5);
    let p = planted_fc2d(12, 0.5, false, &mut rng);
    let s = nsgs(1e-14, 2).solve(&p.problem).unwrap();
    assert_eq!((s.status, s.iterations), (Status::IterationLimit, 2));
    assert!(s.residual.natural > 1e-14);
    let err =
        nsgs(1e-8, 10).solve_into(p.problem.view(), Some(&[0.0; 3]), &mut Fc2dSolution::new());
    assert!(err.is_err());
}

#[test]
fn lcp_route_reports_size_and_certified_infeasibility() {
    let mut rng = Rng::new(9);
    let p = planted_fc2d(6, 0.5, false, &mut rng);
    let small = LcpRoute::new(LcpRouteOptions::default().with_max_contacts(5)).unwrap();
    let s = { small }.solve(&p.problem).unwrap();
    assert_eq!(s.status, Status::TooLarge);
    // A zero W with an approaching contact: no reaction can stop it.
    let problem = Fc2d::from_dense(Mat::<f64>::zeros(2, 2).as_ref(), &[-1.0, 0.0], &[0.5]).unwrap();
    let mut enumeration =
        LcpRoute::new(LcpRouteOptions::default().with_solver(LcpRouteSolver::Enumeration)).unwrap();
    let s = enumeration.solve(&problem).unwrap();
    assert_eq!(s.status, Status::NoSolution);
    let s = nsgs(1e-8, 50).solve(&problem).unwrap();
    assert_ne!(s.status, Status::Solved);
    // The default solver pivots after its first window of 50 sweeps and reports the proof,
    // at r = 0 (u = q), instead of sweeping its 100,000 to an iteration limit.
    let s = Fc2dAuto::default().solve(&problem).unwrap();
    assert_eq!((s.status, s.method), (Status::NoSolution, Method::LcpRoute));
    assert_eq!((s.r.as_slice(), s.u.as_slice()), ([0.0, 0.0].as_slice(), [-1.0, 0.0].as_slice()));
    assert!(s.iterations < 100, "{} iterations", s.iterations);
    assert_eq!(s.residual.natural, 1.0);
}

#[test]
fn a_friction_coefficient_beyond_the_lcps_range_is_a_status_of_the_lcp_route() {
    // W = I, q = (-1, 0), μ = MAX_ENTRY (3.3e150): the contact sticks with r = (1, 0). The
    // LCP's entry 2 μ is beyond what the LCP solvers take; the problem itself is valid.
    let identity = Mat::<f64>::identity(2, 2);
    let problem = Fc2d::from_dense(identity.as_ref(), &[-1.0, 0.0], &[MAX_ENTRY]).unwrap();
    let s = LcpRoute::default().solve(&problem).unwrap();
    assert_eq!(s.status, Status::NumericalFailure, "{s:?}");
    assert!(s.r == [0.0, 0.0] && s.u == [-1.0, 0.0], "{s:?}");
    // Gauss-Seidel finds it exactly, the default solver (over-relaxed sweeps) to 1e-8.
    let s = Nsgs::default().solve(&problem).unwrap();
    assert!(s.is_solved() && s.r == [1.0, 0.0] && s.u == [0.0, 0.0], "{s:?}");
    let s = Fc2dAuto::default().solve(&problem).unwrap();
    assert!(s.is_solved() && (s.r[0] - 1.0).abs() <= 1e-8 && s.r[1] == 0.0, "{s:?}");
    // With a bilateral row whose elimination stays in range, the same: a status, no error.
    let mut builder = Fc2dBuilder::new(1);
    let joint = builder.bilateral_group(1);
    builder.add_block(0, 0, [1.0, 0.0, 0.0, 1.0]);
    builder.add_block(joint, joint, [1.0, 0.0, 0.0, 0.0]);
    let with_joint = builder.build(&[-1.0, 0.0, 0.5], &[MAX_ENTRY]).unwrap();
    let s = LcpRoute::default().solve(&with_joint).unwrap();
    assert_eq!(s.status, Status::NumericalFailure, "{s:?}");
}

/// An island of 10 contacts of a stack of boxes of 0.2 and 2e5 kg in turn
/// (tests/data/moreau/README.md): impulses of about 2,000 N s cancel through the light boxes.
/// Pivoting ends 5.7e-6 off, Gauss-Seidel and Newton started cold stall far from a solution,
/// and Newton's polish from pivoting's candidate solves it in one iteration; `Fc2dAuto` gets
/// there through the LCP route.
#[test]
fn the_lcp_routes_polish_finishes_a_candidate_that_pivoting_leaves_short() {
    let text = include_str!("data/moreau/stack_mass_ratio_island.dat");
    let problem = Fc2d::read_siconos(text.as_bytes()).unwrap();
    assert_eq!(problem.n_contacts(), 10);
    let route = |polish_iterations| {
        let options = LcpRouteOptions::default()
            .with_tolerance(1e-10)
            .with_polish_iterations(polish_iterations);
        LcpRoute::new(options).unwrap().solve(&problem).unwrap()
    };
    let pivoted = route(0);
    assert_eq!(pivoted.status, Status::NumericalFailure);
    assert!(pivoted.residual.natural > 1e-6 && pivoted.residual.natural < 1e-5, "{pivoted:?}");
    let cold = Newton::default().solve(&problem).unwrap();
    assert!(cold.residual.natural > 1e-3, "{:?}", cold.residual);
    assert!(nsgs(1e-10, 10_000).solve(&problem).unwrap().residual.natural > 1e-3);

    let polished = route(20);
    assert_eq!((polished.status, polished.method), (Status::Solved, Method::LcpRoute));
    assert_eq!(polished.iterations, pivoted.iterations + 1);
    assert_in_cones("polished", &problem, &polished);
    // The residual recomputed from r alone.
    let mut u = vec![0.0; problem.n_rows()];
    let again = Fc2dResidual::compute(problem.view(), &polished.r, &mut u);
    assert!(again.natural <= 1e-10, "{again:?}");
    // Reactions of thousands of N s, agreeing with pivoting's to its residual's order.
    let largest = polished.r.iter().fold(0.0f64, |m, r| m.max(r.abs()));
    assert!(largest > 1e3, "{largest}");
    for (a, b) in polished.r.iter().zip(&pivoted.r) {
        assert!((a - b).abs() <= 1e-2 * largest, "{a} vs {b}");
    }

    let auto = Fc2dAuto::default().solve(&problem).unwrap();
    assert_eq!((auto.status, auto.method), (Status::Solved, Method::LcpRoute));
}

/// A planted chain of two contacts, both slipping in the planted solution, found by the
/// random chains below (seed 247572, n_c = 2, μ_max = 0.889). W is symmetric positive
/// definite, but Coulomb's law is not associated, and Gauss-Seidel's iterates settle into a
/// cycle of period two: contact 1 alternates between r_N = 0.995 and r_N = 0.217, both
/// slipping, 5.4e-2 off a solution however many sweeps are made. Under-relaxation damps the
/// cycle (ω = 0.5 converges to the planted solution), and `Fc2dAuto` goes on to pivoting.
#[test]
fn gauss_seidel_cycles_off_a_solution_on_a_planted_chain_of_two_contacts() {
    let mut rng = Rng::new(247_572);
    let p = planted_fc2d(2, 0.889_161_299_819_068_7, false, &mut rng);
    for sweeps in [100, 10_000] {
        let gs = nsgs(1e-10, sweeps).solve(&p.problem).unwrap();
        assert_eq!(gs.status, Status::IterationLimit);
        assert!((gs.residual.natural - 5.424e-2).abs() < 1e-4, "{sweeps}: {:?}", gs.residual);
    }
    // The iterates after 1,000, 1,001 and 1,002 sweeps: a cycle of period two.
    let after = |sweeps| nsgs(1e-14, sweeps).solve(&p.problem).unwrap().r;
    let (a, b, c) = (after(1_000), after(1_001), after(1_002));
    for k in 0..4 {
        assert!((a[k] - c[k]).abs() < 1e-12, "{a:?} vs {c:?}");
    }
    assert!((a[2] - b[2]).abs() > 0.7, "{a:?} vs {b:?}");
    let damped =
        NsgsOptions::default().with_tolerance(1e-12).with_max_sweeps(1_000).with_omega(0.5);
    let damped = Nsgs::new(damped).unwrap().solve(&p.problem).unwrap();
    assert_eq!(damped.status, Status::Solved);
    let auto = Fc2dAuto::default().solve(&p.problem).unwrap();
    assert_eq!(auto.status, Status::Solved);
    for s in [&damped, &auto] {
        for (r, planted) in s.r.iter().zip(&p.r) {
            assert!((r - planted).abs() < 1e-9, "{r} vs {planted}");
        }
    }
}

mod properties {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

        /// The LCP route solves every random chain. Gauss-Seidel solves most, and where it
        /// stalls (`gauss_seidel_cycles_off_a_solution_on_a_planted_chain_of_two_contacts`) it
        /// says so, and `Fc2dAuto` goes on to solve the chain.
        #[test]
        fn random_chains_are_solved_by_the_lcp_route_and_by_gauss_seidel_or_auto(seed in 0u64..1_000_000, n_c in 1usize..9, mu_max in 0.0f64..1.0) {
            let mut rng = common::Rng::new(seed);
            let p = planted_fc2d(n_c, mu_max, false, &mut rng);
            let lcp = LcpRoute::default().solve(&p.problem).unwrap();
            prop_assert_eq!(lcp.status, Status::Solved);
            prop_assert!(lcp.residual.natural <= 1e-8);
            let gs = nsgs(1e-10, 200_000).solve(&p.problem).unwrap();
            prop_assert_eq!(gs.status == Status::Solved, gs.residual.meets(1e-10));
            if gs.status != Status::Solved {
                let auto = Fc2dAuto::default().solve(&p.problem).unwrap();
                prop_assert_eq!(auto.status, Status::Solved);
            }
        }
    }
}

/// An island of 43 contacts of the granular flow (tests/data/moreau/README.md), where the
/// basis pivoting ends on lets some contacts slide with normal impulses of 1e-17 to 1e-16
/// N s. Coulomb's law puts a sliding contact's reaction on its cone's edge, P_T = -μ P_N
/// sign(u_T), which the natural map checks only to its own absolute scale. Taken from the
/// LCP's P_R - μ P_N, P_T carried the solve's error on P_R: 4.07e-17 for μ P_N = 4.23e-17,
/// 4 % inside the cone, and the step's LCP (where w_L = 2 μ P_N - P_R) read 1e-2 off.
#[test]
fn a_contact_the_lcp_route_leaves_sliding_lies_on_its_cones_edge_exactly() {
    let text = include_str!("data/moreau/flow_sliding_island.dat");
    let problem = Fc2d::read_siconos(text.as_bytes()).unwrap();
    assert_eq!(problem.n_contacts(), 43);
    let s = LcpRoute::default().solve(&problem).unwrap();
    assert_eq!(s.status, Status::Solved);
    assert!(s.residual.natural <= 1e-14, "{:?}", s.residual);
    assert_in_cones("lcp route", &problem, &s);
    let (mut sliding, mut small) = (0, 0);
    for (i, &mu) in problem.view().mu().iter().enumerate() {
        let (r_n, r_t, u_t) = (s.r[2 * i], s.r[2 * i + 1], s.u[2 * i + 1]);
        if r_n > 0.0 && u_t.abs() > 1e-9 {
            sliding += 1;
            small += usize::from(r_n < 1e-12);
            assert_eq!(r_t, -(mu * r_n).copysign(u_t), "contact {i}: r_N {r_n:e}, u_T {u_t:e}");
        }
    }
    assert!(sliding >= 2 && small >= 1, "{sliding} sliding, {small} of them with r_N < 1e-12");
}

#[test]
fn the_default_problem_and_builder_are_the_problem_without_contacts() {
    let empty = Fc2d::default();
    assert_eq!((empty.n_contacts(), empty.n_rows(), empty.n_blocks()), (0, 0, 0));
    assert_eq!((empty.view().n_groups(), empty.view().n_bilateral()), (0, 0));
    // The same problem as the one a builder of no contacts, or a 0 x 0 W, gives.
    assert_eq!(Fc2dBuilder::default().build(&[], &[]).unwrap(), empty);
    assert_eq!(Fc2d::from_dense(Mat::<f64>::zeros(0, 0).as_ref(), &[], &[]).unwrap(), empty);
    let solvers: [(&str, Box<dyn Fc2dSolver>); 4] = [
        ("nsgs", Box::new(Nsgs::default())),
        ("lcp", Box::new(LcpRoute::default())),
        ("newton", Box::new(Newton::default())),
        ("auto", Box::new(Fc2dAuto::default())),
    ];
    for (name, mut solver) in solvers {
        let s = solver.solve(&empty).unwrap();
        assert_eq!(s.status, Status::Solved, "{name}");
        assert!(s.r.is_empty() && s.u.is_empty() && s.residual.natural == 0.0, "{name}: {s:?}");
    }
    // A default builder numbers its first bilateral group 0, and builds that one row.
    let mut builder = Fc2dBuilder::default();
    assert_eq!(builder.bilateral_group(1), 0);
    builder.add_entry(0, 0, 2.0);
    let joint = builder.build(&[-1.0], &[]).unwrap();
    let s = Nsgs::default().solve(&joint).unwrap();
    assert!(s.is_solved() && s.r == [0.5] && s.u == [0.0], "{s:?}");
}

#[test]
fn gauss_seidel_started_where_the_residual_overflows_goes_on_from_its_finite_iterate() {
    // W = I, q = (-1, 0), μ = 0.5: r = (1, 0). From r = (1e300, 0), whose natural map squares
    // beyond f64's range, the first sweep gives r = 0 (the contact's velocity without its own
    // part, 1e300 - 1 - 1e300, cancels to 0), the second the solution, the third checks it.
    let identity = Mat::<f64>::identity(2, 2);
    let problem = Fc2d::from_dense(identity.as_ref(), &[-1.0, 0.0], &[0.5]).unwrap();
    let warm = [1e300, 0.0];
    let mut s = Fc2dSolution::new();
    Nsgs::default().solve_into(problem.view(), Some(&warm), &mut s).unwrap();
    assert_eq!(s.status, Status::Solved, "{s:?}");
    assert!(s.r == [1.0, 0.0] && s.u == [0.0, 0.0] && s.iterations == 3, "{s:?}");
    Fc2dAuto::default().solve_into(problem.view(), Some(&warm), &mut s).unwrap();
    assert!(s.is_solved() && (s.r[0] - 1.0).abs() <= 1e-8 && s.r[1] == 0.0, "{s:?}");
    // A W of 2^500 (MAX_ENTRY), whose velocities square beyond f64's range at r = 0: the
    // first sweep's r = (1, -0.3) (slipping, q_T > 0) is the solution, up to the round-off of
    // its terms.
    let big = Mat::from_fn(2, 2, |i, j| if i == j { MAX_ENTRY } else { 0.0 });
    let problem = Fc2d::from_dense(big.as_ref(), &[-MAX_ENTRY, MAX_ENTRY], &[0.3]).unwrap();
    let s = Nsgs::default().solve(&problem).unwrap();
    assert_eq!(s.status, Status::Solved, "{s:?}");
    assert!(s.r == [1.0, -0.3] && s.u[0] == 0.0, "{s:?}");
}

#[test]
fn over_relaxation_costs_sweeps_on_a_single_contact() {
    // One sticking contact: the local solve is exact, so ω = 1 solves it in one sweep (and a
    // second, whose lagged residual certifies it), while ω = 1.4 multiplies the error by
    // −0.4 per sweep: 0.4^20 < 1e-8.
    let identity = Mat::<f64>::identity(2, 2);
    let problem = Fc2d::from_dense(identity.as_ref(), &[-1.0, 0.2], &[0.5]).unwrap();
    let sweeps = |omega: f64| {
        let options = Fc2dAutoOptions::default().with_omega(omega);
        let s = Fc2dAuto::new(options).unwrap().solve(&problem).unwrap();
        assert_eq!(s.status, Status::Solved);
        assert!((s.r[0] - 1.0).abs() < 1e-8 && (s.r[1] + 0.2).abs() < 1e-8, "{:?}", s.r);
        s.iterations
    };
    let (exact, relaxed) = (sweeps(1.0), sweeps(1.4));
    assert_eq!(exact, 2);
    assert!((20..=23).contains(&relaxed), "{relaxed} sweeps");
}
