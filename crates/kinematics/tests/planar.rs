//! The planar contact pairs against hand-computed values, finite differences and the relative
//! velocity of the material contact points.

use approx::assert_relative_eq;
use moreau_kinematics::{
    Circle, ContactGeometry, FdOptions, KinematicsError, LineMotion, PointMotion, PoseMotion,
    SampleOptions, Side, check_jacobians, circle_circle, circle_line, corner_line, point_line,
    rectangle_corners, sample_states,
};
use moreau_testsupport::Pairs;
use nalgebra::{Matrix2x1, Matrix3x2, Point2, SMatrix, SVector, Vector2, Vector3};
use proptest::prelude::*;

/// Drift of body B with time in the tests with a rheonomic line: (ẋ, ẏ, θ̇).
const DRIFT: [f64; 3] = [0.5, -0.2, 0.7];

/// The pose of body A, coordinates q[0..3] = (x, y, θ), as a motion of six coordinates.
fn body_a(q: &SVector<f64, 6>) -> PoseMotion<6> {
    let mut jacobian = SMatrix::<f64, 3, 6>::zeros();
    jacobian.fixed_view_mut::<3, 3>(0, 0).fill_with_identity();
    PoseMotion::from_parts(Vector3::new(q[0], q[1], q[2]), jacobian, Vector3::zeros())
}

/// The pose of body B, coordinates q[3..6] plus the drift [`DRIFT`] t.
fn body_b(q: &SVector<f64, 6>, t: f64) -> PoseMotion<6> {
    let mut jacobian = SMatrix::<f64, 3, 6>::zeros();
    jacobian.fixed_view_mut::<3, 3>(0, 3).fill_with_identity();
    let pose = Vector3::new(q[3] + DRIFT[0] * t, q[4] + DRIFT[1] * t, q[5] + DRIFT[2] * t);
    PoseMotion::from_parts(pose, jacobian, Vector3::from(DRIFT))
}

/// The velocity of the material point `x` of body B (coordinates q[3..6], with drift).
fn material_velocity_b(
    q: &SVector<f64, 6>,
    u: &SVector<f64, 6>,
    t: f64,
    x: &Point2<f64>,
) -> Vector2<f64> {
    let b = body_b(q, t);
    let omega = u[5] + DRIFT[2];
    let r = x - b.origin.position;
    Vector2::new(u[3] + DRIFT[0], u[4] + DRIFT[1]) + Vector2::new(-r.y, r.x) * omega
}

/// The velocity of the material point `x` of body A (coordinates q[0..3]).
fn material_velocity_a(q: &SVector<f64, 6>, u: &SVector<f64, 6>, x: &Point2<f64>) -> Vector2<f64> {
    let r = x - Point2::new(q[0], q[1]);
    Vector2::new(u[0], u[1]) + Vector2::new(-r.y, r.x) * u[2]
}

const POINT_LOCAL: [f64; 2] = [0.3, -0.2];
const LINE_LOCAL: [f64; 3] = [0.1, 0.4, 0.3];

fn point_on_a_against_line_on_b(
    q: &SVector<f64, 6>,
    t: f64,
    side: Side,
) -> Result<ContactGeometry<6>, KinematicsError> {
    let point = body_a(q).point(&Point2::new(POINT_LOCAL[0], POINT_LOCAL[1]));
    let line = body_b(q, t).line(&Point2::new(LINE_LOCAL[0], LINE_LOCAL[1]), LINE_LOCAL[2], side);
    point_line(&point, &line)
}

fn circle_on_a_against_line_on_b(
    q: &SVector<f64, 6>,
    t: f64,
    radius: f64,
    side: Side,
) -> Result<ContactGeometry<6>, KinematicsError> {
    let circle = body_a(q).circle(&Point2::new(POINT_LOCAL[0], POINT_LOCAL[1]), radius);
    let line = body_b(q, t).line(&Point2::new(LINE_LOCAL[0], LINE_LOCAL[1]), LINE_LOCAL[2], side);
    circle_line(&circle, &line)
}

fn circles(
    q: &SVector<f64, 6>,
    t: f64,
    ra: f64,
    rb: f64,
) -> Result<ContactGeometry<6>, KinematicsError> {
    let a = body_a(q).circle(&Point2::origin(), ra);
    let b = body_b(q, t).circle(&Point2::origin(), rb);
    circle_circle(&a, &b)
}

fn moving_pairs() -> Pairs<6> {
    Pairs {
        contacts: vec![
            Box::new(|q, t| point_on_a_against_line_on_b(q, t, Side::Left)),
            Box::new(|q, t| point_on_a_against_line_on_b(q, t, Side::Right)),
            Box::new(|q, t| circle_on_a_against_line_on_b(q, t, 0.25, Side::Left)),
            Box::new(|q, t| circle_on_a_against_line_on_b(q, t, 0.25, Side::Right)),
            Box::new(|q, t| circles(q, t, 0.4, 0.7)),
        ],
    }
}

#[test]
fn point_against_fixed_lines_hand_values() {
    // The point (2, 1) moving with q = (x, y): ∂p/∂q = I.
    let point = PointMotion::<2> {
        position: Point2::new(2.0, 1.0),
        jacobian: SMatrix::identity(),
        time_derivative: Vector2::zeros(),
    };
    let floor = LineMotion::fixed(Point2::new(0.0, 0.5), 0.0, Side::Left);
    let g = point_line(&point, &floor).unwrap();
    assert_eq!((g.g_n, g.g_t), (0.5, 2.0));
    assert_eq!((g.w_n, g.w_t), (Vector2::new(0.0, 1.0), Vector2::new(1.0, 0.0)));
    assert_eq!((g.w_n_hat, g.w_t_hat), (0.0, 0.0));

    // A line through the origin at 30°: n = (−1/2, √3/2), t = (√3/2, 1/2).
    let incline = LineMotion::fixed(Point2::origin(), std::f64::consts::FRAC_PI_6, Side::Left);
    let g = point_line(&point, &incline).unwrap();
    let s3 = 3f64.sqrt();
    assert_relative_eq!(g.g_n, -1.0 + s3 / 2.0, epsilon = 1e-15);
    assert_relative_eq!(g.g_t, s3 + 0.5, epsilon = 1e-15);
    assert_relative_eq!(g.w_n, Vector2::new(-0.5, s3 / 2.0), epsilon = 1e-15);
    assert_relative_eq!(g.w_t, Vector2::new(s3 / 2.0, 0.5), epsilon = 1e-15);

    // The same line with the open side on the right flips n (and g_N) but not t.
    let g_right = point_line(
        &point,
        &LineMotion::fixed(Point2::origin(), std::f64::consts::FRAC_PI_6, Side::Right),
    )
    .unwrap();
    assert_relative_eq!(g_right.g_n, -g.g_n, epsilon = 1e-15);
    assert_relative_eq!(g_right.w_n, -g.w_n, epsilon = 1e-15);
    assert_eq!(g_right.g_t, g.g_t);
}

#[test]
fn point_against_rotating_line_hand_values() {
    // A fixed point (0, 1) and a line through the origin turning at ω = 2 rad/s, at angle 0:
    // g_N = nᵀp = 1, g_T = 0, ŵ_N = −s (tᵀd) ω = 0, ŵ_T = s (nᵀd) ω = 2.
    let point = PointMotion::<1>::fixed(Point2::new(0.0, 1.0));
    let line = LineMotion::rheonomic(Point2::origin(), Vector2::zeros(), 0.0, 2.0, Side::Left);
    let g = point_line(&point, &line).unwrap();
    assert_eq!((g.g_n, g.g_t, g.w_n_hat, g.w_t_hat), (1.0, 0.0, 0.0, 2.0));
    // At the point (3, 1): ŵ_N = −3·2 = −6 (the line rises under the point).
    let g = point_line(&PointMotion::<1>::fixed(Point2::new(3.0, 1.0)), &line).unwrap();
    assert_eq!((g.g_n, g.g_t, g.w_n_hat, g.w_t_hat), (1.0, 3.0, -6.0, 2.0));
    // A line translating upward at 0.5 m/s under a fixed point: ŵ_N = −0.5.
    let lift =
        LineMotion::rheonomic(Point2::origin(), Vector2::new(0.0, 0.5), 0.0, 0.0, Side::Left);
    assert_eq!(point_line(&point, &lift).unwrap().w_n_hat, -0.5);
}

#[test]
fn rolling_disk_on_floor_hand_values() {
    // q = (x, y, φ) of a disk of radius 0.2 on the floor y = 0.
    let disk = PoseMotion::body(1.0, 0.25, 0.3).circle(&Point2::origin(), 0.2);
    let floor = LineMotion::fixed(Point2::origin(), 0.0, Side::Left);
    let g = circle_line(&disk, &floor).unwrap();
    assert_relative_eq!(g.g_n, 0.05, epsilon = 1e-15);
    assert_relative_eq!(g.g_t, 1.0 + 0.2 * 0.3, epsilon = 1e-15);
    assert_eq!(g.w_n, Vector3::new(0.0, 1.0, 0.0));
    assert_eq!(g.w_t, Vector3::new(1.0, 0.0, 0.2));
    // Rolling to the right without slip: ẋ = −r φ̇.
    assert_relative_eq!(g.tangential_velocity(&Vector3::new(1.0, 0.0, -5.0)), 0.0, epsilon = 1e-15);
    assert_relative_eq!(g.tangential_velocity(&Vector3::new(1.0, 0.0, 0.0)), 1.0, epsilon = 1e-15);
    assert_relative_eq!(g.normal_velocity(&Vector3::new(1.0, -3.0, 0.0)), -3.0, epsilon = 1e-15);
}

#[test]
fn two_circles_hand_values() {
    // a at (3, 4) with radius 2, b fixed at the origin with radius 1.5: L = 5,
    // n = (0.6, 0.8), t = (0.8, −0.6), g_N = 1.5, w_T = (r_a + r_b)/L · t plus r_a for φ_a.
    let a = PoseMotion::body(3.0, 4.0, 0.1).circle(&Point2::origin(), 2.0);
    let b = Circle::non_rotating(PointMotion::fixed(Point2::origin()), 1.5);
    let g = circle_circle(&a, &b).unwrap();
    assert_relative_eq!(g.g_n, 1.5, epsilon = 1e-15);
    assert_relative_eq!(g.w_n, Vector3::new(0.6, 0.8, 0.0), epsilon = 1e-15);
    assert_relative_eq!(g.w_t, Vector3::new(0.7 * 0.8, -0.7 * 0.6, 2.0), epsilon = 1e-15);
    assert_relative_eq!(g.g_t, -3.5 * 4f64.atan2(3.0) + 2.0 * 0.1, epsilon = 1e-15);
    assert_eq!((g.w_n_hat, g.w_t_hat), (0.0, 0.0));
}

#[test]
fn rectangle_corner_on_guide_hand_values() {
    let corners = rectangle_corners(0.05, 0.025).unwrap();
    assert_eq!(corners[0], Point2::new(-0.05, 0.025));
    assert_eq!(corners[3], Point2::new(0.05, -0.025));
    // The slider centred at the origin, turned by 90°: corner 2 (+a, +b) is at (−b, +a).
    let body = PoseMotion::body(0.0, 0.0, std::f64::consts::FRAC_PI_2);
    let guide = LineMotion::fixed(Point2::new(0.0, 0.0505), 0.0, Side::Right);
    let g = corner_line(&body, &corners[1], &guide).unwrap();
    assert_relative_eq!(g.g_n, 0.0505 - 0.05, epsilon = 1e-15);
    assert_relative_eq!(g.g_t, -0.025, epsilon = 1e-15);
    // ∂p/∂θ = (−p_y, p_x) = (−a, −b) in world coordinates at θ = 90°.
    assert_relative_eq!(g.w_n, Vector3::new(0.0, -1.0, 0.025), epsilon = 1e-15);
    assert_relative_eq!(g.w_t, Vector3::new(1.0, 0.0, -0.05), epsilon = 1e-15);
}

#[test]
fn all_pairs_on_moving_bodies_match_finite_differences() {
    let pairs = moving_pairs();
    let q0 = [0.2, 1.1, 0.4, -0.3, 0.2, -0.6];
    let samples = sample_states(
        &q0,
        0.3,
        SampleOptions { count: 12, q_radius: 0.5, t_radius: 0.5, seed: 11 },
    )
    .unwrap();
    let report = check_jacobians(&pairs, &samples, FdOptions::default()).unwrap();
    assert_eq!(report.contacts.len(), 5);
    assert!(report.passed(1e-7), "{:?}", report.worst());
}

#[test]
fn chained_pose_with_time_dependence_matches_finite_differences() {
    // Body pose (x, y, θ) = (a cos b, a sin b + 0.2 t, b + t) of coordinates (a, b).
    fn corner(
        q: &SVector<f64, 2>,
        t: f64,
        k: usize,
    ) -> Result<ContactGeometry<2>, KinematicsError> {
        let (a, b) = (q[0], q[1]);
        let body = PoseMotion::body(a * b.cos(), a * b.sin() + 0.2 * t, b + t);
        let corners = rectangle_corners(0.3, 0.1)?;
        let guide = LineMotion::fixed(Point2::new(0.0, -1.0), 0.1, Side::Left);
        let jacobian = Matrix3x2::new(b.cos(), -a * b.sin(), b.sin(), a * b.cos(), 0.0, 1.0);
        Ok(corner_line(&body, &corners[k], &guide)?.chain(&jacobian, &Vector3::new(0.0, 0.2, 1.0)))
    }
    let pairs = Pairs::<2> {
        contacts: (0..4)
            .map(|k| Box::new(move |q: &SVector<f64, 2>, t| corner(q, t, k)) as _)
            .collect(),
    };
    let samples = sample_states(
        &[1.3, 0.4],
        0.2,
        SampleOptions { count: 10, q_radius: 0.5, t_radius: 0.5, seed: 5 },
    )
    .unwrap();
    let report = check_jacobians(&pairs, &samples, FdOptions::default()).unwrap();
    assert!(report.passed(1e-7), "{:?}", report.worst());

    // Dropping the time term of the chain must be caught in ŵ_N.
    let wrong = Pairs::<2> {
        contacts: vec![Box::new(|q: &SVector<f64, 2>, t| {
            let mut g = corner(q, t, 0)?;
            g.w_n_hat = 0.0;
            Ok(g)
        })],
    };
    let report = check_jacobians(&wrong, &samples, FdOptions::default()).unwrap();
    assert_eq!(report.worst().unwrap().component, moreau_kinematics::Component::WNHat);
    assert!(!report.passed(1e-3));
}

#[test]
fn sign_error_in_a_pair_row_is_flagged() {
    let wrong = Pairs::<6> {
        contacts: vec![Box::new(|q, t| {
            let mut g = circle_on_a_against_line_on_b(q, t, 0.25, Side::Left)?;
            g.w_t[2] = -g.w_t[2];
            Ok(g)
        })],
    };
    let samples =
        sample_states(&[0.2, 1.1, 0.4, -0.3, 0.2, -0.6], 0.0, SampleOptions::default()).unwrap();
    let report = check_jacobians(&wrong, &samples, FdOptions::default()).unwrap();
    let worst = report.worst().unwrap();
    assert_eq!(worst.component, moreau_kinematics::Component::WT { coordinate: 2 });
    assert_relative_eq!(worst.analytic, -worst.reference, epsilon = 1e-7);
    assert!(!report.passed(1e-3));
}

#[test]
fn relative_velocity_is_w_dot_u_plus_w_hat() {
    // γ = wᵀu + ŵ = 1 · 3 + 2 · (−1) + 0.5.
    assert_eq!(moreau_kinematics::relative_velocity(&[1.0, 2.0], 0.5, &[3.0, -1.0]), Ok(1.5));
    // It agrees with the pair's own γ_N and γ_T: a point at (0.3, 0.2) moving with q = (x, y)
    // at u = (0.4, −1.5) above a floor rising at 0.25 m/s.
    let point = PointMotion::<2> {
        position: Point2::new(0.3, 0.2),
        jacobian: SMatrix::<f64, 2, 2>::identity(),
        time_derivative: Vector2::zeros(),
    };
    let floor =
        LineMotion::rheonomic(Point2::origin(), Vector2::new(0.0, 0.25), 0.0, 0.0, Side::Left);
    let g = point_line(&point, &floor).unwrap();
    let u = SVector::<f64, 2>::new(0.4, -1.5);
    let gamma_n = moreau_kinematics::relative_velocity(g.w_n.as_slice(), g.w_n_hat, u.as_slice());
    let gamma_t = moreau_kinematics::relative_velocity(g.w_t.as_slice(), g.w_t_hat, u.as_slice());
    assert_eq!((gamma_n, gamma_t), (Ok(-1.75), Ok(0.4)));
    assert_eq!((g.normal_velocity(&u), g.tangential_velocity(&u)), (-1.75, 0.4));
    let err = moreau_kinematics::relative_velocity(&[1.0, 2.0], 0.0, &[3.0]).unwrap_err();
    assert_eq!(
        err,
        KinematicsError::DimensionMismatch { what: "u against w", expected: 2, found: 1 }
    );
    assert_eq!(err.to_string(), "dimension mismatch in u against w: expected 2, found 1");
}

#[test]
fn invalid_geometry_is_a_typed_error() {
    let center = PointMotion::<1>::fixed(Point2::origin());
    let floor = LineMotion::fixed(Point2::origin(), 0.0, Side::Left);
    assert!(matches!(
        circle_line(&Circle::non_rotating(center, -1.0), &floor),
        Err(KinematicsError::InvalidGeometry { what: "circle radius", .. })
    ));
    let c = Circle::non_rotating(center, 1.0);
    assert!(matches!(circle_circle(&c, &c), Err(KinematicsError::InvalidGeometry { .. })));
    let nan = PointMotion::<1>::fixed(Point2::new(f64::NAN, 0.0));
    assert!(matches!(point_line(&nan, &floor), Err(KinematicsError::NonFinite { .. })));
    assert!(matches!(
        circle_circle(&Circle::non_rotating(nan, 1.0), &c),
        Err(KinematicsError::NonFinite { .. })
    ));
    let err = rectangle_corners(-0.1, 0.1).unwrap_err();
    assert_eq!(
        err,
        KinematicsError::InvalidGeometry { what: "rectangle half-width a", value: -0.1 }
    );
    assert_eq!(err.to_string(), "invalid geometry: rectangle half-width a = -0.1");
    assert!(matches!(
        rectangle_corners(0.1, f64::NAN),
        Err(KinematicsError::InvalidGeometry { what: "rectangle half-height b", value }) if value.is_nan()
    ));
    let corners = rectangle_corners(0.3, 0.1).unwrap();
    assert_eq!(corners.map(|c| [c.x, c.y]), [[-0.3, 0.1], [0.3, 0.1], [-0.3, -0.1], [0.3, -0.1]]);
    assert!(matches!(
        circle_line(&Circle::non_rotating(center, f64::NAN), &floor),
        Err(KinematicsError::InvalidGeometry { what: "circle radius", value }) if value.is_nan()
    ));
    // Two coincident centres name their distance, zero.
    assert_eq!(
        circle_circle(&c, &c),
        Err(KinematicsError::InvalidGeometry { what: "distance of circle centres", value: 0.0 })
    );
    let g = point_line(&PointMotion::<1> { jacobian: Matrix2x1::new(0.0, 1.0), ..center }, &floor)
        .unwrap();
    let (mut a, mut b) = ([0.0; 2], [0.0; 1]);
    assert!(matches!(
        g.write(&mut a, &mut b),
        Err(KinematicsError::DimensionMismatch { expected: 1, found: 2, .. })
    ));
    let (mut a, mut b) = ([0.0; 1], [0.0; 1]);
    let cp = g.write(&mut a, &mut b).unwrap();
    assert_eq!((a, b, cp.g_n), ([1.0], [0.0], 0.0));
    let e = moreau_kinematics::ScalarMotion::<2>::coordinate(2, 0.0).unwrap_err();
    assert_eq!(e, KinematicsError::IndexOutOfRange { what: "coordinate", index: 2, len: 2 });
    assert_eq!(e.to_string(), "coordinate 2 is out of range: there are 2, numbered from 0");
    assert_eq!(
        moreau_kinematics::ScalarMotion::<2>::coordinate(1, 0.5).unwrap().gradient,
        Vector2::new(0.0, 1.0)
    );
}

fn state() -> impl Strategy<Value = (SVector<f64, 6>, SVector<f64, 6>, f64)> {
    (prop::array::uniform6(-2.0..2.0f64), prop::array::uniform6(-3.0..3.0f64), -1.0..1.0f64)
        .prop_map(|(q, u, t)| (SVector::from(q), SVector::from(u), t))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// γ_N and γ_T of a point against a line are the normal and tangential components of the
    /// velocity of the point relative to the material point of the line's body it passes.
    #[test]
    fn point_line_velocities_are_material_relative_velocities((q, u, t) in state(), left in any::<bool>()) {
        let side = if left { Side::Left } else { Side::Right };
        let g = point_on_a_against_line_on_b(&q, t, side).unwrap();
        let line = body_b(&q, t).line(&Point2::new(LINE_LOCAL[0], LINE_LOCAL[1]), LINE_LOCAL[2], side);
        let x = body_a(&q).point(&Point2::new(POINT_LOCAL[0], POINT_LOCAL[1])).position;
        let relative = material_velocity_a(&q, &u, &x) - material_velocity_b(&q, &u, t, &x);
        prop_assert!((g.normal_velocity(&u) - line.normal().dot(&relative)).abs() < 1e-12);
        prop_assert!((g.tangential_velocity(&u) - line.tangent().dot(&relative)).abs() < 1e-12);
    }

    /// For a circle against a line the same holds at the circle's material point nearest the
    /// line, x = c − r n, in every state, open or closed.
    #[test]
    fn circle_line_velocities_are_material_relative_velocities((q, u, t) in state(), r in 0.0..1.0f64, left in any::<bool>()) {
        let side = if left { Side::Left } else { Side::Right };
        let g = circle_on_a_against_line_on_b(&q, t, r, side).unwrap();
        let line = body_b(&q, t).line(&Point2::new(LINE_LOCAL[0], LINE_LOCAL[1]), LINE_LOCAL[2], side);
        let c = body_a(&q).point(&Point2::new(POINT_LOCAL[0], POINT_LOCAL[1])).position;
        let x = c - line.normal() * r;
        let relative = material_velocity_a(&q, &u, &x) - material_velocity_b(&q, &u, t, &x);
        prop_assert!((g.normal_velocity(&u) - line.normal().dot(&relative)).abs() < 1e-12);
        prop_assert!((g.tangential_velocity(&u) - line.tangent().dot(&relative)).abs() < 1e-12);
    }

    /// Two touching circles: γ_N and γ_T are the relative velocity of the material contact
    /// points along n and t = (n_y, −n_x).
    #[test]
    fn touching_circles_velocities_are_material_relative_velocities(
        (q, u, t) in state(), ra in 0.1..1.0f64, rb in 0.1..1.0f64, direction in -3.0..3.0f64,
    ) {
        // Place a so that it touches b: c_a = c_b + (r_a + r_b)(cos, sin).
        let mut q = q;
        let cb = body_b(&q, t).origin.position;
        q[0] = cb.x + (ra + rb) * direction.cos();
        q[1] = cb.y + (ra + rb) * direction.sin();
        let g = circles(&q, t, ra, rb).unwrap();
        prop_assert!(g.g_n.abs() < 1e-12);
        let n = Vector2::new(direction.cos(), direction.sin());
        let tangent = Vector2::new(n.y, -n.x);
        let on_a = Point2::new(q[0], q[1]) - n * ra;
        let on_b = cb + n * rb;
        let relative = material_velocity_a(&q, &u, &on_a) - material_velocity_b(&q, &u, t, &on_b);
        prop_assert!((g.normal_velocity(&u) - n.dot(&relative)).abs() < 1e-11);
        prop_assert!((g.tangential_velocity(&u) - tangent.dot(&relative)).abs() < 1e-11);
    }

    /// The rows of every pair agree with finite differences at random states.
    #[test]
    fn pairs_match_finite_differences_at_random_states((q, _u, t) in state()) {
        let report = check_jacobians(&moving_pairs(), &[(q.as_slice().to_vec(), t)], FdOptions::default()).unwrap();
        prop_assert!(report.passed(1e-6), "{:?}", report.worst());
    }
}
