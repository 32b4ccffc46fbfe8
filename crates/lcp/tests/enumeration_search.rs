//! Enumeration's search in closed form: how many bases a complete search examines with and
//! without singular principal submatrices, what it reports when it proves there is no
//! solution, and the solution that only its vertex pass reaches.
#![allow(non_snake_case)]

use faer::{Col, Mat};
use moreau_lcp::{Enumeration, EnumerationOptions, Lcp, LcpError, Method, Solver, Status};

/// C(2n, n): the square systems `M_SK` with |S| = |K| over all sizes.
fn central_binomial(n: usize) -> usize {
    (1..=n).fold(1, |c, k| c * (n + k) / k)
}

#[test]
fn a_nondegenerate_problem_without_solution_examines_every_principal_basis() {
    // M = -I, q = -1: w = -1 - z < 0 for every z >= 0. Every M_αα is regular, so the search
    // is the 2^n principal bases alone, and it ends NoSolution at z = 0 (w = q).
    for n in 1..=4 {
        let lcp = Lcp::new(-Mat::<f64>::identity(n, n), Col::from_fn(n, |_| -1.0)).unwrap();
        let s = Enumeration::default().solve(&lcp).unwrap();
        assert_eq!((s.status, s.method), (Status::NoSolution, Method::Enumeration), "n = {n}");
        assert_eq!(s.iterations, 1 << n, "n = {n}");
        assert_eq!(s.z, vec![0.0; n]);
        assert_eq!(s.w, vec![-1.0; n]);
        assert_eq!(s.residual.relative, 1.0);
        assert!(Enumeration::default().solve_all(lcp.view()).unwrap().is_empty());
    }
}

#[test]
fn a_zero_matrix_with_negative_q_examines_every_square_system() {
    // M = 0, q = -1: no solution, and every M_SK but the empty one is singular, so the
    // vertex pass runs too: 2^n principal systems and the C(2n, n) - 2^n others.
    for n in 1..=4 {
        let lcp = Lcp::new(Mat::<f64>::zeros(n, n), Col::from_fn(n, |_| -1.0)).unwrap();
        let s = Enumeration::default().solve(&lcp).unwrap();
        assert_eq!(s.status, Status::NoSolution, "n = {n}");
        assert_eq!(s.iterations, central_binomial(n), "n = {n}");
        assert_eq!((s.z.clone(), s.w.clone()), (vec![0.0; n], vec![-1.0; n]));
        // Without the vertex pass the search is incomplete: TooLarge, after the principal
        // bases alone.
        let options = EnumerationOptions::default().with_max_n_degenerate(n - 1);
        let s = Enumeration::new(options).unwrap().solve(&lcp).unwrap();
        assert_eq!((s.status, s.iterations), (Status::TooLarge, 1 << n), "n = {n}");
    }
    assert_eq!(central_binomial(4), 70);
}

#[test]
fn the_vertex_pass_finds_a_solution_whose_rows_and_columns_differ() {
    // M = [[0, 1], [0, 0]], q = (-1, 0): w_1 = z_2 - 1 and w_2 = 0, so z = (0, 1) gives
    // w = 0; every principal submatrix but the empty one is singular, so no principal basis
    // holds it, but the system M_12 z_2 = -q_1 (row 1, column 2) does.
    let lcp = Lcp::from_rows(&[vec![0.0, 1.0], vec![0.0, 0.0]], &[-1.0, 0.0]).unwrap();
    let s = Enumeration::default().solve(&lcp).unwrap();
    assert_eq!(s.status, Status::Solved);
    assert_eq!((s.z.as_slice(), s.w.as_slice()), ([0.0, 1.0].as_slice(), [0.0, 0.0].as_slice()));
    assert_eq!(s.residual.relative, 0.0);
    // The bases examined: the four principal ones, then one or both of the two pairs of
    // size one with S != K, whichever order they come in.
    assert!((5..=6).contains(&s.iterations), "{} bases", s.iterations);
    let all = Enumeration::default().solve_all(lcp.view()).unwrap();
    assert_eq!(all.len(), 1);
    assert_eq!(all[0].z, vec![0.0, 1.0]);
}

#[test]
fn one_vertex_reached_from_two_bases_with_different_roundings_is_listed_once() {
    // M = [[3, 3], [7, 7]], q = (-1e6, -7e6 / 3): the solutions are z_1 + z_2 = 1e6 / 3, with
    // the vertices (1e6 / 3, 0) and (0, 1e6 / 3). Each vertex is reached from row 1 (by a
    // division by 3) and from row 2 (by 7), whose results differ by 6e-11, far below 1e-7 of
    // the size of z (3.3e5): two solutions, not four.
    let third = 1e6 / 3.0;
    let lcp = Lcp::from_rows(&[vec![3.0, 3.0], vec![7.0, 7.0]], &[-1e6, -7e6 / 3.0]).unwrap();
    assert_ne!(-lcp.q()[1] / 7.0, third, "the two rows must round differently");
    let all = Enumeration::default().solve_all(lcp.view()).unwrap();
    assert_eq!(all.len(), 2, "{all:?}");
    for s in &all {
        assert_eq!(s.status, Status::Solved);
        assert!(s.z.contains(&0.0), "{:?}", s.z);
        assert!(((s.z[0] + s.z[1]) - third).abs() <= 1e-9 * third, "{:?}", s.z);
    }
    assert!(all[0].z[0] == 0.0 || all[1].z[0] == 0.0);
}

#[test]
fn a_problem_of_size_max_n_is_searched_and_one_row_more_is_refused() {
    // max_n = 3: n = 3 (M = I, q = -1, z = 1) is solved, n = 4 is TooLarge { n: 4, max: 3 },
    // for the first solution and for the list alike.
    let options = EnumerationOptions::default().with_max_n(3).with_max_n_degenerate(3);
    let mut enumeration = Enumeration::new(options).unwrap();
    let lcp = |n: usize| Lcp::new(Mat::identity(n, n), Col::from_fn(n, |_| -1.0)).unwrap();
    let s = enumeration.solve(&lcp(3)).unwrap();
    assert_eq!((s.status, s.z.as_slice()), (Status::Solved, [1.0; 3].as_slice()));
    assert_eq!(enumeration.solve_all(lcp(3).view()).unwrap().len(), 1);
    let too_large = |r: Result<_, LcpError>| matches!(r, Err(LcpError::TooLarge { n: 4, max: 3 }));
    assert!(too_large(enumeration.solve(&lcp(4)).map(|_| ())));
    assert!(too_large(enumeration.solve_all(lcp(4).view()).map(|_| ())));
}
