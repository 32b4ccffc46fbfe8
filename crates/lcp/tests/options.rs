//! The solvers' options are `#[non_exhaustive]`: callers build them from their default with
//! the `with_*` setters (a struct literal does not compile outside the crate, which the
//! `compile_fail` examples of their documentation check), and serde reads them as before.

use moreau_lcp::fc2d::{
    Fc2dAutoOptions, LcpRouteOptions, LcpRouteSolver, NewtonOptions, NsgsOptions, ProximalOptions,
    Rho,
};
use moreau_lcp::{AutoOptions, Covering, EnumerationOptions, LemkeOptions, PgsOptions};

#[test]
fn each_setter_sets_its_field_and_nothing_else() {
    let lemke = LemkeOptions::default()
        .with_max_pivots(7)
        .with_tolerance(1e-11)
        .with_pivot_tolerance(1e-10)
        .with_tie_tolerance(1e-9)
        .with_covering(Covering::RowScaled);
    let mut expected = LemkeOptions::default();
    expected.max_pivots = 7;
    expected.tolerance = 1e-11;
    expected.pivot_tolerance = 1e-10;
    expected.tie_tolerance = 1e-9;
    expected.covering = Covering::RowScaled;
    assert_eq!(lemke, expected);

    let enumeration =
        EnumerationOptions::default().with_max_n(10).with_tolerance(1e-8).with_max_n_degenerate(9);
    assert_eq!(
        (enumeration.max_n, enumeration.tolerance, enumeration.max_n_degenerate),
        (10, 1e-8, 9)
    );

    let auto = AutoOptions::default()
        .with_lemke(lemke.clone())
        .with_alternative_coverings(1)
        .with_enumeration_max_n(8)
        .with_enumeration(enumeration.clone());
    assert_eq!((auto.lemke, auto.enumeration), (lemke, enumeration));
    assert_eq!((auto.alternative_coverings, auto.enumeration_max_n), (1, 8));

    let pgs = PgsOptions::default().with_omega(1.5).with_tolerance(1e-6).with_max_iterations(3);
    assert_eq!((pgs.omega, pgs.tolerance, pgs.max_iterations), (1.5, 1e-6, 3));

    let nsgs = NsgsOptions::default()
        .with_tolerance(1e-6)
        .with_max_sweeps(4)
        .with_omega(1.3)
        .with_keep_history(true);
    assert_eq!(
        (nsgs.tolerance, nsgs.max_sweeps, nsgs.omega, nsgs.keep_history),
        (1e-6, 4, 1.3, true)
    );

    let route = LcpRouteOptions::default()
        .with_tolerance(1e-7)
        .with_max_contacts(5)
        .with_solver(LcpRouteSolver::Lemke)
        .with_polish_iterations(0);
    assert_eq!(
        (route.tolerance, route.max_contacts, route.solver, route.polish_iterations),
        (1e-7, 5, LcpRouteSolver::Lemke, 0)
    );

    let newton = NewtonOptions::default()
        .with_tolerance(1e-7)
        .with_max_iterations(5)
        .with_rho(Rho::Fixed(2.0))
        .with_armijo(1e-3)
        .with_nonmonotone(3)
        .with_backtrack(0.25)
        .with_max_backtracks(6)
        .with_fallback_sweeps(7)
        .with_smoothing_sweeps(8)
        .with_regularization(1e-9)
        .with_regularization_gain(0.5)
        .with_keep_history(true);
    assert_eq!((newton.tolerance, newton.max_iterations, newton.rho), (1e-7, 5, Rho::Fixed(2.0)));
    assert_eq!((newton.armijo, newton.nonmonotone, newton.backtrack), (1e-3, 3, 0.25));
    assert_eq!((newton.max_backtracks, newton.fallback_sweeps, newton.smoothing_sweeps), (6, 7, 8));
    assert_eq!((newton.regularization, newton.regularization_gain), (1e-9, 0.5));
    assert!(newton.keep_history);

    let proximal = ProximalOptions::default()
        .with_tolerance(1e-7)
        .with_max_outer(5)
        .with_inner_iterations(6)
        .with_smoothing_sweeps(7)
        .with_nonmonotone(8)
        .with_initial_weight(0.5)
        .with_shrink(0.4)
        .with_grow(3.0);
    assert_eq!((proximal.tolerance, proximal.max_outer, proximal.inner_iterations), (1e-7, 5, 6));
    assert_eq!((proximal.smoothing_sweeps, proximal.nonmonotone), (7, 8));
    assert_eq!((proximal.initial_weight, proximal.shrink, proximal.grow), (0.5, 0.4, 3.0));

    let auto = Fc2dAutoOptions::default()
        .with_tolerance(1e-7)
        .with_lcp_max_contacts(5)
        .with_max_sweeps(6)
        .with_window(7)
        .with_stall_factor(3.0)
        .with_cluster_depth(1)
        .with_max_cluster_contacts(9)
        .with_cluster_lcp_contacts(4)
        .with_max_rounds(2)
        .with_omega(1.1);
    assert_eq!((auto.tolerance, auto.lcp_max_contacts, auto.max_sweeps), (1e-7, 5, 6));
    assert_eq!((auto.window, auto.stall_factor, auto.cluster_depth), (7, 3.0, 1));
    assert_eq!((auto.max_cluster_contacts, auto.cluster_lcp_contacts), (9, 4));
    assert_eq!((auto.max_rounds, auto.omega), (2, 1.1));
}

#[test]
fn options_read_from_json_as_before() {
    // Missing fields take their defaults, unknown ones are refused.
    let nsgs: NsgsOptions = serde_json::from_str(r#"{"omega": 1.2}"#).unwrap();
    assert_eq!(nsgs, NsgsOptions::default().with_omega(1.2));
    assert!(serde_json::from_str::<NsgsOptions>(r#"{"omgea": 1.2}"#).is_err());
    let auto: AutoOptions =
        serde_json::from_str(r#"{"lemke": {"tolerance": 1e-10}, "enumeration_max_n": 6}"#).unwrap();
    let expected = AutoOptions::default()
        .with_lemke(LemkeOptions::default().with_tolerance(1e-10))
        .with_enumeration_max_n(6);
    assert_eq!(auto, expected);
    assert!(serde_json::from_str::<AutoOptions>(r#"{"lemke": {"tol": 1e-10}}"#).is_err());
    // And what they write reads back the same.
    let newton = NewtonOptions::default().with_rho(Rho::Fixed(3.0)).with_keep_history(true);
    let text = serde_json::to_string(&newton).unwrap();
    assert_eq!(serde_json::from_str::<NewtonOptions>(&text).unwrap(), newton);
    let route = LcpRouteOptions::default().with_solver(LcpRouteSolver::Enumeration);
    let text = serde_json::to_string(&route).unwrap();
    assert_eq!(serde_json::from_str::<LcpRouteOptions>(&text).unwrap(), route);
}
