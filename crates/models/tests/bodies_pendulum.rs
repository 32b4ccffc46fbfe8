//! Declared mechanisms without contacts, against closed forms and hand-written models: a rod
//! hinged at one end (small-angle period, a one-coordinate pendulum, energy), a pin in a
//! bearing of almost no clearance against the ideal hinge, and a free body whose origin is not
//! its centre of mass.

use std::f64::consts::{FRAC_PI_2, PI};

use moreau_kinematics::{ContactKinematics, ContactPoint};
use moreau_models::bodies::{BodySpec, JointSpec, Multibody, MultibodyBuilder};
use moreau_setvalued::ContactLaw;
use moreau_stepper::{Mechanism, Stepper, StepperOptions};

const G: f64 = 9.81;
const M: f64 = 1.0;
const L: f64 = 1.0;
/// The rod's moment of inertia about its centre, m L² / 12.
const I_G: f64 = M * L * L / 12.0;

/// A rod hanging from the world at its end, at angle φ0 from the downward vertical.
fn rod(phi0: f64, hinge: Option<f64>) -> Multibody {
    let d = 0.5 * L;
    let mut b = MultibodyBuilder::new([0.0, -G]);
    b.add_body(BodySpec::dynamic(
        "rod",
        M,
        I_G,
        [d * phi0.sin(), -d * phi0.cos()],
        phi0 - FRAC_PI_2,
    ));
    match hinge {
        None => b.add_joint(JointSpec::revolute("hinge", "ground", [0.0, 0.0], "rod", [-d, 0.0])),
        Some(clearance) => b.add_joint(JointSpec::RevoluteClearance {
            name: "hinge".into(),
            body_a: "rod".into(),
            body_b: "ground".into(),
            anchor_a: [-d, 0.0],
            anchor_b: [0.0, 0.0],
            pin_radius: 0.01,
            bearing_radius: 0.01 + clearance,
            eps_n: 0.0,
            eps_t: 0.0,
            mu: 0.0,
        }),
    };
    b.build().unwrap()
}

/// φ = θ + π/2 of the rod's states, every step until t_end.
fn swing<K: Mechanism>(
    mechanism: K,
    q0: &[f64],
    u0: &[f64],
    angle: impl Fn(&[f64]) -> f64,
    dt: f64,
    t_end: f64,
    projection: bool,
) -> (Vec<f64>, Vec<f64>, Stepper<K>) {
    // A closed contact's midpoint gap is zero only up to round-off; the threshold keeps the
    // pin of the clearance joint in its contact instead of letting it fall for a step.
    let mut options = StepperOptions::new(dt).with_gap_tolerance(1e-14);
    options.projection = projection;
    let mut stepper = Stepper::new(mechanism, q0, u0, 0.0, options).unwrap();
    let (mut t, mut phi) = (vec![0.0], vec![angle(q0)]);
    while stepper.t() < t_end - 0.5 * dt {
        stepper.step().unwrap();
        t.push(stepper.t());
        phi.push(angle(stepper.q()));
    }
    (t, phi, stepper)
}

/// The instants where φ crosses zero upwards, interpolated linearly.
fn upward_crossings(t: &[f64], phi: &[f64]) -> Vec<f64> {
    (1..t.len())
        .filter(|&k| phi[k - 1] < 0.0 && phi[k] >= 0.0)
        .map(|k| t[k - 1] + (t[k] - t[k - 1]) * (-phi[k - 1]) / (phi[k] - phi[k - 1]))
        .collect()
}

#[test]
fn a_hinged_rod_swings_with_the_small_angle_period() {
    let mb = rod(0.01, None);
    let (q0, u0) = mb.initial_state();
    let (t, phi, _) = swing(mb, &q0, &u0, |q| q[2] + FRAC_PI_2, 1e-3, 10.0, true);
    let crossings = upward_crossings(&t, &phi);
    assert!(crossings.len() >= 5, "{crossings:?}");
    let period = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    // T = 2π sqrt(I_O / (m g d)) with I_O = I_G + m d²; the amplitude of 0.01 rad lengthens it
    // by φ0²/16 ≈ 6e-6.
    let d = 0.5 * L;
    let closed = 2.0 * PI * ((I_G + M * d * d) / (M * G * d)).sqrt();
    let rel = (period - closed).abs() / closed;
    assert!(rel < 5e-5, "period {period} s, closed form {closed} s, rel {rel:.2e}");
}

/// The same rod in one coordinate φ: M = I_O, h = −m g d sin φ.
struct OneCoordinate;

impl ContactKinematics for OneCoordinate {
    fn num_coordinates(&self) -> usize {
        1
    }
    fn num_contacts(&self) -> usize {
        0
    }
    fn normal_gap(&self, _: usize, _: &[f64], _: f64) -> f64 {
        unreachable!("no contacts")
    }
    fn contact(&self, _: usize, _: &[f64], _: f64, _: &mut [f64], _: &mut [f64]) -> ContactPoint {
        unreachable!("no contacts")
    }
}

impl Mechanism for OneCoordinate {
    fn laws(&self) -> &[ContactLaw] {
        &[]
    }
    fn mass_matrix(&self, _: &[f64], _: f64, m: &mut [f64]) {
        m[0] = I_G + M * 0.25 * L * L;
    }
    fn forces(&self, q: &[f64], _: &[f64], _: f64, h: &mut [f64]) {
        h[0] = -M * G * 0.5 * L * q[0].sin();
    }
}

/// The largest |φ − φ_ref| against the one-coordinate pendulum over 2 s from φ0 = 1 rad,
/// and the largest energy error relative to m g d.
fn against_one_coordinate(dt: f64) -> (f64, f64) {
    let phi0 = 1.0f64;
    let mb = rod(phi0, None);
    let (q0, u0) = mb.initial_state();
    let (t, phi, _) = swing(mb.clone(), &q0, &u0, |q| q[2] + FRAC_PI_2, dt, 2.0, true);
    let (_, reference, _) = swing(OneCoordinate, &[phi0], &[0.0], |q| q[0], dt, 2.0, false);
    assert_eq!(t.len(), reference.len());
    let worst = phi.iter().zip(&reference).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    // The energy along the run, from the states of a second run (the record of angles alone
    // does not give the velocities).
    let mut options = StepperOptions::new(dt);
    options.projection = true;
    let mut stepper = Stepper::new(mb, &q0, &u0, 0.0, options).unwrap();
    let energy = |s: &Stepper<Multibody>| {
        let m = s.mechanism();
        m.kinetic_energy(s.q(), s.u()) + m.potential_energy(s.q(), s.t()).unwrap()
    };
    let e0 = energy(&stepper);
    let mut drift = 0.0f64;
    while stepper.t() < 2.0 - 0.5 * dt {
        stepper.step().unwrap();
        drift = drift.max((energy(&stepper) - e0).abs());
        let q = stepper.q();
        let hinge = [q[0] - 0.5 * L * q[2].cos(), q[1] - 0.5 * L * q[2].sin()];
        assert!(hinge[0].hypot(hinge[1]) < 1e-11, "{hinge:?}");
    }
    (worst, drift / (M * G * 0.5 * L))
}

#[test]
fn a_hinged_rod_converges_to_the_one_coordinate_pendulum_and_keeps_its_energy() {
    let (phi_coarse, energy_coarse) = against_one_coordinate(2e-4);
    let (phi_fine, energy_fine) = against_one_coordinate(1e-4);
    // Both are second-order discretisations of the same motion: halving Δt quarters the
    // difference of the angles.
    let ratio = phi_coarse / phi_fine;
    assert!(phi_fine < 1e-3 && (3.5..4.5).contains(&ratio), "{phi_coarse:e} {phi_fine:e}");
    // The ideal hinge does no work: the energy error is the scheme's, second order in Δt
    // (2.8e-9 of m g d at Δt = 1e-4 s).
    let ratio = energy_coarse / energy_fine;
    assert!(energy_fine < 1e-8 && (3.5..4.5).contains(&ratio), "{energy_coarse:e} {energy_fine:e}");
}

/// The largest |φ_clearance − φ_ideal| over 0.5 s with step dt, and the last gap of the pin.
fn pin_against_hinge(dt: f64) -> (f64, f64) {
    let ideal = rod(0.6, None);
    let (q0, u0) = ideal.initial_state();
    let (_, phi_ideal, _) = swing(ideal, &q0, &u0, |q| q[2] + FRAC_PI_2, dt, 0.5, true);
    let loose = rod(0.6, Some(1e-9));
    let (q0, u0) = loose.initial_state();
    let (_, phi_loose, stepper) = swing(loose, &q0, &u0, |q| q[2] + FRAC_PI_2, dt, 0.5, true);
    let worst = phi_loose.iter().zip(&phi_ideal).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    (worst, stepper.mechanism().normal_gap(0, stepper.q(), stepper.t()))
}

#[test]
fn a_pin_in_a_bearing_of_almost_no_clearance_converges_to_the_ideal_hinge() {
    // A frictionless pin may slide round a bearing 1e-9 m wider than itself, which the ideal
    // hinge forbids; the sliding is the scheme's, so the difference is first order in Δt.
    let (coarse, gap_coarse) = pin_against_hinge(2e-4);
    let (fine, gap_fine) = pin_against_hinge(1e-4);
    let ratio = coarse / fine;
    assert!(fine < 1e-3 && (1.7..2.3).contains(&ratio), "{coarse:e} {fine:e}");
    // The projection keeps the pin inside its bearing.
    for gap in [gap_coarse, gap_fine] {
        assert!((-1e-12..=1e-9).contains(&gap), "gap {gap:e}");
    }
}

#[test]
fn a_free_body_whose_origin_is_off_its_centre_of_mass_moves_its_centre_uniformly() {
    // A 2 kg body with its centre of mass 0.3 m from its origin, spinning at 4 rad/s, its
    // centre at rest: the centre stays put and the spin stays constant.
    let (m, c, i_g) = (2.0, [0.3, 0.0], 0.05);
    let mut b = MultibodyBuilder::new([0.0, 0.0]);
    let mut body = BodySpec::dynamic("b", m, i_g + m * 0.09, [0.0, 0.0], 0.0);
    body.center_of_mass = Some(c);
    // The origin moves on the circle about the centre: v = −ω × c.
    body.velocity = [0.0, -4.0 * 0.3];
    body.omega = 4.0;
    b.add_body(body);
    let mb = b.build().unwrap();
    assert!(!mb.constant_mass_matrix());
    let (q0, u0) = mb.initial_state();
    let mut stepper = Stepper::new(mb, &q0, &u0, 0.0, StepperOptions::new(1e-3)).unwrap();
    let e0 = stepper.mechanism().kinetic_energy(&q0, &u0);
    while stepper.t() < 2.0 {
        stepper.step().unwrap();
        let q = stepper.q();
        let centre = [q[0] + 0.3 * q[2].cos(), q[1] + 0.3 * q[2].sin()];
        assert!(
            (centre[0] - 0.3).hypot(centre[1]) < 1e-3,
            "centre {centre:?} at t = {}",
            stepper.t()
        );
    }
    let e = stepper.mechanism().kinetic_energy(stepper.q(), stepper.u());
    assert!((e - e0).abs() < 1e-3 * e0, "kinetic energy {e} J, initially {e0} J");
    assert!((stepper.u()[2] - 4.0).abs() < 1e-3, "spin {}", stepper.u()[2]);
}
