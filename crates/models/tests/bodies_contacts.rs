//! Declared shapes in contact, against closed forms: a box on an incline (stick or slide), a
//! disk on an incline (roll or slip), a pendulum striking a wall, a row of disks struck at one
//! end, and a disk swinging in a bowl (rolling or sliding).

use moreau_kinematics::Shape;
use moreau_models::bodies::{BodySpec, ContactSpec, JointSpec, Multibody, MultibodyBuilder};
use moreau_stepper::{Stepper, StepperOptions};

const G: f64 = 9.81;

fn options(dt: f64) -> StepperOptions {
    // Closed contacts' midpoint gaps are zero up to round-off; the threshold keeps them in.
    let mut o = StepperOptions::new(dt).with_gap_tolerance(1e-12);
    o.projection = true;
    o
}

fn law(name: &str, a: &str, b: &str, eps_n: f64, mu: f64) -> ContactSpec {
    ContactSpec {
        name: name.into(),
        body_a: a.into(),
        shape_a: 0,
        body_b: b.into(),
        shape_b: 0,
        eps_n,
        eps_t: 0.0,
        mu,
        margin: None,
    }
}

/// A fixed incline at angle α through the origin (solid below), and one body on it.
fn incline(alpha: f64, body: BodySpec, mu: f64) -> Multibody {
    let (s, c) = alpha.sin_cos();
    let mut b = MultibodyBuilder::new([0.0, -G]);
    b.add_body(
        BodySpec::fixed("slope", [0.0, 0.0], 0.0)
            .with_shape(Shape::HalfPlane { point: [0.0, 0.0], normal: [-s, c] }),
    );
    b.add_body(body);
    b.add_contact(law("foot", "slope", "body", 0.0, mu));
    b.build().unwrap()
}

/// The body's speed down the slope at t1 and t2 (m/s), and its largest speed before t1.
fn speeds(mb: Multibody, alpha: f64, dt: f64, t1: f64, t2: f64) -> (f64, f64, f64) {
    let (q0, u0) = mb.initial_state();
    let mut stepper = Stepper::new(mb, &q0, &u0, 0.0, options(dt)).unwrap();
    let down = |u: &[f64]| -(u[0] * alpha.cos() + u[1] * alpha.sin());
    let mut largest = 0.0f64;
    while stepper.t() < t1 - 0.5 * dt {
        stepper.step().unwrap();
        largest = largest.max(down(stepper.u()).abs());
    }
    let v1 = down(stepper.u());
    while stepper.t() < t2 - 0.5 * dt {
        stepper.step().unwrap();
    }
    (v1, down(stepper.u()), largest)
}

/// A 0.2 m × 0.1 m box of 1 kg resting flat on the incline.
fn box_on(alpha: f64, mu: f64) -> Multibody {
    let (s, c) = alpha.sin_cos();
    let (w, h) = (0.1, 0.05);
    let shape = Shape::Polygon { vertices: vec![[-w, -h], [w, -h], [w, h], [-w, h]] };
    let inertia = (4.0 * w * w + 4.0 * h * h) / 12.0;
    incline(
        alpha,
        BodySpec::dynamic("body", 1.0, inertia, [-s * h, c * h], alpha).with_shape(shape),
        mu,
    )
}

#[test]
fn a_box_on_an_incline_sticks_exactly_when_tan_alpha_is_at_most_mu() {
    // tan α = 0.3 < μ = 0.5, and tan α = μ exactly: the box stays.
    for (alpha, mu) in [(0.3f64.atan(), 0.5), (0.4f64.atan(), 0.4)] {
        let (v1, v2, largest) = speeds(box_on(alpha, mu), alpha, 1e-3, 0.5, 1.0);
        assert!(
            largest < 1e-12 && v1.abs() < 1e-12 && v2.abs() < 1e-12,
            "α = {alpha}: {largest:e}"
        );
    }
}

#[test]
fn a_box_on_a_steeper_incline_slides_at_g_sin_alpha_minus_mu_cos_alpha() {
    let (alpha, mu) = (0.5f64, 0.3);
    let (v1, v2, _) = speeds(box_on(alpha, mu), alpha, 1e-3, 0.2, 0.7);
    let a = (v2 - v1) / 0.5;
    let closed = G * (alpha.sin() - mu * alpha.cos());
    assert!((a - closed).abs() < 1e-9 * closed, "a = {a}, closed form {closed}");
}

/// A 1 kg uniform disk of radius 0.1 m touching the incline.
fn disk_on(alpha: f64, mu: f64) -> Multibody {
    let (s, c) = alpha.sin_cos();
    let r = 0.1;
    let body = BodySpec::dynamic("body", 1.0, 0.5 * r * r, [-s * r, c * r], 0.0)
        .with_shape(Shape::Disk { center: [0.0, 0.0], radius: r });
    incline(alpha, body, mu)
}

#[test]
fn a_disk_on_an_incline_rolls_at_two_thirds_g_sin_alpha_or_slips() {
    let alpha = 0.5f64;
    let critical = alpha.tan() / 3.0;
    // Rolling while μ >= tan α / 3 (at the limit too).
    for mu in [0.4, critical] {
        let (v1, v2, _) = speeds(disk_on(alpha, mu), alpha, 1e-3, 0.2, 0.7);
        let a = (v2 - v1) / 0.5;
        let closed = 2.0 / 3.0 * G * alpha.sin();
        assert!((a - closed).abs() < 1e-9 * closed, "μ = {mu}: a = {a}, rolling {closed}");
    }
    // Slipping below it: the centre accelerates at g (sin α − μ cos α).
    let mu = 0.1;
    let (v1, v2, _) = speeds(disk_on(alpha, mu), alpha, 1e-3, 0.2, 0.7);
    let a = (v2 - v1) / 0.5;
    let closed = G * (alpha.sin() - mu * alpha.cos());
    assert!((a - closed).abs() < 1e-9 * closed, "μ = {mu}: a = {a}, slipping {closed}");
}

#[test]
fn a_pendulum_striking_a_wall_rebounds_with_eps_n() {
    // A rod of 1 m hinged at the origin with a disk of radius 0.05 m at its tip; a wall
    // touches the disk when the rod hangs vertically.
    let (r, m, inertia, l) = (0.05, 1.0, 0.01, 1.0);
    for eps in [0.5, 0.8] {
        let phi0: f64 = -0.5;
        let mut b = MultibodyBuilder::new([0.0, -G]);
        b.add_body(
            BodySpec::fixed("wall", [0.0, 0.0], 0.0)
                .with_shape(Shape::HalfPlane { point: [r, 0.0], normal: [-1.0, 0.0] }),
        );
        b.add_body(
            BodySpec::dynamic("bob", m, inertia, [l * phi0.sin(), -l * phi0.cos()], 0.0)
                .with_shape(Shape::Disk { center: [0.0, 0.0], radius: r }),
        );
        b.add_joint(JointSpec::revolute(
            "hinge",
            "ground",
            [0.0, 0.0],
            "bob",
            [-l * phi0.sin(), l * phi0.cos()],
        ));
        b.add_contact(law("hit", "wall", "bob", eps, 0.0));
        let mb = b.build().unwrap();
        let (q0, u0) = mb.initial_state();
        let mut stepper = Stepper::new(mb, &q0, &u0, 0.0, options(1e-4)).unwrap();
        let mut found = None;
        while stepper.t() < 2.0 && found.is_none() {
            let before = stepper.u().to_vec();
            let report = stepper.step().unwrap();
            if report.contacts[0].p_n > 1e-6 {
                // The bob's speed normal to the wall, before and after: γ_N = −ẋ.
                found = Some((before[0], report.u[0]));
            }
        }
        let (pre, post) = found.expect("the bob reaches the wall");
        // Energy from φ0 to the vertical: (m L² + I) φ̇²/2 = m g L (1 − cos φ0), and there
        // ẋ = L φ̇. Away from impacts the midpoint step errs on the energy by O(Δt²), and the
        // impact step starts within v Δt of the vertical, where the speed is stationary: the
        // approach speed meets the closed form to 8e-9 relative.
        let closed = (2.0 * G * l * (1.0 - phi0.cos()) / (1.0 + inertia / (m * l * l))).sqrt();
        assert!((pre - closed).abs() < 1e-6 * closed, "approach speed {pre}, closed {closed}");
        assert!((post + eps * pre).abs() < 1e-9 * pre, "ε = {eps}: {pre} → {post}");
    }
}

/// n disks of 1 kg and radius 0.05 m on a line, without gravity, `gap` apart; the first
/// approaches the others at 1 m/s. Returns the final velocities along the line.
/// A row of `n` disks of 1 kg and radius `r` at x = `x(k)` without gravity, the first moving
/// at 1 m/s towards the others, each touching its neighbours through a contact with ε_N = 1.
fn row_of_disks(n: usize, r: f64, x: impl Fn(usize) -> f64) -> Multibody {
    let mut b = MultibodyBuilder::new([0.0, 0.0]);
    for k in 0..n {
        let disk = BodySpec::dynamic(&format!("d{k}"), 1.0, 0.5 * r * r, [x(k), 0.0], 0.0)
            .with_shape(Shape::Disk { center: [0.0, 0.0], radius: r });
        b.add_body(if k == 0 { disk.with_velocity([1.0, 0.0], 0.0) } else { disk });
    }
    for k in 1..n {
        b.add_contact(law(&format!("c{k}"), &format!("d{}", k - 1), &format!("d{k}"), 1.0, 0.0));
    }
    b.build().unwrap()
}

fn cradle(n: usize, gap: f64) -> Vec<f64> {
    let r = 0.05;
    let mb =
        row_of_disks(
            n,
            r,
            |k| {
                if k == 0 { -0.05 } else { 2.0 * r * k as f64 + gap * (k - 1) as f64 }
            },
        );
    let (q0, u0) = mb.initial_state();
    let mut stepper = Stepper::new(mb, &q0, &u0, 0.0, options(1e-4)).unwrap();
    let energy = |u: &[f64]| 0.5 * u.iter().map(|v| v * v).sum::<f64>();
    let (p0, e0) = (1.0, energy(&u0));
    while stepper.t() < 0.5 {
        stepper.step().unwrap();
        let u = stepper.u();
        let p: f64 = (0..n).map(|k| u[3 * k]).sum();
        assert!((p - p0).abs() < 1e-14, "momentum {p} at t = {}", stepper.t());
        assert!((energy(u) - e0).abs() < 1e-9 * e0, "energy {} at t = {}", energy(u), stepper.t());
    }
    (0..n).map(|k| stepper.u()[3 * k]).collect()
}

#[test]
fn disks_a_little_apart_pass_the_striker_speed_to_the_last_one() {
    // Gaps of 1 mm close in ten steps each, so the impacts come one at a time.
    let v = cradle(4, 1e-3);
    assert!((v[3] - 1.0).abs() < 1e-12 && v[..3].iter().all(|x| x.abs() < 1e-12), "{v:?}");
}

#[test]
fn touching_disks_struck_at_one_end_follow_newtons_law_at_every_contact_at_once() {
    // With three touching disks the impact at both contacts is one: Newton's law γ⁺ = −ε γ⁻
    // at both (the second contact at rest before) gives −1/3, 2/3, 2/3 m/s, which conserves
    // momentum and energy; the last disk does not take the striker's whole speed.
    let v = cradle(3, 0.0);
    let expected = [-1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0];
    assert!(v.iter().zip(expected).all(|(a, b)| (a - b).abs() < 1e-12), "{v:?}");
}

#[test]
fn five_touching_disks_laid_out_in_decimals_leave_as_a_block_with_the_scene_options() {
    // Disks of radius 0.1 m at x = 0.2 k: the gaps round to ±5.6e-17 m. With the options a
    // scene file gets (`Multibody::stepper_options`, gap tolerance 1e-9 of the size) all four
    // contacts act at once, and with ε_N = 1 the struck row leaves as a block at
    // V = (1 + ε) v / N = 0.4 m/s, the striker at V − ε v = −0.6 m/s (docs/extremes.md).
    let n = 5;
    let mb = row_of_disks(n, 0.1, |k| 0.2 * k as f64);
    let (q0, u0) = mb.initial_state();
    let options = mb.stepper_options(1e-4);
    let mut stepper = Stepper::new(mb, &q0, &u0, 0.0, options).unwrap();
    while stepper.t() < 0.01 {
        stepper.step().unwrap();
    }
    let v: Vec<f64> = (0..n).map(|k| stepper.u()[3 * k]).collect();
    let expected = [-0.6, 0.4, 0.4, 0.4, 0.4];
    assert!(v.iter().zip(expected).all(|(a, b)| (a - b).abs() < 1e-12), "{v:?}");
}

/// A block of 1 kg (0.1 × 0.05 m) on a belt moving at 0.1 m/s, tied to a fixed anchor at its
/// centre's height by a spring of 100 N/m, μ = 0.3, from a scene file without the projection,
/// for 3 s of stick-slip (the limit cycle about μ m g / k = 0.0294 m, of period 0.628 s): its
/// largest tilt and its lowest height. The friction's moment, μ m g times half the height, is
/// 0.15 of the weight's at the corners: both corners stay on the belt.
fn block_on_a_belt(dt: f64) -> (f64, f64) {
    let text = format!(
        "dt = {dt:e}\nt_end = 3.0\ngravity = [0.0, -9.81]\nprojection = false\n\
         [[bodies]]\nname = \"belt\"\ntype = \"driven\"\nposition = [0.0, 0.0]\n\
         motion = {{ kind = \"linear\", velocity = [0.1, 0.0] }}\n\
         shapes = [{{ type = \"half_plane\", point = [0.0, 0.0], normal = [0.0, 1.0] }}]\n\
         [[bodies]]\nname = \"block\"\ntype = \"dynamic\"\nmass = 1.0\ninertia = {}\n\
         position = [0.0, 0.025]\nshapes = [{{ type = \"polygon\", vertices = \
         [[-0.05, -0.025], [0.05, -0.025], [0.05, 0.025], [-0.05, 0.025]] }}]\n\
         [[forces]]\ntype = \"spring\"\nname = \"spring\"\nbody_a = \"ground\"\n\
         anchor_a = [-0.5, 0.025]\nbody_b = \"block\"\nanchor_b = [0.0, 0.0]\n\
         stiffness = 100.0\nrest_length = 0.5\n\
         [[contacts]]\nname = \"c\"\nbody_a = \"belt\"\nbody_b = \"block\"\neps_n = 0.0\n\
         eps_t = 0.0\nmu = 0.3\n",
        (0.1f64 * 0.1 + 0.05 * 0.05) / 12.0
    );
    let scene = moreau_models::Scene::from_toml_str(&text).expect("scene reads");
    let mut stepper = scene.stepper().expect("scene steps");
    let (mut tilt, mut lowest) = (0.0f64, f64::INFINITY);
    stepper
        .run_until(3.0, &mut |s: &moreau_stepper::StepReport<'_>| {
            tilt = tilt.max(s.q[2].abs());
            lowest = lowest.min(s.q[1]);
            std::ops::ControlFlow::Continue(())
        })
        .expect("run");
    (tilt, lowest)
}

/// A block resting on a face has both corners' midpoint gaps at zero, up to round-off. Counted
/// closed only at g_N <= 0, a corner whose gap round-off made positive sat out a step and the
/// block rocked: at Δt = 10 ms it tipped by 6.6e-3 rad. A scene file without the projection
/// now closes contacts within 1e-9 of its size, as with it.
#[test]
fn a_block_on_a_belt_stays_flat_through_stick_slip_without_the_projection() {
    for dt in [1e-3, 1e-2] {
        let (tilt, lowest) = block_on_a_belt(dt);
        assert!(tilt < 1e-12, "Δt = {dt}: tilted by {tilt:e} rad");
        assert!((lowest - 0.025).abs() < 1e-12, "Δt = {dt}: sank to {lowest}");
    }
}

/// A uniform disk (radius r = 0.1 m, 1 kg) let go 0.1 rad up a bowl of radius R = 1 m, the
/// bowl a polyline of 151 points sampled on the circle over 30° (chords of 3.5 mm): the
/// centre swings on a circle of radius R − r. Rolling (μ = 1), the disk's kinetic energy
/// (m + I/r²) v²/2 makes the small swing's period 2π √(3 (R − r) / (2 g)); frictionless
/// (μ = 0) the disk slides without turning, at 2π √((R − r) / g). Both carry the amplitude's
/// factor 1 + φ₀²/16 (6e-4 at φ₀ = 0.1 rad), and the period from two crossings of the bottom
/// is within 2e-4 of them (5e-5 rolling, 3e-5 sliding, the chords' corners taking a little
/// energy at each passage), where the rolling sphere's 2π √(7 (R − r) / (5 g)) is 3.4 % off.
#[test]
fn a_disk_in_a_bowl_swings_at_the_rolling_or_the_sliding_period() {
    let (big, r, phi0, dt) = (1.0f64, 0.1f64, 0.1f64, 1e-3);
    let arc: Vec<[f64; 2]> = (0..151)
        .map(|k| {
            let a = (-105.0 + 30.0 * k as f64 / 150.0f64).to_radians();
            [big * a.cos(), big + big * a.sin()]
        })
        .collect();
    let amplitude = 1.0 + phi0 * phi0 / 16.0;
    let rolling = 2.0 * std::f64::consts::PI * (1.5 * (big - r) / G).sqrt() * amplitude;
    let sliding = 2.0 * std::f64::consts::PI * ((big - r) / G).sqrt() * amplitude;
    for (mu, period) in [(1.0, rolling), (0.0, sliding)] {
        let mut b = MultibodyBuilder::new([0.0, -G]);
        b.add_body(
            BodySpec::fixed("bowl", [0.0, 0.0], 0.0)
                .with_shape(Shape::Polyline { points: arc.clone() }),
        );
        let centre = [(big - r) * phi0.sin(), big - (big - r) * phi0.cos()];
        b.add_body(
            BodySpec::dynamic("disk", 1.0, 0.5 * r * r, centre, 0.0)
                .with_shape(Shape::Disk { center: [0.0, 0.0], radius: r }),
        );
        b.add_contact(law("roll", "bowl", "disk", 0.0, mu));
        let mb = b.build().unwrap();
        let (q0, u0) = mb.initial_state();
        let mut stepper = Stepper::new(mb, &q0, &u0, 0.0, options(dt)).unwrap();
        // The times at which the centre crosses x = 0, by linear interpolation.
        let mut crossings = Vec::new();
        let mut spin = 0.0f64;
        while crossings.len() < 2 {
            assert!(stepper.t() < 3.0, "μ = {mu}: crossings {crossings:?} by t = 3 s");
            let (t0, x0) = (stepper.t(), stepper.q()[0]);
            stepper.step().unwrap();
            let (t1, x1) = (stepper.t(), stepper.q()[0]);
            if (x0 > 0.0) != (x1 > 0.0) {
                crossings.push(t0 + (t1 - t0) * x0 / (x0 - x1));
            }
            let u = stepper.u();
            if mu > 0.0 {
                // Rolling: the centre's speed is ω r.
                let v = (u[0] * u[0] + u[1] * u[1]).sqrt();
                assert!((v - u[2].abs() * r).abs() < 1e-3 * (v + 1e-3), "v = {v}, ω = {}", u[2]);
            }
            spin = spin.max(u[2].abs());
        }
        let swing = 2.0 * (crossings[1] - crossings[0]);
        assert!(
            (swing - period).abs() < 2e-4 * period,
            "μ = {mu}: period {swing} s against {period} s"
        );
        if mu == 0.0 {
            assert!(spin < 1e-12, "sliding disk turned at {spin} rad/s");
        }
    }
}
