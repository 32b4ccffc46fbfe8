//! Bilateral constraints in the step: closed forms, a cross-check between the maximal and the
//! minimal coordinates of one pendulum, a driven constraint with a frictional impact, the
//! projection of the drift, and the errors of constraints that cannot be solved.

use moreau_kinematics::{ContactKinematics, ContactPoint};
use moreau_setvalued::ContactLaw;
use moreau_stepper::{BilateralPoint, Mechanism, StepError, Stepper, StepperOptions};

const G: f64 = 9.81;

/// The kinematics of a test mechanism with `f` coordinates and no contacts.
macro_rules! contactless {
    ($t:ty, $f:expr) => {
        impl ContactKinematics for $t {
            fn num_coordinates(&self) -> usize {
                $f
            }
            fn num_contacts(&self) -> usize {
                0
            }
            fn normal_gap(&self, _i: usize, _q: &[f64], _t: f64) -> f64 {
                unreachable!("no contacts")
            }
            fn contact(
                &self,
                _: usize,
                _: &[f64],
                _: f64,
                _: &mut [f64],
                _: &mut [f64],
            ) -> ContactPoint {
                unreachable!("no contacts")
            }
        }
    };
}

/// A block of mass m on a frictionless line through the origin at angle α below the
/// horizontal, written in (x, y) with the bilateral constraint x sin α + y cos α = 0.
struct BlockOnLine {
    m: f64,
    alpha: f64,
}

contactless!(BlockOnLine, 2);

impl Mechanism for BlockOnLine {
    fn laws(&self) -> &[ContactLaw] {
        &[]
    }
    fn mass_matrix(&self, _q: &[f64], _t: f64, m: &mut [f64]) {
        m.copy_from_slice(&[self.m, 0.0, 0.0, self.m]);
    }
    fn forces(&self, _q: &[f64], _u: &[f64], _t: f64, h: &mut [f64]) {
        h.copy_from_slice(&[0.0, -self.m * G]);
    }
    fn constant_mass_matrix(&self) -> bool {
        true
    }
    fn num_bilaterals(&self) -> usize {
        1
    }
    fn bilateral(&self, _i: usize, q: &[f64], _t: f64, w: &mut [f64]) -> BilateralPoint {
        let (s, c) = self.alpha.sin_cos();
        w.copy_from_slice(&[s, c]);
        BilateralPoint { g: q[0] * s + q[1] * c, w_hat: 0.0 }
    }
}

#[test]
fn a_block_on_a_frictionless_line_accelerates_at_g_sin_alpha() {
    let alpha = 0.4f64;
    let mut stepper = Stepper::new(
        BlockOnLine { m: 2.0, alpha },
        &[0.0; 2],
        &[0.0; 2],
        0.0,
        StepperOptions::new(1e-3),
    )
    .unwrap();
    let record = stepper.record_until(1.0).unwrap();
    let last = record.t.len() - 1;
    let (t, u) = (record.t[last], &record.u[last]);
    // The constant forces make the midpoint rule exact: s = g sin α t along the line.
    let speed = (u[0] * u[0] + u[1] * u[1]).sqrt();
    assert!((speed - G * alpha.sin() * t).abs() < 1e-12, "{speed}");
    let (s, c) = alpha.sin_cos();
    assert!((u[0] * s + u[1] * c).abs() < 1e-14, "velocity off the line: {u:?}");
    let q = &record.q[last];
    let travelled = (q[0] * q[0] + q[1] * q[1]).sqrt();
    assert!((travelled - 0.5 * G * s * t * t).abs() < 1e-12, "{travelled}");
}

/// A slender rod of mass m and length l hanging from a pin at its end, in maximal
/// coordinates (x, y, φ) of its centre with two bilateral constraints (the pin), or in the
/// minimal coordinate φ alone.
struct Pendulum {
    m: f64,
    l: f64,
}

impl Pendulum {
    fn inertia(&self) -> f64 {
        self.m * self.l * self.l / 12.0
    }
}

contactless!(Pendulum, 3);

impl Mechanism for Pendulum {
    fn laws(&self) -> &[ContactLaw] {
        &[]
    }
    fn mass_matrix(&self, _q: &[f64], _t: f64, m: &mut [f64]) {
        m.fill(0.0);
        m[0] = self.m;
        m[4] = self.m;
        m[8] = self.inertia();
    }
    fn forces(&self, _q: &[f64], _u: &[f64], _t: f64, h: &mut [f64]) {
        h.copy_from_slice(&[0.0, -self.m * G, 0.0]);
    }
    fn potential_energy(&self, q: &[f64], _t: f64) -> Option<f64> {
        Some(self.m * G * q[1])
    }
    fn constant_mass_matrix(&self) -> bool {
        true
    }
    fn num_bilaterals(&self) -> usize {
        2
    }
    /// The rod's end (x, y) − (l/2)(sin φ, −cos φ) stays at the origin.
    fn bilateral(&self, i: usize, q: &[f64], _t: f64, w: &mut [f64]) -> BilateralPoint {
        let (s, c) = q[2].sin_cos();
        let h = 0.5 * self.l;
        if i == 0 {
            w.copy_from_slice(&[1.0, 0.0, -h * c]);
            BilateralPoint { g: q[0] - h * s, w_hat: 0.0 }
        } else {
            w.copy_from_slice(&[0.0, 1.0, -h * s]);
            BilateralPoint { g: q[1] + h * c, w_hat: 0.0 }
        }
    }
}

/// The same rod in its minimal coordinate φ: (m l²/3) φ̈ = −m g (l/2) sin φ.
struct MinimalPendulum {
    m: f64,
    l: f64,
}

contactless!(MinimalPendulum, 1);

impl Mechanism for MinimalPendulum {
    fn laws(&self) -> &[ContactLaw] {
        &[]
    }
    fn mass_matrix(&self, _q: &[f64], _t: f64, m: &mut [f64]) {
        m[0] = self.m * self.l * self.l / 3.0;
    }
    fn forces(&self, q: &[f64], _u: &[f64], _t: f64, h: &mut [f64]) {
        h[0] = -self.m * G * 0.5 * self.l * q[0].sin();
    }
    fn constant_mass_matrix(&self) -> bool {
        true
    }
}

fn pendulum_start(phi: f64, l: f64) -> [f64; 3] {
    [0.5 * l * phi.sin(), -0.5 * l * phi.cos(), phi]
}

/// Runs the rod both ways for two seconds (about 1.7 periods) with step `dt`: the largest
/// difference of the angles, the largest joint drift at the midpoints, and the largest
/// energy error of the maximal form.
fn pendulum_pair(dt: f64) -> (f64, f64, f64) {
    let (m, l, phi0) = (1.5, 0.8, 1.0);
    let options = StepperOptions::new(dt).with_projection(true);
    let mut maximal =
        Stepper::new(Pendulum { m, l }, &pendulum_start(phi0, l), &[0.0; 3], 0.0, options).unwrap();
    let mut minimal =
        Stepper::new(MinimalPendulum { m, l }, &[phi0], &[0.0], 0.0, StepperOptions::new(dt))
            .unwrap();
    let energy = |q: &[f64], u: &[f64]| {
        0.5 * m * (u[0] * u[0] + u[1] * u[1])
            + 0.5 * (m * l * l / 12.0) * u[2] * u[2]
            + m * G * q[1]
    };
    let e0 = energy(&pendulum_start(phi0, l), &[0.0; 3]);
    let (mut worst_phi, mut worst_drift, mut worst_energy) = (0.0f64, 0.0f64, 0.0f64);
    let steps = (2.0 / dt).round() as usize;
    for _ in 0..steps {
        let report = maximal.step().unwrap();
        worst_drift = worst_drift.max(report.joint_drift);
        let (q, u) = (report.q.to_vec(), report.u.to_vec());
        let phi = minimal.step().unwrap().q[0];
        worst_phi = worst_phi.max((q[2] - phi).abs());
        worst_energy = worst_energy.max((energy(&q, &u) - e0).abs() / e0.abs());
    }
    let q = maximal.q();
    let pin = [q[0] - 0.5 * l * q[2].sin(), q[1] + 0.5 * l * q[2].cos()];
    assert!(pin[0].abs() < 1e-12 && pin[1].abs() < 1e-12, "pin left the origin: {pin:?}");
    (worst_phi, worst_drift, worst_energy)
}

#[test]
fn a_pinned_rod_in_maximal_coordinates_converges_to_the_rod_in_its_angle() {
    let (phi_coarse, drift_coarse, energy_coarse) = pendulum_pair(2e-4);
    let (phi_fine, drift_fine, energy_fine) = pendulum_pair(1e-4);
    // Both are second-order discretisations of the same motion: halving Δt quarters the
    // difference of the angles.
    let ratio = phi_coarse / phi_fine;
    assert!(phi_fine < 1e-3 && (3.5..4.5).contains(&ratio), "{phi_coarse} {phi_fine}");
    // The projection keeps the end positions on the pin; the midpoints leave it by O(Δt²).
    assert!(drift_fine < 1e-7 && drift_coarse < 4e-7, "drift {drift_coarse} {drift_fine}");
    // The ideal pin does no work: the energy error is the scheme's, second order in Δt.
    let ratio = energy_coarse / energy_fine;
    assert!(energy_fine < 1e-8 && (3.5..4.5).contains(&ratio), "{energy_coarse:e} {energy_fine:e}");
}

#[test]
fn a_start_that_violates_the_pin_loses_the_energy_of_the_violation_and_no_more() {
    // The rod hangs (φ = 0) and its centre is pushed sideways at 1 m/s, which the pin does not
    // admit. The nearest velocity that keeps the pin in the kinetic metric has v_x = l ω / 2
    // and m (v_x − 1) + (I / (l / 2)) ω = 0: v_x = 3/4 m/s, ω = 3 / (2 l), a kinetic energy of
    // 3 m / 8 from m / 2. The first step takes it there; later steps keep the energy, since
    // the pin's impulses do no work once it is kept.
    let (m, l, dt) = (1.5, 0.8, 1e-4);
    let options = StepperOptions::new(dt).with_projection(true);
    let pendulum = Pendulum { m, l };
    let mut stepper =
        Stepper::new(pendulum, &pendulum_start(0.0, l), &[1.0, 0.0, 0.0], 0.0, options).unwrap();
    let energy = |s: &Stepper<Pendulum>| {
        let (q, u) = (s.q(), s.u());
        0.5 * m * (u[0] * u[0] + u[1] * u[1])
            + 0.5 * (m * l * l / 12.0) * u[2] * u[2]
            + m * G * q[1]
    };
    let e0 = energy(&stepper);
    stepper.step().unwrap();
    let e1 = energy(&stepper);
    assert!((e0 - e1 - m / 8.0).abs() < 1e-6 * m, "lost {} of {}", e0 - e1, m / 8.0);
    let mut worst = 0.0f64;
    while stepper.t() < 1.0 {
        stepper.step().unwrap();
        worst = worst.max((energy(&stepper) - e1).abs());
    }
    // What is left is the scheme's O(Δt²) oscillation (5.1e-8 m J at Δt = 1e-4 s).
    assert!(worst < 1e-6 * m, "{worst:e}");
}

/// A ball (x, y) whose x is driven, x = v t (a rheonomic bilateral constraint with
/// ŵ_B = −v), falling onto a floor with friction.
struct DrivenBall {
    v: f64,
    laws: [ContactLaw; 1],
}

impl ContactKinematics for DrivenBall {
    fn num_coordinates(&self) -> usize {
        2
    }
    fn num_contacts(&self) -> usize {
        1
    }
    fn normal_gap(&self, _i: usize, q: &[f64], _t: f64) -> f64 {
        q[1] - 0.1
    }
    fn contact(
        &self,
        i: usize,
        q: &[f64],
        t: f64,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) -> ContactPoint {
        w_n.copy_from_slice(&[0.0, 1.0]);
        w_t.copy_from_slice(&[1.0, 0.0]);
        ContactPoint { g_n: self.normal_gap(i, q, t), g_t: q[0], ..ContactPoint::default() }
    }
}

impl Mechanism for DrivenBall {
    fn laws(&self) -> &[ContactLaw] {
        &self.laws
    }
    fn mass_matrix(&self, _q: &[f64], _t: f64, m: &mut [f64]) {
        m.copy_from_slice(&[1.0, 0.0, 0.0, 1.0]);
    }
    fn forces(&self, _q: &[f64], _u: &[f64], _t: f64, h: &mut [f64]) {
        h.copy_from_slice(&[0.0, -G]);
    }
    fn constant_mass_matrix(&self) -> bool {
        true
    }
    fn num_bilaterals(&self) -> usize {
        1
    }
    fn bilateral(&self, _i: usize, q: &[f64], t: f64, w: &mut [f64]) -> BilateralPoint {
        w.copy_from_slice(&[1.0, 0.0]);
        BilateralPoint { g: q[0] - self.v * t, w_hat: -self.v }
    }
}

#[test]
fn a_driven_coordinate_keeps_its_speed_through_a_frictional_impact() {
    let (v, eps, mu) = (0.7, 0.5, 0.8);
    let ball = DrivenBall { v, laws: [ContactLaw::new(eps, 0.0, mu).unwrap()] };
    let mut stepper =
        Stepper::new(ball, &[0.0, 1.0], &[v, 0.0], 0.0, StepperOptions::new(1e-4)).unwrap();
    let record = stepper.record_until(0.6).unwrap();
    let first = record.p_n.iter().position(|p| p[0] > 0.0).expect("an impact");
    // The floor is reached at t1 = sqrt(2 · 0.9 / g) ≈ 0.4284 s, within a step.
    assert!((record.t[first] - (1.8 / G).sqrt()).abs() < 2e-4, "{}", record.t[first]);
    // Newton's law normal to the floor; the constraint holds u_x = v although friction pulls.
    let (before, after) = (&record.u[first - 1], &record.u[first]);
    // The contact's only normal velocity is u_y (w_N = (0, 1), constant), so Newton's law
    // γ_E = −ε γ_A holds to round-off.
    let law = after[1] + eps * before[1];
    assert!(law.abs() < 1e-12, "u_E + ε u_A = {law:e}: {before:?} {after:?}");
    // The ball slides throughout (γ_T = u_x = v > 0), so friction takes its whole cone:
    // P_T = −μ P_N sign(γ_T).
    let (p_n, p_t) = (record.p_n[first][0], record.p_t[first][0]);
    assert!(p_n > 0.0);
    assert!((p_t + mu * p_n * v.signum()).abs() < 1e-12 * p_n, "P_T = {p_t}, P_N = {p_n}");
    for u in &record.u {
        assert!((u[0] - v).abs() < 1e-12, "u_x = {}", u[0]);
    }
}

/// The same pin stated twice: S = W_Bᵀ M⁻¹ W_B is singular. The second statement moves at
/// `moving` (m/s): with 0 the rows agree, otherwise they disagree.
struct TwicePinned {
    pendulum: Pendulum,
    moving: f64,
}

contactless!(TwicePinned, 3);

impl Mechanism for TwicePinned {
    fn laws(&self) -> &[ContactLaw] {
        &[]
    }
    fn mass_matrix(&self, q: &[f64], t: f64, m: &mut [f64]) {
        self.pendulum.mass_matrix(q, t, m);
    }
    fn forces(&self, q: &[f64], u: &[f64], t: f64, h: &mut [f64]) {
        self.pendulum.forces(q, u, t, h);
    }
    fn num_bilaterals(&self) -> usize {
        3
    }
    fn bilateral(&self, i: usize, q: &[f64], t: f64, w: &mut [f64]) -> BilateralPoint {
        let p = self.pendulum.bilateral(i.min(1), q, t, w);
        if i == 2 { BilateralPoint { w_hat: p.w_hat + self.moving, ..p } } else { p }
    }
}

/// The pin with the sign of its first row's W_B turned: the velocity it keeps is the same, but
/// its correction of the positions moves them away from g_B = 0.
struct Misderived(Pendulum);

contactless!(Misderived, 3);

impl Mechanism for Misderived {
    fn laws(&self) -> &[ContactLaw] {
        &[]
    }
    fn mass_matrix(&self, q: &[f64], t: f64, m: &mut [f64]) {
        self.0.mass_matrix(q, t, m);
    }
    fn forces(&self, q: &[f64], u: &[f64], t: f64, h: &mut [f64]) {
        self.0.forces(q, u, t, h);
    }
    fn num_bilaterals(&self) -> usize {
        2
    }
    fn bilateral(&self, i: usize, q: &[f64], t: f64, w: &mut [f64]) -> BilateralPoint {
        let p = self.0.bilateral(i, q, t, w);
        if i == 0 {
            w.iter_mut().for_each(|v| *v = -*v);
        }
        p
    }
}

/// States a constraint and never writes it.
struct Unwritten(Pendulum);

contactless!(Unwritten, 3);

impl Mechanism for Unwritten {
    fn laws(&self) -> &[ContactLaw] {
        &[]
    }
    fn mass_matrix(&self, q: &[f64], t: f64, m: &mut [f64]) {
        self.0.mass_matrix(q, t, m);
    }
    fn forces(&self, q: &[f64], u: &[f64], t: f64, h: &mut [f64]) {
        self.0.forces(q, u, t, h);
    }
    fn num_bilaterals(&self) -> usize {
        1
    }
}

#[test]
fn constraints_that_cannot_be_solved_are_typed_errors() {
    let start = pendulum_start(0.3, 1.0);
    // A pin stated twice agrees with itself: S is singular, the step solves it with a ridge,
    // and the pendulum swings as when pinned once, its impulses split between the two rows.
    let (mut once, mut twice) = (
        Stepper::new(
            Pendulum { m: 1.0, l: 1.0 },
            &start,
            &[0.0; 3],
            0.0,
            StepperOptions::new(1e-3),
        )
        .unwrap(),
        Stepper::new(
            TwicePinned { pendulum: Pendulum { m: 1.0, l: 1.0 }, moving: 0.0 },
            &start,
            &[0.0; 3],
            0.0,
            StepperOptions::new(1e-3),
        )
        .unwrap(),
    );
    for _ in 0..1000 {
        let split = {
            let r = twice.step().unwrap();
            [r.joint_impulses[0], r.joint_impulses[1] + r.joint_impulses[2]]
        };
        let r = once.step().unwrap();
        let pinned = [r.joint_impulses[0], r.joint_impulses[1]];
        for (a, b) in split.iter().zip(pinned) {
            assert!((a - b).abs() < 1e-9 * (1.0 + b.abs()), "{split:?} {pinned:?}");
        }
    }
    let apart = once.q().iter().zip(twice.q()).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(apart < 1e-9, "{apart:e}");
    // The second statement moving at 1 m/s disagrees with the first: the rows cannot all be
    // kept, and the step is refused with the state left as it was.
    let mut disagreeing = Stepper::new(
        TwicePinned { pendulum: Pendulum { m: 1.0, l: 1.0 }, moving: 1.0 },
        &start,
        &[0.0; 3],
        0.0,
        StepperOptions::new(1e-3),
    )
    .unwrap();
    let e = disagreeing.step().unwrap_err();
    assert!(matches!(e, StepError::RedundantConstraints { .. }), "{e}");
    assert_eq!(disagreeing.steps(), 0);
    let mut unwritten = Stepper::new(
        Unwritten(Pendulum { m: 1.0, l: 1.0 }),
        &start,
        &[0.0; 3],
        0.0,
        StepperOptions::new(1e-3),
    )
    .unwrap();
    let e = unwritten.step().unwrap_err();
    assert!(
        matches!(e, StepError::NonFinite { what: "bilateral constraint", index: 0, .. }),
        "{e}"
    );
    // A row whose W_B is not the derivative of its g_B: the swing runs until the correction
    // of the positions makes the drift grow past 1e3 times its tolerance, and is refused then
    // rather than taken off the pin.
    let options = StepperOptions::new(1e-3).with_projection(true);
    let swinging = pendulum_start(1.0, 1.0);
    let mut misderived =
        Stepper::new(Misderived(Pendulum { m: 1.0, l: 1.0 }), &swinging, &[0.0; 3], 0.0, options)
            .unwrap();
    let e = loop {
        if let Err(e) = misderived.step() {
            break e;
        }
        assert!(misderived.t() < 1.0, "ran to 1 s off its pin: {:?}", misderived.q());
    };
    let StepError::JointCorrectionDiverged { before, after, .. } = e else { panic!("{e}") };
    assert!(after > before && after > 1e-9, "{before:e} {after:e}");
    let q = misderived.q();
    let pin = [q[0] - 0.5 * q[2].sin(), q[1] + 0.5 * q[2].cos()];
    assert!(pin[0].hypot(pin[1]) < after, "the state is the failed step's start: {pin:?}");
}

#[test]
fn a_stepper_of_a_shareable_mechanism_is_send_and_sync() {
    fn send_sync<T: Send + Sync>() {}
    send_sync::<Stepper<Pendulum>>();
    send_sync::<Stepper<DrivenBall>>();
    send_sync::<StepperOptions>();
    send_sync::<moreau_stepper::SolverChoice>();
    send_sync::<moreau_stepper::Record>();
    send_sync::<StepError>();
}
