//! A fill beyond `MAX_FILL_BODIES` bodies is refused naming its field, before any body is
//! made, whatever its size field holds (a pyramid's base (base + 1)/2 is computed without
//! overflow).

use std::path::Path;

use moreau_kinematics::Shape;
use moreau_models::bodies::{FillPattern, FillSpec, MAX_FILL_BODIES};
use moreau_models::{ModelError, Scene};

fn scale_scene(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/scale").join(name);
    Scene::from_path(&path).unwrap()
}

fn disk() -> Shape {
    Shape::Disk { center: [0.0; 2], radius: 0.1 }
}

/// The key and reason of a refused value.
fn refused(scene: &mut Scene, key: &str, value: &str) -> (String, String) {
    match scene.set(key, value).and_then(|()| scene.validate()) {
        Err(ModelError::BadValue { key, reason, .. }) => (key, reason),
        other => panic!("expected {key} = {value} refused, got {other:?}"),
    }
}

#[test]
fn a_fill_beyond_the_limit_is_refused_naming_its_field() {
    for base in ["100000", "4294967296", &i64::MAX.to_string()] {
        let mut s = scale_scene("pyramid.toml");
        let (key, reason) = refused(&mut s, "fill.box.base", base);
        assert_eq!(key, "fill.box.base");
        assert!(reason.contains(&MAX_FILL_BODIES.to_string()), "{reason}");
    }
    let mut s = scale_scene("disk-column.toml");
    let (key, reason) = refused(&mut s, "fill.grain.count", "1000000000");
    assert_eq!(key, "fill.grain.count");
    assert!(reason.contains("1000000000 bodies"), "{reason}");
    // The count of a pyramid's bodies, at the limit and beyond a usize.
    let mut fill = FillSpec::lattice("box", 1, 1, [0.0; 2], [1.0; 2], disk(), 1.0);
    fill.pattern = FillPattern::Pyramid;
    fill.count = None;
    fill.columns = None;
    for (base, len) in [(4471, 4471 * 4472 / 2), (1 << 32, (1 << 31) * ((1 << 32) + 1))] {
        fill.base = Some(base);
        assert_eq!(fill.len(), len);
    }
    const { assert!(4471 * 4472 / 2 <= MAX_FILL_BODIES && 4472 * 4473 / 2 > MAX_FILL_BODIES) };
    fill.base = Some(usize::MAX);
    assert_eq!(fill.len(), usize::MAX);
}
