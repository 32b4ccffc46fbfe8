//! Siconos numerics' LCP test problems (tests/data/siconos/lcp, copied unchanged; see its
//! README), each solved by Auto, Lemke's method and enumeration (where n allows it), against
//! the outcome known for it: the solutions in closed form where they are, the vertices of a
//! continuum of solutions, no solution (`lcp_Pang_isolated_sol_perturbed`), Lemke's method
//! ending on a ray where Siconos documents that Lemke-based solvers fail (`lcp_CPS_3`, a
//! bimatrix game for Lemke–Howson), and enumeration's typed refusal beyond its size limit.

mod common;

use std::path::PathBuf;

use common::{assert_solves, rel_dist};
use moreau_lcp::{
    Auto, Enumeration, EnumerationOptions, Lcp, LcpError, Lemke, Method, Solver, Status,
};

/// What enumeration reports for a problem.
enum Solutions {
    /// Every solution, or for a continuum every vertex of the solution set, in some order.
    Known(Vec<Vec<f64>>),
    /// This many solutions, none with a closed form.
    Count(usize),
    /// n exceeds enumeration's default `max_n`.
    TooLarge,
}

/// One file and its expected outcome.
struct Case {
    file: &'static str,
    /// The status Lemke's method (covering vector 1) ends with.
    lemke: Status,
    /// The status and method of Auto's answer.
    auto: (Status, Method),
    solutions: Solutions,
    /// Lemke's pivots, where they are known.
    pivots: Option<usize>,
}

fn unit(n: usize, k: usize, value: f64) -> Vec<f64> {
    let mut z = vec![0.0; n];
    z[k] = value;
    z
}

fn cases() -> Vec<Case> {
    use Solutions::*;
    let solved = (Status::Solved, Method::Lemke);
    let case = |file, lemke, auto, solutions, pivots| Case { file, lemke, auto, solutions, pivots };
    // M = [[2, 1], [1, 2]], q = (−5, −6): positive definite, z = (4/3, 7/3).
    let deudeu = || Known(vec![vec![4.0 / 3.0, 7.0 / 3.0]]);
    // w3 = 3 z3 + z2 − z4 − 1 = 0 and w1 = 3 z1 + z2 − z4 − 2 = 0 with z2 = z4 = 0.
    let ortiz = || Known(vec![vec![2.0 / 3.0, 0.0, 1.0 / 3.0, 0.0]]);
    // M = diag(1, ..., 9), q = −1: z_i = 1/i.
    let trivial = || Known(vec![(1..=9).map(|i| 1.0 / i as f64).collect()]);
    vec![
        // M = [[1, 1], [1, 1]], q = −1 (CPS Remark 4.1.14): the segment z1 + z2 = 1.
        case(
            "lcp_CPS_1.dat",
            Status::Solved,
            solved,
            Known(vec![unit(2, 0, 1.0), unit(2, 1, 1.0)]),
            None,
        ),
        // CPS Example 4.4.7: w = (2, 0, 0) at z = (0, 1, 3), the only solution.
        case("lcp_CPS_2.dat", Status::Solved, solved, Known(vec![vec![0.0, 1.0, 3.0]]), None),
        // CPS Example 4.4.23, a bimatrix game: Lemke's method with covering vector 1 ends on
        // a ray at once (Siconos marks every Lemke-based solver as failing on it); Auto falls
        // back to enumeration, which finds the game's three equilibria.
        case(
            "lcp_CPS_3.dat",
            Status::RayTermination,
            (Status::Solved, Method::Enumeration),
            Known(vec![
                vec![0.1, 0.0, 0.1, 0.0],
                vec![0.0, 1.0 / 15.0, 0.0, 1.0 / 15.0],
                vec![1.0 / 90.0, 4.0 / 90.0, 1.0 / 90.0, 4.0 / 90.0],
            ]),
            None,
        ),
        // A convex QP's KKT system (Q and the constraint z1 + z2 + z3 >= 6): one solution
        // each, with the constraint's multiplier last.
        case("lcp_CPS_4.dat", Status::Solved, solved, Known(vec![vec![2.0, 2.0, 2.0, 92.0]]), None),
        case(
            "lcp_CPS_4bis.dat",
            Status::Solved,
            solved,
            Known(vec![vec![3.0, 3.0, 0.0, 83.0]]),
            None,
        ),
        // M = [[1, −1], [−1, 1]], q = (1, −1) (CPS Example 4.4.16): w1 = −w2 forces
        // w = 0, the ray z = (t, 1 + t), whose one vertex is (0, 1).
        case("lcp_CPS_5.dat", Status::Solved, solved, Known(vec![vec![0.0, 1.0]]), None),
        // w1 = −z2 − z3, w2 = z1 − 1, w3 = 1 − z1: the isolated, totally degenerate solution
        // z = (1, 0, 0), w = 0.
        case(
            "lcp_Pang_isolated_sol.dat",
            Status::Solved,
            solved,
            Known(vec![unit(3, 0, 1.0)]),
            None,
        ),
        // q1 = −1e-4 makes w1 = −z2 − z3 − 1e-4 < 0: no solution (Siconos' enumeration test
        // on it is marked to fail). Lemke's method ends on a ray, enumeration proves it.
        case(
            "lcp_Pang_isolated_sol_perturbed.dat",
            Status::RayTermination,
            (Status::NoSolution, Method::Enumeration),
            Known(vec![]),
            None,
        ),
        case("lcp_deudeu.dat", Status::Solved, solved, deudeu(), None),
        case("lcp_deudeu_block.dat", Status::Solved, solved, deudeu(), None),
        // Kept by Siconos to show its enumeration failing, "likely due to numerical
        // problems": this one finds the one solution, which Lemke's method and Auto meet.
        case("lcp_enum_fails.dat", Status::Solved, solved, Count(1), None),
        // Murty's upper-triangular matrix (1 on the diagonal, 2 above), n = 6: z = e_6 in the
        // pivot that brings in z_0 and one more, and with q_i = −(2^7 − 2^i) z = 2^6 e_6
        // after 2^6 pivots.
        case("lcp_exp_murty.dat", Status::Solved, solved, Known(vec![unit(6, 5, 1.0)]), Some(2)),
        case("lcp_exp_murty2.dat", Status::Solved, solved, Known(vec![unit(6, 5, 64.0)]), Some(64)),
        // w1 = −z2 + z3 − 1e-4, w2 = z1 − 1, w3 = 1 − z1: the ray z = (1, t, t + 1e-4),
        // whose one vertex is (1, 0, 1e-4).
        case(
            "lcp_inf_sol_perturbed.dat",
            Status::Solved,
            solved,
            Known(vec![vec![1.0, 0.0, 1e-4]]),
            None,
        ),
        case("lcp_mmc.dat", Status::Solved, solved, TooLarge, None),
        case("lcp_ortiz.dat", Status::Solved, solved, ortiz(), None),
        case("lcp_ortiz_block.dat", Status::Solved, solved, ortiz(), None),
        // n = 40; its 127 pivots are checked in lemke_degenerate.rs.
        case("lcp_tobenna.dat", Status::Solved, solved, TooLarge, None),
        case("lcp_trivial.dat", Status::Solved, solved, trivial(), None),
        case("lcp_trivial_block.dat", Status::Solved, solved, trivial(), None),
    ]
}

fn dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/siconos/lcp")
}

#[test]
fn every_file_of_the_collection_is_listed() {
    let mut files: Vec<String> = std::fs::read_dir(dir())
        .unwrap()
        .map(|entry| entry.unwrap().file_name().into_string().unwrap())
        .filter(|name| name.ends_with(".dat"))
        .collect();
    files.sort();
    let listed: Vec<&str> = cases().iter().map(|c| c.file).collect();
    assert_eq!(files, listed);
}

#[test]
fn every_problem_has_its_known_outcome_with_each_method() {
    let max_n = EnumerationOptions::default().max_n;
    for c in cases() {
        let file = std::fs::File::open(dir().join(c.file)).unwrap();
        let lcp = Lcp::read_siconos(file).unwrap_or_else(|e| panic!("{}: {e}", c.file));
        let name = c.file;
        // Enumeration: every solution (or vertex), each of which solves the problem.
        let found = match Enumeration::default().solve_all(lcp.view()) {
            Ok(all) => {
                for s in &all {
                    assert_eq!(s.status, Status::Solved, "{name}");
                    assert_solves(&lcp, &s.z, 1e-12);
                }
                let single = Enumeration::default().solve(&lcp).unwrap();
                let expected = if all.is_empty() { Status::NoSolution } else { Status::Solved };
                assert_eq!(single.status, expected, "{name}");
                Some(all.into_iter().map(|s| s.z).collect::<Vec<_>>())
            }
            Err(LcpError::TooLarge { n, max }) => {
                assert!(matches!(c.solutions, Solutions::TooLarge), "{name}: refused");
                assert_eq!((n, max), (lcp.n(), max_n), "{name}");
                assert!(n > max_n);
                None
            }
            Err(e) => panic!("{name}: {e}"),
        };
        match (&c.solutions, &found) {
            (Solutions::Known(expected), Some(all)) => {
                assert_eq!(all.len(), expected.len(), "{name}: {all:?}");
                for z in expected {
                    assert!(all.iter().any(|s| rel_dist(z, s) < 1e-12), "{name}: {z:?} in {all:?}");
                }
            }
            (Solutions::Count(k), Some(all)) => assert_eq!(all.len(), *k, "{name}"),
            (Solutions::TooLarge, None) => {}
            _ => panic!("{name}: enumeration found {found:?}"),
        }
        // Lemke's method and Auto: the expected status, and when solved a solution, one of
        // those enumeration found where it could enumerate.
        let lemke = Lemke::default().solve(&lcp).unwrap();
        let auto = Auto::default().solve(&lcp).unwrap();
        assert_eq!(lemke.status, c.lemke, "{name}: Lemke {:?}", lemke.residual);
        assert_eq!((auto.status, auto.method), c.auto, "{name}: Auto {:?}", auto.residual);
        if let Some(pivots) = c.pivots {
            assert_eq!(lemke.iterations, pivots, "{name}");
        }
        for s in [&lemke, &auto] {
            if s.is_solved() {
                assert_solves(&lcp, &s.z, 1e-12);
                if let Some(all) = &found {
                    assert!(all.iter().any(|z| rel_dist(z, &s.z) < 1e-12), "{name}: {:?}", s.z);
                }
            }
        }
    }
}
