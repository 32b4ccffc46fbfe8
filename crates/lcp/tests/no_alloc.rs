//! Repeated solves of the same size do not allocate, counted per thread by a global allocator.

mod common;

use common::{Rng, friction, planted, random_spd};
use moreau_lcp::{Auto, Lcp, Lemke, Pgs, Solution, Solver};
use moreau_testsupport::{CountingAllocator, allocations_in};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

fn check(solver: &mut dyn Solver, problems: &[Lcp], warm: bool) {
    let mut out = Solution::new();
    let warm_start = vec![0.5; problems[0].n()];
    let ws = warm.then_some(warm_start.as_slice());
    // Warm-up: the first solve sizes the workspace and the solution.
    solver.solve_into(problems[0].view(), ws, &mut out).unwrap();
    assert!(out.is_solved());
    let count = allocations_in(|| {
        for p in problems {
            solver.solve_into(p.view(), ws, &mut out).unwrap();
            assert!(out.is_solved());
        }
    });
    assert_eq!(count, 0, "{count} allocations in {} solves", problems.len());
}

#[test]
fn lemke_nine_by_nine_does_not_allocate() {
    let mut rng = Rng::new(31);
    let friction_problems: Vec<Lcp> = (0..20)
        .map(|_| friction(3, 5, &mut rng).lcp)
        .filter(|lcp| Lemke::default().solve(lcp).is_ok_and(|s| s.is_solved()))
        .collect();
    assert!(friction_problems.len() >= 15);
    check(&mut Lemke::default(), &friction_problems, false);
    let spd: Vec<Lcp> =
        (0..20).map(|_| planted(random_spd(9, &mut rng), &mut rng, false).0).collect();
    check(&mut Lemke::default(), &spd, false);
    check(&mut Auto::default(), &friction_problems, false);
}

#[test]
fn pgs_nine_by_nine_does_not_allocate() {
    let mut rng = Rng::new(32);
    let spd: Vec<Lcp> =
        (0..20).map(|_| planted(random_spd(9, &mut rng), &mut rng, false).0).collect();
    check(&mut Pgs::default(), &spd, false);
    check(&mut Pgs::default(), &spd, true);
}

#[test]
fn larger_lemke_solves_do_not_allocate() {
    // n = 40 uses faer's LU for the final basis: its stack is also reused.
    let mut rng = Rng::new(33);
    let spd: Vec<Lcp> =
        (0..5).map(|_| planted(random_spd(40, &mut rng), &mut rng, false).0).collect();
    check(&mut Lemke::default(), &spd, false);
}

#[test]
fn nsgs_with_the_same_sparsity_does_not_allocate() {
    use moreau_lcp::fc2d::{Fc2dSolution, Fc2dSolver, Nsgs, NsgsOptions};
    let (w, problems) = fc2d_chains(34);
    let n_c = problems[0].n_contacts();
    let mut solver = Nsgs::new(NsgsOptions::default().with_tolerance(1e-10)).unwrap();
    let mut out = Fc2dSolution::new();
    let warm = vec![0.1; 2 * n_c];
    solver.solve_into(problems[0].view(), None, &mut out).unwrap();
    assert!(out.is_solved());
    let count = allocations_in(|| {
        for p in &problems {
            solver.solve_into(p.view(), None, &mut out).unwrap();
            assert!(out.is_solved());
            solver.solve_into(p.view(), Some(&warm), &mut out).unwrap();
            assert!(out.is_solved());
        }
    });
    assert_eq!(count, 0, "{count} allocations in {} NSGS solves", 2 * problems.len());
    // Refilling a problem from a dense W of the same size reuses its buffers.
    let mut problem = problems[0].clone();
    let q = problems[1].q().to_vec();
    let mu = problems[1].mu().to_vec();
    let count = allocations_in(|| {
        problem.set_dense(w.as_ref(), &q, &mu).unwrap();
        solver.solve_into(problem.view(), None, &mut out).unwrap();
    });
    assert_eq!(count, 0, "{count} allocations in a refill and a solve");
    assert_eq!(problem, problems[1]);
}

/// Ten chains of 30 contacts with the same W and different q and μ, and that W: blocks
/// (i, i - 1), (i, i), (i, i + 1), diagonally dominant.
fn fc2d_chains(seed: u64) -> (faer::Mat<f64>, Vec<moreau_lcp::fc2d::Fc2d>) {
    let mut rng = Rng::new(seed);
    let n_c = 30;
    let w = faer::Mat::from_fn(2 * n_c, 2 * n_c, |i, j| {
        let (ci, cj) = (i / 2, j / 2);
        if i == j {
            4.0
        } else if ci.abs_diff(cj) == 1 && i % 2 == j % 2 {
            0.5
        } else if ci == cj {
            0.3
        } else {
            0.0
        }
    });
    let problems = (0..10)
        .map(|_| {
            let q: Vec<f64> = (0..2 * n_c).map(|_| rng.uniform(-1.0, 1.0)).collect();
            let mu: Vec<f64> = (0..n_c).map(|_| rng.uniform(0.0, 0.8)).collect();
            moreau_lcp::fc2d::Fc2d::from_dense(w.as_ref(), &q, &mu).unwrap()
        })
        .collect();
    (w, problems)
}

#[test]
fn newton_and_auto_with_the_same_sparsity_do_not_allocate() {
    use moreau_lcp::fc2d::{Fc2dAuto, Fc2dSolution, Fc2dSolver, Newton, NewtonOptions};
    let (_, problems) = fc2d_chains(35);
    let mut out = Fc2dSolution::new();
    let mut newton = Newton::new(NewtonOptions::default().with_tolerance(1e-10)).unwrap();
    // Warm-up: the pattern of J, its symbolic LU and faer's numeric LU storage are sized.
    for p in &problems {
        newton.solve_into(p.view(), None, &mut out).unwrap();
        assert!(out.is_solved());
    }
    let count = allocations_in(|| {
        for p in &problems {
            newton.solve_into(p.view(), None, &mut out).unwrap();
            assert!(out.is_solved());
        }
    });
    assert_eq!(count, 0, "{count} allocations in {} Newton solves", problems.len());
    let mut auto = Fc2dAuto::default();
    auto.solve_into(problems[0].view(), None, &mut out).unwrap();
    let count = allocations_in(|| {
        for p in &problems {
            auto.solve_into(p.view(), None, &mut out).unwrap();
            assert!(out.is_solved());
        }
    });
    assert_eq!(count, 0, "{count} allocations in {} Auto solves", problems.len());
}

#[test]
fn lcp_route_with_bilateral_rows_does_not_allocate() {
    // Planted problems of 6 contacts and a two-row joint: the elimination of the joint's rows,
    // the LCP of 18 rows and its pivoting solve run on the route's kept buffers.
    use moreau_lcp::fc2d::{Fc2dSolution, Fc2dSolver, LcpRoute};
    let mut rng = Rng::new(36);
    let planted: Vec<_> = (0..10).map(|_| common::planted_fc2d(6, 0.5, true, &mut rng)).collect();
    let mut route = LcpRoute::default();
    let mut out = Fc2dSolution::new();
    route.solve_into(planted[0].problem.view(), None, &mut out).unwrap();
    assert!(out.is_solved());
    let mut worst = 0.0f64;
    let count = allocations_in(|| {
        for p in &planted {
            route.solve_into(p.problem.view(), None, &mut out).unwrap();
            assert!(out.is_solved());
            let error = out.r.iter().zip(&p.r).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            worst = worst.max(error);
        }
    });
    assert_eq!(count, 0, "{count} allocations in {} LcpRoute solves", planted.len());
    // The planted reactions are found (W is positive definite, so they are the solution).
    assert!(worst < 1e-8, "{worst:e}");
}

#[test]
fn newton_alternating_between_block_structures_does_not_allocate() {
    // A time-stepper's island whose contact opens and closes from one step to the next gives
    // Newton two block structures in turn; each keeps its pattern and LU analysis.
    use moreau_lcp::fc2d::{Fc2dSolution, Fc2dSolver, Newton, NewtonOptions};
    let (_, chains) = fc2d_chains(37);
    let mut rng = Rng::new(38);
    let jointed: Vec<_> = (0..10).map(|_| common::planted_fc2d(6, 0.5, true, &mut rng)).collect();
    let mut newton = Newton::new(NewtonOptions::default().with_tolerance(1e-10)).unwrap();
    let mut out = Fc2dSolution::new();
    // Warm-up: faer's numeric LU storage of each structure grows to its largest fill.
    for (chain, jointed) in chains.iter().zip(&jointed) {
        newton.solve_into(chain.view(), None, &mut out).unwrap();
        newton.solve_into(jointed.problem.view(), None, &mut out).unwrap();
    }
    let mut solved = 0;
    let count = allocations_in(|| {
        for (chain, jointed) in chains.iter().zip(&jointed) {
            newton.solve_into(chain.view(), None, &mut out).unwrap();
            solved += usize::from(out.is_solved());
            newton.solve_into(jointed.problem.view(), None, &mut out).unwrap();
            solved += usize::from(out.is_solved());
        }
    });
    assert_eq!(count, 0, "{count} allocations in {} alternating Newton solves", 2 * chains.len());
    assert_eq!(solved, 2 * chains.len());
}
