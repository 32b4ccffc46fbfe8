//! Steps with many closed contacts: the default solver hands them to the planar
//! frictional-contact solvers instead of the dense LCP, and must give what the dense LCP
//! gives.

use moreau_stepper::prelude::*;

const G: f64 = 9.81;

/// A column of n disks (radius r, mass m, no rotation) standing on the floor, q = (x_0, y_0,
/// x_1, y_1, ...): contact 0 is disk 0 on the floor, contact i disk i on disk i − 1, each with
/// friction along x.
struct Column {
    n: usize,
    r: f64,
    m: f64,
    laws: Vec<ContactLaw>,
}

impl ContactKinematics for Column {
    fn num_coordinates(&self) -> usize {
        2 * self.n
    }
    fn num_contacts(&self) -> usize {
        self.n
    }
    fn normal_gap(&self, i: usize, q: &[f64], _t: f64) -> f64 {
        if i == 0 { q[1] - self.r } else { q[2 * i + 1] - q[2 * i - 1] - 2.0 * self.r }
    }
    fn contact(
        &self,
        i: usize,
        q: &[f64],
        t: f64,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) -> ContactPoint {
        w_n.fill(0.0);
        w_t.fill(0.0);
        w_n[2 * i + 1] = 1.0;
        w_t[2 * i] = 1.0;
        if i > 0 {
            w_n[2 * i - 1] = -1.0;
            w_t[2 * i - 2] = -1.0;
        }
        let g_t = if i == 0 { q[0] } else { q[2 * i] - q[2 * i - 2] };
        ContactPoint { g_n: self.normal_gap(i, q, t), g_t, ..ContactPoint::default() }
    }
}

impl Mechanism for Column {
    fn laws(&self) -> &[ContactLaw] {
        &self.laws
    }
    fn mass_matrix(&self, _q: &[f64], _t: f64, m: &mut [f64]) {
        let f = 2 * self.n;
        m.fill(0.0);
        for k in 0..f {
            m[k + k * f] = self.m;
        }
    }
    fn forces(&self, _q: &[f64], _u: &[f64], _t: f64, h: &mut [f64]) {
        for (k, h) in h.iter_mut().enumerate() {
            *h = if k % 2 == 1 { -self.m * G } else { 0.0 };
        }
    }
    fn constant_mass_matrix(&self) -> bool {
        true
    }
}

fn run(n: usize, steps: usize, solver: SolverChoice) -> (Vec<f64>, Vec<f64>, usize) {
    let column =
        Column { n, r: 0.1, m: 0.5, laws: vec![ContactLaw::new(0.0, 0.0, 0.3).unwrap(); n] };
    // Stacked 1 mm apart, sliding sideways in alternating directions.
    let q0: Vec<f64> = (0..n).flat_map(|i| [0.0, 0.1 + 0.201 * i as f64]).collect();
    let u0: Vec<f64> = (0..n).flat_map(|i| [if i % 2 == 0 { 0.5 } else { -0.5 }, 0.0]).collect();
    let options = StepperOptions::new(1e-3).with_solver(solver).with_gap_tolerance(1e-12);
    let mut stepper = Stepper::new(column, &q0, &u0, 0.0, options).unwrap();
    let mut most = 0;
    for _ in 0..steps {
        let report = stepper.step().unwrap();
        most = most.max(report.contacts.iter().filter(|c| c.active).count());
        if let Some(lcp) = report.lcp {
            assert!(lcp.residual <= 1e-8, "t = {}: residual {}", report.t, lcp.residual);
        }
    }
    (stepper.q().to_vec(), stepper.u().to_vec(), most)
}

#[test]
fn a_column_of_twenty_six_sliding_disks_steps_alike_through_both_routes() {
    let (q_auto, u_auto, most) = run(26, 100, SolverChoice::Auto);
    let (q_lemke, u_lemke, _) = run(26, 100, SolverChoice::Lemke);
    // The whole column comes to rest on the floor: every contact closes, well past the
    // size at which the default solver leaves the dense LCP.
    assert_eq!(most, 26);
    for (a, b) in q_auto.iter().zip(&q_lemke).chain(u_auto.iter().zip(&u_lemke)) {
        assert!((a - b).abs() < 1e-7, "{a} against {b}");
    }
    // The column has settled onto the floor, each disk on the one below, 2 r apart up to the
    // scheme's O(Δt) penetration of the first impacts (no projection here), and
    // friction has slowed the sliding: the top disk, held by one contact of normal force m g,
    // by μ g t = 0.29 m/s at most.
    for i in 1..q_auto.len() / 2 {
        let gap = q_auto[2 * i + 1] - q_auto[2 * i - 1] - 0.2;
        assert!(gap.abs() < 1e-3, "gap {i}: {gap}");
    }
    let top = u_auto[u_auto.len() - 2].abs();
    assert!(top < 0.5 - 0.25 * 0.3 * G * 0.1, "top disk at {top}");
}
