//! `simulate --contacts`: the located contacts of the recorded steps, against the record's own
//! impulses (the pendulum striking a wall, fixed contact set) and against the closed-form
//! forces of a resting stack (detected contact set), and the refusals.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use moreau_cli::CliError;
use moreau_cli::contacts::HEADER;
use moreau_cli::simulate::{SimulateOptions, run_to_csv};

fn pendulum() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/bodies/pendulum-wall.toml")
}

fn cli_error(e: &anyhow::Error) -> Option<&CliError> {
    e.chain().find_map(|c| c.downcast_ref::<CliError>())
}

/// The rows of a CSV file as maps from column to cell.
fn rows(path: &Path) -> Result<(Vec<String>, Vec<Vec<String>>)> {
    let mut r = csv::Reader::from_path(path)?;
    let header = r.headers()?.iter().map(str::to_owned).collect();
    let rows = r
        .records()
        .map(|row| Ok(row?.iter().map(str::to_owned).collect()))
        .collect::<Result<_>>()?;
    Ok((header, rows))
}

fn cell(header: &[String], row: &[String], name: &str) -> Result<f64> {
    let i = header.iter().position(|h| h == name).with_context(|| format!("no column {name}"))?;
    Ok(row[i].parse()?)
}

fn text<'a>(header: &[String], row: &'a [String], name: &str) -> Result<&'a str> {
    let i = header.iter().position(|h| h == name).with_context(|| format!("no column {name}"))?;
    Ok(&row[i])
}

#[test]
fn the_pendulums_impacts_are_located_on_the_wall_with_the_records_impulses() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let (out, contacts) = (dir.path().join("p.csv"), dir.path().join("c.csv"));
    let options = SimulateOptions {
        scene: Some(pendulum()),
        sets: vec!["record_every=1".into()],
        contacts: Some(contacts.clone()),
        ..Default::default()
    };
    let done = run_to_csv(&options, &out, &mut |_| {})?;
    let (h, record) = rows(&out)?;
    let (hc, located) = rows(&contacts)?;
    assert_eq!(hc.join(","), HEADER);
    assert_eq!(done.contact_rows, Some(located.len() as u64));
    // Every step in which the contact was active is in the file, once, with its impulse.
    let active: Vec<&Vec<String>> =
        record.iter().filter(|r| cell(&h, r, "hit.active").is_ok_and(|a| a == 1.0)).collect();
    assert!(active.len() >= 3, "{} impacts", active.len());
    assert_eq!(active.len(), located.len());
    for (r, c) in active.iter().zip(&located) {
        assert_eq!(cell(&hc, c, "t")?, cell(&h, r, "t")?);
        assert_eq!(cell(&hc, c, "PN")?, cell(&h, r, "hit.PN")?);
        assert_eq!(cell(&hc, c, "PT")?, cell(&h, r, "hit.PT")?);
        assert_eq!(
            (text(&hc, c, "id")?, text(&hc, c, "body_a")?, text(&hc, c, "body_b")?),
            ("0", "wall", "bob")
        );
        // The wall's face x = 0.05 m, its normal towards the bob, the bob's surface point
        // inside the wall by the gap, and an impact's rebound γ_N,E = ε_N (−γ_N,A) > 0.
        assert_eq!(
            [cell(&hc, c, "xa")?, cell(&hc, c, "nx")?, cell(&hc, c, "ny")?],
            [0.05, -1.0, 0.0]
        );
        let gap = cell(&hc, c, "gap")?;
        assert!(gap <= 0.0);
        assert!((cell(&hc, c, "xb")? - (0.05 - gap)).abs() < 1e-15);
        assert_eq!(cell(&hc, c, "ya")?, cell(&hc, c, "yb")?);
        assert!(cell(&hc, c, "PN")? > 0.0 && cell(&hc, c, "gamma_n")? > 0.0);
        assert_eq!(text(&hc, c, "impact")?, "1");
    }
    Ok(())
}

#[test]
fn a_resting_stack_carries_the_weight_above_each_contact() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/bodies/stack.toml");
    let (out, contacts) = (dir.path().join("s.csv"), dir.path().join("c.csv"));
    let options = SimulateOptions {
        scene: Some(scene),
        contacts: Some(contacts.clone()),
        ..Default::default()
    };
    run_to_csv(&options, &out, &mut |_| {})?;
    let (h, located) = rows(&contacts)?;
    let last: Vec<&Vec<String>> =
        located.iter().filter(|r| cell(&h, r, "t").is_ok_and(|t| t == 1.0)).collect();
    // P_N over one step of Δt = 1 ms: the weight of the disks above the contact.
    let (g, dt) = (9.81, 0.001);
    let expected = [("floor", "d0", 6.0), ("d0", "d1", 5.0), ("d1", "d2", 3.0)];
    assert_eq!(last.len(), expected.len());
    for (c, (a, b, mass)) in last.iter().zip(expected) {
        assert_eq!((text(&h, c, "body_a")?, text(&h, c, "body_b")?), (a, b));
        let p_n = cell(&h, c, "PN")?;
        assert!((p_n - mass * g * dt).abs() <= 1e-8 * mass * g * dt, "{a}-{b}: P_N = {p_n}");
        assert!(cell(&h, c, "PT")?.abs() <= 1e-12, "{a}-{b}");
        // Round-off moves the disks sideways by 1e-17 m, no more.
        assert!(cell(&h, c, "nx")?.abs() < 1e-12 && (cell(&h, c, "ny")? - 1.0).abs() < 1e-12);
        assert_eq!(text(&h, c, "state")?, "stick");
        // The points: on the axis x = 0, a's top and b's bottom, the gap apart.
        let (ya, yb, gap) = (cell(&h, c, "ya")?, cell(&h, c, "yb")?, cell(&h, c, "gap")?);
        assert!(cell(&h, c, "xa")?.abs() < 1e-12 && cell(&h, c, "xb")?.abs() < 1e-12);
        assert!(gap <= 0.0 && gap > -1e-3 && (yb - ya - gap).abs() < 1e-12, "{a}-{b}");
    }
    // The contacts touch at the floor and between the disks, about 0, 0.2 and 0.4 m up.
    for (c, y) in last.iter().zip([0.0, 0.2, 0.4]) {
        assert!((cell(&h, c, "ya")? - y).abs() < 2e-3);
    }
    Ok(())
}

#[test]
fn a_contacts_file_is_refused_for_a_report_model_and_as_the_output_itself() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let out = dir.path().join("r.csv");
    let report = SimulateOptions {
        model: Some("ball".into()),
        contacts: Some(dir.path().join("c.csv")),
        ..Default::default()
    };
    let e = run_to_csv(&report, &out, &mut |_| {}).unwrap_err();
    assert!(
        matches!(cli_error(&e), Some(CliError::ContactsOfReportModel { model }) if model == "ball"),
        "{e:#}"
    );
    let same = SimulateOptions {
        scene: Some(pendulum()),
        contacts: Some(out.clone()),
        ..Default::default()
    };
    let e = run_to_csv(&same, &out, &mut |_| {}).unwrap_err();
    assert!(matches!(cli_error(&e), Some(CliError::Output { path, .. }) if *path == out), "{e:#}");
    // Neither run wrote anything.
    assert_eq!(std::fs::read_dir(dir.path())?.count(), 0);
    Ok(())
}

#[test]
fn a_failed_run_leaves_its_contacts_partial() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let (out, contacts) = (dir.path().join("p.csv"), dir.path().join("c.csv"));
    // A step above the stability limit of a stiff spring stops the run before its first step.
    let scene = dir.path().join("spring.toml");
    let text = std::fs::read_to_string(pendulum())?;
    std::fs::write(
        &scene,
        format!(
            "{text}\n[[forces]]\ntype = \"spring\"\nbody_a = \"ground\"\nanchor_a = [0.0, 0.0]\n\
             body_b = \"bob\"\nanchor_b = [0.0, 0.0]\nstiffness = 1e12\nrest_length = 1.0\n"
        ),
    )?;
    let options = SimulateOptions {
        scene: Some(scene),
        contacts: Some(contacts.clone()),
        ..Default::default()
    };
    let e = run_to_csv(&options, &out, &mut |_| {}).unwrap_err();
    assert!(matches!(cli_error(&e), Some(CliError::Diverged { .. })), "{e:#}");
    assert!(!contacts.exists() && !out.exists());
    let partial = dir.path().join("c.csv.partial");
    assert_eq!(std::fs::read_to_string(partial)?.trim_end(), HEADER);
    Ok(())
}

#[test]
fn a_run_its_stop_rule_ends_writes_the_contacts_of_its_last_step() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let stack = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/bodies/stack.toml");
    // A stop rule never met: the run ends at t_end = 0.5 s, 500 steps, which 7 does not divide.
    type Rows = Vec<Vec<String>>;
    let run = |every: &str, name: &str| -> Result<(Rows, Rows)> {
        let (out, contacts) = (dir.path().join(name), dir.path().join(format!("c-{name}")));
        let options = SimulateOptions {
            scene: Some(stack.clone()),
            sets: vec![
                "t_end=0.5".into(),
                r#"stop_at={coordinate="d2.y", value=-10.0}"#.into(),
                every.into(),
            ],
            contacts: Some(contacts.clone()),
            ..Default::default()
        };
        run_to_csv(&options, &out, &mut |_| {})?;
        Ok((rows(&out)?.1, rows(&contacts)?.1))
    };
    let (record, located) = run("record_every=7", "thinned.csv")?;
    let (_, all) = run("record_every=1", "all.csv")?;
    let last_t = |rows: &[Vec<String>]| rows.last().map(|r| r[0].clone());
    assert_eq!(last_t(&record).as_deref(), Some("0.5"));
    assert_eq!(last_t(&located), last_t(&record));
    // The last step's contacts are those of the full record's last step.
    let at_end = |rows: &[Vec<String>]| -> Vec<Vec<String>> {
        rows.iter().filter(|r| r[0] == "0.5").cloned().collect()
    };
    assert_eq!(at_end(&located).len(), 3);
    assert_eq!(at_end(&located), at_end(&all));
    Ok(())
}
