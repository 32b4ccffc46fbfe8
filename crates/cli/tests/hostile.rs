//! A seeded batch of hostile inputs through the built `moreau` binary: no input may panic,
//! and none may exit successfully with a meaningless result (a non-finite number, a last row
//! not at t_end, a row whose labels are not the values it ran, a merge of parts that do not
//! belong together).

use std::path::Path;
use std::process::{Command, Output};

/// A small linear congruential generator: the batch is the same on every run.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 =
            self.0.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        self.0 >> 33
    }

    fn pick<'a>(&mut self, items: &[&'a str]) -> &'a str {
        items[self.next() as usize % items.len()]
    }

    fn chance(&mut self, percent: u64) -> bool {
        self.next() % 100 < percent
    }
}

fn moreau(args: &[String]) -> Output {
    let out = Command::new(env!("CARGO_BIN_EXE_moreau")).args(args).output();
    out.unwrap_or_else(|e| panic!("cannot start moreau: {e}"))
}

/// Checks the outcome of one invocation: no panic, and exit 0, 1 (refused or failed) or 2
/// (a malformed command line).
fn outcome(args: &[String], out: &Output) -> bool {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{args:?} panicked: {stderr}");
    let code = out.status.code();
    assert!(matches!(code, Some(0..=2)), "{args:?} exited with {code:?}: {stderr}");
    if code != Some(0) {
        assert!(stderr.contains("error:"), "{args:?} failed without a message: {stderr}");
    }
    code == Some(0)
}

const MODELS: [&str; 5] = ["ball", "woodpecker", "cam", "painleve", "slider-crank-ideal"];
const DT: [&str; 12] =
    ["1e-3", "1e-4", "1e-2", "3e-3", "1e6", "1e300", "1e-300", "0", "-1e-3", "NaN", "inf", "2e-3"];
const TF: [&str; 9] = ["0.05", "0.1", "0.0123", "1e300", "0", "-1", "0.02", "NaN", "0.2"];
const SETS: [&str; 23] = [
    "j2=1e30",
    "eps_n=1.5",
    "eps_n=0.5",
    "eps_n=0.2",
    "init.y0=-1",
    "y0=0.1",
    "y0=0.10000000000000003",
    "mu=0.3",
    "mu=-1",
    "solver=pgs",
    "solver=lemke",
    "solver=enum",
    "solver=newton",
    "solver.tolerance=1",
    "g=0",
    "g=-9.81",
    "g=1e300",
    "m=0",
    "m=1e-300",
    "record_every=2",
    "record_every=0",
    "no_such_key=1",
    "dt=1e-3",
];

/// The model's scene has a stop rule, which may end it before t_end.
fn has_stop_rule(model: &str) -> bool {
    matches!(model, "painleve" | "slider-crank" | "slider-crank-ideal")
}

fn check_record(args: &[String], path: &Path, model: &str, t_end: Option<f64>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{args:?}: {e}"));
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    assert_eq!(header[0], "t", "{args:?}");
    let mut last_t = f64::NAN;
    let mut rows = 0;
    for line in lines {
        let cells: Vec<&str> = line.split(',').collect();
        assert_eq!(cells.len(), header.len(), "{args:?}: {line}");
        for c in &cells {
            let x: f64 = c.parse().unwrap_or(f64::NAN);
            assert!(x.is_finite(), "{args:?}: non-finite cell in {line}");
        }
        last_t = cells[0].parse().unwrap_or(f64::NAN);
        rows += 1;
    }
    assert!(rows >= 2, "{args:?}: {rows} rows");
    if let Some(t_end) = t_end {
        if has_stop_rule(model) {
            assert!(last_t <= t_end, "{args:?}: last row at {last_t} > t_end {t_end}");
        } else {
            assert_eq!(last_t, t_end, "{args:?}: last row not at t_end");
        }
    }
}

#[test]
fn hostile_simulate_inputs() {
    let dir = tempfile::tempdir().unwrap_or_else(|e| panic!("{e}"));
    let mut rng = Lcg(0x5eed_0001);
    let (mut succeeded, mut refused) = (0, 0);
    for n in 0..120 {
        let model = rng.pick(&MODELS);
        let out = dir.path().join(format!("s{n}.csv"));
        let mut args = vec!["simulate".to_owned(), model.to_owned()];
        let dt = rng.chance(70).then(|| rng.pick(&DT));
        let tf = rng.pick(&TF);
        if let Some(dt) = dt {
            args.push(format!("--dt={dt}"));
        }
        args.push(format!("--tf={tf}"));
        for _ in 0..rng.next() % 3 {
            args.extend(["--set".to_owned(), rng.pick(&SETS).to_owned()]);
        }
        args.extend(["--max-steps".into(), "5000".into(), "--out".into()]);
        args.push(out.display().to_string());
        let result = moreau(&args);
        if outcome(&args, &result) {
            succeeded += 1;
            check_record(&args, &out, model, tf.parse().ok());
        } else {
            refused += 1;
            assert!(!out.exists(), "{args:?}: failed but wrote {}", out.display());
        }
    }
    println!("simulate: {succeeded} ran, {refused} refused");
    // The batch exercises both sides.
    assert!(succeeded >= 5 && refused >= 20, "{succeeded} ran, {refused} refused");
}

/// The swept values of member i, by mixed radix with the first axis outermost.
fn member_values(axes: &[Vec<&str>], mut i: usize) -> Vec<String> {
    let mut out = Vec::new();
    for values in axes.iter().rev() {
        out.push(values[i % values.len()].to_owned());
        i /= values.len();
    }
    out.reverse();
    out
}

#[test]
fn hostile_sweeps_and_merges() {
    let dir = tempfile::tempdir().unwrap_or_else(|e| panic!("{e}"));
    let mut rng = Lcg(0x5eed_0002);
    let keys = ["eps_n", "init.y0", "y0", "dt", "t_end", "g", "solver"];
    let values: [&[&str]; 7] = [
        &["0.1", "0.5", "0.9", "1.5"],
        &["1", "-1", "0.1"],
        &["0.5", "2"],
        &["1e-3", "2e-3", "3e-3", "1e300"],
        &["0.05", "0.1", "1e300"],
        &["9.81", "0", "-1"],
        &["auto", "lemke", "pgs", "newton"],
    ];
    let mut ok_sweeps = 0;
    for n in 0..30 {
        let out = dir.path().join(format!("w{n}.csv"));
        let mut args = vec!["sweep".to_owned(), "ball".to_owned()];
        let mut axes: Vec<(String, Vec<&str>)> = Vec::new();
        for _ in 0..1 + rng.next() % 3 {
            let k = rng.next() as usize % keys.len();
            let count = 1 + rng.next() as usize % 2;
            let vals: Vec<&str> = (0..count).map(|_| rng.pick(values[k])).collect();
            args.extend(["--set".to_owned(), format!("{}={}", keys[k], vals.join(","))]);
            axes.push((keys[k].to_owned(), vals));
        }
        // Short runs unless an axis says otherwise.
        if !axes.iter().any(|(k, _)| k == "t_end") {
            args.extend(["--set".to_owned(), "t_end=0.05".to_owned()]);
            axes.push(("t_end".to_owned(), vec!["0.05"]));
        }
        args.extend(["--max-steps".into(), "5000".into(), "--out".into()]);
        args.push(out.display().to_string());
        let result = moreau(&args);
        if !outcome(&args, &result) {
            continue;
        }
        ok_sweeps += 1;
        let text = std::fs::read_to_string(&out).unwrap_or_else(|e| panic!("{e}"));
        let mut lines = text.lines();
        assert!(lines.next().is_some_and(|l| l.starts_with("# moreau sweep")), "{args:?}");
        let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
        let status = header.iter().position(|c| *c == "status").unwrap_or(0);
        let vals: Vec<Vec<&str>> = axes.iter().map(|(_, v)| v.clone()).collect();
        let members: usize = vals.iter().map(Vec::len).product();
        let mut rows = 0;
        for (i, line) in lines.enumerate() {
            let cells: Vec<&str> = line.split(',').collect();
            rows += 1;
            assert_eq!(cells[0], i.to_string(), "{args:?}");
            // The labels are the values the member ran.
            assert_eq!(cells[2..2 + axes.len()], member_values(&vals, i), "{args:?}: {line}");
            if cells[status] == "ok" {
                for c in &cells[2 + axes.len()..status] {
                    let x: f64 = if c.is_empty() { 0.0 } else { c.parse().unwrap_or(f64::NAN) };
                    assert!(x.is_finite(), "{args:?}: {line}");
                }
                // The member ran the values on its row: t_end / dt steps, the last key given.
                let value = |key: &str, default: f64| {
                    let ran = member_values(&vals, i);
                    let found = axes.iter().zip(&ran).rfind(|((k, _), _)| k == key);
                    found.map_or(default, |(_, v)| v.parse().unwrap_or(f64::NAN))
                };
                let steps_at = header.iter().position(|c| *c == "steps").expect("a steps column");
                let steps: f64 = cells[steps_at].parse().unwrap_or(f64::NAN);
                let expected = (value("t_end", 10.0) / value("dt", 1e-3)).round();
                assert_eq!(steps, expected, "{args:?}: {line}");
            } else {
                assert!(["diverged", "failed"].contains(&cells[status]), "{args:?}: {line}");
            }
        }
        assert_eq!(rows, members, "{args:?}");
    }
    println!("sweeps: {ok_sweeps} of 30 ran");
    assert!(ok_sweeps >= 2, "{ok_sweeps} sweeps ran");

    // Merges: parts of two sweeps that differ in one value, shards of each, random subsets.
    let part = |eps: &str, k: usize, n: usize| -> String {
        let p = dir.path().join(format!("p{eps}_{k}_{n}.csv"));
        let args: Vec<String> = [
            "sweep",
            "ball",
            "--set",
            &format!("eps_n=0.3,{eps}"),
            "--set",
            "t_end=0.05,0.1",
            "--shard",
            &format!("{k}/{n}"),
            "--out",
            &p.display().to_string(),
        ]
        .map(str::to_owned)
        .to_vec();
        assert!(outcome(&args, &moreau(&args)), "{args:?}");
        p.display().to_string()
    };
    let a: Vec<String> = (1..=3).map(|k| part("0.5", k, 3)).collect();
    let b: Vec<String> = (1..=3).map(|k| part("0.55", k, 3)).collect();
    let mut merges = [0; 2];
    for n in 0..20 {
        // Per shard: left out, the part of sweep a, or the part of sweep b.
        let picks: Vec<u64> = (0..3).map(|_| rng.next() % 3).collect();
        let chosen: Vec<String> = picks
            .iter()
            .enumerate()
            .filter_map(|(k, &p)| match p {
                1 => Some(a[k].clone()),
                2 => Some(b[k].clone()),
                _ => None,
            })
            .collect();
        if chosen.is_empty() {
            continue;
        }
        let out = dir.path().join(format!("m{n}.csv"));
        let mut args = vec!["merge".to_owned(), "--out".to_owned(), out.display().to_string()];
        args.extend(chosen);
        let good = picks.iter().all(|&p| p == 1) || picks.iter().all(|&p| p == 2);
        assert_eq!(outcome(&args, &moreau(&args)), good, "{args:?}");
        merges[usize::from(good)] += 1;
    }
    println!("merges: {} joined, {} refused", merges[1], merges[0]);
    assert!(merges[0] >= 5, "{merges:?}");
}
