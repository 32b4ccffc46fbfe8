//! Joints on the many-body path: a declared mechanism with joints steps the same with its
//! contacts detected as with its explicit contact list, a chain hanging onto a pile of disks
//! keeps its joints and links its bodies into one island, and bad joints keep their errors.

use moreau_models::bodies::{ContactSet, Multibody, SystemSpec};
use moreau_models::{ModelParams, Scene};
use moreau_stepper::{Mechanism, Stepper, StepperOptions};

fn scene(file: &str) -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(file);
    Scene::from_path(&path).unwrap()
}

fn declared(scene: &Scene) -> SystemSpec {
    match &scene.params {
        ModelParams::Declared(s) => (**s).clone(),
        other => panic!("not declared: {other:?}"),
    }
}

/// Steps `spec` with the fixed and with the detected contact set in lockstep for `steps`
/// steps; returns the largest |q_fixed − q_detected|, |u_fixed − u_detected|, the largest
/// joint drift of either and the number of steps whose contact counts differ.
fn lockstep(spec: &SystemSpec, options: StepperOptions, steps: usize) -> [f64; 5] {
    let mut fixed = spec.clone();
    fixed.contact_set = ContactSet::Fixed;
    let mut detected = spec.clone();
    detected.contact_set = ContactSet::Detected;
    let (fixed, detected): (Multibody, Multibody) =
        (fixed.build().unwrap(), detected.build().unwrap());
    let (q0, u0) = fixed.initial_state();
    assert_eq!((q0.clone(), u0.clone()), detected.initial_state());
    let mut a = Stepper::new(fixed, &q0, &u0, 0.0, options.clone()).unwrap();
    let mut b = Stepper::new(detected, &q0, &u0, 0.0, options).unwrap();
    let (mut dq, mut du, mut drift, mut differ, mut impulses) =
        (0.0f64, 0.0f64, 0.0f64, 0.0, 0.0f64);
    for _ in 0..steps {
        let ra = a.step().unwrap();
        let (na, da) = (ra.contacts.iter().filter(|c| c.active).count(), ra.joint_drift);
        let pa: f64 = ra.contacts.iter().map(|c| c.p_n).sum();
        let rb = b.step().unwrap();
        let nb = rb.contacts.len();
        let pb: f64 = rb.contacts.iter().map(|c| c.p_n).sum();
        drift = drift.max(da).max(rb.joint_drift);
        impulses = impulses.max((pa - pb).abs());
        if na != nb {
            differ += 1.0;
        }
        let (qa, ua) = (a.q().to_vec(), a.u().to_vec());
        for (x, y) in qa.iter().zip(b.q()) {
            dq = dq.max((x - y).abs());
        }
        for (x, y) in ua.iter().zip(b.u()) {
            du = du.max((x - y).abs());
        }
    }
    [dq, du, drift, differ, impulses]
}

/// Steps the scene `file` for `steps` steps with the fixed and with the detected contact
/// set, without and with the projection, and asserts that they agree within `bounds` on q,
/// u and the summed normal impulses, with the same contact counts, and that the joints'
/// drift is reported.
fn steps_alike(file: &str, steps: usize, bounds: [f64; 3]) {
    let s = scene(file);
    let spec = declared(&s);
    for projection in [false, true] {
        let options = s.stepper_options().with_projection(projection);
        let [dq, du, drift, differ, impulses] = lockstep(&spec, options, steps);
        let [bq, bu, bp] = bounds;
        assert!(dq < bq && du < bu && impulses < bp, "{dq:e} {du:e} {impulses:e}");
        assert_eq!(differ, 0.0, "steps whose contact counts differ");
        assert!(drift > 0.0, "the joints drift and the report says so");
    }
}

#[test]
fn the_pendulum_striking_a_wall_steps_alike_with_detected_contacts() {
    // The same contact, the same joint rows: the two paths differ by round-off and the
    // islands' solver tolerance (the dense path eliminates the joint by its Schur complement,
    // the sparse one solves it with the contact by Newton to a natural map of 1e-13), with
    // and without the projection; 2 s, several impacts. Measured: 7e-14 in q, 2.2e-13 in u.
    steps_alike("bodies/pendulum-wall.toml", 20000, [1e-12, 1e-12, 1e-12]);
}

#[test]
fn the_woodpecker_steps_alike_with_detected_contacts() {
    // Three frictional contacts, two joints and impacts every few milliseconds: the islands'
    // solver stops at a natural-map residual of 1e-13 where the dense path pivots exactly,
    // and each impact carries that difference on; over 0.5 s the contact sets stay the same
    // and q agrees to 1e-7 m (3.3e-8 measured), u to 1e-4 (5.1e-6 measured, ω ~ 10² rad/s).
    steps_alike("bodies/woodpecker.toml", 5000, [1e-7, 1e-4, 1e-9]);
}

/// A chain of `links` rods (capsules 0.1 m long) hinged to each other and, at its top, to a
/// fixed pivot at (0, 1), released at 30° from the vertical; below it a pile of three rows of
/// ten disks (radius 0.05 m) in a box one metre wide. The chain is 0.1 m longer than the
/// height of the pivot above the pile, so it swings onto the disks and drapes over them.
fn chain_on_a_pile(links: usize) -> Multibody {
    use moreau_kinematics::Shape;
    use moreau_models::LawParams;
    use moreau_models::bodies::{AutoContacts, BodySpec, JointSpec, MultibodyBuilder};
    let mut b = MultibodyBuilder::new([0.0, -9.81]);
    for (name, point, normal) in [
        ("floor", [0.0, 0.0], [0.0, 1.0]),
        ("left", [-0.5, 0.0], [1.0, 0.0]),
        ("right", [0.5, 0.0], [-1.0, 0.0]),
    ] {
        b.add_body(
            BodySpec::fixed(name, [0.0, 0.0], 0.0).with_shape(Shape::HalfPlane { point, normal }),
        );
    }
    let r = 0.05;
    for k in 0..30 {
        let p = [-0.45 + 0.1 * (k % 10) as f64, r + 0.1 * (k / 10) as f64];
        b.add_body(
            BodySpec::dynamic(&format!("disk{k}"), 0.2, 0.5 * 0.2 * r * r, p, 0.0)
                .with_shape(Shape::Disk { center: [0.0, 0.0], radius: r }),
        );
    }
    let (len, tilt) = (0.1, 30f64.to_radians());
    let top = [0.0, 1.0];
    for k in 0..links {
        let d = (k as f64 + 0.5) * len;
        let p = [top[0] + d * tilt.sin(), top[1] - d * tilt.cos()];
        let (m, l) = (0.05, len);
        b.add_body(
            BodySpec::dynamic(
                &format!("link{k}"),
                m,
                m * l * l / 12.0,
                p,
                tilt - 0.5 * std::f64::consts::PI,
            )
            .with_shape(Shape::Capsule {
                a: [-0.5 * l, 0.0],
                b: [0.5 * l, 0.0],
                radius: 0.01,
            }),
        );
        let (above, anchor) = if k == 0 {
            ("ground".to_owned(), top)
        } else {
            (format!("link{}", k - 1), [0.5 * l, 0.0])
        };
        b.add_joint(JointSpec::revolute(
            &format!("pin{k}"),
            &above,
            anchor,
            &format!("link{k}"),
            [-0.5 * l, 0.0],
        ));
    }
    b.auto_contacts(AutoContacts::new(LawParams::new(0.0, 0.0, 0.3)));
    b.with_contact_set(ContactSet::Detected);
    b.build().unwrap()
}

#[test]
fn a_chain_draped_on_a_pile_keeps_its_joints_and_links_one_island() {
    // Projection on: the joints' drift is corrected at every step. Its contact part is left
    // to penetrations beyond 0.1 mm, so that the pile (hyperstatic, whose projection problem
    // has no solution at times) keeps the scheme's O(g Δt²) penetration.
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let mb = chain_on_a_pile(8);
            let (q0, u0) = mb.initial_state();
            let options = StepperOptions::new(1e-3)
                .with_gap_tolerance(1e-9)
                .with_projection(true)
                .with_projection_tolerance(1e-4);
            let mut s = Stepper::new(mb, &q0, &u0, 0.0, options).unwrap();
            let mut islands = Vec::new();
            let (mut drift, mut end_drift) = (0.0f64, 0.0f64);
            let mut w = vec![0.0; q0.len()];
            for _ in 0..600 {
                let r = s.step().unwrap();
                islands.push(r.islands);
                drift = drift.max(r.joint_drift);
                let (m, q, t) = (s.mechanism(), s.q(), s.t());
                for i in 0..m.num_bilaterals() {
                    end_drift = end_drift.max(m.bilateral(i, q, t, &mut w).g.abs());
                }
            }
            (s.q().to_vec(), s.u().to_vec(), islands, drift, end_drift)
        })
    };
    let (q1, u1, islands, drift, end_drift) = run(1);
    // The chain's eight links are one island through their joints and the pile another (the
    // walls and the floor link nothing), until the chain lands on the pile and both are one.
    assert_eq!(islands[0], 2, "{:?}", &islands[..3]);
    let landed = islands.iter().position(|&n| n == 1).expect("the chain lands on the pile");
    assert!(landed > 10, "{landed}");
    let joined = islands[landed..].iter().filter(|&&n| n == 1).count();
    assert!(joined > 100, "{joined}");
    // The midpoint sits Δt/2 off the corrected positions: its drift is O(Δt² |u|²/ℓ), below
    // 1e-3 of a link's 0.1 m (1.1e-5 m measured over 1.5 s). The end of a step is back on the
    // joints to round-off after their correction; the contact projection that follows keeps
    // them to first order only, leaving O(δ²/ℓ) for a push δ of up to the 0.1 mm projection
    // tolerance (6.9e-7 m measured), as on the path of fixed contacts.
    assert!(drift > 0.0 && drift < 1e-4, "{drift:e}");
    assert!(end_drift < 1e-5, "{end_drift:e}");
    let (q2, u2, ..) = run(2);
    let same = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
    assert!(same(&q1, &q2) && same(&u1, &u2), "one and two threads differ");
}

#[test]
fn bad_joints_keep_their_typed_errors_with_detected_contacts() {
    use moreau_models::ModelError;
    // A joint between two bodies without coordinates.
    let mut spec = declared(&scene("bodies/pendulum-wall.toml"));
    spec.contact_set = ContactSet::Detected;
    let hinge = spec.joints[0].clone();
    let moreau_models::bodies::JointSpec::Revolute { anchor_a, anchor_b, .. } = hinge else {
        panic!("a revolute hinge")
    };
    spec.joints[0] =
        moreau_models::bodies::JointSpec::revolute("hinge", "ground", anchor_a, "wall", anchor_b);
    match spec.build() {
        Err(ModelError::BadValue { key, reason, .. }) => {
            assert_eq!(key, "joints.hinge.body_b");
            assert!(reason.contains("dynamic"), "{reason}");
        }
        other => panic!("expected a refusal naming the joint, got {other:?}"),
    }
    // A clearance joint is a set of contact slots, which the detected set does not keep.
    let mut spec = declared(&scene("bodies/slider-crank.toml"));
    spec.contact_set = ContactSet::Detected;
    match spec.build() {
        Err(ModelError::BadValue { key, reason, .. }) => {
            assert_eq!(key, "contact_set");
            assert!(reason.contains("clearance"), "{reason}");
        }
        other => panic!("expected a refusal naming contact_set, got {other:?}"),
    }
}

#[test]
fn the_work_of_the_joints_and_contacts_closes_the_energy_balance() {
    // The pendulum striking a wall with ε_N = 1, without the projection: under gravity alone
    // kinetic + potential energy + the impulses' dissipation stays at its start, on both
    // paths.
    let mut s = scene("bodies/pendulum-wall.toml");
    s.set("contacts.hit.eps_n", "1").unwrap();
    let spec = declared(&s);
    let options = s.stepper_options().with_projection(false);
    let mut lost = Vec::new();
    for set in [ContactSet::Fixed, ContactSet::Detected] {
        let mut spec = spec.clone();
        spec.contact_set = set;
        let mech = spec.build().unwrap();
        let (q0, u0) = mech.initial_state();
        let mut stepper = Stepper::new(mech, &q0, &u0, 0.0, options.clone()).unwrap();
        let record = stepper.record_until(2.0).unwrap();
        let energy = record.total_energy();
        assert!(!record.impacts.is_empty());
        for (k, (e, d)) in energy.iter().zip(&record.cumulative_dissipation).enumerate() {
            assert!((e + d - energy[0]).abs() < 1e-9, "{set:?}, row {k}: {e} + {d}");
        }
        lost.push(*record.cumulative_dissipation.last().unwrap());
    }
    // The hinge does no work: 7.3e-10 J of about 1.2 J over 2 s on both paths (1.37 mJ when
    // it was held at γ_B,E = 0, which removed the part of u_A the midpoint's w_B did not admit).
    assert!(lost.iter().all(|l| l.abs() < 1e-8), "{lost:?}");
}

#[test]
fn a_hinge_pulls_on_a_swinging_bob_with_three_times_its_weight_at_the_bottom() {
    // A 1 kg bob (inertia 1e-6 kg m²) on a 0.5 m massless rod hinged at the origin, released
    // from the horizontal: at the bottom v² = 2 g L and the rod's tension is m g + m v² / L =
    // 3 m g. The hinge's two rows are the bob's position minus the pivot's, so their impulses
    // are the force on the bob over the step; both paths give the same.
    use moreau_models::bodies::{BodySpec, JointSpec, MultibodyBuilder};
    let (m, g, dt) = (1.0, 9.81, 1e-4);
    let mut largest = Vec::new();
    for set in [ContactSet::Fixed, ContactSet::Detected] {
        let mut b = MultibodyBuilder::new([0.0, -g]);
        b.add_body(BodySpec::dynamic("bob", m, 1e-6, [0.5, 0.0], 0.0));
        b.add_joint(JointSpec::revolute("hinge", "ground", [0.0, 0.0], "bob", [-0.5, 0.0]));
        let pendulum = b.with_contact_set(set).build().unwrap();
        assert_eq!(pendulum.bilateral_names(), ["hinge.Lx", "hinge.Ly"]);
        let (q0, u0) = pendulum.initial_state();
        let options = pendulum.stepper_options(dt);
        let mut stepper = Stepper::new(pendulum, &q0, &u0, 0.0, options).unwrap();
        let (mut most, mut at_lowest, mut lowest) = (0.0f64, 0.0, 0.0f64);
        while stepper.t() < 0.6 {
            let r = stepper.step().unwrap();
            assert_eq!(r.joint_impulses.len(), 2);
            let force = [r.joint_impulses[0] / dt, r.joint_impulses[1] / dt];
            most = most.max(force[0].hypot(force[1]));
            if r.q[1] < lowest {
                (lowest, at_lowest) = (r.q[1], force[1]);
            }
        }
        // At the bottom the force points up, 3 m g to the scheme's O(Δt).
        assert!((lowest + 0.5).abs() < 1e-6, "{lowest}");
        assert!((at_lowest - 3.0 * m * g).abs() < 1e-3 * 3.0 * m * g, "{at_lowest}");
        assert!((most - 3.0 * m * g).abs() < 1e-3 * 3.0 * m * g, "{most}");
        largest.push(most);
    }
    assert!((largest[0] - largest[1]).abs() < 1e-9 * largest[0], "{largest:?}");
}

#[test]
fn a_motor_turning_a_rod_at_constant_speed_applies_the_torque_gravity_asks() {
    // A 1 kg rod 1 m long hinged at its end (its origin, the centre of mass 0.5 m below it at
    // θ = 0), turned by a motor at Ω = 2 rad/s from θ = 0: with θ̈ = 0 the motor's torque is
    // m g d sin Ω t, d = 0.5 m. Its impulse is the motor's row, on the rod.
    use moreau_models::bodies::{BodySpec, JointSpec, MultibodyBuilder};
    let (m, g, d, omega, dt) = (1.0, 9.81, 0.5, 2.0, 1e-4);
    for set in [ContactSet::Fixed, ContactSet::Detected] {
        let mut b = MultibodyBuilder::new([0.0, -g]);
        let mut rod =
            BodySpec::dynamic("rod", m, m / 3.0, [0.0, 0.0], 0.0).with_velocity([0.0, 0.0], omega);
        rod.center_of_mass = Some([0.0, -d]);
        b.add_body(rod);
        b.add_joint(JointSpec::revolute("hinge", "ground", [0.0, 0.0], "rod", [0.0, 0.0]));
        b.add_joint(JointSpec::Motor {
            name: "drive".into(),
            body_a: "ground".into(),
            body_b: "rod".into(),
            omega,
            angle: None,
        });
        let mechanism = b.with_contact_set(set).build().unwrap();
        assert_eq!(mechanism.bilateral_names(), ["hinge.Lx", "hinge.Ly", "drive.Ltheta"]);
        let (q0, u0) = mechanism.initial_state();
        let options = mechanism.stepper_options(dt);
        let mut stepper = Stepper::new(mechanism, &q0, &u0, 0.0, options).unwrap();
        let mut worst = 0.0f64;
        while stepper.t() < 3.0 {
            let r = stepper.step().unwrap();
            // The step's mean torque, against the closed form at its midpoint.
            let torque = r.joint_impulses[2] / dt;
            let expected = m * g * d * (omega * (r.t - 0.5 * dt)).sin();
            worst = worst.max((torque - expected).abs());
        }
        assert!(worst < 1e-6 * m * g * d, "{set:?}: {worst}");
    }
}

/// A parallelogram of three equal cranks 0.5 m long, hinged to the ground at x = 0, 0.5 and
/// 1 m and to a coupler 1 m long, released at 45°: the third crank repeats what the other two
/// impose, so the joints' S = W_Bᵀ M⁻¹ W_B is singular.
fn parallelogram(set: ContactSet) -> Multibody {
    use moreau_models::bodies::{BodySpec, JointSpec, MultibodyBuilder};
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let mut b = MultibodyBuilder::new([0.0, -9.81]);
    for (i, x) in [0.0, 0.5, 1.0].into_iter().enumerate() {
        let crank = BodySpec::dynamic(
            &format!("crank{i}"),
            1.0,
            1.0 / 48.0,
            [x + 0.25 * s, 0.25 * s],
            -std::f64::consts::FRAC_PI_4,
        );
        b.add_body(crank);
    }
    b.add_body(BodySpec::dynamic("coupler", 2.0, 1.0 / 6.0, [0.5 + 0.5 * s, 0.5 * s], 0.0));
    for (i, x) in [0.0, 0.5, 1.0].into_iter().enumerate() {
        let crank = format!("crank{i}");
        b.add_joint(JointSpec::revolute(
            &format!("base{i}"),
            "ground",
            [x, 0.0],
            &crank,
            [0.0, -0.25],
        ));
        b.add_joint(JointSpec::revolute(
            &format!("top{i}"),
            &crank,
            [0.0, 0.25],
            "coupler",
            [x - 0.5, 0.0],
        ));
    }
    b.with_contact_set(set).build().unwrap()
}

#[test]
fn a_parallelogram_with_a_redundant_crank_swings_with_its_cranks_parallel() {
    // Before, the singular S stopped the run at its first step. The cranks turn alike and the
    // coupler stays level, on both paths, which agree on the motion. Released at 45° from the
    // top, the cranks swing down through the two flat positions, where the coupler lies on the
    // line of the hinges and the joints lose one more rank, to the mirror of their start and
    // back: the joints do no work, and with the energy kept the swing ends at −7π/4.
    let mut finals = Vec::new();
    for set in [ContactSet::Fixed, ContactSet::Detected] {
        let mechanism = parallelogram(set);
        let (q0, u0) = mechanism.initial_state();
        let options = mechanism.stepper_options(1e-3);
        let mut stepper = Stepper::new(mechanism, &q0, &u0, 0.0, options).unwrap();
        let (mut spread, mut tilt, mut lowest) = (0.0f64, 0.0f64, 0.0f64);
        while stepper.t() < 2.0 {
            let r = stepper.step().unwrap();
            let angles = [r.q[2], r.q[5], r.q[8]];
            spread = spread.max(
                angles.iter().fold(f64::NEG_INFINITY, |m, &a| m.max(a))
                    - angles.iter().fold(f64::INFINITY, |m, &a| m.min(a)),
            );
            tilt = tilt.max(r.q[11].abs());
            lowest = lowest.min(r.q[2]);
        }
        assert!(spread < 1e-8 && tilt < 1e-8, "{set:?}: {spread:e} {tilt:e}");
        let mirror = -7.0 * std::f64::consts::FRAC_PI_4;
        assert!((lowest - mirror).abs() < 1e-3, "{set:?}: turned to {lowest}");
        finals.push(stepper.q().to_vec());
    }
    let apart = finals[0].iter().zip(&finals[1]).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(apart < 1e-8, "{apart:e}");
}

#[test]
fn a_step_too_long_for_its_joints_is_refused_on_both_paths() {
    // A 1 m rod hinged at one end spins at 20 rad/s without gravity. At Δt = 0.1 s it would
    // turn 2 rad per step: the midpoint leaves the hinge by 0.23 m, and the step is refused
    // with the state left at its start. At Δt = 0.01 s the rod spins on with its hinge kept.
    use moreau_models::bodies::{BodySpec, JointSpec, MultibodyBuilder};
    use moreau_stepper::StepError;
    for set in [ContactSet::Fixed, ContactSet::Detected] {
        for projection in [false, true] {
            let rod = || {
                let mut b = MultibodyBuilder::new([0.0, 0.0]);
                let mut body = BodySpec::dynamic("rod", 1.0, 1.0 / 12.0, [0.5, 0.0], 0.0);
                body.velocity = [0.0, 10.0];
                body.omega = 20.0;
                b.add_body(body);
                b.add_joint(JointSpec::revolute("hinge", "ground", [0.0, 0.0], "rod", [-0.5, 0.0]));
                b.with_contact_set(set).build().unwrap()
            };
            let (q0, u0) = rod().initial_state();
            let options = rod().stepper_options(0.1).with_projection(projection);
            let mut stepper = Stepper::new(rod(), &q0, &u0, 0.0, options).unwrap();
            match stepper.step() {
                Err(StepError::JointsApart { drift, limit, .. }) => {
                    assert!((drift - 0.2298).abs() < 1e-3 && limit < drift, "{drift} {limit}");
                }
                other => panic!("{set:?}, {projection}: expected a refusal, got {:?}", other.err()),
            }
            assert_eq!((stepper.t(), stepper.q(), stepper.u()), (0.0, &q0[..], &u0[..]));
            let options = rod().stepper_options(0.01).with_projection(projection);
            let mut stepper = Stepper::new(rod(), &q0, &u0, 0.0, options).unwrap();
            stepper.record_until(3.0).unwrap();
            let q = stepper.q();
            let hinge = (q[0] - 0.5 * q[2].cos()).hypot(q[1] - 0.5 * q[2].sin());
            assert!(
                hinge < if projection { 1e-11 } else { 1e-2 },
                "{set:?}, {projection}: {hinge}"
            );
        }
    }
}
