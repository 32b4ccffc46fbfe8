//! Planted solutions, scaling, small edge cases and input validation for every solver.
#![allow(non_snake_case)]

mod common;

use common::{Rng, assert_solves, planted, random_p_matrix, random_spd, rel_dist};
use faer::{Col, Mat};
use moreau_lcp::{
    Auto, Covering, Enumeration, EnumerationOptions, Lcp, LcpError, LcpRef, Lemke, LemkeOptions,
    Method, Pgs, PgsOptions, Residual, Solution, Solver, Status,
};

#[test]
fn planted_spd_problems_all_solvers_agree() {
    let mut rng = Rng::new(1);
    for trial in 0..40 {
        let n = 1 + (trial % 12);
        let (lcp, z_star) = planted(random_spd(n, &mut rng), &mut rng, false);
        let lemke = Lemke::default().solve(&lcp).unwrap();
        let pgs = Pgs::default().solve(&lcp).unwrap();
        let enumeration = Enumeration::default().solve(&lcp).unwrap();
        let auto = Auto::default().solve(&lcp).unwrap();
        for (name, s) in [("lemke", &lemke), ("pgs", &pgs), ("enum", &enumeration), ("auto", &auto)]
        {
            assert_eq!(s.status, Status::Solved, "{name} trial {trial}");
            assert_solves(&lcp, &s.z, 1e-8);
            let tol = if name == "pgs" { 1e-6 } else { 1e-9 };
            assert!(
                rel_dist(&z_star, &s.z) < tol,
                "{name} trial {trial}: {:?} vs {:?}",
                s.z,
                z_star
            );
        }
    }
}

#[test]
fn planted_p_matrix_problems_all_solvers_agree() {
    let mut rng = Rng::new(2);
    for trial in 0..40 {
        let n = 1 + (trial % 10);
        let (lcp, z_star) = planted(random_p_matrix(n, &mut rng), &mut rng, trial % 2 == 0);
        for (name, s) in [
            ("lemke", Lemke::default().solve(&lcp).unwrap()),
            ("pgs", Pgs::default().solve(&lcp).unwrap()),
            ("enum", Enumeration::default().solve(&lcp).unwrap()),
            ("auto", Auto::default().solve(&lcp).unwrap()),
        ] {
            assert_eq!(s.status, Status::Solved, "{name} trial {trial}");
            let tol = if name == "pgs" { 1e-7 } else { 1e-9 };
            assert!(
                rel_dist(&z_star, &s.z) < tol,
                "{name} trial {trial}: {:?} vs {:?}",
                s.z,
                z_star
            );
        }
    }
}

#[test]
fn larger_spd_problems_lemke_and_pgs_agree() {
    let mut rng = Rng::new(3);
    for n in [30, 45, 90] {
        let (lcp, z_star) = planted(random_spd(n, &mut rng), &mut rng, false);
        let lemke = Lemke::default().solve(&lcp).unwrap();
        assert_eq!(lemke.status, Status::Solved);
        assert!(rel_dist(&z_star, &lemke.z) < 1e-9, "n = {n}");
        let pgs = Pgs::new(PgsOptions::default().with_max_iterations(100_000))
            .unwrap()
            .solve(&lcp)
            .unwrap();
        assert_eq!(pgs.status, Status::Solved, "pgs n = {n}");
        assert!(rel_dist(&z_star, &pgs.z) < 1e-6, "pgs n = {n}");
    }
}

#[test]
fn badly_scaled_matrix_is_solved_accurately() {
    // Entries of M span 1e-9 to 1e6: a diagonal scaling D1 A D2 of a P-matrix A keeps the
    // P-property and the planted solution moves to D2^{-1} z.
    let mut rng = Rng::new(4);
    for trial in 0..20 {
        let n = 2 + trial % 6;
        let a = random_p_matrix(n, &mut rng);
        let d1: Vec<f64> = (0..n).map(|i| if i % 2 == 0 { 1e-9 } else { 1e6 }).collect();
        let d2: Vec<f64> = (0..n).map(|_| 10f64.powf(rng.uniform(-3.0, 3.0))).collect();
        let (base, z_base) = planted(a.clone(), &mut rng, false);
        let m = Mat::from_fn(n, n, |i, j| d1[i] * a[(i, j)] * d2[j]);
        let q = Col::from_fn(n, |i| d1[i] * base.q()[i]);
        let lcp = Lcp::new(m, q).unwrap();
        let z_star: Vec<f64> = (0..n).map(|j| z_base[j] / d2[j]).collect();
        let mut row_scaled =
            Lemke::new(LemkeOptions::default().with_covering(Covering::RowScaled)).unwrap();
        for (name, s) in [
            ("lemke", row_scaled.solve(&lcp).unwrap()),
            ("enum", Enumeration::default().solve(&lcp).unwrap()),
            ("auto", Auto::default().solve(&lcp).unwrap()),
        ] {
            assert_eq!(
                s.status,
                Status::Solved,
                "{name} trial {trial}: {:?} {:?} vs {:?}",
                s.residual,
                s.z,
                z_star
            );
            // Normwise: the columns scaled by 1e-3..1e3 make componentwise bounds meaningless
            // for the small components.
            assert!(
                rel_dist(&z_star, &s.z) < 1e-9,
                "{name} trial {trial}: {:?} vs {:?}",
                s.z,
                z_star
            );
            assert!(s.residual.relative <= 1e-9);
        }
    }
}

#[test]
fn scalar_problems_have_the_closed_form_answers() {
    // a > 0: z = max(0, -b/a).
    for (a, b) in [(2.0, -3.0), (2.0, 3.0), (1e-6, -1.0), (5.0, 0.0)] {
        let lcp = Lcp::from_rows(&[vec![a]], &[b]).unwrap();
        let expected: f64 = (-b / a).max(0.0);
        for s in [
            Lemke::default().solve(&lcp).unwrap(),
            Pgs::default().solve(&lcp).unwrap(),
            Enumeration::default().solve(&lcp).unwrap(),
            Auto::default().solve(&lcp).unwrap(),
        ] {
            assert_eq!(s.status, Status::Solved);
            assert!(
                (s.z[0] - expected).abs() <= 1e-12 * expected.max(1.0),
                "a={a} b={b}: {}",
                s.z[0]
            );
            assert!((s.w[0] - (a * s.z[0] + b)).abs() < 1e-12);
        }
    }
}

#[test]
fn scalar_with_negative_a_and_positive_b_has_two_solutions() {
    let (a, b) = (-2.0, 3.0);
    let lcp = Lcp::from_rows(&[vec![a]], &[b]).unwrap();
    let all = Enumeration::default().solve_all(lcp.view()).unwrap();
    let mut zs: Vec<f64> = all.iter().map(|s| s.z[0]).collect();
    zs.sort_by(f64::total_cmp);
    assert_eq!(zs.len(), 2);
    assert_eq!(zs[0], 0.0);
    assert!((zs[1] - 1.5).abs() < 1e-14);
    // q >= 0: the trivial solution.
    let s = Auto::default().solve(&lcp).unwrap();
    assert_eq!((s.status, s.method, s.z[0]), (Status::Solved, Method::Trivial, 0.0));
}

#[test]
fn scalar_with_negative_a_and_negative_b_has_none() {
    let lcp = Lcp::from_rows(&[vec![-2.0]], &[-3.0]).unwrap();
    assert!(Enumeration::default().solve_all(lcp.view()).unwrap().is_empty());
    let e = Enumeration::default().solve(&lcp).unwrap();
    assert_eq!(e.status, Status::NoSolution);
    let l = Lemke::default().solve(&lcp).unwrap();
    assert_eq!(l.status, Status::RayTermination);
    assert!(l.residual.relative > 1e-9);
    let a = Auto::default().solve(&lcp).unwrap();
    assert_eq!((a.status, a.method), (Status::NoSolution, Method::Enumeration));
    assert!(!a.is_solved());
}

#[test]
fn zero_scalar_problems() {
    // M = 0, q = 0: z = 0 solves (any z >= 0 does).
    let lcp = Lcp::from_rows(&[vec![0.0]], &[0.0]).unwrap();
    assert!(Auto::default().solve(&lcp).unwrap().is_solved());
    // M = 0, q < 0: w = q < 0 for every z, no solution.
    let lcp = Lcp::from_rows(&[vec![0.0]], &[-1.0]).unwrap();
    assert_eq!(Enumeration::default().solve(&lcp).unwrap().status, Status::NoSolution);
    assert_eq!(Auto::default().solve(&lcp).unwrap().status, Status::NoSolution);
    assert!(matches!(
        Pgs::default().solve(&lcp),
        Err(LcpError::NonPositiveDiagonal { index: 0, value }) if value == 0.0
    ));
}

#[test]
fn pgs_reports_iteration_limit_and_divergence_honestly() {
    // w1 = z1 - 2 z2 - 1, w2 = -2 z1 + z2 - 1: w1 + w2 = -(z1 + z2) - 2 < 0, infeasible.
    // PGS sets z1 = 1 + 2 z2, z2 = 1 + 2 z1: the iterates grow fourfold per sweep.
    let lcp = Lcp::from_rows(&[vec![1.0, -2.0], vec![-2.0, 1.0]], &[-1.0, -1.0]).unwrap();
    let s = Pgs::new(PgsOptions::default().with_max_iterations(50)).unwrap().solve(&lcp).unwrap();
    assert_eq!(s.status, Status::IterationLimit);
    assert_eq!(s.iterations, 50);
    assert!(s.residual.relative > 1e-10);
    // After 4^k overflows (k about 512) the last finite iterate is returned.
    let s = Pgs::new(PgsOptions::default().with_max_iterations(2000)).unwrap().solve(&lcp).unwrap();
    assert_eq!(s.status, Status::NumericalFailure);
    assert!(s.iterations > 500 && s.iterations < 2000, "{}", s.iterations);
    assert!(s.z.iter().all(|v| v.is_finite()));
    // The problem is infeasible, which enumeration proves.
    assert_eq!(Enumeration::default().solve(&lcp).unwrap().status, Status::NoSolution);
    // PGS solves a problem that is not diagonally dominant when its sweep lands on a
    // solution: w1 = z1 + 2 z2 - 1, w2 = 2 z1 + z2 - 1 gives z = (1, 0) after one sweep.
    let lcp = Lcp::from_rows(&[vec![1.0, 2.0], vec![2.0, 1.0]], &[-1.0, -1.0]).unwrap();
    let s = Pgs::default().solve(&lcp).unwrap();
    assert_eq!(
        (s.status, s.iterations, s.z.as_slice()),
        (Status::Solved, 1, [1.0, 0.0].as_slice())
    );
}

#[test]
fn pgs_warm_start_at_the_solution_needs_no_sweep() {
    let mut rng = Rng::new(5);
    let (lcp, z_star) = planted(random_spd(6, &mut rng), &mut rng, false);
    let mut pgs = Pgs::default();
    let mut out = Solution::new();
    pgs.solve_into(lcp.view(), Some(&z_star), &mut out).unwrap();
    assert_eq!((out.status, out.iterations), (Status::Solved, 0));
    let cold = Pgs::default().solve(&lcp).unwrap();
    assert!(cold.iterations > 0);
    // A nearby warm start takes fewer sweeps than a cold one.
    let near: Vec<f64> = z_star.iter().map(|v| v * 1.001).collect();
    pgs.solve_into(lcp.view(), Some(&near), &mut out).unwrap();
    assert!(out.is_solved() && out.iterations < cold.iterations);
}

#[test]
fn pgs_over_relaxation_converges_for_spd() {
    let mut rng = Rng::new(6);
    let (lcp, z_star) = planted(random_spd(8, &mut rng), &mut rng, false);
    for omega in [0.5, 1.0, 1.3, 1.8] {
        let s = Pgs::new(PgsOptions::default().with_omega(omega).with_max_iterations(100_000))
            .unwrap()
            .solve(&lcp)
            .unwrap();
        assert_eq!(s.status, Status::Solved, "omega {omega}");
        assert!(rel_dist(&z_star, &s.z) < 1e-6);
    }
}

/// A problem of order 1e-12 meets the natural residual (absolute below ‖q‖∞ = 1) at z = 0
/// and after its first sweep, but not the scale-free one: PGS sweeps on until `relative`
/// meets the tolerance too, and lands on the planted z* = (1, 2) · 1e-12 with w* = 0.
#[test]
fn pgs_stops_only_when_the_relative_residual_also_meets_the_tolerance() {
    let z_star = [1e-12, 2e-12];
    let q = [-(z_star[0] + 0.5 * z_star[1]), -(0.5 * z_star[0] + z_star[1])];
    let lcp = Lcp::from_rows(&[vec![1.0, 0.5], vec![0.5, 1.0]], &q).unwrap();
    let s = Pgs::default().solve(&lcp).unwrap();
    assert_eq!(s.status, Status::Solved);
    assert!(s.residual.relative <= 1e-10, "{:?}", s.residual);
    // The first sweep gives z = (2, 1.5) · 1e-12 with relative residual about 0.27; the
    // error contracts fourfold per sweep.
    assert!(s.iterations > 10, "{}", s.iterations);
    for (z, z_s) in s.z.iter().zip(z_star) {
        assert!((z - z_s).abs() <= 1e-9 * z_s, "{:?}", s.z);
    }
}

/// The options a solver was built with are the ones it reports.
#[test]
fn pgs_reports_its_options() {
    let options = PgsOptions::default().with_omega(1.3).with_tolerance(1e-8).with_max_iterations(7);
    assert_eq!(Pgs::new(options.clone()).unwrap().options(), &options);
}

#[test]
fn non_finite_and_malformed_input_is_rejected() {
    let nan = f64::NAN;
    assert!(matches!(
        Lcp::from_rows(&[vec![1.0, 0.0], vec![0.0, nan]], &[1.0, 1.0]),
        Err(LcpError::NonFinite { what: "M", index: (1, 1) })
    ));
    assert!(matches!(
        Lcp::from_rows(&[vec![1.0]], &[f64::INFINITY]),
        Err(LcpError::NonFinite { what: "q", index: (0, 0) })
    ));
    assert!(matches!(Lcp::from_rows(&[], &[]), Err(LcpError::Empty)));
    assert!(matches!(
        Lcp::from_rows(&[vec![1.0, 2.0], vec![1.0]], &[1.0, 1.0]),
        Err(LcpError::RaggedRow { row: 1, expected: 2, found: 1 })
    ));
    // Every row of a 3 x 3 problem is checked, and the first bad one is named.
    let ragged = Lcp::from_rows(&[vec![1.0; 3], vec![1.0; 4], vec![1.0; 2]], &[1.0; 3]);
    assert!(matches!(ragged, Err(LcpError::RaggedRow { row: 1, expected: 3, found: 4 })));
    assert_eq!(
        ragged.unwrap_err().to_string(),
        "row 1 of the LCP matrix M has 4 entries, expected 3 (one per row)"
    );
    assert!(matches!(
        Lcp::from_rows(&[vec![1.0]], &[1.0, 2.0]),
        Err(LcpError::DimensionMismatch { what: "q", expected: 1, found: 2 })
    ));
    assert!(matches!(
        Lcp::from_column_major(2, &[1.0, 2.0, 3.0], &[1.0, 1.0]),
        Err(LcpError::DimensionMismatch { expected: 4, found: 3, .. })
    ));
    let m = Mat::<f64>::zeros(2, 3);
    let q = Col::<f64>::zeros(2);
    assert!(matches!(
        LcpRef::new(m.as_ref(), q.as_ref()),
        Err(LcpError::NotSquare { rows: 2, cols: 3 })
    ));
    // A transposed (row-major) view is validated and solved like any other.
    let m = Mat::from_fn(2, 2, |i, j| [[2.0, 1.0], [0.0, 2.0]][j][i]);
    let q = Col::from_fn(2, |i| [-1.0, -1.0][i]);
    let view = LcpRef::new(m.transpose(), q.as_ref()).unwrap();
    let mut out = Solution::new();
    Lemke::default().solve_into(view, None, &mut out).unwrap();
    assert!(out.is_solved());
    assert!((out.z[0] - 0.25).abs() < 1e-15 && (out.z[1] - 0.5).abs() < 1e-15, "{:?}", out.z);
    assert_eq!(view.to_owned().m()[(0, 1)], 1.0);
    // The view of column-major slices: the same checks, the same problem.
    let (m, q) = ([2.0, 0.0, 1.0, 2.0], [-1.0, -1.0]);
    let view = LcpRef::from_column_major(2, &m, &q).unwrap();
    assert_eq!((view.m()[(0, 1)], view.m()[(1, 0)], view.q()[1]), (1.0, 0.0, -1.0));
    for (k, what, index) in [(3, "M", (1, 1)), (1, "M", (1, 0)), (4, "q", (0, 0))] {
        let mut data = [2.0, 0.0, 1.0, 2.0, -1.0, -1.0];
        data[k] = [f64::NAN, f64::INFINITY][k % 2];
        let (m, q) = data.split_at(4);
        let err = LcpRef::from_column_major(2, m, q).unwrap_err();
        assert!(
            matches!(err, LcpError::NonFinite { what: w, index: i } if w == what && i == index),
            "{err:?}"
        );
    }
    assert!(matches!(LcpRef::from_column_major(0, &[], &[]), Err(LcpError::Empty)));
    assert!(matches!(
        LcpRef::from_column_major(2, &m, &[1.0]),
        Err(LcpError::DimensionMismatch { what: "q", expected: 2, found: 1 })
    ));
    assert!(matches!(
        LcpRef::from_column_major(2, &m[..3], &q),
        Err(LcpError::DimensionMismatch { expected: 4, found: 3, .. })
    ));
}

#[test]
fn a_size_whose_square_overflows_is_a_dimension_mismatch() {
    // n² beyond usize: no slice has that many entries, so the sizes disagree (no overflow).
    for n in [1usize << 32, usize::MAX] {
        assert!(matches!(
            LcpRef::from_column_major(n, &[], &[]),
            Err(LcpError::DimensionMismatch { expected: usize::MAX, found: 0, .. })
        ));
        assert!(matches!(
            Lcp::from_column_major(n, &[1.0], &[-1.0]),
            Err(LcpError::DimensionMismatch { expected: usize::MAX, found: 1, .. })
        ));
        assert_eq!(Residual::compute_column_major(n, &[], &[], &[], &[]), Residual::INFINITE);
    }
    // The same entry points still take a problem of the size they are given.
    let r = Residual::compute_column_major(1, &[2.0], &[-1.0], &[0.5], &[0.0]);
    assert_eq!((r.relative, r.equation), (0.0, 0.0));
}

#[test]
fn warm_start_errors() {
    let lcp = Lcp::from_rows(&[vec![1.0]], &[-1.0]).unwrap();
    let mut out = Solution::new();
    for solver in
        [&mut Pgs::default() as &mut dyn Solver, &mut Lemke::default(), &mut Auto::default()]
    {
        assert!(matches!(
            solver.solve_into(lcp.view(), Some(&[1.0, 2.0]), &mut out),
            Err(LcpError::WarmStartLength { expected: 1, found: 2 })
        ));
        assert!(matches!(
            solver.solve_into(lcp.view(), Some(&[f64::NAN]), &mut out),
            Err(LcpError::NonFinite { what: "warm start", .. })
        ));
    }
}

#[test]
fn options_are_validated() {
    for omega in [0.0, 2.0, -1.0, f64::NAN] {
        assert!(matches!(
            Pgs::new(PgsOptions::default().with_omega(omega)),
            Err(LcpError::InvalidOption { name: "omega", .. })
        ));
    }
    assert!(Pgs::new(PgsOptions::default().with_tolerance(0.0)).is_err());
    assert!(Pgs::new(PgsOptions::default().with_max_iterations(0)).is_err());
    assert!(Lemke::new(LemkeOptions::default().with_max_pivots(0)).is_err());
    assert!(Lemke::new(LemkeOptions::default().with_tolerance(f64::INFINITY)).is_err());
    // z = 0 measures at most 1 on any problem (w = q), so a tolerance of 1 or more would call
    // it a solution of M = [-1], q = [-1], which has none: every LCP solver refuses it.
    let infeasible = Lcp::from_rows(&[vec![-1.0]], &[-1.0]).unwrap();
    let at_zero = Residual::compute(infeasible.view(), &[0.0], &[-1.0]);
    assert_eq!(at_zero.relative, 1.0);
    for tolerance in [1.0, 1.5, 0.0, -1e-9, f64::NAN] {
        let refused = |r: Result<(), LcpError>| {
            matches!(r, Err(LcpError::InvalidOption { name: "tolerance", .. }))
        };
        let lemke = Lemke::new(LemkeOptions::default().with_tolerance(tolerance));
        let enumeration = Enumeration::new(EnumerationOptions::default().with_tolerance(tolerance));
        let pgs = Pgs::new(PgsOptions::default().with_tolerance(tolerance));
        let auto = Auto::new(
            moreau_lcp::AutoOptions::default()
                .with_lemke(LemkeOptions::default().with_tolerance(tolerance)),
        );
        assert!(refused(lemke.map(|_| ())), "lemke, tolerance {tolerance}");
        assert!(refused(enumeration.map(|_| ())), "enumeration, tolerance {tolerance}");
        assert!(refused(pgs.map(|_| ())), "pgs, tolerance {tolerance}");
        // Auto names the nested option by its path.
        let auto_refused =
            matches!(auto, Err(LcpError::InvalidOption { name: "lemke.tolerance", .. }));
        assert!(auto_refused, "auto, tolerance {tolerance}");
    }
    // Just below 1 is taken, and the infeasible problem is still not solved.
    let mut loose = Lemke::new(LemkeOptions::default().with_tolerance(0.999)).unwrap();
    assert_eq!(loose.solve(&infeasible).unwrap().status, Status::RayTermination);
    assert!(matches!(
        Lemke::new(LemkeOptions::default().with_covering(Covering::Custom(vec![1.0, 0.0]))),
        Err(LcpError::InvalidOption { name: "covering", .. })
    ));
    assert!(matches!(
        Enumeration::new(EnumerationOptions::default().with_max_n(40)),
        Err(LcpError::InvalidOption { name: "max_n", .. })
    ));
    assert!(matches!(
        Enumeration::new(EnumerationOptions::default().with_max_n_degenerate(15)),
        Err(LcpError::InvalidOption { name: "max_n_degenerate", .. })
    ));
    assert!(
        Enumeration::new(EnumerationOptions::default().with_max_n(10).with_max_n_degenerate(11))
            .is_err()
    );
    assert!(matches!(
        Auto::new(moreau_lcp::AutoOptions::default().with_enumeration_max_n(21)),
        Err(LcpError::InvalidOption { name: "enumeration_max_n", .. })
    ));
    // A covering vector of the wrong length is an input error at solve time.
    let mut lemke =
        Lemke::new(LemkeOptions::default().with_covering(Covering::Custom(vec![1.0, 2.0])))
            .unwrap();
    let lcp = Lcp::from_rows(&[vec![1.0]], &[-1.0]).unwrap();
    assert!(matches!(
        lemke.solve(&lcp),
        Err(LcpError::DimensionMismatch { what: "covering vector d", .. })
    ));
}

#[test]
fn custom_covering_vector_gives_the_same_unique_solution() {
    let mut rng = Rng::new(7);
    let (lcp, z_star) = planted(random_p_matrix(7, &mut rng), &mut rng, false);
    let d: Vec<f64> = (0..7).map(|_| rng.uniform(0.2, 5.0)).collect();
    let s = Lemke::new(LemkeOptions::default().with_covering(Covering::Custom(d)))
        .unwrap()
        .solve(&lcp)
        .unwrap();
    assert_eq!(s.status, Status::Solved);
    assert!(rel_dist(&z_star, &s.z) < 1e-10);
}

#[test]
fn enumeration_size_guard() {
    let n = 21;
    let lcp = Lcp::new(Mat::identity(n, n), Col::from_fn(n, |_| -1.0)).unwrap();
    assert!(matches!(
        Enumeration::default().solve(&lcp),
        Err(LcpError::TooLarge { n: 21, max: 20 })
    ));
    assert!(matches!(Enumeration::default().solve_all(lcp.view()), Err(LcpError::TooLarge { .. })));
    // Auto skips enumeration for such sizes and still solves with Lemke.
    let s = Auto::default().solve(&lcp).unwrap();
    assert_eq!((s.status, s.method), (Status::Solved, Method::Lemke));
    assert!(s.z.iter().all(|&v| (v - 1.0).abs() < 1e-15));
}

#[test]
fn residual_definition() {
    let lcp = Lcp::from_rows(&[vec![2.0, 0.0], vec![0.0, 1.0]], &[-4.0, 1.0]).unwrap();
    // Exact solution z = (2, 0), w = (0, 1).
    let r = Residual::compute(lcp.view(), &[2.0, 0.0], &[0.0, 1.0]);
    assert_eq!(r.max(), 0.0);
    assert_eq!(r.relative, 0.0);
    // A wrong candidate z = (1, -0.5), claimed w = (0, 1).
    let r = Residual::compute(lcp.view(), &[1.0, -0.5], &[0.0, 1.0]);
    assert_eq!(r.z_violation, 0.5);
    assert_eq!(r.w_violation, 0.0);
    assert_eq!(r.complementarity, 0.5);
    // M z + q - w = (-2, 0.5 - 1).
    assert_eq!(r.equation, 2.0);
    // min(z, w) = (0, -0.5), divided by max(1, ‖q‖∞) = 4.
    assert_eq!(r.natural, 0.125);
    assert_eq!(r.max(), 2.0);
    // Z = 1; row 0: s_0 = max(4, 2) = 4, equation 2 / 4; row 1: s_1 = max(1, 0.5) = 1,
    // z violation 0.5 / 1 and equation 0.5 / 1.
    assert_eq!(r.relative, 0.5);
    // A candidate that violates complementarity only: z = (2, 1), w = M z + q = (0, 2).
    let r = Residual::compute(lcp.view(), &[2.0, 1.0], &[0.0, 2.0]);
    assert_eq!((r.z_violation, r.w_violation, r.equation), (0.0, 0.0, 0.0));
    assert_eq!(r.complementarity, 2.0);
    // min(z_1 / Z, w_1 / s_1) = min(1 / 2, 2 / max(1, 1)) = 0.5.
    assert_eq!(r.relative, 0.5);
    // Scaling a row of (M, q) leaves `relative` unchanged.
    let scaled = Lcp::from_rows(&[vec![2e-9, 0.0], vec![0.0, 1.0]], &[-4e-9, 1.0]).unwrap();
    let r2 = Residual::compute(scaled.view(), &[2.0, 1.0], &[0.0, 2.0]);
    assert_eq!(r2.relative, 0.5);
    assert_eq!(Residual::compute(lcp.view(), &[1.0], &[0.0, 1.0]), Residual::INFINITE);
    assert_eq!(
        Residual::compute(lcp.view(), &[f64::NAN, 0.0], &[0.0, 1.0]).relative,
        f64::INFINITY
    );
}

/// A claimed w that is non-negative and complementary to z but is not M z + q: `natural`
/// and the sign terms are zero, and only the equation term, |1 − 1.5| / s_1 with
/// s_1 = max(|q_1|, 0) = 1, makes `relative` 0.5.
#[test]
fn a_claimed_w_off_m_z_plus_q_is_measured_by_the_equation_term_alone() {
    let lcp = Lcp::from_rows(&[vec![2.0, 0.0], vec![0.0, 1.0]], &[-4.0, 1.0]).unwrap();
    let r = Residual::compute(lcp.view(), &[2.0, 0.0], &[0.0, 1.5]);
    assert_eq!((r.natural, r.complementarity), (0.0, 0.0));
    assert_eq!((r.z_violation, r.w_violation), (0.0, 0.0));
    assert_eq!((r.equation, r.relative), (0.5, 0.5));
}

/// A row whose z_i or w_i is not finite makes the accumulated residual infinite, even when
/// the row's (M z + q)_i is finite and the other terms would drop the non-finite value.
#[test]
fn a_non_finite_row_makes_the_accumulated_residual_infinite() {
    for (z, w) in [(f64::INFINITY, 0.0), (0.0, f64::NAN), (1.0, f64::NEG_INFINITY)] {
        let mut rows = moreau_lcp::ResidualRows::new([1.0]);
        rows.row(-1.0, z, w, 1.0, 0.0);
        assert_eq!(rows.finish(), Residual::INFINITE, "z = {z}, w = {w}");
    }
    // The same rows with finite entries are measured.
    let mut rows = moreau_lcp::ResidualRows::new([1.0]);
    rows.row(-1.0, 1.0, 0.0, 1.0, 0.0);
    assert_eq!(rows.finish().relative, 0.0);
}

#[test]
fn display_names() {
    let statuses = [
        (Status::Solved, "solved"),
        (Status::NoSolution, "no_solution"),
        (Status::RayTermination, "ray_termination"),
        (Status::IterationLimit, "iteration_limit"),
        (Status::NumericalFailure, "numerical_failure"),
        (Status::TooLarge, "too_large"),
    ];
    for (s, name) in statuses {
        assert_eq!(s.to_string(), name);
        assert_eq!(serde_json::to_string(&s).unwrap(), format!("\"{name}\""));
    }
    for (m, name) in [
        (Method::Trivial, "trivial"),
        (Method::Lemke, "lemke"),
        (Method::Pgs, "pgs"),
        (Method::Enumeration, "enumeration"),
        (Method::WarmBasis, "warm_basis"),
        (Method::ClosedForm, "closed_form"),
    ] {
        assert_eq!(m.to_string(), name);
        assert_eq!(serde_json::to_string(&m).unwrap(), format!("\"{name}\""));
    }
}

#[test]
fn solutions_and_options_serialize() {
    let lcp = Lcp::from_rows(&[vec![2.0]], &[-1.0]).unwrap();
    let s = Auto::default().solve(&lcp).unwrap();
    let text = serde_json::to_string(&s).unwrap();
    let back: Solution = serde_json::from_str(&text).unwrap();
    assert_eq!(back, s);
    let opts: LemkeOptions = serde_json::from_str(r#"{"max_pivots": 10}"#).unwrap();
    assert_eq!(opts.max_pivots, 10);
    assert_eq!(opts.tolerance, LemkeOptions::default().tolerance);
    // A misspelt field is refused, naming it, rather than left at its default unnoticed (as
    // the FC2D solvers' options do).
    let typo = r#"{"tolerence": 1e-3}"#;
    let refusals = [
        serde_json::from_str::<LemkeOptions>(typo).err(),
        serde_json::from_str::<PgsOptions>(typo).err(),
        serde_json::from_str::<EnumerationOptions>(typo).err(),
        serde_json::from_str::<moreau_lcp::AutoOptions>(typo).err(),
        serde_json::from_str::<moreau_lcp::AutoOptions>(r#"{"lemke": {"max_pivot": 5}}"#).err(),
    ];
    for e in refusals {
        let e = e.expect("an unknown field is an error").to_string();
        let named = e.contains("`tolerence`") || e.contains("`max_pivot`");
        assert!(e.contains("unknown field") && named, "{e}");
    }
    let auto: moreau_lcp::AutoOptions =
        serde_json::from_str(r#"{"lemke": {"tolerance": 1e-6}, "enumeration_max_n": 8}"#).unwrap();
    assert_eq!((auto.lemke.tolerance, auto.enumeration_max_n), (1e-6, 8));
    assert_eq!(auto.lemke.max_pivots, LemkeOptions::default().max_pivots);
}

#[test]
fn solvers_are_send_and_sync() {
    fn check<T: Send + Sync>() {}
    check::<Lemke>();
    check::<Pgs>();
    check::<Enumeration>();
    check::<Auto>();
    check::<Lcp>();
    check::<LcpRef<'static>>();
    check::<Solution>();
    check::<LcpError>();
}

#[test]
fn workspace_reuse_across_sizes_gives_the_same_answers() {
    let mut rng = Rng::new(8);
    let mut lemke = Lemke::default();
    let mut pgs = Pgs::default();
    let mut out = Solution::new();
    for n in [9, 3, 30, 1, 12, 9] {
        let (lcp, z_star) = planted(random_spd(n, &mut rng), &mut rng, false);
        lemke.solve_into(lcp.view(), None, &mut out).unwrap();
        assert!(out.is_solved() && rel_dist(&z_star, &out.z) < 1e-9, "lemke n = {n}");
        pgs.solve_into(lcp.view(), None, &mut out).unwrap();
        assert!(out.is_solved() && rel_dist(&z_star, &out.z) < 1e-6, "pgs n = {n}");
        assert_eq!(out.z.len(), n);
    }
}

#[test]
fn accepted_solutions_pass_the_residual_test_on_badly_scaled_problems() {
    // Lemke accepts the tableau's own basic values when their residual passes and
    // re-solves the final basis otherwise: whichever z it returns as solved must pass the
    // residual test recomputed here, at the default and at much tighter tolerances.
    let mut rng = Rng::new(11);
    let mut solved_by_tolerance = [0usize; 3];
    let tolerances = [1e-9, 1e-13, 1e-15];
    let trials = 60;
    for trial in 0..trials {
        let n = 2 + trial % 9;
        let a = if trial % 2 == 0 { random_p_matrix(n, &mut rng) } else { random_spd(n, &mut rng) };
        let d1: Vec<f64> = (0..n).map(|_| 10f64.powf(rng.uniform(-9.0, 6.0))).collect();
        let d2: Vec<f64> = (0..n).map(|_| 10f64.powf(rng.uniform(-3.0, 3.0))).collect();
        let (base, z_base) = planted(a.clone(), &mut rng, false);
        let m = Mat::from_fn(n, n, |i, j| d1[i] * a[(i, j)] * d2[j]);
        let q = Col::from_fn(n, |i| d1[i] * base.q()[i]);
        let lcp = Lcp::new(m, q).unwrap();
        let z_star: Vec<f64> = (0..n).map(|j| z_base[j] / d2[j]).collect();
        for (t, &tolerance) in tolerances.iter().enumerate() {
            for covering in [Covering::Ones, Covering::RowScaled] {
                let name = format!("{covering:?}");
                let covering_is_row_scaled = covering == Covering::RowScaled;
                let mut lemke = Lemke::new(
                    LemkeOptions::default().with_tolerance(tolerance).with_covering(covering),
                )
                .unwrap();
                let s = lemke.solve(&lcp).unwrap();
                // With d = 1 the column of z_0 spans the row magnitudes and the pivoting
                // may end in a wrong basis (reported honestly); the row-scaled covering
                // is the one for such problems.
                if t == 0 && covering_is_row_scaled {
                    assert_eq!(s.status, Status::Solved, "trial {trial} {name}: {:?}", s.residual);
                }
                if s.status == Status::Solved {
                    solved_by_tolerance[t] += 1;
                    let r = Residual::compute(lcp.view(), &s.z, &s.w);
                    assert!(r.relative <= tolerance, "trial {trial} tol {tolerance}: {r:?}");
                    assert_eq!(r.relative, s.residual.relative, "trial {trial}");
                    assert!(rel_dist(&z_star, &s.z) < 1e-9, "trial {trial}: {:?}", s.z);
                } else {
                    assert_eq!(s.status, Status::NumericalFailure, "trial {trial}");
                    assert!(s.residual.relative > tolerance, "trial {trial}");
                }
            }
        }
    }
    eprintln!("solved per tolerance {tolerances:?}: {solved_by_tolerance:?} of {}", 2 * trials);
    assert!(solved_by_tolerance[0] >= trials, "{solved_by_tolerance:?}");
    // The tight tolerances are met on most problems (by the tableau or by the re-solve).
    assert!(solved_by_tolerance[1] >= trials, "{solved_by_tolerance:?}");
}

#[test]
fn auto_takes_the_basis_a_warm_start_names_and_falls_back_when_it_is_wrong() {
    let mut rng = Rng::new(31);
    let mut auto = Auto::default();
    let mut out = Solution::new();
    for trial in 0..60 {
        // Sizes 1 to 10: both the stack solve (up to 6 basic variables) and the LU.
        let n = 1 + (trial % 10);
        let m = if trial % 2 == 0 { random_spd(n, &mut rng) } else { random_p_matrix(n, &mut rng) };
        let (lcp, z_star) = planted(m, &mut rng, false);
        if z_star.iter().all(|&v| v == 0.0) {
            continue;
        }
        // The planted solution itself names its basis: no pivot.
        auto.solve_into(lcp.view(), Some(&z_star), &mut out).unwrap();
        assert_eq!(
            (out.status, out.method, out.iterations),
            (Status::Solved, Method::WarmBasis, 0)
        );
        assert_solves(&lcp, &out.z, 1e-9);
        assert!(rel_dist(&z_star, &out.z) < 1e-9, "trial {trial}");
        // The complementary guess (every other basis) is wrong unless the solution is zero:
        // the result is Lemke's, and still the planted solution (unique for P-matrices).
        let wrong: Vec<f64> = z_star.iter().map(|&v| if v > 0.0 { 0.0 } else { 1.0 }).collect();
        auto.solve_into(lcp.view(), Some(&wrong), &mut out).unwrap();
        assert_eq!((out.status, out.method), (Status::Solved, Method::Lemke), "trial {trial}");
        assert!(rel_dist(&z_star, &out.z) < 1e-9, "trial {trial}");
    }
}

#[test]
fn a_warm_basis_with_a_negative_basic_value_is_not_accepted() {
    // M = [1 1/2; 1/2 1], q = (1, -1): the solution is z = (0, 1). The guess with both z
    // basic gives z = (-2, 2); clamped to (0, 2) it leaves w = (2, 1), not complementary:
    // rejected, and Lemke solves it.
    let lcp = Lcp::from_rows(&[vec![1.0, 0.5], vec![0.5, 1.0]], &[1.0, -1.0]).unwrap();
    let mut out = Solution::new();
    Auto::default().solve_into(lcp.view(), Some(&[1.0, 1.0]), &mut out).unwrap();
    assert_eq!((out.status, out.method), (Status::Solved, Method::Lemke));
    assert!(rel_dist(&out.z, &[0.0, 1.0]) < 1e-15, "{:?}", out.z);
    // A singular basis (M_αα = 0) is not accepted either.
    let lcp = Lcp::from_rows(&[vec![0.0, 1.0], vec![-1.0, 1.0]], &[-1.0, 2.0]).unwrap();
    Auto::default().solve_into(lcp.view(), Some(&[1.0, 0.0]), &mut out).unwrap();
    assert_ne!(out.method, Method::WarmBasis);
    assert_solves(&lcp, &out.z, 1e-9);
}

#[test]
fn a_warm_start_of_the_wrong_length_or_not_finite_is_an_error() {
    let lcp = Lcp::from_rows(&[vec![2.0]], &[-1.0]).unwrap();
    let mut out = Solution::new();
    let err = Auto::default().solve_into(lcp.view(), Some(&[1.0, 1.0]), &mut out).unwrap_err();
    assert!(matches!(err, LcpError::WarmStartLength { expected: 1, found: 2 }));
    let err = Auto::default().solve_into(lcp.view(), Some(&[f64::NAN]), &mut out).unwrap_err();
    assert!(matches!(err, LcpError::NonFinite { .. }));
}

#[test]
fn the_residual_accumulated_by_rows_is_the_residual_of_the_dense_problem() {
    let mut rng = Rng::new(31);
    for trial in 0..200 {
        let n = 1 + trial % 9;
        let (lcp, z_star) = planted(random_spd(n, &mut rng), &mut rng, false);
        // Candidates near the solution and far from it, with negative entries too.
        let spread = [1e-12, 1e-6, 1.0][trial % 3];
        let z: Vec<f64> = z_star.iter().map(|v| v + spread * rng.uniform(-1.0, 1.0)).collect();
        let (m, q) = (lcp.view().m(), lcp.view().q());
        let mut w = vec![0.0; n];
        let fresh = moreau_lcp::ResidualRows::new(z.iter().copied());
        let mut rows = fresh.clone();
        // The same rows split between two accumulators, the later rows first, then merged.
        let (mut early, mut late) = (fresh.clone(), fresh);
        let cut = rng.below(n as u64 + 1) as usize;
        let mut given = Vec::new();
        for i in 0..n {
            let (mut sum, mut abs) = (q[i], 0.0);
            for j in 0..n {
                let t = m[(i, j)] * z[j];
                sum += t;
                abs += t.abs();
            }
            // w as a solver would report it: the product plus a rounding-sized error.
            w[i] = sum + 1e-15 * rng.uniform(-1.0, 1.0);
            rows.row(q[i], z[i], w[i], abs, sum);
            given.push((q[i], z[i], w[i], abs, sum));
        }
        for &(q, z, w, abs, sum) in given[cut..].iter().rev() {
            late.row(q, z, w, abs, sum);
        }
        for &(q, z, w, abs, sum) in &given[..cut] {
            early.row(q, z, w, abs, sum);
        }
        late.merge(&early);
        let dense = Residual::compute(lcp.view(), &z, &w);
        assert_eq!(late.finish(), dense, "trial {trial}, split at {cut}");
        assert_eq!(rows.finish(), dense, "trial {trial}");
    }
}
