//! The contact kinematics of the report's models, built from the planar pairs and compared
//! with the closed forms of the specification, and the checker on the woodpecker's rows.

use approx::assert_relative_eq;
use moreau_kinematics::{
    Component, ContactGeometry, ContactKinematics, ContactPoint, FdOptions, KinematicsError,
    LineMotion, PointMotion, PoseMotion, SampleOptions, Side, assert_consistent, check_jacobians,
    corner_line, point_line, rectangle_corners, sample_states,
};
use moreau_testsupport::Pairs;
use nalgebra::{Matrix2x1, Matrix3, Point2, SVector, Vector1, Vector2, Vector3};

// Slider-crank with a translational clearance joint (section 7.3).
const L1: f64 = 0.153;
const L2: f64 = 0.306;
const A: f64 = 0.05;
const B: f64 = 0.025;
const C: f64 = 0.001;

/// Corner k (0-based) of the slider against its guide surface, from the slider's pose and the
/// chain rule through ∂(x3, y3, θ3)/∂q.
fn slider_corner(q: &SVector<f64, 3>, k: usize) -> Result<ContactGeometry<3>, KinematicsError> {
    let (th1, th2, th3) = (q[0], q[1], q[2]);
    let (c1, s1, c2, s2) = (th1.cos(), th1.sin(), th2.cos(), th2.sin());
    let slider = PoseMotion::body(L1 * c1 + L2 * c2, L1 * s1 + L2 * s2, th3);
    let d = 2.0 * B + C;
    // Corners 1, 2 touch the upper surface (open below it), 3, 4 the lower one; both
    // tangents point along +X as in the specification.
    let guide = if k < 2 {
        LineMotion::fixed(Point2::new(0.0, d / 2.0), 0.0, Side::Right)
    } else {
        LineMotion::fixed(Point2::new(0.0, -d / 2.0), 0.0, Side::Left)
    };
    let corners = rectangle_corners(A, B)?;
    let pose_jacobian = Matrix3::new(-L1 * s1, -L2 * s2, 0.0, L1 * c1, L2 * c2, 0.0, 0.0, 0.0, 1.0);
    Ok(corner_line(&slider, &corners[k], &guide)?.chain(&pose_jacobian, &Vector3::zeros()))
}

/// The gaps and rows of docs/theory.md §7.3, written out.
fn slider_corner_closed_form(
    q: &SVector<f64, 3>,
    k: usize,
) -> (f64, f64, Vector3<f64>, Vector3<f64>) {
    let (c1, s1, c2, s2) = (q[0].cos(), q[0].sin(), q[1].cos(), q[1].sin());
    let (c3, s3) = (q[2].cos(), q[2].sin());
    let (x3, y3, d) = (L1 * c1 + L2 * c2, L1 * s1 + L2 * s2, 2.0 * B + C);
    let wt = |third: f64| Vector3::new(-L1 * s1, -L2 * s2, third);
    match k {
        0 => (
            d / 2.0 - y3 + A * s3 - B * c3,
            x3 - A * c3 - B * s3,
            Vector3::new(-L1 * c1, -L2 * c2, A * c3 + B * s3),
            wt(A * s3 - B * c3),
        ),
        1 => (
            d / 2.0 - y3 - A * s3 - B * c3,
            x3 + A * c3 - B * s3,
            Vector3::new(-L1 * c1, -L2 * c2, -A * c3 + B * s3),
            wt(-A * s3 - B * c3),
        ),
        2 => (
            d / 2.0 + y3 - A * s3 - B * c3,
            x3 - A * c3 + B * s3,
            Vector3::new(L1 * c1, L2 * c2, -A * c3 + B * s3),
            wt(A * s3 + B * c3),
        ),
        _ => (
            d / 2.0 + y3 + A * s3 - B * c3,
            x3 + A * c3 + B * s3,
            Vector3::new(L1 * c1, L2 * c2, A * c3 + B * s3),
            wt(-A * s3 + B * c3),
        ),
    }
}

#[test]
fn slider_crank_corners_match_the_specification() {
    let samples = sample_states(
        &[0.0, 0.0, 0.0],
        0.0,
        SampleOptions { count: 20, q_radius: 3.0, t_radius: 0.0, seed: 73 },
    )
    .unwrap();
    for (q, _) in &samples {
        let q = SVector::<f64, 3>::from_column_slice(q);
        for k in 0..4 {
            let g = slider_corner(&q, k).unwrap();
            let (g_n, g_t, w_n, w_t) = slider_corner_closed_form(&q, k);
            assert_relative_eq!(g.g_n, g_n, epsilon = 1e-15);
            assert_relative_eq!(g.g_t, g_t, epsilon = 1e-15);
            assert_relative_eq!(g.w_n, w_n, epsilon = 1e-15);
            assert_relative_eq!(g.w_t, w_t, epsilon = 1e-15);
            assert_eq!((g.w_n_hat, g.w_t_hat), (0.0, 0.0));
        }
    }
    // All gaps are c/2 in the initial state.
    for k in 0..4 {
        assert_relative_eq!(
            slider_corner(&SVector::zeros(), k).unwrap().g_n,
            C / 2.0,
            epsilon = 1e-16
        );
    }
    let pairs = Pairs::<3> {
        contacts: (0..4)
            .map(|k| Box::new(move |q: &SVector<f64, 3>, _t| slider_corner(q, k)) as _)
            .collect(),
    };
    let report = assert_consistent(&pairs, &samples, 1e-8).unwrap();
    assert_eq!(report.contacts.len(), 4);
}

// Woodpecker toy (section 7.2), small-angle model.
const R_O: f64 = 0.0025;
const R_M: f64 = 0.0031;
const H_M: f64 = 0.0058;
const L_M: f64 = 0.0100;
const L_G: f64 = 0.0150;
const H_S: f64 = 0.0200;
const L_S: f64 = 0.0201;

/// The woodpecker's contacts as written in docs/theory.md §7.2; `misprint` puts lG in the second
/// entry of w_T1, as the source report prints it.
struct Woodpecker {
    misprint: bool,
}

impl Woodpecker {
    fn gaps(i: usize, q: &[f64]) -> (f64, f64) {
        let (y, phi_m, phi_s) = (q[0], q[1], q[2]);
        match i {
            0 => (L_M + L_G - L_S - R_O - H_S * phi_s, y + L_M * phi_m + (L_G - L_S) * phi_s),
            1 => (R_M - R_O + H_M * phi_m, y + R_M * phi_m),
            _ => (R_M - R_O - H_M * phi_m, y + R_M * phi_m),
        }
    }
}

impl ContactKinematics for Woodpecker {
    fn num_coordinates(&self) -> usize {
        3
    }
    fn num_contacts(&self) -> usize {
        3
    }
    fn normal_gap(&self, i: usize, q: &[f64], _t: f64) -> f64 {
        Self::gaps(i, q).0
    }
    fn contact(
        &self,
        i: usize,
        q: &[f64],
        _t: f64,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) -> ContactPoint {
        let (rows_n, rows_t) = match i {
            0 => ([0.0, 0.0, -H_S], [1.0, if self.misprint { L_G } else { L_M }, L_G - L_S]),
            1 => ([0.0, H_M, 0.0], [1.0, R_M, 0.0]),
            _ => ([0.0, -H_M, 0.0], [1.0, R_M, 0.0]),
        };
        w_n.copy_from_slice(&rows_n);
        w_t.copy_from_slice(&rows_t);
        let (g_n, g_t) = Self::gaps(i, q);
        ContactPoint { g_n, g_t, w_n_hat: 0.0, w_t_hat: 0.0 }
    }
}

#[test]
fn woodpecker_rows_pass_and_the_misprinted_row_is_flagged() {
    let samples = sample_states(
        &[0.0, -0.1036, -0.2788],
        0.0,
        SampleOptions { q_radius: 0.05, ..Default::default() },
    )
    .unwrap();
    // Contact 2 is closed at t = 0 with g_N2 = −8.8e-7 m.
    assert_relative_eq!(Woodpecker::gaps(1, &samples[0].0).0, -8.8e-7, epsilon = 1e-12);
    let report = assert_consistent(&Woodpecker { misprint: false }, &samples, 1e-9).unwrap();
    assert!(report.worst().unwrap().abs < 1e-10);

    let report =
        check_jacobians(&Woodpecker { misprint: true }, &samples, FdOptions::default()).unwrap();
    let worst = report.worst().unwrap();
    assert_eq!((worst.contact, worst.component), (0, Component::WT { coordinate: 1 }));
    assert_relative_eq!(worst.abs, L_G - L_M, epsilon = 1e-9);
    assert_relative_eq!(worst.reference, L_M, epsilon = 1e-9);
    assert!(report.contacts[1].scaled < 1e-10 && report.contacts[2].scaled < 1e-10);
    assert!(!report.passed(1e-6));
    assert_eq!(report.failures(1e-6).map(|m| m.contact).collect::<Vec<_>>(), vec![0]);
    match assert_consistent(&Woodpecker { misprint: true }, &samples, 1e-6) {
        Err(KinematicsError::JacobianMismatch {
            contact: 0,
            component: Component::WT { coordinate: 1 },
            abs,
            ..
        }) => {
            assert_relative_eq!(abs, 0.005, epsilon = 1e-9)
        }
        other => panic!("expected a mismatch of w_T1[1], got {other:?}"),
    }
}

/// The Painlevé rod's lower end against the ground (section 7.5), tangent along −X.
fn painleve(q: &SVector<f64, 3>, s: f64) -> Result<ContactGeometry<3>, KinematicsError> {
    let rod = PoseMotion::body(q[0], q[1], q[2]);
    let ground = LineMotion::fixed(Point2::origin(), std::f64::consts::PI, Side::Right);
    corner_line(&rod, &Point2::new(-s, 0.0), &ground)
}

#[test]
fn painleve_rod_matches_the_specification() {
    let s = 1.0;
    let phi0 = 2f64.atan();
    for (q, _) in
        sample_states(&[0.3, s * phi0.sin(), phi0], 0.0, SampleOptions::default()).unwrap()
    {
        let q = SVector::<f64, 3>::from_column_slice(&q);
        let g = painleve(&q, s).unwrap();
        let (x, y, phi) = (q[0], q[1], q[2]);
        assert_relative_eq!(g.g_n, y - s * phi.sin(), epsilon = 1e-15);
        assert_relative_eq!(g.g_t, s * phi.cos() - x, epsilon = 1e-15);
        assert_relative_eq!(g.w_n, Vector3::new(0.0, 1.0, -s * phi.cos()), epsilon = 1e-15);
        assert_relative_eq!(g.w_t, Vector3::new(-1.0, 0.0, -s * phi.sin()), epsilon = 1e-15);
    }
    // In the initial state the end touches the ground.
    assert_relative_eq!(
        painleve(&Vector3::new(0.0, s * phi0.sin(), phi0), s).unwrap().g_n,
        0.0,
        epsilon = 1e-15
    );
}

// Cam with a translating flat-face follower (section 7.4).
const OMEGA: f64 = 20.94;
const LIFT: f64 = 0.017;
const LOBES: f64 = 6.0;

/// Cam lift s(t) and ds/dt with β = 2π/N (the rise spans the whole lobe).
fn cam_lift(t: f64) -> (f64, f64) {
    let beta = 2.0 * std::f64::consts::PI / LOBES;
    let psi = (OMEGA * t).rem_euclid(beta);
    let x = psi / beta;
    let tau = 2.0 * std::f64::consts::PI;
    (LIFT * (x - (tau * x).sin() / tau), LIFT * OMEGA / beta * (1.0 - (tau * x).cos()))
}

fn cam(q: &SVector<f64, 1>, t: f64) -> Result<ContactGeometry<1>, KinematicsError> {
    let (s, ds) = cam_lift(t);
    let follower = PointMotion {
        position: Point2::new(0.0, q[0]),
        jacobian: Matrix2x1::new(0.0, 1.0),
        time_derivative: Vector2::zeros(),
    };
    let cam_face =
        LineMotion::rheonomic(Point2::new(0.0, s), Vector2::new(0.0, ds), 0.0, 0.0, Side::Left);
    point_line(&follower, &cam_face)
}

#[test]
fn cam_contact_is_rheonomic_with_the_lift_speed() {
    let t = 0.01;
    let (s, ds) = cam_lift(t);
    let g = cam(&Vector1::new(0.012), t).unwrap();
    assert_relative_eq!(g.g_n, 0.012 - s, epsilon = 1e-15);
    assert_eq!(g.w_n, Vector1::new(1.0));
    assert_eq!(g.w_n_hat, -ds);
    // γ_N = v − ds/dt: a follower moving with the cam surface keeps the gap.
    assert_relative_eq!(g.normal_velocity(&Vector1::new(ds)), 0.0, epsilon = 1e-15);
    // Sample times inside the first lobe's rise (0 < ψ < β), away from the drop.
    let pairs = Pairs::<1> { contacts: vec![Box::new(cam)] };
    let samples = sample_states(
        &[0.01],
        0.025,
        SampleOptions { count: 10, q_radius: 0.005, t_radius: 0.02, seed: 2 },
    )
    .unwrap();
    let report =
        check_jacobians(&pairs, &samples, FdOptions { t_scale: 1e-2, ..FdOptions::default() })
            .unwrap();
    assert!(report.passed(1e-6), "{:?}", report.worst());
    // Leaving out ŵ_N (a scleronomic cam) is flagged in the time derivative.
    let frozen = Pairs::<1> {
        contacts: vec![Box::new(|q: &SVector<f64, 1>, t| {
            let mut g = cam(q, t)?;
            g.w_n_hat = 0.0;
            Ok(g)
        })],
    };
    let report =
        check_jacobians(&frozen, &samples, FdOptions { t_scale: 1e-2, ..FdOptions::default() })
            .unwrap();
    assert_eq!(report.worst().unwrap().component, Component::WNHat);
    assert!(!report.passed(1e-3));
}
