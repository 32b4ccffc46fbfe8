//! A `--set` whose value the scene's reader refuses gives the reader's reason under the key
//! as given, without the reader's own path of the field, which names an array of tables
//! without its element (`in `contacts.shape_b``, where the key is `contacts.rub.shape_b`).

use moreau_models::{ModelError, Scene};

const TABLE: &str = include_str!("../../../scenes/bodies/shaken-table.toml");

#[test]
fn a_refused_value_gives_the_reason_under_the_key_alone() {
    let mut scene = Scene::from_toml_str(TABLE).unwrap();
    for (key, value, reason) in [
        ("contacts.rub.shape_b", "-1", "invalid value: integer `-1`, expected usize"),
        (
            "bodies.table.motion.kind",
            "linear",
            "unknown field `amplitude`, expected `velocity` or `omega`",
        ),
        ("contact_set", "detectd", "unknown variant `detectd`, expected `fixed` or `detected`"),
        ("projection", "maybe", "invalid type: string \"maybe\", expected a boolean"),
    ] {
        let e = scene.set(key, value).unwrap_err();
        let ModelError::BadValue { key: named, reason: got, .. } = &e else { panic!("{e}") };
        assert_eq!((named.as_str(), got.as_str()), (key, reason), "{e}");
    }
}
