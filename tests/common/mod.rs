//! Mechanisms written for the integration tests, and helpers shared by them.
//!
//! [`Chain`] is a row of balls on a line (Newton's cradle), [`FlatRod`] a rod whose two ends
//! can touch the ground; both exist to put several contacts in one LCP at once.
#![allow(dead_code)]

use moreau::kinematics::{ContactKinematics, ContactPoint};
use moreau::models::AnyModel;
use moreau::setvalued::ContactLaw;
use moreau::stepper::{Mechanism, Record};

/// N balls of radius R on a horizontal line without gravity: q = (x_1, ..., x_N), contact i
/// between balls i and i+1 with g_N,i = x_(i+1) − x_i − 2R, w_N,i = e_(i+1) − e_i, μ = 0.
pub struct Chain {
    /// Masses m_i (kg).
    pub masses: Vec<f64>,
    /// Radius R (m).
    pub radius: f64,
    laws: Vec<ContactLaw>,
}

impl Chain {
    /// A chain with the given masses, radius and one ε_N for every contact.
    pub fn new(masses: Vec<f64>, radius: f64, eps_n: f64) -> Self {
        let laws = vec![ContactLaw::frictionless(eps_n).expect("ε_N in [0, 1]"); masses.len() - 1];
        Self { masses, radius, laws }
    }

    /// A chain with one ε_N per contact.
    pub fn with_laws(masses: Vec<f64>, radius: f64, eps_n: &[f64]) -> Self {
        let laws = eps_n.iter().map(|&e| ContactLaw::frictionless(e).expect("ε_N in [0, 1]"));
        Self { laws: laws.collect(), masses, radius }
    }

    /// Total momentum Σ m_i v_i (kg m/s).
    pub fn momentum(&self, u: &[f64]) -> f64 {
        self.masses.iter().zip(u).map(|(m, v)| m * v).sum()
    }

    /// Kinetic energy Σ m_i v_i² / 2 (J).
    pub fn kinetic(&self, u: &[f64]) -> f64 {
        self.masses.iter().zip(u).map(|(m, v)| 0.5 * m * v * v).sum()
    }
}

impl ContactKinematics for Chain {
    fn num_coordinates(&self) -> usize {
        self.masses.len()
    }
    fn num_contacts(&self) -> usize {
        self.masses.len() - 1
    }
    fn normal_gap(&self, i: usize, q: &[f64], _t: f64) -> f64 {
        q[i + 1] - q[i] - 2.0 * self.radius
    }
    fn contact(
        &self,
        i: usize,
        q: &[f64],
        t: f64,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) -> ContactPoint {
        w_n.fill(0.0);
        w_t.fill(0.0);
        w_n[i] = -1.0;
        w_n[i + 1] = 1.0;
        ContactPoint { g_n: self.normal_gap(i, q, t), ..ContactPoint::default() }
    }
}

impl Mechanism for Chain {
    fn laws(&self) -> &[ContactLaw] {
        &self.laws
    }
    fn mass_matrix(&self, _q: &[f64], _t: f64, m: &mut [f64]) {
        let n = self.masses.len();
        m.fill(0.0);
        for (i, mi) in self.masses.iter().enumerate() {
            m[i + i * n] = *mi;
        }
    }
    fn forces(&self, _q: &[f64], _u: &[f64], _t: f64, h: &mut [f64]) {
        h.fill(0.0);
    }
    fn potential_energy(&self, _q: &[f64], _t: f64) -> Option<f64> {
        Some(0.0)
    }
    fn constant_mass_matrix(&self) -> bool {
        true
    }
}

/// A rod of length 2s, mass m and J = m s²/3 whose two ends can touch the ground y = 0:
/// q = (x, y, φ), end 1 at (x − s cos φ, y − s sin φ), end 2 at (x + s cos φ, y + s sin φ).
pub struct FlatRod {
    /// Mass m (kg).
    pub m: f64,
    /// Half length s (m).
    pub s: f64,
    /// Gravity g (m/s²).
    pub g: f64,
    laws: [ContactLaw; 2],
}

impl FlatRod {
    /// A rod with both ends under the same law (ε_N, μ; ε_T = 0).
    pub fn new(m: f64, s: f64, g: f64, eps_n: f64, mu: f64) -> Self {
        let law = ContactLaw::new(eps_n, 0.0, mu).expect("valid law");
        Self { m, s, g, laws: [law, law] }
    }

    /// Total energy m (v_x² + v_y²)/2 + J ω²/2 + m g y (J).
    pub fn energy(&self, q: &[f64], u: &[f64]) -> f64 {
        let j = self.m * self.s * self.s / 3.0;
        0.5 * self.m * (u[0] * u[0] + u[1] * u[1]) + 0.5 * j * u[2] * u[2] + self.m * self.g * q[1]
    }
}

impl ContactKinematics for FlatRod {
    fn num_coordinates(&self) -> usize {
        3
    }
    fn num_contacts(&self) -> usize {
        2
    }
    fn normal_gap(&self, i: usize, q: &[f64], _t: f64) -> f64 {
        let sign = if i == 0 { -1.0 } else { 1.0 };
        q[1] + sign * self.s * q[2].sin()
    }
    fn contact(
        &self,
        i: usize,
        q: &[f64],
        t: f64,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) -> ContactPoint {
        let sign = if i == 0 { -1.0 } else { 1.0 };
        let (sp, cp) = q[2].sin_cos();
        w_n.copy_from_slice(&[0.0, 1.0, sign * self.s * cp]);
        w_t.copy_from_slice(&[1.0, 0.0, -sign * self.s * sp]);
        ContactPoint {
            g_n: self.normal_gap(i, q, t),
            g_t: q[0] + sign * self.s * cp,
            ..ContactPoint::default()
        }
    }
}

impl Mechanism for FlatRod {
    fn laws(&self) -> &[ContactLaw] {
        &self.laws
    }
    fn mass_matrix(&self, _q: &[f64], _t: f64, m: &mut [f64]) {
        m.fill(0.0);
        m[0] = self.m;
        m[4] = self.m;
        m[8] = self.m * self.s * self.s / 3.0;
    }
    fn forces(&self, _q: &[f64], _u: &[f64], _t: f64, h: &mut [f64]) {
        h.copy_from_slice(&[0.0, -self.m * self.g, 0.0]);
    }
    fn potential_energy(&self, q: &[f64], _t: f64) -> Option<f64> {
        Some(self.m * self.g * q[1])
    }
    fn constant_mass_matrix(&self) -> bool {
        true
    }
}

/// Whether every number of a record (state, impulses, energies) is finite.
pub fn record_is_finite(r: &Record) -> bool {
    let rows = r.q.iter().chain(&r.u).chain(&r.p_n).chain(&r.p_t);
    rows.flatten().all(|x| x.is_finite())
        && r.kinetic
            .iter()
            .chain(&r.potential)
            .chain(&r.cumulative_dissipation)
            .all(|x| x.is_finite())
}

/// Largest penetration max(0, −g_N) over every contact and row of a record (m).
pub fn deepest_penetration(model: &AnyModel, r: &Record) -> f64 {
    let mut pen = 0.0f64;
    for k in 0..r.len() {
        for i in 0..model.num_contacts() {
            pen = pen.max(-model.normal_gap(i, &r.q[k], r.t[k]));
        }
    }
    pen
}

/// Largest increase of the total energy over its initial value, max_k (E_k − E_0) (J).
pub fn energy_gain(r: &Record) -> f64 {
    let e = r.total_energy();
    e.iter().map(|x| x - e[0]).fold(f64::NEG_INFINITY, f64::max)
}

/// Prints one row of the results table of docs/extremes.md (pipes inside cells escaped).
pub fn row(case: &str, outcome: &str, number: &str) {
    let cell = |s: &str| s.replace('|', "\\|");
    println!("| {} | {} | {} |", cell(case), cell(outcome), cell(number));
}
