//! The detected contact set against the fixed one: the same scene built both ways gives, at the
//! same (q, t), the same closed contacts with the same gaps, force directions, rheonomic terms
//! and laws; the identities are unique, increasing and stable; the mass blocks are the dense
//! mass matrix's; and the joints' rows split by body are the dense rows.

use moreau_kinematics::{ContactKinematics, Shape, SplitMix64};
use moreau_models::LawParams;
use moreau_models::bodies::{
    AutoContacts, BodySpec, ContactSet, ContactSpec, Multibody, MultibodyBuilder, PairOverride,
    SystemSpec,
};
use moreau_models::{ModelError, ModelParams, Scene};
use moreau_stepper::{BodyContact, Mechanism, NO_BODY};

/// One closed contact in the dense form: gap, w_N, w_T (length f), ŵ_N, ŵ_T and the law.
#[derive(Debug)]
struct Dense {
    gap: f64,
    w_n: Vec<f64>,
    w_t: Vec<f64>,
    hat: [f64; 2],
    law: [f64; 3],
}

fn law_of(c: &moreau_setvalued::ContactLaw) -> [f64; 3] {
    [c.eps_n(), c.eps_t(), c.mu()]
}

/// The fixed slots closed within `margin` (a found feature has a unit normal); `margin` must
/// be below the slots' own margin, the gap their open slots report.
fn fixed_closed(m: &Multibody, q: &[f64], t: f64, margin: f64) -> Vec<Dense> {
    let f = m.num_coordinates();
    let mut gaps = vec![0.0; m.num_contacts()];
    m.normal_gaps(q, t, &mut gaps);
    (0..m.num_contacts())
        .filter(|&i| gaps[i] <= margin)
        .filter_map(|i| {
            let g = m.contact_geometry(i, q, t);
            if g.normal == [0.0; 2] || g.gap > margin {
                return None;
            }
            let (mut w_n, mut w_t) = (vec![0.0; f], vec![0.0; f]);
            let p = m.contact(i, q, t, &mut w_n, &mut w_t);
            Some(Dense {
                gap: p.g_n,
                w_n,
                w_t,
                hat: [p.w_n_hat, p.w_t_hat],
                law: law_of(&m.laws()[i]),
            })
        })
        .collect()
}

/// A detected contact scattered into rows of length f.
fn scatter(c: &BodyContact, f: usize) -> Dense {
    let (mut w_n, mut w_t) = (vec![0.0; f], vec![0.0; f]);
    for s in 0..2 {
        if c.bodies[s] != NO_BODY {
            let k = 3 * c.bodies[s] as usize;
            for r in 0..3 {
                w_n[k + r] += c.w_n[s][r];
                w_t[k + r] += c.w_t[s][r];
            }
        }
    }
    Dense {
        gap: c.point.g_n,
        w_n,
        w_t,
        hat: [c.point.w_n_hat, c.point.w_t_hat],
        law: law_of(&c.law),
    }
}

fn distance(a: &Dense, b: &Dense) -> f64 {
    let rows = a.w_n.iter().zip(&b.w_n).chain(a.w_t.iter().zip(&b.w_t));
    let mut d = (a.gap - b.gap).abs() + (a.hat[0] - b.hat[0]).abs() + (a.hat[1] - b.hat[1]).abs();
    d += rows.map(|(x, y)| (x - y).abs()).sum::<f64>();
    d + a.law.iter().zip(&b.law).map(|(x, y)| (x - y).abs()).sum::<f64>()
}

/// Asserts that `detect` and the fixed slots give the same closed contacts, one for one, and
/// that the detected identities increase strictly. Returns the detected contacts.
fn same_contacts(
    fixed: &Multibody,
    detected: &Multibody,
    q: &[f64],
    t: f64,
    margin: f64,
) -> Vec<BodyContact> {
    let structure = detected.body_structure().expect("the detected set announces its bodies");
    assert!(fixed.body_structure().is_none());
    assert_eq!(detected.num_contacts(), 0);
    assert_eq!(structure.num_bodies() * 3, fixed.num_coordinates());
    let mut out = Vec::new();
    structure.detect(q, t, margin, &mut out);
    let dense = fixed_closed(fixed, q, t, margin);
    assert_eq!(out.len(), dense.len(), "detected {} contacts, fixed {}", out.len(), dense.len());
    assert!(out.windows(2).all(|w| w[0].id < w[1].id), "identities not increasing");
    let f = fixed.num_coordinates();
    let mut used = vec![false; dense.len()];
    for c in &out {
        let d = scatter(c, f);
        let (best, gap) = dense
            .iter()
            .enumerate()
            .filter(|(k, _)| !used[*k])
            .map(|(k, x)| (k, distance(x, &d)))
            .min_by(|x, y| x.1.total_cmp(&y.1))
            .expect("a fixed slot for every detected contact");
        assert!(gap < 1e-12, "contact {:x} differs from every fixed slot by {gap}: {d:?}", c.id);
        used[best] = true;
    }
    out
}

fn disk(r: f64) -> Shape {
    Shape::Disk { center: [0.0, 0.0], radius: r }
}

fn square(h: f64) -> Shape {
    Shape::Polygon { vertices: vec![[-h, -h], [h, -h], [h, h], [-h, h]] }
}

/// A heap of disks, boxes and capsules in a box of three half-planes, some touching and
/// overlapping, with collision groups that keep the boxes off each other, an explicit contact
/// declared from the later body to the earlier, and a pair with its own law.
fn heap(set: ContactSet) -> Multibody {
    let mut rng = SplitMix64::new(11);
    let mut b = MultibodyBuilder::new([0.0, -9.81]);
    b.add_body(
        BodySpec::fixed("box", [0.0, 0.0], 0.0)
            .with_shape(Shape::HalfPlane { point: [0.0, 0.0], normal: [0.0, 1.0] })
            .with_shape(Shape::HalfPlane { point: [-1.0, 0.0], normal: [1.0, 0.0] })
            .with_shape(Shape::HalfPlane { point: [1.0, 0.0], normal: [-1.0, 0.0] }),
    );
    for k in 0..40 {
        let p = [rng.uniform(-0.95, 0.95), rng.uniform(0.0, 0.5)];
        let angle = rng.uniform(-3.0, 3.0);
        let shape = match k % 4 {
            0 => square(rng.uniform(0.05, 0.08)),
            1 => Shape::Capsule { a: [-0.05, 0.0], b: [0.05, 0.0], radius: 0.03 },
            _ => disk(rng.uniform(0.04, 0.1)),
        };
        let mut body = BodySpec::with_density(&format!("b{k}"), 1000.0, p, angle).with_shape(shape);
        if k % 4 == 0 {
            // Boxes do not meet boxes.
            body.group = 2;
            body.mask = !2;
        }
        b.add_body(body);
    }
    // A body whose origin is not its centre of mass.
    b.add_body(
        BodySpec::with_density("offset", 500.0, [0.2, 0.1], 0.3)
            .with_shape(Shape::Disk { center: [0.03, 0.01], radius: 0.08 }),
    );
    let mut auto = AutoContacts::new(LawParams::new(0.2, 0.0, 0.4));
    auto.margin = Some(0.02);
    auto.overrides.push(PairOverride {
        bodies: ["b2".into(), "box".into()],
        eps_n: 0.7,
        eps_t: 0.0,
        mu: 0.9,
    });
    b.auto_contacts(auto);
    b.add_contact(ContactSpec {
        name: "late".into(),
        body_a: "b9".into(),
        shape_a: 0,
        body_b: "b5".into(),
        shape_b: 0,
        eps_n: 0.5,
        eps_t: 0.0,
        mu: 0.1,
        margin: Some(0.02),
    });
    b.with_contact_set(set);
    b.build().unwrap()
}

#[test]
fn a_heap_detects_the_fixed_slots_closed_contacts() {
    let (fixed, detected) = (heap(ContactSet::Fixed), heap(ContactSet::Detected));
    let (q0, _) = fixed.initial_state();
    let mut rng = SplitMix64::new(3);
    let mut total = 0;
    for round in 0..4 {
        let q: Vec<f64> =
            q0.iter().map(|v| v + 0.02 * round as f64 * rng.uniform(-1.0, 1.0)).collect();
        let out = same_contacts(&fixed, &detected, &q, 0.0, 0.01);
        total += out.len();
        // Walls and floors have no coordinates: each such contact has one NO_BODY side.
        assert!(out.iter().any(|c| c.bodies.contains(&NO_BODY)));
        assert!(out.iter().any(|c| !c.bodies.contains(&NO_BODY)));
    }
    assert!(total > 60, "too few contacts to compare: {total}");
}

#[test]
fn every_contact_is_located_on_its_bodies_with_its_gap() {
    let detected = heap(ContactSet::Detected);
    let (q0, _) = detected.initial_state();
    let names = detected.body_names();
    // The name of each body with coordinates, by its index in the body structure.
    let dynamic: Vec<&str> = detected
        .coordinate_names()
        .iter()
        .step_by(3)
        .map(|n| n.strip_suffix(".x").unwrap())
        .collect();
    let mut found = Vec::new();
    detected.body_structure().unwrap().detect(&q0, 0.0, 0.01, &mut found);
    assert!(found.len() > 20);
    for c in &found {
        let l = detected.locate_contact(c.id, &q0, 0.0, 0.01).expect("located");
        assert_eq!(l.geometry.gap, c.point.g_n);
        assert!((l.geometry.normal[0].hypot(l.geometry.normal[1]) - 1.0).abs() < 1e-12);
        for s in 0..2 {
            let name = names[l.bodies[s]];
            match c.bodies[s] {
                NO_BODY => assert!(!dynamic.contains(&name), "{name}"),
                k => assert_eq!(dynamic[k as usize], name),
            }
        }
    }
    // The explicit contact declared from b9 to b5 keeps that order: b9 (dynamic body 9) laid
    // on b5, two capsules of radius 0.03 m, 0.05 m apart.
    let mut q = q0.clone();
    let (x5, y5, a5) = (q0[15], q0[16], q0[17]);
    q[27..30].copy_from_slice(&[x5, y5 + 0.05, a5]);
    found.clear();
    detected.body_structure().unwrap().detect(&q, 0.0, 0.01, &mut found);
    let pairs: Vec<[&str; 2]> = found
        .iter()
        .map(|c| detected.locate_contact(c.id, &q, 0.0, 0.01).unwrap().bodies.map(|b| names[b]))
        .filter(|p| p.contains(&"b5") && p.contains(&"b9"))
        .collect();
    assert!(!pairs.is_empty() && pairs.iter().all(|p| *p == ["b9", "b5"]), "{pairs:?}");
    // An identity of no contact, and a contact farther than the margin, are not located.
    assert_eq!(detected.locate_contact(u64::MAX, &q0, 0.0, 0.01), None);
    let far: Vec<f64> =
        q0.iter().enumerate().map(|(i, v)| if i % 3 == 1 { v + 10.0 } else { *v }).collect();
    assert_eq!(detected.locate_contact(found[0].id, &far, 0.0, 0.01), None);
    // With the fixed contact set the identity is the contact's index.
    let fixed = heap(ContactSet::Fixed);
    for i in 0..fixed.num_contacts() {
        let l = fixed.locate_contact(i as u64, &q0, 0.0, 0.0).unwrap();
        assert_eq!(l.geometry, fixed.contact_geometry(i, &q0, 0.0));
    }
    assert_eq!(fixed.locate_contact(fixed.num_contacts() as u64, &q0, 0.0, 0.0), None);
}

#[test]
fn identities_are_stable_under_small_moves() {
    let detected = heap(ContactSet::Detected);
    let (q0, _) = detected.initial_state();
    let structure = detected.body_structure().unwrap();
    let (mut before, mut after) = (Vec::new(), Vec::new());
    structure.detect(&q0, 0.0, 0.01, &mut before);
    let mut rng = SplitMix64::new(5);
    let q: Vec<f64> = q0.iter().map(|v| v + 1e-7 * rng.uniform(-1.0, 1.0)).collect();
    structure.detect(&q, 0.0, 0.01, &mut after);
    // Contacts well inside the margin keep their identity and move by about the motion.
    let inside: Vec<&BodyContact> = before.iter().filter(|c| c.point.g_n < 0.009).collect();
    assert!(inside.len() > 10);
    for c in inside {
        let moved = after.iter().find(|d| d.id == c.id).expect("the contact keeps its identity");
        assert!((moved.point.g_n - c.point.g_n).abs() < 1e-6);
        assert_eq!(moved.bodies, c.bodies);
    }
    let mut ids: Vec<u64> = after.iter().map(|c| c.id).collect();
    ids.dedup();
    assert_eq!(ids.len(), after.len(), "identities unique");
}

#[test]
fn mass_blocks_are_the_dense_mass_matrix() {
    let m = heap(ContactSet::Detected);
    let (q0, _) = m.initial_state();
    let f = m.num_coordinates();
    let mut dense = vec![0.0; f * f];
    m.mass_matrix(&q0, 0.0, &mut dense);
    let structure = m.body_structure().unwrap();
    let mut blocks = vec![[0.0; 9]; structure.num_bodies()];
    structure.mass_blocks(&q0, 0.0, &mut blocks);
    let mut coupled = false;
    for (k, block) in blocks.iter().enumerate() {
        for c in 0..3 {
            for r in 0..3 {
                assert_eq!(block[r + 3 * c], dense[3 * k + r + (3 * k + c) * f]);
            }
        }
        coupled |= block[2] != 0.0;
    }
    assert!(coupled, "the offset body's block couples translation and rotation");
    // Everything off the blocks is zero.
    let on_blocks: f64 = blocks.iter().flatten().map(|v| v.abs()).sum();
    let all: f64 = dense.iter().map(|v| v.abs()).sum();
    assert_eq!(on_blocks, all);
}

fn declared(name: &str) -> SystemSpec {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(name);
    match Scene::from_path(&path).unwrap().params {
        ModelParams::Declared(s) => *s,
        other => panic!("not declared: {other:?}"),
    }
}

fn both(mut spec: SystemSpec) -> (Multibody, Multibody) {
    let fixed = spec.build().unwrap();
    spec.contact_set = ContactSet::Detected;
    (fixed, spec.build().unwrap())
}

#[test]
fn the_declared_ball_detects_its_floor_contact() {
    let (fixed, detected) = both(declared("bodies/ball.toml"));
    // The ball 1 mm into the floor, then 0.5 mm above it, then far above (no contact).
    for (y, expected) in [(0.099, 1), (0.1005, 1), (0.5, 0)] {
        let out = same_contacts(&fixed, &detected, &[0.0, y, 0.0], 0.0, 1e-3);
        assert_eq!(out.len(), expected, "y = {y}");
        if let Some(c) = out.first() {
            assert!((c.point.g_n - (y - 0.1)).abs() < 1e-15);
            assert_eq!(c.bodies, [NO_BODY, 0]);
            assert_eq!(c.w_n[1], [0.0, 1.0, 0.0]);
        }
    }
}

#[test]
fn the_declared_cam_detects_its_rheonomic_contact() {
    // The follower without its guide (joints need the fixed set): its knife edge on the
    // turning cam, at several angles, with the same ŵ_N from the cam's rotation.
    let mut spec = declared("bodies/cam.toml");
    spec.joints.clear();
    spec.contacts[0].margin = Some(1e-3);
    let (fixed, detected) = both(spec);
    let structure = detected.body_structure().unwrap();
    let mut seen = 0;
    for k in 0..4 {
        let t = 0.011 * k as f64;
        // The knife edge's height where it meets the cam's profile on the vertical through
        // the cam's centre, by bisection on the nearest gap.
        let gap = |y: f64| {
            let mut out = Vec::new();
            structure.detect(&[0.0, y, 0.0], t, 0.05, &mut out);
            out.iter().map(|c| c.point.g_n).fold(f64::INFINITY, f64::min)
        };
        let (mut lo, mut hi) = (0.0, 0.03);
        for _ in 0..50 {
            let mid = 0.5 * (lo + hi);
            if gap(mid) < 0.0 { lo = mid } else { hi = mid }
        }
        let out = same_contacts(&fixed, &detected, &[0.0, lo - 2e-5, 0.0], t, 5e-4);
        assert!(!out.is_empty(), "t = {t}");
        seen += out.iter().filter(|c| c.point.w_n_hat != 0.0).count();
        assert!(out.iter().all(|c| c.bodies == [NO_BODY, 0]));
    }
    assert!(seen > 0, "the turning cam gives rheonomic terms");
}

#[test]
fn ideal_joints_build_in_the_detected_mode() {
    // The cam's follower in its guide: the guide's rows split by body, one per row.
    let mut spec = declared("bodies/cam.toml");
    spec.contact_set = ContactSet::Detected;
    let m = spec.build().unwrap();
    let structure = m.body_structure().unwrap();
    let (q0, _) = m.initial_state();
    let mut rows = vec![moreau_stepper::BodyBilateral::default(); m.num_bilaterals()];
    structure.bilateral_rows(&q0, 0.0, &mut rows);
    assert!(!rows.is_empty());
    let f = m.num_coordinates();
    let mut w = vec![0.0; f];
    for (i, r) in rows.iter().enumerate() {
        let p = m.bilateral(i, &q0, 0.0, &mut w);
        assert_eq!(p, r.point);
        let mut split = vec![0.0; f];
        for s in 0..2 {
            if r.bodies[s] != NO_BODY {
                for k in 0..3 {
                    split[3 * r.bodies[s] as usize + k] += r.w[s][k];
                }
            }
        }
        assert_eq!(split, w, "row {i}");
    }
}

#[test]
fn the_contact_set_is_a_scene_field() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/bodies/ball.toml");
    let mut scene = Scene::from_path(&path).unwrap();
    assert!(!scene.to_toml_string().unwrap().contains("contact_set"), "the default is left out");
    scene.set("contact_set", "detected").unwrap();
    let text = scene.to_toml_string().unwrap();
    assert!(text.contains("contact_set = \"detected\""), "{text}");
    let again = Scene::from_toml_str(&text).unwrap();
    let model = again.build().unwrap();
    assert!(model.body_structure().is_some());
    let bad = text.replace("\"detected\"", "\"sometimes\"");
    match Scene::from_toml_str(&bad) {
        Err(ModelError::Parse { message, .. }) => {
            assert!(message.contains("sometimes"), "{message}")
        }
        other => panic!("expected a parse error, got {other:?}"),
    }
}

#[test]
fn detection_and_forces_are_the_same_on_one_and_two_threads() {
    // The disk column of 4,000 grains at its lattice places with a 6 mm margin: more than 5,000
    // contacts, each from its own pair of disks, and more colliders than the detection takes in
    // one piece: the frames, the boxes and the broad and narrow phases of chunks of colliders
    // run on two threads.
    let path = moreau_testsupport::scene_path("scale/disk-column.toml");
    let mut scene = Scene::from_path(&path).unwrap();
    scene.set("fill.grain.count", "4000").unwrap();
    let ModelParams::Declared(spec) = &scene.params else { panic!("a declared scene") };
    let column = spec.build().unwrap();
    let structure = column.body_structure().unwrap();
    let (q0, _) = column.initial_state();
    // The grains turned and spinning, so that h has its centrifugal and gravity terms.
    let q: Vec<f64> = q0.iter().enumerate().map(|(i, v)| v + 0.01 * (i % 3) as f64).collect();
    let u: Vec<f64> = (0..q.len()).map(|i| 0.1 * (i % 7) as f64).collect();
    let detect = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let mut out = Vec::new();
            structure.detect(&q0, 0.0, 0.006, &mut out);
            let mut h = vec![0.0; q.len()];
            column.forces(&q, &u, 0.0, &mut h);
            (out, h)
        })
    };
    let ((one, h_one), (two, h_two)) = (detect(1), detect(2));
    assert!(one.len() > 5000, "{} contacts", one.len());
    assert!(one.windows(2).all(|w| w[0].id < w[1].id), "identities not increasing");
    // Debug prints each number's shortest round-trip form: equal texts are equal bits.
    assert_eq!(format!("{one:?}"), format!("{two:?}"));
    assert!(h_one.iter().any(|&v| v != 0.0), "h is zero");
    assert_eq!(format!("{h_one:?}"), format!("{h_two:?}"), "the forces, body by body");
}

/// A square of 0.2 m dropped tilted onto a slab, declared once as a profile (the solid
/// bounded by a chain) and once as a polygon, runs to the same bits: it lands on a corner,
/// turns onto its face and rests on both corners at y = 0.1 m, on both paths. Declared as a
/// profile it used to find, at the steps where a side stood square to the slab, the slab's far
/// corner 1.17 m "deep" behind that side, and the projection threw the square more than
/// 0.5 m in one step.
#[test]
fn a_square_declared_as_a_profile_lands_and_rests_as_the_polygon_does() {
    let scene = |shape: &str, contact_set: &str| {
        format!(
            r#"
dt = 1e-3
t_end = 1.0
gravity = [0.0, -9.81]
contact_set = "{contact_set}"

[[bodies]]
name = "slab"
type = "fixed"
position = [0.0, 0.0]
shapes = [{{ type = "polygon", vertices = [[-1.0, -0.2], [1.0, -0.2], [1.0, 0.0], [-1.0, 0.0]] }}]

[[bodies]]
name = "square"
type = "dynamic"
mass = 1.0
inertia = 0.01
position = [0.03, 0.3]
angle = 0.2
shapes = [{{ type = "{shape}", {shape}s = [[-0.1, -0.1], [0.1, -0.1], [0.1, 0.1], [-0.1, 0.1]] }}]

[contacts_auto]
eps_n = 0.2
eps_t = 0.0
mu = 0.3
"#
        )
        .replace("polygons =", "vertices =")
        .replace("profiles =", "points =")
    };
    for contact_set in ["fixed", "detected"] {
        let mut ends = Vec::new();
        for shape in ["profile", "polygon"] {
            let scene = Scene::from_toml_str(&scene(shape, contact_set)).unwrap();
            let mut stepper = scene.stepper().unwrap();
            let (mut jump, mut deepest) = (0.0f64, 0.0f64);
            let mut last = stepper.q().to_vec();
            stepper
                .run_until(1.0, &mut |r: &moreau_stepper::StepReport<'_>| {
                    jump = jump.max((r.q[0] - last[0]).abs()).max((r.q[1] - last[1]).abs());
                    deepest = deepest.max(r.penetration);
                    last.copy_from_slice(r.q);
                    std::ops::ControlFlow::Continue(())
                })
                .unwrap();
            // Falling from 0.3 m, the square moves at most 2.5 mm per step.
            assert!(jump < 3e-3, "{shape}, {contact_set}: a step moved it by {jump} m");
            assert!(deepest < 1e-3, "{shape}, {contact_set}: {deepest} m deep");
            // It rests on its face within the projection's tolerance of 2 g Δt² = 1.96e-5 m,
            // which leaves its corners as deep as the scheme puts them (3.0e-6 m here).
            let tolerance = 2.0 * 9.81 * 1e-3 * 1e-3;
            assert!((last[1] - 0.1).abs() < tolerance, "{last:?}");
            assert!(last[2].abs() < tolerance / 0.1, "{last:?}");
            ends.push(last);
        }
        assert_eq!(ends[0], ends[1], "{contact_set}: profile and polygon");
    }
}
