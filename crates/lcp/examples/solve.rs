//! Solves an LCP file (plain or Siconos format, detected) and prints one JSON object.
//!
//! ```text
//! cargo run --release -p moreau-lcp --example solve -- [--solver auto|lemke|pgs|enum] [--repeat N] FILE
//! ```
//!
//! Keys: `solver`, `status` ("solved" exactly when z satisfies the conditions), `method`,
//! `z`, `w`, `residual`, `iterations`; with `--repeat N` also `seconds_per_solve` (mean
//! wall time of one solve over N solves after a warm-up solve); with `--solver enum` also
//! `solutions` (every solution found). Bad input: a message on stderr and exit code 2.

use std::process::ExitCode;
use std::time::Instant;

use moreau_lcp::{Auto, Enumeration, Lcp, Lemke, Pgs, Solution, Solver};

struct Args {
    solver: String,
    repeat: Option<usize>,
    file: String,
}

const USAGE: &str = "usage: solve [--solver auto|lemke|pgs|enum] [--repeat N] FILE";

fn parse_args() -> Result<Args, String> {
    let mut solver = "auto".to_string();
    let mut repeat = None;
    let mut file = None;
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--solver" => {
                let v = args.next().ok_or("--solver needs a value")?;
                if !["auto", "lemke", "pgs", "enum"].contains(&v.as_str()) {
                    return Err(format!(
                        "unknown solver '{v}' (expected auto, lemke, pgs or enum)"
                    ));
                }
                solver = v;
            }
            "--repeat" => {
                let v = args.next().ok_or("--repeat needs a value")?;
                let n: usize = v
                    .parse()
                    .map_err(|_| format!("--repeat expects a positive integer, got '{v}'"))?;
                if n == 0 {
                    return Err("--repeat must be at least 1".to_string());
                }
                repeat = Some(n);
            }
            "-h" | "--help" => return Err(USAGE.to_string()),
            s if s.starts_with("--") => return Err(format!("unknown option '{s}'\n{USAGE}")),
            s => {
                if file.replace(s.to_string()).is_some() {
                    return Err(format!("more than one input file given\n{USAGE}"));
                }
            }
        }
    }
    let file = file.ok_or_else(|| format!("no input file given\n{USAGE}"))?;
    Ok(Args { solver, repeat, file })
}

fn run() -> Result<serde_json::Value, String> {
    let args = parse_args()?;
    let text = std::fs::read_to_string(&args.file)
        .map_err(|e| format!("cannot read '{}': {e}", args.file))?;
    let lcp = Lcp::read_any(&text).map_err(|e| format!("'{}': {e}", args.file))?;
    let mut solver: Box<dyn Solver> = match args.solver.as_str() {
        "lemke" => Box::new(Lemke::default()),
        "pgs" => Box::new(Pgs::default()),
        "enum" => Box::new(Enumeration::default()),
        _ => Box::new(Auto::default()),
    };
    let mut out = Solution::new();
    solver.solve_into(lcp.view(), None, &mut out).map_err(|e| e.to_string())?;
    let mut json = serde_json::json!({
        "solver": args.solver,
        "n": lcp.n(),
        "status": out.status.to_string(),
        "method": out.method.to_string(),
        "z": out.z,
        "w": out.w,
        "residual": out.residual,
        "iterations": out.iterations,
    });
    if let Some(n) = args.repeat {
        let start = Instant::now();
        for _ in 0..n {
            solver.solve_into(lcp.view(), None, &mut out).map_err(|e| e.to_string())?;
        }
        json["seconds_per_solve"] = serde_json::json!(start.elapsed().as_secs_f64() / n as f64);
    }
    if args.solver == "enum" {
        let all = Enumeration::default().solve_all(lcp.view()).map_err(|e| e.to_string())?;
        let solutions: Vec<serde_json::Value> = all
            .iter()
            .map(|s| serde_json::json!({ "z": s.z, "w": s.w, "residual": s.residual }))
            .collect();
        json["solutions"] = serde_json::Value::Array(solutions);
    }
    Ok(json)
}

fn main() -> ExitCode {
    match run() {
        Ok(json) => {
            println!("{json}");
            ExitCode::SUCCESS
        }
        Err(message) => {
            eprintln!("solve: {message}");
            ExitCode::from(2)
        }
    }
}
