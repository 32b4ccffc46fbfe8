//! The numbering and names of the fixed contact set's slots: slot k of a polygon on a
//! half-plane is the polygon's vertex k, slot i of two polygons A and B is vertex i of A and
//! slot n_A + j vertex j of B, and the names follow the contacts' and bodies' order.

use moreau_kinematics::Shape;
use moreau_models::LawParams;
use moreau_models::bodies::{AutoContacts, BodySpec, ContactSpec, Multibody, MultibodyBuilder};

const W: f64 = 0.2;
const H: f64 = 0.1;

/// A 2W × 2H box, its vertices counter-clockwise from the lower left: 0 lower left, 1 lower
/// right, 2 upper right, 3 upper left.
fn box_shape(w: f64, h: f64) -> Shape {
    Shape::Polygon { vertices: vec![[-w, -h], [w, -h], [w, h], [-w, h]] }
}

fn floor() -> BodySpec {
    BodySpec::fixed("floor", [0.0, 0.0], 0.0)
        .with_shape(Shape::HalfPlane { point: [0.0, 0.0], normal: [0.0, 1.0] })
}

/// A box at `pose`.
fn block(name: &str, pose: [f64; 3], w: f64, h: f64) -> BodySpec {
    BodySpec::dynamic(name, 1.0, 0.01, [pose[0], pose[1]], pose[2]).with_shape(box_shape(w, h))
}

fn contact(name: &str, a: &str, b: &str, margin: Option<f64>) -> ContactSpec {
    ContactSpec {
        name: name.into(),
        body_a: a.into(),
        shape_a: 0,
        body_b: b.into(),
        shape_b: 0,
        eps_n: 0.0,
        eps_t: 0.0,
        mu: 0.5,
        margin,
    }
}

/// Vertex k of the box at `pose` in the world.
fn corner(pose: [f64; 3], w: f64, h: f64, k: usize) -> [f64; 2] {
    let [x, y] = [[-w, -h], [w, -h], [w, h], [-w, h]][k];
    let (s, c) = pose[2].sin_cos();
    [pose[0] + c * x - s * y, pose[1] + s * x + c * y]
}

fn near(a: [f64; 2], b: [f64; 2]) -> bool {
    (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12
}

#[test]
fn a_box_on_a_floor_has_one_slot_per_vertex_in_vertex_order() {
    // Tilted, so that each corner is at its own height; a margin that finds all four.
    let pose = [0.3, 0.25, 0.4];
    let mut b = MultibodyBuilder::new([0.0, -9.81]);
    b.add_body(floor());
    b.add_body(block("box", pose, W, H));
    b.add_contact(contact("feet", "floor", "box", Some(1.0)));
    let mb = b.build().unwrap();
    assert_eq!(mb.contact_names(), ["feet.0", "feet.1", "feet.2", "feet.3"]);
    let (q, _) = mb.initial_state();
    for k in 0..4 {
        let g = mb.contact_geometry(k, &q, 0.0);
        let v = corner(pose, W, H, k);
        assert!(near(g.point_b, v), "slot {k}: {:?} is not vertex {k} {v:?}", g.point_b);
        assert!(near(g.point_a, [v[0], 0.0]) && (g.gap - v[1]).abs() < 1e-12, "slot {k}: {g:?}");
        assert_eq!(g.normal, [0.0, 1.0]);
    }
}

#[test]
fn a_box_resting_flat_closes_its_first_two_slots_its_lower_corners() {
    let mut b = MultibodyBuilder::new([0.0, -9.81]);
    b.add_body(floor());
    b.add_body(block("box", [0.0, H, 0.0], W, H));
    b.add_contact(contact("feet", "floor", "box", None));
    let mb: Multibody = b.build().unwrap();
    let (q, _) = mb.initial_state();
    let gaps: Vec<f64> = (0..4).map(|k| mb.contact_geometry(k, &q, 0.0).gap).collect();
    assert_eq!(&gaps[..2], [0.0, 0.0]);
    // The upper corners are beyond the margin (1 % of the box's diagonal): open, with the
    // margin as their gap.
    let margin = 0.01 * (2.0 * W).hypot(2.0 * H);
    assert!(gaps[2..].iter().all(|&g| (g - margin).abs() < 1e-15), "{gaps:?}");
}

#[test]
fn automatic_slots_are_named_by_bodies_in_declaration_order_then_vertex() {
    let pose = [0.0, 0.2, 0.3];
    // The floor declared first, then the box after it, and the other way round: the slot of
    // vertex k is k either way; the name puts the earlier body first.
    for (floor_first, names) in [
        (true, ["floor.0-box.0.0", "floor.0-box.0.1", "floor.0-box.0.2", "floor.0-box.0.3"]),
        (false, ["box.0-floor.0.0", "box.0-floor.0.1", "box.0-floor.0.2", "box.0-floor.0.3"]),
    ] {
        let mut b = MultibodyBuilder::new([0.0, -9.81]);
        if floor_first {
            b.add_body(floor());
            b.add_body(block("box", pose, W, H));
        } else {
            b.add_body(block("box", pose, W, H));
            b.add_body(floor());
        }
        let mut auto = AutoContacts::new(LawParams::new(0.0, 0.0, 0.5));
        auto.margin = Some(1.0);
        b.auto_contacts(auto);
        let mb = b.build().unwrap();
        assert_eq!(mb.contact_names(), names);
        let (q, _) = mb.initial_state();
        for k in 0..4 {
            let g = mb.contact_geometry(k, &q, 0.0);
            let on_box = if floor_first { g.point_b } else { g.point_a };
            assert!(near(on_box, corner(pose, W, H, k)), "slot {k}: {g:?}");
        }
    }
}

#[test]
fn two_boxes_number_the_vertices_of_a_then_those_of_b() {
    // A narrow box (b) resting flat on a wide one (a): b's lower corners, its vertices 0 and
    // 1, lie on a's upper face, so the closed slots are n_A + 0 = 4 and n_A + 1 = 5.
    let mut b = MultibodyBuilder::new([0.0, -9.81]);
    b.add_body(block("wide", [0.0, H, 0.0], W, H));
    b.add_body(block("narrow", [0.05, 3.0 * H, 0.0], 0.5 * W, H));
    b.add_contact(contact("stack", "wide", "narrow", None));
    let mb = b.build().unwrap();
    let expected: Vec<String> = (0..8).map(|k| format!("stack.{k}")).collect();
    assert_eq!(mb.contact_names(), expected);
    let (q, _) = mb.initial_state();
    let closed: Vec<usize> =
        (0..8).filter(|&k| mb.contact_geometry(k, &q, 0.0).gap.abs() < 1e-12).collect();
    assert_eq!(closed, [4, 5]);
    let pose = [0.05, 3.0 * H, 0.0];
    for (slot, vertex) in [(4, 0), (5, 1)] {
        let g = mb.contact_geometry(slot, &q, 0.0);
        assert!(near(g.point_b, corner(pose, 0.5 * W, H, vertex)), "slot {slot}: {g:?}");
    }
}
