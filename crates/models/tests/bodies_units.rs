//! Declared mechanisms written in other units: lengths from micrometres to kilometres and
//! masses from milligrams to kilotonnes give the same motion, measured in the mechanism's own
//! scales, and the same balance of forces; a chain whose links' masses differ a million times
//! moves alike on the paths of fixed and of detected contacts.

use std::ops::ControlFlow;

use moreau_models::{ModelParams, Scene};
use moreau_stepper::StepReport;

const G: f64 = 9.81;

/// The pendulum striking a wall of `scenes/bodies/pendulum-wall.toml` with lengths times `s`,
/// masses times `m` (times of √s, so that g stays 9.81), with the position projection.
fn pendulum(s: f64, m: f64) -> String {
    let r = s.sqrt();
    let (x, y) = (0.479425538604203 * s, 0.8775825618903728 * s);
    format!(
        r#"
dt = {dt}
t_end = {t_end}
gravity = [0.0, -9.81]
[[bodies]]
name = "wall"
type = "fixed"
position = [0.0, 0.0]
shapes = [{{ type = "half_plane", point = [{wall}, 0.0], normal = [-1.0, 0.0] }}]
[[bodies]]
name = "bob"
type = "dynamic"
mass = {mass}
inertia = {inertia}
position = [{px}, {py}]
shapes = [{{ type = "disk", center = [0.0, 0.0], radius = {radius} }}]
[[joints]]
type = "revolute"
name = "hinge"
body_a = "ground"
anchor_a = [0.0, 0.0]
body_b = "bob"
anchor_b = [{x}, {y}]
[[contacts]]
name = "hit"
body_a = "wall"
body_b = "bob"
eps_n = 0.8
eps_t = 0.0
mu = 0.0
"#,
        dt = 1e-4 * r,
        t_end = 0.8 * r,
        wall = 0.05 * s,
        mass = m,
        inertia = 0.00125 * m * s * s,
        px = -x,
        py = -y,
        radius = 0.05 * s,
    )
}

/// The bob's state after each step in the unit mechanism's scales: (x, y)/s, θ, (vx, vy)/√s,
/// ω √s, and its largest impulse over m √s.
fn pendulum_run(s: f64, m: f64) -> (Vec<[f64; 6]>, f64) {
    let scene = Scene::from_toml_str(&pendulum(s, m)).unwrap();
    let mut stepper = scene.stepper().unwrap();
    let (mut states, mut impulse) = (Vec::new(), 0.0f64);
    for _ in 0..8000 {
        let report = stepper.step().unwrap();
        impulse = report.contacts.iter().fold(impulse, |p, c| p.max(c.p_n));
        let (q, u) = (stepper.q(), stepper.u());
        let r = s.sqrt();
        states.push([q[0] / s, q[1] / s, q[2], u[0] / r, u[1] / r, u[2] * r]);
    }
    (states, impulse / (m * s.sqrt()))
}

#[test]
fn a_pendulum_striking_a_wall_moves_alike_in_any_unit_of_length_and_mass() {
    let (reference, impulse) = pendulum_run(1.0, 1.0);
    // It strikes the wall within the run.
    assert!(impulse > 0.1, "{impulse}");
    for (s, m) in [(1e-6, 1.0), (1e-3, 1e-6), (1e3, 1e6), (1e6, 1e-3)] {
        let (states, scaled) = pendulum_run(s, m);
        let worst = reference
            .iter()
            .zip(&states)
            .flat_map(|(a, b)| a.iter().zip(b).map(|(x, y)| (x - y).abs()))
            .fold(0.0f64, f64::max);
        assert!(worst < 1e-12, "lengths × {s:e}, masses × {m:e}: {worst:e}");
        assert!((scaled - impulse).abs() < 1e-12 * impulse, "{s:e}, {m:e}: {scaled} {impulse}");
    }
}

/// A floor y = 0 with detected contacts of restitution `eps_n` and friction `mu`, stepped
/// by `dt` until `t_end`, to which the bodies are added.
fn floor(dt: f64, t_end: f64, eps_n: f64, mu: f64) -> String {
    format!(
        r#"
dt = {dt}
t_end = {t_end}
gravity = [0.0, -9.81]
contact_set = "detected"
[[bodies]]
name = "floor"
type = "fixed"
position = [0.0, 0.0]
shapes = [{{ type = "half_plane", point = [0.0, 0.0], normal = [0.0, 1.0] }}]
[contacts_auto]
eps_n = {eps_n}
eps_t = 0.0
mu = {mu}
"#
    )
}

/// A dynamic box of half-sides `w` × `h` and `density` at (x, y), with its initial velocity
/// and angular velocity.
fn block(
    name: &str,
    density: f64,
    [x, y]: [f64; 2],
    [w, h]: [f64; 2],
    v: f64,
    omega: f64,
) -> String {
    format!(
        r#"
[[bodies]]
name = "{name}"
type = "dynamic"
density = {density}
position = [{x}, {y}]
velocity = [{v}, 0.0]
omega = {omega}
shapes = [{{ type = "polygon", vertices = [[{l}, {b}], [{w}, {b}], [{w}, {h}], [{l}, {h}]] }}]
"#,
        l = -w,
        b = -h,
    )
}

/// Three boxes of `density` (kg/m²), 1 × 0.5, 0.8 × 0.4 and 0.6 × 0.3 m times `s`, stacked
/// on a floor with detected contacts and the projection, at rest from t = 0.
fn stack(s: f64, density: f64) -> String {
    let mut text = floor(1e-3 * s.sqrt(), 0.2 * s.sqrt(), 0.0, 0.5);
    let mut bottom = 0.0;
    for (k, (w, h)) in [(0.5, 0.25), (0.4, 0.2), (0.3, 0.15)].into_iter().enumerate() {
        let (w, h) = (w * s, h * s);
        text += &block(&format!("box{k}"), density, [0.0, bottom + h], [w, h], 0.0, 0.0);
        bottom += 2.0 * h;
    }
    text
}

#[test]
fn a_stack_of_heavy_or_light_boxes_rests_on_its_floor_in_any_unit() {
    // Masses from 0.35 mg (0.3 mm boxes of paper) to 6,800 t (40 m blocks of granite):
    // every step's problem is solved, and the floor carries the weight.
    for (s, density) in [(1.0, 1.0), (1.0, 1e4), (1e-3, 1e-3), (40.0, 2.7e3), (1e3, 1e-2)] {
        let scene = Scene::from_toml_str(&stack(s, density)).unwrap();
        let mut stepper = scene.stepper().unwrap();
        let masses: Vec<f64> = [(0.5, 0.25), (0.4, 0.2), (0.3, 0.15)]
            .iter()
            .map(|(w, h)| density * 4.0 * w * h * s * s)
            .collect();
        let total: f64 = masses.iter().sum();
        let dt = 1e-3 * s.sqrt();
        let q0 = stepper.q().to_vec();
        let momentum =
            |u: &[f64]| masses.iter().enumerate().map(|(k, m)| m * u[3 * k + 1]).sum::<f64>();
        let p0 = momentum(stepper.u());
        let mut floor = 0.0;
        let steps = 200;
        for _ in 0..steps {
            let report = stepper.step().unwrap_or_else(|e| panic!("{s}, {density}: {e}"));
            // The floor's contacts are those of collider 0 (its half-plane).
            floor += report
                .contact_ids
                .iter()
                .zip(report.contacts)
                .filter(|(id, _)| **id >> 40 == 0)
                .map(|(_, c)| c.p_n)
                .sum::<f64>();
        }
        // Momentum: the floor's impulses carry the weight over the run, less the stack's
        // change of vertical momentum.
        let weight = total * G * dt * steps as f64;
        let balance = (floor - weight - (momentum(stepper.u()) - p0)).abs() / weight;
        assert!(balance < 1e-12, "lengths × {s}, density {density}: {balance:e}");
        let moved = q0.iter().zip(stepper.q()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(moved < 1e-6 * s, "lengths × {s}, density {density}: moved {moved:e}");
    }
}

/// A box of 1 × 0.5 m and `density`, dropped from 0.3 m with 3 m/s along a floor of
/// friction μ = 0.5 without restitution, turning at 4 rad/s.
fn tumbling(density: f64) -> String {
    floor(1e-3, 2.0, 0.0, 0.5) + &block("box", density, [0.0, 0.55], [0.5, 0.25], 3.0, 4.0)
}

#[test]
fn a_tumbling_box_of_any_mass_lands_and_slides_to_rest_by_coulomb_friction() {
    // Dropped turning, it bounces on its corners and slides; then, flat, it decelerates at
    // μ g and stops. Masses from 5 g to 5,000 t: every step's problem is solved.
    let mut reference = None;
    for density in [1e-2, 1.0, 1e2, 1e4, 1e7] {
        let scene = Scene::from_toml_str(&tumbling(density)).unwrap();
        let mut stepper = scene.stepper().unwrap();
        let mut path = Vec::new();
        for _ in 0..2000 {
            stepper.step().unwrap_or_else(|e| panic!("density {density}: {e}"));
            path.push(stepper.q()[0]);
        }
        let u = stepper.u();
        assert!(u.iter().all(|v| v.abs() < 1e-9), "density {density}: {u:?}");
        // The same motion for every mass: the units change only where the solver stops.
        let reference = reference.get_or_insert(path.clone());
        let worst = reference.iter().zip(&path).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(worst < 1e-12, "density {density}: {worst:e}");
    }
}

/// A chain of six links of 0.5 m hinged end to end from the ground, released horizontally,
/// their masses alternating between 1 kg and `ratio`, its contacts fixed or detected.
fn chain(ratio: f64, detected: bool) -> String {
    let set = if detected { "detected" } else { "fixed" };
    let mut text = format!(
        "dt = 1e-4\nt_end = 1.0\ngravity = [0.0, -9.81]\nprojection = true\n\
         contact_set = \"{set}\"\n[contacts_auto]\neps_n = 0.5\neps_t = 0.0\nmu = 0.3\n"
    );
    for k in 0..6 {
        let m = if k % 2 == 0 { 1.0 } else { ratio };
        let (a, anchor) =
            if k == 0 { ("ground".into(), 0.0) } else { (format!("l{}", k - 1), 0.25) };
        text += &format!(
            "[[bodies]]\nname = \"l{k}\"\ntype = \"dynamic\"\nmass = {m}\ninertia = {i}\n\
             position = [{x}, 0.0]\n\
             shapes = [{{ type = \"capsule\", a = [-0.25, 0.0], b = [0.25, 0.0], radius = 0.02 }}]\n\
             [[joints]]\ntype = \"revolute\"\nname = \"j{k}\"\nbody_a = \"{a}\"\n\
             anchor_a = [{anchor}, 0.0]\nbody_b = \"l{k}\"\nanchor_b = [-0.25, 0.0]\n",
            i = m * 0.25 / 12.0,
            x = 0.5 * k as f64 + 0.25,
        );
    }
    text
}

#[test]
fn a_chain_of_links_a_million_times_heavier_or_lighter_than_the_next_moves_alike_on_both_paths() {
    // Its joints' islands on the path of detected contacts: before small islands went on to
    // the large islands' chain, an island of the six joints alone stopped the run at step
    // 1,052 (ratio 10⁶) or 1,089 (ratio 10⁻⁶) at the iteration limit, its round-off above the
    // small islands' tolerance.
    for ratio in [1e6, 1e-6] {
        let run = |detected: bool| {
            let scene = Scene::from_toml_str(&chain(ratio, detected)).unwrap();
            let mut stepper = scene.stepper().unwrap();
            for step in 0..1500 {
                let report = stepper.step().unwrap_or_else(|e| panic!("{ratio} {step}: {e}"));
                assert!(report.joint_drift < 1e-8, "{ratio}, step {step}: {}", report.joint_drift);
            }
            stepper.q().to_vec()
        };
        let (fixed, detected) = (run(false), run(true));
        let worst = fixed.iter().zip(&detected).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(worst < 1e-12, "ratio {ratio}: {worst:e}");
    }
}

/// A box of 0.2 × 0.1 m dropped tilted onto a floor drawn as a slab `half_length` long on
/// either side, 2 s at Δt = 1 ms with the projection: its size and its pose at the end.
fn box_on_a_slab(half_length: f64) -> (f64, Vec<f64>) {
    let text = format!(
        "dt = 1e-3\nt_end = 2.0\ngravity = [0.0, -9.81]\n\
         [[bodies]]\nname = \"floor\"\ntype = \"fixed\"\nposition = [0.0, 0.0]\n\
         shapes = [{{ type = \"polygon\", vertices = [[-{half_length}, -1.0], \
         [{half_length}, -1.0], [{half_length}, 0.0], [-{half_length}, 0.0]] }}]\n\
         [[bodies]]\nname = \"box\"\ntype = \"dynamic\"\nmass = 1.0\ninertia = {}\n\
         position = [0.0, 0.1]\nangle = 0.05\nshapes = [{{ type = \"polygon\", vertices = \
         [[-0.1, -0.05], [0.1, -0.05], [0.1, 0.05], [-0.1, 0.05]] }}]\n\
         [[contacts]]\nname = \"c\"\nbody_a = \"floor\"\nbody_b = \"box\"\neps_n = 0.0\n\
         eps_t = 0.0\nmu = 0.5\n",
        (0.2f64 * 0.2 + 0.1 * 0.1) / 12.0
    );
    let scene = Scene::from_toml_str(&text).expect("scene reads");
    let ModelParams::Declared(spec) = &scene.params else { panic!("a declared scene") };
    let size = spec.build().expect("builds").size();
    let mut stepper = scene.stepper().expect("scene steps");
    stepper.run_until(2.0, &mut |_: &StepReport<'_>| ControlFlow::Continue(())).expect("run");
    (size, stepper.q().to_vec())
}

/// The size that the tolerances are relative to is the moving bodies': the box on a slab
/// 2 km long came to rest 0.6 mm deep and tilted, the slab making the size 1,200 m and the
/// projection's tolerance 1.2 mm. Whatever the slab's length, the box now ends where it ends
/// on a slab 2 m long, to the bit.
#[test]
fn the_fixed_geometry_drawn_around_a_mechanism_does_not_set_its_tolerances() {
    let (short_size, short) = box_on_a_slab(1.0);
    let (long_size, long) = box_on_a_slab(1000.0);
    // 0.6 times the diagonal of the box around the box turned by 0.05 rad.
    let (c, s) = (0.05f64.cos(), 0.05f64.sin());
    let diagonal = (0.2 * c + 0.1 * s).hypot(0.1 * c + 0.2 * s);
    assert!((short_size - 0.6 * diagonal).abs() < 1e-15, "{short_size}");
    assert_eq!(short_size, long_size);
    assert_eq!(short, long);
    assert!((long[1] - 0.05).abs() < 2e-5 && long[2].abs() < 1e-6, "{long:?}");
}
