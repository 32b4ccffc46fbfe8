//! Drawings: every model draws its parts in metres, and contact markers sit where the gaps
//! close.

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
