//! The guards of a run: keys given twice, solver tables, divergence, the step plan, streaming
//! and the warnings about initial gaps.

use anyhow::{Context, Result, ensure};
use moreau_cli::grid::Axis;
use moreau_cli::guard::{self, DEFAULT_MAX_STEPS};
use moreau_cli::simulate::{SimulateOptions, run, run_to_csv, scene, write_record};
use moreau_cli::sweep::{SweepOptions, run as sweep};
use moreau_cli::{CliError, Divergence};

fn ball(sets: &[&str]) -> SimulateOptions {
    SimulateOptions {
        model: Some("ball".into()),
        sets: sets.iter().map(|s| (*s).to_owned()).collect(),
        ..SimulateOptions::default()
    }
}

fn cli_error(e: &anyhow::Error) -> Option<&CliError> {
    e.chain().find_map(|c| c.downcast_ref::<CliError>())
}

#[test]
fn a_key_given_twice_is_refused_aliases_included() -> Result<()> {
    for sets in [
        &["init.y0=1", "y0=3"][..],
        &["eps_n=0.1", "eps_n=0.3"],
        &["params.eps_n=0.1", "eps_n=0.3"],
        &["solver=pgs", "solver=lemke"],
    ] {
        let e = scene(&ball(sets)).expect_err("refused");
        ensure!(matches!(cli_error(&e), Some(CliError::RepeatedKey { .. })), "{sets:?}: {e:#}");
    }
    // --dt and --set dt= set the same entry.
    let e = scene(&SimulateOptions { dt: Some(1e-3), ..ball(&["dt=2e-3"]) }).expect_err("dt");
    ensure!(matches!(cli_error(&e), Some(CliError::RepeatedKey { .. })), "{e:#}");
    // On the woodpecker, `mu` sets all three contacts' μ, so `beak.mu` after it repeats one.
    let wood = SimulateOptions {
        model: Some("woodpecker".into()),
        sets: vec!["mu=0.2".into(), "beak.mu=0.3".into()],
        ..SimulateOptions::default()
    };
    let e = scene(&wood).expect_err("mu");
    ensure!(format!("{e:#}").contains("params.beak.mu"), "{e:#}");
    // A solver and then its tolerance are two entries.
    let s = scene(&ball(&["solver=pgs", "solver.tolerance=1e-8"]))?;
    ensure!(s.solver.name() == "pgs");
    // In a sweep the same holds, and no member runs.
    let dir = tempfile::tempdir()?;
    let out = dir.path().join("s.csv");
    let o = SweepOptions::new("ball", vec![Axis::parse("init.y0=1,2")?, Axis::parse("y0=3")?]);
    let e = sweep(&o, &out).expect_err("sweep");
    ensure!(matches!(cli_error(&e), Some(CliError::RepeatedKey { .. })), "{e:#}");
    ensure!(!out.exists());
    Ok(())
}

#[test]
fn an_entry_set_by_index_and_by_name_or_whole_and_part_is_refused() -> Result<()> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/bodies");
    let declared = |file: &str, sets: &[&str]| SimulateOptions {
        scene: Some(root.join(file)),
        sets: sets.iter().map(|s| (*s).to_owned()).collect(),
        ..SimulateOptions::default()
    };
    // The woodpecker's second body is `sleeve`, its first contact `beak`; the pendulum's bob
    // has a velocity, the scene a gravity.
    for (file, sets, entry) in [
        ("woodpecker.toml", &["bodies.1.mass=1", "bodies.sleeve.mass=3"][..], "bodies.sleeve.mass"),
        ("woodpecker.toml", &["contacts.beak.mu=0.1", "contacts.0.mu=0.3"], "contacts.beak.mu"),
        (
            "pendulum-wall.toml",
            &["bodies.bob.velocity=[1, 0]", "bodies.bob.velocity.0=5"],
            "bodies.bob.velocity",
        ),
        ("pendulum-wall.toml", &["gravity.1=-5", "gravity=[0, -1]"], "gravity"),
        (
            "pendulum-wall.toml",
            &["bodies.1.velocity.1=2", "bodies.bob.velocity=[1, 0]"],
            "bodies.bob.velocity",
        ),
    ] {
        let e = scene(&declared(file, sets)).expect_err("refused");
        let Some(CliError::RepeatedKey { entry: got, .. }) = cli_error(&e) else {
            anyhow::bail!("{sets:?}: {e:#}");
        };
        ensure!(got == entry, "{sets:?}: {got}");
    }
    // Two entries of one array, and one body's field by index after another's by name, are not
    // repeats.
    let s = scene(&declared("pendulum-wall.toml", &["gravity.0=1", "gravity.1=-5"]))?;
    ensure!(s.to_toml_string()?.contains("gravity = [1.0, -5.0]"), "{}", s.to_toml_string()?);
    scene(&declared("woodpecker.toml", &["bodies.2.mass=1", "bodies.sleeve.mass=3"]))?;
    // An option names itself when a `--set` repeats it.
    let e = scene(&SimulateOptions { tf: Some(0.01), ..ball(&["t_end=0.02"]) }).expect_err("tf");
    ensure!(format!("{e:#}").contains("'--tf'"), "{e:#}");
    Ok(())
}

#[test]
fn solver_tables_are_validated() -> Result<()> {
    for (sets, field) in [
        (&["solver=pgs", "solver.tolerance=1"][..], "tolerance"),
        (&["solver=pgs", "solver.tolerance=0"], "tolerance"),
        (&["solver=pgs", "solver.omega=2"], "omega"),
        (&["solver=pgs", "solver.max_iterations=0"], "max_iterations"),
    ] {
        let e = format!("{:#}", scene(&ball(sets)).expect_err(field));
        ensure!(e.contains(field), "{e}");
    }
    let dir = tempfile::tempdir()?;
    for kind in ["auto", "lemke", "enumeration"] {
        let path = dir.path().join(format!("{kind}.toml"));
        std::fs::write(
            &path,
            format!(
                "dt = 0.001\nt_end = 1.0\nsolver = {{ kind = \"{kind}\", max_pivots = 0 }}\n\
                 [params]\nmodel = \"ball\"\nm = 1.0\nr = 0.1\ng = 9.81\neps_n = 0.9\n"
            ),
        )?;
        let o = SimulateOptions { scene: Some(path), ..ball(&[]) };
        let e = format!("{:#}", scene(&o).expect_err(kind));
        ensure!(e.contains("max_pivots"), "{e}");
    }
    Ok(())
}

#[test]
fn divergence_stops_the_run_naming_cause_and_step() -> Result<()> {
    // The woodpecker's torsion spring: ω_max ≈ 458 rad/s, so Δt = 1e-2 s is above 2/ω_max.
    let wood = SimulateOptions {
        model: Some("woodpecker".into()),
        dt: Some(1e-2),
        ..SimulateOptions::default()
    };
    let e = run(&wood).expect_err("unstable");
    match cli_error(&e) {
        Some(CliError::Diverged {
            cause: Divergence::StepAboveStability { limit, .. },
            step,
            ..
        }) => {
            ensure!(*step == 0 && (4e-3..5e-3).contains(limit), "{e:#}")
        }
        _ => anyhow::bail!("{e:#}"),
    }
    // At the report's Δt = 1e-4 s it runs, and its energy never grows.
    let ok = run(&SimulateOptions { dt: Some(1e-4), tf: Some(0.05), ..wood })?;
    let e_total = ok.record().total_energy();
    ensure!(e_total.iter().all(|&e| e <= e_total[0] + 1e-9), "energy grew");
    // The ideal slider-crank with an absurd rod inertia gains energy: stopped with the step.
    let ideal = SimulateOptions {
        model: Some("slider-crank-ideal".into()),
        sets: vec!["j2=1e30".into()],
        ..SimulateOptions::default()
    };
    let e = run(&ideal).expect_err("energy");
    match cli_error(&e) {
        Some(CliError::Diverged {
            cause: Divergence::EnergyGrowth { initial, reached, bound },
            step,
            ..
        }) => ensure!(*step > 0 && reached > bound && bound > initial, "{e:#}"),
        _ => anyhow::bail!("{e:#}"),
    }
    // In a sweep, a diverging member keeps its row, marked diverged with the cause.
    let dir = tempfile::tempdir()?;
    let out = dir.path().join("s.csv");
    let mut o = SweepOptions::new("woodpecker", vec![Axis::parse("dt=1e-4,1e-2")?]);
    o.axes.push(Axis::parse("t_end=0.02")?);
    let s = sweep(&o, &out)?;
    ensure!(s.rows == 2 && s.diverged == 1, "{s:?}");
    let text = std::fs::read_to_string(&out)?;
    let rows: Vec<&str> = text.lines().skip(2).collect();
    ensure!(rows[0].contains(",ok,"), "{}", rows[0]);
    ensure!(rows[1].starts_with("1,2,1e-2,") && rows[1].contains(",diverged,"), "{}", rows[1]);
    ensure!(rows[1].contains("stability limit"), "{}", rows[1]);
    Ok(())
}

/// A time step that carries a body through what it should strike is a divergence: the ball
/// dropped from 1 m (radius 0.1 m) in one step of 10 s used to end 489.5 m below its floor
/// with status `ok`.
#[test]
fn a_body_carried_through_its_contact_stops_the_run() -> Result<()> {
    let penetration = |e: &anyhow::Error| match cli_error(e) {
        Some(CliError::Diverged {
            cause: Divergence::Penetration { depth, bound, at },
            step,
            ..
        }) => Some((*depth, *bound, *at, *step)),
        _ => None,
    };
    // One step: its midpoint is the initial state, 0.9 m above the floor; the end is not.
    let e = run(&SimulateOptions { dt: Some(10.0), tf: Some(10.0), ..ball(&[]) })
        .expect_err("one step through the floor");
    let (depth, bound, at, step) = penetration(&e).context(format!("{e:#}"))?;
    // y = 1 - 10 · 98.1 / 2 = -489.5, the gap y - r = -489.6.
    // The bound is the ball's diameter, 0.2 m.
    ensure!((depth - 489.6).abs() < 1e-9 && bound == 0.2 && step == 0, "{e:#}");
    ensure!(at == "the run's end", "{e:#}");
    // Steps of 1 s: the second step's midpoint lies 8.91 m deep.
    let e = run(&SimulateOptions { dt: Some(1.0), tf: Some(10.0), ..ball(&[]) })
        .expect_err("through the floor");
    let (depth, _, at, step) = penetration(&e).context(format!("{e:#}"))?;
    ensure!((depth - 8.91).abs() < 1e-9 && at == "the step's midpoint" && step == 1, "{e:#}");
    // Steps of 0.1 s take the ball wholly below its floor at the midpoint of its 20th step
    // (0.348 m deep, past its diameter); steps of 0.04 s sink it by 0.06 m at most (its
    // centre at y = 0.0401 m) and bounce: a coarse run, kept.
    let e = run(&SimulateOptions { dt: Some(0.1), tf: Some(10.0), ..ball(&[]) })
        .expect_err("through the floor at a midpoint");
    let (depth, _, at, step) = penetration(&e).context(format!("{e:#}"))?;
    ensure!((depth - 0.347832).abs() < 1e-6 && at == "the step's midpoint" && step == 20);
    let coarse = run(&SimulateOptions { dt: Some(0.04), tf: Some(10.0), ..ball(&[]) })?;
    let lowest = coarse.record().q.column(0).fold(f64::INFINITY, f64::min);
    ensure!((lowest - 0.0401103).abs() < 1e-6, "{lowest}");
    // The report's cam turned at 5e4 rad/s (the report's 20.94) drives its follower into
    // the cam, deeper than its base radius r_b = 3 mm (0.13 m, which the 1 m of every report
    // model let pass); turned at 20.94 rad/s its lift stays above -0.24 mm (the follower's
    // impacts on the cam, stepped at the velocity level), and the run is kept.
    let cam = |omega: &str| SimulateOptions {
        model: Some("cam".into()),
        sets: vec![format!("omega={omega}")],
        ..SimulateOptions::default()
    };
    let e = run(&cam("5e4")).expect_err("the follower inside the cam");
    let (depth, bound, ..) = penetration(&e).context(format!("{e:#}"))?;
    ensure!(depth > 3e-3 && bound == 3e-3, "{e:#}");
    let report = run(&cam("20.94"))?;
    let lowest = report.record().q.column(0).fold(f64::INFINITY, f64::min);
    ensure!(lowest > -2.4e-4 && lowest < 0.0, "{lowest}");
    // A ball that starts 1.1 m deep (with a warning) is measured from there.
    run(&SimulateOptions { tf: Some(0.01), ..ball(&["init.y0=-1"]) })?;
    // The declared ball with its contact detected, in one step: its size is 0.17 m.
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/bodies");
    let detected = |sets: &[&str]| SimulateOptions {
        scene: Some(root.join("ball.toml")),
        sets: sets.iter().map(|s| (*s).to_owned()).collect(),
        dt: Some(10.0),
        tf: Some(10.0),
        ..SimulateOptions::default()
    };
    let e = run(&detected(&["contact_set=detected"])).expect_err("one detected step through");
    let (depth, bound, at, _) = penetration(&e).context(format!("{e:#}"))?;
    ensure!((depth - 489.6).abs() < 1e-9 && at == "the run's end", "{e:#}");
    ensure!((bound - 0.6 * 0.2 * 2f64.sqrt()).abs() < 1e-12, "{e:#}");
    // Started 0.5 m inside the floor, it is measured from there too.
    let deep = SimulateOptions { dt: Some(1e-3), tf: Some(0.01), ..detected(&[]) };
    let sets = ["contact_set=detected", "bodies.ball.position=[0,-0.4]"];
    run(&SimulateOptions { sets: sets.map(str::to_owned).to_vec(), ..deep })?;
    // In a sweep the member is diverged, its row kept.
    let dir = tempfile::tempdir()?;
    let out = dir.path().join("s.csv");
    let axes = vec![Axis::parse("dt=10,1e-3")?, Axis::parse("t_end=10")?];
    let s = sweep(&SweepOptions::new("ball", axes), &out)?;
    ensure!(s.rows == 2 && s.diverged == 1, "{s:?}");
    let text = std::fs::read_to_string(&out)?;
    let rows: Vec<&str> = text.lines().skip(2).collect();
    ensure!(rows[0].contains(",diverged,") && rows[0].contains("penetrates"), "{}", rows[0]);
    ensure!(rows[1].contains(",ok,"), "{}", rows[1]);
    Ok(())
}

#[test]
fn the_step_plan_ends_at_t_end_or_refuses() -> Result<()> {
    for (dt, tf, what) in [
        (1e6, 10.0, "longer than the run"),
        (1e300, 10.0, "longer than the run"),
        (3e-3, 10.0, "not a whole number"),
        (1e-300, 10.0, "--max-steps"),
        (1e-3, 1e300, "--max-steps"),
    ] {
        let o = SimulateOptions { dt: Some(dt), tf: Some(tf), ..ball(&[]) };
        let e = format!("{:#}", run(&o).expect_err(what));
        ensure!(e.contains(what), "dt {dt}, t_end {tf}: {e}");
    }
    // A t_end that Δt divides only up to round-off still ends exactly at t_end.
    for (dt, tf) in [(1e-4, 0.15), (0.1, 0.3), (7e-4, 0.7)] {
        let r = run(&SimulateOptions { dt: Some(dt), tf: Some(tf), ..ball(&[]) })?;
        ensure!(r.record().t.last() == Some(&tf), "{dt} {tf}: {:?}", r.record().t.last());
    }
    // The limit can be raised.
    let o = SimulateOptions { tf: Some(1.0), max_steps: Some(999), ..ball(&[]) };
    ensure!(run(&o).is_err());
    ensure!(run(&SimulateOptions { max_steps: Some(1000), ..o })?.sim.steps == 1000);
    ensure!(DEFAULT_MAX_STEPS == 10_000_000);
    // record_every must keep the last step.
    let e = format!("{:#}", run(&ball(&["record_every=3", "t_end=1"])).expect_err("thinned"));
    ensure!(e.contains("record_every"), "{e}");
    Ok(())
}

#[test]
fn streamed_records_equal_the_kept_ones() -> Result<()> {
    // 12 000 rows: three batches written while running and a last one at the end.
    let dir = tempfile::tempdir()?;
    let o = SimulateOptions { tf: Some(12.0), ..ball(&[]) };
    let streamed = dir.path().join("streamed.csv");
    let done = run_to_csv(&o, &streamed, &mut |_| {})?;
    ensure!(done.rows == 12_001 && done.steps == 12_000);
    let kept = dir.path().join("kept.csv");
    write_record(&run(&o)?, &kept)?;
    ensure!(std::fs::read(&streamed)? == std::fs::read(&kept)?, "the files differ");
    let text = std::fs::read_to_string(&streamed)?;
    ensure!(text.lines().last().is_some_and(|l| l.starts_with("12,")));
    ensure!(!moreau_cli::simulate::partial_path(&streamed).exists());
    // A bad output path is refused before the run; a diverging run leaves only the partial.
    let e = format!(
        "{:#}",
        run_to_csv(&o, &dir.path().join("no/such/dir.csv"), &mut |_| {}).expect_err("path")
    );
    ensure!(e.contains("no/such"), "{e}");
    let bad = dir.path().join("bad.csv");
    let wood = SimulateOptions {
        model: Some("woodpecker".into()),
        dt: Some(1e-2),
        ..SimulateOptions::default()
    };
    ensure!(run_to_csv(&wood, &bad, &mut |_| {}).is_err());
    ensure!(!bad.exists() && moreau_cli::simulate::partial_path(&bad).exists());
    Ok(())
}

#[test]
fn initial_gaps_near_zero_or_negative_are_warned_about() -> Result<()> {
    let warnings = |y0: &str| -> Result<Vec<String>> {
        let s = scene(&ball(&[&format!("init.y0={y0}")]))?;
        Ok(guard::gap_warnings(&s.build()?, 0.0, s.projection))
    };
    ensure!(warnings("1")?.is_empty());
    // r = 0.1: gaps of +2.8e-17 and −1.4e-17 m (round-off) are both reported as touching.
    for y0 in ["0.10000000000000003", "0.09999999999999999", "0.1"] {
        let w = warnings(y0)?;
        ensure!(w.len() == 1 && w[0].contains("touching"), "{y0}: {w:?}");
    }
    let w = warnings("-1")?;
    ensure!(w.len() == 1 && w[0].contains("penetrating") && w[0].contains("-1.1"), "{w:?}");
    // A report model's contacts are numbered from 1, as its columns `PN1`, `PT1`, `A1`.
    ensure!(w[0].starts_with("contact 1 (floor)"), "{w:?}");
    // Without the position projection (the report's scheme) the penetration stays; with it,
    // the first step moves the ball out without an impulse.
    ensure!(w[0].contains("leaves a penetration in place"), "{w:?}");
    let s = scene(&ball(&["init.y0=-1", "projection=true"]))?;
    let w = guard::gap_warnings(&s.build()?, 0.0, s.projection);
    ensure!(w.len() == 1 && w[0].contains("the position projection moves the bodies out"), "{w:?}");
    // The woodpecker's sleeve at y = 0 puts its lower edge 8.8e-7 m into the pole: PN2.
    let s = scene(&SimulateOptions {
        model: Some("woodpecker".into()),
        sets: vec!["init.y=0".into()],
        ..SimulateOptions::default()
    })?;
    let w = guard::gap_warnings(&s.build()?, 0.0, s.projection);
    let lower = "contact 2 (lower sleeve edge) starts penetrating: g_N = -8.800000e-7";
    ensure!(w.len() == 1 && w[0].starts_with(lower), "{w:?}");
    // 1e-6 m above the floor is a gap, not a touch.
    ensure!(warnings("0.100001")?.is_empty());
    let mut seen = Vec::new();
    run_to_csv(
        &SimulateOptions { tf: Some(0.01), ..ball(&["init.y0=-1"]) },
        &tempfile::tempdir()?.path().join("p.csv"),
        &mut |w| seen.push(w.to_owned()),
    )
    .context("run")?;
    ensure!(seen.len() == 1, "{seen:?}");
    Ok(())
}

/// Two bodies joined by a linear spring at its rest length at 45° (k = 400 N/m, m_a = 2 kg,
/// m_b = 3 kg), a body held to the ground by a torsion spring (k_t N m/rad, I = 0.05 kg m²)
/// and six free disks, all above a floor, with the contact set `contact_set`.
fn springs_and_free_disks(contact_set: &str, k_t: f64) -> Result<moreau_models::AnyModel> {
    springs_in_units(contact_set, k_t, 1.0, 1.0, 0.4)
}

/// [`springs_and_free_disks`] with lengths times `s`, masses times `m` and times times √s (so
/// that g stays 9.81), and a probe disk of radius 0.1 resting `probe` above the floor (before
/// scaling).
fn springs_in_units(
    contact_set: &str,
    k_t: f64,
    s: f64,
    m: f64,
    probe: f64,
) -> Result<moreau_models::AnyModel> {
    let (l, time) = (|x: f64| x * s, |x: f64| x * s.sqrt());
    // A dynamic disk of radius 0.1 (mass, inertia about its centre, position, angle).
    let disk = |name: &str, mass: f64, inertia: f64, x: f64, y: f64, angle: f64| {
        format!(
            "[[bodies]]\nname = \"{name}\"\ntype = \"dynamic\"\nmass = {:e}\ninertia = {:e}\n\
             position = [{:e}, {:e}]\nangle = {angle}\n\
             shapes = [{{ type = \"disk\", center = [0.0, 0.0], radius = {:e} }}]\n",
            mass * m,
            inertia * m * s * s,
            l(x),
            l(y),
            l(0.1),
        )
    };
    let diagonal = 1.5 * std::f64::consts::FRAC_1_SQRT_2;
    let text = format!(
        r#"
dt = {dt:e}
t_end = {t_end:e}
gravity = [0.0, -9.81]
contact_set = "{contact_set}"

[[bodies]]
name = "floor"
type = "fixed"
position = [0.0, 0.0]
shapes = [{{ type = "half_plane", point = [0.0, 0.0], normal = [0.0, 1.0] }}]

{a}
{wheel}
{probe}
[[fill]]
name = "grain"
pattern = "lattice"
count = 6
columns = 4
origin = [{five:e}, {half:e}]
spacing = [{spacing:e}, {spacing:e}]
shape = {{ type = "disk", center = [0.0, 0.0], radius = {r:e} }}
density = {density:e}
seed = 1

{b}
[[forces]]
type = "spring"
body_a = "a"
anchor_a = [0.0, 0.0]
body_b = "b"
anchor_b = [0.0, 0.0]
stiffness = {k:e}
rest_length = {rest:e}

[[forces]]
type = "torsion"
body_a = "ground"
body_b = "wheel"
stiffness = {k_t:e}
rest_angle = 0.0

[contacts_auto]
eps_n = 0.0
eps_t = 0.0
mu = 0.3
"#,
        dt = time(0.001),
        t_end = time(0.01),
        a = disk("a", 2.0, 0.1, 0.0, 1.0, 0.0),
        wheel = disk("wheel", 1.0, 0.05, 3.0, 1.0, 0.2),
        probe = disk("probe", 1.0, 0.05, 4.0, 0.1 + probe, 0.0),
        b = disk("b", 3.0, 0.2, diagonal, 1.0 + diagonal, 0.0),
        five = l(5.0),
        half = l(0.5),
        r = l(0.1),
        spacing = l(0.3),
        rest = l(1.5),
        density = 100.0 * m / (s * s),
        k = 400.0 * m / s,
        k_t = k_t * m * s,
    );
    Ok(moreau_models::Scene::from_toml_str(&text)?.build()?)
}

#[test]
fn a_declared_mechanism_is_guarded_alike_in_any_units() -> Result<()> {
    // Lengths times s, masses times m, times times √s: ω scales as 1/√s, energies as m s,
    // lengths as s, velocities as √s, and the gaps that count as touching as s. With the
    // guards' constants in metres, seconds and joules, the mechanism of micrometres and
    // milligrams had an energy bound of 1e-6 J (a floor a hundred thousand times its m |g| ℓ),
    // velocity bounds of 1e8 m/s, and a probe disk 1e-7 of a micrometre above the floor
    // counted as touching.
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs();
    let reference = springs_in_units("detected", 5.0, 1.0, 1.0, 1e-6)?;
    let omega = guard::omega_max(&reference);
    let bounds = guard::Bounds::of(&reference, 1e-3, 0.0);
    let (e0, e_max) = bounds.energy.context("no drives: the energy bound applies")?;
    for (s, m) in [(1e-6, 1e-6), (1e-3, 1.0), (1e3, 1e6), (1.0, 1e-6)] {
        let model = springs_in_units("detected", 5.0, s, m, 1e-6)?;
        let w = guard::omega_max(&model);
        ensure!((w * s.sqrt() - omega).abs() <= 1e-6 * omega, "{s} {m}: ω_max {w} vs {omega}");
        let b = guard::Bounds::of(&model, 1e-3 * s.sqrt(), 0.0);
        let (e, e_bound) = b.energy.context("energy bound")?;
        ensure!(close(e_bound - e, (e_max - e0) * m * s), "{s} {m}: {e_bound} − {e}");
        for (j, (x, x0)) in b.q.iter().zip(&bounds.q).enumerate() {
            let unit = if j % 3 == 2 { 1.0 } else { s };
            ensure!(close(*x, x0 * unit), "{s} {m}: q bound {j}: {x} vs {x0}");
        }
        for (j, (v, v0)) in b.u.iter().zip(&bounds.u).enumerate() {
            let unit = if j % 3 == 2 { 1.0 / s.sqrt() } else { s.sqrt() };
            ensure!(close(*v, v0 * unit), "{s} {m}: u bound {j}: {v} vs {v0}");
        }
        // The gaps of the contacts that a fixed contact set lists at the start.
        let w = guard::gap_warnings(&springs_in_units("fixed", 5.0, s, m, 1e-6)?, 0.0, true);
        ensure!(w.is_empty(), "{s} {m}: {w:?}");
        let touching = springs_in_units("fixed", 5.0, s, m, 1e-12)?;
        let w = guard::gap_warnings(&touching, 0.0, true);
        // A declared contact is named as its columns are (`floor.0-probe.0.PN`).
        let name = w.first().and_then(|w| w.split_once(" starts touching")).map(|p| p.0);
        ensure!(w.len() == 1 && name == Some("contact `floor.0-probe.0`"), "{w:?}");
        // The same with a detected contact set: the contacts that detection finds at the start,
        // counted and named by their bodies.
        let w = guard::gap_warnings(&springs_in_units("detected", 5.0, s, m, 1e-6)?, 0.0, true);
        ensure!(w.is_empty(), "{s} {m}: {w:?}");
        let w = guard::gap_warnings(&springs_in_units("detected", 5.0, s, m, 1e-12)?, 0.0, true);
        let named = w.len() == 1 && w[0].starts_with("1 detected contact starts touching");
        ensure!(named && w[0].contains("`probe`"), "{s} {m}: {w:?}");
        let w = guard::gap_warnings(&springs_in_units("detected", 5.0, s, m, -1e-3)?, 0.0, true);
        let named = w.len() == 1 && w[0].starts_with("1 detected contact starts penetrating");
        ensure!(named && w[0].contains("`probe`"), "{s} {m}: {w:?}");
        let g = format!("g_N = {:.6e}", -1e-3 * s);
        ensure!(w[0].contains(&g), "{s} {m}: {w:?} without {g}");
    }
    Ok(())
}

#[test]
fn the_stability_limit_by_body_equals_the_dense_one() -> Result<()> {
    use moreau_stepper::Mechanism;
    // The spring's axial mode, ω² = k (1/m_a + 1/m_b), above the torsion's k_t/I = 100; then a
    // stiffer torsion spring, k_t/I = 1e4, as the stiffest mode.
    for (k_t, closed) in [(5.0, (400.0f64 * (1.0 / 2.0 + 1.0 / 3.0)).sqrt()), (500.0, 100.0)] {
        let dense = springs_and_free_disks("fixed", k_t)?;
        let by_body = springs_and_free_disks("detected", k_t)?;
        ensure!(dense.body_structure().is_none() && by_body.body_structure().is_some());
        let (w_dense, w_body) = (guard::omega_max(&dense), guard::omega_max(&by_body));
        ensure!((w_dense - closed).abs() <= 1e-6 * closed, "dense {w_dense}, closed {closed}");
        ensure!((w_body - w_dense).abs() <= 1e-9 * w_dense, "by body {w_body}, dense {w_dense}");
    }
    Ok(())
}

#[test]
fn a_pile_under_gravity_alone_has_no_stiffness() -> Result<()> {
    use moreau_stepper::Mechanism;
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/scale");
    for (file, set) in [("pyramid.toml", "fill.box.base=12"), ("disk-column.toml", "t_end=1")] {
        let o = SimulateOptions {
            scene: Some(path.join(file)),
            sets: vec![set.to_owned()],
            ..SimulateOptions::default()
        };
        let model = scene(&o)?.build()?;
        ensure!(model.body_structure().is_some(), "{file}");
        let w = guard::omega_max(&model);
        ensure!(w == 0.0, "{file}: ω_max = {w}");
    }
    Ok(())
}

#[test]
fn a_body_carried_through_a_thin_wall_stops_the_run() -> Result<()> {
    // A disk of radius 0.1 m flies at a plate 10 mm thick, with Δt = 1 ms.
    let dir = tempfile::tempdir()?;
    let file = dir.path().join("plate.toml");
    std::fs::write(
        &file,
        r#"dt = 0.001
t_end = 0.1
gravity = [0.0, 0.0]

[[bodies]]
name = "plate"
type = "fixed"
position = [0.0, 0.0]
shapes = [{ type = "polygon", vertices = [[-0.005, -0.5], [0.005, -0.5], [0.005, 0.5], [-0.005, 0.5]] }]

[[bodies]]
name = "ball"
type = "dynamic"
mass = 1.0
inertia = 0.005
position = [-0.5, 0.0]
velocity = [100.0, 0.0]
shapes = [{ type = "disk", center = [0.0, 0.0], radius = 0.1 }]

[[contacts]]
name = "hit"
body_a = "plate"
body_b = "ball"
eps_n = 1.0
eps_t = 0.0
mu = 0.0
"#,
    )?;
    let at = |v: f64, contact_set: &str| SimulateOptions {
        scene: Some(file.clone()),
        sets: vec![format!("bodies.ball.velocity=[{v},0]"), format!("contact_set={contact_set}")],
        ..SimulateOptions::default()
    };
    for contact_set in ["fixed", "detected"] {
        // Up to 300 m/s (0.3 m a step, 1.5 diameters) it bounces back, elastically.
        for v in [10.0, 100.0, 300.0] {
            let r = run(&at(v, contact_set))?;
            let vx = r.record().u.column(0).last().context("rows")?;
            ensure!((vx + v).abs() <= 1e-9 * v, "{contact_set}, {v} m/s: back at {vx}");
        }
        // At 400 m/s the second step's midpoint lies past the plate's middle, where the gap
        // is measured to its far face; at 1,000 m/s the first step jumps over it. Neither sinks
        // a contact deep.
        for (v, step) in [(400.0, 1), (1000.0, 0)] {
            let e = run(&at(v, contact_set)).expect_err("through the plate");
            match cli_error(&e) {
                Some(CliError::Diverged {
                    cause: Divergence::Crossed { body, other, moved, thickness, gap },
                    step: s,
                    ..
                }) => ensure!(
                    (body.as_str(), other.as_str(), *s) == ("ball", "plate", step)
                        && (moved - v * 1e-3).abs() < 1e-9
                        && *thickness == 0.2
                        && *gap < -0.05,
                    "{e:#}"
                ),
                _ => anyhow::bail!("{contact_set}, {v} m/s: {e:#}"),
            }
        }
    }
    Ok(())
}
