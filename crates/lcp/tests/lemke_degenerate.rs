//! Lemke's method on degenerate problems, where only the lexicographic rule keeps it from
//! cycling: Siconos' `lcp_tobenna` (a game whose ratio tests tie at zero in most pivots),
//! that problem permuted and rescaled, and random problems of the same structure.
#![allow(non_snake_case)]

mod common;

use common::{Rng, assert_solves};
use faer::{Col, Mat};
use moreau_lcp::{Auto, Covering, Lcp, Lemke, LemkeOptions, Solver, Status};

/// Siconos numerics' test problem `lcp_tobenna.dat` (Apache-2.0, copied unchanged from
/// Siconos' LCP test data; see tests/data/siconos/README.md).
fn tobenna() -> Lcp {
    let text = include_str!("data/siconos/lcp/lcp_tobenna.dat");
    Lcp::read_siconos(text.as_bytes()).expect("lcp_tobenna.dat reads")
}

/// A polymatrix game in the form of `lcp_tobenna`: `2 h` strategies in `groups` groups of
/// equal size, w = M z + q with
///
/// ```text
///     [ 1  A  −G ]        [  0 ]
/// M = [ B  1  −G ],   q = [  0 ]
///     [ Gᵀ    0  ]        [ −1 ]
/// ```
///
/// (1: blocks of ones, A and B: payoffs, integers from 1 to `top`, G: the membership of
/// the strategies in the groups). The zeros in q and the integer payoffs make most ratio
/// tests tie.
fn game(h: usize, groups: usize, top: u64, rng: &mut Rng) -> Lcp {
    let m = 2 * h;
    let size = m / groups;
    assert_eq!(size * groups, m);
    let n = m + groups;
    let mut a = Mat::zeros(n, n);
    for i in 0..m {
        for j in 0..m {
            a[(i, j)] = if (i < h) == (j < h) { 1.0 } else { (1 + rng.below(top)) as f64 };
        }
        a[(i, m + i / size)] = -1.0;
        a[(m + i / size, i)] = 1.0;
    }
    Lcp::new(a, Col::from_fn(n, |i| if i < m { 0.0 } else { -1.0 })).unwrap()
}

/// `(R P M Pᵀ D, R P q)`: the rows and columns permuted alike by `perm`, the rows scaled by
/// `r` and the columns by `d` (all > 0). Its solutions are `z' = D⁻¹ P z`.
fn transformed(lcp: &Lcp, perm: &[usize], r: &[f64], d: &[f64]) -> Lcp {
    let (m, q) = (lcp.m(), lcp.q());
    let n = lcp.n();
    let m2 = Mat::from_fn(n, n, |i, j| r[i] * m[(perm[i], perm[j])] * d[j]);
    Lcp::new(m2, Col::from_fn(n, |i| r[i] * q[perm[i]])).unwrap()
}

#[test]
fn tobenna_is_solved_in_as_many_pivots_as_exact_arithmetic_takes() {
    let lcp = tobenna();
    let s = Lemke::default().solve(&lcp).unwrap();
    // The lexicographic rule in rational arithmetic (no round-off) takes 127 pivots: the one
    // that brings in z_0 and 126 complementary ones, as Siconos' `lcp_lexicolemke`
    // reports. Round-off of 1e-15 in zero entries of B^-1 deciding the comparison had made
    // the method cycle until the pivot limit.
    assert_eq!(s.status, Status::Solved);
    assert_eq!(s.iterations, 127);
    assert!(s.residual.relative <= 1e-12, "{:?}", s.residual);
    assert_solves(&lcp, &s.z, 1e-9);
    // Each group's strategies are a probability distribution.
    for g in 0..8 {
        let sum: f64 = s.z[4 * g..4 * g + 4].iter().sum();
        assert!((sum - 1.0).abs() < 1e-12, "group {g}: {sum}");
    }
}

#[test]
fn tobenna_permuted_and_rescaled_is_solved() {
    // Other orders of the variables take other lexicographic paths, and row and column
    // scales that are not powers of two change every rounding; the rule must end on each.
    let lcp = tobenna();
    let n = lcp.n();
    let mut rng = Rng::new(31);
    for trial in 0..12 {
        let mut perm: Vec<usize> = (0..n).collect();
        for i in (1..n).rev() {
            perm.swap(i, rng.below(i as u64 + 1) as usize);
        }
        let r: Vec<f64> = (0..n).map(|_| rng.uniform(0.3, 7.0)).collect();
        let d: Vec<f64> = (0..n).map(|_| rng.uniform(0.3, 7.0)).collect();
        let t = transformed(&lcp, &perm, &r, &d);
        let s = Lemke::default().solve(&t).unwrap();
        assert_eq!(s.status, Status::Solved, "trial {trial}: {} pivots", s.iterations);
        assert!(s.iterations < 2000, "trial {trial}: {} pivots", s.iterations);
        assert_solves(&t, &s.z, 1e-9);
        // Back to the original variables: z_{perm[j]} = d_j z'_j.
        let mut z = vec![0.0; n];
        for j in 0..n {
            z[perm[j]] = d[j] * s.z[j];
        }
        assert_solves(&lcp, &z, 1e-9);
    }
}

#[test]
fn random_games_of_tobenna_form_are_solved() {
    let mut rng = Rng::new(32);
    let mut lemke = Lemke::default();
    let mut long_paths = 0;
    for (h, groups, top) in [(4, 4, 3), (6, 4, 5), (8, 8, 250), (12, 6, 9), (16, 8, 250)] {
        for trial in 0..8 {
            let lcp = game(h, groups, top, &mut rng);
            let s = lemke.solve(&lcp).unwrap();
            assert_eq!(s.status, Status::Solved, "h {h}, trial {trial}: {} pivots", s.iterations);
            assert!(s.iterations < 4 * lcp.n() * lcp.n(), "h {h}, trial {trial}");
            assert_solves(&lcp, &s.z, 1e-9);
            long_paths += usize::from(s.iterations > lcp.n());
        }
    }
    // Some paths are longer than n pivots, so the degenerate pivots are exercised.
    assert!(long_paths > 0);
}

#[test]
fn a_zero_tie_tolerance_compares_exactly_and_still_ends_on_exact_data() {
    // M = 2 I and q with equal negative entries: every pivot is exact in binary, so with
    // tie_tolerance = 0 the comparisons are exact, and the first ratio test ties n / 2 rows.
    let n = 8;
    let m = Mat::from_fn(n, n, |i, j| if i == j { 2.0 } else { 0.0 });
    let lcp = Lcp::new(m, Col::from_fn(n, |i| if i % 2 == 0 { -2.0 } else { 0.0 })).unwrap();
    let mut lemke = Lemke::new(LemkeOptions::default().with_tie_tolerance(0.0)).unwrap();
    let s = lemke.solve(&lcp).unwrap();
    assert_eq!(s.status, Status::Solved);
    let expected: Vec<f64> = (0..n).map(|i| if i % 2 == 0 { 1.0 } else { 0.0 }).collect();
    assert_eq!(s.z, expected);
    // z_0 enters, then z_i for each of the n / 2 rows with q_i < 0.
    assert_eq!(s.iterations, 1 + n / 2);
}

/// A step LCP of a hyperstatic stack of five boxes at rest (tests/data/moreau/README.md).
/// With the covering d_i = max(|q_i|, 1e-3 ‖q‖∞) (one of those `Auto` tries), round-off in
/// the ratio test brings a basis back after 20 pivots; from there the pivots went round the
/// same bases to the limit of 131,072, 20 ms on 30 rows. A basis seen again now ends the
/// method at once, and `Auto` goes on to a covering that solves the problem.
#[test]
fn a_basis_seen_again_ends_the_pivots() {
    let text = include_str!("data/moreau/stack5_step_lcp.dat");
    let lcp = Lcp::read_siconos(text.as_bytes()).expect("stack5_step_lcp.dat reads");
    let q: Vec<f64> = lcp.q().iter().copied().collect();
    let q_max = q.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let d = q.iter().map(|v| v.abs().max(1e-3 * q_max)).collect();
    let options = LemkeOptions::default().with_covering(Covering::Custom(d));
    let s = Lemke::new(options).unwrap().solve(&lcp).unwrap();
    assert_eq!(s.status, Status::NumericalFailure);
    assert!(s.iterations < 100, "{} pivots", s.iterations);

    let s = Auto::default().solve(&lcp).unwrap();
    assert_eq!(s.status, Status::Solved);
    assert!(s.residual.relative <= 1e-12, "{:?}", s.residual);
    assert_solves(&lcp, &s.z, 1e-9);
}

/// A step LCP of a stack of boxes of masses 1 and 10⁻³ in turn (tests/data/moreau/README.md).
/// With the unit covering, the tableau's z passes the tolerance but not the accuracy at which
/// it is kept at once, and the basis cannot be factored to re-solve it. The failed
/// factorisation used to leave the residual of the tableau's z beside the vectors of an
/// earlier solve (here zeros): `Solved` with z = 0 and w = 0, where w = q has entries of
/// −9.8e-3; in the stepper the stack's light boxes then spun at 92 rad/s. The solution
/// returned must be the one its residual measures.
#[test]
fn a_basis_that_cannot_be_factored_again_keeps_the_tableau_solution() {
    let text = include_str!("data/moreau/stack_mass_ratio_lcp.dat");
    let lcp = Lcp::read_siconos(text.as_bytes()).expect("stack_mass_ratio_lcp.dat reads");
    let n = lcp.n();
    let s = Lemke::default().solve(&lcp).unwrap();
    assert_eq!(s.status, Status::Solved);
    assert!(s.z.iter().any(|&z| z > 1e-3), "{:?}", s.z);
    let w: Vec<f64> = (0..n)
        .map(|i| lcp.q()[i] + (0..n).map(|j| lcp.m()[(i, j)] * s.z[j]).sum::<f64>())
        .collect();
    for (mine, theirs) in w.iter().zip(&s.w) {
        assert!((mine - theirs).abs() <= 1e-14, "{mine} vs {theirs}");
    }
    let again = moreau_lcp::Residual::compute(lcp.view(), &s.z, &s.w);
    assert_eq!(again.relative, s.residual.relative);
    assert_solves(&lcp, &s.z, 1e-9);
}
