//! The bouncing ball (docs/theory.md §7.1): q = (y), one frictionless contact with the floor.

use moreau_kinematics::{ContactKinematics, ContactPoint};
use moreau_setvalued::ContactLaw;
use moreau_stepper::Mechanism;
use serde::{Deserialize, Serialize};

use crate::ModelError;
use crate::draw::{Drawing, Role};
use crate::params::{all_finite, positive, unit_interval};

/// Parameters of the bouncing ball: a ball of mass m and radius R whose centre is at height
/// y above the floor; g_N = y − R.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BallParams {
    /// Mass m (kg), > 0.
    pub m: f64,
    /// Radius R (m), > 0.
    pub r: f64,
    /// Gravitational acceleration g (m/s²), > 0.
    pub g: f64,
    /// Normal restitution ε_N in `[0, 1]` (the contact is frictionless, μ = 0).
    pub eps_n: f64,
    /// Initial state; the report's (y0 = 1 m, v0 = 0) when omitted.
    #[serde(default = "BallInit::report")]
    pub init: BallInit,
}

/// Initial state of the ball.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BallInit {
    /// Initial height y0 of the centre (m).
    pub y0: f64,
    /// Initial velocity v0 (m/s, positive up).
    pub v0: f64,
}

impl BallInit {
    /// The report's initial state: y0 = 1 m, v0 = 0.
    pub fn report() -> Self {
        Self { y0: 1.0, v0: 0.0 }
    }
}

impl BallParams {
    /// The report's Table 8.1: m = 1 kg, R = 0.1 m, g = 9.81 m/s², ε_N = 0.9, y0 = 1 m, v0 = 0.
    pub fn report() -> Self {
        Self { m: 1.0, r: 0.1, g: 9.81, eps_n: 0.9, init: BallInit::report() }
    }

    /// Closed form: time t1 = sqrt(2H/g) of the first impact, H = y0 − R, for a ball
    /// released at rest (v0 = 0) (s).
    pub fn first_impact_time(&self) -> f64 {
        (2.0 * (self.init.y0 - self.r) / self.g).sqrt()
    }

    /// Closed form: impact speed v1 = sqrt(2 g H) of the first impact (m/s), for v0 = 0.
    pub fn first_impact_speed(&self) -> f64 {
        (2.0 * self.g * (self.init.y0 - self.r)).sqrt()
    }

    /// Closed form: time of impact `k` (1-based), t_(k+1) = t_k + 2 ε_N^k v1 / g, for v0 = 0 (s).
    pub fn impact_time(&self, k: usize) -> f64 {
        let v1 = self.first_impact_speed();
        let mut t = self.first_impact_time();
        for j in 1..k {
            t += 2.0 * self.eps_n.powi(j as i32) * v1 / self.g;
        }
        t
    }

    /// Closed form: accumulation time t_inf = t1 (1 + ε_N)/(1 − ε_N) after which the ball rests
    /// (s; infinite for ε_N = 1).
    pub fn accumulation_time(&self) -> f64 {
        if self.eps_n >= 1.0 {
            f64::INFINITY
        } else {
            self.first_impact_time() * (1.0 + self.eps_n) / (1.0 - self.eps_n)
        }
    }
}

/// The bouncing ball as a [`Mechanism`]: M = (m), h = (−m g), g_N = y − R, w_N = (1), μ = 0.
#[derive(Clone, Debug)]
pub struct Ball {
    params: BallParams,
    laws: [ContactLaw; 1],
}

impl Ball {
    /// Names of the coordinates q.
    pub const COORDINATES: &'static [&'static str] = &["y"];
    /// Names of the velocities u.
    pub const VELOCITIES: &'static [&'static str] = &["v"];

    /// Validates the parameters and builds the model.
    ///
    /// # Errors
    /// [`ModelError::InvalidParameter`] naming the field when m, R or g is not positive,
    /// ε_N is outside `[0, 1]`, or the initial state is not finite.
    pub fn new(params: BallParams) -> Result<Self, ModelError> {
        positive("m", params.m)?;
        positive("r", params.r)?;
        positive("g", params.g)?;
        unit_interval("eps_n", params.eps_n)?;
        all_finite(&[("init.y0", params.init.y0), ("init.v0", params.init.v0)])?;
        let laws = [ContactLaw::frictionless(params.eps_n)?];
        Ok(Self { params, laws })
    }

    /// The parameters.
    pub fn params(&self) -> &BallParams {
        &self.params
    }

    /// The initial state (q0, u0).
    pub fn initial_state(&self) -> (Vec<f64>, Vec<f64>) {
        (vec![self.params.init.y0], vec![self.params.init.v0])
    }

    /// Names of the contacts.
    pub fn contact_names(&self) -> Vec<String> {
        vec!["floor".to_owned()]
    }

    /// Location of every contact point at `q`.
    pub fn contact_points(&self, _q: &[f64], _t: f64) -> Vec<[f64; 2]> {
        vec![[0.0, 0.0]]
    }

    /// Draws the floor and the ball (centre at (0, y)); marks the contact when it is closed.
    pub fn draw(&self, q: &[f64], t: f64) -> Drawing {
        let r = self.params.r;
        let mut d = Drawing::new();
        d.line(Role::Ground, vec![[-3.0 * r, 0.0], [3.0 * r, 0.0]]);
        d.circle(Role::Ball, [0.0, q[0]], r);
        if self.normal_gap(0, q, t) <= 1e-6 * r {
            d.circle(Role::ContactPoint, [0.0, 0.0], 0.1 * r);
        }
        d
    }
}

impl ContactKinematics for Ball {
    fn num_coordinates(&self) -> usize {
        1
    }
    fn num_contacts(&self) -> usize {
        1
    }
    fn normal_gap(&self, _i: usize, q: &[f64], _t: f64) -> f64 {
        q[0] - self.params.r
    }
    fn normal_gaps(&self, q: &[f64], t: f64, g: &mut [f64]) {
        g[0] = self.normal_gap(0, q, t);
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
        ContactPoint { g_n: self.normal_gap(i, q, t), g_t: 0.0, w_n_hat: 0.0, w_t_hat: 0.0 }
    }
}

impl Mechanism for Ball {
    fn laws(&self) -> &[ContactLaw] {
        &self.laws
    }
    fn mass_matrix(&self, _q: &[f64], _t: f64, m: &mut [f64]) {
        m[0] = self.params.m;
    }
    fn forces(&self, _q: &[f64], _u: &[f64], _t: f64, h: &mut [f64]) {
        h[0] = -self.params.m * self.params.g;
    }
    fn potential_energy(&self, q: &[f64], _t: f64) -> Option<f64> {
        Some(self.params.m * self.params.g * (q[0] - self.params.r))
    }
    fn constant_mass_matrix(&self) -> bool {
        true
    }
}
