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

/// `LcpError::OutOfRange`'s (what, index, value), or a panic naming what came instead.
fn out_of_range<T: std::fmt::Debug>(
    result: Result<T, LcpError>,
) -> (&'static str, (usize, usize), f64) {
    match result {
        Err(LcpError::OutOfRange { what, index, value }) => (what, index, value),
        other => panic!("expected OutOfRange, got {other:?}"),
    }
}

#[test]
fn frictional_contact_entries_beyond_the_range_are_refused_naming_the_entry() {
    use faer::Mat;
    use moreau_lcp::fc2d::{Fc2d, Fc2dBuilder, Fc2dParts, Fc2dRef, Gfc2d};

    let above = f64::from_bits(MAX_ENTRY.to_bits() + 1);
    // Two contacts, W = I but for one entry, q = (-1, 0, -1, 0), μ = 0.5.
    let w = |i, j, v| {
        Mat::from_fn(
            4,
            4,
            move |a, b| if (a, b) == (i, j) { v } else { f64::from(u8::from(a == b)) },
        )
    };
    let (q, mu) = ([-1.0, 0.0, -1.0, 0.0], [0.5, 0.5]);
    // The bound itself is accepted, in W, q and μ alike.
    assert!(Fc2d::from_dense(w(2, 2, MAX_ENTRY).as_ref(), &q, &mu).is_ok());
    assert!(Fc2d::from_dense(w(0, 0, 1.0).as_ref(), &[-MAX_ENTRY, 0.0, -1.0, 0.0], &mu).is_ok());
    assert!(Fc2d::from_dense(w(0, 0, 1.0).as_ref(), &q, &[0.5, MAX_ENTRY]).is_ok());
    // Beyond it: an entry of W off the diagonal blocks (row 3, column 0), one on a diagonal
    // block, of q, of μ, each named with its value.
    assert_eq!(
        out_of_range(Fc2d::from_dense(w(3, 0, -1e200).as_ref(), &q, &mu)),
        ("W", (3, 0), -1e200)
    );
    assert_eq!(
        out_of_range(Fc2d::from_dense(w(2, 2, above).as_ref(), &q, &mu)),
        ("W", (2, 2), above)
    );
    let q_big = [-1.0, 0.0, -1.0, 1e151];
    assert_eq!(
        out_of_range(Fc2d::from_dense(w(0, 0, 1.0).as_ref(), &q_big, &mu)),
        ("q", (3, 0), 1e151)
    );
    let absurd = [0.5, 1e200];
    assert_eq!(
        out_of_range(Fc2d::from_dense(w(0, 0, 1.0).as_ref(), &q, &absurd)),
        ("μ", (1, 0), 1e200)
    );
    let message = Fc2d::from_dense(w(0, 0, 1.0).as_ref(), &q, &absurd).unwrap_err().to_string();
    assert!(message.contains("μ[1][0] = 1e200") && message.contains("scale"), "{message}");
    // Negative and non-finite friction coefficients keep their own errors.
    assert!(matches!(
        Fc2d::from_dense(w(0, 0, 1.0).as_ref(), &q, &[0.5, -0.1]),
        Err(LcpError::NegativeFriction { contact: 1, .. })
    ));
    assert!(matches!(
        Fc2d::from_dense(w(0, 0, 1.0).as_ref(), &q, &[f64::INFINITY, 0.5]),
        Err(LcpError::NonFinite { what: "μ", index: (0, 0) })
    ));
    // The borrowed parts and the builder, with a bilateral row (row 4), refuse alike.
    let mut builder = Fc2dBuilder::new(2);
    let joint = builder.bilateral_group(1);
    builder.add_block(0, 0, [1.0, 0.0, 0.0, 1.0]);
    builder.add_block(1, 1, [1.0, 0.0, 0.0, 1.0]);
    builder.add_block(joint, joint, [1.0, 0.0, 0.0, 0.0]);
    builder.add_entry(4, 1, 1e160);
    let q5 = [-1.0, 0.0, -1.0, 0.0, 0.5];
    assert_eq!(out_of_range(builder.build(&q5, &mu)), ("W", (4, 1), 1e160));
    let blocks = [[1.0, 0.0, 0.0, 1.0], [1.0, 0.0, 0.0, 1e300]];
    let parts = Fc2dParts {
        n_contacts: 2,
        group_start: &[0, 2, 4],
        row_ptr: &[0, 1, 2],
        col: &[0, 1],
        blocks: &blocks,
        q: &q,
        mu: &mu,
    };
    assert_eq!(out_of_range(Fc2dRef::from_parts(parts)), ("W", (3, 3), 1e300));
    // Siconos' files: FC2D (W dense, q, μ) and GFC2D (M, H, q, b, μ).
    let fc2d =
        |w11: &str, q1: &str, mu: &str| format!("2\n1\n0\n2\n2\n2 2\n1 0 0 {w11}\n-1 {q1}\n{mu}\n");
    assert!(Fc2d::read_siconos(fc2d("1", "0", "0.5").as_bytes()).is_ok());
    assert_eq!(
        out_of_range(Fc2d::read_siconos(fc2d("1e200", "0", "0.5").as_bytes())),
        ("W", (1, 1), 1e200)
    );
    assert_eq!(
        out_of_range(Fc2d::read_siconos(fc2d("1", "-4e151", "0.5").as_bytes())),
        ("q", (1, 0), -4e151)
    );
    assert_eq!(
        out_of_range(Fc2d::read_siconos(fc2d("1", "0", "1e300").as_bytes())),
        ("μ", (0, 0), 1e300)
    );
    let gfc2d = |h: &str, mu: &str| {
        format!("2\n1\n0\n2\n2\n2 2\n1 0 0 1\n0\n2\n2\n2 2\n1 0 {h} 1\n0 -1\n0 0\n{mu}\n")
    };
    assert!(Gfc2d::read_siconos(gfc2d("0", "0.5").as_bytes()).is_ok());
    assert_eq!(
        out_of_range(Gfc2d::read_siconos(gfc2d("1e155", "0.5").as_bytes())),
        ("H", (0, 1), 1e155)
    );
    assert_eq!(
        out_of_range(Gfc2d::read_siconos(gfc2d("0", "1e155").as_bytes())),
        ("μ", (0, 0), 1e155)
    );
}
