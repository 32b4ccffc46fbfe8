//! The ranges of Lemke's and enumeration's options at their bounds: each value just inside
//! a bound is taken, each value on or beyond it is refused with the field's name.

use moreau_lcp::{Covering, Enumeration, EnumerationOptions, LcpError, Lemke, LemkeOptions};

/// The name of the refused field, or `None` when the options are taken.
fn lemke_refuses(options: LemkeOptions) -> Option<&'static str> {
    match Lemke::new(options) {
        Ok(_) => None,
        Err(LcpError::InvalidOption { name, .. }) => Some(name),
        Err(e) => panic!("not an option error: {e:?}"),
    }
}

/// As [`lemke_refuses`], for enumeration.
fn enumeration_refuses(options: EnumerationOptions) -> Option<&'static str> {
    match Enumeration::new(options) {
        Ok(_) => None,
        Err(LcpError::InvalidOption { name, .. }) => Some(name),
        Err(e) => panic!("not an option error: {e:?}"),
    }
}

#[test]
fn lemke_pivot_tolerance_lies_in_the_open_unit_interval() {
    // (0, 1): both ends and anything non-finite are refused, values inside are taken.
    let with = |v: f64| lemke_refuses(LemkeOptions::default().with_pivot_tolerance(v));
    for v in [0.0, 1.0, -1e-12, 2.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert_eq!(with(v), Some("pivot_tolerance"), "pivot_tolerance = {v}");
    }
    for v in [f64::MIN_POSITIVE, 1e-12, 0.5, 1.0 - f64::EPSILON] {
        assert_eq!(with(v), None, "pivot_tolerance = {v}");
    }
}

#[test]
fn lemke_tie_tolerance_lies_in_the_half_open_unit_interval() {
    // [0, 1): zero (exact comparisons) is taken, 1, negative and non-finite values are not.
    let with = |v: f64| lemke_refuses(LemkeOptions::default().with_tie_tolerance(v));
    for v in [1.0, -1e-300, -1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(with(v), Some("tie_tolerance"), "tie_tolerance = {v}");
    }
    for v in [0.0, 1e-12, 0.5, 1.0 - f64::EPSILON] {
        assert_eq!(with(v), None, "tie_tolerance = {v}");
    }
}

#[test]
fn lemke_max_pivots_and_custom_covering_are_checked() {
    // At least one pivot; a custom covering vector is nonempty with finite entries > 0.
    assert_eq!(lemke_refuses(LemkeOptions::default().with_max_pivots(0)), Some("max_pivots"));
    assert_eq!(lemke_refuses(LemkeOptions::default().with_max_pivots(1)), None);
    let covering =
        |d: Vec<f64>| lemke_refuses(LemkeOptions::default().with_covering(Covering::Custom(d)));
    assert_eq!(covering(vec![]), Some("covering"));
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(covering(vec![1.0, bad]), Some("covering"), "entry {bad}");
    }
    assert_eq!(covering(vec![f64::MIN_POSITIVE, 1e300]), None);
}

#[test]
fn enumeration_max_n_lies_between_one_and_twenty_six() {
    // 1..=26, and max_n_degenerate at most min(max_n, 14): equal to either bound is taken.
    let with = |n: usize, d: usize| {
        enumeration_refuses(EnumerationOptions::default().with_max_n(n).with_max_n_degenerate(d))
    };
    assert_eq!(with(0, 0), Some("max_n"));
    assert_eq!(with(27, 12), Some("max_n"));
    assert_eq!(with(1, 0), None);
    assert_eq!(with(1, 1), None);
    assert_eq!(with(26, 12), None);
    assert_eq!(with(26, 14), None);
    assert_eq!(with(26, 15), Some("max_n_degenerate"));
    assert_eq!(with(10, 10), None);
    assert_eq!(with(10, 11), Some("max_n_degenerate"));
    assert_eq!(with(14, 14), None);
}

#[test]
fn a_solver_reports_the_options_it_was_built_with() {
    // Options other than the defaults come back unchanged from `options()`.
    let lemke = LemkeOptions::default().with_max_pivots(9).with_covering(Covering::RowScaled);
    assert_eq!(Lemke::new(lemke.clone()).unwrap().options(), &lemke);
    let enumeration = EnumerationOptions::default().with_max_n(7).with_max_n_degenerate(5);
    assert_eq!(Enumeration::new(enumeration.clone()).unwrap().options(), &enumeration);
}
