//! Lemke's method along its shortest paths: no pivot when q >= 0, a ray after one pivot on a
//! zero column, two pivots on a scalar problem, and a pivot limit of one that stops short.
#![allow(non_snake_case)]

use moreau_lcp::{Lcp, Lemke, LemkeOptions, Method, Solver, Status};

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
