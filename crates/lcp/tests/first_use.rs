//! The crate as a caller meets it: a planted LCP and a planar frictional-contact problem
//! with a sticking and a sliding contact, each solved by every solver and compared with the
//! known solution, and bad input refused with an error that names what is wrong.

mod common;

use common::uniqueness_margin;
use faer::{Col, Mat};
use moreau_lcp::fc2d::{
    Fc2d, Fc2dAuto, Fc2dResidual, Fc2dSolution, Fc2dSolver, Gfc2d, LcpRoute, Newton, NewtonOptions,
    Nsgs, NsgsOptions, Proximal,
};
use moreau_lcp::{
    Auto, AutoOptions, Enumeration, EnumerationOptions, Lcp, LcpError, Lemke, LemkeOptions, Method,
    Pgs, Solution, Solver, Status,
};

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

/// M = AᵀA + I (positive definite, so the solution is unique) with z and w planted:
/// z = (1, 0, 2.5, 0, 0, 0.7), w = (0, 3, 0, 0.2, 1, 0), q = w − M z.
fn planted_lcp() -> (Lcp, [f64; 6], [f64; 6]) {
    let n = 6;
    let a = Mat::<f64>::from_fn(n, n, |i, j| ((i * 7 + j * 3) % 5) as f64 - 2.0);
    let m = Mat::<f64>::from_fn(n, n, |i, j| {
        (0..n).map(|k| a[(k, i)] * a[(k, j)]).sum::<f64>() + if i == j { 1.0 } else { 0.0 }
    });
    let z = [1.0, 0.0, 2.5, 0.0, 0.0, 0.7];
    let w = [0.0, 3.0, 0.0, 0.2, 1.0, 0.0];
    let q = Col::<f64>::from_fn(n, |i| w[i] - (0..n).map(|j| m[(i, j)] * z[j]).sum::<f64>());
    (Lcp::new(m, q).expect("a valid LCP"), z, w)
}

#[test]
fn every_lcp_solver_finds_the_planted_solution() {
    let (lcp, z, w) = planted_lcp();
    let solvers: [(Box<dyn Solver>, f64); 4] = [
        (Box::new(Auto::default()), 1e-12),
        (Box::new(Lemke::default()), 1e-12),
        (Box::new(Enumeration::default()), 1e-12),
        // PGS stops at a relative residual of 1e-10; z is then within 1.4e-9.
        (Box::new(Pgs::default()), 1e-7),
    ];
    for (mut solver, within) in solvers {
        let s = solver.solve(&lcp).unwrap();
        assert_eq!(s.status, Status::Solved, "{}", s.method);
        assert!(max_diff(&s.z, &z) <= within, "{}: z = {:?}", s.method, s.z);
        assert!(max_diff(&s.w, &w) <= 10.0 * within, "{}: w = {:?}", s.method, s.w);
        assert!(s.residual.relative <= 1e-9, "{}: {:?}", s.method, s.residual);
    }
    let all = Enumeration::default().solve_all(lcp.view()).unwrap();
    assert_eq!(all.len(), 1, "M positive definite: one solution");
    assert!(max_diff(&all[0].z, &z) <= 1e-12);
}

/// Two coupled contacts with μ = 0.5: contact 0 sticks with r = (1, 0.2), u = 0; contact 1
/// slides with r = (2, −1) on the cone's edge and u = (0, 0.7); q = u − W r.
fn stick_and_slide() -> (Fc2d, [f64; 4], [f64; 4]) {
    let w =
        [[2.0, 0.3, 0.5, 0.1], [0.3, 1.5, 0.2, 0.4], [0.5, 0.2, 1.8, 0.3], [0.1, 0.4, 0.3, 1.2]];
    let r = [1.0, 0.2, 2.0, -1.0];
    let u = [0.0, 0.0, 0.0, 0.7];
    let q: Vec<f64> = (0..4).map(|i| u[i] - (0..4).map(|j| w[i][j] * r[j]).sum::<f64>()).collect();
    let problem = Fc2d::from_dense(Mat::from_fn(4, 4, |i, j| w[i][j]).as_ref(), &q, &[0.5, 0.5])
        .expect("a valid problem");
    (problem, r, u)
}

#[test]
fn every_fc2d_solver_finds_the_sticking_and_the_sliding_contact() {
    let (problem, r, u) = stick_and_slide();
    // Strongly monotone: the planted r is the only solution.
    let margin = uniqueness_margin(&problem);
    assert!(margin > 0.5, "uniqueness margin {margin}");
    let solvers: [Box<dyn Fc2dSolver>; 5] = [
        Box::new(Nsgs::default()),
        Box::new(LcpRoute::default()),
        Box::new(Newton::default()),
        Box::new(Proximal::default()),
        Box::new(Fc2dAuto::default()),
    ];
    for mut solver in solvers {
        let s = solver.solve(&problem).unwrap();
        assert_eq!(s.status, Status::Solved, "{}", s.method);
        assert!(s.residual.natural <= 1e-8, "{}: {:?}", s.method, s.residual);
        // natural bounds ‖F_i‖; with W's smallest eigenvalue near 0.9, r and u are within a
        // few times that.
        assert!(max_diff(&s.r, &r) <= 1e-7, "{}: r = {:?}", s.method, s.r);
        assert!(max_diff(&s.u, &u) <= 1e-7, "{}: u = {:?}", s.method, s.u);
        // Sliding contact on the edge of its cone, opposing u_T > 0.
        assert!((s.r[3] + 0.5 * s.r[2]).abs() <= 1e-12, "{}: {:?}", s.method, s.r);
    }
    let exact = LcpRoute::default().solve(&problem).unwrap();
    assert!(max_diff(&exact.r, &r) <= 1e-14 && max_diff(&exact.u, &u) <= 1e-14, "{exact:?}");
}

#[test]
fn bad_lcp_input_is_refused_naming_the_culprit() {
    let (lcp, _, _) = planted_lcp();
    let m = lcp.m().to_owned();
    let mut q = lcp.q().to_owned();
    q[3] = f64::NAN;
    let e = Lcp::new(m.clone(), q).unwrap_err();
    assert!(matches!(e, LcpError::NonFinite { what: "q", index: (3, 0) }), "{e:?}");
    assert_eq!(e.to_string(), "non-finite entry in q at index (3, 0)");

    let e = Lcp::new(m.clone(), Col::zeros(5)).unwrap_err();
    assert!(matches!(e, LcpError::DimensionMismatch { what: "q", expected: 6, found: 5 }));
    let e = Lcp::new(Mat::zeros(3, 4), Col::zeros(3)).unwrap_err();
    assert!(matches!(e, LcpError::NotSquare { rows: 3, cols: 4 }), "{e:?}");
    let e = Auto::default().solve_into(lcp.view(), Some(&[1.0]), &mut Solution::new());
    assert!(matches!(e, Err(LcpError::WarmStartLength { expected: 6, found: 1 })));
}

#[test]
fn bad_fc2d_input_is_refused_naming_the_culprit() {
    let (problem, _, _) = stick_and_slide();
    let w = Mat::from_fn(4, 4, |i, j| problem.view().to_dense()[i + 4 * j]);
    let q = problem.q().to_vec();

    let e = Fc2d::from_dense(w.as_ref(), &q, &[0.5, -0.5]).unwrap_err();
    assert!(matches!(e, LcpError::NegativeFriction { contact: 1, mu: -0.5 }), "{e:?}");
    assert_eq!(e.to_string(), "friction coefficient μ of contact 1 is -0.5, it must be >= 0");

    let mut bad_q = q.clone();
    bad_q[1] = f64::NAN;
    let e = Fc2d::from_dense(w.as_ref(), &bad_q, &[0.5, 0.5]).unwrap_err();
    assert!(matches!(e, LcpError::NonFinite { what: "q", index: (1, 0) }), "{e:?}");

    let e = Fc2d::from_dense(w.as_ref(), &q[..3], &[0.5, 0.5]).unwrap_err();
    assert!(matches!(e, LcpError::DimensionMismatch { what: "q", expected: 4, found: 3 }));

    // A W that is not square is W's fault, not an LCP matrix M's.
    let e = Fc2d::from_dense(Mat::<f64>::zeros(4, 3).as_ref(), &q, &[0.5, 0.5]).unwrap_err();
    assert!(matches!(e, LcpError::DimensionMismatch { expected: 4, found: 3, .. }), "{e:?}: {e}");
    assert_eq!(e.to_string(), "dimension mismatch for columns of W: expected 4, found 3");
    // W of 4 rows and one μ: the message says that the rows follow from μ.
    let e = Fc2d::from_dense(w.as_ref(), &q, &[0.5]).unwrap_err();
    assert_eq!(
        e.to_string(),
        "dimension mismatch for rows of W (2 per friction coefficient μ): expected 2, found 4"
    );
}

#[test]
fn a_global_problem_whose_mass_matrix_is_not_square_is_refused_naming_it() {
    // M dense 2 x 3, then H, q, b and μ of one contact.
    let text = "2\n1\n0\n2\n3\n2 3\n1 0 0 1 0 0\n0\n2\n2\n2 2\n1 0 0 1\n0 -1\n0 0\n0.5\n";
    let e = Gfc2d::read_siconos(text.as_bytes()).unwrap_err();
    assert!(matches!(e, LcpError::DimensionMismatch { expected: 2, found: 3, .. }), "{e:?}");
    assert_eq!(
        e.to_string(),
        "dimension mismatch for columns of the mass matrix M: expected 2, found 3"
    );
}

#[test]
fn nested_options_name_their_path() {
    let bad_lemke = LemkeOptions::default().with_tolerance(-1.0);
    assert!(matches!(
        Lemke::new(bad_lemke.clone()).err(),
        Some(LcpError::InvalidOption { name: "tolerance", .. })
    ));
    let e = Auto::new(AutoOptions::default().with_lemke(bad_lemke)).err().unwrap();
    assert!(matches!(e, LcpError::InvalidOption { name: "lemke.tolerance", .. }), "{e:?}");
    assert_eq!(e.to_string(), "invalid option lemke.tolerance: must be in (0, 1)");
    let bad_enumeration = EnumerationOptions::default().with_max_n(30);
    let e = Auto::new(AutoOptions::default().with_enumeration(bad_enumeration)).err().unwrap();
    assert!(matches!(e, LcpError::InvalidOption { name: "enumeration.max_n", .. }), "{e:?}");
    let e = Auto::new(AutoOptions::default().with_enumeration_max_n(21)).err().unwrap();
    assert!(matches!(e, LcpError::InvalidOption { name: "enumeration_max_n", .. }), "{e:?}");
}

/// Six coupled contacts, some sticking and some sliding, whose round-off (2.1e-15) is above
/// the tolerances asked for below.
fn coupled_six() -> Fc2d {
    let n = 12;
    let w = Mat::<f64>::from_fn(n, n, |i, j| {
        if i == j {
            3.0 + (i % 3) as f64 * 0.1
        } else if i.abs_diff(j) == 2 {
            0.7
        } else if i / 2 == j / 2 {
            0.3
        } else {
            0.0
        }
    });
    let q: Vec<f64> = (0..n)
        .map(|i| if i % 2 == 0 { -1.0 - 0.1 * i as f64 } else { 0.3 * (i as f64 - 5.0) })
        .collect();
    Fc2d::from_dense(w.as_ref(), &q, &[0.3; 6]).expect("a valid problem")
}

#[test]
fn a_tolerance_below_round_off_is_met_at_round_off_without_the_sweeps_left() {
    let problem = coupled_six();
    let exact = LcpRoute::default().solve(&problem).unwrap();
    assert!(exact.residual.natural <= 1e-15, "{:?}", exact.residual);
    for tolerance in [1e-17, 1e-300] {
        let options = NsgsOptions::default().with_tolerance(tolerance).with_max_sweeps(10_000);
        let s = Nsgs::new(options).unwrap().solve(&problem).unwrap();
        assert_eq!(s.status, Status::Solved, "{:?}", s.residual);
        assert!(s.residual.round_off > tolerance, "{:?}", s.residual);
        assert!(s.residual.natural <= s.residual.round_off, "{:?}", s.residual);
        // 1e-15 takes 22 sweeps; the round-off is found by the full check of sweep 64
        // instead of the last of the 10,000.
        assert!(s.iterations <= 64, "{} sweeps", s.iterations);
        assert!(max_diff(&s.r, &exact.r) <= 1e-14, "{:?} against {:?}", s.r, exact.r);
        let mut newton = Newton::new(NewtonOptions::default().with_tolerance(tolerance)).unwrap();
        let s = newton.solve(&problem).unwrap();
        assert_eq!(s.status, Status::Solved);
        assert!(s.iterations <= 5 && max_diff(&s.r, &exact.r) <= 1e-14, "{s:?}");
    }
}

#[test]
fn a_fresh_fc2d_solution_measures_nothing_as_solved() {
    let fresh = Fc2dSolution::new();
    assert_eq!(fresh.status, Status::NumericalFailure);
    assert_eq!(fresh.residual, Fc2dResidual::INFINITE);
    assert!(!fresh.residual.meets(1.0));
    // As for the LCP: a fresh Solution's residual is infinite too.
    assert_eq!(Solution::new().residual.relative, f64::INFINITY);
    // Filled by a solver, it carries the solve's residual.
    let mut out = Fc2dSolution::new();
    Nsgs::default().solve_into(stick_and_slide().0.view(), None, &mut out).unwrap();
    assert_eq!((out.status, out.method), (Status::Solved, Method::Nsgs));
    assert!(out.residual.natural <= 1e-8);
}
