//! The ideal slider-crank (no clearance, docs/theory.md §7.3 "Ideal joint"): one coordinate θ1,
//! no contacts, with the reduced mass M_r(θ1) = M11 + 2 M12 k + M22 k².

use moreau_kinematics::{ContactKinematics, ContactPoint};
use moreau_setvalued::ContactLaw;
use moreau_stepper::Mechanism;
use serde::{Deserialize, Serialize};

use crate::ModelError;
use crate::draw::{Drawing, Role};
use crate::params::{all_finite, positive, relation};

/// Parameters of the ideal slider-crank: the bodies of [`crate::SliderCrankParams`] with the
/// slider held on the line y3 = 0 and θ3 = 0.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SliderCrankIdealParams {
    /// Crank length l1 (m), < l2.
    pub l1: f64,
    /// Connecting-rod length l2 (m).
    pub l2: f64,
    /// Half length a of the slider (m); only drawn.
    pub a: f64,
    /// Half height b of the slider (m); only drawn.
    pub b: f64,
    /// Crank mass m1 (kg).
    pub m1: f64,
    /// Connecting-rod mass m2 (kg).
    pub m2: f64,
    /// Slider mass m3 (kg).
    pub m3: f64,
    /// Crank moment of inertia J1 (kg m²).
    pub j1: f64,
    /// Connecting-rod moment of inertia J2 (kg m²).
    pub j2: f64,
    /// Gravitational acceleration g (m/s²).
    pub g: f64,
    /// Initial state; the report's (θ1 = 0, ω1 = 150 rad/s) when omitted.
    #[serde(default = "SliderCrankIdealInit::report")]
    pub init: SliderCrankIdealInit,
}

/// Initial state of the ideal slider-crank.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SliderCrankIdealInit {
    /// Crank angle θ1 (rad).
    pub th1: f64,
    /// Crank speed ω1 (rad/s).
    pub w1: f64,
}

impl SliderCrankIdealInit {
    /// The report's initial state: θ1 = 0, ω1 = 150 rad/s.
    pub fn report() -> Self {
        Self { th1: 0.0, w1: 150.0 }
    }
}

impl SliderCrankIdealParams {
    /// The bodies of the report's Table 8.4.
    pub fn report() -> Self {
        crate::SliderCrankParams::report().ideal()
    }
}

/// The ideal slider-crank as a [`Mechanism`] with one coordinate θ1 and no contacts.
///
/// With ρ = l1/l2, the rod angle follows from sin θ2 = −ρ sin θ1 (cos θ2 > 0) and
/// k = dθ2/dθ1 = −l1 cos θ1/(l2 cos θ2). Then M = (M_r(θ1)) with
/// M_r = M11 + 2 M12 k + M22 k², and h = −½ dM_r/dθ1 ω1² − dV/dθ1, so that
/// E = ½ M_r ω1² + V(θ1) is conserved.
#[derive(Clone, Debug)]
pub struct SliderCrankIdeal {
    params: SliderCrankIdealParams,
}

/// The reduced quantities at one crank angle.
struct Reduced {
    mass: f64,
    dmass: f64,
    dpotential: f64,
}

impl SliderCrankIdeal {
    /// Names of the coordinates q.
    pub const COORDINATES: &'static [&'static str] = &["th1"];
    /// Names of the velocities u.
    pub const VELOCITIES: &'static [&'static str] = &["w1"];

    /// Validates the parameters and builds the model.
    ///
    /// # Errors
    /// [`ModelError::InvalidParameter`] naming the field for a non-positive length, mass or
    /// inertia, a crank not shorter than the rod, or a non-finite initial state.
    pub fn new(params: SliderCrankIdealParams) -> Result<Self, ModelError> {
        let p = &params;
        for (f, v) in [
            ("l1", p.l1),
            ("l2", p.l2),
            ("a", p.a),
            ("b", p.b),
            ("m1", p.m1),
            ("m2", p.m2),
            ("m3", p.m3),
            ("j1", p.j1),
            ("j2", p.j2),
            ("g", p.g),
        ] {
            positive(f, v)?;
        }
        if p.l1 >= p.l2 {
            return Err(relation(
                "l1",
                p.l1,
                "the crank l1 must be shorter than the connecting rod l2",
            ));
        }
        all_finite(&[("init.th1", p.init.th1), ("init.w1", p.init.w1)])?;
        Ok(Self { params })
    }

    /// The parameters.
    pub fn params(&self) -> &SliderCrankIdealParams {
        &self.params
    }

    /// The initial state (q0, u0).
    pub fn initial_state(&self) -> (Vec<f64>, Vec<f64>) {
        (vec![self.params.init.th1], vec![self.params.init.w1])
    }

    /// Rod angle θ2(θ1) = −asin((l1/l2) sin θ1) (rad).
    pub fn rod_angle(&self, th1: f64) -> f64 {
        (-(self.params.l1 / self.params.l2) * th1.sin()).asin()
    }

    /// k = dθ2/dθ1 = −l1 cos θ1 / (l2 cos θ2).
    pub fn rod_ratio(&self, th1: f64) -> f64 {
        -self.params.l1 * th1.cos() / (self.params.l2 * self.rod_angle(th1).cos())
    }

    /// Rod speed ω2 = k ω1 (rad/s).
    pub fn rod_speed(&self, th1: f64, w1: f64) -> f64 {
        self.rod_ratio(th1) * w1
    }

    /// Reduced mass M_r(θ1) = M11 + 2 M12 k + M22 k² (kg m²).
    pub fn reduced_mass(&self, th1: f64) -> f64 {
        self.reduced(th1).mass
    }

    /// Its derivative dM_r/dθ1 (kg m²/rad), analytic.
    pub fn reduced_mass_derivative(&self, th1: f64) -> f64 {
        self.reduced(th1).dmass
    }

    /// Potential V(θ1) = (m1/2 + m2 + m3) g l1 sin θ1 + (m2/2 + m3) g l2 sin θ2 (J).
    pub fn potential(&self, th1: f64) -> f64 {
        let p = &self.params;
        let th2 = self.rod_angle(th1);
        (0.5 * p.m1 + p.m2 + p.m3) * p.g * p.l1 * th1.sin()
            + (0.5 * p.m2 + p.m3) * p.g * p.l2 * th2.sin()
    }

    /// Its derivative dV/dθ1 (J/rad), analytic.
    pub fn potential_derivative(&self, th1: f64) -> f64 {
        self.reduced(th1).dpotential
    }

    /// Energy E = ½ M_r ω1² + V(θ1) (J).
    pub fn energy(&self, th1: f64, w1: f64) -> f64 {
        0.5 * self.reduced_mass(th1) * w1 * w1 + self.potential(th1)
    }

    fn reduced(&self, th1: f64) -> Reduced {
        let p = &self.params;
        let rho = p.l1 / p.l2;
        let (s1, c1) = th1.sin_cos();
        let s2 = -rho * s1;
        let c2 = (1.0 - s2 * s2).sqrt();
        let th2 = s2.asin();
        let k = -rho * c1 / c2;
        // d(cos θ2)/dθ1 = −sin θ2 k, so dk/dθ1 = ρ (sin θ1 cos θ2 − cos θ1 sin θ2 k)/cos² θ2.
        let dk = rho * (s1 * c2 - c1 * s2 * k) / (c2 * c2);
        let m11 = p.j1 + (0.25 * p.m1 + p.m2 + p.m3) * p.l1 * p.l1;
        let big_a = (0.5 * p.m2 + p.m3) * p.l1 * p.l2;
        let m12 = big_a * (th2 - th1).cos();
        let dm12 = -big_a * (th2 - th1).sin() * (k - 1.0);
        let m22 = p.j2 + (0.25 * p.m2 + p.m3) * p.l2 * p.l2;
        let mass = m11 + 2.0 * m12 * k + m22 * k * k;
        let dmass = 2.0 * dm12 * k + 2.0 * m12 * dk + 2.0 * m22 * k * dk;
        let dpotential = (0.5 * p.m1 + p.m2 + p.m3) * p.g * p.l1 * c1
            + (0.5 * p.m2 + p.m3) * p.g * p.l2 * c2 * k;
        Reduced { mass, dmass, dpotential }
    }

    /// Names of the contacts (none).
    pub fn contact_names(&self) -> Vec<String> {
        Vec::new()
    }

    /// Draws crank, rod and slider on the line y = 0 (the slider as a 2a × 2b rectangle).
    pub fn draw(&self, q: &[f64], _t: f64) -> Drawing {
        let p = &self.params;
        let mut d = Drawing::new();
        let th1 = q[0];
        let tip = [p.l1 * th1.cos(), p.l1 * th1.sin()];
        let x3 = tip[0] + p.l2 * self.rod_angle(th1).cos();
        let (x0, x1) = (p.l2 - p.l1 - 2.0 * p.a, p.l2 + p.l1 + 2.0 * p.a);
        d.line(Role::Guide, vec![[x0, p.b], [x1, p.b]]);
        d.line(Role::Guide, vec![[x0, -p.b], [x1, -p.b]]);
        d.line(Role::Crank, vec![[0.0, 0.0], tip]);
        d.line(Role::Rod, vec![tip, [x3, 0.0]]);
        d.polygon(
            Role::Slider,
            vec![[x3 - p.a, -p.b], [x3 + p.a, -p.b], [x3 + p.a, p.b], [x3 - p.a, p.b]],
        );
        let r = 0.04 * p.l1;
        d.circle(Role::Ground, [0.0, 0.0], r);
        d.circle(Role::Joint, tip, r);
        d.circle(Role::Joint, [x3, 0.0], r);
        d
    }
}

impl ContactKinematics for SliderCrankIdeal {
    fn num_coordinates(&self) -> usize {
        1
    }
    fn num_contacts(&self) -> usize {
        0
    }
    fn normal_gap(&self, _i: usize, _q: &[f64], _t: f64) -> f64 {
        f64::INFINITY
    }
    fn contact(
        &self,
        _i: usize,
        _q: &[f64],
        _t: f64,
        _w_n: &mut [f64],
        _w_t: &mut [f64],
    ) -> ContactPoint {
        ContactPoint { g_n: f64::INFINITY, ..ContactPoint::default() }
    }
}

impl Mechanism for SliderCrankIdeal {
    fn laws(&self) -> &[ContactLaw] {
        &[]
    }
    fn mass_matrix(&self, q: &[f64], _t: f64, m: &mut [f64]) {
        m[0] = self.reduced_mass(q[0]);
    }
    fn forces(&self, q: &[f64], u: &[f64], _t: f64, h: &mut [f64]) {
        let r = self.reduced(q[0]);
        h[0] = -0.5 * r.dmass * u[0] * u[0] - r.dpotential;
    }
    fn potential_energy(&self, q: &[f64], _t: f64) -> Option<f64> {
        Some(self.potential(q[0]))
    }
}
