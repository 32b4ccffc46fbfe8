//! Drawings: every model draws its parts in metres, contact markers sit where the gaps close,
//! and a declared mechanism draws alike in any length unit.

use moreau_kinematics::ContactKinematics;
use moreau_models::*;

#[test]
fn every_model_draws_its_parts() {
    let expected: [(ModelKind, &[Role]); 6] = [
        (ModelKind::Ball, &[Role::Ground, Role::Ball]),
        (ModelKind::Woodpecker, &[Role::Pole, Role::Sleeve, Role::Bird, Role::Beak]),
        (ModelKind::SliderCrank, &[Role::Crank, Role::Rod, Role::Slider, Role::Guide]),
        (ModelKind::SliderCrankIdeal, &[Role::Crank, Role::Rod, Role::Slider, Role::Guide]),
        (ModelKind::Cam, &[Role::Cam, Role::Follower, Role::Guide]),
        (ModelKind::Painleve, &[Role::Ground, Role::Rod]),
    ];
    for (kind, roles) in expected {
        let model = Scene::report(kind).build().unwrap();
        let (q, _) = model.initial_state();
        let d = model.draw(&q, 0.0);
        for &role in roles {
            let (lines, circles) = d.count(role);
            assert!(lines + circles > 0, "{kind}: no {role:?}");
        }
        let b = d.bounds().unwrap();
        assert!(
            b.width() > 0.0 && b.height() > 0.0 && b.width().is_finite() && b.height().is_finite()
        );
        for p in d.polylines.iter().flat_map(|p| &p.points) {
            assert!(b.contains(*p));
        }
        // Every contact point of the model lies in the drawing's frame.
        let points = model.contact_points(&q, 0.0);
        assert_eq!(points.len(), model.num_contacts(), "{kind}");
        for p in points {
            assert!(b.contains(p), "{kind}: contact point {p:?} outside {b:?}");
        }
    }
    assert_eq!(Drawing::new().bounds(), None);
}

#[test]
fn woodpecker_beak_touches_the_pole_when_its_gap_closes() {
    let wp = Woodpecker::new(WoodpeckerParams::report()).unwrap();
    let p = wp.params();
    // g_N1 = 0 at φ_S = (l_M + l_G − l_S − r_O)/h_S.
    let phi_s = (p.l_m + p.l_g - p.l_s - p.r_o) / p.h_s;
    let q = [0.0, 0.0, phi_s];
    assert!(wp.normal_gap(0, &q, 0.0).abs() < 1e-15);
    let beak = wp.contact_points(&q, 0.0)[0];
    assert!((beak[0] - p.r_o).abs() < 1e-15, "beak tip at x = {}", beak[0]);
    let d = wp.draw(&q, 0.0);
    let tip = d.polylines.iter().find(|l| l.role == Role::Beak).unwrap().points[1];
    assert_eq!(tip, beak);
    assert!(d.circles.iter().any(|c| c.role == Role::ContactPoint && c.center == beak));
    // At the start only the lower sleeve edge is closed, and it lies on the pole's surface.
    let (q0, _) = wp.initial_state();
    let d0 = wp.draw(&q0, 0.0);
    let markers: Vec<_> = d0.circles.iter().filter(|c| c.role == Role::ContactPoint).collect();
    assert_eq!(markers.len(), 1);
    let lower = wp.contact_points(&q0, 0.0)[1];
    assert_eq!(markers[0].center, lower);
    assert!((lower[0] - p.r_o - wp.normal_gap(1, &q0, 0.0)).abs() < 1e-15);
}

#[test]
fn slider_corners_are_drawn_on_the_guide_when_they_touch() {
    let sc = SliderCrank::new(SliderCrankParams::report()).unwrap();
    let th2 = (0.0005f64 / 0.306).asin();
    let q = [0.0, th2, 0.0];
    let d = sc.draw(&q, 0.0);
    let markers: Vec<_> = d.circles.iter().filter(|c| c.role == Role::ContactPoint).collect();
    assert_eq!(markers.len(), 2);
    for m in markers {
        assert!((m.center[1] - 0.5 * sc.params().guide_width()).abs() < 1e-12);
    }
    let slider = d.polylines.iter().find(|l| l.role == Role::Slider).unwrap();
    assert_eq!(slider.points.len(), 4);
    assert!(slider.closed);
}

#[test]
fn cam_contact_point_lies_on_the_follower_face() {
    let cam = Cam::new(CamParams::report()).unwrap();
    for t in [0.005, 0.02, 0.04] {
        let s = cam.params().lift(t);
        let q = [s];
        assert!(cam.normal_gap(0, &q, t).abs() < 1e-15);
        let c = cam.contact_points(&q, t)[0];
        assert!((c[1] - cam.face_height(s)).abs() < 1e-15);
        let d = cam.draw(&q, t);
        assert!(d.circles.iter().any(|m| m.role == Role::ContactPoint && m.center == c));
        // The face is drawn at the contact height.
        let follower = d.polylines.iter().find(|l| l.role == Role::Follower).unwrap();
        assert_eq!(follower.points[0][1], c[1]);
    }
}

#[test]
fn bounds_union_and_ball_drawing() {
    let ball = Ball::new(BallParams::report()).unwrap();
    let d = ball.draw(&[0.5], 0.0);
    let b = d.bounds().unwrap();
    assert_eq!(b.max[1], 0.6);
    assert_eq!(b.min[1], 0.0);
    let on_floor = ball.draw(&[0.1], 0.0);
    assert_eq!(on_floor.count(Role::ContactPoint), (0, 1));
    let u = b.union(&on_floor.bounds().unwrap());
    // The contact marker (radius R/10) reaches below the floor.
    assert_eq!((u.min[1], u.max[1]), (-0.1 * 0.1, 0.6));
}

/// A pendulum on a revolute joint and a block on a prismatic one, declared in metres and in
/// millimetres: the second drawing is the first scaled by 1,000, its pins and joint axes
/// included (they are sized after the mechanism, not in metres: a pin of 1 cm drawn on a
/// 4 cm cam hid its follower, and would vanish on a mechanism of kilometres).
#[test]
fn a_declared_mechanism_draws_alike_in_any_length_unit() {
    let declared = |s: f64| {
        let text = format!(
            "dt = 0.001\nt_end = 0.01\ngravity = [0.0, {g:e}]\n\
             [[bodies]]\nname = \"bob\"\ntype = \"dynamic\"\nmass = 1.0\ninertia = {i:e}\n\
             position = [{x:e}, {y:e}]\n\
             shapes = [{{ type = \"disk\", center = [0.0, 0.0], radius = {r:e} }}]\n\
             [[bodies]]\nname = \"block\"\ntype = \"dynamic\"\nmass = 1.0\ninertia = {i:e}\n\
             position = [{bx:e}, 0.0]\n\
             shapes = [{{ type = \"polygon\", vertices = [[{m:e}, {m:e}], [{r:e}, {m:e}], \
             [{r:e}, {r:e}], [{m:e}, {r:e}]] }}]\n\
             [[joints]]\ntype = \"revolute\"\nname = \"hinge\"\nbody_a = \"ground\"\n\
             anchor_a = [0.0, 0.0]\nbody_b = \"bob\"\nanchor_b = [{ax:e}, {ay:e}]\n\
             [[joints]]\ntype = \"prismatic\"\nname = \"rail\"\nbody_a = \"ground\"\n\
             anchor_a = [{bx:e}, 0.0]\nbody_b = \"block\"\nanchor_b = [0.0, 0.0]\n\
             axis = [1.0, 0.0]\n",
            g = -9.81 * s,
            i = 1e-3 * s * s,
            x = 0.6 * s,
            y = -0.8 * s,
            r = 0.05 * s,
            m = -0.05 * s,
            bx = 1.5 * s,
            ax = -0.6 * s,
            ay = 0.8 * s,
        );
        let model = Scene::from_toml_str(&text).expect("scene").build().expect("model");
        let (q, _) = model.initial_state();
        model.draw(&q, 0.0)
    };
    let (metres, millimetres) = (declared(1.0), declared(1e3));
    assert_eq!(metres.circles.len(), millimetres.circles.len());
    assert!(metres.circles.iter().any(|c| c.role == Role::Joint), "{metres:?}");
    let close = |a: f64, b: f64| (a * 1e3 - b).abs() <= 1e-9 * (1.0 + b.abs());
    for (a, b) in metres.circles.iter().zip(&millimetres.circles) {
        assert_eq!(a.role, b.role);
        assert!(close(a.radius, b.radius), "{a:?} against {b:?}");
        assert!(close(a.center[0], b.center[0]) && close(a.center[1], b.center[1]), "{a:?}");
    }
    assert_eq!(metres.polylines.len(), millimetres.polylines.len());
    for (a, b) in metres.polylines.iter().zip(&millimetres.polylines) {
        assert_eq!((a.role, a.points.len()), (b.role, b.points.len()));
        for (p, q) in a.points.iter().zip(&b.points) {
            assert!(close(p[0], q[0]) && close(p[1], q[1]), "{a:?} against {b:?}");
        }
    }
}
