//! The many-body path (a mechanism with a body structure) against the path of fixed contacts
//! on the same disks, and against closed forms.

use std::ops::ControlFlow;

use moreau_lcp::Method;
use moreau_lcp::fc2d::{Fc2d, Fc2dSolution, Fc2dSolver, Nsgs, NsgsOptions};
use moreau_setvalued::ContactLaw;
use moreau_stepper::{
    BodyContact, BodyStructure, SolverChoice, StepError, StepReport, Stepper, StepperOptions,
};
use moreau_testsupport::{Disks, Feature, G};

/// One step's numbers, by contact id: (id, P_N, P_T).
type Impulses = Vec<(u64, f64, f64)>;

/// Runs `steps` steps and keeps q, u, the impulses of the closed contacts and the impulse
/// dissipation of every step.
fn run(stepper: &mut Stepper<Disks>, steps: usize) -> Vec<(Vec<f64>, Vec<f64>, Impulses, f64)> {
    (0..steps)
        .map(|_| {
            let r = stepper.step().unwrap();
            let impulses = r
                .contacts
                .iter()
                .zip(r.contact_ids)
                .filter(|(c, _)| c.p_n != 0.0 || c.p_t != 0.0)
                .map(|(c, &id)| (id, c.p_n, c.p_t))
                .collect();
            (r.q.to_vec(), r.u.to_vec(), impulses, r.impulse_dissipation())
        })
        .collect()
}

/// The two paths from the same state agree to `tol` in q, u, the impulses and the dissipation.
/// A resting contact's gap is zero up to rounding, which differs between the paths at the
/// level of the solvers' tolerance: a gap tolerance keeps such a contact closed on both.
fn agree(make: impl Fn(bool) -> Disks, q0: &[f64], u0: &[f64], steps: usize, tol: f64) {
    agree_with(StepperOptions::new(1e-3).with_gap_tolerance(1e-9), make, q0, u0, steps, tol)
}

fn agree_with(
    opts: StepperOptions,
    make: impl Fn(bool) -> Disks,
    q0: &[f64],
    u0: &[f64],
    steps: usize,
    tol: f64,
) {
    let mut dense = Stepper::new(make(false), q0, u0, 0.0, opts.clone()).unwrap();
    let mut sparse = Stepper::new(make(true), q0, u0, 0.0, opts).unwrap();
    let (a, b) = (run(&mut dense, steps), run(&mut sparse, steps));
    let mut closed = 0;
    for (k, (a, b)) in a.iter().zip(&b).enumerate() {
        for (x, y) in a.0.iter().zip(&b.0).chain(a.1.iter().zip(&b.1)) {
            assert!((x - y).abs() <= tol, "step {k}: q or u {x} against {y}");
        }
        assert_eq!(a.2.len(), b.2.len(), "step {k}: closed contacts {:?} {:?}", a.2, b.2);
        for (x, y) in a.2.iter().zip(&b.2) {
            assert_eq!(x.0, y.0, "step {k}");
            assert!((x.1 - y.1).abs() <= tol && (x.2 - y.2).abs() <= tol, "step {k}: {x:?} {y:?}");
        }
        assert!((a.3 - b.3).abs() <= tol, "step {k}: dissipation {} against {}", a.3, b.3);
        closed += a.2.len();
    }
    assert!(closed > 0, "no contact closed: the comparison tests nothing");
}

fn law(eps: f64, mu: f64) -> ContactLaw {
    ContactLaw::new(eps, 0.0, mu).unwrap()
}

#[test]
fn a_bouncing_disk_is_the_same_on_both_paths() {
    let make = |s| Disks::new(vec![1.0], vec![0.1], law(0.5, 0.3), s);
    // Thrown sideways and spinning, so that friction acts at the impacts.
    agree(make, &[0.0, 0.5, 0.0], &[1.0, 0.0, 5.0], 1500, 1e-10);
}

#[test]
fn a_column_of_five_disks_settles_alike_on_both_paths() {
    let centres: Vec<_> =
        (0..5).map(|k| (0.01 * (k % 2) as f64, 0.1 + 0.2 * k as f64 + 0.01 * k as f64)).collect();
    let (q0, u0) = Disks::state_at(&centres);
    let make = |s| Disks::new(vec![1.0; 5], vec![0.1; 5], law(0.0, 0.4), s).with_walls(-1.0, 1.0);
    agree(make, &q0, &u0, 600, 1e-10);
}

#[test]
fn three_touching_disks_struck_at_one_end_follow_newtons_law_at_every_contact() {
    let make = |s| Disks::new(vec![1.0; 3], vec![0.1; 3], law(1.0, 0.0), s).with_gravity(0.0);
    let (q0, mut u0) = Disks::state_at(&[(0.0, 1.0), (0.2, 1.0), (0.4, 1.0)]);
    u0[0] = 1.0;
    agree(make, &q0, &u0, 3, 1e-12);
    let mut s = Stepper::new(make(true), &q0, &u0, 0.0, StepperOptions::new(1e-3)).unwrap();
    let r = s.step().unwrap();
    for (k, v) in [-1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0].into_iter().enumerate() {
        assert!((r.u[3 * k] - v).abs() < 1e-12, "disk {k}: {}", r.u[3 * k]);
    }
    assert_eq!(r.contacts.len(), 2);
    assert!(r.contacts.iter().all(|c| c.impact == (c.gamma_n_a < 0.0)));
    assert!(r.impulse_dissipation().abs() < 1e-12, "elastic: {}", r.impulse_dissipation());
}

#[test]
fn the_projection_removes_penetration_alike_on_both_paths() {
    // Three disks in a column, each sunk 1 mm into the one below and the lowest into the floor.
    let centres: Vec<_> = (0..3).map(|k| (0.0, 0.099 + 0.199 * k as f64)).collect();
    let (q0, u0) = Disks::state_at(&centres);
    let make = |s| Disks::new(vec![1.0, 2.0, 3.0], vec![0.1; 3], law(0.0, 0.3), s);
    let opts = StepperOptions::new(1e-3)
        .with_gap_tolerance(1e-9)
        .with_projection(true)
        .with_projection_tolerance(1e-9);
    agree_with(opts.clone(), make, &q0, &u0, 200, 1e-10);
    let mut s = Stepper::new(make(true), &q0, &u0, 0.0, opts).unwrap();
    let r = s.step().unwrap();
    assert!(r.penetration > 9e-4, "at the midpoint: {}", r.penetration);
    assert!(r.times.projection > std::time::Duration::ZERO);
    let q = s.q().to_vec();
    let mut gaps = Vec::new();
    s.mechanism().detect(&q, s.t(), 1.0, &mut gaps);
    let worst = gaps.iter().map(|c| c.point.g_n).fold(f64::INFINITY, f64::min);
    assert!(worst >= -1e-9, "after the projection: {worst}");
}

#[test]
fn the_record_keeps_bodies_energies_and_impacts_by_identity() {
    let disks = Disks::new(vec![2.0], vec![0.1], law(0.5, 0.0), true);
    let mut s =
        Stepper::new(disks, &[0.0, 0.6, 0.0], &[0.0; 3], 0.0, StepperOptions::new(1e-3)).unwrap();
    let record = s.record_until(0.5).unwrap();
    assert_eq!(record.len(), 501);
    assert_eq!(record.p_n.width(), 0);
    // The first impact at t = sqrt(2 · 0.5 / g), on the floor (id 0), loses 3/4 of the
    // kinetic energy: kinetic + potential + dissipated is kept to round-off.
    let first = record.impacts[0];
    assert_eq!(first.contact, 0);
    assert!((first.t - (1.0 / G).sqrt()).abs() < 2e-3, "{}", first.t);
    let total = record.total_energy();
    for (k, e) in total.iter().enumerate() {
        let balance = e + record.cumulative_dissipation[k] - total[0];
        assert!(balance.abs() < 1e-12 * total[0], "row {k}: {balance}");
    }
    assert!(record.cumulative_dissipation.last().unwrap() > &(0.7 * 2.0 * G * 0.5));
}

#[test]
fn every_solver_choice_steps_a_pile() {
    let (_, q, u) = piles([true, true], true);
    let reference = {
        let (d, ..) = piles([true, true], true);
        let mut s = Stepper::new(d, &q, &u, 0.0, StepperOptions::new(1e-3)).unwrap();
        run(&mut s, 300)
    };
    let pgs = SolverChoice::Pgs { tolerance: 1e-12, omega: 1.0, max_iterations: 10_000 };
    for solver in [SolverChoice::Lemke, SolverChoice::Enumeration, pgs] {
        let (d, ..) = piles([true, true], true);
        let opts = StepperOptions::new(1e-3).with_solver(solver);
        let mut s = Stepper::new(d, &q, &u, 0.0, opts).unwrap();
        let other = run(&mut s, 300);
        for (a, b) in reference.iter().zip(&other) {
            for (x, y) in a.0.iter().zip(&b.0) {
                assert!((x - y).abs() < 1e-9, "{solver:?}: {x} {y}");
            }
        }
    }
}

#[test]
fn a_sliding_disk_decelerates_at_mu_g_until_it_rolls() {
    let (mu, u0, dt) = (0.2, 3.0, 1e-3);
    let disks = Disks::new(vec![2.0], vec![0.1], law(0.0, mu), true);
    let mut s =
        Stepper::new(disks, &[0.0, 0.1, 0.0], &[u0, 0.0, 0.0], 0.0, StepperOptions::new(dt))
            .unwrap();
    // Slipping, friction −μ m g decelerates the centre and spins the disk up until
    // u_x + ω r = 0 at t* = u0 / (3 μ g); the angular momentum about the contact point is
    // kept, so it rolls on at 2 u0 / 3.
    let t_star = u0 / (3.0 * mu * G);
    let mut slipping = 0;
    while s.t() < 2.0 * t_star {
        let r = s.step().unwrap();
        let (t, ux) = (r.t, r.u[0]);
        if t < t_star - dt {
            assert!((ux - (u0 - mu * G * t)).abs() < 1e-9, "t = {t}: {ux} {:?}", r.lcp);
            slipping += 1;
        } else if t > t_star + dt {
            assert!((ux - 2.0 * u0 / 3.0).abs() < 1e-9, "t = {t}: {ux}");
            assert!((ux + r.u[2] * 0.1).abs() < 1e-9, "rolling: {} {}", ux, r.u[2]);
        }
    }
    assert!(slipping > 400, "{slipping}");
}

/// A column of n disks of masses 1, 2, ... standing on the floor between walls.
fn column(n: usize, structured: bool) -> (Disks, Vec<f64>, Vec<f64>) {
    let m = (1..=n).map(|k| k as f64).collect();
    let disks = Disks::new(m, vec![0.1; n], law(0.0, 0.3), structured).with_walls(-0.5, 0.5);
    let centres: Vec<_> = (0..n).map(|k| (0.0, 0.1 + 0.2 * k as f64)).collect();
    let (q, u) = Disks::state_at(&centres);
    (disks, q, u)
}

#[test]
fn a_settled_column_rests_on_the_floor_with_its_weight() {
    let (disks, q, u) = column(10, true);
    let weight: f64 = disks.m.iter().sum::<f64>() * G;
    let dt = 1e-3;
    let mut s = Stepper::new(disks, &q, &u, 0.0, StepperOptions::new(dt)).unwrap();
    for _ in 0..500 {
        s.step().unwrap();
    }
    let r = s.step().unwrap();
    let floor: f64 = r
        .contacts
        .iter()
        .zip(r.contact_ids)
        .filter(|(_, id)| **id < 30 && **id % 3 == 0)
        .map(|(c, _)| c.p_n)
        .sum();
    let rel = (floor - weight * dt).abs() / (weight * dt);
    assert!(rel < 1e-8, "floor {floor} against weight x dt {}: {rel:e}", weight * dt);
    assert_eq!(r.contacts.len(), 10);
    assert!(r.lcp.unwrap().residual < 1e-9, "{:?}", r.lcp);
}

#[test]
fn a_resting_column_needs_fewer_sweeps_once_warm() {
    let (disks, q, u) = column(20, true);
    let mut s = Stepper::new(disks, &q, &u, 0.0, StepperOptions::new(1e-3)).unwrap();
    for _ in 0..300 {
        s.step().unwrap();
    }
    let warm = s.step().unwrap().lcp.unwrap();
    let (t, q, u) = (s.t(), s.q().to_vec(), s.u().to_vec());
    s.set_state(t, &q, &u).unwrap();
    let cold = s.step().unwrap().lcp.unwrap();
    assert_eq!(warm.method, Method::Nsgs);
    assert!(warm.iterations <= 2, "warm: {warm:?}");
    assert!(cold.iterations >= 20, "cold: {cold:?}");
}

/// Two piles of three disks, far apart.
fn piles(which: [bool; 2], structured: bool) -> (Disks, Vec<f64>, Vec<f64>) {
    let mut centres = Vec::new();
    for (p, x) in [(0, 0.0), (1, 5.0)] {
        if which[p] {
            for k in 0..3 {
                centres.push((x + 0.02 * k as f64, 0.12 + 0.21 * k as f64));
            }
        }
    }
    let n = centres.len();
    let disks = Disks::new(vec![1.0; n], vec![0.1; n], law(0.2, 0.5), structured);
    let (q, u) = Disks::state_at(&centres);
    (disks, q, u)
}

#[test]
fn two_separate_piles_step_as_each_pile_alone() {
    let steps = 800;
    let (both, q, u) = piles([true, true], true);
    let mut s = Stepper::new(both, &q, &u, 0.0, StepperOptions::new(1e-3)).unwrap();
    let together = run(&mut s, steps);
    for (p, which) in [(0, [true, false]), (1, [false, true])] {
        let (alone, q, u) = piles(which, true);
        let mut s = Stepper::new(alone, &q, &u, 0.0, StepperOptions::new(1e-3)).unwrap();
        let alone = run(&mut s, steps);
        for (a, b) in alone.iter().zip(&together) {
            assert_eq!(a.0[..], b.0[9 * p..9 * p + 9]);
            assert_eq!(a.1[..], b.1[9 * p..9 * p + 9]);
        }
    }
}

#[test]
fn the_last_islands_are_the_step_problems_that_gave_the_impulses() {
    let (disks, q, u) = column(6, true);
    let mut s = Stepper::new(disks, &q, &u, 0.0, StepperOptions::new(1e-3)).unwrap();
    run(&mut s, 300);
    let reported: Vec<f64> =
        s.step().unwrap().contacts.iter().flat_map(|c| [c.p_n, c.p_t]).collect();
    let islands: Vec<Fc2d> = s.last_islands().map(|p| p.to_owned()).collect();
    // The resting column is one island: the floor and five contacts between disks.
    assert_eq!(islands.iter().map(|p| p.view().n_contacts()).collect::<Vec<_>>(), [6]);
    let mut solver = Nsgs::new(NsgsOptions::default().with_tolerance(1e-13)).unwrap();
    let mut again = Vec::new();
    for p in &islands {
        let mut out = Fc2dSolution::new();
        solver.solve_into(p.view(), None, &mut out).unwrap();
        assert!(out.is_solved(), "{:?}", out.residual);
        // At rest the normal velocities vanish: u_N = (W r + q)_N = 0.
        assert!(out.u.iter().step_by(2).all(|v| v.abs() < 1e-12), "{:?}", out.u);
        again.extend_from_slice(&out.r);
    }
    assert_eq!(again.len(), reported.len());
    for (a, b) in again.iter().zip(&reported) {
        assert!((a - b).abs() < 1e-9 * (1.0 + b.abs()), "{again:?} against {reported:?}");
    }
}

#[test]
fn one_and_two_threads_give_bit_identical_trajectories() {
    // Twelve columns of thirty disks: more contacts than one batch holds.
    let centres: Vec<_> = (0..12)
        .flat_map(|c| (0..30).map(move |k| (0.5 * c as f64, 0.1 + 0.2 * k as f64)))
        .collect();
    let n = centres.len();
    let (q, u) = Disks::state_at(&centres);
    let trajectory = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let disks = Disks::new(vec![1.0; n], vec![0.1; n], law(0.0, 0.3), true);
            let mut s = Stepper::new(disks, &q, &u, 0.0, StepperOptions::new(1e-3)).unwrap();
            let mut contacts = 0;
            s.run_until(0.15, &mut |r: &StepReport<'_>| {
                contacts = contacts.max(r.contacts.len());
                ControlFlow::Continue(())
            })
            .unwrap();
            assert!(contacts > 300, "{contacts}");
            (s.q().to_vec(), s.u().to_vec())
        })
    };
    let (one, two) = (trajectory(1), trajectory(2));
    assert!(one.0.iter().zip(&two.0).all(|(a, b)| a.to_bits() == b.to_bits()));
    assert!(one.1.iter().zip(&two.1).all(|(a, b)| a.to_bits() == b.to_bits()));
}

#[test]
fn a_one_contact_island_is_solved_exactly() {
    let disks = Disks::new(vec![1.0], vec![0.1], law(0.5, 0.3), true);
    let mut s =
        Stepper::new(disks, &[0.0, 0.1005, 0.0], &[1.0, -1.0, 0.0], 0.0, StepperOptions::new(1e-3))
            .unwrap();
    let r = s.step().unwrap();
    let info = r.lcp.unwrap();
    assert!(r.contacts[0].p_n > 0.0 && r.contacts[0].impact);
    assert!(info.residual <= 1e-12, "{info:?}");
    // Newton's law: γ_N,E = −ε γ_N,A.
    assert!((r.contacts[0].gamma_n + 0.5 * r.contacts[0].gamma_n_a).abs() < 1e-12);
    assert_eq!(disks_feature(r.contact_ids[0]), Feature::Floor(0));
}

fn disks_feature(id: u64) -> Feature {
    Disks::new(vec![1.0], vec![0.1], law(0.0, 0.0), true).feature(id)
}

/// Disks whose detection reports the first contact with a NaN gap.
struct Poisoned(Disks);

impl moreau_kinematics::ContactKinematics for Poisoned {
    fn num_coordinates(&self) -> usize {
        3 * self.0.n()
    }
    fn num_contacts(&self) -> usize {
        0
    }
    fn normal_gap(&self, _i: usize, _q: &[f64], _t: f64) -> f64 {
        unreachable!("the stepper asks the body structure")
    }
    fn contact(
        &self,
        _i: usize,
        _q: &[f64],
        _t: f64,
        _w_n: &mut [f64],
        _w_t: &mut [f64],
    ) -> moreau_kinematics::ContactPoint {
        unreachable!("the stepper asks the body structure")
    }
}

impl moreau_stepper::Mechanism for Poisoned {
    fn laws(&self) -> &[ContactLaw] {
        &[]
    }
    fn mass_matrix(&self, q: &[f64], t: f64, m: &mut [f64]) {
        moreau_stepper::Mechanism::mass_matrix(&self.0, q, t, m)
    }
    fn forces(&self, q: &[f64], u: &[f64], t: f64, h: &mut [f64]) {
        moreau_stepper::Mechanism::forces(&self.0, q, u, t, h)
    }
    fn body_structure(&self) -> Option<&dyn BodyStructure> {
        Some(self)
    }
}

impl BodyStructure for Poisoned {
    fn num_bodies(&self) -> usize {
        self.0.n()
    }
    fn mass_blocks(&self, q: &[f64], t: f64, blocks: &mut [[f64; 9]]) {
        self.0.mass_blocks(q, t, blocks)
    }
    fn detect(&self, q: &[f64], t: f64, margin: f64, out: &mut Vec<BodyContact>) {
        let first = out.len();
        self.0.detect(q, t, margin, out);
        if let Some(c) = out.get_mut(first) {
            c.point.g_n = f64::NAN;
        }
    }
}

#[test]
fn bad_structures_and_gaps_are_typed_errors() {
    // Two bodies over three coordinates.
    let two = Disks::new(vec![1.0; 2], vec![0.1; 2], law(0.0, 0.0), true);
    let e = Stepper::new(two, &[0.0; 3], &[0.0; 3], 0.0, StepperOptions::new(1e-3)).unwrap_err();
    assert!(matches!(e, StepError::Dimension { expected: 6, found: 3, .. }), "{e}");
    let one = Poisoned(Disks::new(vec![1.0], vec![0.1], law(0.0, 0.0), true));
    let opts = StepperOptions::new(1e-3);
    let mut s = Stepper::new(one, &[0.0, 0.1, 0.0], &[0.0; 3], 0.0, opts).unwrap();
    let e = s.step().unwrap_err();
    assert!(matches!(e, StepError::NonFinite { what: "g_N", index: 0, .. }), "{e}");
    // The state is left at the start of the failed step.
    assert_eq!((s.t(), s.q()), (0.0, &[0.0, 0.1, 0.0][..]));
}

#[test]
fn a_stepper_of_disks_with_a_body_structure_is_send_and_sync() {
    fn send_sync<T: Send + Sync>() {}
    send_sync::<Stepper<Disks>>();
}

#[test]
fn an_island_the_solver_does_not_finish_is_a_typed_error_with_its_problem() {
    let (disks, q, u) = column(10, true);
    let pgs = SolverChoice::Pgs { tolerance: 1e-12, omega: 1.0, max_iterations: 2 };
    let opts = StepperOptions::new(1e-3).with_solver(pgs).with_gap_tolerance(1e-9);
    let mut s = Stepper::new(disks, &q, &u, 0.0, opts).unwrap();
    let e = s.step().unwrap_err();
    let StepError::IslandFailed { step, status, problem, .. } = e else { panic!("{e}") };
    assert_eq!((step, status), (0, moreau_lcp::Status::IterationLimit));
    // The column's ten contacts, q = b: the floor's approached at g Δt, the others at rest
    // relative to each other (every disk falls alike without impulses).
    assert_eq!(problem.n_contacts(), 10);
    let q = problem.q();
    assert!((q[0] + G * 1e-3).abs() < 1e-15, "{q:?}");
    assert!(q[1..].iter().all(|b| b.abs() < 1e-15), "{q:?}");
}

#[test]
fn one_large_island_is_bit_identical_on_one_and_two_threads() {
    // A square-packed pile of 2,100 disks in rows of 20 between walls: one island of about
    // 4,200 contacts, whose per-contact work, block rows, residual, reports and per-body
    // impulses run in chunks on two threads.
    let (n, r, width) = (2100, 0.1, 20);
    let centres: Vec<_> = (0..n)
        .map(|k| (r + 2.0 * r * (k % width) as f64, r + 2.0 * r * (k / width) as f64))
        .collect();
    let (q, u) = Disks::state_at(&centres);
    let trajectory = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let disks = Disks::new(vec![1.0; n], vec![r; n], law(0.0, 0.3), true)
                .with_walls(0.0, 2.0 * r * width as f64);
            let opts = StepperOptions::new(1e-3).with_gap_tolerance(1e-9);
            let mut s = Stepper::new(disks, &q, &u, 0.0, opts).unwrap();
            let (mut contacts, mut islands, mut impulses) = (0, 0, Vec::new());
            let mut reports = String::new();
            for _ in 0..3 {
                let r = s.step().unwrap_or_else(|e| panic!("{e}"));
                contacts = r.contacts.len();
                islands = r.islands;
                impulses = r.contacts.iter().map(|c| [c.p_n, c.p_t]).collect();
                // Debug prints each number's shortest round-trip form: equal texts are equal
                // bits.
                reports = format!("{:?} {:?}", r.contacts, r.lcp);
            }
            assert!(contacts > 4100 && islands == 1, "{contacts} contacts, {islands} islands");
            assert!(impulses.iter().any(|p: &[f64; 2]| p[0] > 0.0), "no contact carries a load");
            (s.q().to_vec(), s.u().to_vec(), impulses, reports)
        })
    };
    let (one, two) = (trajectory(1), trajectory(2));
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&one.0), bits(&two.0), "q differs");
    assert_eq!(bits(&one.1), bits(&two.1), "u differs");
    let flat = |v: &[[f64; 2]]| v.iter().flatten().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(flat(&one.2), flat(&two.2), "the impulses differ");
    assert!(one.3 == two.3, "the reports differ");
}
