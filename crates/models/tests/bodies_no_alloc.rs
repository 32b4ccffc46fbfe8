//! A declared scene steps without touching the heap once warm, its contacts changing or not.

use moreau_kinematics::Shape;
use moreau_models::LawParams;
use moreau_models::bodies::{AutoContacts, BodySpec, ContactSet, JointSpec, MultibodyBuilder};
use moreau_stepper::{Mechanism, Stepper, StepperOptions};
use moreau_testsupport::{CountingAllocator, allocations_in};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

#[test]
fn a_declared_scene_steps_without_allocating() {
    // A hinged rod with a box at its end swinging onto a floor, and a disk bouncing beside it:
    // joints, automatic contacts opening and closing, polygons and disks.
    let mut b = MultibodyBuilder::new([0.0, -9.81]);
    b.add_body(
        BodySpec::fixed("floor", [0.0, 0.0], 0.0)
            .with_shape(Shape::HalfPlane { point: [0.0, 0.0], normal: [0.0, 1.0] }),
    );
    b.add_body(BodySpec::with_density("arm", 100.0, [0.5, 0.4], 0.0).with_shape(Shape::Polygon {
        vertices: vec![[-0.5, -0.02], [0.5, -0.02], [0.5, 0.02], [-0.5, 0.02]],
    }));
    b.add_body(
        BodySpec::dynamic("ball", 1.0, 0.005, [2.0, 0.5], 0.0)
            .with_shape(Shape::Disk { center: [0.0, 0.0], radius: 0.1 }),
    );
    b.add_joint(JointSpec::revolute("pivot", "ground", [0.0, 0.4], "arm", [-0.5, 0.0]));
    b.auto_contacts(AutoContacts::new(LawParams::new(0.5, 0.0, 0.3)));
    let mb = b.build().unwrap();
    let (q0, u0) = mb.initial_state();
    let mut options = StepperOptions::new(1e-3);
    options.projection = true;
    let mut stepper = Stepper::new(mb, &q0, &u0, 0.0, options).unwrap();
    while stepper.t() < 3.0 {
        stepper.step().unwrap();
    }
    let mut closed = 0;
    let n = allocations_in(|| {
        while stepper.t() < 6.0 {
            let report = stepper.step().unwrap();
            closed += report.contacts.iter().filter(|c| c.active).count();
        }
    });
    assert!(closed > 0, "no contact closed");
    assert_eq!(n, 0, "{n} allocations in 3000 steps");
}

#[test]
fn detection_allocates_nothing_once_warm() {
    // A lattice of 400 disks and boxes on a floor, moved a little at each call: the broad
    // phase's grid, the narrow phase and the contact list keep their buffers.
    let mut b = MultibodyBuilder::new([0.0, -9.81]);
    b.add_body(
        BodySpec::fixed("floor", [0.0, 0.0], 0.0)
            .with_shape(Shape::HalfPlane { point: [0.0, 0.0], normal: [0.0, 1.0] }),
    );
    for k in 0..400 {
        let p = [0.1 * (k % 20) as f64, 0.05 + 0.1 * (k / 20) as f64];
        let shape = if k % 3 == 0 {
            Shape::Polygon {
                vertices: vec![[-0.05, -0.05], [0.05, -0.05], [0.05, 0.05], [-0.05, 0.05]],
            }
        } else {
            Shape::Disk { center: [0.0, 0.0], radius: 0.05 }
        };
        b.add_body(BodySpec::with_density(&format!("b{k}"), 1.0, p, 0.0).with_shape(shape));
    }
    b.auto_contacts(AutoContacts::new(LawParams::new(0.0, 0.0, 0.3)));
    b.with_contact_set(ContactSet::Detected);
    let mb = b.build().unwrap();
    let structure = mb.body_structure().unwrap();
    let (q0, _) = mb.initial_state();
    let mut q = q0.clone();
    let mut out = Vec::new();
    let wiggle = |q: &mut Vec<f64>, step: usize| {
        for (i, v) in q.iter_mut().enumerate() {
            *v = q0[i] + 1e-3 * ((i * 7 + step) as f64).sin();
        }
    };
    for step in 0..5 {
        wiggle(&mut q, step);
        out.clear();
        structure.detect(&q, 0.0, 0.01, &mut out);
    }
    out.reserve(out.len());
    let mut found = 0;
    let n = allocations_in(|| {
        for step in 0..50 {
            wiggle(&mut q, step);
            out.clear();
            structure.detect(&q, 0.0, 0.01, &mut out);
            found += out.len();
        }
    });
    assert_eq!(n, 0, "{n} allocations in 50 detections");
    assert!(found > 50 * 700, "{found}");
}
