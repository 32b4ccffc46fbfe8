//! Gauss-Seidel's local problems in closed form: one contact open, sticking or slipping
//! either way with a coupled diagonal block, the contact whose local problem has no
//! solution, bilateral groups of one and two rows (regular and redundant), the first
//! sweeps over two coupled contacts, relaxation and the warm start's projection, and when
//! Gauss-Seidel checks its iterate: every sweep with the history kept, at sweep 64 for a
//! tolerance below round-off, and after as many sweeps whatever the scale of q.

use faer::Mat;
use moreau_lcp::Status;
use moreau_lcp::fc2d::{Fc2d, Fc2dBuilder, Fc2dSolution, Fc2dSolver, Nsgs, NsgsOptions};

/// One contact with diagonal block `a` (row-major), q and μ.
fn contact(a: [f64; 4], q: [f64; 2], mu: f64) -> Fc2d {
    let w = Mat::from_fn(2, 2, |i, j| a[2 * i + j]);
    Fc2d::from_dense(w.as_ref(), &q, &[mu]).unwrap()
}

/// NSGS with the given sweep limit and relaxation, tolerance 1e-12.
fn nsgs(max_sweeps: usize, omega: f64) -> Nsgs {
    let options =
        NsgsOptions::default().with_tolerance(1e-12).with_max_sweeps(max_sweeps).with_omega(omega);
    Nsgs::new(options).unwrap()
}

/// Whether each entry of `got` is within 1e-15 of `want`.
fn close(got: &[f64], want: &[f64]) -> bool {
    got.len() == want.len() && got.iter().zip(want).all(|(g, w)| (g - w).abs() <= 1e-15)
}

/// The block [[2, 1], [1, 2]]: positive definite, normal and tangential rows coupled.
const COUPLED: [f64; 4] = [2.0, 1.0, 1.0, 2.0];

#[test]
fn a_separating_contact_stays_open_and_is_certified_in_one_sweep() {
    // q_N = 0.5 >= 0: r = 0, u = q, and the natural map at r = 0 is already zero.
    let s = nsgs(10, 1.0).solve(&contact(COUPLED, [0.5, -3.0], 0.5)).unwrap();
    assert_eq!((s.status, s.iterations), (Status::Solved, 1), "{s:?}");
    assert_eq!((s.r.as_slice(), s.u.as_slice()), ([0.0, 0.0].as_slice(), [0.5, -3.0].as_slice()));
}

#[test]
fn a_sticking_contact_takes_minus_the_inverse_block_times_q() {
    // r = -A⁻¹ q = (1/3) [[2, -1], [-1, 2]] (3, 0) = (2, -1), inside the cone |r_T| <= 1 · 2;
    // the first sweep finds it and the second certifies it.
    let s = nsgs(10, 1.0).solve(&contact(COUPLED, [-3.0, 0.0], 1.0)).unwrap();
    assert_eq!((s.status, s.iterations), (Status::Solved, 2), "{s:?}");
    assert_eq!(s.r, vec![2.0, -1.0]);
    assert_eq!(s.u, vec![0.0, 0.0]);
}

#[test]
fn a_contact_slipping_backwards_takes_friction_forwards() {
    // q = (-1, -3), μ = 0.3: sticking needs r_N = -1/3 < 0, and slipping forwards gives
    // u_T = -3 + 0.4 / 1.7 < 0. Slipping backwards (u_T < 0, r_T = +μ r_N) with u_N = 0:
    // (2 + 0.3) r_N = 1, so r = (1, 0.3) / 2.3 and u_T = -3 + 1.6 / 2.3 < 0.
    let s = nsgs(10, 1.0).solve(&contact(COUPLED, [-1.0, -3.0], 0.3)).unwrap();
    assert_eq!(s.status, Status::Solved, "{s:?}");
    assert!(close(&s.r, &[1.0 / 2.3, 0.3 / 2.3]), "{s:?}");
    assert!(s.u[0].abs() <= 1e-15 && (s.u[1] - (-3.0 + 1.6 / 2.3)).abs() <= 1e-15, "{s:?}");
}

#[test]
fn a_contact_slipping_forwards_takes_friction_backwards() {
    // q = (-1, 3), μ = 0.3: sticking gives r = (5/3, -7/3), outside the cone. Slipping
    // forwards (u_T > 0, r_T = -μ r_N): (2 - 0.3) r_N = 1, r = (1, -0.3) / 1.7, and
    // u_T = 3 + 0.4 / 1.7 > 0.
    let s = nsgs(10, 1.0).solve(&contact(COUPLED, [-1.0, 3.0], 0.3)).unwrap();
    assert_eq!(s.status, Status::Solved, "{s:?}");
    assert!(close(&s.r, &[1.0 / 1.7, -0.3 / 1.7]), "{s:?}");
    assert!(s.u[0].abs() <= 1e-15 && (s.u[1] - (3.0 + 0.4 / 1.7)).abs() <= 1e-15, "{s:?}");
}

#[test]
fn a_frictionless_contact_takes_the_normal_reaction_alone() {
    // μ = 0: r_T = 0 and 2 r_N - 1 = 0, whatever q_T; u_T = 3 + 1 · 0.5.
    let s = nsgs(10, 1.0).solve(&contact(COUPLED, [-1.0, 3.0], 0.0)).unwrap();
    assert_eq!(s.status, Status::Solved, "{s:?}");
    assert_eq!(s.r, vec![0.5, 0.0]);
    assert_eq!(s.u, vec![0.0, 3.5]);
}

#[test]
fn a_regular_block_of_small_scale_still_takes_the_sticking_case() {
    // A = 1e-8 I (a heavy body), q = 1e-8 (-1, -0.1), μ = 0.5: r = -A⁻¹ q = (1, 0.1), inside
    // the cone. det A = 1e-16 is tiny, but relative to the block's scale squared it is 1:
    // the block is regular, and neither slipping candidate would solve the contact.
    let problem = contact([1e-8, 0.0, 0.0, 1e-8], [-1e-8, -1e-9], 0.5);
    let s = nsgs(10, 1.0).solve(&problem).unwrap();
    assert_eq!((s.status, s.iterations), (Status::Solved, 2), "{s:?}");
    assert!(close(&s.r, &[1.0, 0.1]), "{s:?}");
    assert!(s.u.iter().all(|v| v.abs() <= 1e-22), "{s:?}");
}

#[test]
fn a_contact_without_a_local_solution_takes_the_candidate_of_least_natural_map() {
    // A = [[1, 1], [1, 1]] (singular), q = (-1, 0), μ = 2: closed, u_T = u_N + 1 = 1 > 0, so
    // the contact slips forwards, r_T = -2 r_N and u_N = -r_N - 1 < 0: no solution. Of the
    // candidates, r = 0 has natural map (-1, 0) and the backward slip r = (1/3, 2/3)
    // (u = (0, 1)) has (1/3, 2/3), the smaller: every sweep returns that one.
    let s = nsgs(3, 1.0).solve(&contact([1.0, 1.0, 1.0, 1.0], [-1.0, 0.0], 2.0)).unwrap();
    assert_eq!((s.status, s.iterations), (Status::IterationLimit, 3), "{s:?}");
    assert!(close(&s.r, &[1.0 / 3.0, 2.0 / 3.0]), "{s:?}");
    let natural = (1.0f64 / 9.0 + 4.0 / 9.0).sqrt();
    assert!((s.residual.natural - natural).abs() <= 1e-15, "{:?}", s.residual);
    // A = [[4, 2], [2, 1]] (singular), q = (-1, 2), μ = 2: the backward slip r = (1/8, 1/4)
    // has u = (0, 2.5) and natural map r itself, |F|² = 0.078125; r = 0 has
    // F = -proj(-3, -2) = (-0.2, 0.4), |F|² = 0.2: the slip is kept.
    let s = nsgs(3, 1.0).solve(&contact([4.0, 2.0, 2.0, 1.0], [-1.0, 2.0], 2.0)).unwrap();
    assert_eq!((s.status, s.r.as_slice()), (Status::IterationLimit, [0.125, 0.25].as_slice()));
    assert_eq!(s.u, vec![0.0, 2.5]);
    assert!((s.residual.natural - 0.078125f64.sqrt() / 2.0).abs() <= 1e-15, "{:?}", s.residual);
}

#[test]
fn without_a_local_solution_the_open_contact_can_be_the_least_bad_candidate() {
    // The same block and μ with q = (-1, 5): the backward slip r = (1/3, 2/3) has u = (0, 6)
    // and natural map (1/3, 2/3), |F|² = 5/9; r = 0 has u = q, and r - proj(r - (u + 2 · 5
    // e_N)) = -proj(-9, -5) = (-0.2, 0.4), |F|² = 0.2, the smaller: r stays 0.
    let s = nsgs(3, 1.0).solve(&contact([1.0, 1.0, 1.0, 1.0], [-1.0, 5.0], 2.0)).unwrap();
    assert_eq!((s.status, s.iterations), (Status::IterationLimit, 3), "{s:?}");
    assert_eq!(s.r, vec![0.0, 0.0]);
    assert!((s.residual.natural - 0.2f64.sqrt() / 5.0).abs() <= 1e-15, "{:?}", s.residual);
    // With q = (-1, -0.25) the slip keeps |F|² = 5/9 (u = (0, 0.75)), and r = 0 has
    // F = -(1 - 2 · 0.25, 0.25) = (-0.5, -0.25), |F|² = 0.3125: r stays 0 again.
    let s = nsgs(3, 1.0).solve(&contact([1.0, 1.0, 1.0, 1.0], [-1.0, -0.25], 2.0)).unwrap();
    assert_eq!((s.status, s.r.as_slice()), (Status::IterationLimit, [0.0, 0.0].as_slice()));
    assert!((s.residual.natural - 0.3125f64.sqrt()).abs() <= 1e-15, "{:?}", s.residual);
}

/// A problem of bilateral groups only: one group of `rows` rows with diagonal block `a`.
fn bilateral(rows: usize, a: [f64; 4], q: &[f64]) -> Fc2d {
    let mut b = Fc2dBuilder::new(0);
    let g = b.bilateral_group(rows);
    b.add_block(g, g, a);
    b.build(q, &[]).unwrap()
}

#[test]
fn bilateral_groups_of_one_and_two_rows_are_solved_exactly() {
    // One row: 4 x - 2 = 0. Two rows: [[2, 1], [1, 2]] x = (3, 0), x = (2, -1). Both found
    // by the first sweep, certified by the second.
    let s = nsgs(10, 1.0).solve(&bilateral(1, [4.0, 0.0, 0.0, 0.0], &[-2.0])).unwrap();
    assert_eq!((s.status, s.iterations, s.r.as_slice()), (Status::Solved, 2, [0.5].as_slice()));
    let s = nsgs(10, 1.0).solve(&bilateral(2, COUPLED, &[-3.0, 0.0])).unwrap();
    assert_eq!((s.status, s.iterations), (Status::Solved, 2), "{s:?}");
    assert_eq!((s.r.as_slice(), s.u.as_slice()), ([2.0, -1.0].as_slice(), [0.0, 0.0].as_slice()));
}

#[test]
fn a_redundant_bilateral_pair_solves_its_rows_in_turn_from_the_warm_start() {
    // [[2, 2], [2, 2]] x = (4, 4) from x = (0, 1): the first row takes x_0 = (4 - 2 · 1) / 2
    // = 1, the second x_1 = (4 - 2 · 1) / 2 = 1, which solves both: (1, 1) of the solutions
    // x_0 + x_1 = 2, found by the first sweep.
    let problem = bilateral(2, [2.0; 4], &[-4.0, -4.0]);
    let mut out = Fc2dSolution::new();
    nsgs(1, 1.0).solve_into(problem.view(), Some(&[0.0, 1.0]), &mut out).unwrap();
    assert_eq!((out.status, out.iterations), (Status::Solved, 1), "{out:?}");
    assert_eq!(
        (out.r.as_slice(), out.u.as_slice()),
        ([1.0, 1.0].as_slice(), [0.0, 0.0].as_slice())
    );
    // A zero second diagonal entry: the first row is solved, x_0 = 1, the second keeps its
    // start. One row with a zero entry keeps its start the same way.
    let problem = bilateral(2, [1.0, 0.0, 0.0, 0.0], &[-1.0, 0.0]);
    nsgs(10, 1.0).solve_into(problem.view(), Some(&[0.0, 5.0]), &mut out).unwrap();
    assert_eq!((out.status, out.r.as_slice()), (Status::Solved, [1.0, 5.0].as_slice()));
    let problem = bilateral(1, [0.0; 4], &[0.0]);
    nsgs(10, 1.0).solve_into(problem.view(), Some(&[3.0]), &mut out).unwrap();
    assert_eq!((out.status, out.r.as_slice()), (Status::Solved, [3.0].as_slice()));
}

#[test]
fn a_regular_bilateral_pair_of_small_scale_is_solved_as_a_pair() {
    // 1e-8 [[2, 1], [1, 2]] x = 1e-8 (3, 0): x = (2, -1). The determinant 3e-16 is tiny but
    // 3/4 of the block's scale squared, so the pair is solved at once (one sweep, and a
    // second that certifies it), not row by row.
    let a = COUPLED.map(|v| 1e-8 * v);
    let s = nsgs(10, 1.0).solve(&bilateral(2, a, &[-3e-8, 0.0])).unwrap();
    assert_eq!((s.status, s.iterations), (Status::Solved, 2), "{s:?}");
    assert!(close(&s.r, &[2.0, -1.0]), "{s:?}");
}

#[test]
fn a_redundant_bilateral_pair_is_solved_row_by_row() {
    // [[1, 1], [1, 1]] x = (2, 2): singular. The first row takes x_0 = 2 - x_1 with x_1 at
    // its start 0, the second then x_1 = 2 - x_0 = 0: x = (2, 0), u = 0.
    let s = nsgs(10, 1.0).solve(&bilateral(2, [1.0, 1.0, 1.0, 1.0], &[-2.0, -2.0])).unwrap();
    assert_eq!(s.status, Status::Solved, "{s:?}");
    assert_eq!((s.r.as_slice(), s.u.as_slice()), ([2.0, 0.0].as_slice(), [0.0, 0.0].as_slice()));
    // With a zero first diagonal entry the first row keeps its start, the second solves
    // x_1 = 3.
    let s = nsgs(10, 1.0).solve(&bilateral(2, [0.0, 0.0, 0.0, 1.0], &[0.0, -3.0])).unwrap();
    assert_eq!(s.status, Status::Solved, "{s:?}");
    assert_eq!(s.r, vec![0.0, 3.0]);
    // A zero block determines neither row: both keep their start, here a warm start that
    // solves the problem (u = q = 0).
    let problem = bilateral(2, [0.0; 4], &[0.0, 0.0]);
    let mut out = Fc2dSolution::new();
    nsgs(10, 1.0).solve_into(problem.view(), Some(&[1.0, 2.0]), &mut out).unwrap();
    assert_eq!((out.status, out.r.as_slice()), (Status::Solved, [1.0, 2.0].as_slice()));
    // And a warm start of that first row is kept as it was.
    let problem = bilateral(2, [0.0, 0.0, 0.0, 1.0], &[0.0, -3.0]);
    let mut out = Fc2dSolution::new();
    nsgs(10, 1.0).solve_into(problem.view(), Some(&[7.0, 0.0]), &mut out).unwrap();
    assert_eq!((out.status, out.r.as_slice()), (Status::Solved, [7.0, 3.0].as_slice()));
}

/// Two contacts with diagonal blocks 2 I, coupled by W_12 = [[1, 0.5], [0.25, 0.5]] and
/// W_21 = W_12ᵀ, q = (-2, 0, -2, 0), μ = 1.
fn two_coupled_contacts() -> Fc2d {
    let mut b = Fc2dBuilder::new(2);
    b.add_block(0, 0, [2.0, 0.0, 0.0, 2.0]);
    b.add_block(1, 1, [2.0, 0.0, 0.0, 2.0]);
    b.add_block(0, 1, [1.0, 0.5, 0.25, 0.5]);
    b.add_block(1, 0, [1.0, 0.25, 0.5, 0.5]);
    b.build(&[-2.0, 0.0, -2.0, 0.0], &[1.0, 1.0]).unwrap()
}

#[test]
fn gauss_seidel_uses_the_newest_reaction_of_the_other_contact() {
    // Sweep 1: contact 0 sees v = (-2, 0) and sticks at (1, 0); contact 1 then sees
    // v = (-2 + 1, 0.5) and sticks at (0.5, -0.25). Sweep 2: contact 0 sees
    // v = (-2 + 0.5 - 0.125, 0.125 - 0.125) = (-1.625, 0), r = (0.8125, 0); contact 1 sees
    // v = (-2 + 0.8125, 0.40625), r = (0.59375, -0.203125). Every number is dyadic, so exact.
    let problem = two_coupled_contacts();
    let s = nsgs(1, 1.0).solve(&problem).unwrap();
    assert_eq!((s.status, s.iterations), (Status::IterationLimit, 1));
    assert_eq!(s.r, vec![1.0, 0.0, 0.5, -0.25]);
    let s = nsgs(2, 1.0).solve(&problem).unwrap();
    assert_eq!((s.status, s.iterations), (Status::IterationLimit, 2));
    assert_eq!(s.r, vec![0.8125, 0.0, 0.59375, -0.203125]);
    // The sweeps converge to the solution: both contacts stick, W r + q = 0.
    let s = nsgs(1000, 1.0).solve(&problem).unwrap();
    assert_eq!(s.status, Status::Solved, "{s:?}");
    assert!(s.u.iter().all(|v| v.abs() <= 1e-11), "{s:?}");
    assert!(s.r[1].abs() <= s.r[0] && s.r[3].abs() <= s.r[2], "{s:?}");
}

#[test]
fn under_relaxation_moves_a_fraction_omega_of_the_way_per_sweep() {
    // One sticking contact, A = 2 I, q = (-2, 1), μ = 1: r* = (1, -0.5). With ω = 0.5 from
    // r = 0 each sweep halves the distance to r*: after 3 sweeps r = (1 - 1/8) r*, inside
    // the cone, so the projection leaves it.
    let problem = contact([2.0, 0.0, 0.0, 2.0], [-2.0, 1.0], 1.0);
    let s = nsgs(3, 0.5).solve(&problem).unwrap();
    assert_eq!((s.status, s.iterations), (Status::IterationLimit, 3));
    assert_eq!(s.r, vec![0.875, -0.4375]);
    // A bilateral row the same way: 4 x = 2, x = 0.5 (1 - 1/4) after two sweeps.
    let s = nsgs(2, 0.5).solve(&bilateral(1, [4.0, 0.0, 0.0, 0.0], &[-2.0])).unwrap();
    assert_eq!((s.status, s.r.as_slice()), (Status::IterationLimit, [0.375].as_slice()));
}

#[test]
fn a_warm_start_is_projected_onto_the_cone_and_relaxed_iterates_are_too() {
    // A = I, q = (-1, -2), μ = 0.5: the contact slips backwards, r* = (1, 0.5). The warm start
    // (-1, 5) projects onto the cone at ((-1 + 0.5 · 5) / 1.25, 0.5 ·) = (1.2, 0.6), and
    // ω = 0.5 gives 0.5 r* + 0.5 (1.2, 0.6) = (1.1, 0.55), on the cone's edge.
    let problem = contact([1.0, 0.0, 0.0, 1.0], [-1.0, -2.0], 0.5);
    let mut out = Fc2dSolution::new();
    nsgs(1, 0.5).solve_into(problem.view(), Some(&[-1.0, 5.0]), &mut out).unwrap();
    assert!(close(&out.r, &[1.1, 0.55]), "{out:?}");
    // ω = 1.5 from (1, -0.5) (inside the cone): 1.5 r* - 0.5 (1, -0.5) = (1, 1), outside the
    // cone, projected to ((1 + 0.5) / 1.25, 0.5 ·) = (1.2, 0.6).
    nsgs(1, 1.5).solve_into(problem.view(), Some(&[1.0, -0.5]), &mut out).unwrap();
    assert!(close(&out.r, &[1.2, 0.6]), "{out:?}");
}

#[test]
fn a_non_finite_iterate_ends_the_sweeps_as_a_numerical_failure() {
    // A bilateral row 1e-300 x = 1e10: x = 1e310 overflows in the first sweep.
    let s = nsgs(10, 1.0).solve(&bilateral(1, [1e-300, 0.0, 0.0, 0.0], &[-1e10])).unwrap();
    assert_eq!((s.status, s.iterations), (Status::NumericalFailure, 1), "{s:?}");
    assert!(!s.is_solved());
}

#[test]
fn keeping_the_history_checks_every_sweep() {
    // The sticking contact is exact after the first sweep; with the history kept that sweep
    // is checked at once and ends the solve (one sweep, not two), its residual recorded.
    let problem = contact(COUPLED, [-3.0, 0.0], 1.0);
    let options = NsgsOptions::default().with_tolerance(1e-12).with_keep_history(true);
    let s = Nsgs::new(options.clone()).unwrap().solve(&problem).unwrap();
    assert_eq!((s.status, s.iterations), (Status::Solved, 1), "{s:?}");
    assert_eq!(s.r, vec![2.0, -1.0]);
    assert_eq!(s.history, vec![s.residual.natural]);
    assert_eq!(s.history, vec![0.0]);
    // Over three sweeps short of the solution, three entries, the last the final residual.
    let problem = contact([2.0, 0.0, 0.0, 2.0], [-2.0, 1.0], 1.0);
    let relaxed = options.with_omega(0.5).with_max_sweeps(3);
    let s = Nsgs::new(relaxed.clone()).unwrap().solve(&problem).unwrap();
    assert_eq!((s.status, s.iterations, s.history.len()), (Status::IterationLimit, 3, 3));
    assert_eq!(s.history[2], s.residual.natural);
    assert!(s.history[0] > s.history[1] && s.history[1] > s.history[2], "{:?}", s.history);
    assert_eq!(Nsgs::new(relaxed.clone()).unwrap().options(), &relaxed);
}

#[test]
fn a_tolerance_below_round_off_is_met_at_the_first_scheduled_check() {
    // The backward slip of r = (1, 0.3) / 2.3 leaves round-off in the lagged residual, which
    // a tolerance of 1e-300 never sees met; the full check after sweep 64 finds r solved at
    // round-off and ends there, not at the limit of 10,000 sweeps.
    let problem = contact(COUPLED, [-1.0, -3.0], 0.3);
    let options = NsgsOptions::default().with_tolerance(1e-300);
    let s = Nsgs::new(options).unwrap().solve(&problem).unwrap();
    assert_eq!(s.status, Status::Solved, "{s:?}");
    assert!(s.residual.natural > 1e-300 && s.residual.natural <= s.residual.round_off, "{s:?}");
    assert_eq!(s.iterations, 64, "{s:?}");
}

#[test]
fn a_warm_start_off_the_solution_in_one_row_is_not_taken_for_solved() {
    // The lagged residual of the first sweep is measured at the warm start, in every row.
    // A = 2 I, q = (-2, 1), μ = 1 from r = (1, 0.5): u = (0, 2) and the natural map is
    // (0.75, 0.75), so the first sweep's exact r = (1, -0.5) is certified by the second.
    let problem = contact([2.0, 0.0, 0.0, 2.0], [-2.0, 1.0], 1.0);
    let mut out = Fc2dSolution::new();
    nsgs(10, 1.0).solve_into(problem.view(), Some(&[1.0, 0.5]), &mut out).unwrap();
    assert_eq!((out.status, out.iterations), (Status::Solved, 2), "{out:?}");
    assert_eq!(out.r, vec![1.0, -0.5]);
    // A bilateral pair 2 I x = (2, 2) from x = (1, 0): u = (0, -2), the second row off.
    let problem = bilateral(2, [2.0, 0.0, 0.0, 2.0], &[-2.0, -2.0]);
    nsgs(10, 1.0).solve_into(problem.view(), Some(&[1.0, 0.0]), &mut out).unwrap();
    assert_eq!((out.status, out.iterations), (Status::Solved, 2), "{out:?}");
    assert_eq!(out.r, vec![1.0, 1.0]);
}

#[test]
fn under_relaxation_moves_both_rows_of_a_bilateral_pair() {
    // [[2, 1], [1, 2]] x = (3, 0) has x* = (2, -1), which the pair's local solve gives at
    // once; with ω = 0.5 from x = (0, 4) the sweep moves half way: (1, 1.5), in each row.
    let problem = bilateral(2, COUPLED, &[-3.0, 0.0]);
    let mut out = Fc2dSolution::new();
    nsgs(1, 0.5).solve_into(problem.view(), Some(&[0.0, 4.0]), &mut out).unwrap();
    assert_eq!((out.status, out.iterations), (Status::IterationLimit, 1), "{out:?}");
    assert_eq!(out.r, vec![1.0, 1.5]);
}

/// Two bilateral rows of one row each, W = [[1, 0.5], [0.5, 1]], q = s (-2, 1): Gauss-Seidel
/// contracts their error by 1/4 a sweep towards r = s (10/3, -8/3).
fn two_coupled_rows(s: f64) -> Fc2d {
    let mut b = Fc2dBuilder::new(0);
    let (g, h) = (b.bilateral_group(1), b.bilateral_group(1));
    b.add_block(g, g, [1.0, 0.0, 0.0, 0.0]);
    b.add_block(h, h, [1.0, 0.0, 0.0, 0.0]);
    b.add_block(g, h, [0.5, 0.0, 0.0, 0.0]);
    b.add_block(h, g, [0.5, 0.0, 0.0, 0.0]);
    b.build(&[-2.0 * s, s], &[]).unwrap()
}

#[test]
fn gauss_seidel_stops_after_as_many_sweeps_whatever_the_scale_of_q() {
    // Scaling q by a power of two scales every iterate exactly. The test on the lagged
    // residual is relative to max(1, ‖q‖∞), so the problems with ‖q‖∞ = 1, 2 and 2048 stop
    // after the same sweep (before the first scheduled check at 64), with r scaled exactly.
    let base = nsgs(1000, 1.0).solve(&two_coupled_rows(0.5)).unwrap();
    assert_eq!(base.status, Status::Solved, "{base:?}");
    assert!(base.iterations < 64, "{base:?}");
    let want = [5.0 / 3.0, -4.0 / 3.0];
    assert!(base.r.iter().zip(want).all(|(r, w)| (r - w).abs() <= 1e-11), "{base:?}");
    for s in [2.0, 2048.0] {
        let scaled = nsgs(1000, 1.0).solve(&two_coupled_rows(0.5 * s)).unwrap();
        assert_eq!((scaled.status, scaled.iterations), (Status::Solved, base.iterations), "{s}");
        assert!(scaled.r.iter().zip(&base.r).all(|(a, b)| *a == s * b), "{s}: {scaled:?}");
    }
}
