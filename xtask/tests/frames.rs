//! `frames` end to end: the pendulum striking a wall (a declared scene) and a report model's
//! scene file drawn as a strip (SVG, PNG) and an animation.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, ensure};
use xtask::frames::{Shape, paint};
use xtask::scene_frames::{ANIMATION_FRAMES, FramesArgs, FramesError, rows, run, strip};
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

/// The run of a scene file of the repository with `sets`.
fn simulated(path: &str, sets: &[&str]) -> Result<xtask::runs::RunResult> {
    let o = SimulateOptions {
        scene: Some(scene(path)),
        sets: sets.iter().map(|s| (*s).to_owned()).collect(),
        ..SimulateOptions::default()
    };
    simulate(&o)
}

#[test]
fn instants_out_of_order_repeated_or_outside_the_run_are_refused_by_name() -> Result<()> {
    let result = simulated("scenes/bodies/pendulum-wall.toml", &["t_end=1"])?;
    let refused = |times: &[f64], count: Option<usize>| -> Result<FramesError> {
        let e = rows(&result, Some(times).filter(|_| count.is_none()), count).expect_err("refused");
        e.downcast_ref::<FramesError>().cloned().with_context(|| format!("untyped: {e:#}"))
    };
    assert_eq!(refused(&[0.5, 0.25], None)?, FramesError::NotIncreasing { before: 0.5, t: 0.25 });
    assert_eq!(refused(&[0.5, 0.5], None)?, FramesError::NotIncreasing { before: 0.5, t: 0.5 });
    // Rows every 10 steps of 1e-4 s: 0.5001 s is drawn from the row at 0.5 s.
    match refused(&[0.5, 0.5001], None)? {
        FramesError::SameRow { row_t, spacing, .. } => {
            assert_eq!(row_t, 0.5);
            assert!((spacing - 1e-3).abs() < 1e-15, "{spacing}");
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(refused(&[], None)?, FramesError::NoTimes);
    let outside = refused(&[0.0, 1.5], None)?;
    assert_eq!(outside, FramesError::OutsideRun { t: 1.5, first: 0.0, last: 1.0, t_end: 1.0 });
    assert!(matches!(refused(&[f64::NAN], None)?, FramesError::OutsideRun { .. }));
    assert_eq!(refused(&[], Some(0))?, FramesError::ZeroCount);
    // 1 s in rows of 1 ms: 1,001 rows, fewer than 100 frames need, more than 2,000 would.
    assert_eq!(rows(&result, None, Some(100))?.len(), 100);
    let stack = simulated("scenes/bodies/stack.toml", &[])?;
    let e = rows(&stack, None, Some(20)).expect_err("11 rows");
    let e = e.downcast_ref::<FramesError>().context("untyped")?;
    assert_eq!(*e, FramesError::CountAboveRows { count: 20, rows: 11 });
    // Painlevé's rod stops at its rule before t_end = 1.5 s; the message says so.
    let rod = simulated("scenes/painleve.toml", &[])?;
    let e = rows(&rod, Some(&[1.2]), None).expect_err("after the stop");
    let text = e.to_string();
    assert!(text.contains("t = 1.2 s") && text.contains("stop rule"), "{text}");
    Ok(())
}

#[test]
fn a_resting_pile_with_detected_contacts_is_drawn_with_its_contacts_closed() -> Result<()> {
    let result = simulated("scenes/bodies/stack.toml", &[])?;
    let r = result.record();
    let rows = rows(&result, Some(&[0.0, 0.5, 1.0]), None)?;
    let s = strip(&result, "stack", &rows);
    assert_eq!(s.frames[0].caption[1], "contacts open");
    let marker = paint(moreau_models::Role::ContactPoint);
    for (frame, &k) in s.frames.iter().zip(&rows).skip(1) {
        // Floor to d0, d0 to d1, d1 to d2: three closed contacts, each marked midway between
        // the disk's lowest point, a radius (0.1 m) below its centre, and the floor or the top
        // of the disk under it (the pile rests slightly into its contacts, by less than 1e-3 m).
        assert_eq!(frame.caption[1], "3 contacts closed");
        let mut marks: Vec<[f64; 2]> = frame
            .shapes
            .iter()
            .filter_map(|sh| match sh {
                Shape::Circle { center, paint, .. } if *paint == marker => Some(*center),
                _ => None,
            })
            .collect();
        marks.sort_by(|a, b| a[1].total_cmp(&b[1]));
        assert_eq!(marks.len(), 3);
        for (d, m) in marks.iter().enumerate() {
            let (x, y) = (r.q[k][3 * d], r.q[k][3 * d + 1]);
            let below = if d == 0 { 0.0 } else { r.q[k][3 * d - 2] + 0.1 };
            let expected = 0.5 * (y - 0.1 + below);
            assert!((m[0] - x).abs() < 1e-12 && (m[1] - expected).abs() < 1e-12, "{m:?}");
            assert!((y - 0.1 - below).abs() < 1e-3, "disk {d} is not resting");
        }
        // Each disk's radius, which shows its angle, is drawn over its disk: after it, from
        // the centre to (x + r cos θ, y + r sin θ).
        for d in 0..3 {
            let (x, y, th) = (r.q[k][3 * d], r.q[k][3 * d + 1], r.q[k][3 * d + 2]);
            let disk = frame.shapes.iter().position(|sh| {
                matches!(sh, Shape::Circle { center, radius, .. }
                    if *center == [x, y] && *radius == 0.1)
            });
            let tip = [x + 0.1 * th.cos(), y + 0.1 * th.sin()];
            let radius = frame.shapes.iter().position(|sh| match sh {
                Shape::Poly { points, closed: false, .. } => {
                    points.len() == 2
                        && points[0] == [x, y]
                        && (points[1][0] - tip[0]).abs() < 1e-15
                        && (points[1][1] - tip[1]).abs() < 1e-15
                }
                _ => false,
            });
            let (disk, radius) = (disk.context("no disk")?, radius.context("no radius")?);
            assert!(disk < radius, "disk {d} drawn over its radius");
        }
    }
    Ok(())
}

#[test]
fn the_first_frame_names_the_contacts_closed_at_the_start() -> Result<()> {
    // The woodpecker starts with its lower sleeve edge on the pole (g_N2 = 0): its own
    // drawing marks it, and the caption says so.
    let result = simulated("scenes/woodpecker.toml", &["t_end=0.01"])?;
    let s = strip(&result, "woodpecker", &[0]);
    assert_eq!(s.frames[0].caption[1], "lower sleeve edge closed");
    let marker = paint(moreau_models::Role::ContactPoint);
    let marks = s.frames[0]
        .shapes
        .iter()
        .filter(|sh| matches!(sh, Shape::Circle { paint, .. } if *paint == marker))
        .count();
    assert_eq!(marks, 1);
    // A declared pendulum starts clear of its wall.
    let pendulum = simulated("scenes/bodies/pendulum-wall.toml", &["t_end=0.01"])?;
    assert_eq!(strip(&pendulum, "p", &[0]).frames[0].caption[1], "contacts open");
    Ok(())
}

#[test]
fn a_refused_instant_exits_non_zero_and_leaves_no_earlier_picture() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let out = dir.path().to_str().context("a UTF-8 path")?;
    let scene = scene("scenes/bodies/pendulum-wall.toml");
    let scene = scene.to_str().context("a UTF-8 path")?;
    let xtask = |times: &str| {
        std::process::Command::new(env!("CARGO_BIN_EXE_xtask"))
            .args(["frames", "--scene", scene, "--set", "t_end=0.1", "--out", out])
            .arg(format!("--times={times}"))
            .output()
    };
    let ok = xtask("0,0.05")?;
    ensure!(ok.status.success(), "{}", String::from_utf8_lossy(&ok.stderr));
    ensure!(dir.path().join("pendulum-wall.png").is_file());
    for (times, words) in [
        ("-0.1,0.05", "t = -0.1 s lies outside the run (0 to 0.1 s)"),
        ("0.05,0.02", "t = 0.02 s follows t = 0.05 s"),
        ("0,0.2", "t = 0.2 s lies outside the run"),
    ] {
        let o = xtask(times)?;
        let err = String::from_utf8_lossy(&o.stderr);
        ensure!(o.status.code() == Some(1) && err.contains(words), "{times}: {err}");
        for name in ["pendulum-wall.svg", "pendulum-wall.png", "pendulum-wall_anim.svg"] {
            ensure!(!dir.path().join(name).exists(), "{times}: an earlier {name} is left");
        }
    }
    // A negative instant given as its own word is read as a time, not as an option.
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_xtask"))
        .args(["frames", "--scene", scene, "--set", "t_end=0.1", "--out", out, "--times", "-1"])
        .output()?;
    let err = String::from_utf8_lossy(&o.stderr);
    ensure!(o.status.code() == Some(1) && err.contains("t = -1 s lies outside"), "{err}");
    Ok(())
}

#[test]
fn captions_are_cut_to_the_cell_and_the_title_widens_the_picture() -> Result<()> {
    use xtask::frames::{CAPTION, Frame, LINE, Paint, Strip, TITLE, TITLE_FONT, text_width, wrap};
    let line = "corner 3 (lower) impact · corner 4 (lower) impact";
    // 240-pixel cells leave 232 pixels: the line is wider and is cut at its separator.
    assert!(text_width(line, CAPTION, false) > 232);
    assert_eq!(wrap(line, 232), ["corner 3 (lower) impact", "corner 4 (lower) impact"]);
    assert_eq!(wrap("t = 0.5000 s", 232), ["t = 0.5000 s"]);
    // A single item too wide is cut at its spaces, each line within the width.
    let long = "a-contact-name with a rather long description of its state here";
    let lines = wrap(long, 120);
    assert!(lines.len() > 1 && lines.join(" ") == long, "{lines:?}");
    assert!(lines.iter().all(|l| text_width(l, CAPTION, false) <= 120), "{lines:?}");
    let paint = Paint { stroke: (0, 0, 0), width: 1, fill: None };
    let frame = Frame {
        t: 0.0,
        shapes: vec![Shape::Circle { center: [0.0, 0.0], radius: 1.0, paint }],
        caption: vec!["t = 0.000 s".into(), line.into()],
        window: None,
    };
    let strip = Strip {
        title: "a title far wider than one cell of the strip (declared, Δt = 1e-4 s)".into(),
        frames: vec![frame],
        columns: 6,
        cell_width: 240,
        cell_height: 240,
        window: None,
    };
    // Three caption lines under the 240-pixel drawing; the title's width sets the picture's.
    let (w, h) = strip.size();
    assert_eq!(h, TITLE + 240 + 3 * LINE + 10);
    assert!(w > 240 && w == text_width(&strip.title, TITLE_FONT, true) + 24, "{w}");
    let dir = tempfile::tempdir()?;
    strip.write_still(dir.path(), "wide")?;
    let svg = std::fs::read_to_string(dir.path().join("wide.svg"))?;
    ensure!(svg.contains(&format!(r#"width="{w}" height="{h}""#)), "{}", &svg[..200]);
    for part in ["corner 3 (lower) impact", "corner 4 (lower) impact"] {
        ensure!(svg.contains(&format!("\n{part}\n")), "{part} not a line of its own");
    }
    // The drawing cell is centred under the title: its frame starts (w − 240)/2 + 4 in.
    let x = (w - 240) / 2 + 4;
    ensure!(svg.contains(&format!(r#"<rect x="{x}" y="44" width="232""#)), "cell not centred");
    Ok(())
}

#[test]
fn disks_lie_under_their_lines_and_pins_and_markers_on_top() {
    use moreau_models::{Drawing, Role};
    let mut d = Drawing::new();
    d.circle(Role::Joint, [0.0, 0.0], 0.01);
    d.line(Role::Slider, vec![[0.0, 0.0], [0.1, 0.0]]);
    d.circle(Role::Ball, [0.0, 0.0], 0.1);
    d.circle(Role::ContactPoint, [0.0, -0.1], 0.01);
    d.circle(Role::Ground, [1.0, 0.0], 0.05);
    let drawn = xtask::frames::shapes(&d);
    let order: Vec<(bool, f64)> = drawn
        .iter()
        .map(|s| match s {
            Shape::Circle { radius, .. } => (true, *radius),
            Shape::Poly { points, .. } => (false, points[1][0]),
        })
        .collect();
    // The disk, its radius over it, then the pin and the pivot, then the marker.
    assert_eq!(order, [(true, 0.1), (false, 0.1), (true, 0.01), (true, 0.05), (true, 0.01)]);
    let marker = paint(Role::ContactPoint);
    assert!(matches!(drawn.last(), Some(Shape::Circle { paint, .. }) if *paint == marker));
}
