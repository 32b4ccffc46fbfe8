//! Every joint's bilateral rows and every clearance contact's normal rows, checked against
//! central differences of their g (w = ∂g/∂q, ŵ = ∂g/∂t), with fixed, dynamic and driven
//! bodies; the springs' and gravity's forces against the potential (h = −∂V/∂q); the tangent
//! rows of the clearance contacts against the material points' relative velocity.

use moreau_kinematics::{
    ContactKinematics, ContactPoint, FdOptions, SampleOptions, check_jacobians, sample_states,
};
use moreau_models::bodies::{BodySpec, ForceSpec, JointSpec, Motion, Multibody, MultibodyBuilder};
use moreau_stepper::Mechanism;

/// The bilateral rows of a mechanism seen as contacts, so that the checker compares w_B with
/// ∂g_B/∂q and ŵ_B with ∂g_B/∂t.
struct Rows<'a>(&'a Multibody);

impl ContactKinematics for Rows<'_> {
    fn num_coordinates(&self) -> usize {
        self.0.num_coordinates()
    }
    fn num_contacts(&self) -> usize {
        self.0.num_bilaterals()
    }
    fn normal_gap(&self, i: usize, q: &[f64], t: f64) -> f64 {
        let mut w = vec![0.0; q.len()];
        self.0.bilateral(i, q, t, &mut w).g
    }
    fn contact(
        &self,
        i: usize,
        q: &[f64],
        t: f64,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) -> ContactPoint {
        let p = self.0.bilateral(i, q, t, w_n);
        w_t.fill(0.0);
        ContactPoint { g_n: p.g, g_t: 0.0, w_n_hat: p.w_hat, w_t_hat: 0.0 }
    }
}

/// The normal rows of a mechanism's contacts alone (g_T is not a function of (q, t)).
struct Normals<'a>(&'a Multibody);

impl ContactKinematics for Normals<'_> {
    fn num_coordinates(&self) -> usize {
        self.0.num_coordinates()
    }
    fn num_contacts(&self) -> usize {
        self.0.num_contacts()
    }
    fn normal_gap(&self, i: usize, q: &[f64], t: f64) -> f64 {
        self.0.normal_gap(i, q, t)
    }
    fn contact(
        &self,
        i: usize,
        q: &[f64],
        t: f64,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) -> ContactPoint {
        let p = self.0.contact(i, q, t, w_n, w_t);
        w_t.fill(0.0);
        ContactPoint { g_t: 0.0, w_t_hat: 0.0, ..p }
    }
}

/// Body `a` (dynamic, centre of mass off its origin), `b` (dynamic), `d` (driven: turning
/// about a pivot), and the world; one joint between two of them. A bilateral joint's dynamic
/// body (`body_b` when both are) is declared where the joint puts it, anchors together and a
/// weld's angle met, since assembly refuses to move a body far.
fn mechanism(joint: JointSpec) -> Multibody {
    let mut builder = bodies();
    let (anchors, weld) = match joint {
        JointSpec::Revolute { anchor_a, anchor_b, .. }
        | JointSpec::Prismatic { anchor_a, anchor_b, .. }
        | JointSpec::PointOnLine { anchor_a, anchor_b, .. } => (Some((anchor_a, anchor_b)), None),
        JointSpec::Weld { anchor_a, anchor_b, angle, .. } => (Some((anchor_a, anchor_b)), angle),
        _ => (None, None),
    };
    if let Some((ra, rb)) = anchors {
        let free = builder.build().unwrap();
        let (q0, _) = free.initial_state();
        let poses = free.body_poses(&q0, 0.0);
        let pose = |name: &str| free.body_index(name).map_or([0.0; 3], |i| poses[i]);
        let (na, nb) = joint.bodies();
        let dynamic = |name: &str| name == "a" || name == "b";
        // (moved body, its anchor, the other's pose, its anchor, sign of the moved one's angle)
        let (moved, r_moved, other, r_other, sign) =
            if dynamic(nb) { (nb, rb, pose(na), ra, 1.0) } else { (na, ra, pose(nb), rb, -1.0) };
        let world = |p: [f64; 3], r: [f64; 2]| {
            let (s, c) = p[2].sin_cos();
            [p[0] + c * r[0] - s * r[1], p[1] + s * r[0] + c * r[1]]
        };
        let mut spec = builder.spec().clone();
        let body = spec.bodies.iter_mut().find(|b| b.name == moved).unwrap();
        if let Some(angle) = weld {
            body.angle = other[2] + sign * angle;
        }
        let at = world(other, r_other);
        let offset = world([0.0, 0.0, body.angle], r_moved);
        body.position = [at[0] - offset[0], at[1] - offset[1]];
        builder = MultibodyBuilder::from_spec(spec);
    }
    builder.add_joint(joint);
    builder.build().unwrap_or_else(|e| panic!("{e}"))
}

/// The bodies of [`mechanism`], without its joint.
fn bodies() -> MultibodyBuilder {
    let mut builder = MultibodyBuilder::new([0.3, -9.81]);
    let mut a = BodySpec::dynamic("a", 2.0, 0.5, [0.1, 0.2], 0.3);
    a.center_of_mass = Some([0.05, -0.02]);
    builder.add_body(a);
    builder.add_body(BodySpec::dynamic("b", 1.5, 0.2, [0.7, -0.1], -0.4));
    builder.add_body(BodySpec::driven(
        "d",
        [0.4, 0.5],
        0.2,
        Motion::Rotate { pivot: [0.3, 0.1], omega: 1.3, phase: 0.2 },
    ));
    builder
}

fn samples(mb: &Multibody) -> Vec<(Vec<f64>, f64)> {
    let (q0, _) = mb.initial_state();
    let options = SampleOptions { count: 12, q_radius: 0.3, t_radius: 0.8, seed: 17 };
    sample_states(&q0, 0.7, options).unwrap()
}

fn check(mb: &Multibody, what: &str) {
    let s = samples(mb);
    if mb.num_bilaterals() > 0 {
        let report = check_jacobians(&Rows(mb), &s, FdOptions::default()).unwrap();
        let worst = report.worst().unwrap();
        assert!(worst.scaled < 1e-7, "{what} rows: {worst:?}");
    }
    if mb.num_contacts() > 0 {
        let report = check_jacobians(&Normals(mb), &s, FdOptions::default()).unwrap();
        let worst = report.worst().unwrap();
        assert!(worst.scaled < 1e-7, "{what} contacts: {worst:?}");
    }
}

/// The joints of one type between (a, b), (d, a) and (b, ground).
fn check_pairs(what: &str, make: impl Fn(&str, &str) -> JointSpec) {
    for (a, b) in [("a", "b"), ("d", "a"), ("b", "d"), ("b", "ground"), ("ground", "a")] {
        let mb = mechanism(make(a, b));
        check(&mb, &format!("{what} {a}-{b}"));
    }
}

#[test]
fn revolute_rows_are_the_derivatives_of_their_gaps() {
    check_pairs("revolute", |a, b| JointSpec::revolute("j", a, [0.1, -0.2], b, [-0.3, 0.05]));
}

#[test]
fn prismatic_rows_are_the_derivatives_of_their_gaps() {
    check_pairs("prismatic", |a, b| JointSpec::Prismatic {
        name: "j".into(),
        body_a: a.into(),
        body_b: b.into(),
        anchor_a: [0.1, -0.2],
        anchor_b: [-0.3, 0.05],
        axis: [0.8, 0.3],
        angle: None,
    });
}

#[test]
fn weld_rows_are_the_derivatives_of_their_gaps() {
    check_pairs("weld", |a, b| JointSpec::Weld {
        name: "j".into(),
        body_a: a.into(),
        body_b: b.into(),
        anchor_a: [0.1, -0.2],
        anchor_b: [-0.3, 0.05],
        angle: Some(0.25),
    });
}

#[test]
fn point_on_line_row_is_the_derivative_of_its_gap() {
    check_pairs("point_on_line", |a, b| JointSpec::PointOnLine {
        name: "j".into(),
        body_a: a.into(),
        body_b: b.into(),
        anchor_a: [0.1, -0.2],
        anchor_b: [-0.3, 0.05],
        axis: [-0.2, 1.0],
    });
}

#[test]
fn motor_row_is_the_derivative_of_its_gap() {
    check_pairs("motor", |a, b| JointSpec::Motor {
        name: "j".into(),
        body_a: a.into(),
        body_b: b.into(),
        omega: 2.5,
        angle: None,
    });
}

fn revolute_clearance(a: &str, b: &str) -> JointSpec {
    JointSpec::RevoluteClearance {
        name: "j".into(),
        body_a: a.into(),
        body_b: b.into(),
        anchor_a: [0.1, -0.2],
        anchor_b: [-0.3, 0.05],
        pin_radius: 0.01,
        bearing_radius: 0.012,
        eps_n: 0.5,
        eps_t: 0.0,
        mu: 0.1,
    }
}

fn translational_clearance(a: &str, b: &str) -> JointSpec {
    JointSpec::TranslationalClearance {
        name: "j".into(),
        body_a: a.into(),
        body_b: b.into(),
        anchor_a: [0.1, -0.2],
        axis_a: [1.0, 0.2],
        length: 0.3,
        width: 0.1,
        anchor_b: [-0.3, 0.05],
        axis_b: [0.9, -0.1],
        guide_width: 0.11,
        eps_n: 0.5,
        eps_t: 0.0,
        mu: 0.1,
    }
}

#[test]
fn clearance_contacts_normal_rows_are_the_derivatives_of_their_gaps() {
    check_pairs("revolute_clearance", revolute_clearance);
    check_pairs("translational_clearance", translational_clearance);
}

/// γ_T = w_Tᵀ u + ŵ_T equals t · (v_b − v_a) of the two surface points taken as material
/// points of their bodies, by central differences of their positions along (u, 1).
#[test]
fn clearance_contacts_tangent_rows_are_the_material_points_relative_velocity() {
    for (make, contacts) in
        [(revolute_clearance as fn(&str, &str) -> JointSpec, 1), (translational_clearance, 4)]
    {
        for (a, b) in [("a", "b"), ("d", "a"), ("b", "d")] {
            let mb = mechanism(make(a, b));
            assert_eq!(mb.num_contacts(), contacts);
            let (ia, ib) = (mb.body_index(a).unwrap(), mb.body_index(b).unwrap());
            let f = mb.num_coordinates();
            let u: Vec<f64> = (0..f).map(|j| 0.3 + 0.7 * j as f64 - 0.2 * (j * j) as f64).collect();
            for (q, t) in samples(&mb) {
                for i in 0..contacts {
                    let (mut w_n, mut w_t) = (vec![0.0; f], vec![0.0; f]);
                    let point = mb.contact(i, &q, t, &mut w_n, &mut w_t);
                    let gamma_t: f64 =
                        w_t.iter().zip(&u).map(|(w, v)| w * v).sum::<f64>() + point.w_t_hat;
                    // The surface points and the normal at (q, t), from the contact's drawing
                    // points and its force direction.
                    let poses = mb.body_poses(&q, t);
                    let (pa, pb, n) = surface_points(&mb, i, &q, t);
                    let local = |pose: [f64; 3], p: [f64; 2]| {
                        let (s, c) = pose[2].sin_cos();
                        let d = [p[0] - pose[0], p[1] - pose[1]];
                        [c * d[0] + s * d[1], -s * d[0] + c * d[1]]
                    };
                    let (la, lb) = (local(poses[ia], pa), local(poses[ib], pb));
                    let world = |pose: [f64; 3], r: [f64; 2]| {
                        let (s, c) = pose[2].sin_cos();
                        [pose[0] + c * r[0] - s * r[1], pose[1] + s * r[0] + c * r[1]]
                    };
                    let h = 1e-6;
                    let moved = |e: f64| {
                        let qe: Vec<f64> = q.iter().zip(&u).map(|(x, v)| x + e * v).collect();
                        let p = mb.body_poses(&qe, t + e);
                        let (wa, wb) = (world(p[ia], la), world(p[ib], lb));
                        [wb[0] - wa[0], wb[1] - wa[1]]
                    };
                    let (plus, minus) = (moved(h), moved(-h));
                    let rel = [(plus[0] - minus[0]) / (2.0 * h), (plus[1] - minus[1]) / (2.0 * h)];
                    let tangent = [-n[1], n[0]];
                    let reference = tangent[0] * rel[0] + tangent[1] * rel[1];
                    assert!(
                        (gamma_t - reference).abs() < 1e-6 * (1.0 + reference.abs()),
                        "{a}-{b} contact {i}: γ_T = {gamma_t}, material {reference}"
                    );
                }
            }
        }
    }
}

/// The two surface points and the normal of contact i.
fn surface_points(mb: &Multibody, i: usize, q: &[f64], t: f64) -> ([f64; 2], [f64; 2], [f64; 2]) {
    let g = mb.contact_geometry(i, q, t);
    (g.point_a, g.point_b, g.normal)
}

/// h = −∂V/∂q at rest for gravity (with a centre of mass off the origin), linear springs
/// between dynamic, driven and fixed bodies, and a torsional spring.
#[test]
fn conservative_forces_are_minus_the_gradient_of_the_potential() {
    let mut builder = MultibodyBuilder::from_spec(
        mechanism(JointSpec::revolute("j", "a", [0.0, 0.0], "b", [0.5, 0.1])).spec().clone(),
    );
    for (a, b) in [("a", "b"), ("d", "a"), ("ground", "b")] {
        builder.add_force(ForceSpec::Spring {
            name: None,
            body_a: a.into(),
            anchor_a: [0.1, 0.05],
            body_b: b.into(),
            anchor_b: [-0.2, 0.1],
            stiffness: 40.0,
            rest_length: 0.3,
            damping: 0.0,
        });
    }
    builder.add_force(ForceSpec::Torsion {
        name: Some("twist".into()),
        body_a: "a".into(),
        body_b: "b".into(),
        stiffness: 3.0,
        rest_angle: 0.1,
        damping: 0.0,
    });
    let mb = builder.build().unwrap();
    let f = mb.num_coordinates();
    let zero = vec![0.0; f];
    for (q, t) in samples(&mb) {
        let mut h = vec![0.0; f];
        mb.forces(&q, &zero, t, &mut h);
        for j in 0..f {
            let step = 1e-6;
            let mut qp = q.clone();
            qp[j] += step;
            let mut qm = q.clone();
            qm[j] -= step;
            let dv = (mb.potential_energy(&qp, t).unwrap() - mb.potential_energy(&qm, t).unwrap())
                / (2.0 * step);
            assert!(
                (h[j] + dv).abs() < 1e-6 * (1.0 + dv.abs()),
                "h[{j}] = {}, −∂V/∂q = {}",
                h[j],
                -dv
            );
        }
    }
}
