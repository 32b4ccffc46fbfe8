//! Property tests of the set-valued maps: the identities of docs/theory.md section 1, the
//! complementarity and relay-split equivalences, inverse graphs, the proximal maps and the
//! projection onto the friction cone.

use moreau_setvalued::{
    ContactLaw, CoulombSplit, CoulombState, FrictionCone, GraphWindow, RelativeVelocity,
    SetValuedMap, Sgn, Upr, ValueSet, check_impact, complementarity, coulomb_holds, sample_graph,
};
use proptest::prelude::*;

/// Values on a dyadic grid, so that sums and products below are exact, with zero and the
/// relay bounds hit often.
fn grid() -> impl Strategy<Value = f64> {
    prop_oneof![Just(0.0), Just(1.0), Just(-1.0), (-64i32..=64).prop_map(|k| f64::from(k) / 8.0)]
}

/// Any real of moderate size, zero included.
fn real() -> impl Strategy<Value = f64> {
    prop_oneof![Just(0.0), -1e3..1e3f64]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    #[test]
    fn upr_is_invariant_under_positive_scaling(x in real(), a in 1e-3..1e3f64) {
        prop_assert_eq!(Upr.value(a * x), Upr.value(x));
        prop_assert_eq!(Upr.value(x).scale(a), Upr.value(x));
    }

    #[test]
    fn upr_plus_upr_is_upr(x in real()) {
        prop_assert_eq!(Upr.value(x).sum(&Upr.value(x)), Upr.value(x));
    }

    #[test]
    fn sgn_is_invariant_under_scaling_of_its_argument(x in real(), a in 1e-3..1e3f64, b in 0.0..10.0f64) {
        let relay = Sgn::scaled(b).unwrap();
        prop_assert_eq!(relay.value(a * x), relay.value(x));
        prop_assert_eq!(Sgn::unit().value(x).scale(b), relay.value(x));
    }

    /// −y ∈ Upr(x) ⇔ 0 ≤ x ⊥ y ≥ 0, exactly and with any tolerance.
    #[test]
    fn complementarity_equals_upr_membership(x in real(), y in real(), tol in prop_oneof![Just(0.0), 0.0..10.0f64]) {
        prop_assert_eq!(complementarity(x, y, tol), Upr.contains(x, -y, tol));
        prop_assert_eq!(complementarity(x, y, 0.0), x >= 0.0 && y >= 0.0 && x * y == 0.0);
        prop_assert_eq!(Upr.contains(x, -y, 0.0), Upr.value(x).contains(-y, 0.0));
    }

    /// y ∈ F(x) ⇔ x ∈ F⁻¹(y) ⇔ (x, y) on the graph, for Upr and the relay.
    #[test]
    fn inverse_graphs_agree_with_values(x in grid(), y in grid(), b in grid()) {
        let on_graph = Upr.value(x).contains(y, 0.0);
        prop_assert_eq!(on_graph, Upr.inverse(y).contains(x, 0.0));
        prop_assert_eq!(on_graph, Upr.graph_distance(x, y) == 0.0);
        let relay = Sgn::scaled(b.abs()).unwrap();
        let on_graph = relay.value(x).contains(y, 0.0);
        prop_assert_eq!(on_graph, relay.inverse(y).contains(x, 0.0));
        prop_assert_eq!(on_graph, relay.graph_distance(x, y) == 0.0);
    }

    /// −λ_T ∈ μλ_N Sgn(γ_T) ⇔ 0 ≤ γ_R ⊥ λ_R ≥ 0 and 0 ≤ γ_L ⊥ λ_L ≥ 0, and the split goes back.
    #[test]
    fn relay_holds_iff_both_complementarities_hold(
        mu in prop_oneof![Just(0.0), Just(0.25), Just(0.5), Just(2.0)],
        lambda_n in grid(), lambda_t in grid(), gamma_t in grid(),
    ) {
        let state = CoulombState { lambda_n, lambda_t, gamma_t };
        let split = CoulombSplit::from_coulomb(mu, state).unwrap();
        prop_assert_eq!(coulomb_holds(mu, lambda_n, lambda_t, gamma_t, 0.0), split.holds(0.0));
        prop_assert_eq!(split.lambda_t(), lambda_t);
        prop_assert_eq!(split.gamma_t(), gamma_t);
        prop_assert_eq!(split.friction_bound(), mu * lambda_n);
        if mu > 0.0 {
            prop_assert_eq!(split.to_coulomb(mu).unwrap(), state);
        }
    }

    /// States on the relay's graph, built from their kind (stick or slide), satisfy both.
    #[test]
    fn planted_coulomb_states_satisfy_the_split(mu in 0.0..2.0f64, lambda_n in 0.0..100.0f64, r in -1.0..1.0f64, speed in 0.0..5.0f64, kind in 0..3u8) {
        let bound = mu * lambda_n;
        let (lambda_t, gamma_t) = match kind {
            0 => (r * bound, 0.0),
            1 => (-bound, speed),
            _ => (bound, -speed),
        };
        prop_assert!(coulomb_holds(mu, lambda_n, lambda_t, gamma_t, 1e-12));
        let split = CoulombSplit::from_coulomb(mu, CoulombState { lambda_n, lambda_t, gamma_t }).unwrap();
        prop_assert!(split.holds(1e-12));
    }

    #[test]
    fn projections_are_idempotent_and_non_expansive(a in real(), c in real(), b in 0.0..100.0f64) {
        let relay = Sgn::scaled(b).unwrap();
        prop_assert_eq!(Upr::prox(Upr::prox(a)), Upr::prox(a));
        prop_assert_eq!(relay.prox(relay.prox(a)), relay.prox(a));
        prop_assert!((Upr::prox(a) - Upr::prox(c)).abs() <= (a - c).abs());
        prop_assert!((relay.prox(a) - relay.prox(c)).abs() <= (a - c).abs());
        prop_assert!(Upr::prox(a) >= 0.0 && relay.prox(a).abs() <= b);
        prop_assert_eq!(ValueSet::interval(-b, b).project(a), Some(relay.prox(a)));
    }

    /// The laws as fixed points of their proximal maps, for any r > 0.
    #[test]
    fn laws_are_fixed_points_of_the_proximal_maps(x in grid(), y in grid(), b in grid(), r in prop_oneof![Just(0.5), Just(1.0), Just(4.0)]) {
        prop_assert_eq!(Upr.contains(x, -y, 0.0), x == Upr::prox(x - r * y));
        let relay = Sgn::scaled(b.abs()).unwrap();
        // −λ ∈ b Sgn(γ) ⇔ λ = prox(λ − r γ), with γ = x and λ = y.
        prop_assert_eq!(relay.contains(x, -y, 0.0), y == relay.prox(y - r * x));
    }

    /// Every point of a sampled graph lies on the graph.
    #[test]
    fn sampled_graphs_lie_on_the_graph(x_min in -5.0..0.5f64, width in 0.1..10.0f64, b in 0.0..3.0f64, points in 2usize..40) {
        let window = GraphWindow { x_min, x_max: x_min + width, y_min: -4.0, y_max: 4.0 };
        for (x, y) in sample_graph(&Upr, &window, points).unwrap() {
            prop_assert!(Upr.contains(x, y, 0.0), "({}, {})", x, y);
        }
        let relay = Sgn::scaled(b).unwrap();
        let polyline = sample_graph(&relay, &window, points).unwrap();
        prop_assert!(polyline.len() >= points);
        for pair in polyline.windows(2) {
            // The relay's polyline never steps down.
            prop_assert!(pair[1].1 >= pair[0].1 && pair[1].0 >= pair[0].0);
        }
        for (x, y) in polyline {
            prop_assert!(relay.contains(x, y, 0.0));
        }
    }

    /// Moreau's decomposition x = proj_K(x) + proj_K°(x) into orthogonal parts, with the polar
    /// cone K°_μ = {y_N + μ|y_T| ≤ 0} = −K_{1/μ} projected on independently.
    #[test]
    fn cone_projection_is_moreaus_decomposition(mu in 0.01..20.0f64, x_n in real(), x_t in real()) {
        let (p_n, p_t) = FrictionCone::new(mu).unwrap().project(x_n, x_t);
        let (m_n, m_t) = FrictionCone::new(1.0 / mu).unwrap().project(-x_n, -x_t);
        let (q_n, q_t) = (-m_n, -m_t);
        let scale = 1.0 + x_n.abs() + x_t.abs();
        prop_assert!((p_n + q_n - x_n).abs() <= 1e-12 * scale, "{} + {} != {}", p_n, q_n, x_n);
        prop_assert!((p_t + q_t - x_t).abs() <= 1e-12 * scale, "{} + {} != {}", p_t, q_t, x_t);
        prop_assert!((p_n * q_n + p_t * q_t).abs() <= 1e-12 * scale * scale);
    }

    /// The projection lands in the cone, is idempotent and non-expansive, and no point of the
    /// cone's edges or apex is nearer.
    #[test]
    fn cone_projection_is_the_nearest_point(mu in prop_oneof![Just(0.0), 0.0..5.0f64], a in real(), b in real(), c in real(), d in real(), s in 0.0..100.0f64) {
        let cone = FrictionCone::new(mu).unwrap();
        let (p_n, p_t) = cone.project(a, b);
        let scale = 1.0 + a.abs() + b.abs();
        prop_assert!(p_n >= 0.0 && p_t.abs() <= mu * p_n * (1.0 + 1e-15));
        let (pp_n, pp_t) = cone.project(p_n, p_t);
        prop_assert!((pp_n - p_n).abs() <= 1e-12 * scale && (pp_t - p_t).abs() <= 1e-12 * scale);
        let (r_n, r_t) = cone.project(c, d);
        prop_assert!((p_n - r_n).hypot(p_t - r_t) <= (a - c).hypot(b - d) * (1.0 + 1e-12) + 1e-12);
        let distance = cone.distance(a, b);
        for (e_n, e_t) in [(s, mu * s), (s, -mu * s), (0.0, 0.0)] {
            prop_assert!(distance <= (a - e_n).hypot(b - e_t) + 1e-12 * scale);
        }
    }

    /// λ = proj_K(λ − r γ̂) ⇔ 0 ≤ γ_N ⊥ λ_N ≥ 0 and −λ_T ∈ μλ_N Sgn(γ_T), exactly on the grid
    /// (μ = 0 and μ = 1 keep every sum and the division by 1 + μ² exact).
    #[test]
    fn natural_map_vanishes_iff_signorini_and_coulomb_hold(
        mu in prop_oneof![Just(0.0), Just(1.0)],
        lambda_n in grid(), lambda_t in grid(), gamma_n in grid(), gamma_t in grid(),
        r in prop_oneof![Just(0.5), Just(1.0), Just(4.0)],
    ) {
        let map = FrictionCone::new(mu).unwrap().natural_map((lambda_n, lambda_t), (gamma_n, gamma_t), r).unwrap();
        let laws = complementarity(gamma_n, lambda_n, 0.0) && coulomb_holds(mu, lambda_n, lambda_t, gamma_t, 0.0);
        prop_assert_eq!(map == (0.0, 0.0), laws, "map {:?}", map);
    }

    /// States planted on both laws (closed and sticking or sliding, or open with no force)
    /// have a natural map of round-off size for any μ and r.
    #[test]
    fn planted_contact_states_have_a_vanishing_natural_map(mu in 0.0..2.0f64, lambda_n in 0.0..100.0f64, u in -1.0..1.0f64, speed in 0.0..5.0f64, r in 0.01..10.0f64, kind in 0..4u8) {
        let bound = mu * lambda_n;
        let (lambda, gamma) = match kind {
            0 => ((lambda_n, u * bound), (0.0, 0.0)),
            1 => ((lambda_n, -bound), (0.0, speed)),
            2 => ((lambda_n, bound), (0.0, -speed)),
            _ => ((0.0, 0.0), (speed, 10.0 * u)),
        };
        let (f_n, f_t) = FrictionCone::new(mu).unwrap().natural_map(lambda, gamma, r).unwrap();
        prop_assert!(f_n.hypot(f_t) <= 1e-12 * (1.0 + lambda_n + r * speed), "{} {}", f_n, f_t);
    }

    /// Newton's impact law checked on the graphs of Upr and Sgn holds exactly when the friction
    /// cone's natural map of (P_N, P_T) and ξ = γ⁺ + ε γ⁻ vanishes (exact on the grid with
    /// ε = 1/2 and μ ∈ {0, 1}).
    #[test]
    fn impact_check_agrees_with_the_cone_natural_map(
        mu in prop_oneof![Just(0.0), Just(1.0)],
        pre_n in grid(), pre_t in grid(), post_n in grid(), post_t in grid(),
        p_n in grid(), p_t in grid(),
    ) {
        let law = ContactLaw::new(0.5, 0.5, mu).unwrap();
        let pre = RelativeVelocity { gamma_n: pre_n, gamma_t: pre_t };
        let post = RelativeVelocity { gamma_n: post_n, gamma_t: post_t };
        let check = check_impact(pre, post, p_n, p_t, &law, 0.0);
        let map = FrictionCone::new(mu).unwrap().natural_map((p_n, p_t), (check.xi_n, check.xi_t), 1.0).unwrap();
        prop_assert_eq!(check.holds(), map == (0.0, 0.0), "{:?} {:?}", check, map);
    }
}
