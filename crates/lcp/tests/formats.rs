//! The plain and Siconos text formats: round trips, detection, layout and errors.

mod common;

use common::{Rng, planted, random_p_matrix};
use moreau_lcp::{Lcp, LcpError};

/// A non-symmetric problem, so that a transposed reading would be caught.
fn sample() -> Lcp {
    Lcp::from_rows(
        &[vec![2.0, 1.0, 0.5], vec![0.0, 3.0, -1.0], vec![1.0, 0.25, 4.0]],
        &[-1.0, 2.0, -3.0],
    )
    .unwrap()
}

/// The sample as Siconos numerics' `linearComplementarity_printInFile` writes it: dense
/// storage, M column by column with `%32.24e `, then q.
const SICONOS_SAMPLE: &str = "3
0
3
3
3\t3
  2.000000000000000000000000e+00   0.000000000000000000000000e+00   1.000000000000000000000000e+00 
  1.000000000000000000000000e+00   3.000000000000000000000000e+00   2.500000000000000000000000e-01 
  5.000000000000000000000000e-01  -1.000000000000000000000000e+00   4.000000000000000000000000e+00 
 -1.000000000000000000000000e+00   2.000000000000000000000000e+00  -3.000000000000000000000000e+00 ";

#[test]
fn siconos_file_is_read_column_major() {
    let lcp = Lcp::read_siconos(SICONOS_SAMPLE.as_bytes()).unwrap();
    assert_eq!(lcp, sample());
    assert_eq!(Lcp::read_any(SICONOS_SAMPLE).unwrap(), sample());
    // Anything after q is a comment.
    let with_comment = format!("{SICONOS_SAMPLE}\n\nRemark: a free-text comment, 1 2 3.\n");
    assert_eq!(Lcp::read_any(&with_comment).unwrap(), sample());
}

#[test]
fn siconos_writer_layout() {
    let mut out = Vec::new();
    sample().write_siconos(&mut out).unwrap();
    let text = String::from_utf8(out).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(&lines[..5], &["3", "0", "3", "3", "3\t3"]);
    // One column of M per line.
    assert_eq!(lines[5], "2e0 0e0 1e0");
    assert_eq!(lines[6], "1e0 3e0 2.5e-1");
    assert_eq!(lines[8], "-1e0 2e0 -3e0");
    assert_eq!(lines.len(), 9);
}

#[test]
fn plain_writer_layout_and_reader() {
    let mut out = Vec::new();
    sample().write_plain(&mut out).unwrap();
    let text = String::from_utf8(out).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines, ["3", "2e0 1e0 5e-1", "0e0 3e0 -1e0", "1e0 2.5e-1 4e0", "-1e0 2e0 -3e0"]);
    let hand = "# a 2 x 2 problem\n2\n1 2   # first row\n3 4\n-1 -1\n";
    let lcp = Lcp::read_plain(hand.as_bytes()).unwrap();
    assert_eq!(lcp, Lcp::from_rows(&[vec![1.0, 2.0], vec![3.0, 4.0]], &[-1.0, -1.0]).unwrap());
    assert_eq!(Lcp::read_any(hand).unwrap(), lcp);
}

#[test]
fn round_trips_are_exact_in_both_formats() {
    let mut rng = Rng::new(21);
    for trial in 0..30 {
        let n = 1 + trial % 9;
        let (mut lcp, _) = planted(random_p_matrix(n, &mut rng), &mut rng, true);
        if trial % 3 == 0 {
            // Awkward magnitudes and signs.
            let m = faer::Mat::from_fn(n, n, |i, j| {
                lcp.m()[(i, j)] * 10f64.powi((i * 7 + j * 3) as i32 % 31 - 15)
            });
            lcp = Lcp::new(m, lcp.q().to_owned()).unwrap();
        }
        let mut plain = Vec::new();
        lcp.write_plain(&mut plain).unwrap();
        assert_eq!(Lcp::read_plain(plain.as_slice()).unwrap(), lcp);
        assert_eq!(Lcp::read_any(std::str::from_utf8(&plain).unwrap()).unwrap(), lcp);
        let mut siconos = Vec::new();
        lcp.write_siconos(&mut siconos).unwrap();
        assert_eq!(Lcp::read_siconos(siconos.as_slice()).unwrap(), lcp);
        assert_eq!(Lcp::read_any(std::str::from_utf8(&siconos).unwrap()).unwrap(), lcp);
    }
}

#[test]
fn detection_of_ambiguous_plain_files() {
    // A plain 2 x 2 file whose first row happens to be "0 2": exactly 1 + n + n^2 numbers,
    // so it is plain even though "2 0 2 ..." starts like a Siconos header.
    let text = "2\n0 2\n2 2\n2 2\n";
    let lcp = Lcp::read_any(text).unwrap();
    assert_eq!(lcp, Lcp::from_rows(&[vec![0.0, 2.0], vec![2.0, 2.0]], &[2.0, 2.0]).unwrap());
}

#[test]
fn unknown_storage_is_a_clear_error() {
    let text = "2\n3\n2\n2\n1 1 2 2 0 0\n";
    assert!(matches!(
        Lcp::read_siconos(text.as_bytes()),
        Err(LcpError::UnsupportedStorage { storage: 3 })
    ));
    let err = Lcp::read_any(text).unwrap_err();
    assert!(
        matches!(&err, LcpError::UnknownFormat { siconos, .. }
            if matches!(**siconos, LcpError::UnsupportedStorage { storage: 3 })),
        "{err}"
    );
}

#[test]
fn parse_errors_name_the_line() {
    let err = Lcp::read_plain("2\n1 2\n3 x\n1 1\n".as_bytes()).unwrap_err();
    assert!(
        matches!(&err, LcpError::Parse { line: 3, message } if message.contains("'x'")),
        "{err}"
    );
    let err = Lcp::read_plain("2\n1 2\n3 4\n1\n".as_bytes()).unwrap_err();
    assert!(
        matches!(&err, LcpError::Parse { message, .. } if message.contains("end of input")),
        "{err}"
    );
    let err = Lcp::read_plain("1\n1\n1\n5\n".as_bytes()).unwrap_err();
    assert!(
        matches!(&err, LcpError::TrailingData { line: 4, found, after: "q" } if found == "5"),
        "{err}"
    );
    let err = Lcp::read_plain("0\n".as_bytes()).unwrap_err();
    assert!(matches!(err, LcpError::Parse { line: 1, .. }));
    let err = Lcp::read_plain("-3\n".as_bytes()).unwrap_err();
    assert!(matches!(err, LcpError::Parse { line: 1, .. }));
    let err = Lcp::read_plain("".as_bytes()).unwrap_err();
    assert!(matches!(err, LcpError::Parse { .. }));
    // A size far beyond the input is refused before allocating.
    let err = Lcp::read_plain("100000000000\n1 2 3\n".as_bytes()).unwrap_err();
    assert!(matches!(err, LcpError::Parse { line: 1, .. }));
    // A contact problem's W of the wrong size is refused on the line of its sizes.
    let err = moreau_lcp::fc2d::Fc2d::read_siconos("2\n1\n0\n3\n3\n".as_bytes()).unwrap_err();
    assert!(
        matches!(&err, LcpError::Parse { line: 5, message } if message.contains("3 x 3")),
        "{err}"
    );
    // Siconos header inconsistencies.
    let err = Lcp::read_siconos("2\n0\n2\n2\n2 3\n".as_bytes()).unwrap_err();
    assert!(matches!(err, LcpError::Parse { .. }), "{err}");
    let err = Lcp::read_siconos("2\n0\n3\n3\n3 3\n".as_bytes()).unwrap_err();
    assert!(matches!(err, LcpError::DimensionMismatch { expected: 2, found: 3, .. }), "{err}");
    let err = Lcp::read_siconos("1\n0\n1\n1\n1\t1\n2\n".as_bytes()).unwrap_err();
    assert!(matches!(&err, LcpError::Parse { message, .. } if message.contains("q")), "{err}");
    // A size whose n² + n values overflow is named as given, on its line.
    let err = Lcp::read_plain("# size\n99999999999\n1\n".as_bytes()).unwrap_err();
    let expected = "the size n = 99999999999 announces n² + n values, more than the input can hold";
    assert!(matches!(&err, LcpError::Parse { line: 2, message } if message == expected), "{err}");
    let err = Lcp::read_plain("3\n1 2\n".as_bytes()).unwrap_err();
    let expected = "12 values announced, more than the input can hold";
    assert!(matches!(&err, LcpError::Parse { line: 1, message } if message == expected), "{err}");
    // Non-finite numbers parse but are rejected by validation.
    let err = Lcp::read_plain("1\nnan\n1\n".as_bytes()).unwrap_err();
    assert!(matches!(err, LcpError::NonFinite { what: "M", index: (0, 0) }));
    let err = Lcp::read_plain("1\n1\ninf\n".as_bytes()).unwrap_err();
    assert!(matches!(err, LcpError::NonFinite { what: "q", .. }));
}

#[test]
fn io_errors_are_wrapped() {
    struct Broken;
    impl std::io::Read for Broken {
        fn read(&mut self, _: &mut [u8]) -> std::io::Result<usize> {
            Err(std::io::Error::other("disk on fire"))
        }
    }
    assert!(matches!(Lcp::read_plain(Broken), Err(LcpError::Io(_))));
    assert!(matches!(Lcp::read_siconos(Broken), Err(LcpError::Io(_))));
}

#[test]
fn data_after_a_siconos_problem_is_refused_naming_its_line() {
    use moreau_lcp::fc2d::{Fc2d, Gfc2d};
    let trailing = |err: LcpError, at: usize, token: &str, part: &str| {
        assert!(
            matches!(&err, LcpError::TrailingData { line, found, after }
                if *line == at && found == token && *after == part),
            "{err}"
        );
        assert!(err.to_string().contains(&format!("'{token}' on line {at} after {part}")), "{err}");
    };
    // An LCP of one row: n, M dense 1 x 1, q; then a comment, or a number.
    let lcp = "1\n0\n1\n1\n1 1\n2\n-1\n";
    assert!(Lcp::read_siconos(lcp.as_bytes()).is_ok());
    assert!(Lcp::read_siconos(format!("{lcp}\nExample 4.4.7 CPS 2009\n").as_bytes()).is_ok());
    assert!(Lcp::read_siconos(format!("{lcp}# from Murty (1988)\n").as_bytes()).is_ok());
    trailing(Lcp::read_siconos(format!("{lcp}\n7 8 9\n").as_bytes()).unwrap_err(), 9, "7", "q");
    trailing(Lcp::read_siconos(format!("{lcp}-1e-3\n").as_bytes()).unwrap_err(), 8, "-1e-3", "q");
    // A contact problem of one contact: W dense 2 x 2, q, μ; then the flag, or more.
    let fc2d = "2\n1\n0\n2\n2\n2 2\n1 0 0 1\n-1 0\n0.5\n";
    assert!(Fc2d::read_siconos(fc2d.as_bytes()).is_ok());
    assert!(Fc2d::read_siconos(format!("{fc2d}1\n").as_bytes()).is_ok());
    assert!(Fc2d::read_siconos(format!("{fc2d}0\n\n").as_bytes()).is_ok());
    trailing(
        Fc2d::read_siconos(format!("{fc2d}0.3 0.3\n").as_bytes()).unwrap_err(),
        10,
        "0.3",
        "μ",
    );
    trailing(Fc2d::read_siconos(format!("{fc2d}1\n2\n").as_bytes()).unwrap_err(), 11, "2", "μ");
    trailing(Fc2d::read_siconos(format!("{fc2d}x\n").as_bytes()).unwrap_err(), 10, "x", "μ");
    // A global one: M dense 2 x 2, H dense 2 x 2, q, b, μ; then nothing.
    let gfc2d = "2\n1\n0\n2\n2\n2 2\n1 0 0 1\n0\n2\n2\n2 2\n1 0 0 1\n0 -1\n0 0\n0.5\n";
    assert!(Gfc2d::read_siconos(gfc2d.as_bytes()).is_ok());
    trailing(Gfc2d::read_siconos(format!("{gfc2d}1\n").as_bytes()).unwrap_err(), 16, "1", "μ");
}

#[test]
fn a_contact_count_that_disagrees_with_the_matrix_is_refused_with_the_counts() {
    use moreau_lcp::fc2d::{Fc2d, Gfc2d};
    // Two contacts announced on line 2, then the W of one contact (2 x 2) on line 5.
    let fc2d = "2\n2\n0\n2\n2\n2 2\n1 0 0 1\n-1 0\n0.5\n";
    let err = Fc2d::read_siconos(fc2d.as_bytes()).unwrap_err();
    let expected = "W is 2 x 2, expected 4 x 4: 2 per contact, for n_c = 2 announced on line 2";
    assert!(matches!(&err, LcpError::Parse { line: 5, message } if message == expected), "{err}");
    // One contact announced, then the sizes of a 4 x 4 W.
    let err = Fc2d::read_siconos("2\n1\n0\n4\n4\n".as_bytes()).unwrap_err();
    let expected = "W is 4 x 4, expected 2 x 2: 2 per contact, for n_c = 1 announced on line 2";
    assert!(matches!(&err, LcpError::Parse { line: 5, message } if message == expected), "{err}");
    // A global problem: M of 2 rows, and H of 2 columns where 3 contacts need 6.
    let gfc2d = "2\n3\n0\n2\n2\n2 2\n1 0 0 1\n0\n2\n2\n2 2\n1 0 0 1\n0 -1\n0 0\n0.5\n";
    let err = Gfc2d::read_siconos(gfc2d.as_bytes()).unwrap_err();
    let expected = "H is 2 x 2, expected 2 x 6: one row per row of M, columns 2 per contact, for \
                    n_c = 3 announced on line 2";
    assert!(matches!(&err, LcpError::Parse { line: 10, message } if message == expected), "{err}");
}
