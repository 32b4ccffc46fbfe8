//! A scene refused before its run leaves no file beside the output: neither `OUT.partial` nor
//! the lock `OUT.lock`, which the run takes only once the scene is checked.

use std::path::Path;

use anyhow::{Result, ensure};
use moreau_cli::simulate::{SimulateOptions, run_to_csv};

#[test]
fn a_fill_beyond_the_limit_is_refused_before_any_file_is_written() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/scale");
    for (scene, set, field) in [
        ("pyramid.toml", "fill.box.base=100000", "fill.box.base"),
        ("disk-column.toml", "fill.grain.count=1000000000", "fill.grain.count"),
    ] {
        let out = dir.path().join("out.csv");
        let options = SimulateOptions {
            scene: Some(scenes.join(scene)),
            sets: vec![set.into()],
            ..Default::default()
        };
        let e = format!("{:#}", run_to_csv(&options, &out, &mut |_| {}).unwrap_err());
        ensure!(e.contains(field) && e.contains("10000000"), "{e}");
        let left: Vec<_> = std::fs::read_dir(dir.path())?.collect();
        ensure!(left.is_empty(), "{left:?}");
    }
    Ok(())
}
