//! The force network of a resting stack of three disks against its closed form: one line per
//! contact, from the floor's contact point or a disk's centre to the next disk's centre, its
//! width in proportion to the weight the contact carries.

use std::path::Path;

use anyhow::Result;
use moreau_models::{ModelKind, Scene};
use xtask::frames::Shape;
use xtask::network;

#[test]
fn a_resting_stack_draws_one_line_per_contact_as_wide_as_its_load() -> Result<()> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/bodies/stack.toml");
    let scene = Scene::from_path(&path)?;
    let mut stepper = scene.stepper()?;
    let dt = scene.dt;
    for _ in 0..999 {
        stepper.step()?;
    }
    let (q_a, u_a, t_a) = (stepper.q().to_vec(), stepper.u().to_vec(), stepper.t());
    let report = stepper.step()?;
    let (ids, contacts) = (report.contact_ids.to_vec(), report.contacts.to_vec());
    let model = stepper.mechanism();
    let state = (q_a.as_slice(), u_a.as_slice(), t_a);
    let frame = network::frame(model, state, dt, 0.0, &ids, &contacts, vec!["stack".into()])?;
    let links: Vec<(&[[f64; 2]], u32)> = frame
        .shapes
        .iter()
        .filter_map(|s| match s {
            Shape::Poly { points, paint, .. } if paint.stroke == (180, 20, 20) => {
                Some((points.as_slice(), paint.width))
            }
            _ => None,
        })
        .collect();
    // Loads 6, 5 and 3 m g from the floor up: widths 1 + round(5 × load / 6 m g), the last
    // on the rounding boundary 1 + round(2.5), which the impulses' round-off decides.
    let widths: Vec<u32> = links.iter().map(|l| l.1).collect();
    assert!(widths[..2] == [6, 5] && [3, 4].contains(&widths[2]), "{widths:?}");
    // From the floor's contact point (0, 0) to the centre of d0, then centre to centre, the
    // disks 0.2 m apart (within their resting penetration of a few tenths of a millimetre).
    let ends = [[0.0, 0.0], [0.0, 0.1], [0.0, 0.3], [0.0, 0.5]];
    for (k, (points, _)) in links.iter().enumerate() {
        for (p, e) in points.iter().zip(&ends[k..k + 2]) {
            assert!((p[0] - e[0]).abs() < 1e-12 && (p[1] - e[1]).abs() < 2e-3, "{p:?} {e:?}");
        }
    }
    // The disks are drawn under the lines, and the window frames the disks, not the floor.
    assert!(frame.shapes.iter().any(|s| matches!(s, Shape::Circle { .. })));
    let window = frame.window.expect("its own window");
    assert!(window[2] - window[0] < 0.3 && window[3] - window[1] > 0.6, "{window:?}");
    Ok(())
}

#[test]
fn a_report_model_has_no_force_network() -> Result<()> {
    let mut stepper = Scene::report(ModelKind::Ball).stepper()?;
    let (q, u) = (stepper.q().to_vec(), stepper.u().to_vec());
    let report = stepper.step()?;
    let (ids, contacts) = (report.contact_ids.to_vec(), report.contacts.to_vec());
    let model = stepper.mechanism();
    let e = network::frame(model, (&q, &u, 0.0), 1e-3, 0.0, &ids, &contacts, Vec::new());
    assert!(e.unwrap_err().to_string().contains("declared bodies"));
    Ok(())
}
