//! The woodpecker toy (docs/theory.md §7.2): a sleeve on a pole with a bird on a torsion spring,
//! q = (y, φ_M, φ_S), three frictional contacts, small-angle model.

use moreau_kinematics::{ContactKinematics, ContactPoint};
use moreau_setvalued::ContactLaw;
use moreau_stepper::Mechanism;
use serde::{Deserialize, Serialize};

use crate::ModelError;
use crate::draw::{Drawing, Role};
use crate::params::{LawParams, all_finite, positive, relation};

fn enabled() -> bool {
    true
}

/// Parameters of the woodpecker toy (the report's Table 8.3 in [`WoodpeckerParams::report`]).
///
/// Geometry (all in m): the pole has radius r_O, the sleeve's bore radius r_M, and its edges
/// lie h_M above and below its centre; the bird's hinge lies l_M to the right of the sleeve's
/// centre, its centre of mass l_G further along the bird, and its beak tip at
/// (l_G − l_S, h_S) in the bird's frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WoodpeckerParams {
    /// Pole radius r_O (m).
    pub r_o: f64,
    /// Sleeve bore radius r_M (m), > r_O.
    pub r_m: f64,
    /// Half height h_M of the sleeve (m).
    pub h_m: f64,
    /// Distance l_M from the sleeve's centre to the bird's hinge (m).
    pub l_m: f64,
    /// Distance l_G from the hinge to the bird's centre of mass (m).
    pub l_g: f64,
    /// Height h_S of the beak tip above the hinge (m).
    pub h_s: f64,
    /// Horizontal distance l_S from the bird's centre of mass back to the beak tip (m).
    pub l_s: f64,
    /// Sleeve mass m_M (kg).
    pub m_m: f64,
    /// Bird mass m_S (kg).
    pub m_s: f64,
    /// Sleeve moment of inertia J_M about its centre (kg m²).
    pub j_m: f64,
    /// Bird moment of inertia J_S about its centre of mass (kg m²).
    pub j_s: f64,
    /// Torsion spring stiffness c_φ between sleeve and bird (N m/rad).
    pub c_phi: f64,
    /// Gravitational acceleration g (m/s²).
    pub g: f64,
    /// Laws of contact 1, beak against pole.
    pub beak: LawParams,
    /// Laws of contact 2, lower sleeve edge against pole.
    pub lower: LawParams,
    /// Laws of contact 3, upper sleeve edge against pole.
    pub upper: LawParams,
    /// Whether contact 1 (beak) is modelled; default `true`. When `false` the contact is not
    /// listed at all and the LCP shrinks.
    #[serde(default = "enabled")]
    pub beak_contact: bool,
    /// Whether contact 2 (lower sleeve edge) is modelled; default `true`.
    #[serde(default = "enabled")]
    pub lower_contact: bool,
    /// Whether contact 3 (upper sleeve edge) is modelled; default `true`.
    #[serde(default = "enabled")]
    pub upper_contact: bool,
    /// Initial state; the report's when omitted.
    #[serde(default = "WoodpeckerInit::report")]
    pub init: WoodpeckerInit,
}

/// Initial state of the woodpecker.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WoodpeckerInit {
    /// Sleeve height y0 (m).
    pub y: f64,
    /// Sleeve angle φ_M0 (rad).
    pub phi_m: f64,
    /// Bird angle φ_S0 (rad).
    pub phi_s: f64,
    /// Sleeve velocity v0 (m/s).
    pub v: f64,
    /// Sleeve angular velocity ω_M0 (rad/s).
    pub omega_m: f64,
    /// Bird angular velocity ω_S0 (rad/s).
    pub omega_s: f64,
}

impl WoodpeckerInit {
    /// The report's initial state: y = 0, φ_M = −0.1036, φ_S = −0.2788, v = −0.3411,
    /// ω_M = 0, ω_S = −7.4583 (contact 2 closed).
    pub fn report() -> Self {
        Self { y: 0.0, phi_m: -0.1036, phi_s: -0.2788, v: -0.3411, omega_m: 0.0, omega_s: -7.4583 }
    }
}

impl WoodpeckerParams {
    /// The report's Table 8.3.
    pub fn report() -> Self {
        Self {
            r_o: 0.0025,
            r_m: 0.0031,
            h_m: 0.0058,
            l_m: 0.0100,
            l_g: 0.0150,
            h_s: 0.0200,
            l_s: 0.0201,
            m_m: 0.0003,
            m_s: 0.0045,
            j_m: 5.0e-9,
            j_s: 7.0e-7,
            c_phi: 0.0056,
            g: 9.81,
            beak: LawParams::new(0.5, 0.0, 0.3),
            lower: LawParams::new(0.0, 0.0, 0.3),
            upper: LawParams::new(0.0, 0.0, 0.3),
            beak_contact: true,
            lower_contact: true,
            upper_contact: true,
            init: WoodpeckerInit::report(),
        }
    }
}

/// The woodpecker toy as a [`Mechanism`] with the constant mass matrix and the gaps of
/// docs/theory.md §7.2; contacts switched off in the parameters are not listed.
#[derive(Clone, Debug)]
pub struct Woodpecker {
    params: WoodpeckerParams,
    /// Which of the three contacts (0 beak, 1 lower, 2 upper) each listed contact is.
    contacts: Vec<usize>,
    laws: Vec<ContactLaw>,
}

const CONTACT_NAMES: [&str; 3] = ["beak", "lower sleeve edge", "upper sleeve edge"];

impl Woodpecker {
    /// Names of the coordinates q.
    pub const COORDINATES: &'static [&'static str] = &["y", "phiM", "phiS"];
    /// Names of the velocities u.
    pub const VELOCITIES: &'static [&'static str] = &["v", "omegaM", "omegaS"];

    /// Validates the parameters and builds the model.
    ///
    /// # Errors
    /// [`ModelError::InvalidParameter`] naming the field for a non-positive length, mass,
    /// inertia or stiffness, a bore not wider than the pole, a bad law or a non-finite state.
    pub fn new(params: WoodpeckerParams) -> Result<Self, ModelError> {
        let p = &params;
        for (f, v) in [
            ("r_o", p.r_o),
            ("r_m", p.r_m),
            ("h_m", p.h_m),
            ("l_m", p.l_m),
            ("l_g", p.l_g),
            ("h_s", p.h_s),
            ("l_s", p.l_s),
            ("m_m", p.m_m),
            ("m_s", p.m_s),
            ("j_m", p.j_m),
            ("j_s", p.j_s),
            ("c_phi", p.c_phi),
            ("g", p.g),
        ] {
            positive(f, v)?;
        }
        if p.r_m <= p.r_o {
            return Err(relation(
                "r_m",
                p.r_m,
                "the sleeve's bore radius r_m must exceed the pole radius r_o",
            ));
        }
        let i = &p.init;
        all_finite(&[
            ("init.y", i.y),
            ("init.phi_m", i.phi_m),
            ("init.phi_s", i.phi_s),
            ("init.v", i.v),
            ("init.omega_m", i.omega_m),
            ("init.omega_s", i.omega_s),
        ])?;
        let all = [p.beak.law("beak")?, p.lower.law("lower")?, p.upper.law("upper")?];
        let on = [p.beak_contact, p.lower_contact, p.upper_contact];
        let contacts: Vec<usize> = (0..3).filter(|&k| on[k]).collect();
        let laws = contacts.iter().map(|&k| all[k]).collect();
        Ok(Self { params, contacts, laws })
    }

    /// The parameters.
    pub fn params(&self) -> &WoodpeckerParams {
        &self.params
    }

    /// Which contact of the full model (0 beak, 1 lower sleeve edge, 2 upper sleeve edge)
    /// each listed contact is.
    pub fn contact_ids(&self) -> &[usize] {
        &self.contacts
    }

    /// The initial state (q0, u0).
    pub fn initial_state(&self) -> (Vec<f64>, Vec<f64>) {
        let i = &self.params.init;
        (vec![i.y, i.phi_m, i.phi_s], vec![i.v, i.omega_m, i.omega_s])
    }

    /// Names of the listed contacts.
    pub fn contact_names(&self) -> Vec<String> {
        self.contacts.iter().map(|&k| CONTACT_NAMES[k].to_owned()).collect()
    }

    /// A point given in the sleeve's frame (origin at the sleeve's centre), placed with the
    /// model's small-angle rotation, so that drawn contacts close exactly when g_N = 0.
    fn sleeve_point(&self, q: &[f64], p: [f64; 2]) -> [f64; 2] {
        let phi = q[1];
        [p[0] - p[1] * phi, q[0] + p[1] + p[0] * phi]
    }

    /// A point given in the bird's frame (origin at the hinge, x along the bird).
    fn bird_point(&self, q: &[f64], p: [f64; 2]) -> [f64; 2] {
        let hinge = self.sleeve_point(q, [self.params.l_m, 0.0]);
        let phi = q[2];
        [hinge[0] + p[0] - p[1] * phi, hinge[1] + p[1] + p[0] * phi]
    }

    fn full_contact_point(&self, k: usize, q: &[f64]) -> [f64; 2] {
        let p = &self.params;
        match k {
            0 => self.bird_point(q, [p.l_g - p.l_s, p.h_s]),
            1 => self.sleeve_point(q, [p.r_m, -p.h_m]),
            _ => self.sleeve_point(q, [p.r_m, p.h_m]),
        }
    }

    /// Locations of the listed contacts' points on the moving bodies at `q`.
    pub fn contact_points(&self, q: &[f64], _t: f64) -> Vec<[f64; 2]> {
        self.contacts.iter().map(|&k| self.full_contact_point(k, q)).collect()
    }

    /// Draws pole, sleeve, bird body and beak without exaggeration, with the small-angle
    /// rotations of the model; closed contacts are marked.
    pub fn draw(&self, q: &[f64], t: f64) -> Drawing {
        let p = &self.params;
        let mut d = Drawing::new();
        let y = q[0];
        let top = y + 2.5 * p.h_s;
        let bottom = y - 2.5 * p.h_s;
        d.polygon(Role::Pole, vec![[-p.r_o, bottom], [p.r_o, bottom], [p.r_o, top], [-p.r_o, top]]);
        // The sleeve's wall, cut through its axis, on both sides of the pole.
        let wall = 0.4 * p.r_m;
        for side in [-1.0, 1.0] {
            let inner = side * p.r_m;
            let outer = side * (p.r_m + wall);
            let pts = [[inner, -p.h_m], [outer, -p.h_m], [outer, p.h_m], [inner, p.h_m]];
            d.polygon(Role::Sleeve, pts.iter().map(|&v| self.sleeve_point(q, v)).collect());
        }
        let arm = [[p.r_m + wall, 0.0], [p.l_m, 0.0]];
        d.line(Role::Sleeve, arm.iter().map(|&v| self.sleeve_point(q, v)).collect());
        d.circle(Role::Joint, self.sleeve_point(q, [p.l_m, 0.0]), 0.4 * wall);
        // The bird's outline in its own frame, scaled by l_G and h_S.
        let (sx, sy) = (p.l_g / 0.015, p.h_s / 0.02);
        let body: [[f64; 2]; 12] = [
            [0.000, -0.002],
            [0.012, -0.006],
            [0.024, -0.004],
            [0.030, 0.002],
            [0.020, 0.002],
            [0.008, 0.008],
            [0.006, 0.016],
            [0.003, 0.0225],
            [-0.001, 0.0215],
            [-0.0012, 0.0185],
            [0.002, 0.012],
            [0.000, 0.004],
        ];
        d.polygon(
            Role::Bird,
            body.iter().map(|v| self.bird_point(q, [v[0] * sx, v[1] * sy])).collect(),
        );
        let beak = [
            [-0.0012 * sx, p.h_s + 0.0008 * sy],
            [p.l_g - p.l_s, p.h_s],
            [-0.0012 * sx, p.h_s - 0.0012 * sy],
        ];
        d.polygon(Role::Beak, beak.iter().map(|&v| self.bird_point(q, v)).collect());
        for (i, &k) in self.contacts.iter().enumerate() {
            if self.normal_gap(i, q, t) <= 1e-6 * p.r_o {
                d.circle(Role::ContactPoint, self.full_contact_point(k, q), 0.2 * p.r_o);
            }
        }
        d
    }

    fn full_gap(&self, k: usize, q: &[f64]) -> f64 {
        let p = &self.params;
        match k {
            0 => p.l_m + p.l_g - p.l_s - p.r_o - p.h_s * q[2],
            1 => p.r_m - p.r_o + p.h_m * q[1],
            _ => p.r_m - p.r_o - p.h_m * q[1],
        }
    }
}

impl ContactKinematics for Woodpecker {
    fn num_coordinates(&self) -> usize {
        3
    }
    fn num_contacts(&self) -> usize {
        self.contacts.len()
    }
    fn normal_gap(&self, i: usize, q: &[f64], _t: f64) -> f64 {
        self.full_gap(self.contacts[i], q)
    }
    fn contact(
        &self,
        i: usize,
        q: &[f64],
        _t: f64,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) -> ContactPoint {
        let p = &self.params;
        let k = self.contacts[i];
        let (wn, wt, g_t) = match k {
            0 => (
                [0.0, 0.0, -p.h_s],
                [1.0, p.l_m, p.l_g - p.l_s],
                q[0] + p.l_m * q[1] + (p.l_g - p.l_s) * q[2],
            ),
            1 => ([0.0, p.h_m, 0.0], [1.0, p.r_m, 0.0], q[0] + p.r_m * q[1]),
            _ => ([0.0, -p.h_m, 0.0], [1.0, p.r_m, 0.0], q[0] + p.r_m * q[1]),
        };
        w_n[..3].copy_from_slice(&wn);
        w_t[..3].copy_from_slice(&wt);
        ContactPoint { g_n: self.full_gap(k, q), g_t, w_n_hat: 0.0, w_t_hat: 0.0 }
    }
}

impl Mechanism for Woodpecker {
    fn laws(&self) -> &[ContactLaw] {
        &self.laws
    }
    fn mass_matrix(&self, _q: &[f64], _t: f64, m: &mut [f64]) {
        let p = &self.params;
        let m12 = p.m_s * p.l_m;
        let m13 = p.m_s * p.l_g;
        let m23 = p.m_s * p.l_m * p.l_g;
        let full = [
            p.m_s + p.m_m,
            m12,
            m13,
            m12,
            p.j_m + p.m_s * p.l_m * p.l_m,
            m23,
            m13,
            m23,
            p.j_s + p.m_s * p.l_g * p.l_g,
        ];
        m[..9].copy_from_slice(&full);
    }
    fn forces(&self, q: &[f64], _u: &[f64], _t: f64, h: &mut [f64]) {
        let p = &self.params;
        let spring = p.c_phi * (q[1] - q[2]);
        h[0] = -(p.m_s + p.m_m) * p.g;
        h[1] = -spring - p.m_s * p.l_m * p.g;
        h[2] = spring - p.m_s * p.l_g * p.g;
    }
    fn potential_energy(&self, q: &[f64], _t: f64) -> Option<f64> {
        let p = &self.params;
        let d = q[1] - q[2];
        Some(
            (p.m_s + p.m_m) * p.g * q[0]
                + p.m_s * p.g * (p.l_m * q[1] + p.l_g * q[2])
                + 0.5 * p.c_phi * d * d,
        )
    }
    fn constant_mass_matrix(&self) -> bool {
        true
    }
}
