//! Lemke's method along paths of known length: no pivot when q >= 0, the pivot limit met
//! exactly or one pivot short on Murty's problems (2^n pivots), and the ends of the
//! shortest paths.
#![allow(non_snake_case)]

use faer::{Col, Mat};
use moreau_lcp::{Lcp, Lemke, LemkeOptions, Method, Solver, Status};

/// Murty's matrix transposed (lower triangular, 1 on the diagonal, 2 below) with q = -1:
/// the solution is z = e_1, reached after 2^n pivots with d = 1.
fn murty_lower(n: usize) -> Lcp {
    let m = Mat::from_fn(n, n, |i, j| match i.cmp(&j) {
        std::cmp::Ordering::Equal => 1.0,
        std::cmp::Ordering::Greater => 2.0,
        std::cmp::Ordering::Less => 0.0,
    });
    Lcp::new(m, Col::from_fn(n, |_| -1.0)).unwrap()
}

fn lemke(max_pivots: usize) -> Lemke {
    Lemke::new(LemkeOptions::default().with_max_pivots(max_pivots)).unwrap()
}

#[test]
fn a_non_negative_q_is_solved_by_z_zero_without_a_pivot() {
    // q >= 0 (zeros included, -0 too): z = 0 and w = q solve, whatever M.
    let lcp = Lcp::from_rows(&[vec![-1.0, 3.0], vec![2.0, -5.0]], &[0.0, 2.0]).unwrap();
    let s = Lemke::default().solve(&lcp).unwrap();
    assert_eq!((s.status, s.method, s.iterations), (Status::Solved, Method::Lemke, 0));
    assert_eq!((s.z.as_slice(), s.w.as_slice()), ([0.0, 0.0].as_slice(), [0.0, 2.0].as_slice()));
    assert_eq!(s.residual.relative, 0.0);
    let lcp = Lcp::from_rows(&[vec![-1.0]], &[-0.0]).unwrap();
    let s = Lemke::default().solve(&lcp).unwrap();
    assert_eq!((s.status, s.iterations, s.z[0]), (Status::Solved, 0, 0.0));
}

#[test]
fn the_pivot_limit_is_met_exactly_or_ends_the_path_one_pivot_short() {
    // Murty's path has 2^n pivots, its last the one where z_0 leaves: a limit of 2^n
    // solves, 2^n - 1 stops with the limit's status after that many pivots. For n = 5 the
    // path is longer than 2 n = 10 pivots, where the watch for a repeated basis runs.
    for n in [1, 3, 5] {
        let lcp = murty_lower(n);
        let path = 1 << n;
        let s = lemke(path).solve(&lcp).unwrap();
        assert_eq!((s.status, s.iterations), (Status::Solved, path), "n = {n}");
        let mut e1 = vec![0.0; n];
        e1[0] = 1.0;
        assert_eq!(s.z, e1, "n = {n}");
        let s = lemke(path - 1).solve(&lcp).unwrap();
        assert_eq!((s.status, s.iterations), (Status::IterationLimit, path - 1), "n = {n}");
        assert!(s.residual.relative > 1e-9, "n = {n}: {:?}", s.residual);
    }
}

#[test]
fn a_zero_column_ends_the_path_on_a_ray_after_the_first_pivot() {
    // M = 0, q = -1 (n = 1): z_0 = 1 enters and w leaves; the entering z has the zero
    // column, which no row blocks. M = 0 is positive semidefinite, so the ray proves that
    // there is no solution (w = -1 for every z).
    let lcp = Lcp::from_rows(&[vec![0.0]], &[-1.0]).unwrap();
    let s = Lemke::default().solve(&lcp).unwrap();
    assert_eq!((s.status, s.iterations), (Status::RayTermination, 1), "{s:?}");
    assert!(!s.is_solved());
    // The same with the row-scaled covering vector.
    let options = LemkeOptions::default().with_covering(moreau_lcp::Covering::RowScaled);
    let s = Lemke::new(options).unwrap().solve(&lcp).unwrap();
    assert_eq!((s.status, s.iterations), (Status::RayTermination, 1), "{s:?}");
}

#[test]
fn a_scalar_problem_takes_two_pivots() {
    // M = [a], q = [-b] with a, b > 0: z_0 enters (w leaves), z enters and z_0 leaves:
    // z = b / a, w = 0, after exactly two pivots; one pivot allowed stops short.
    for (a, b) in [(1.0, 1.0), (4.0, 2.0), (0.25, 3.0)] {
        let lcp = Lcp::from_rows(&[vec![a]], &[-b]).unwrap();
        let s = Lemke::default().solve(&lcp).unwrap();
        assert_eq!((s.status, s.iterations), (Status::Solved, 2));
        assert_eq!((s.z[0], s.w[0]), (b / a, 0.0));
        let s = lemke(1).solve(&lcp).unwrap();
        assert_eq!((s.status, s.iterations), (Status::IterationLimit, 1));
    }
}
