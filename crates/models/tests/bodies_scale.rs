//! Generated bodies (`[[fill]]`) and the scale scenes: the fills expand into the counts,
//! places and sizes they declare, bad fills name their field, and each scale scene loads,
//! builds and detects the initial contacts its layout implies.

use moreau_kinematics::{ContactKinematics, Shape};
use moreau_models::bodies::{BodySpec, FillPattern, FillSpec, Multibody, SystemSpec};
use moreau_models::{ModelError, ModelParams, Scene};
use moreau_stepper::{BodyContact, Mechanism, NO_BODY};

fn scene(name: &str) -> Scene {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/scale").join(name);
    Scene::from_path(&path).unwrap()
}

fn spec(scene: &Scene) -> SystemSpec {
    match &scene.params {
        ModelParams::Declared(s) => (**s).clone(),
        other => panic!("not declared: {other:?}"),
    }
}

fn contacts(m: &Multibody, margin: f64) -> Vec<BodyContact> {
    let (q0, _) = m.initial_state();
    let mut out = Vec::new();
    m.body_structure().expect("detected").detect(&q0, 0.0, margin, &mut out);
    out
}

fn radius(m: &Multibody, body: usize) -> f64 {
    match &m.spec().fill[0].shape {
        Shape::Disk { radius, .. } => {
            // The body's mass is ρ π r², so its radius follows from its mass.
            let (mass, _, _) = m.mass_properties(body).unwrap();
            let _ = radius;
            (mass / (m.spec().fill[0].density * std::f64::consts::PI)).sqrt()
        }
        other => panic!("not a disk: {other:?}"),
    }
}

#[test]
fn the_disk_column_fills_its_box_and_touches_nothing_at_first() {
    let s = scene("disk-column.toml");
    let m = spec(&s).build().unwrap();
    let names = m.body_names();
    assert_eq!(names.len(), 101);
    assert_eq!((names[0], names[1], names[100]), ("box", "grain0", "grain99"));
    assert_eq!(m.num_coordinates(), 300);
    assert_eq!(m.num_contacts(), 0, "no slots in the detected set");
    // Radii in [0.8 r, 1.2 r], spread over the range; places within the jitter of the lattice.
    let radii: Vec<f64> = (1..=100).map(|b| radius(&m, b)).collect();
    assert!(radii.iter().all(|r| (0.008..=0.012).contains(r)), "{radii:?}");
    let (lo, hi) = radii.iter().fold((1.0f64, 0.0f64), |(l, h), r| (l.min(*r), h.max(*r)));
    assert!(lo < 0.0085 && hi > 0.0115, "radii not spread: {lo} {hi}");
    let poses = m.body_poses(&m.initial_state().0, 0.0);
    for (k, p) in poses[1..].iter().enumerate() {
        let place = [-0.1875 + 0.025 * (k % 16) as f64, 0.013 + 0.025 * (k / 16) as f64];
        assert!((p[0] - place[0]).abs() <= 5e-4 && (p[1] - place[1]).abs() <= 5e-4, "{k}: {p:?}");
    }
    // Nothing overlaps at t = 0; within 6 mm, each of the 16 grains of the bottom row sees
    // the floor (their gaps are 0.5 to 5.5 mm) and nothing else has a floor contact.
    let near = contacts(&m, 0.006);
    assert!(near.iter().all(|c| c.point.g_n >= 0.0));
    let floor: Vec<&BodyContact> =
        near.iter().filter(|c| c.bodies[0] == NO_BODY && c.w_n[1] == [0.0, 1.0, 0.0]).collect();
    assert_eq!(floor.len(), 16);
    assert!(floor.iter().all(|c| (c.bodies[1] as usize) < 16));
    // --set reaches the count: the column of 1000 has 1000 grains.
    let mut big = s.clone();
    big.set("fill.grain.count", "1000").unwrap();
    let m = big.build().unwrap();
    assert_eq!(m.num_coordinates(), 3000);
}

#[test]
fn the_pyramid_has_its_rows_and_its_ground_contacts() {
    let s = scene("pyramid.toml");
    let m = spec(&s).build().unwrap();
    assert_eq!(m.num_coordinates(), 3 * 55);
    let poses = m.body_poses(&m.initial_state().0, 0.0);
    // Row i has 10 − i boxes at height 0.501 + 1.002 i, the top one centred over the base.
    assert!((poses[55][1] - (0.501 + 9.0 * 1.002)).abs() < 1e-12);
    assert!((poses[55][0] - (-4.59 + 4.5 * 1.02)).abs() < 1e-12);
    // Within 5 mm: two corners of each base box on the ground (gap 1 mm), and each box of the
    // upper rows on the two below it (gap 2 mm); the 20 mm gaps within a row stay open.
    let near = contacts(&m, 0.005);
    let ground = near.iter().filter(|c| c.bodies[0] == NO_BODY).count();
    assert_eq!(ground, 20);
    for c in near.iter().filter(|c| c.bodies[0] != NO_BODY) {
        let (a, b) = (poses[c.bodies[0] as usize + 1], poses[c.bodies[1] as usize + 1]);
        assert!((a[1] - b[1]).abs() > 0.5, "a contact within a row: {c:?}");
        assert!((c.point.g_n - 0.002).abs() < 1e-12);
    }
    let stacked = near.len() - ground;
    assert!(stacked >= 2 * 45, "{stacked} contacts between rows");
    let mut big = s.clone();
    big.set("fill.box.base", "100").unwrap();
    assert_eq!(big.build().unwrap().num_coordinates(), 3 * 5050);
}

#[test]
fn the_granular_flow_rests_its_bottom_row_above_the_ramp() {
    let s = scene("granular-flow.toml");
    let m = spec(&s).build().unwrap();
    assert_eq!(m.num_coordinates(), 3 * 600);
    let near = contacts(&m, 0.2);
    assert!(near.iter().all(|c| c.point.g_n > 0.0), "nothing overlaps at t = 0");
    // The ramp's normal is (sin 20°, cos 20°), the back wall's +x.
    let (s20, c20) = 0.3490658504f64.sin_cos();
    let ramp = near.iter().filter(|c| c.bodies[0] == NO_BODY && (c.w_n[1][1] - c20).abs() < 1e-12);
    assert!(ramp.count() >= 20, "the bottom row sees the ramp");
    assert!(near.iter().any(|c| c.bodies[0] == NO_BODY && (c.w_n[1][0] - 1.0).abs() < 1e-12));
    assert!(near.iter().any(|c| c.bodies[0] == NO_BODY && (c.w_n[1][0] - s20).abs() < 1e-12));
}

fn fill() -> FillSpec {
    FillSpec::lattice(
        "grain",
        10,
        4,
        [0.0, 0.0],
        [0.1, 0.1],
        Shape::Disk { center: [0.0, 0.0], radius: 0.04 },
        1000.0,
    )
}

fn build_with(f: FillSpec) -> Result<Multibody, ModelError> {
    let mut b = moreau_models::bodies::MultibodyBuilder::new([0.0, -9.81]);
    b.add_body(BodySpec::fixed("floor", [0.0, -1.0], 0.0));
    b.add_fill(f);
    b.build()
}

fn key(e: ModelError) -> String {
    match e {
        ModelError::InvalidParameter { field, .. } => field,
        ModelError::BadValue { key, .. } => key,
        other => panic!("not a field error: {other:?}"),
    }
}

#[test]
fn fills_are_seeded_and_name_their_fields_when_wrong() {
    let mut f = fill();
    f.scale = [0.8, 1.2];
    f.jitter = 0.001;
    let a = build_with(f.clone()).unwrap();
    assert_eq!(
        a.body_names()[1..],
        [
            "grain0", "grain1", "grain2", "grain3", "grain4", "grain5", "grain6", "grain7",
            "grain8", "grain9"
        ]
    );
    // The same seed gives the same bodies; another seed others.
    assert_eq!(a.initial_state(), build_with(f.clone()).unwrap().initial_state());
    let mut other = f.clone();
    other.seed = 2;
    assert_ne!(a.initial_state(), build_with(other).unwrap().initial_state());
    let mut pyramid = fill();
    pyramid.pattern = FillPattern::Pyramid;
    pyramid.count = None;
    pyramid.columns = None;
    pyramid.base = Some(4);
    assert_eq!(build_with(pyramid.clone()).unwrap().num_coordinates(), 30);
    let cases: Vec<(FillSpec, &str)> = vec![
        (FillSpec { count: None, ..fill() }, "fill.grain.count"),
        (FillSpec { columns: Some(0), ..fill() }, "fill.grain.columns"),
        (FillSpec { base: Some(3), ..fill() }, "fill.grain.base"),
        (FillSpec { count: Some(3), ..pyramid }, "fill.grain.count"),
        (FillSpec { spacing: [0.07, 0.1], ..fill() }, "fill.grain.spacing.0"),
        (FillSpec { jitter: 0.02, ..fill() }, "fill.grain.spacing.0"),
        (FillSpec { scale: [1.2, 0.8], ..fill() }, "fill.grain.scale.1"),
        (FillSpec { density: 0.0, ..fill() }, "fill.grain.density"),
        (FillSpec { jitter: -1.0, ..fill() }, "fill.grain.jitter"),
        (
            FillSpec {
                shape: Shape::HalfPlane { point: [0.0, 0.0], normal: [0.0, 1.0] },
                ..fill()
            },
            "fill.grain.shape",
        ),
        (FillSpec { origin: [f64::NAN, 0.0], ..fill() }, "fill.grain.origin.0"),
    ];
    for (f, field) in cases {
        assert_eq!(key(build_with(f).unwrap_err()), field);
    }
}

#[test]
fn a_fill_table_with_an_unknown_field_is_named() {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../scenes/scale/disk-column.toml"),
    )
    .unwrap()
    .replace("jitter = 0.0005", "jiter = 0.0005");
    match Scene::from_toml_str(&text) {
        Err(ModelError::Parse { field, .. }) => {
            assert_eq!(field.as_deref(), Some("fill.grain.jiter"))
        }
        other => panic!("expected a parse error, got {other:?}"),
    }
}

#[test]
fn the_settling_scenes_name_their_inexact_residual_and_keep_it_through_set_and_toml() {
    let column = scene("disk-column.toml");
    assert_eq!(column.inexact_residual, 1e-3);
    assert_eq!(column.stepper_options().inexact_residual, 1e-3);
    assert_eq!(scene("pyramid.toml").stepper_options().inexact_residual, 1e-4);
    assert_eq!(scene("granular-flow.toml").inexact_residual, 1e-4);
    let mut s = scene("disk-column.toml");
    s.set("inexact_residual", "2e-4").unwrap();
    assert_eq!(s.stepper_options().inexact_residual, 2e-4);
    let again = Scene::from_toml_str(&s.to_toml_string().unwrap()).unwrap();
    assert_eq!(again, s);
    // A value the stepper would refuse is refused by the scene itself, naming the field, and
    // leaves the scene as it was.
    match s.set("inexact_residual", "1.5") {
        Err(moreau_models::ModelError::BadValue { key, value, reason }) => {
            assert_eq!((key.as_str(), value.as_str()), ("inexact_residual", "1.5"));
            assert!(reason.starts_with("must lie in [0, 1)"), "{reason}");
        }
        other => panic!("1.5 is not a residual to accept: {other:?}"),
    }
    assert_eq!(s, again);
}

/// Steps `s` to `t_end`; the information of every step taken above the solvers' tolerance, or
/// the error that ended the run.
fn inexact_steps(s: &Scene, t_end: f64) -> Result<Vec<moreau_stepper::LcpInfo>, String> {
    let mut stepper = s.stepper().unwrap();
    let mut seen = Vec::new();
    while stepper.t() < t_end - 1e-9 {
        let report = stepper.step().map_err(|e| e.to_string())?;
        seen.extend(report.lcp.filter(|info| info.inexact().is_some()));
    }
    Ok(seen)
}

#[test]
fn the_settling_column_takes_its_slow_islands_within_the_limit_before_the_budget() {
    // Solved to 1e-10 by the whole chain (Gauss-Seidel's 5,000 sweeps, then Newton, the
    // proximal stage, more sweeps and pivoting), the 100-disk column's landings go through.
    let mut strict = scene("disk-column.toml");
    strict.set("inexact_residual", "0").unwrap();
    assert_eq!(inexact_steps(&strict, 1.0).unwrap(), Vec::new());
    // With the scene's 1e-3, the islands whose Gauss-Seidel residual falls too slowly to reach
    // the tolerance within the budget are taken once within the limit: after at least one
    // chunk of 250 sweeps and well before the 5,000, with their residual reported.
    let seen = inexact_steps(&scene("disk-column.toml"), 1.0).unwrap();
    assert!(!seen.is_empty());
    for info in &seen {
        assert_eq!(info.status, moreau_lcp::Status::IterationLimit);
        assert!((250..5_000).contains(&info.iterations), "{info:?}");
        assert!(info.residual > 1e-10 && info.residual < 1e-2, "{info:?}");
    }
}
