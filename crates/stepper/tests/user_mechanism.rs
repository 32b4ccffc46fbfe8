//! A mechanism derived by hand as a user of the crate would: a rigid rod whose two ends can
//! touch the floor, checked against closed forms, with the gap tolerance's default and the
//! errors a wrong implementation gets.

use moreau_stepper::StepError;
use moreau_stepper::prelude::*;

const G: f64 = 9.81;

/// A rod of mass m and length L, q = (x, y, θ) of its centre; end k (k = 0, 1) at
/// (x ± a cos θ, y ± a sin θ), a = L/2, touches the floor y = 0.
#[derive(Clone)]
struct Rod {
    m: f64,
    l: f64,
    /// A horizontal force on the centre (N).
    push: f64,
    laws: [ContactLaw; 2],
    /// What the mechanism gets wrong, for the error tests.
    fault: Fault,
}

#[derive(Clone, Copy, PartialEq)]
enum Fault {
    None,
    RheonomicNan,
    TinyInertia,
    /// M couples x and θ so that its θ column is 3 times its x column: singular, with a
    /// Cholesky pivot that round-off leaves at 1.1e-16 instead of 0.
    SingularMass,
    /// `contact` writes only the first two entries of end 1's w_T.
    UnwrittenWt,
    /// `contact` writes only the first two entries of end 1's w_N.
    UnwrittenWn,
}

impl Rod {
    fn new(law: ContactLaw) -> Self {
        Rod { m: 1.0, l: 1.0, push: 0.0, laws: [law, law], fault: Fault::None }
    }
    fn side(i: usize) -> f64 {
        if i == 0 { 1.0 } else { -1.0 }
    }
    fn inertia(&self) -> f64 {
        if self.fault == Fault::TinyInertia { 1e-300 } else { self.m * self.l * self.l / 12.0 }
    }
}

impl ContactKinematics for Rod {
    fn num_coordinates(&self) -> usize {
        3
    }
    fn num_contacts(&self) -> usize {
        2
    }
    fn normal_gap(&self, i: usize, q: &[f64], _t: f64) -> f64 {
        q[1] + Self::side(i) * 0.5 * self.l * q[2].sin()
    }
    fn contact(
        &self,
        i: usize,
        q: &[f64],
        t: f64,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) -> ContactPoint {
        let a = Self::side(i) * 0.5 * self.l;
        let (s, c) = q[2].sin_cos();
        let (w_n, w_t) = match (self.fault, i) {
            (Fault::UnwrittenWn, 1) => (&mut w_n[..2], w_t),
            (Fault::UnwrittenWt, 1) => (w_n, &mut w_t[..2]),
            _ => (w_n, w_t),
        };
        let k = w_n.len();
        w_n.copy_from_slice(&[0.0, 1.0, a * c][..k]);
        let k = w_t.len();
        w_t.copy_from_slice(&[1.0, 0.0, -a * s][..k]);
        let w_n_hat = if self.fault == Fault::RheonomicNan && i == 1 { f64::NAN } else { 0.0 };
        ContactPoint { g_n: self.normal_gap(i, q, t), g_t: q[0] + a * c, w_n_hat, w_t_hat: 0.0 }
    }
}

impl Mechanism for Rod {
    fn laws(&self) -> &[ContactLaw] {
        &self.laws
    }
    fn mass_matrix(&self, _q: &[f64], _t: f64, m: &mut [f64]) {
        m.fill(0.0);
        m[0] = self.m;
        m[4] = self.m;
        m[8] = self.inertia();
        if self.fault == Fault::SingularMass {
            (m[0], m[2], m[6], m[8]) = (0.1, 0.3, 0.3, 0.9);
        }
    }
    fn forces(&self, _q: &[f64], _u: &[f64], _t: f64, h: &mut [f64]) {
        h.copy_from_slice(&[self.push, -self.m * G, 0.0]);
    }
    fn potential_energy(&self, q: &[f64], _t: f64) -> Option<f64> {
        Some(self.m * G * q[1])
    }
    fn constant_mass_matrix(&self) -> bool {
        true
    }
}

fn options(dt: f64) -> StepperOptions {
    StepperOptions::new(dt).with_gap_tolerance(1e-12)
}

#[test]
fn a_tilted_rod_bouncing_without_friction_at_eps_one_keeps_its_energy() {
    // Lower end 0.5 m above the floor, θ = −0.3: it lands at v = sqrt(2 g 0.5) and, with
    // ε_N = 1 on one end, leaves with P_N = 2 v m_eff, 1/m_eff = 1/m + (a cos θ)²/J.
    let (th, a, dt) = (0.3f64, 0.5, 1e-4);
    let mut s = Stepper::new(
        Rod::new(ContactLaw::frictionless(1.0).unwrap()),
        &[0.0, a * th.sin() + 0.5, -th],
        &[0.0; 3],
        0.0,
        options(dt),
    )
    .unwrap();
    let record = s.record_until(3.0).unwrap();
    assert!(record.impacts.len() >= 10, "{} impacts", record.impacts.len());
    let e = record.total_energy();
    let spread = e.iter().map(|x| (x - e[0]).abs()).fold(0.0, f64::max);
    assert!(spread < 1e-12 * e[0], "energy spread {spread:e} of {}", e[0]);
    let first = &record.impacts[0];
    let v = (2.0 * G * 0.5f64).sqrt();
    let arm = a * th.cos();
    let m_eff = 1.0 / (1.0 + arm * arm * 12.0);
    // Within a step's gravity g Δt of the closed form.
    assert!((first.gamma_n_before + v).abs() < 2.0 * G * dt, "{}", first.gamma_n_before);
    assert!((first.gamma_n_after + first.gamma_n_before).abs() < 1e-12);
    assert!((first.p_n - 2.0 * v * m_eff).abs() < 4.0 * G * dt * m_eff, "{}", first.p_n);
}

#[test]
fn a_flat_rod_sliding_stops_where_coulomb_says() {
    // v0 = 2 m/s, μ = 0.3: it stops at v0 / (μ g) after v0² / (2 μ g).
    let (mu, v0, dt) = (0.3, 2.0, 1e-3);
    let law = ContactLaw::new(0.0, 0.0, mu).unwrap();
    let mut s = Stepper::new(Rod::new(law), &[0.0; 3], &[v0, 0.0, 0.0], 0.0, options(dt)).unwrap();
    let record = s.record_until(1.0).unwrap();
    let stop = record.u.iter().position(|u| u[0].abs() < 1e-12).unwrap();
    assert!((record.t[stop] - v0 / (mu * G)).abs() < 2.0 * dt, "{}", record.t[stop]);
    let x = record.q[record.len() - 1][0];
    assert!((x - v0 * v0 / (2.0 * mu * G)).abs() < 1e-3, "{x}");
    assert!(record.impacts.is_empty());
}

#[test]
fn a_pushed_rod_sticks_below_mu_m_g_and_slides_above() {
    let mu = 0.3;
    for frac in [0.9, 1.1] {
        let mut rod = Rod::new(ContactLaw::new(0.0, 0.0, mu).unwrap());
        rod.push = frac * mu * G;
        let mut s = Stepper::new(rod, &[0.0; 3], &[0.0; 3], 0.0, options(1e-3)).unwrap();
        s.run_until(1.0, &mut ()).unwrap();
        let acc = if frac > 1.0 { (frac - 1.0) * mu * G } else { 0.0 };
        assert!((s.u()[0] - acc).abs() < 1e-12, "{frac}: {}", s.u()[0]);
        assert!((s.q()[0] - 0.5 * acc).abs() < 1e-9, "{frac}: {}", s.q()[0]);
    }
}

#[test]
fn without_a_gap_tolerance_a_rod_started_on_the_floor_falls_through_one_step() {
    // The default threshold of 0: the first step closes both ends, round-off leaves their next
    // midpoint gaps above zero, the rod falls freely for a step and lands with impacts at
    // γ_N,A = −g Δt, resting g Δt² deep; held by friction below μ m g, it slips F Δt² / m.
    let dt = 1e-3;
    let run = |gap_tolerance: f64| {
        let mut rod = Rod::new(ContactLaw::new(0.0, 0.0, 0.3).unwrap());
        rod.push = 0.9 * 0.3 * G;
        let o = StepperOptions::new(dt).with_gap_tolerance(gap_tolerance);
        let mut s = Stepper::new(rod, &[0.0; 3], &[0.0; 3], 0.0, o).unwrap();
        let record = s.record_until(0.1).unwrap();
        let n = record.len() - 1;
        (record.impacts, record.q[n][0], record.q[n][1])
    };
    let (impacts, x, y) = run(0.0);
    assert_eq!(impacts.len(), 2);
    assert!(impacts.iter().all(|i| (i.gamma_n_before + G * dt).abs() < 1e-12));
    assert!((y + G * dt * dt).abs() < 1e-12, "{y}");
    assert!((x - 0.9 * 0.3 * G * dt * dt).abs() < 1e-12, "{x}");
    let (impacts, x, y) = run(1e-12);
    assert!(impacts.is_empty());
    assert!(x.abs() < 1e-15 && y.abs() < 1e-15, "{x} {y}");
}

#[test]
fn a_non_finite_rheonomic_term_is_named_as_such() {
    let mut rod = Rod::new(ContactLaw::new(0.5, 0.0, 0.3).unwrap());
    rod.fault = Fault::RheonomicNan;
    let mut s = Stepper::new(rod, &[0.0; 3], &[0.0; 3], 0.0, options(1e-3)).unwrap();
    let e = s.step().unwrap_err();
    // Found in what was evaluated at the first step's midpoint, t_M = Δt / 2, as M, h and g_N
    // are reported.
    assert!(matches!(e, StepError::NonFinite { index: 1, t: 5e-4, .. }), "{e:?}");
    assert!(e.to_string().contains("ŵ_N/ŵ_T of contact at index 1 (t = 0.0005)"), "{e}");
    // End 1 alone on the floor and frictionless takes the closed form, and is named alike.
    let mut rod = Rod::new(ContactLaw::frictionless(0.5).unwrap());
    rod.fault = Fault::RheonomicNan;
    let mut s =
        Stepper::new(rod, &[0.0, 0.5 * 0.1f64.sin(), 0.1], &[0.0; 3], 0.0, options(1e-3)).unwrap();
    let e = s.step().unwrap_err();
    assert!(e.to_string().contains("ŵ_N/ŵ_T of contact at index 1"), "{e}");
}

#[test]
fn a_problem_beyond_the_solvers_range_names_the_step_and_the_mass_matrix() {
    // Resting on both ends with J = 1e-300: W_Nᵀ M⁻¹ W_N holds (a cos θ)² / J = 2.5e299.
    let mut rod = Rod::new(ContactLaw::new(0.5, 0.0, 0.3).unwrap());
    rod.fault = Fault::TinyInertia;
    let mut s = Stepper::new(rod, &[0.0; 3], &[0.0; 3], 0.5, options(1e-3)).unwrap();
    let e = s.step().unwrap_err();
    match &e {
        StepError::ProblemOutOfRange { step, t, value, .. } => {
            assert_eq!((*step, *t), (0, 0.5));
            assert!(*value > 1e150, "{value:e}");
        }
        other => panic!("{other:?}"),
    }
    assert!(e.to_string().contains("M(q, t) is nearly singular"), "{e}");
    assert!(std::error::Error::source(&e).is_some());
    assert_eq!(s.t(), 0.5);
}

/// A point of mass 1 on a vertical line, q = (y), that says it holds rigid bodies in maximal
/// coordinates (x, y, θ per body), which one coordinate cannot.
struct Slider {
    laws: [ContactLaw; 1],
}

impl ContactKinematics for Slider {
    fn num_coordinates(&self) -> usize {
        1
    }
    fn num_contacts(&self) -> usize {
        1
    }
    fn normal_gap(&self, _i: usize, q: &[f64], _t: f64) -> f64 {
        q[0]
    }
    fn contact(
        &self,
        i: usize,
        q: &[f64],
        t: f64,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) -> ContactPoint {
        (w_n[0], w_t[0]) = (1.0, 0.0);
        ContactPoint { g_n: self.normal_gap(i, q, t), ..ContactPoint::default() }
    }
}

impl Mechanism for Slider {
    fn laws(&self) -> &[ContactLaw] {
        &self.laws
    }
    fn mass_matrix(&self, _q: &[f64], _t: f64, m: &mut [f64]) {
        m[0] = 1.0;
    }
    fn forces(&self, _q: &[f64], _u: &[f64], _t: f64, h: &mut [f64]) {
        h[0] = -G;
    }
    fn maximal_coordinates(&self) -> bool {
        true
    }
}

#[test]
fn maximal_coordinates_need_three_coordinates_per_body() {
    let slider = Slider { laws: [ContactLaw::frictionless(0.0).unwrap()] };
    let e =
        Stepper::new(slider, &[0.1], &[0.0], 0.0, options(1e-3).with_projection(true)).unwrap_err();
    assert!(matches!(e, StepError::Dimension { expected: 3, found: 1, .. }), "{e:?}");
    assert!(e.to_string().contains("maximal_coordinates"), "{e}");
}

#[test]
fn a_singular_mass_matrix_is_refused_though_round_off_leaves_its_pivot_positive() {
    // Column θ of M is 3 times column x, and the elimination leaves 0.9 − (0.3/√0.1)² =
    // 1.1e-16: a factor of M that amplifies round-off by 1e16. Without the refusal the rod
    // pushed at 1 m/s flew off to 1.8e11 m within 2 s.
    let mut rod = Rod::new(ContactLaw::new(0.5, 0.0, 0.3).unwrap());
    rod.fault = Fault::SingularMass;
    let mut s = Stepper::new(rod, &[0.0, 0.05, 0.0], &[1.0, 0.0, 0.0], 0.0, options(1e-3)).unwrap();
    let e = s.step().unwrap_err();
    match &e {
        StepError::MassNotSpd { t, reason } => {
            assert_eq!(*t, 5e-4);
            assert!(reason.contains("singular") && reason.contains("column 2"), "{reason}");
            assert!(reason.contains("1.2e-16"), "{reason}");
        }
        other => panic!("{other:?}"),
    }
    assert_eq!((s.t(), s.steps(), s.q()), (0.0, 0, &[0.0, 0.05, 0.0][..]));
}

#[test]
fn a_force_direction_entry_left_unwritten_is_named_by_contact_and_entry() {
    // Both ends resting (the general LCP), and end 1 alone touching and frictionless (the
    // closed form of one contact): an entry that `contact` did not write stops the step, where
    // it would have kept the value another contact left in the reused buffer.
    let rest = [0.0; 3];
    let tilted = [0.0, 0.5 * 0.1f64.sin(), 0.1];
    for (fault, law, q0, what) in [
        (Fault::UnwrittenWt, ContactLaw::new(0.0, 0.0, 0.3).unwrap(), rest, "w_T"),
        (Fault::UnwrittenWn, ContactLaw::new(0.0, 0.0, 0.3).unwrap(), rest, "w_N"),
        (Fault::UnwrittenWn, ContactLaw::frictionless(0.5).unwrap(), tilted, "w_N"),
    ] {
        let mut rod = Rod::new(law);
        rod.fault = fault;
        let mut s = Stepper::new(rod, &q0, &[0.0; 3], 0.0, options(1e-3)).unwrap();
        let e = s.step().unwrap_err();
        match &e {
            StepError::Unwritten { what: w, contact, entry, t } => {
                assert_eq!((*w, *contact, *entry, *t), (what, 1, 2, 5e-4), "{e}");
            }
            other => panic!("{what}: {other:?}"),
        }
        let text = e.to_string();
        assert!(text.contains(&format!("{what}[2] of contact 1")), "{text}");
        assert_eq!((s.t(), s.q()), (0.0, &q0[..]));
    }
}

/// Nine coupled coordinates without contacts, M tridiagonal (2 on the diagonal, 0.5 beside
/// it), pushed by a force of 1 N on coordinate 0 alone; `forces` writes that entry only, or
/// every entry.
struct Chain {
    write_all: bool,
}

impl ContactKinematics for Chain {
    fn num_coordinates(&self) -> usize {
        9
    }
    fn num_contacts(&self) -> usize {
        0
    }
    fn normal_gap(&self, _i: usize, _q: &[f64], _t: f64) -> f64 {
        unreachable!("no contacts")
    }
    fn contact(&self, _: usize, _: &[f64], _: f64, _: &mut [f64], _: &mut [f64]) -> ContactPoint {
        unreachable!("no contacts")
    }
}

impl Mechanism for Chain {
    fn laws(&self) -> &[ContactLaw] {
        &[]
    }
    fn mass_matrix(&self, _q: &[f64], _t: f64, m: &mut [f64]) {
        m.fill(0.0);
        for j in 0..9 {
            m[j + 9 * j] = 2.0;
            if j > 0 {
                (m[j + 9 * (j - 1)], m[j - 1 + 9 * j]) = (0.5, 0.5);
            }
        }
    }
    fn forces(&self, _q: &[f64], _u: &[f64], _t: f64, h: &mut [f64]) {
        if self.write_all {
            h.fill(0.0);
        }
        h[0] = 1.0;
    }
}

#[test]
fn forces_arrive_zeroed_so_that_a_mechanism_writes_only_its_non_zero_entries() {
    // Under a constant force and a constant M the midpoint rule is exact: u(t) = t M⁻¹ h.
    // M⁻¹ e_0 by the tridiagonal elimination (Thomas' algorithm).
    let (n, dt, steps) = (9, 1e-3, 1000);
    let (mut c, mut d) = (vec![0.0; n], vec![0.0; n]);
    (c[0], d[0]) = (0.25, 0.5);
    for j in 1..n {
        let den = 2.0 - 0.5 * c[j - 1];
        c[j] = 0.5 / den;
        d[j] = -0.5 * d[j - 1] / den;
    }
    let mut x = d.clone();
    for j in (0..n - 1).rev() {
        x[j] = d[j] - c[j] * x[j + 1];
    }
    let run = |write_all: bool| {
        let mut s =
            Stepper::new(Chain { write_all }, &[0.0; 9], &[0.0; 9], 0.0, options(dt)).unwrap();
        for _ in 0..steps {
            s.step().unwrap();
        }
        s.u().to_vec()
    };
    let (some, all) = (run(false), run(true));
    assert_eq!(some, all);
    let t = dt * steps as f64;
    for j in 0..n {
        assert!((some[j] - t * x[j]).abs() < 1e-14, "u[{j}] = {} against {}", some[j], t * x[j]);
    }
    // M⁻¹ e_0 alternates in sign along the chain, shrinking by about 2 − √3 per coordinate:
    // x_0 = 0.5359, x_1 = −0.1436, x_8 = 1.32e-5.
    let expected = [(0, 0.5359), (1, -0.1436), (8, 1.3217e-5)];
    for (j, v) in expected {
        assert!((x[j] - v).abs() < 1e-4 * v.abs(), "x[{j}] = {}", x[j]);
    }
}
