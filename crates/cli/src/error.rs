//! The command's error type: every refusal and every stopped run, each saying what is wrong.

use std::path::PathBuf;

/// Why the divergence guard stopped a run.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Divergence {
    /// The total energy T + V of a mechanism without drives grew beyond its bound.
    EnergyGrowth {
        /// Total energy at the start (J).
        initial: f64,
        /// Total energy at the step (J).
        reached: f64,
        /// The largest energy the guard accepts (J).
        bound: f64,
    },
    /// An entry of q or u grew beyond the guard's magnitude bound.
    StateMagnitude {
        /// `q` or `u`.
        what: &'static str,
        /// Name of the coordinate or velocity.
        name: String,
        /// Its value.
        value: f64,
        /// The bound it passed.
        bound: f64,
    },
    /// The time step exceeds the stability limit 2/ω_max of the smooth dynamics.
    StepAboveStability {
        /// The scene's time step Δt (s).
        dt: f64,
        /// The stability limit 2/ω_max (s).
        limit: f64,
        /// The largest natural angular frequency ω_max at the initial state (rad/s).
        omega_max: f64,
    },
    /// A contact penetrates deeper than the model's size: a body passed through another, the
    /// step too long for its contacts.
    Penetration {
        /// The depth max(0, −g_N) of the deepest contact (the model's length unit: m for a
        /// report model).
        depth: f64,
        /// The deepest penetration the guard accepts (the thickness of what the model's
        /// contacts join, see [`crate::guard::contact_depth`]).
        bound: f64,
        /// Where the gap was taken: `the step's midpoint` (where the step's contacts are
        /// chosen) or `the run's end`.
        at: &'static str,
    },
    /// A step carried a body through a shape it should strike, without any contact sinking
    /// deep: it moved by more than its own thickness in one step
    /// (`moreau_models::bodies::CrossingCheck`).
    Crossed {
        /// The body that moved.
        body: String,
        /// The body it passed through.
        other: String,
        /// How far it moved in the step (the mechanism's length unit).
        moved: f64,
        /// Its thickness (the same unit).
        thickness: f64,
        /// The deepest overlap on its way (a negative gap).
        gap: f64,
    },
    /// The stepper met a non-finite number.
    NonFinite {
        /// The stepper's message.
        message: String,
    },
}

impl std::fmt::Display for Divergence {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::EnergyGrowth { initial, reached, bound } => write!(
                f,
                "energy grew from {initial:.6e} J to {reached:.6e} J, beyond the bound \
                 {bound:.6e} J of a mechanism without drives"
            ),
            Self::StateMagnitude { what, name, value, bound } => {
                write!(f, "{what} entry {name} = {value:.6e} exceeds the bound {bound:.3e}")
            }
            Self::StepAboveStability { dt, limit, omega_max } => write!(
                f,
                "time step dt = {dt:e} s exceeds the stability limit 2/ω_max = {limit:.6e} s of \
                 the stiffest mode (ω_max = {omega_max:.6e} rad/s at the initial state)"
            ),
            Self::Penetration { depth, bound, at } => write!(
                f,
                "a contact penetrates {depth:.6e} deep at {at}, deeper than the bound \
                 {bound:.3e} (the thickness of what the contact joins, or a declared \
                 mechanism's size): a body has passed through another, the time step is too \
                 long for the contacts"
            ),
            Self::Crossed { body, other, moved, thickness, gap } => write!(
                f,
                "`{body}` went through `{other}` in one step: it moved {moved:.6e} (its \
                 thickness {thickness:.3e}) and overlapped `{other}` by {:.3e} on its way \
                 between the step's ends, which the step's midpoint did not see: the time step \
                 is too long for the bodies' speeds",
                -gap
            ),
            Self::NonFinite { message } => write!(f, "{message}"),
        }
    }
}

/// Everything the `moreau` command refuses or stops on.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CliError {
    /// A run diverged: the cause and the step at which the guard saw it.
    #[error("the run diverged at step {step} (t = {t:e} s): {cause}")]
    Diverged {
        /// What the guard saw.
        cause: Divergence,
        /// Index of the step (0 for the first; 0 too for a refusal before the first step).
        step: u64,
        /// Time of the step's end (s).
        t: f64,
    },
    /// The time step is longer than the run.
    #[error("time step dt = {dt:e} s is longer than the run ({})", run_span(*t_start, *t_end))]
    StepLongerThanRun {
        /// Time step (s).
        dt: f64,
        /// Start time (s).
        t_start: f64,
        /// End time (s).
        t_end: f64,
    },
    /// The run's length t_end − t_start is not a whole number of steps.
    #[error(
        "{} is not a whole number of steps of dt = {dt:e} s ({}/dt = {ratio}); choose {} so \
         that the last row lies at t_end",
        run_span(*t_start, *t_end),
        if *t_start == 0.0 { "t_end" } else { "(t_end − t_start)" },
        if *t_start == 0.0 { "t_end = n dt" } else { "t_end = t_start + n dt" }
    )]
    NotWholeSteps {
        /// Start time (s).
        t_start: f64,
        /// End time (s).
        t_end: f64,
        /// Time step (s).
        dt: f64,
        /// (t_end − t_start) / dt.
        ratio: f64,
    },
    /// More steps than the limit.
    #[error(
        "the run needs {steps:.4e} steps, more than the limit of {limit}; raise it with \
         --max-steps if that is meant"
    )]
    TooManySteps {
        /// Steps the run needs.
        steps: f64,
        /// The limit.
        limit: u64,
    },
    /// A command-line option whose text is not of its form (a sweep's `--set key=v1,v2,...`,
    /// `--shard K/N`), named as it was typed.
    #[error("{option} {text}: {reason}")]
    BadOption {
        /// The option: `--set`, `--shard` or `--members`.
        option: &'static str,
        /// Its text as given.
        text: String,
        /// What is wrong with it.
        reason: String,
    },
    /// The same scene entry set twice (directly or through an alias).
    #[error("'{second}' sets {entry}, which '{first}' already sets; give each key once")]
    RepeatedKey {
        /// The first key.
        first: String,
        /// The key that repeats it.
        second: String,
        /// The scene entry both set.
        entry: String,
    },
    /// A sweep whose run (its shard) holds more members than one run may.
    #[error(
        "the sweep's run holds {members} members (of {total} in the sweep), more than the \
         {limit} one run may hold: its rows are read back and sorted in memory at its end, and \
         its members are checked one by one before the first runs; split it with --shard K/N, \
         N >= {shards}, and merge the parts"
    )]
    SweepTooLarge {
        /// Members of the run (of its shard).
        members: u64,
        /// Members of the whole sweep.
        total: u64,
        /// The most members one run may hold (`sweep::MAX_MEMBERS`).
        limit: u64,
        /// The fewest shards that bring each run under the limit.
        shards: u64,
    },
    /// A sweep whose every row is written but some of whose members diverged or failed.
    #[error(
        "{diverged} members diverged and {failed} failed of the {rows} in {out}; each row's \
         `status` and `error` say which and why"
    )]
    MembersFailed {
        /// The sweep's output.
        out: PathBuf,
        /// Its rows.
        rows: u64,
        /// Members the divergence guard stopped.
        diverged: u64,
        /// Members whose run failed otherwise.
        failed: u64,
    },
    /// An output path that cannot be written, or would overwrite data.
    #[error("output {path}: {reason}")]
    Output {
        /// The path.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// An output whose lock file exists and whose process runs, or may run since it cannot be
    /// seen (another host's, a lock without a host, no `/proc`); a lock whose process is seen
    /// to be gone is taken over instead (`output::OutputLock`).
    #[error(
        "output {output} is locked by {lock}: {why}; wait for that run to end, or remove \
         {lock} if no run is going on"
    )]
    Locked {
        /// The output as given.
        output: PathBuf,
        /// The lock file, `<out>.lock`.
        lock: PathBuf,
        /// The process id the lock file holds (`unknown` when it holds none).
        holder: String,
        /// Whether its process runs, or why that cannot be seen.
        why: String,
    },
    /// A sweep part that does not belong with the others.
    #[error("{part}: {reason}")]
    MixedParts {
        /// The part.
        part: PathBuf,
        /// How it differs.
        reason: String,
    },
    /// A sweep part that lacks members of its shard, or a set of parts that lacks members.
    #[error("{part}: members missing: {members}")]
    MissingMembers {
        /// The part (or the set of parts).
        part: PathBuf,
        /// The missing member indices (a list, shortened when long).
        members: String,
    },
    /// Neither a model nor a scene file was given, so there is nothing to run.
    #[error(
        "no model to run: name one ({accepted}) or give a scene file with --scene FILE, \
         which names its model or declares its bodies"
    )]
    NoModel {
        /// The accepted model names.
        accepted: String,
    },
    /// The model named on the command line is not the model the scene file describes.
    #[error(
        "the model '{given}' disagrees with the scene file {path}, which describes model \
         '{in_scene}'; leave out the model name to run the scene's own"
    )]
    ModelMismatch {
        /// The model named on the command line.
        given: String,
        /// The scene file.
        path: PathBuf,
        /// The scene's model (`declared` for a declared mechanism).
        in_scene: String,
    },
    /// A contacts file asked of a model whose contacts have no declared bodies and shapes to
    /// locate them on.
    #[error(
        "a contacts file needs a declared mechanism; the report's model '{model}' records its \
         contacts' impulses and active flags in the main CSV (PN1, PT1, ..., A1, ...)"
    )]
    ContactsOfReportModel {
        /// The model's name.
        model: String,
    },
    /// A sweep of a report model with a thinned record: its key numbers are read from every
    /// step's row (the ball's impacts and rest time, the woodpecker's contact events, the
    /// slider-crank's gaps and crank speeds, the cam's lobes, the Painlevé rod's phases), so
    /// that a record of one step in `record_every` would give other numbers under the same
    /// names. A declared mechanism's key numbers do not depend on the thinning.
    #[error(
        "record_every = {record_every}: the key numbers of the report's model '{model}' are \
         read from every step's row, which a record of one step in {record_every} does not \
         have; sweep it with record_every = 1"
    )]
    KeysNeedEveryRow {
        /// The model's name.
        model: String,
        /// The scene's `record_every` (> 1).
        record_every: usize,
    },
    /// A contact that a step reported and that its detection does not find again.
    #[error(
        "contact {id} of the step ending at t = {t:e} s is not found again at the step's \
         midpoint"
    )]
    ContactNotLocated {
        /// The contact's identity (`StepReport::contact_ids`).
        id: u64,
        /// End time of the step (s).
        t: f64,
    },
    /// A damaged sweep part: a cut-off or altered row.
    #[error("{part}: line {line} is damaged ({reason})")]
    DamagedPart {
        /// The part.
        part: PathBuf,
        /// 1-based line number.
        line: u64,
        /// What is wrong.
        reason: String,
    },
    /// A problem file that cannot be read as the problem asked for.
    #[error("problem file {path} {reason}")]
    Problem {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// A problem file whose problem is followed by data that the sizes it announces leave out
    /// (a size too small, two problems in one file): it is not solved as a smaller problem.
    #[error(
        "problem file {path} is {kind} followed by unexpected data '{found}' on line {line}, \
         after its {after}: the sizes the file announces end the problem there; correct them, \
         or remove what follows"
    )]
    TrailingData {
        /// The file.
        path: PathBuf,
        /// What it reads as up to the data (`an LCP file`, `an FC2D file`, `a GFC2D file`).
        kind: &'static str,
        /// 1-based line number of the first unexpected token.
        line: usize,
        /// That token.
        found: String,
        /// The problem's last part (`q`, `μ`).
        after: &'static str,
    },
    /// A kind of problem other than `lcp`, `fc2d` and `gfc2d`.
    #[error("unknown kind of problem '{kind}'; the kinds are lcp, fc2d and gfc2d")]
    UnknownProblemKind {
        /// The kind given.
        kind: String,
    },
    /// A `--tolerance` outside (0, 1), the range of a scene's solver tolerance: the
    /// residuals are relative, and z = 0 measures at most 1 on any problem, so a tolerance of
    /// 1 or more would call a problem solved that is not.
    #[error(
        "--tolerance {value}: must be in (0, 1); the residual is relative, and 1 or more would \
         accept z = 0 for any problem"
    )]
    BadTolerance {
        /// The tolerance given.
        value: f64,
    },
    /// A solver name that is not a solver of the problem's kind.
    #[error("unknown {kind} solver '{name}'; the {kind} solvers are {accepted}")]
    UnknownSolver {
        /// The name given.
        name: String,
        /// `lcp`, `fc2d` or `gfc2d`.
        kind: &'static str,
        /// The accepted names.
        accepted: String,
    },
    /// A solve that missed its tolerance.
    #[error(
        "{solver} did not solve the problem: status {status} after {iterations} iterations, \
         residual {residual:e}{}",
        partial.as_ref().map(|p| format!("; its last iterate is in {}", p.display())).unwrap_or_default()
    )]
    NotSolved {
        /// The solver's name.
        solver: String,
        /// How it ended.
        status: moreau_lcp::Status,
        /// Its residual at the end (dimensionless).
        residual: f64,
        /// Its iterations.
        iterations: usize,
        /// Where its last iterate was written, if it was.
        partial: Option<PathBuf>,
    },
}

/// The run's span in a message: `t_end = 1e0 s`, or from a start time other than 0
/// `t_end − t_start = 5e-1 s (t_start = 2e0 s, t_end = 2.5e0 s)`.
fn run_span(t_start: f64, t_end: f64) -> String {
    if t_start == 0.0 {
        format!("t_end = {t_end:e} s")
    } else {
        format!(
            "t_end − t_start = {:e} s (t_start = {t_start:e} s, t_end = {t_end:e} s)",
            t_end - t_start
        )
    }
}
