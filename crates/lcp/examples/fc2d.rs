//! Solves a Siconos FC2D or GFC2D file and prints one JSON object.
//!
//! ```text
//! cargo run --release -p moreau-lcp --example fc2d -- [--solver auto|nsgs|lcp|newton|proximal] [--tol T] [--repeat N] FILE
//! ```
//!
//! Keys: `solver`, `status` ("solved" when, and only when, the natural-map residual is
//! within the tolerance), `method` (the method that produced r), `contacts`, `blocks` (the
//! stored 2x2 blocks of W), `iterations`, `residual` (`natural` and `siconos`),
//! `seconds_per_solve` (with `--repeat`), `r`. The file is told by its content: one that
//! reads as a GFC2D problem and not as an FC2D one is reduced to the contact space first,
//! and the global velocity `v` is printed too.

use std::process::ExitCode;
use std::time::Instant;

use moreau_lcp::LcpError;
use moreau_lcp::fc2d::{
    Fc2d, Fc2dAuto, Fc2dAutoOptions, Fc2dSolution, Fc2dSolver, Gfc2d, LcpRoute, LcpRouteOptions,
    Newton, NewtonOptions, Nsgs, NsgsOptions, Proximal, ProximalOptions,
};

struct Args {
    solver: String,
    tolerance: f64,
    repeat: usize,
    file: String,
}

fn parse_args() -> Result<Args, String> {
    let mut args = Args { solver: "auto".into(), tolerance: 1e-8, repeat: 0, file: String::new() };
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        let mut value = |name: &str| it.next().ok_or(format!("{name} needs a value"));
        match a.as_str() {
            "--solver" => args.solver = value("--solver")?,
            "--tol" => {
                let v = value("--tol")?;
                args.tolerance = v.parse().map_err(|_| format!("--tol: '{v}' is not a number"))?;
            }
            "--repeat" => {
                let v = value("--repeat")?;
                args.repeat = v.parse().map_err(|_| format!("--repeat: '{v}' is not a count"))?;
            }
            _ if a.starts_with("--") => return Err(format!("unknown option {a}")),
            _ => args.file = a,
        }
    }
    if args.file.is_empty() {
        return Err(
            "usage: fc2d [--solver auto|nsgs|lcp|newton|proximal] [--tol T] [--repeat N] FILE"
                .into(),
        );
    }
    Ok(args)
}

/// The chosen solver, made once so that repeated solves reuse its workspace; returns its
/// name as reported.
fn make_solver(
    solver: &str,
    tolerance: f64,
) -> Result<(Box<dyn Fc2dSolver>, &'static str), String> {
    let err = |e: LcpError| e.to_string();
    Ok(match solver {
        "nsgs" => {
            let options = NsgsOptions::default().with_tolerance(tolerance).with_max_sweeps(100_000);
            (Box::new(Nsgs::new(options).map_err(err)?), "nsgs")
        }
        "lcp" => {
            let options =
                LcpRouteOptions::default().with_tolerance(tolerance).with_max_contacts(usize::MAX);
            (Box::new(LcpRoute::new(options).map_err(err)?), "lcp")
        }
        "auto" => {
            let options = Fc2dAutoOptions::default().with_tolerance(tolerance);
            (Box::new(Fc2dAuto::new(options).map_err(err)?), "auto")
        }
        "newton" => {
            let options = NewtonOptions::default().with_tolerance(tolerance);
            (Box::new(Newton::new(options).map_err(err)?), "newton")
        }
        "proximal" => {
            let options = ProximalOptions::default().with_tolerance(tolerance);
            (Box::new(Proximal::new(options).map_err(err)?), "proximal")
        }
        other => {
            return Err(format!("unknown solver '{other}' (auto, nsgs, lcp, newton, proximal)"));
        }
    })
}

fn run() -> Result<(), String> {
    let args = parse_args()?;
    let text = std::fs::read_to_string(&args.file).map_err(|e| format!("{}: {e}", args.file))?;
    // The two formats share their header (dimension, n_c); what follows tells them apart:
    // a GFC2D file read as FC2D leaves its H, q, b and μ after the reduced problem's data.
    let (problem, global) = match Fc2d::read_siconos(text.as_bytes()) {
        Ok(problem) => (problem, None),
        Err(as_fc2d) => {
            let global = Gfc2d::read_siconos(text.as_bytes()).map_err(|as_gfc2d| {
                format!("{}: neither FC2D ({as_fc2d}) nor GFC2D ({as_gfc2d})", args.file)
            })?;
            let reduced = global.reduce().map_err(|e| e.to_string())?;
            (reduced.problem.clone(), Some((global, reduced)))
        }
    };
    let mut out = Fc2dSolution::new();
    let (mut solver, name) = make_solver(&args.solver, args.tolerance)?;
    solver.solve_into(problem.view(), None, &mut out).map_err(|e| e.to_string())?;
    let mut json = serde_json::json!({
        "solver": name,
        "status": out.status.to_string(),
        "method": out.method.to_string(),
        "contacts": problem.n_contacts(),
        "blocks": problem.n_blocks(),
        "iterations": out.iterations,
        "residual": { "natural": out.residual.natural, "siconos": out.residual.siconos },
        "r": out.r,
    });
    if let Some((global, reduced)) = &global {
        json["v"] = serde_json::json!(reduced.global_velocity(global, &out.r));
    }
    if args.repeat > 0 {
        let start = Instant::now();
        let mut again = Fc2dSolution::new();
        for _ in 0..args.repeat {
            solver.solve_into(problem.view(), None, &mut again).map_err(|e| e.to_string())?;
        }
        json["seconds_per_solve"] =
            serde_json::json!(start.elapsed().as_secs_f64() / args.repeat as f64);
    }
    println!("{json}");
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("fc2d: {e}");
            ExitCode::FAILURE
        }
    }
}
