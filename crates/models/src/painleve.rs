//! Painlevé's sliding rod (docs/theory.md §7.5): q = (x, y, φ), one frictional contact of the
//! rod's lower end with the ground.

use moreau_kinematics::{ContactKinematics, ContactPoint};
use moreau_setvalued::ContactLaw;
use moreau_stepper::Mechanism;
use serde::{Deserialize, Serialize};

use crate::ModelError;
use crate::draw::{Drawing, Role};
use crate::params::{LawParams, all_finite, positive};

/// Parameters of the Painlevé rod: length 2s, mass m, J = m s²/3 about its centre.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PainleveParams {
    /// Mass m (kg).
    pub m: f64,
    /// Half length s (m).
    pub s: f64,
    /// Gravitational acceleration g (m/s²).
    pub g: f64,
    /// Normal restitution ε_N (dimensionless, in `[0, 1]`).
    pub eps_n: f64,
    /// Tangential restitution ε_T (dimensionless, in `[0, 1]`).
    pub eps_t: f64,
    /// Friction coefficient μ (dimensionless, >= 0); a < 0 is possible only for μ > 4/3.
    pub mu: f64,
    /// Initial state; the report's (φ0 = atan 2, lower end on the ground, sliding at
    /// x' = −1 m/s) when omitted.
    #[serde(default = "PainleveInit::report")]
    pub init: PainleveInit,
}

/// Initial state of the rod.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PainleveInit {
    /// Centre x (m).
    pub x: f64,
    /// Centre y (m); s sin φ puts the lower end on the ground.
    pub y: f64,
    /// Angle φ to the ground (rad).
    pub phi: f64,
    /// Velocity x' (m/s).
    pub vx: f64,
    /// Velocity y' (m/s).
    pub vy: f64,
    /// Angular velocity φ' (rad/s).
    pub omega: f64,
}

impl PainleveInit {
    /// The report's initial state for s = 1 m: φ0 = atan 2, y0 = s sin φ0, x'0 = −1 m/s.
    pub fn report() -> Self {
        let phi = 2f64.atan();
        Self { x: 0.0, y: phi.sin(), phi, vx: -1.0, vy: 0.0, omega: 0.0 }
    }
}

impl PainleveParams {
    /// The report's test data with μ = 0.3: m = 1 kg, s = 1 m, g = 9.81, ε_N = ε_T = 0.
    pub fn report() -> Self {
        Self::report_with_mu(0.3)
    }

    /// The report's test data with another friction coefficient (the report uses 0.3 and 2.0).
    pub fn report_with_mu(mu: f64) -> Self {
        Self { m: 1.0, s: 1.0, g: 9.81, eps_n: 0.0, eps_t: 0.0, mu, init: PainleveInit::report() }
    }

    /// The scalar LCP of the acceleration level while the end slides with g_T' > 0:
    /// g_N'' = a λ_N + b with a = (1 + 3 cos φ (cos φ − μ sin φ))/m and
    /// b = s φ'² sin φ − g. Returns (a, b).
    pub fn acceleration_lcp(&self, phi: f64, omega: f64) -> (f64, f64) {
        let (sp, cp) = phi.sin_cos();
        let a = (1.0 + 3.0 * cp * (cp - self.mu * sp)) / self.m;
        let b = self.s * omega * omega * sp - self.g;
        (a, b)
    }
}

/// The Painlevé rod as a [`Mechanism`]: M = diag(m, m, m s²/3), h = (0, −m g, 0),
/// g_N = y − s sin φ, g_T = s cos φ − x (tangent −X).
#[derive(Clone, Debug)]
pub struct PainleveRod {
    params: PainleveParams,
    laws: [ContactLaw; 1],
}

impl PainleveRod {
    /// Names of the coordinates q.
    pub const COORDINATES: &'static [&'static str] = &["x", "y", "phi"];
    /// Names of the velocities u.
    pub const VELOCITIES: &'static [&'static str] = &["vx", "vy", "omega"];

    /// Validates the parameters and builds the model.
    ///
    /// # Errors
    /// [`ModelError::InvalidParameter`] naming the field for a non-positive m, s or g, a bad
    /// law or a non-finite initial state.
    pub fn new(params: PainleveParams) -> Result<Self, ModelError> {
        let p = &params;
        positive("m", p.m)?;
        positive("s", p.s)?;
        positive("g", p.g)?;
        let law = LawParams::new(p.eps_n, p.eps_t, p.mu).law("")?;
        let i = &p.init;
        all_finite(&[
            ("init.x", i.x),
            ("init.y", i.y),
            ("init.phi", i.phi),
            ("init.vx", i.vx),
            ("init.vy", i.vy),
            ("init.omega", i.omega),
        ])?;
        Ok(Self { params, laws: [law] })
    }

    /// The parameters.
    pub fn params(&self) -> &PainleveParams {
        &self.params
    }

    /// The initial state (q0, u0).
    pub fn initial_state(&self) -> (Vec<f64>, Vec<f64>) {
        let i = &self.params.init;
        (vec![i.x, i.y, i.phi], vec![i.vx, i.vy, i.omega])
    }

    /// Names of the contacts.
    pub fn contact_names(&self) -> Vec<String> {
        vec!["lower end/ground".to_owned()]
    }

    /// The rod's lower end (x − s cos φ, y − s sin φ) (m).
    pub fn lower_end(&self, q: &[f64]) -> [f64; 2] {
        let s = self.params.s;
        [q[0] - s * q[2].cos(), q[1] - s * q[2].sin()]
    }

    /// Location of the contact point (the lower end).
    pub fn contact_points(&self, q: &[f64], _t: f64) -> Vec<[f64; 2]> {
        vec![self.lower_end(q)]
    }

    /// Draws the ground and the rod; marks the lower end when it touches.
    pub fn draw(&self, q: &[f64], t: f64) -> Drawing {
        let s = self.params.s;
        let mut d = Drawing::new();
        let low = self.lower_end(q);
        let high = [q[0] + s * q[2].cos(), q[1] + s * q[2].sin()];
        d.line(Role::Ground, vec![[q[0] - 2.0 * s, 0.0], [q[0] + 2.0 * s, 0.0]]);
        d.line(Role::Rod, vec![low, high]);
        d.circle(Role::Joint, [q[0], q[1]], 0.02 * s);
        if self.normal_gap(0, q, t) <= 1e-6 * s {
            d.circle(Role::ContactPoint, low, 0.04 * s);
        }
        d
    }
}

impl ContactKinematics for PainleveRod {
    fn num_coordinates(&self) -> usize {
        3
    }
    fn num_contacts(&self) -> usize {
        1
    }
    fn normal_gap(&self, _i: usize, q: &[f64], _t: f64) -> f64 {
        q[1] - self.params.s * q[2].sin()
    }
    fn contact(
        &self,
        i: usize,
        q: &[f64],
        t: f64,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) -> ContactPoint {
        let s = self.params.s;
        let (sp, cp) = q[2].sin_cos();
        w_n[..3].copy_from_slice(&[0.0, 1.0, -s * cp]);
        w_t[..3].copy_from_slice(&[-1.0, 0.0, -s * sp]);
        ContactPoint {
            g_n: self.normal_gap(i, q, t),
            g_t: s * cp - q[0],
            w_n_hat: 0.0,
            w_t_hat: 0.0,
        }
    }
}

impl Mechanism for PainleveRod {
    fn laws(&self) -> &[ContactLaw] {
        &self.laws
    }
    fn mass_matrix(&self, _q: &[f64], _t: f64, m: &mut [f64]) {
        let p = &self.params;
        m[..9].copy_from_slice(&[p.m, 0.0, 0.0, 0.0, p.m, 0.0, 0.0, 0.0, p.m * p.s * p.s / 3.0]);
    }
    fn forces(&self, _q: &[f64], _u: &[f64], _t: f64, h: &mut [f64]) {
        h[..3].copy_from_slice(&[0.0, -self.params.m * self.params.g, 0.0]);
    }
    fn potential_energy(&self, q: &[f64], _t: f64) -> Option<f64> {
        Some(self.params.m * self.params.g * q[1])
    }
    fn constant_mass_matrix(&self) -> bool {
        true
    }
}
