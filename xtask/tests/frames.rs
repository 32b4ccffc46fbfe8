//! `frames` end to end: the pendulum striking a wall (a declared scene) and a report model's
//! scene file drawn as a strip (SVG, PNG) and an animation.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, ensure};
use xtask::frames::{Shape, paint};
use xtask::scene_frames::{ANIMATION_FRAMES, FramesArgs, rows, run, strip};
use xtask::simulate::{SimulateOptions, run as simulate};

fn scene(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(path)
}

fn args(scene: PathBuf, out: &Path) -> FramesArgs {
    FramesArgs {
        model: None,
        scene: Some(scene),
        sets: vec!["t_end=1".into()],
        times: None,
        count: None,
        out: out.to_owned(),
        forces: false,
    }
}

#[test]
fn frames_draw_a_declared_scene() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let a = FramesArgs {
        times: Some(vec![0.0, 0.25, 0.5098, 0.75]),
        ..args(scene("scenes/bodies/pendulum-wall.toml"), dir.path())
    };
    let files = run(&a)?;
    let names: Vec<String> =
        files.iter().filter_map(|f| Some(f.file_name()?.to_string_lossy().into_owned())).collect();
    assert_eq!(names, ["pendulum-wall.svg", "pendulum-wall.png", "pendulum-wall_anim.svg"]);
    for f in &files {
        ensure!(std::fs::metadata(f)?.len() > 1000, "{} is nearly empty", f.display());
    }
    let png = std::fs::read(&files[1])?;
    ensure!(png.starts_with(b"\x89PNG\r\n\x1a\n"), "not a PNG");
    let svg = std::fs::read_to_string(&files[0])?;
    for caption in ["t = 0.0000 s", "t = 0.2500 s", "t = 0.7500 s", "contacts open"] {
        ensure!(svg.contains(caption), "the strip lacks the caption {caption}");
    }
    let anim = std::fs::read_to_string(&files[2])?;
    assert_eq!(anim.matches("<animate ").count(), ANIMATION_FRAMES);
    // The bob is a disk drawn in every frame of the animation.
    ensure!(anim.matches("<circle").count() >= ANIMATION_FRAMES, "no bob in the animation");
    Ok(())
}

#[test]
fn the_frame_at_the_impact_marks_the_closed_contact() -> Result<()> {
    let o = SimulateOptions {
        scene: Some(scene("scenes/bodies/pendulum-wall.toml")),
        sets: vec!["t_end=1".into()],
        ..SimulateOptions::default()
    };
    let result = simulate(&o)?;
    // The row that holds the first impact step, and a row in free flight before it.
    let r = result.record();
    let impact = r.impacts.first().context("no impact")?.t;
    let row = r.t.iter().position(|&t| t >= impact - 1e-9).context("impact row")?;
    let before = rows(&result, Some(&[0.25]), None)?[0];
    assert_eq!(r.t[before], 0.25);
    let s = strip(&result, "pendulum-wall", &[before, row]);
    let marker = paint(moreau_models::Role::ContactPoint);
    let marked = |k: usize| {
        s.frames[k]
            .shapes
            .iter()
            .any(|sh| matches!(sh, Shape::Circle { paint, .. } if *paint == marker))
    };
    ensure!(!marked(0), "a contact marked before the impact");
    ensure!(marked(1), "no contact marked at the impact: {:?}", s.frames[1].caption);
    // With ε_N = 0.8 the bob leaves the wall within the row: closed, then open again.
    ensure!(s.frames[1].caption[1] == "hit impact", "{:?}", s.frames[1].caption);
    // The marker lies on the wall's face x = 0.05 m.
    let on_wall = s.frames[1].shapes.iter().any(|sh| {
        matches!(sh, Shape::Circle { center, paint, .. }
            if *paint == marker && (center[0] - 0.05).abs() < 1e-3)
    });
    ensure!(on_wall, "the marker is not on the wall");
    // Times outside the run are refused, naming the time.
    let e = rows(&result, Some(&[2.0]), None).expect_err("outside");
    ensure!(format!("{e}").contains("t = 2"), "{e}");
    Ok(())
}

#[test]
fn frames_draw_a_report_scene_file_and_count_evenly() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let a = FramesArgs {
        count: Some(4),
        sets: vec!["t_end=1".into()],
        ..args(scene("scenes/ball.toml"), dir.path())
    };
    let files = run(&a)?;
    let svg = std::fs::read_to_string(&files[0])?;
    for caption in ["t = 0.0000 s", "t = 0.3330 s", "t = 0.6670 s", "t = 1.0000 s"] {
        ensure!(svg.contains(caption), "the strip lacks {caption}");
    }
    ensure!(files[1].file_name().context("name")? == "ball.png");
    Ok(())
}

#[test]
fn force_networks_of_a_pile_are_drawn_at_the_rows_steps() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let a = FramesArgs {
        times: Some(vec![0.0, 0.5, 1.0]),
        forces: true,
        sets: Vec::new(),
        ..args(scene("scenes/bodies/stack.toml"), dir.path())
    };
    let files = run(&a)?;
    for f in &files {
        ensure!(std::fs::metadata(f)?.len() > 1000, "{} is tiny", f.display());
    }
    // The animation shows the networks too: the red of their lines (180, 20, 20) is in it.
    let anim = files.iter().find(|f| f.to_string_lossy().ends_with("_anim.svg")).context("anim")?;
    ensure!(std::fs::read_to_string(anim)?.contains("#b41414"), "no network lines");
    // The same frames through the library: the initial state has no line; at rest each of
    // the three contacts is one.
    let options = SimulateOptions { scene: a.scene.clone(), ..SimulateOptions::default() };
    let result = simulate(&options)?;
    let rows = rows(&result, a.times.as_deref(), None)?;
    let frames = xtask::scene_frames::networks(&result, &rows)?;
    let lines = |f: &xtask::frames::Frame| {
        f.shapes
            .iter()
            .filter(|s| matches!(s, Shape::Poly { paint, .. } if paint.stroke == (180, 20, 20)))
            .count()
    };
    assert_eq!(frames.iter().map(lines).collect::<Vec<_>>(), [0, 3, 3]);
    assert_eq!(frames[2].caption, ["t = 1.0000 s", "3 contacts carry an impulse"]);
    // A report model has no bodies to draw the network on.
    let ball = FramesArgs { model: Some("ball".into()), scene: None, ..a };
    ensure!(run(&ball).is_err());
    Ok(())
}
