//! Data near the end of f64's range: entries whose products overflow are refused with a
//! typed error, and a problem whose solution no f64 vector represents never gets NaN, a
//! false success or a false "no solution".

use moreau_lcp::{
    Auto, Enumeration, Lcp, LcpError, LcpRef, Lemke, MAX_ENTRY, Pgs, Solution, Solver, Status,
};

/// `w = M z + q` with every entry of M near 1e308 and `z = (1, 0)` a solution:
/// `w = (0, M_21 + q_2) = (0, 1e308)`.
fn huge() -> (Vec<Vec<f64>>, Vec<f64>) {
    (vec![vec![1e308, 1e308], vec![1e308, 1e308]], vec![-1e308, 0.0])
}

#[test]
fn entries_whose_products_overflow_are_refused_naming_the_entry() {
    let (m, q) = huge();
    let err = Lcp::from_rows(&m, &q).unwrap_err();
    match err {
        LcpError::OutOfRange { what, index, value } => {
            assert_eq!((what, index, value), ("M", (0, 0), 1e308));
        }
        other => panic!("expected OutOfRange, got {other:?}"),
    }
    let message = Lcp::from_rows(&m, &q).unwrap_err().to_string();
    assert!(message.contains("M[0][0] = 1e308") && message.contains("scale"), "{message}");
    // The allocation-free entry point and the file reader refuse it alike.
    let cols = [1e308, 1e308, 1e308, 1e308];
    assert!(matches!(
        LcpRef::from_column_major(2, &cols, &q),
        Err(LcpError::OutOfRange { what: "M", index: (0, 0), .. })
    ));
    let text = "2\n1 1e-3\n0 1\n-1 -1.7e308\n";
    assert!(matches!(
        Lcp::read_any(text),
        Err(LcpError::OutOfRange { what: "q", index: (1, 0), .. })
    ));
    // The bound itself is accepted, the next f64 above it is not.
    assert!(Lcp::from_rows(&[vec![MAX_ENTRY]], &[-MAX_ENTRY]).is_ok());
    let above = f64::from_bits(MAX_ENTRY.to_bits() + 1);
    assert!(matches!(
        Lcp::from_rows(&[vec![1.0]], &[above]),
        Err(LcpError::OutOfRange { what: "q", .. })
    ));
}

#[test]
fn the_same_problem_scaled_into_range_is_solved_by_every_solver() {
    // Rows of (M, q) scaled by 2^-1000 (exact) keep the solution z = (1, 0).
    let (m, q) = huge();
    let s = 2f64.powi(-1000);
    let m: Vec<Vec<f64>> = m.iter().map(|r| r.iter().map(|v| v * s).collect()).collect();
    let q: Vec<f64> = q.iter().map(|v| v * s).collect();
    let lcp = Lcp::from_rows(&m, &q).unwrap();
    let solvers: [Box<dyn Solver>; 3] =
        [Box::new(Auto::default()), Box::new(Lemke::default()), Box::new(Enumeration::default())];
    for mut solver in solvers {
        let sol = solver.solve(&lcp).unwrap();
        assert_eq!(sol.status, Status::Solved);
        assert_eq!(sol.z, vec![1.0, 0.0]);
        assert_eq!(sol.w, vec![0.0, 1e308 * s]);
    }
}

/// Checks that a solution holds no NaN or infinity and does not claim success.
fn assert_finite_and_unsolved(sol: &Solution, who: &str) {
    assert!(sol.z.iter().chain(&sol.w).all(|v| v.is_finite()), "{who}: {sol:?}");
    assert!(sol.residual.relative.is_finite(), "{who}: {:?}", sol.residual);
    assert!(!sol.is_solved(), "{who}");
    assert_ne!(sol.status, Status::NoSolution, "{who}");
}

#[test]
fn a_solution_beyond_the_range_of_f64_gives_no_nan_and_no_false_verdict() {
    // Entries within range, but the only solution z = (1e300, 0) has w_2 = 1e450:
    // w_1 = 1e-150 z_1 − 1e150 = 0 needs z_1 = 1e300, and w_2 = 1e150 z_1 + z_2 > 0 forces
    // z_2 = 0.
    let lcp = Lcp::from_rows(&[vec![1e-150, 0.0], vec![1e150, 1.0]], &[-1e150, 0.0]).unwrap();
    let solvers: [(&str, Box<dyn Solver>); 4] = [
        ("auto", Box::new(Auto::default())),
        ("lemke", Box::new(Lemke::default())),
        ("enumeration", Box::new(Enumeration::default())),
        ("pgs", Box::new(Pgs::default())),
    ];
    for (who, mut solver) in solvers {
        let sol = solver.solve(&lcp).unwrap();
        assert_finite_and_unsolved(&sol, who);
    }
    // Enumeration cannot list every solution, and says so.
    assert!(matches!(Enumeration::default().solve_all(lcp.view()), Err(LcpError::Overflow)));
}
