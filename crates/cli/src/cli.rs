//! The command-line interface: the `simulate`, `sweep`, `merge` and `solve` subcommands with
//! their arguments, shared by the `moreau` binary and the repository's `cargo xtask`.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::{Args, Subcommand};

use crate::grid::{Axis, Shard};
use crate::{parts, simulate, solve, sweep};

/// Arguments of `simulate`.
#[derive(Args, Clone, Debug)]
pub struct SimulateArgs {
    /// Model: ball, woodpecker, slider-crank, slider-crank-ideal, cam, painleve; optional
    /// with --scene, which names the model or declares the mechanism.
    pub model: Option<String>,
    /// Scene file (TOML) to start from instead of the report's scene: a report model's or a
    /// declared mechanism's.
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Override a scene key: --set key=value (repeatable; each entry once; in order, the
    /// scene validated once all are applied).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
    /// Time step Δt (s).
    #[arg(long)]
    pub dt: Option<f64>,
    /// End time (s); a whole number of steps.
    #[arg(long)]
    pub tf: Option<f64>,
    /// LCP solver: auto, lemke, pgs or enum.
    #[arg(long)]
    pub solver: Option<String>,
    /// Largest number of steps (default 10 000 000).
    #[arg(long, value_name = "N")]
    pub max_steps: Option<u64>,
    /// Output CSV file (written as OUT.partial until the run succeeds).
    #[arg(long)]
    pub out: PathBuf,
    /// Also write every active contact of the recorded steps, located on its bodies, to this
    /// CSV file (declared mechanisms): t, id, bodies, points, normal, gap, impulses, state.
    #[arg(long, value_name = "FILE")]
    pub contacts: Option<PathBuf>,
    /// Also write the run's end state as a scene file that starts there (t_start the last
    /// time, the bodies or the model's initial state at the last step), to continue the run
    /// or to start others from it: a pile settled once, swept over its friction.
    #[arg(long, value_name = "FILE")]
    pub end_scene: Option<PathBuf>,
}

/// Arguments of `sweep`.
#[derive(Args, Clone, Debug)]
pub struct SweepArgs {
    /// Model: ball, woodpecker, slider-crank, slider-crank-ideal, cam, painleve; optional
    /// with --scene, which names the model or declares the mechanism.
    pub model: Option<String>,
    /// Swept key and its values: --set key=v1,v2,... (repeatable; each entry once; the
    /// members are the product of the axes). The values are split at the commas outside
    /// brackets, braces and quotes only, so that an array or a table is one value:
    /// --set 'gravity=[0,-9.81],[0,-1.62]' sweeps two. A key written +key takes its values
    /// with the --set before it, the i-th with the i-th, as many as it has:
    /// --set 'bodies.bob.position=[..],[..]' --set '+joints.hinge.anchor_b=[..],[..]'.
    #[arg(long = "set", value_name = "KEY=V1,V2,...")]
    pub sets: Vec<String>,
    /// Members listed in a CSV file: a header row of scene keys, then one row of values per
    /// member (a value with a comma quoted, "[0,-9.81]"; # starts a comment line). The rows
    /// are members in their order; --set axes multiply them, the rows outermost.
    #[arg(long, value_name = "FILE")]
    pub members: Option<PathBuf>,
    /// Scene file (TOML) to start from instead of the report's scene: a report model's or a
    /// declared mechanism's.
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Run only part K of N (members i with i mod N = K − 1).
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
    /// Largest number of steps of a member (default 10 000 000).
    #[arg(long, value_name = "N")]
    pub max_steps: Option<u64>,
    /// Continue the unfinished run OUT.partial without rerunning its finished members (a
    /// finished OUT of the same sweep is left as it is; one of another sweep is refused).
    #[arg(long)]
    pub resume: bool,
    /// Output CSV file.
    #[arg(long)]
    pub out: PathBuf,
}

/// Arguments of `merge`.
#[derive(Args, Clone, Debug)]
pub struct MergeArgs {
    /// Output CSV file.
    #[arg(long)]
    pub out: PathBuf,
    /// The parts.
    #[arg(required = true)]
    pub parts: Vec<PathBuf>,
}

/// Arguments of `solve`.
#[derive(Args, Clone, Debug)]
pub struct SolveArgs {
    /// The problem file, in Siconos' LCP, FC2D or GFC2D format (`simulate` writes the
    /// problem of a step it stopped on as LCP or FC2D).
    pub file: PathBuf,
    /// The kind of problem, lcp, fc2d or gfc2d, when the file reads as more than one.
    #[arg(long)]
    pub problem: Option<String>,
    /// The solver: auto, lemke, pgs or enum for an LCP; auto, nsgs, newton, proximal or
    /// lcp-route for an FC2D or GFC2D problem.
    #[arg(long)]
    pub solver: Option<String>,
    /// The solver's tolerance (its default otherwise), in (0, 1) as a scene's solver
    /// tolerance: the residuals are relative.
    #[arg(long)]
    pub tolerance: Option<f64>,
    /// Output CSV file of the solution: i,z,w or contact,r_n,r_t,u_n,u_t (OUT.partial when
    /// the solver misses its tolerance).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// The subcommands.
#[derive(Subcommand, Clone, Debug)]
pub enum Command {
    /// Run one model or scene file and write its record as CSV.
    Simulate(SimulateArgs),
    /// Run the Cartesian product of parameter values (and the members a file lists) in
    /// parallel; one CSV row per member.
    Sweep(SweepArgs),
    /// Join the CSV parts of a sharded sweep, sorted by member. The merged file is written in
    /// full; as `sweep`, the command then exits with status 1 when a member diverged or
    /// failed.
    Merge(MergeArgs),
    /// Solve one LCP or planar frictional-contact problem (local or global) from a file in
    /// Siconos' format.
    Solve(SolveArgs),
}

impl Command {
    /// Runs the subcommand, printing what it did on stdout and warnings on stderr.
    ///
    /// # Errors
    /// Every refusal and failure of the subcommand.
    pub fn run(self) -> Result<()> {
        match self {
            Self::Simulate(a) => a.run(),
            Self::Sweep(a) => a.run(),
            Self::Merge(a) => a.run(),
            Self::Solve(a) => a.run(),
        }
    }
}

impl SimulateArgs {
    /// Runs `simulate`.
    ///
    /// # Errors
    /// As [`simulate::run_to_csv`].
    pub fn run(self) -> Result<()> {
        let options = simulate::SimulateOptions {
            model: self.model,
            scene: self.scene,
            sets: self.sets,
            dt: self.dt,
            tf: self.tf,
            solver: self.solver,
            max_steps: self.max_steps,
            contacts: self.contacts.clone(),
            end_scene: self.end_scene.clone(),
        };
        let done = simulate::run_to_csv(&options, &self.out, &mut |w| eprintln!("warning: {w}"))?;
        println!(
            "{}: {} steps, {} LCP solves, {:.3} s; wrote {} rows to {}",
            done.scene.kind(),
            done.steps,
            done.lcp_solves,
            done.wall_seconds,
            done.rows,
            self.out.display()
        );
        if let (Some(rows), Some(path)) = (done.contact_rows, &self.contacts) {
            println!("wrote {rows} contact rows to {}", path.display());
        }
        if done.inexact_steps > 0 {
            println!(
                "{} steps took an island above the solvers' tolerance, at a natural residual \
                 up to inexact_residual = {} (their largest scale-free LCP residual {:.1e})",
                done.inexact_steps, done.scene.inexact_residual, done.inexact_residual
            );
        }
        Ok(())
    }
}

impl SweepArgs {
    /// Runs `sweep`.
    ///
    /// # Errors
    /// As [`sweep::run`], and [`CliError::MembersFailed`](crate::CliError::MembersFailed) once every row is written when a
    /// member of the output diverged or failed.
    pub fn run(self) -> Result<()> {
        let axes = self.sets.iter().map(|s| Axis::parse(s)).collect::<Result<Vec<_>>>()?;
        let shard = self.shard.as_deref().map(Shard::parse).transpose()?;
        let options = sweep::SweepOptions {
            model: self.model,
            scene: self.scene,
            axes,
            members: self.members,
            shard,
            max_steps: self.max_steps,
            resume: self.resume,
        };
        let s = sweep::run(&options, &self.out).context("sweep")?;
        if s.finished_before {
            println!(
                "{} holds this sweep's {} members already; nothing is left to run",
                self.out.display(),
                s.rows
            );
        } else {
            if s.dropped_damaged_row {
                eprintln!(
                    "warning: the unfinished run's last row was damaged (cut off while written, \
                     or altered): it was dropped and its member run again"
                );
            }
            println!(
                "wrote {} to {} ({} run now, {} diverged, {} failed)",
                members(s.rows),
                self.out.display(),
                s.ran,
                s.diverged,
                s.failed
            );
        }
        Ok(s.members_ok(self.out)?)
    }
}

/// `n` members, in words: `1 member`, `2 members`.
fn members(n: u64) -> String {
    if n == 1 { "1 member".to_owned() } else { format!("{n} members") }
}

impl MergeArgs {
    /// Runs `merge`.
    ///
    /// # Errors
    /// As [`parts::merge`], and [`CliError::MembersFailed`](crate::CliError::MembersFailed) once every row is written when a
    /// member of the merged file diverged or failed, as `sweep` ends on the same rows.
    pub fn run(self) -> Result<()> {
        let s = parts::merge_summary(&self.out, &self.parts)?;
        println!(
            "merged {} into {} ({} diverged, {} failed)",
            members(s.rows),
            self.out.display(),
            s.diverged,
            s.failed
        );
        Ok(s.members_ok(self.out)?)
    }
}

impl SolveArgs {
    /// Runs `solve`.
    ///
    /// # Errors
    /// As [`solve::run`].
    pub fn run(self) -> Result<()> {
        let s = solve::run(
            &self.file,
            self.problem.as_deref(),
            self.solver.as_deref(),
            self.tolerance,
            self.out.as_deref(),
        )?;
        let size = match s.kind {
            "lcp" => format!("LCP of {} rows", s.size),
            "gfc2d" => format!("GFC2D problem of {} contacts (reduced to W = Hᵀ M⁻¹ H)", s.size),
            _ => format!("FC2D problem of {} contacts", s.size),
        };
        let method = match s.lcp_method {
            Some(lcp) => format!("{} ({lcp})", s.method),
            None => s.method.to_string(),
        };
        // A residual above the tolerance was accepted at the round-off of the solution.
        let round_off = if s.residual > s.tolerance {
            format!(
                " (above the tolerance {:e}, within the round-off {:.3e} that floating point \
                 leaves at this solution)",
                s.tolerance, s.round_off
            )
        } else {
            String::new()
        };
        println!(
            "{size}: {} by {method} in {} iterations, residual {:.3e}{round_off}",
            s.status, s.iterations, s.residual
        );
        if let Some(out) = &self.out {
            println!("wrote {} rows to {}", s.rows.len(), out.display());
        }
        Ok(())
    }
}
