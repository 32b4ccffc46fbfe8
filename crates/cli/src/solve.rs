//! `moreau solve`: one step problem from a file in Siconos' format, solved by one of
//! `moreau-lcp`'s solvers: the problem a run stopped on (`simulate` writes it, see
//! [`crate::failed`]), a problem of Siconos' collection, or one of your own.
//!
//! Three kinds of problems are read: an LCP (`0 ≤ z ⊥ w = M z + q ≥ 0`, Siconos' LCP format,
//! as the LCP of eq. 7.41 is written), a planar frictional-contact problem (`u = W r + q`,
//! Coulomb's law at each contact, Siconos' FC2D format, as an island's problem is written),
//! and a global one (`M v = H r + q`, `u = Hᵀ v + b`, Siconos' GFC2D format), which is
//! reduced to the contacts' problem with `W = Hᵀ M⁻¹ H` and solved as such. The kind is told
//! from the file when only one reader accepts it, or given. The solution goes to a CSV file,
//! `i,z,w` for an LCP and `contact,r_n,r_t,u_n,u_t` for a contact problem; a solve that misses
//! its tolerance is an error, and its last iterate goes to `<out>.partial`.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::Result;
use moreau_lcp::fc2d::{
    Fc2d, Fc2dAuto, Fc2dAutoOptions, Fc2dSolution, Fc2dSolver, Gfc2d, LcpRoute, LcpRouteOptions,
    Newton, NewtonOptions, Nsgs, NsgsOptions, Proximal, ProximalOptions,
};
use moreau_lcp::{
    Auto, AutoOptions, Enumeration, EnumerationOptions, Lcp, LcpError, Lemke, LemkeOptions, Method,
    Pgs, PgsOptions, Solution, Solver, Status,
};

use crate::error::CliError;
use crate::number;
use crate::output::{self, Output, OutputLock, csv_record};

/// The solvers of an LCP, by name; the first is the default.
pub const LCP_SOLVERS: [&str; 4] = ["auto", "lemke", "pgs", "enum"];

/// The solvers of a planar frictional-contact problem, by name; the first is the default.
pub const FC2D_SOLVERS: [&str; 5] = ["auto", "nsgs", "newton", "proximal", "lcp-route"];

/// A problem read from a file.
#[derive(Clone, Debug, PartialEq)]
pub enum Problem {
    /// A linear complementarity problem.
    Lcp(Lcp),
    /// A planar frictional-contact problem.
    Fc2d(Fc2d),
    /// A global planar frictional-contact problem, held as the contacts' problem it reduces
    /// to (`Gfc2d::reduce`).
    Gfc2d(Fc2d),
}

impl Problem {
    /// `lcp`, `fc2d` or `gfc2d`.
    pub fn kind(&self) -> &'static str {
        match self {
            Self::Lcp(_) => "lcp",
            Self::Fc2d(_) => "fc2d",
            Self::Gfc2d(_) => "gfc2d",
        }
    }

    /// Its size: the rows n of an LCP, the contacts n_c of a contact problem.
    pub fn size(&self) -> usize {
        match self {
            Self::Lcp(lcp) => lcp.n(),
            Self::Fc2d(p) | Self::Gfc2d(p) => p.n_contacts(),
        }
    }
}

/// Reads the problem in `path`: as `kind` (`lcp`, `fc2d` or `gfc2d`) when given, otherwise as
/// whichever of the three formats accepts the file. A global problem is reduced on reading.
///
/// # Errors
/// [`CliError::TrailingData`] naming the line when the file holds a problem (of the kind
/// given, or of a kind the file reads as up to there) followed by data its sizes leave out
/// (Siconos' free-text comment after an LCP, and the flag after an FC2D problem, are read);
/// [`CliError::Problem`] when the file cannot be read, is not of the kind given, is of no
/// kind (with each reader's reason) or of more than one, is a global problem whose M
/// cannot be factored, or ends inside a number (no space or line end after its last
/// number, as in a file cut off: `1.000e-02` cut to `1.` would read as μ = 1);
/// [`CliError::UnknownProblemKind`] for another kind.
pub fn read(path: &Path, kind: Option<&str>) -> Result<Problem> {
    let refuse = |reason: String| CliError::Problem { path: path.to_owned(), reason };
    let trailing = |kind: &'static str, e: &LcpError| match e {
        LcpError::TrailingData { line, found, after } => Some(CliError::TrailingData {
            path: path.to_owned(),
            kind,
            line: *line,
            found: found.clone(),
            after,
        }),
        _ => None,
    };
    let text = std::fs::read_to_string(path).map_err(|e| refuse(format!("cannot be read: {e}")))?;
    let problem = read_text(&text, kind, &refuse, &trailing)?;
    if let Some((line, token)) = cut_inside_number(&text) {
        return Err(refuse(format!(
            "ends inside its last number '{token}' on line {line}, with no space or line end \
             after it: the file looks cut off (Siconos and `simulate` end every file with one), \
             and the number may be the start of a longer one; add a line end if the file is \
             whole"
        ))
        .into());
    }
    Ok(problem)
}

/// Where `text` ends inside a number: its last token, when it reads as a number and no
/// whitespace follows it, with its 1-based line.
fn cut_inside_number(text: &str) -> Option<(usize, &str)> {
    if text.ends_with(|c: char| c.is_whitespace()) {
        return None;
    }
    let token = text.split_whitespace().next_back()?;
    token.parse::<f64>().ok()?;
    Some((text.lines().count(), token))
}

/// [`read`] of the file's `text`, with its refusals.
fn read_text(
    text: &str,
    kind: Option<&str>,
    refuse: &dyn Fn(String) -> CliError,
    trailing: &dyn Fn(&'static str, &LcpError) -> Option<CliError>,
) -> Result<Problem> {
    let bytes = text.as_bytes();
    let read_as = |kind: &str| match kind {
        "lcp" => Lcp::read_siconos(bytes).map(Problem::Lcp),
        "fc2d" => Fc2d::read_siconos(bytes).map(Problem::Fc2d),
        _ => Gfc2d::read_siconos(bytes).and_then(|g| g.reduce()).map(|r| Problem::Gfc2d(r.problem)),
    };
    let kinds = [("lcp", "an LCP file"), ("fc2d", "an FC2D file"), ("gfc2d", "a GFC2D file")];
    if let Some(kind) = kind {
        let Some(&(_, name)) = kinds.iter().find(|(k, _)| *k == kind) else {
            return Err(CliError::UnknownProblemKind { kind: kind.to_owned() }.into());
        };
        return Ok(read_as(kind).map_err(|e| {
            trailing(name, &e).unwrap_or_else(|| refuse(format!("is not {name}: {e}")))
        })?);
    }
    let readers = kinds.map(|(kind, name)| (kind, name, read_as(kind)));
    let (read, refused): (Vec<_>, Vec<_>) = readers.into_iter().partition(|(_, _, r)| r.is_ok());
    let mut read = read.into_iter().filter_map(|(k, _, r)| r.ok().map(|p| (k, p)));
    match (read.next(), read.next()) {
        (Some((_, problem)), None) => Ok(problem),
        (Some((a, _)), Some((b, _))) => {
            Err(refuse(format!("reads both as {a} and as {b}; say which with --problem")).into())
        }
        (None, _) => {
            // A problem followed by data is told as such, whatever the other readers say.
            if let Some(e) = refused
                .iter()
                .find_map(|(_, name, r)| r.as_ref().err().and_then(|e| trailing(name, e)))
            {
                return Err(e.into());
            }
            let reasons: Vec<String> = refused
                .into_iter()
                .filter_map(|(_, name, r)| r.err().map(|e| format!("{name} ({e})")))
                .collect();
            Err(refuse(format!("is not {}", reasons.join(", nor "))).into())
        }
    }
}

/// What a solve found.
#[derive(Clone, Debug, PartialEq)]
pub struct Solved {
    /// `lcp`, `fc2d` or `gfc2d`.
    pub kind: &'static str,
    /// The problem's size: rows of an LCP, contacts of a contact problem.
    pub size: usize,
    /// The solver's name, as given or defaulted.
    pub solver: String,
    /// How the solve ended; [`Status::Solved`] only when the residual meets the tolerance.
    pub status: Status,
    /// The method that produced the solution.
    pub method: Method,
    /// For a contact problem solved through the LCP route, the LCP solver's own method.
    pub lcp_method: Option<Method>,
    /// Pivots or sweeps or Newton iterations, as the method counts them.
    pub iterations: usize,
    /// The residual the solver is judged by (dimensionless): `Residual::relative` of an
    /// LCP, `Fc2dResidual::natural` of a contact problem.
    pub residual: f64,
    /// The tolerance the solver was given: `--tolerance`, or the solver's default.
    pub tolerance: f64,
    /// For a contact problem whose residual is above the tolerance, the residual that
    /// floating point does not resolve at the solution (`Fc2dResidual::round_off`): a solver
    /// calls such a problem solved when its residual is within it; 0 otherwise.
    pub round_off: f64,
    /// The CSV columns of the solution.
    pub columns: Vec<&'static str>,
    /// The solution's rows: (i, z_i, w_i), or (contact, r_N, r_T, u_N, u_T).
    pub rows: Vec<Vec<f64>>,
}

/// The default options of type `$options` with their `tolerance` replaced by `$tolerance`
/// (an `Option<f64>`) when it is given.
macro_rules! options {
    ($options:ident, $tolerance:expr) => {{
        let default = $options::default();
        let tolerance = $tolerance.unwrap_or(default.tolerance);
        default.with_tolerance(tolerance)
    }};
}

/// The solver `$solver` of options `$options` to `$tolerance` (as [`options!`]), boxed as
/// `$boxed`, with the tolerance it was given.
macro_rules! solver {
    ($solver:ident, $options:ident, $tolerance:expr, $boxed:ty) => {{
        let options = options!($options, $tolerance);
        let tolerance = options.tolerance;
        (Box::new($solver::new(options)?) as $boxed, tolerance)
    }};
}

/// Solves `problem` with the solver named `solver` (the first of [`LCP_SOLVERS`] or
/// [`FC2D_SOLVERS`] when `None`), to `tolerance` when given (the solver's default otherwise).
///
/// A contact problem's solver calls it solved when its residual is within the tolerance or
/// within the round-off at the solution ([`Solved::round_off`]), which may exceed a tight
/// tolerance.
///
/// # Errors
/// [`CliError::UnknownSolver`] for a name that is not a solver of the problem's kind;
/// [`CliError::BadTolerance`] for a tolerance outside (0, 1), the rule of the scenes' solver
/// tolerance and of the LCP solvers' options, applied to every solver; a tolerance the
/// solver refuses.
pub fn solve(problem: &Problem, solver: Option<&str>, tolerance: Option<f64>) -> Result<Solved> {
    if let Some(value) = tolerance.filter(|t| !(*t > 0.0 && *t < 1.0)) {
        return Err(CliError::BadTolerance { value }.into());
    }
    let unknown = |name: &str, accepted: &[&str]| CliError::UnknownSolver {
        name: name.to_owned(),
        kind: problem.kind(),
        accepted: accepted.join(", "),
    };
    match problem {
        Problem::Lcp(lcp) => {
            let name = solver.unwrap_or(LCP_SOLVERS[0]);
            type Boxed = Box<dyn Solver>;
            let (mut solver, given) = match name {
                "auto" => {
                    let lemke = options!(LemkeOptions, tolerance);
                    let given = lemke.tolerance;
                    let options = AutoOptions::default()
                        .with_lemke(lemke)
                        .with_enumeration(options!(EnumerationOptions, tolerance));
                    (Box::new(Auto::new(options)?) as Boxed, given)
                }
                "lemke" => solver!(Lemke, LemkeOptions, tolerance, Boxed),
                "pgs" => solver!(Pgs, PgsOptions, tolerance, Boxed),
                "enum" => solver!(Enumeration, EnumerationOptions, tolerance, Boxed),
                other => return Err(unknown(other, &LCP_SOLVERS).into()),
            };
            let s: Solution = solver.solve(lcp)?;
            let rows = (0..lcp.n()).map(|i| vec![i as f64, s.z[i], s.w[i]]).collect();
            Ok(Solved {
                kind: "lcp",
                size: lcp.n(),
                solver: name.to_owned(),
                status: s.status,
                method: s.method,
                lcp_method: None,
                iterations: s.iterations,
                residual: s.residual.relative,
                tolerance: given,
                round_off: 0.0,
                columns: vec!["i", "z", "w"],
                rows,
            })
        }
        Problem::Fc2d(p) | Problem::Gfc2d(p) => {
            let name = solver.unwrap_or(FC2D_SOLVERS[0]);
            type Boxed = Box<dyn Fc2dSolver>;
            let (mut solver, given) = match name {
                "auto" => solver!(Fc2dAuto, Fc2dAutoOptions, tolerance, Boxed),
                "nsgs" => solver!(Nsgs, NsgsOptions, tolerance, Boxed),
                "newton" => solver!(Newton, NewtonOptions, tolerance, Boxed),
                "proximal" => solver!(Proximal, ProximalOptions, tolerance, Boxed),
                "lcp-route" => solver!(LcpRoute, LcpRouteOptions, tolerance, Boxed),
                other => return Err(unknown(other, &FC2D_SOLVERS).into()),
            };
            let s: Fc2dSolution = solver.solve(p)?;
            let rows = (0..p.n_contacts())
                .map(|c| vec![c as f64, s.r[2 * c], s.r[2 * c + 1], s.u[2 * c], s.u[2 * c + 1]])
                .collect();
            Ok(Solved {
                kind: problem.kind(),
                size: p.n_contacts(),
                solver: name.to_owned(),
                status: s.status,
                method: s.method,
                lcp_method: s.lcp_method,
                iterations: s.iterations,
                residual: s.residual.natural,
                tolerance: given,
                round_off: if s.residual.natural > given { s.residual.round_off } else { 0.0 },
                columns: vec!["contact", "r_n", "r_t", "u_n", "u_t"],
                rows,
            })
        }
    }
}

/// Writes a solution as CSV (numbers as [`number`] writes them, indices as integers).
fn write_csv(solved: &Solved, mut w: impl Write) -> Result<()> {
    writeln!(w, "{}", csv_record(&solved.columns)?)?;
    for row in &solved.rows {
        write!(w, "{}", row[0] as usize)?;
        for &x in &row[1..] {
            number::write_next(&mut w, x)?;
        }
        writeln!(w)?;
    }
    w.flush()?;
    Ok(())
}

/// Reads the problem in `path` (see [`read`]), solves it (see [`solve`]) and, with `out`,
/// writes its solution there as CSV: to `<out>.partial`, renamed to `out` when the solve met
/// its tolerance. `out` must not be the problem file nor an existing file other than a regular
/// file (a symbolic link is written through to its file), and is locked (`<out>.lock`) while
/// it is written; see [`output`].
///
/// # Errors
/// Those of [`read`] and [`solve`]; an output that is the problem file or not a regular file
/// ([`CliError::Output`]) or that another run holds ([`CliError::Locked`]); an unwritable
/// output; [`CliError::NotSolved`] when the solver misses its tolerance, after writing its
/// last iterate to `<out>.partial` and removing an `out` that an earlier solve left (nothing
/// is written to `out`).
pub fn run(
    path: &Path,
    kind: Option<&str>,
    solver: Option<&str>,
    tolerance: Option<f64>,
    out: Option<&Path>,
) -> Result<Solved> {
    let out = out.map(Output::new).transpose()?;
    if let Some(out) = &out {
        output::check_distinct(&[path], &[out])?;
    }
    let _lock = out.as_ref().map(OutputLock::acquire).transpose()?;
    let problem = read(path, kind)?;
    let solved = solve(&problem, solver, tolerance)?;
    let Some(out) = out else {
        return if solved.status == Status::Solved {
            Ok(solved)
        } else {
            Err(not_solved(&solved, None).into())
        };
    };
    let (partial, mut w) = out.create_partial()?;
    write_csv(&solved, &mut w)?;
    if solved.status == Status::Solved {
        out.publish_written(&partial, w)?;
        Ok(solved)
    } else {
        // An `out` an earlier solve wrote is the solution of another problem, or of this one
        // by another solver or tolerance: it does not describe this solve.
        drop(w);
        output::remove_stale(out.target())?;
        Err(not_solved(&solved, Some(partial)).into())
    }
}

/// The error of a solve that missed its tolerance.
fn not_solved(solved: &Solved, partial: Option<PathBuf>) -> CliError {
    CliError::NotSolved {
        solver: solved.solver.clone(),
        status: solved.status,
        residual: solved.residual,
        iterations: solved.iterations,
        partial,
    }
}
