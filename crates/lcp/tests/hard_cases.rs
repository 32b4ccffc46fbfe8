//! Classic hard cases: Murty's exponential problem, degenerate and tied problems,
//! infeasible problems, multiple solutions, degenerate matrices, and the friction LCP.
#![allow(non_snake_case)]

mod common;

use common::{Rng, assert_solves, friction, murty, planted, random_spd, rel_dist};
use faer::{Col, Mat};
use moreau_lcp::{Auto, Enumeration, Lcp, LcpError, Lemke, LemkeOptions, Method, Solver, Status};

/// Murty's matrix transposed: lower triangular, 1 on the diagonal and 2 below.
fn murty_lower(n: usize, q: impl Fn(usize) -> f64) -> Lcp {
    let m = Mat::from_fn(n, n, |i, j| {
        if i == j {
            1.0
        } else if j < i {
            2.0
        } else {
            0.0
        }
    });
    Lcp::new(m, Col::from_fn(n, q)).unwrap()
}

#[test]
fn murty_upper_triangular_with_q_minus_one_is_solved_exactly() {
    // Upper triangular, q = -1: the unique solution is z = e_n (the last row reads
    // w_n = z_n - 1, and every other row is then positive). The lexicographic rule breaks
    // the n-fold tie of the first ratio test towards row n, which ends at once.
    for n in [1, 2, 3, 8, 16] {
        let s = Lemke::default().solve(&murty(n)).unwrap();
        assert_eq!(s.status, Status::Solved, "n = {n}");
        let mut expected = vec![0.0; n];
        expected[n - 1] = 1.0;
        assert_eq!(s.z, expected, "n = {n}");
        assert_eq!(s.iterations, 2);
        assert_eq!(s.residual.relative, 0.0);
    }
}

#[test]
fn murty_exponential_instances_take_two_to_the_n_pivots() {
    // Murty (1978): on these instances Lemke's method with d = 1 makes 2^n - 1
    // complementary pivots after the pivot that brings in z_0.
    for n in [1, 2, 3, 5, 8, 12, 16] {
        // Lower triangular, q = -1: z = e_1.
        let s = Lemke::default().solve(&murty_lower(n, |_| -1.0)).unwrap();
        assert_eq!(s.status, Status::Solved, "n = {n}");
        assert_eq!(s.iterations, 1 << n, "n = {n}");
        let mut expected = vec![0.0; n];
        expected[0] = 1.0;
        assert_eq!(s.z, expected, "n = {n}");
        // Upper triangular, q_i = -(2^(n+1) - 2^(i+1)) (i from 0): z = 2^n e_n, since row i
        // then reads w_i = z_i + 2^(i+1).
        let q = Col::from_fn(n, |i| -(2f64.powi(n as i32 + 1) - 2f64.powi(i as i32 + 1)));
        let lcp = Lcp::new(murty(n).m().to_owned(), q).unwrap();
        let s = Lemke::default().solve(&lcp).unwrap();
        assert_eq!(s.status, Status::Solved, "n = {n}");
        assert_eq!(s.iterations, 1 << n, "n = {n}");
        let mut expected = vec![0.0; n];
        expected[n - 1] = 2f64.powi(n as i32);
        assert_eq!(s.z, expected, "n = {n}");
        for i in 0..n - 1 {
            assert_eq!(s.w[i], 2f64.powi(i as i32 + 1));
        }
    }
}

#[test]
fn murty_sixteen_hits_a_lower_pivot_limit_honestly() {
    let lcp = murty_lower(16, |_| -1.0);
    let mut lemke = Lemke::new(LemkeOptions::default().with_max_pivots(1000)).unwrap();
    let s = lemke.solve(&lcp).unwrap();
    assert_eq!(s.status, Status::IterationLimit);
    assert_eq!(s.iterations, 1000);
    assert!(s.residual.relative > 1e-9);
}

#[test]
fn the_pivot_limit_is_met_exactly_or_ends_the_path_one_pivot_short() {
    // Murty's path has 2^n pivots, its last the one where z_0 leaves: a limit of 2^n
    // solves, 2^n - 1 stops with the limit's status after that many pivots. For n = 5 the
    // path is longer than 2 n = 10 pivots, where the watch for a repeated basis runs.
    for n in [1, 3, 5] {
        let lcp = murty_lower(n, |_| -1.0);
        let path = 1 << n;
        let limit = |k| Lemke::new(LemkeOptions::default().with_max_pivots(k)).unwrap();
        let s = limit(path).solve(&lcp).unwrap();
        assert_eq!((s.status, s.iterations), (Status::Solved, path), "n = {n}");
        let mut e1 = vec![0.0; n];
        e1[0] = 1.0;
        assert_eq!(s.z, e1, "n = {n}");
        let s = limit(path - 1).solve(&lcp).unwrap();
        assert_eq!((s.status, s.iterations), (Status::IterationLimit, path - 1), "n = {n}");
        assert!(s.residual.relative > 1e-9, "n = {n}: {:?}", s.residual);
    }
}

#[test]
fn degenerate_q_with_zero_entries() {
    // q has zeros: the first ratio tests tie at 0. The lexicographic rule must still end.
    let mut rng = Rng::new(11);
    for trial in 0..50 {
        let n = 2 + trial % 9;
        let m = common::random_p_matrix(n, &mut rng);
        // z* with many zeros and w* = 0 on those (both zero): q has zeros.
        let (lcp, z_star) = common::planted(m, &mut rng, true);
        let s = Lemke::default().solve(&lcp).unwrap();
        assert_eq!(s.status, Status::Solved, "trial {trial}");
        assert!(rel_dist(&z_star, &s.z) < 1e-9, "trial {trial}");
    }
}

#[test]
fn fully_degenerate_q_zero_and_ties() {
    // q = 0: z = 0 is the solution at once.
    let lcp = Lcp::from_rows(&[vec![1.0, 2.0], vec![3.0, 1.0]], &[0.0, 0.0]).unwrap();
    let s = Lemke::default().solve(&lcp).unwrap();
    assert_eq!((s.status, s.iterations, s.z.clone()), (Status::Solved, 0, vec![0.0, 0.0]));
    // Identical rows and q: every ratio test ties.
    let lcp = Lcp::from_rows(
        &[vec![1.0, 1.0, 1.0], vec![1.0, 1.0, 1.0], vec![1.0, 1.0, 1.0]],
        &[-1.0, -1.0, -1.0],
    )
    .unwrap();
    let s = Lemke::default().solve(&lcp).unwrap();
    assert_eq!(s.status, Status::Solved);
    assert_solves(&lcp, &s.z, 1e-12);
    assert!((s.z.iter().sum::<f64>() - 1.0).abs() < 1e-14);
    // M = I with q = -1 everywhere: n-fold tie in the first ratio test.
    let n = 12;
    let lcp = Lcp::new(Mat::identity(n, n), Col::from_fn(n, |_| -1.0)).unwrap();
    let s = Lemke::default().solve(&lcp).unwrap();
    // The pivot that brings in z_0, then one per z_i.
    assert_eq!((s.status, s.iterations), (Status::Solved, n + 1));
    assert!(s.z.iter().all(|&v| v == 1.0));
}

#[test]
fn cycling_prone_degenerate_problem_terminates() {
    // A degenerate problem with a zero diagonal and ties at zero (q has zeros); without
    // a lexicographic rule Lemke's method can revisit bases here. It has no solution: the
    // second row reads w2 = −z1 − 1 < 0 for every z1 >= 0. (Its transpose is Siconos'
    // `lcp_Pang_isolated_sol`, whose file lists M by columns, with the isolated solution
    // z = (1, 0, 0): siconos_lcp.rs.)
    let lcp = Lcp::from_rows(
        &[vec![0.0, 1.0, -1.0], vec![-1.0, 0.0, 0.0], vec![-1.0, 0.0, 0.0]],
        &[0.0, -1.0, 1.0],
    )
    .unwrap();
    let all = Enumeration::default().solve_all(lcp.view()).unwrap();
    assert!(all.is_empty(), "{all:?}");
    assert_eq!(Enumeration::default().solve(&lcp).unwrap().status, Status::NoSolution);
    // Auto decides it by enumeration; Lemke's method ends on a ray, within a few pivots.
    let auto = Auto::default().solve(&lcp).unwrap();
    assert_eq!((auto.status, auto.method), (Status::NoSolution, Method::Enumeration));
    let lemke = Lemke::default().solve(&lcp).unwrap();
    assert_eq!(lemke.status, Status::RayTermination);
    assert!(!lemke.is_solved());
    assert!(lemke.iterations <= 20);
}

#[test]
fn infeasible_positive_semidefinite_problem_ends_on_a_ray() {
    // M = [[1, -1], [-1, 1]] is PSD (copositive-plus); w1 + w2 = -2 < 0: no solution.
    let lcp = Lcp::from_rows(&[vec![1.0, -1.0], vec![-1.0, 1.0]], &[-1.0, -1.0]).unwrap();
    let l = Lemke::default().solve(&lcp).unwrap();
    assert_eq!(l.status, Status::RayTermination);
    assert!(!l.is_solved());
    let e = Enumeration::default().solve(&lcp).unwrap();
    assert_eq!(e.status, Status::NoSolution);
    let a = Auto::default().solve(&lcp).unwrap();
    assert_eq!((a.status, a.method), (Status::NoSolution, Method::Enumeration));
    // Without enumeration Auto reports Lemke's status and never claims NoSolution.
    let mut no_enum =
        Auto::new(moreau_lcp::AutoOptions::default().with_enumeration_max_n(0)).unwrap();
    let a = no_enum.solve(&lcp).unwrap();
    assert_eq!((a.status, a.method), (Status::RayTermination, Method::Lemke));
}

#[test]
fn multiple_solutions_are_all_found() {
    // w1 = z1 + 2 z2 - 1, w2 = 2 z1 + z2 - 1: solutions (1, 0), (0, 1), (1/3, 1/3).
    let lcp = Lcp::from_rows(&[vec![1.0, 2.0], vec![2.0, 1.0]], &[-1.0, -1.0]).unwrap();
    let mut all: Vec<Vec<f64>> =
        Enumeration::default().solve_all(lcp.view()).unwrap().into_iter().map(|s| s.z).collect();
    all.sort_by(|a, b| a[0].total_cmp(&b[0]));
    assert_eq!(all.len(), 3);
    assert_eq!(all[0], vec![0.0, 1.0]);
    assert!((all[1][0] - 1.0 / 3.0).abs() < 1e-15 && (all[1][1] - 1.0 / 3.0).abs() < 1e-15);
    assert_eq!(all[2], vec![1.0, 0.0]);
    // Lemke and Auto find one of them.
    for s in [Lemke::default().solve(&lcp).unwrap(), Auto::default().solve(&lcp).unwrap()] {
        assert!(s.is_solved());
        assert!(all.iter().any(|z| rel_dist(z, &s.z) < 1e-12));
    }
    // A continuum (z1 + z2 = 1) is reported by its vertices.
    let lcp = Lcp::from_rows(&[vec![1.0, 1.0], vec![1.0, 1.0]], &[-1.0, -1.0]).unwrap();
    let all = Enumeration::default().solve_all(lcp.view()).unwrap();
    assert_eq!(all.len(), 2);
    for s in &all {
        assert!((s.z[0] + s.z[1] - 1.0).abs() < 1e-15 && s.z[0] * s.z[1] == 0.0);
    }
}

#[test]
fn solution_hidden_from_principal_bases_is_found_by_the_vertex_pass() {
    // M = [[0, 0], [1, 0]], q = (0, -1): every principal submatrix containing index 1 or
    // 0 is singular, yet z = (1, 0) solves (w = (0, 0)).
    let lcp = Lcp::from_rows(&[vec![0.0, 0.0], vec![1.0, 0.0]], &[0.0, -1.0]).unwrap();
    let e = Enumeration::default().solve(&lcp).unwrap();
    assert_eq!(e.status, Status::Solved);
    assert_eq!(e.z, vec![1.0, 0.0]);
    assert_eq!(e.w, vec![0.0, 0.0]);
    let all = Enumeration::default().solve_all(lcp.view()).unwrap();
    assert_eq!(all.len(), 1);
    let a = Auto::default().solve(&lcp).unwrap();
    assert!(a.is_solved());
    assert_solves(&lcp, &a.z, 1e-12);
    // With the vertex pass disabled the search is incomplete and says so.
    let mut short =
        Enumeration::new(moreau_lcp::EnumerationOptions::default().with_max_n_degenerate(1))
            .unwrap();
    assert_eq!(short.solve(&lcp).unwrap().status, Status::TooLarge);
    // And the list of every solution is not given as if it were complete (it was empty).
    assert!(matches!(short.solve_all(lcp.view()), Err(LcpError::TooLarge { n: 2, max: 1 })));
    // The same above the default guard of the vertex pass (n = 12): the problem padded with
    // 11 rows z_i = 0, w_i = 1 has the one solution z = e_1, which no principal basis holds.
    let n = 13;
    let m =
        Mat::from_fn(n, n, |i, j| if (i, j) == (1, 0) || (i == j && i >= 2) { 1.0 } else { 0.0 });
    let q = Col::from_fn(n, |i| [0.0, -1.0, 1.0][i.min(2)]);
    let padded = Lcp::new(m, q).unwrap();
    let e1: Vec<f64> = (0..n).map(|i| if i == 0 { 1.0 } else { 0.0 }).collect();
    let w: Vec<f64> = (0..n).map(|i| if i >= 2 { 1.0 } else { 0.0 }).collect();
    assert_eq!(moreau_lcp::Residual::compute(padded.view(), &e1, &w).relative, 0.0);
    assert!(matches!(
        Enumeration::default().solve_all(padded.view()),
        Err(LcpError::TooLarge { n: 13, max: 12 })
    ));
    assert_eq!(Enumeration::default().solve(&padded).unwrap().status, Status::TooLarge);
}

#[test]
fn friction_lcps_are_solved_and_agree_with_enumeration() {
    let mut rng = Rng::new(12);
    let mut solved = 0;
    for trial in 0..30 {
        let nc = 1 + trial % 3;
        let ndof = 3 + trial % 3;
        let f = friction(nc, ndof, &mut rng);
        let auto = Auto::default().solve(&f.lcp).unwrap();
        let all = Enumeration::default().solve_all(f.lcp.view()).unwrap();
        // Auto is solved exactly when enumeration finds solutions, and otherwise says
        // NoSolution (enumeration runs inside Auto for n <= 12).
        assert_eq!(auto.is_solved(), !all.is_empty(), "trial {trial}: {:?}", auto.status);
        if all.is_empty() {
            assert_eq!(auto.status, Status::NoSolution);
            continue;
        }
        solved += 1;
        assert_solves(&f.lcp, &auto.z, 1e-9);
        // Compare through the velocity change, which is unique even when x is not.
        let du = f.delta_u(&auto.z);
        let du_scale = du.iter().fold(1.0f64, |a, v| a.max(v.abs()));
        let matches = all.iter().any(|s| {
            f.delta_u(&s.z).iter().zip(&du).all(|(a, b)| (a - b).abs() <= 1e-8 * du_scale)
        });
        assert!(matches, "trial {trial}: Auto's velocity change is not among enumeration's");
        let lemke = Lemke::default().solve(&f.lcp).unwrap();
        assert!(lemke.is_solved(), "trial {trial}: Lemke {:?}", lemke.status);
        assert_solves(&f.lcp, &lemke.z, 1e-9);
    }
    assert!(solved >= 25, "only {solved} of 30 random friction LCPs have solutions");
}

#[test]
fn friction_lcp_zero_impulse_when_separating() {
    // Normal entries of b >= 0 and tangential ones negative: q is not >= 0, but
    // P_N = P_R = 0, ξ_L = max(0, -b_R) solves (docs/theory.md section 5).
    let mut rng = Rng::new(13);
    let f = friction(2, 4, &mut rng);
    let nc = 2;
    let q: Vec<f64> = (0..3 * nc)
        .map(|i| match i / nc {
            0 => 0.5,
            1 => -0.25,
            _ => 0.0,
        })
        .collect();
    let m = f.lcp.m().to_owned();
    let lcp = Lcp::new(m, faer::Col::from_fn(3 * nc, |i| q[i])).unwrap();
    let s = Auto::default().solve(&lcp).unwrap();
    assert!(s.is_solved());
    let du = f.delta_u(&s.z);
    assert!(du.iter().all(|v| v.abs() < 1e-12), "{du:?}");
}

#[test]
fn lemke_with_d_1_solves_a_positive_definite_problem_at_any_scale() {
    // (M, q) times s > 0 has the same solutions. With d = 1, M of order 1e-12 put z_0's row
    // below the pivot tolerance once z_0 was basic, and the method ended on a secondary ray,
    // which for a positive definite M claims that there is no solution; at 1e12 it failed.
    let small = Lcp::from_rows(&[vec![1e-12, 0.0], vec![0.0, 1e-12]], &[-1e-12, -2e-12]).unwrap();
    let s = Lemke::default().solve(&small).unwrap();
    assert_eq!(s.status, Status::Solved, "{s:?}");
    assert_eq!(s.z, [1.0, 2.0]);
    let mut rng = Rng::new(21);
    for trial in 0..24 {
        let n = [2, 3, 5, 9, 20, 40][trial % 6];
        let (base, z_star) = planted(random_spd(n, &mut rng), &mut rng, trial % 2 == 0);
        let at_one = Lemke::default().solve(&base).unwrap();
        assert_eq!(at_one.status, Status::Solved, "trial {trial}");
        for scale in [1e-30, 1e-12, 1e-11, 2f64.powi(-40), 1e12, 2f64.powi(40), 1e30, 1e100] {
            let lcp = Lcp::new(
                Mat::from_fn(n, n, |i, j| scale * base.m()[(i, j)]),
                Col::from_fn(n, |i| scale * base.q()[i]),
            )
            .unwrap();
            let s = Lemke::default().solve(&lcp).unwrap();
            assert_eq!(s.status, Status::Solved, "trial {trial}, n = {n}, scale {scale:e}: {s:?}");
            assert!(rel_dist(&z_star, &s.z) < 1e-9, "trial {trial}, scale {scale:e}");
            assert!(s.residual.relative <= 1e-9);
            // The covering vector's scale changes z_0 alone: the same pivots as at scale 1.
            assert_eq!(s.iterations, at_one.iterations, "trial {trial}, scale {scale:e}");
        }
    }
}
