//! Guards that keep a run from passing off a meaningless result: the step plan (Δt ≤ t_end,
//! t_end a whole number of steps, a bound on the number of steps), warnings about the initial
//! gaps, and the divergence guard (stability limit, energy growth, state magnitude,
//! penetration).
//!
//! # The step plan
//! A run takes n = t_end/Δt steps and its last row lies at t_end. A t_end that is not a whole
//! number of steps (up to [`WHOLE_STEPS_TOLERANCE`] of a step) is refused rather than reached
//! with a shortened last step: Moreau's scheme evaluates the contacts at the midpoint of each
//! step and its impact law acts per step, so a last step of another length would be a
//! different discretisation from the rest of the run. A scene with a stop rule may end earlier,
//! at the step that reaches the rule's value. Runs of more than [`DEFAULT_MAX_STEPS`] steps are
//! refused unless a larger limit is given (`--max-steps`).
//!
//! # Initial gaps
//! A contact whose gap g_N at the start is below −[`GAP_TOLERANCE`] ℓ penetrates; one within
//! ±[`GAP_TOLERANCE`] ℓ touches, and round-off then decides whether it is in the first step's
//! active set (g_N ≤ 0). Both are reported as warnings before the run. ℓ is 1 m for a report
//! model and a declared mechanism's size in its own length unit ([`Scales`]).
//!
//! # The divergence guard
//! Before the first step, Δt is compared with the stability limit 2/ω_max of the smooth
//! dynamics: the midpoint scheme is the leapfrog scheme for the smooth part, stable for
//! ω Δt < 2, with ω_max² the largest eigenvalue of M⁻¹K, K = −sym(∂h/∂q) taken by central
//! differences at the initial state. After every step, a mechanism without drives (every report
//! model but the cam; a declared mechanism without driven bodies, motors and applied forces or
//! torques, see [`energy_bound_applies`]) must not gain energy: the run stops when T + V
//! exceeds its initial value by more than [`ENERGY_GROWTH`] times max(T₀ + |V₀|,
//! [`ENERGY_FLOOR`]) (for a declared mechanism, T₀ + |V₀| + m |g| ℓ with m its dynamic mass
//! and ℓ its size, since its V has an arbitrary zero). A driven mechanism gets the stability
//! and magnitude checks only. Every entry of q and u must stay below
//! [`MAGNITUDE_FACTOR`] (1 + max |q₀, u₀|), for a declared mechanism in its own units
//! ([`Bounds::of`]). And no contact may sink more than [`PENETRATION_LIMIT`] ℓ_c (the
//! thickness of what the contacts join, [`contact_depth`]) deeper than the
//! deepest one at the start, at a step's midpoint (where the step's contacts are chosen) or at
//! the run's end: a body carried through what it should strike by a step too long for its
//! contacts. A thin wall can be crossed without any contact sinking deep (the midpoint past
//! its middle, where the gap is measured to its far face, or the whole wall skipped in one
//! step): a declared mechanism's bodies that move by more than a quarter of their thickness
//! in a step are followed along their path (`moreau_models::bodies::CrossingCheck`), and one
//! that overlaps a shape it may strike there by more than a quarter of its thickness stops
//! the run.
//!
//! **Units.** The constants are in metres, seconds and joules for the report's models. A
//! declared mechanism may be written in any consistent units, and its guards measure it in
//! them ([`Scales`]): gaps against its size, positions and the differences' shifts in its
//! length, velocities in its length over √(ℓ/|g|), energies without a floor in joules. A
//! mechanism of milligrams and micrometres is then guarded as the same one in kilograms and
//! metres.

use std::ops::ControlFlow;

use moreau_kinematics::ContactKinematics;
use moreau_models::bodies::{BodyType, Crossing, CrossingCheck, ForceSpec, JointSpec};
use moreau_models::{AnyModel, ModelError, ModelKind, Scene};
use moreau_stepper::{Mechanism, Observer, RunSummary, StepError, StepReport};

use crate::error::{CliError, Divergence};

mod stability;
use stability::by_body;
pub use stability::omega_max;

/// The largest number of steps a run takes unless a larger limit is given.
pub const DEFAULT_MAX_STEPS: u64 = 10_000_000;

/// How far t_end/Δt may lie from a whole number (in steps): the stepper's own rounding of
/// its step count, so that it takes exactly the planned steps.
pub const WHOLE_STEPS_TOLERANCE: f64 = 1e-6;

/// Gaps within ± this (m) at the start count as touching; below −this as penetrating.
pub const GAP_TOLERANCE: f64 = 1e-9;

/// Relative energy growth beyond which a mechanism without drives counts as diverged.
pub const ENERGY_GROWTH: f64 = 1.0;

/// The smallest energy scale of the energy test (J), for a mechanism that starts at rest with
/// zero potential.
pub const ENERGY_FLOOR: f64 = 1e-6;

/// Factor of the state magnitude bound.
pub const MAGNITUDE_FACTOR: f64 = 1e8;

/// The deepest penetration accepted beyond the deepest one at the start, in units of the
/// model's contact depth ℓ_c ([`contact_depth`]): a contact that sinks deeper than the bodies
/// it joins are thick means that a body has passed through another.
pub const PENETRATION_LIMIT: f64 = 1.0;

/// The depth ℓ_c at which a contact of `model` has passed through what it strikes (in the
/// model's length unit): a declared mechanism's size ([`Scales`]); for a report model, the
/// thickness of what its contacts join: the ball's diameter 2R, the cam's base radius r_b (a
/// follower sunk by r_b lies on the cam's axis), the pole's diameter 2 r_O of the woodpecker,
/// the slider's height 2b in its guide, the rod's half length s of Painlevé's rod; 1 m for the
/// ideal slider-crank, which has no contact. The report's cam turned at 10⁵ rad/s used to end
/// with its follower 0.11 m inside the cam, 37 base radii, against the 1 m of every report
/// model, and pass.
pub fn contact_depth(model: &AnyModel) -> f64 {
    match model {
        AnyModel::Declared(m) => m.size(),
        AnyModel::Ball(b) => 2.0 * b.params().r,
        AnyModel::Cam(c) => c.params().rb,
        AnyModel::Woodpecker(w) => 2.0 * w.params().r_o,
        AnyModel::SliderCrank(s) => 2.0 * s.params().b,
        AnyModel::Painleve(p) => p.params().s,
        AnyModel::SliderCrankIdeal(_) => 1.0,
    }
}

/// The deepest penetration max(0, −g_N) of the contacts of `model` at (q, t): those it lists
/// and those its bodies' detection finds (a detected contact set); 0 without contacts.
fn deepest_penetration(model: &AnyModel, q: &[f64], t: f64) -> f64 {
    let mut gaps = vec![0.0; model.num_contacts()];
    if !gaps.is_empty() {
        model.normal_gaps(q, t, &mut gaps);
    }
    let mut detected = Vec::new();
    if let Some(s) = model.body_structure() {
        s.detect(q, t, 0.0, &mut detected);
    }
    let found = detected.iter().map(|c| c.point.g_n);
    gaps.iter().copied().chain(found).fold(0.0f64, |m, g| m.max(-g))
}

/// The units in which the guards measure a model: a length for its gaps, positions and the
/// shifts of the stability limit's differences, and a time that makes velocities of lengths.
///
/// A report model is written in metres and seconds, and its guards' constants are in those
/// units (length and time 1). A declared mechanism may be written in any consistent units
/// (millimetres and grams, or kilometres and tonnes), and its guards measure it in its own:
/// the length is its size (`Multibody::size`), the time √(ℓ/|g|) under gravity, else the
/// scene's Δt.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scales {
    /// The length unit ℓ (the unit of the model's lengths).
    pub length: f64,
    /// The time unit τ (the unit of the model's times).
    pub time: f64,
}

impl Scales {
    /// The scales of `model` run with the step `dt`.
    pub fn of(model: &AnyModel, dt: f64) -> Scales {
        let length = Self::length(model);
        let AnyModel::Declared(m) = model else { return Scales { length, time: 1.0 } };
        let g = m.spec().gravity;
        let g = g[0].hypot(g[1]);
        let time = if g > 0.0 { (length / g).sqrt() } else { dt };
        Scales { length, time }
    }

    /// The length unit alone: a declared mechanism's size, 1 (m) for a report model.
    fn length(model: &AnyModel) -> f64 {
        match model {
            AnyModel::Declared(m) => m.size(),
            _ => 1.0,
        }
    }

    /// Whether coordinate j is an angle measured in radians whatever the length unit: θ of a
    /// declared mechanism's body (its coordinates are x, y, θ per body). A report model's
    /// constants are in metres and radians alike, so none of its coordinates is told apart.
    fn is_angle(model: &AnyModel, j: usize) -> bool {
        matches!(model, AnyModel::Declared(_)) && j % 3 == 2
    }

    /// The unit of coordinate j: 1 for an angle ([`Self::is_angle`]), the length otherwise.
    fn coordinate(model: &AnyModel, j: usize) -> f64 {
        if Self::is_angle(model, j) { 1.0 } else { Self::length(model) }
    }
}

/// The number of steps of a scene's run after checking Δt ≤ t_end − t_start, that the run's
/// length t_end − t_start is a whole number of steps and that there are at most `max_steps`
/// of them.
///
/// # Errors
/// [`CliError::StepLongerThanRun`], [`CliError::NotWholeSteps`] or [`CliError::TooManySteps`].
pub fn plan_steps(scene: &Scene, max_steps: u64) -> Result<u64, CliError> {
    let (dt, t_start, t_end) = (scene.dt, scene.t_start, scene.t_end);
    let ratio = (t_end - t_start) / dt;
    // One step within the rounding of the steps (t_end − t_start of 2.001 − 2 is
    // 0.99999999999989 Δt for Δt = 1e-3) is a step.
    if !(ratio >= 1.0 - WHOLE_STEPS_TOLERANCE) {
        return Err(CliError::StepLongerThanRun { dt, t_start, t_end });
    }
    if !(ratio <= max_steps as f64 + 0.5) {
        return Err(CliError::TooManySteps { steps: ratio, limit: max_steps });
    }
    let n = ratio.round();
    if !((ratio - n).abs() <= WHOLE_STEPS_TOLERANCE) {
        return Err(CliError::NotWholeSteps { t_start, t_end, dt, ratio });
    }
    Ok(n as u64)
}

/// Warnings about the initial gaps: contacts that penetrate or touch within
/// [`GAP_TOLERANCE`] times the model's length unit ([`Scales`]), named with their gaps as the
/// record names them: a report model's contact by its number from 1 (the columns `PN<i>`,
/// `PT<i>`, `A<i>` and the scene files' comments), a declared mechanism's by its name (the
/// columns `<name>.PN`, `<name>.PT`, `<name>.active`); with a detected contact
/// set, the contacts that detection finds at the start, counted, with the deepest and the
/// first touching named by their bodies.
///
/// With `projection` (the scene's position projection), a penetration is said to be moved out
/// in the first step; without, to stay.
pub fn gap_warnings(model: &AnyModel, t0: f64, projection: bool) -> Vec<String> {
    let stays = if projection {
        "the position projection moves the bodies out of it, down to its tolerance, at the \
         first step: a move that no impulse makes, whose change of energy the record's \
         `projected` column counts"
    } else {
        "the scheme acts on velocities and leaves a penetration in place"
    };
    let (q0, _) = model.initial_state();
    let names = model.contact_names();
    let tolerance = GAP_TOLERANCE * Scales::length(model);
    let declared = matches!(model, AnyModel::Declared(_));
    let unit = if declared {
        format!(" (1e-9 of the mechanism's size, {:.3e})", tolerance * 1e9)
    } else {
        " m".to_owned()
    };
    let contact = |i: usize, name: &str| {
        if declared { format!("contact `{name}`") } else { format!("contact {} ({name})", i + 1) }
    };
    let mut out = Vec::new();
    for (i, name) in names.iter().enumerate() {
        let g = model.normal_gap(i, &q0, t0);
        if g < -tolerance {
            out.push(format!("{} starts penetrating: g_N = {g:.6e} ({stays})", contact(i, name)));
        } else if g.abs() <= tolerance {
            out.push(format!(
                "{} starts touching: g_N = {g:.3e} is within ±{tolerance:.3e}{unit}, so \
                 round-off decides whether it is active in the first step",
                contact(i, name)
            ));
        }
    }
    if let AnyModel::Declared(m) = model {
        out.extend(detected_gap_warnings(model, m, (&q0, t0), (tolerance, &unit), stays));
    }
    out
}

/// [`gap_warnings`] for the contacts that the detection of a declared mechanism with a
/// detected contact set finds at the start (within `tolerance` of touching), in two warnings
/// at most, since a pile may hold thousands: how many start penetrating, with the deepest and
/// its bodies, and how many start touching, with the first and its bodies.
fn detected_gap_warnings(
    model: &AnyModel,
    m: &moreau_models::bodies::Multibody,
    (q0, t0): (&[f64], f64),
    (tolerance, unit): (f64, &str),
    stays: &str,
) -> Vec<String> {
    let Some(structure) = model.body_structure() else { return Vec::new() };
    let mut found = Vec::new();
    structure.detect(q0, t0, tolerance, &mut found);
    let names = m.body_names();
    let between = |id: u64| match m.locate_contact(id, q0, t0, tolerance) {
        Some(c) => format!("between `{}` and `{}`", names[c.bodies[0]], names[c.bodies[1]]),
        None => format!("of identity {id}"),
    };
    let plural = |n: usize| if n == 1 { "contact starts" } else { "contacts start" };
    let mut out = Vec::new();
    let penetrating: Vec<_> = found.iter().filter(|c| c.point.g_n < -tolerance).collect();
    if let Some(deepest) = penetrating.iter().min_by(|a, b| a.point.g_n.total_cmp(&b.point.g_n)) {
        let n = penetrating.len();
        out.push(format!(
            "{n} detected {} penetrating, the deepest {}: g_N = {:.6e} ({stays})",
            plural(n),
            between(deepest.id),
            deepest.point.g_n
        ));
    }
    let touching: Vec<_> = found.iter().filter(|c| c.point.g_n.abs() <= tolerance).collect();
    if let Some(first) = touching.first() {
        let n = touching.len();
        out.push(format!(
            "{n} detected {} touching, the first {}: g_N = {:.3e} is within \
             ±{tolerance:.3e}{unit}, so round-off decides whether {} active in the first \
             step",
            plural(n),
            between(first.id),
            first.point.g_n,
            if n == 1 { "it is" } else { "they are" }
        ));
    }
    out
}

/// Whether the mechanism has no drive, so that its energy T + V cannot grow: every model
/// but the cam, whose rotating cam does work on the follower.
pub fn energy_cannot_grow(kind: ModelKind) -> bool {
    kind != ModelKind::Cam
}

/// Whether the energy T + V of this built model cannot grow, so that the energy test
/// applies: for a report model as [`energy_cannot_grow`]; a declared mechanism qualifies when
/// nothing does work on it from outside, that is when it has no driven body (whose prescribed
/// motion pushes through contacts and joints), no motor and no applied force or torque (whose
/// work the potential V does not count). Springs, dampers, gravity, joints and contacts keep
/// it.
pub fn energy_bound_applies(model: &AnyModel) -> bool {
    match model {
        AnyModel::Declared(m) => {
            let spec = m.spec();
            !spec.bodies.iter().any(|b| b.kind == BodyType::Driven)
                && !spec.joints.iter().any(|j| matches!(j, JointSpec::Motor { .. }))
                && !spec
                    .forces
                    .iter()
                    .any(|f| matches!(f, ForceSpec::Force { .. } | ForceSpec::Torque { .. }))
        }
        other => energy_cannot_grow(other.kind()),
    }
}

/// The energy scale of the energy test: max(T₀ + |V₀|, [`ENERGY_FLOOR`]) for a report
/// model (J). A declared mechanism's V has its zero wherever the scene's origin happens to be,
/// so that T₀ + |V₀| may vanish for a mechanism that starts at rest level with the origin (a
/// rod released horizontally from a hinge at the origin); its scale adds m |g| ℓ, the work
/// gravity can do on the total mass m of the dynamic bodies over its size ℓ, and takes no floor
/// in joules, which would hide the growth of a mechanism of milligrams and micrometres
/// (m |g| ℓ = 1e-11 J) beneath it: the floor applies only when the scale is zero (nothing
/// moves, no gravity, no potential).
fn energy_scale(model: &AnyModel, t0: f64, v0: f64) -> f64 {
    let base = t0 + v0.abs();
    let AnyModel::Declared(m) = model else { return base.max(ENERGY_FLOOR) };
    let mass: f64 =
        (0..m.body_names().len()).filter_map(|i| m.mass_properties(i)).map(|p| p.0).sum();
    let g = m.spec().gravity;
    let scale = base + mass * g[0].hypot(g[1]) * m.size();
    if scale > 0.0 { scale } else { ENERGY_FLOOR }
}

/// The bounds of the divergence guard for a model at its initial state.
#[derive(Clone, Debug, PartialEq)]
pub struct Bounds {
    /// (E₀, the largest T + V accepted) for a mechanism whose energy cannot grow
    /// ([`energy_bound_applies`]), in the model's energy unit.
    pub energy: Option<(f64, f64)>,
    /// The largest |q_j| accepted, per coordinate.
    pub q: Vec<f64>,
    /// The largest |u_j| accepted, per velocity.
    pub u: Vec<f64>,
    /// The deepest penetration max(0, −g_N) accepted: the deepest at the start (a scene may
    /// start penetrating) plus [`PENETRATION_LIMIT`] ℓ_c ([`contact_depth`]).
    pub penetration: f64,
}

impl Bounds {
    /// The bounds of `model` run with the step `dt`: the energy bound E₀ + [`ENERGY_GROWTH`]
    /// times the energy scale, and [`MAGNITUDE_FACTOR`] (1 + max |q₀, u₀|) on every entry of a
    /// report model. A declared mechanism's entries are bounded in its own units ([`Scales`]):
    /// positions by [`MAGNITUDE_FACTOR`] (ℓ + max |x₀, y₀|), angles by
    /// [`MAGNITUDE_FACTOR`] (1 + max |θ₀|), velocities by [`MAGNITUDE_FACTOR`]
    /// (ℓ/τ + max |v₀|) and angular velocities by [`MAGNITUDE_FACTOR`] (1/τ + max |ω₀|).
    pub fn of(model: &AnyModel, dt: f64, t0: f64) -> Bounds {
        let (q0, u0) = model.initial_state();
        Self::with_mass(model, dt, (t0, &q0, &u0), &mut Mass::new(model, &q0))
    }

    /// [`Self::of`] from the initial state (q₀, u₀) at t₀, with the mass matrix of the energy
    /// test given (at q₀ or to be evaluated).
    fn with_mass(
        model: &AnyModel,
        dt: f64,
        (t0, q0, u0): (f64, &[f64], &[f64]),
        mass: &mut Mass,
    ) -> Bounds {
        let energy = energy_bound_applies(model)
            .then(|| {
                let v0 = model.potential_energy(q0, t0)?;
                let k0 = kinetic(model, q0, u0, t0, mass);
                let e0 = k0 + v0;
                Some((e0, e0 + ENERGY_GROWTH * energy_scale(model, k0, v0)))
            })
            .flatten();
        let scales = Scales::of(model, dt);
        let (q, u) = if matches!(model, AnyModel::Declared(_)) {
            // Lengths and angles apart: the largest initial entry of each kind, and its unit.
            let angle = |j: usize| Scales::is_angle(model, j);
            let largest = |x: &[f64], of_angles: bool| {
                x.iter()
                    .enumerate()
                    .filter(|&(j, _)| angle(j) == of_angles)
                    .fold(0.0f64, |m, (_, v)| m.max(v.abs()))
            };
            let bound = |x: &[f64], units: [f64; 2]| -> Vec<f64> {
                let b = [largest(x, false) + units[0], largest(x, true) + units[1]];
                (0..x.len()).map(|j| MAGNITUDE_FACTOR * b[usize::from(angle(j))]).collect()
            };
            let (l, t) = (scales.length, scales.time);
            (bound(q0, [l, 1.0]), bound(u0, [l / t, 1.0 / t]))
        } else {
            let largest = q0.iter().chain(u0).fold(0.0f64, |m, x| m.max(x.abs()));
            let b = MAGNITUDE_FACTOR * (1.0 + largest);
            (vec![b; q0.len()], vec![b; u0.len()])
        };
        let penetration =
            deepest_penetration(model, q0, t0) + PENETRATION_LIMIT * contact_depth(model);
        Bounds { energy, q, u, penetration }
    }
}

/// The checks of the divergence guard after each step, wrapped around another observer.
pub struct Guarded<'a, O> {
    inner: &'a mut O,
    bounds: Bounds,
    mass: Mass,
    /// For a declared mechanism: the check of bodies carried through shapes, and the state
    /// (t, q) at the start of the step it looks at.
    crossing: Option<(CrossingCheck, f64, Vec<f64>)>,
    /// The divergence seen, if any.
    pub diverged: Option<CliError>,
}

impl<'a, O: Observer<AnyModel>> Guarded<'a, O> {
    /// The guard of `model` at its initial state at t₀, run with the step `dt`, passing every
    /// step on to `inner`.
    pub fn new(model: &AnyModel, dt: f64, t0: f64, inner: &'a mut O) -> Self {
        let (q0, u0) = model.initial_state();
        let mut mass = Mass::new(model, &q0);
        let bounds = Bounds::with_mass(model, dt, (t0, &q0, &u0), &mut mass);
        let crossing = match model {
            AnyModel::Declared(m) => Some((m.crossing_check(), t0, q0.clone())),
            _ => None,
        };
        Self { inner, bounds, mass, crossing, diverged: None }
    }

    fn check(&mut self, model: &AnyModel, r: &StepReport<'_>) -> Option<Divergence> {
        for (what, values, bounds, names) in [
            ("q", r.q, &self.bounds.q, model.coordinate_names()),
            ("u", r.u, &self.bounds.u, model.velocity_names()),
        ] {
            if let Some(j) = values.iter().zip(bounds).position(|(x, b)| !(x.abs() <= *b)) {
                return Some(Divergence::StateMagnitude {
                    what,
                    name: names.get(j).map_or_else(|| j.to_string(), |s| (*s).to_owned()),
                    value: values[j],
                    bound: bounds[j],
                });
            }
        }
        let bound = self.bounds.penetration;
        if !(r.penetration <= bound) {
            let (depth, at) = (r.penetration, "the step's midpoint");
            return Some(Divergence::Penetration { depth, bound, at });
        }
        if let (Some((check, t, q)), AnyModel::Declared(m)) = (&mut self.crossing, model) {
            let found = check.find(m, (q, *t), (r.q, r.t));
            q.copy_from_slice(r.q);
            *t = r.t;
            if let Some(c) = found {
                let Crossing { body, other, moved, thickness, gap } = c;
                return Some(Divergence::Crossed { body, other, moved, thickness, gap });
            }
        }
        if let Some((initial, bound)) = self.bounds.energy {
            let v = model.potential_energy(r.q, r.t).unwrap_or(0.0);
            let reached = kinetic(model, r.q, r.u, r.t, &mut self.mass) + v;
            if !(reached <= bound) {
                return Some(Divergence::EnergyGrowth { initial, reached, bound });
            }
        }
        None
    }
}

/// The mass matrix of the energy test: one 3 × 3 block per body for a mechanism with a
/// [`BodyStructure`], so that the test costs O(f) per step, the dense f × f M otherwise.
enum Mass {
    /// M, column-major f × f.
    Dense(Vec<f64>),
    /// M's 3 × 3 block of each body, column-major.
    Blocks(Vec<[f64; 9]>),
}

impl Mass {
    /// M at (q, 0).
    fn new(model: &AnyModel, q: &[f64]) -> Self {
        let f = q.len();
        let mut mass = match by_body(model, f) {
            Some(s) => Self::Blocks(vec![[0.0; 9]; s.num_bodies()]),
            None => Self::Dense(vec![0.0; f * f]),
        };
        mass.evaluate(model, q, 0.0);
        mass
    }

    fn evaluate(&mut self, model: &AnyModel, q: &[f64], t: f64) {
        match (self, model.body_structure()) {
            (Self::Blocks(blocks), Some(s)) => s.mass_blocks(q, t, blocks),
            (Self::Dense(m), _) => model.mass_matrix(q, t, m),
            (Self::Blocks(_), None) => unreachable!("blocks are kept for a body structure only"),
        }
    }
}

/// ½ uᵀ M u, with M evaluated into `mass` unless the model's M is constant (and already there).
fn kinetic(model: &AnyModel, q: &[f64], u: &[f64], t: f64, mass: &mut Mass) -> f64 {
    if !model.constant_mass_matrix() {
        mass.evaluate(model, q, t);
    }
    let half = |m: &[f64], u: &[f64]| {
        let f = u.len();
        let mut s = 0.0;
        for j in 0..f {
            for i in 0..f {
                s += u[i] * m[i + f * j] * u[j];
            }
        }
        0.5 * s
    };
    match mass {
        Mass::Dense(m) => half(m, u),
        Mass::Blocks(blocks) => blocks.iter().zip(u.chunks_exact(3)).map(|(m, u)| half(m, u)).sum(),
    }
}

impl<O: Observer<AnyModel>> Observer<AnyModel> for Guarded<'_, O> {
    fn observe(&mut self, model: &AnyModel, report: &StepReport<'_>) -> ControlFlow<()> {
        if let Some(cause) = self.check(model, report) {
            self.diverged = Some(CliError::Diverged { cause, step: report.step, t: report.t });
            return ControlFlow::Break(());
        }
        self.inner.observe(model, report)
    }

    /// Checks the contacts' gaps at the run's end, which no step's midpoint has seen (a run of
    /// one step that carries a body through another), and passes the last step on unless the
    /// run diverged, which the inner observer did not see.
    fn finish(&mut self, model: &AnyModel, last: &StepReport<'_>) {
        if self.diverged.is_none() {
            let depth = deepest_penetration(model, last.q, last.t);
            let bound = self.bounds.penetration;
            if !(depth <= bound) {
                let cause = Divergence::Penetration { depth, bound, at: "the run's end" };
                self.diverged = Some(CliError::Diverged { cause, step: last.step, t: last.t });
            }
        }
        if self.diverged.is_none() {
            self.inner.finish(model, last);
        }
    }
}

/// What a guarded run did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GuardedRun {
    /// The stepper's summary.
    pub summary: RunSummary,
    /// The steps planned (n = t_end/Δt).
    pub planned: u64,
    /// Whether the scene's stop rule ended the run before t_end.
    pub stopped_by_rule: bool,
}

/// Runs `scene` under every guard, streaming each step to `observer`: plans the steps, checks
/// the stability limit, stops on divergence and checks that the run reached t_end (or its stop
/// rule). `model` is the scene's built model.
///
/// # Errors
/// The errors of [`plan_steps`]; [`CliError::Diverged`] for a step above the stability limit,
/// energy growth, a state beyond the magnitude bound, a contact sunk beyond its bound or a
/// non-finite state (with the step); the scene's and the stepper's other errors.
pub fn run_guarded<O: Observer<AnyModel>>(
    scene: &Scene,
    model: &AnyModel,
    max_steps: u64,
    observer: &mut O,
) -> anyhow::Result<GuardedRun> {
    let planned = plan_steps(scene, max_steps)?;
    let omega = omega_max(model);
    if omega * scene.dt >= 2.0 {
        let cause =
            Divergence::StepAboveStability { dt: scene.dt, limit: 2.0 / omega, omega_max: omega };
        return Err(CliError::Diverged { cause, step: 0, t: scene.t_start }.into());
    }
    let mut guarded = Guarded::new(model, scene.dt, scene.t_start, observer);
    let summary = match scene.run_with(&mut guarded) {
        Ok(s) => s,
        Err(ModelError::Step(StepError::NonFinite { what, index, t })) => {
            let message = format!("non-finite {what} at index {index}");
            let cause = Divergence::NonFinite { message };
            let step = ((t - scene.t_start) / scene.dt).round().max(0.0) as u64;
            return Err(CliError::Diverged { cause, step, t }.into());
        }
        Err(e) => return Err(e.into()),
    };
    if let Some(e) = guarded.diverged {
        return Err(e.into());
    }
    let stopped_by_rule = summary.stopped_early;
    anyhow::ensure!(
        stopped_by_rule || summary.steps == planned,
        "the run took {} steps where {planned} were planned",
        summary.steps
    );
    Ok(GuardedRun { summary, planned, stopped_by_rule })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn step_plan_refuses_what_cannot_end_at_t_end() {
        let mut s = Scene::report(ModelKind::Ball);
        assert_eq!(plan_steps(&s, DEFAULT_MAX_STEPS).ok(), Some(10_000));
        s.dt = 1e6;
        assert!(matches!(plan_steps(&s, 10), Err(CliError::StepLongerThanRun { .. })));
        s.dt = 1e300;
        assert!(matches!(plan_steps(&s, 10), Err(CliError::StepLongerThanRun { .. })));
        s.dt = 3e-3;
        assert!(matches!(plan_steps(&s, DEFAULT_MAX_STEPS), Err(CliError::NotWholeSteps { .. })));
        s.dt = 1e-300;
        assert!(matches!(plan_steps(&s, DEFAULT_MAX_STEPS), Err(CliError::TooManySteps { .. })));
        s.dt = 1e-3;
        s.t_end = 1e300;
        assert!(matches!(plan_steps(&s, DEFAULT_MAX_STEPS), Err(CliError::TooManySteps { .. })));
        s.t_end = 0.15;
        s.dt = 1e-4;
        assert_eq!(plan_steps(&s, DEFAULT_MAX_STEPS).ok(), Some(1500));
        assert!(matches!(plan_steps(&s, 1499), Err(CliError::TooManySteps { .. })));
        // One step from a start time, whose span t_end − t_start rounds below Δt.
        (s.dt, s.t_start, s.t_end) = (1e-3, 2.0, 2.001);
        assert!(s.t_end - s.t_start < s.dt);
        assert_eq!(plan_steps(&s, 10).ok(), Some(1));
        s.t_end = 2.0009;
        assert!(matches!(plan_steps(&s, 10), Err(CliError::StepLongerThanRun { .. })));
    }
}
