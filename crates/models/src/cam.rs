//! The cam with a translating flat-face follower (docs/theory.md §7.4, reconstructed):
//! q = (y), one frictionless rheonomic contact.

use std::f64::consts::{PI, TAU};

use moreau_kinematics::{ContactKinematics, ContactPoint};
use moreau_setvalued::ContactLaw;
use moreau_stepper::Mechanism;
use serde::{Deserialize, Serialize};

use crate::ModelError;
use crate::draw::{Drawing, Role};
use crate::params::{all_finite, finite, non_negative, positive, relation, unit_interval};

/// Which spring law acts on the follower.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SpringLaw {
    /// The reconstruction: the spring acts on the follower, h = −m g − K0 − K_s y (free
    /// length at y = 0), g_N = y − s(t). The default.
    #[default]
    OnFollower,
    /// The law as printed in the source, kept for comparison: h = −m g − K0 − K_s s(t),
    /// g_N = y − R_b − s(t) with y the follower's absolute position.
    AsPrinted,
}

/// Parameters of the cam-follower (the reconstruction's Table 8.5 in [`CamParams::report`]).
///
/// The cam turns at constant speed ω with N identical lobes; over the rise angle β of each
/// lobe the lift is cycloidal, s = H (ψ/β − sin(2πψ/β)/(2π)), and it then drops back to zero
/// at the end of the lobe, where ψ = (ω t + ψ0) mod (2π/N).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CamParams {
    /// Follower mass m (kg).
    pub m: f64,
    /// Cam angular speed ω (rad/s), > 0.
    pub omega: f64,
    /// Base-circle radius R_b (m), >= 0; it does not enter the dynamics of a flat-faced
    /// follower (except in the printed variant's gap); see [`Cam::drawing_radius`].
    pub rb: f64,
    /// Stroke H (m).
    pub stroke: f64,
    /// Rise angle β of a lobe (rad), in (0, 2π/N].
    pub beta: f64,
    /// Number of lobes N (>= 1).
    pub lobes: u32,
    /// Initial cam angle ψ0 (rad).
    pub psi0: f64,
    /// Spring preload K0 (N), >= 0.
    pub k0: f64,
    /// Spring stiffness K_s (N/m), >= 0.
    pub ks: f64,
    /// Gravitational acceleration g (m/s²).
    pub g: f64,
    /// Normal restitution ε_N (the contact is frictionless).
    pub eps_n: f64,
    /// The spring law; [`SpringLaw::OnFollower`] when omitted.
    #[serde(default)]
    pub spring_law: SpringLaw,
    /// Initial state; the report's (y0 = H = 0.017 m, v0 = 0) when omitted.
    #[serde(default = "CamInit::report")]
    pub init: CamInit,
}

/// Initial state of the follower.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CamInit {
    /// Initial follower coordinate y0 (m).
    pub y0: f64,
    /// Initial follower velocity v0 (m/s).
    pub v0: f64,
}

impl CamInit {
    /// The report's initial state: the up-dead point y0 = 0.017 m, v0 = 0.
    pub fn report() -> Self {
        Self { y0: 0.017, v0: 0.0 }
    }
}

impl CamParams {
    /// The reconstruction's table: m = 1 kg, ω = 20.94 rad/s, R_b = 3 mm, H = 17 mm,
    /// N = 6 lobes, β = 60°, ψ0 = 0, K0 = 0, K_s = 2.4e5 N/m, ε_N = 0.4, spring on the follower.
    pub fn report() -> Self {
        Self {
            m: 1.0,
            omega: 20.94,
            rb: 0.003,
            stroke: 0.017,
            beta: PI / 3.0,
            lobes: 6,
            psi0: 0.0,
            k0: 0.0,
            ks: 2.4e5,
            g: 9.81,
            eps_n: 0.4,
            spring_law: SpringLaw::OnFollower,
            init: CamInit::report(),
        }
    }

    /// The variant with the spring law as printed in the source.
    pub fn as_printed() -> Self {
        Self { spring_law: SpringLaw::AsPrinted, ..Self::report() }
    }

    /// Angle 2π/N of one lobe (rad).
    pub fn lobe_angle(&self) -> f64 {
        TAU / f64::from(self.lobes)
    }

    /// Duration 2π/(N ω) of one lobe (s).
    pub fn lobe_period(&self) -> f64 {
        self.lobe_angle() / self.omega
    }

    /// Angle ψ = (ω t + ψ0) mod (2π/N) within the current lobe (rad).
    pub fn lobe_position(&self, t: f64) -> f64 {
        (self.omega * t + self.psi0).rem_euclid(self.lobe_angle())
    }

    /// Lift s and its slope ds/dψ at lobe angle ψ.
    fn lift_at(&self, psi: f64) -> (f64, f64) {
        if psi < self.beta {
            let x = TAU * psi / self.beta;
            (
                self.stroke * (psi / self.beta - x.sin() / TAU),
                self.stroke / self.beta * (1.0 - x.cos()),
            )
        } else {
            (0.0, 0.0)
        }
    }

    /// The cam's lift s(t) (m).
    pub fn lift(&self, t: f64) -> f64 {
        self.lift_at(self.lobe_position(t)).0
    }

    /// The cam's lift rate ds/dt (m/s).
    pub fn lift_rate(&self, t: f64) -> f64 {
        self.omega * self.lift_at(self.lobe_position(t)).1
    }
}

/// The cam-follower as a [`Mechanism`]: M = (m), g_N = y − s(t) (or y − R_b − s(t)),
/// w_N = (1), ŵ_N = −ds/dt, μ = 0.
#[derive(Clone, Debug)]
pub struct Cam {
    params: CamParams,
    laws: [ContactLaw; 1],
}

impl Cam {
    /// Names of the coordinates q.
    pub const COORDINATES: &'static [&'static str] = &["y"];
    /// Names of the velocities u.
    pub const VELOCITIES: &'static [&'static str] = &["v"];

    /// Validates the parameters and builds the model.
    ///
    /// # Errors
    /// [`ModelError::InvalidParameter`] naming the field for a non-positive mass, speed,
    /// stroke or rise angle, β > 2π/N, N = 0, a negative spring constant, ε_N outside
    /// `[0, 1]` or a non-finite value.
    pub fn new(params: CamParams) -> Result<Self, ModelError> {
        let p = &params;
        for (f, v) in
            [("m", p.m), ("omega", p.omega), ("stroke", p.stroke), ("beta", p.beta), ("g", p.g)]
        {
            positive(f, v)?;
        }
        for (f, v) in [("rb", p.rb), ("k0", p.k0), ("ks", p.ks)] {
            non_negative(f, v)?;
        }
        finite("psi0", p.psi0)?;
        if p.lobes == 0 {
            return Err(relation("lobes", 0.0, "the cam needs at least one lobe"));
        }
        if p.beta > p.lobe_angle() * (1.0 + 1e-12) {
            return Err(relation("beta", p.beta, "the rise angle must not exceed one lobe, 2π/N"));
        }
        unit_interval("eps_n", p.eps_n)?;
        all_finite(&[("init.y0", p.init.y0), ("init.v0", p.init.v0)])?;
        let laws = [ContactLaw::frictionless(p.eps_n)?];
        Ok(Self { params, laws })
    }

    /// The parameters.
    pub fn params(&self) -> &CamParams {
        &self.params
    }

    /// The initial state (q0, u0).
    pub fn initial_state(&self) -> (Vec<f64>, Vec<f64>) {
        (vec![self.params.init.y0], vec![self.params.init.v0])
    }

    /// Names of the contacts.
    pub fn contact_names(&self) -> Vec<String> {
        vec!["cam/follower".to_owned()]
    }

    /// The base radius the drawing uses: R_b, or the smallest radius for which the cam
    /// profile a flat face needs is convex (p + p'' ≥ 0 with p = R + s(ψ)) if R_b is smaller,
    /// with a 10 % margin (m).
    ///
    /// A flat-faced follower's dynamics do not depend on the base radius (docs/theory.md §7.4), and
    /// the report's R_b = 3 mm is far too small for this lift law: its profile would undercut
    /// and loop. Drawing with a larger base circle shows a cam that could be made.
    pub fn drawing_radius(&self) -> f64 {
        let p = &self.params;
        let k = TAU / p.beta;
        let need = (0..=720)
            .map(|i| {
                let psi = p.beta * f64::from(i) / 720.0;
                let s = p.stroke * (psi / p.beta - (k * psi).sin() / TAU);
                let s2 = p.stroke / p.beta * k * (k * psi).sin();
                -(s + s2)
            })
            .fold(0.0, f64::max);
        p.rb.max(1.1 * need)
    }

    /// Height of the follower's face in the drawing frame (origin at the cam's axis, base
    /// circle of radius [`Self::drawing_radius`]) (m).
    pub fn face_height(&self, y: f64) -> f64 {
        match self.params.spring_law {
            SpringLaw::OnFollower => self.drawing_radius() + y,
            SpringLaw::AsPrinted => self.drawing_radius() + y - self.params.rb,
        }
    }

    /// The point where the face touches the cam at time t, in the drawing frame:
    /// (ds/dψ, R + s(t)) with R = [`Self::drawing_radius`] (m).
    pub fn contact_points(&self, _q: &[f64], t: f64) -> Vec<[f64; 2]> {
        let (s, slope) = self.params.lift_at(self.params.lobe_position(t));
        vec![[slope, self.drawing_radius() + s]]
    }

    /// Draws the cam (the envelope of the face positions p(φ) = R + s, turned by ω t + ψ0, with
    /// R = [`Self::drawing_radius`]), its axis, the follower with its stem, and the follower's
    /// guide; marks the contact when it is closed.
    pub fn draw(&self, q: &[f64], t: f64) -> Drawing {
        let p = &self.params;
        let radius = self.drawing_radius();
        let mut d = Drawing::new();
        let theta = p.omega * t + p.psi0;
        let (st, ct) = theta.sin_cos();
        let samples = 72 * p.lobes as usize;
        let mut outline = Vec::with_capacity(samples);
        for k in 0..samples {
            let phi = TAU * k as f64 / samples as f64;
            // The face with normal φ in the cam's frame touches when θ = π/2 − φ.
            let psi = (PI / 2.0 - phi).rem_euclid(TAU).rem_euclid(p.lobe_angle());
            let (s, slope) = p.lift_at(psi);
            let (support, dsupport) = (radius + s, -slope);
            let (sp, cp) = phi.sin_cos();
            let local = [support * cp - dsupport * sp, support * sp + dsupport * cp];
            outline.push([ct * local[0] - st * local[1], st * local[0] + ct * local[1]]);
        }
        d.polygon(Role::Cam, outline);
        let width = 2.0 * p.stroke / p.beta + radius + 0.2 * (radius + p.stroke);
        d.circle(Role::Ground, [0.0, 0.0], 0.05 * width);
        let face = self.face_height(q[0]);
        let (plate, stem, len) = (0.05 * width, 0.1 * width, p.stroke + width);
        d.polygon(
            Role::Follower,
            vec![
                [-width, face],
                [width, face],
                [width, face + plate],
                [stem, face + plate],
                [stem, face + len],
                [-stem, face + len],
                [-stem, face + plate],
                [-width, face + plate],
            ],
        );
        let (g0, g1) = (radius + p.stroke + 0.5 * width, radius + p.stroke + 0.9 * width);
        for side in [-1.2 * stem, 1.2 * stem] {
            d.line(Role::Guide, vec![[side, g0], [side, g1]]);
        }
        if self.normal_gap(0, q, t) <= 1e-6 * p.stroke {
            d.circle(Role::ContactPoint, self.contact_points(q, t)[0], 0.03 * width);
        }
        d
    }
}

impl ContactKinematics for Cam {
    fn num_coordinates(&self) -> usize {
        1
    }
    fn num_contacts(&self) -> usize {
        1
    }
    fn normal_gap(&self, _i: usize, q: &[f64], t: f64) -> f64 {
        let s = self.params.lift(t);
        match self.params.spring_law {
            SpringLaw::OnFollower => q[0] - s,
            SpringLaw::AsPrinted => q[0] - self.params.rb - s,
        }
    }
    fn contact(
        &self,
        i: usize,
        q: &[f64],
        t: f64,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) -> ContactPoint {
        w_n[0] = 1.0;
        w_t[0] = 0.0;
        ContactPoint {
            g_n: self.normal_gap(i, q, t),
            g_t: 0.0,
            w_n_hat: -self.params.lift_rate(t),
            w_t_hat: 0.0,
        }
    }
}

impl Mechanism for Cam {
    fn laws(&self) -> &[ContactLaw] {
        &self.laws
    }
    fn mass_matrix(&self, _q: &[f64], _t: f64, m: &mut [f64]) {
        m[0] = self.params.m;
    }
    fn forces(&self, q: &[f64], _u: &[f64], t: f64, h: &mut [f64]) {
        let p = &self.params;
        let spring = match p.spring_law {
            SpringLaw::OnFollower => p.ks * q[0],
            SpringLaw::AsPrinted => p.ks * p.lift(t),
        };
        h[0] = -p.m * p.g - p.k0 - spring;
    }
    fn potential_energy(&self, q: &[f64], t: f64) -> Option<f64> {
        let p = &self.params;
        let y = q[0];
        Some(match p.spring_law {
            SpringLaw::OnFollower => (p.m * p.g + p.k0) * y + 0.5 * p.ks * y * y,
            SpringLaw::AsPrinted => (p.m * p.g + p.k0 + p.ks * p.lift(t)) * y,
        })
    }
    fn constant_mass_matrix(&self) -> bool {
        true
    }
}
