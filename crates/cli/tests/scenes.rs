//! Declared scene files through `simulate` and `sweep`: columns named after the bodies and
//! contacts, the pendulum striking a wall against its closed forms, sweeps over declared
//! fields, the energy guard, and typed refusals that name what is wrong.

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context, Result, ensure};
use moreau_cli::grid::Axis;
use moreau_cli::guard;
use moreau_cli::simulate::{SimulateOptions, run, scene};
use moreau_cli::sweep::{SweepOptions, run as sweep};
use moreau_cli::{CliError, Divergence};
use moreau_models::{ModelError, Scene};

/// Radius of the bob and x of the wall's face in scenes/bodies/pendulum-wall.toml (m).
const RADIUS: f64 = 0.05;
const WALL: f64 = 0.05;

fn pendulum() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/bodies/pendulum-wall.toml")
}

fn moreau(args: &[&str]) -> std::process::Output {
    let out = Command::new(env!("CARGO_BIN_EXE_moreau")).args(args).output();
    out.unwrap_or_else(|e| panic!("cannot start moreau: {e}"))
}

fn cli_error(e: &anyhow::Error) -> Option<&CliError> {
    e.chain().find_map(|c| c.downcast_ref::<CliError>())
}

fn column(headers: &[String], name: &str) -> Result<usize> {
    headers.iter().position(|h| h == name).with_context(|| format!("no column {name}"))
}

#[test]
fn simulate_runs_a_declared_scene_with_columns_named_after_bodies_and_contacts() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let out = dir.path().join("pendulum.csv");
    let scene = pendulum();
    let o = moreau(&[
        "simulate",
        "--scene",
        scene.to_str().context("path")?,
        "--tf",
        "1.5",
        "--out",
        out.to_str().context("path")?,
    ]);
    ensure!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut r = csv::Reader::from_path(&out)?;
    let h: Vec<String> = r.headers()?.iter().map(str::to_owned).collect();
    assert_eq!(
        h,
        [
            "t",
            "bob.x",
            "bob.y",
            "bob.theta",
            "bob.vx",
            "bob.vy",
            "bob.omega",
            "hit.PN",
            "hit.PT",
            "hit.active",
            "hinge.Lx",
            "hinge.Ly",
            "T",
            "V",
            "dissipated",
            "projected"
        ]
    );
    let rows: Vec<Vec<f64>> = r
        .records()
        .map(|row| row?.iter().map(|x| x.parse::<f64>().map_err(Into::into)).collect())
        .collect::<Result<_>>()?;
    // Row 0, then one row per 10 steps of 1e-4 s up to t_end = 1.5 s.
    assert_eq!(rows.len(), 1501);
    assert_eq!(rows[1500][0], 1.5);
    let (x, p_n) = (column(&h, "bob.x")?, column(&h, "hit.PN")?);
    // The bob never crosses the wall, and it does reach it (the wall is not out of range).
    let closest = rows.iter().map(|row| row[x] + RADIUS).fold(f64::NEG_INFINITY, f64::max);
    ensure!(closest <= WALL + 1e-6, "the bob crossed the wall: x + r = {closest}");
    ensure!(closest >= WALL - 1e-3, "the bob never reached the wall: x + r <= {closest}");
    ensure!(rows.iter().any(|row| row[p_n] > 0.0), "no impulse at the wall");
    // The wall pushes along x only (μ = 0): the bob's vertical momentum changes by gravity's
    // impulse and the hinge's over each row's 10 steps of 1e-4 s.
    let (vy, l_y) = (column(&h, "bob.vy")?, column(&h, "hinge.Ly")?);
    for k in 1..rows.len() {
        let change = rows[k][vy] - rows[k - 1][vy];
        ensure!((change - (-9.81 * 1e-3 + rows[k][l_y])).abs() < 1e-12, "row {k}");
    }
    // The rod keeps its length 1 m within the projection's tolerance.
    let y = column(&h, "bob.y")?;
    for row in &rows {
        ensure!((row[x].hypot(row[y]) - 1.0).abs() < 1e-6, "rod length at t = {}", row[0]);
    }
    Ok(())
}

#[test]
fn a_sweep_over_the_wall_restitution_rebounds_with_eps() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let out = dir.path().join("sweep.csv");
    let axes = vec![Axis::parse("contacts.hit.eps_n=0.5,0.8")?, Axis::parse("t_end=1")?];
    let summary = sweep(&SweepOptions::scene(&pendulum(), axes), &out)?;
    assert_eq!((summary.rows, summary.diverged, summary.failed), (2, 0, 0));
    let part = moreau_cli::parts::read_part(&out, false)?;
    let h = &part.columns;
    let (eps, pre, post, t) = (
        column(h, "contacts.hit.eps_n")?,
        column(h, "hit.first_impact_gamma_pre")?,
        column(h, "hit.first_impact_gamma_post")?,
        column(h, "hit.first_impact_t")?,
    );
    // The bob (m = 1 kg, I = 1.25e-3 kg m² about its centre) falls from φ0 = 0.5 rad on a
    // rod of L = 1 m: (m L² + I) φ̇²/2 = m g L (1 − cos φ0) at the bottom, where it meets the
    // wall with the speed L φ̇, after a quarter of the large-amplitude period,
    // K(sin(φ0/2))/ω0 with ω0² = m g L/(m L² + I). The midpoint step errs on the energy
    // by O(Δt²) (the approach speed meets the closed form to 7e-9 relative; the CSV prints
    // it in full).
    let (g, m, inertia, l, phi0, dt) = (9.81, 1.0, 1.25e-3, 1.0, 0.5f64, 1e-4);
    let j = m * l * l + inertia;
    let speed = l * (2.0 * m * g * l * (1.0 - phi0.cos()) / j).sqrt();
    // K(k) = π / (2 AGM(1, sqrt(1 − k²))).
    let k = (0.5 * phi0).sin();
    let (mut a, mut b) = (1.0f64, (1.0 - k * k).sqrt());
    for _ in 0..10 {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    let quarter = std::f64::consts::FRAC_PI_2 / a / (m * g * l / j).sqrt();
    let mut times = Vec::new();
    for (_, row) in &part.rows {
        let get = |j: usize| -> Result<f64> { Ok(row[j].parse::<f64>()?) };
        let (e, before, after) = (get(eps)?, get(pre)?, get(post)?);
        ensure!((-after / before - e).abs() < 1e-8, "eps_n = {e}: {after} / {before}");
        ensure!((before + speed).abs() < 1e-6 * speed, "approach {before}, closed form {speed}");
        times.push(get(t)?);
    }
    // ε acts after the first impact only: both members reach the wall at the same step.
    assert_eq!(times[0], times[1]);
    // The first impact is the midpoint of the first step whose midpoint gap is closed:
    // within the step after the closed-form instant, up to the scheme's O(Δt²) phase error.
    let late = times[0] - quarter;
    ensure!(
        (-1e-7..dt + 1e-7).contains(&late),
        "first impact at {}, closed form {quarter}",
        times[0]
    );
    Ok(())
}

#[test]
fn model_and_scene_must_agree_and_one_must_be_given() -> Result<()> {
    let path = pendulum();
    let both = SimulateOptions {
        model: Some("ball".into()),
        scene: Some(path.clone()),
        ..Default::default()
    };
    let e = scene(&both).expect_err("disagreement");
    ensure!(matches!(cli_error(&e), Some(CliError::ModelMismatch { .. })), "{e:#}");
    ensure!(format!("{e:#}").contains("'declared'"), "{e:#}");
    // Naming the scene's own model is accepted; so is a report scene file without a name.
    let named = SimulateOptions { model: Some("declared".into()), ..both.clone() };
    ensure!(scene(&named)?.kind().name() == "declared");
    let report = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/ball.toml");
    let ball = SimulateOptions { scene: Some(report), ..Default::default() };
    ensure!(scene(&ball)?.kind().name() == "ball");
    let neither = SimulateOptions::default();
    let e = run(&neither).expect_err("nothing to run");
    ensure!(matches!(cli_error(&e), Some(CliError::NoModel { .. })), "{e:#}");
    // Through the command: a non-zero exit and the reason.
    let dir = tempfile::tempdir()?;
    let out = dir.path().join("x.csv");
    let out = out.to_str().context("path")?;
    let p = path.to_str().context("path")?;
    for (args, needle) in [
        (vec!["simulate", "ball", "--scene", p, "--out", out], "disagrees"),
        (vec!["simulate", "--out", out], "no model to run"),
        (vec!["sweep", "--set", "eps_n=0.5", "--out", out], "no model to run"),
        (vec!["sweep", "cam", "--scene", p, "--set", "t_end=1", "--out", out], "disagrees"),
    ] {
        let o = moreau(&args);
        let stderr = String::from_utf8_lossy(&o.stderr);
        ensure!(!o.status.success() && stderr.contains(needle), "{args:?}: {stderr}");
    }
    Ok(())
}

#[test]
fn bad_paths_and_fields_are_refused_naming_them() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let out = dir.path().join("x.csv");
    let out = out.to_str().context("path")?;
    let path = pendulum();
    let p = path.to_str().context("path")?;
    for (args, needle) in [
        (
            vec!["simulate", "--scene", p, "--set", "bodies.bobb.mass=2", "--out", out],
            "bodies.bobb.mass",
        ),
        (
            vec!["simulate", "--scene", p, "--set", "bodies.bob.mass=-1", "--out", out],
            "bodies.bob.mass",
        ),
        (vec!["simulate", "--scene", p, "--set", "contacts.hit.eps_n=1.5", "--out", out], "eps_n"),
        (
            vec!["sweep", "--scene", p, "--set", "contacts.hitt.mu=0.1,0.2", "--out", out],
            "contacts.hitt.mu",
        ),
    ] {
        let o = moreau(&args);
        let stderr = String::from_utf8_lossy(&o.stderr);
        ensure!(!o.status.success() && stderr.contains(needle), "{args:?}: {stderr}");
        ensure!(!Path::new(out).exists(), "{args:?} wrote {out}");
    }
    // A misspelt field in the file itself is named by its path.
    let text = std::fs::read_to_string(&path)?.replace("inertia = 0.00125", "inertiaa = 0.00125");
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, text)?;
    let o = moreau(&["simulate", "--scene", bad.to_str().context("path")?, "--out", out]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    ensure!(!o.status.success() && stderr.contains("bodies.bob.inertiaa"), "{stderr}");
    Ok(())
}

#[test]
fn the_energy_bound_guards_declared_scenes_without_external_work_only() -> Result<()> {
    let text = std::fs::read_to_string(pendulum())?;
    let free = Scene::from_toml_str(&text)?;
    ensure!(guard::energy_bound_applies(&free.build()?));
    // A constant torque on the bob does work that V does not count: no energy bound, and the
    // pendulum, pumped round and round without its wall, runs to the end.
    let pumped = text.split("[[contacts]]").next().context("scene")?.to_owned()
        + "\n[[forces]]\ntype = \"torque\"\nbody = \"bob\"\ntorque = 50.0\n";
    let pumped = Scene::from_toml_str(&pumped)?;
    ensure!(!guard::energy_bound_applies(&pumped.build()?));
    let sim = moreau_cli::simulate::run_scene(&Scene { t_end: 1.0, ..pumped }, 1_000_000)?;
    let r = &sim.record;
    let gained = r.kinetic.last().context("rows")? + r.potential.last().context("rows")?
        - (r.kinetic[0] + r.potential[0]);
    ensure!(gained > 100.0, "the torque did {gained} J of work");
    // A rod released level with its hinge at the origin starts with T + V = 0; the midpoint
    // scheme's energy error must not pass for a divergence.
    let level = text
        .replace("position = [-0.479425538604203, -0.8775825618903728]", "position = [-1.0, 0.0]")
        .replace("anchor_b = [0.479425538604203, 0.8775825618903728]", "anchor_b = [1.0, 0.0]");
    let level = Scene::from_toml_str(&level)?;
    let sim = moreau_cli::simulate::run_scene(&Scene { t_end: 1.0, ..level }, 1_000_000)?;
    ensure!(sim.steps == 10_000);
    Ok(())
}

#[test]
fn a_declared_step_above_the_stability_limit_is_refused() -> Result<()> {
    // A stiff spring between the bob and the ground with a step far above 2/ω: the guard
    // refuses the run before the first step and names the limit.
    let text = std::fs::read_to_string(pendulum())?
        + "\n[[forces]]\ntype = \"spring\"\nbody_a = \"ground\"\nanchor_a = [0.0, -1.0]\n\
           body_b = \"bob\"\nanchor_b = [0.0, 0.0]\nstiffness = 1e9\nrest_length = 0.0\n";
    let scene = Scene::from_toml_str(&text)?;
    let e = moreau_cli::simulate::run_scene(&scene, 1_000_000).expect_err("above the limit");
    match cli_error(&e) {
        Some(CliError::Diverged {
            cause: Divergence::StepAboveStability { limit, .. }, ..
        }) => {
            // ω² = k/m for the bob's translation: the limit is 2 sqrt(m/k).
            ensure!((limit - 2.0 * (1.0f64 / 1e9).sqrt()).abs() < 1e-3 * limit, "{limit}");
        }
        _ => anyhow::bail!("{e:#}"),
    }
    Ok(())
}

/// Each cause is said once: a scene file that cannot be read names the operating system's
/// reason once, and a `--set` that the scene's checks refuse names its key and value once.
#[test]
fn a_refusal_says_its_cause_once() {
    let missing = std::env::temp_dir().join("moreau-no-such-scene.toml");
    let out = moreau(&["simulate", "--scene", missing.to_str().unwrap(), "--out", "unused.csv"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && stderr.contains("cannot read scene file"), "{stderr}");
    assert_eq!(stderr.matches("(os error").count(), 1, "{stderr}");
    let scene = pendulum();
    let out = moreau(&[
        "simulate",
        "--scene",
        scene.to_str().unwrap(),
        "--set",
        "bodies.bob.density=100",
        "--out",
        "unused.csv",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("not instead"), "{stderr}");
    assert_eq!(stderr.matches("bad value `100` for `bodies.bob.density`").count(), 1, "{stderr}");
}

/// A CSV file read back with the `csv` crate: its header and its rows, each row as many
/// fields as it has.
fn read_csv(path: &Path) -> Result<(Vec<String>, Vec<Vec<String>>)> {
    let mut r = csv::ReaderBuilder::new().flexible(true).from_path(path)?;
    let header = r.headers()?.iter().map(str::to_owned).collect();
    let rows = r
        .records()
        .map(|row| Ok(row?.iter().map(str::to_owned).collect()))
        .collect::<Result<_>>()?;
    Ok((header, rows))
}

#[test]
fn names_with_commas_and_quotes_are_quoted_in_the_record_and_the_contacts() -> Result<()> {
    // A disk dropped 5 cm onto a floor: it lands at t ≈ 0.1 s and rests in contact.
    let dir = tempfile::tempdir()?;
    let path = dir.path().join("odd.toml");
    std::fs::write(
        &path,
        r#"dt = 0.001
t_end = 0.3
record_every = 10
gravity = [0.0, -9.81]

[[bodies]]
name = "flo,or"
type = "fixed"
position = [0.0, 0.0]
shapes = [{ type = "half_plane", point = [0.0, 0.0], normal = [0.0, 1.0] }]

[[bodies]]
name = "b\"x"
type = "dynamic"
mass = 1.0
inertia = 0.005
position = [0.0, 0.15]
shapes = [{ type = "disk", center = [0.0, 0.0], radius = 0.1 }]

[[contacts]]
name = "c,1"
body_a = "flo,or"
body_b = "b\"x"
eps_n = 0.0
eps_t = 0.0
mu = 0.5
"#,
    )?;
    let (out, contacts) = (dir.path().join("odd.csv"), dir.path().join("contacts.csv"));
    let options = SimulateOptions {
        scene: Some(path),
        contacts: Some(contacts.clone()),
        ..SimulateOptions::default()
    };
    let done = moreau_cli::simulate::run_to_csv(&options, &out, &mut |_| {})?;
    let (header, rows) = read_csv(&out)?;
    let names = [
        "t",
        "b\"x.x",
        "b\"x.y",
        "b\"x.theta",
        "b\"x.vx",
        "b\"x.vy",
        "b\"x.omega",
        "c,1.PN",
        "c,1.PT",
        "c,1.active",
        "T",
        "V",
        "dissipated",
        "projected",
    ];
    ensure!(header == names, "{header:?}");
    ensure!(rows.len() as u64 == done.rows && done.rows == 31, "{} rows", rows.len());
    ensure!(rows.iter().all(|r| r.len() == header.len()), "a row's fields differ from the header");
    // The disk rests on the floor at the end.
    let y: f64 = rows[30][column(&header, "b\"x.y")?].parse()?;
    ensure!((y - 0.1).abs() < 1e-3 && rows[30][column(&header, "c,1.active")?] == "1", "{y}");
    let (header, rows) = read_csv(&contacts)?;
    ensure!(header.join(",") == moreau_cli::contacts::HEADER, "{header:?}");
    ensure!(!rows.is_empty() && done.contact_rows == Some(rows.len() as u64));
    for row in &rows {
        ensure!(row.len() == header.len(), "{row:?}");
        let (a, b) = (column(&header, "body_a")?, column(&header, "body_b")?);
        ensure!(row[a] == "flo,or" && row[b] == "b\"x", "{row:?}");
    }
    Ok(())
}

#[test]
fn an_unknown_key_is_told_as_such_with_the_keys_of_its_level() -> Result<()> {
    let ball = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/bodies/ball.toml");
    let b = ball.to_str().context("path")?;
    for (args, said) in [
        (
            vec!["simulate", "--scene", b, "--set", "zzz=1"],
            "--set zzz=1: unknown key `zzz`; the keys of the scene are dt, t_start, t_end, record_every, \
             solver, stop_at, projection, inexact_residual, gravity, bodies, joints, forces, \
             contacts, contacts_auto, contact_set, fill, impulses",
        ),
        (
            vec!["simulate", "--scene", b, "--set", "bodies.ball.masss=2"],
            "unknown key `bodies.ball.masss`: `bodies.ball` has no key `masss` (did you mean \
             `bodies.ball.mass`?); the keys of `bodies.ball` are name, type, mass, inertia,",
        ),
        (
            vec!["simulate", "--scene", b, "--set", "bodies.bal.mass=2"],
            "`bodies` has no key `bal` (did you mean `bodies.ball.mass`?); the keys of `bodies` \
             are floor, ball",
        ),
        (
            vec!["sweep", "ball", "--set", "eps_nn=0.1,0.2"],
            "unknown key `eps_nn` (did you mean `eps_n`?); the keys of the scene are solver, dt, \
             record_every, t_end, t_start, stop_at, projection, inexact_residual, impulses, eps_n, g, \
             init.v0, init.y0, m, r",
        ),
        (
            vec!["simulate", "ball", "--set", "init.y00=2"],
            "unknown key `init.y00`: `init` has no key `y00` (did you mean `init.y0`?); the keys \
             of `init` are y0, v0",
        ),
    ] {
        let o = moreau(&[args.as_slice(), &["--out", "unused.csv"]].concat());
        let stderr = String::from_utf8_lossy(&o.stderr);
        ensure!(o.status.code() == Some(1), "{args:?}: {stderr}");
        ensure!(stderr.contains(said) && !stderr.contains("bad value"), "{args:?}: {stderr}");
    }
    // Typed, with the optional fields of a body among the keys; a bad value stays one.
    let options = |set: &str| SimulateOptions {
        scene: Some(ball.clone()),
        sets: vec![set.to_owned()],
        ..Default::default()
    };
    let e = scene(&options("bodies.ball.masss=2")).expect_err("unknown");
    let Some(ModelError::UnknownKey { level, name, valid, suggestion, .. }) =
        e.chain().find_map(|c| c.downcast_ref::<ModelError>())
    else {
        anyhow::bail!("{e:#}")
    };
    ensure!(level == "bodies.ball" && name == "masss", "{e:#}");
    ensure!(suggestion.as_deref() == Some("bodies.ball.mass"), "{e:#}");
    ensure!(valid.iter().any(|k| k == "density"), "{valid:?}");
    let e = scene(&options("bodies.ball.mass=-1")).expect_err("bad value");
    ensure!(cli_error(&e).is_none() && format!("{e:#}").contains("bad value `-1`"), "{e:#}");
    Ok(())
}

/// The report's ball declared (`scenes/bodies/ball.toml`, 1 kg from y = 1 m, ε_N = 0.9,
/// without the projection) over 2 s: the record's last columns are T, V, the energy the
/// impulses removed and the energy the projection added, and T + V + dissipated − projected
/// stays at the 9.81 J the ball starts with; `projected` is 0 without the projection and
/// positive with it, which lifts the ball out of the floor after each impact.
#[test]
fn the_record_ends_with_the_energies_whose_sum_is_kept() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/bodies/ball.toml");
    let scene = scene.to_str().context("path")?;
    for projection in [false, true] {
        let out = dir.path().join(format!("ball-{projection}.csv"));
        let set = format!("projection={projection}");
        let args = ["simulate", "--scene", scene, "--tf", "2", "--set", &set, "--out"];
        let o = moreau(&[&args[..], &[out.to_str().context("path")?]].concat());
        ensure!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let (h, rows) = read_csv(&out)?;
        ensure!(h[h.len() - 4..] == ["T", "V", "dissipated", "projected"], "{h:?}");
        let [t, v, d, p] = ["T", "V", "dissipated", "projected"].map(|c| column(&h, c));
        let (t, v, d, p) = (t?, v?, d?, p?);
        let number = |row: &[String], k: usize| row[k].parse::<f64>().map_err(anyhow::Error::from);
        ensure!(number(&rows[0], t)? == 0.0 && number(&rows[0], d)? == 0.0);
        ensure!((number(&rows[0], v)? - 9.81).abs() < 1e-12, "V₀ = {}", rows[0][v]);
        let mut before = 0.0;
        for row in &rows {
            let sum = number(row, t)? + number(row, v)? + number(row, d)? - number(row, p)?;
            ensure!(
                (sum - 9.81).abs() < 1e-9,
                "T + V + dissipated − projected = {sum} at {}",
                row[0]
            );
            let dissipated = number(row, d)?;
            ensure!(dissipated >= before - 1e-15, "dissipation fell at t = {}", row[0]);
            before = dissipated;
        }
        // Three impacts by 2 s at ε_N = 0.9, each removing (1 − 0.81) of the kinetic energy.
        ensure!(before > 0.19 * 9.81, "dissipated {before} J");
        // The first impact at 4.43 m/s penetrates by at most 4.43 Δt = 4.4 mm (Δt = 1e-3 s),
        // which the projection lifts out at m g = 9.81 N: at most 0.044 J per impact.
        let projected = number(&rows[rows.len() - 1], p)?;
        match projection {
            false => ensure!(projected == 0.0, "projected {projected} J without the projection"),
            true => ensure!((1e-4..0.15).contains(&projected), "projected {projected} J"),
        }
    }
    Ok(())
}

#[test]
fn overrides_valid_only_together_are_taken_together() -> Result<()> {
    // The bob released 0.3 rad to the left rather than 0.5: its position and the hinge's
    // anchor on it move together; either alone leaves the joint open by 0.2 m.
    let theta0: f64 = -0.3;
    let position = format!("bodies.bob.position=[{}, {}]", theta0.sin(), -theta0.cos());
    let anchor = format!("joints.hinge.anchor_b=[{}, {}]", -theta0.sin(), theta0.cos());
    let with = |sets: &[&str]| SimulateOptions {
        scene: Some(pendulum()),
        sets: sets.iter().map(|s| (*s).to_owned()).collect(),
        tf: Some(0.6),
        ..SimulateOptions::default()
    };
    for alone in [&position, &anchor] {
        let e = scene(&with(&[alone])).expect_err("the joint is open");
        ensure!(format!("{e:#}").contains("correct the position or the joint's anchors"), "{e:#}");
        ensure!(e.to_string() == format!("--set {alone}"), "{e}");
    }
    // In either order; a later override that breaks the scene is the one named.
    for sets in [[&position, &anchor], [&anchor, &position]] {
        let sets = sets.map(String::as_str);
        ensure!(scene(&with(&sets))?.to_toml_string()?.contains("anchor_b = [0.29552020666133955"));
        let e = scene(&with(&[sets[0], sets[1], "dt=-1"])).expect_err("dt < 0");
        ensure!(e.to_string() == "--set dt=-1", "{e:#}");
    }
    let dir = tempfile::tempdir()?;
    let out = dir.path().join("released.csv");
    moreau_cli::simulate::run_to_csv(&with(&[&position, &anchor]), &out, &mut |_| {})?;
    let (h, rows) = read_csv(&out)?;
    let rows: Vec<Vec<f64>> = rows
        .iter()
        .map(|row| row.iter().map(|x| x.parse::<f64>().map_err(Into::into)).collect())
        .collect::<Result<_>>()?;
    let (x, vx, p_n) = (column(&h, "bob.x")?, column(&h, "bob.vx")?, column(&h, "hit.PN")?);
    ensure!((rows[0][x] - theta0.sin()).abs() < 1e-15, "released at x = {}", rows[0][x]);
    // Energy to the wall, where the rod hangs vertically: m g L (1 − cos θ0) = ½ (m L² + I) ω²
    // with m = 1 kg, L = 1 m, I = 0.00125 kg m².
    let v = (2.0 * 9.81 * (1.0 - theta0.cos()) / 1.00125).sqrt();
    let first = rows.iter().position(|row| row[p_n] > 0.0).context("no impact")?;
    let fastest = rows[..first].iter().map(|row| row[vx]).fold(0.0, f64::max);
    ensure!((fastest - v).abs() < 1e-3 * v, "speed at the wall {fastest}, closed form {v}");
    Ok(())
}
