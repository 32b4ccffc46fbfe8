//! Small mechanisms with closed-form answers, shared by the stepper's tests.
#![allow(dead_code)]

use moreau_kinematics::{ContactKinematics, ContactPoint};
use moreau_setvalued::ContactLaw;
use moreau_stepper::Mechanism;

/// Gravity (m/s²).
pub const G: f64 = 9.81;

/// A ball of mass m, radius r above a floor at height A sin(Ω t): q = (y).
#[derive(Clone, Debug)]
pub struct Ball {
    pub m: f64,
    pub r: f64,
    pub amplitude: f64,
    pub omega: f64,
    pub laws: Vec<ContactLaw>,
}

impl Ball {
    pub fn new(eps_n: f64) -> Self {
        Self {
            m: 1.0,
            r: 0.1,
            amplitude: 0.0,
            omega: 0.0,
            laws: vec![ContactLaw::frictionless(eps_n).unwrap()],
        }
    }
    pub fn floor(&self, t: f64) -> (f64, f64) {
        let (s, c) = (self.omega * t).sin_cos();
        (self.amplitude * s, self.amplitude * self.omega * c)
    }
}

impl ContactKinematics for Ball {
    fn num_coordinates(&self) -> usize {
        1
    }
    fn num_contacts(&self) -> usize {
        1
    }
    fn normal_gap(&self, _i: usize, q: &[f64], t: f64) -> f64 {
        q[0] - self.r - self.floor(t).0
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
            w_n_hat: -self.floor(t).1,
            w_t_hat: 0.0,
        }
    }
}

impl Mechanism for Ball {
    fn laws(&self) -> &[ContactLaw] {
        &self.laws
    }
    fn mass_matrix(&self, _q: &[f64], _t: f64, m: &mut [f64]) {
        m[0] = self.m;
    }
    fn forces(&self, _q: &[f64], _u: &[f64], _t: f64, h: &mut [f64]) {
        h[0] = -self.m * G;
    }
    fn potential_energy(&self, q: &[f64], _t: f64) -> Option<f64> {
        Some(self.m * G * (q[0] - self.r))
    }
    fn constant_mass_matrix(&self) -> bool {
        true
    }
}

/// A point mass (a block whose rotation is irrelevant) on a plane through the origin
/// inclined by α, in world coordinates q = (x, y), gravity along −y.
#[derive(Clone, Debug)]
pub struct Block {
    pub m: f64,
    pub alpha: f64,
    pub laws: Vec<ContactLaw>,
}

impl Block {
    pub fn new(alpha: f64, mu: f64) -> Self {
        Self { m: 2.0, alpha, laws: vec![ContactLaw::new(0.0, 0.0, mu).unwrap()] }
    }
}

impl ContactKinematics for Block {
    fn num_coordinates(&self) -> usize {
        2
    }
    fn num_contacts(&self) -> usize {
        1
    }
    fn normal_gap(&self, _i: usize, q: &[f64], _t: f64) -> f64 {
        let (s, c) = self.alpha.sin_cos();
        -q[0] * s + q[1] * c
    }
    fn contact(
        &self,
        i: usize,
        q: &[f64],
        t: f64,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) -> ContactPoint {
        let (s, c) = self.alpha.sin_cos();
        w_n.copy_from_slice(&[-s, c]);
        w_t.copy_from_slice(&[c, s]);
        ContactPoint {
            g_n: self.normal_gap(i, q, t),
            g_t: q[0] * c + q[1] * s,
            w_n_hat: 0.0,
            w_t_hat: 0.0,
        }
    }
}

impl Mechanism for Block {
    fn laws(&self) -> &[ContactLaw] {
        &self.laws
    }
    fn mass_matrix(&self, _q: &[f64], _t: f64, m: &mut [f64]) {
        m.copy_from_slice(&[self.m, 0.0, 0.0, self.m]);
    }
    fn forces(&self, _q: &[f64], _u: &[f64], _t: f64, h: &mut [f64]) {
        h.copy_from_slice(&[0.0, -self.m * G]);
    }
    fn potential_energy(&self, q: &[f64], _t: f64) -> Option<f64> {
        Some(self.m * G * q[1])
    }
}

/// A rod of half-length s, mass m, centre (x, y), angle φ, with both ends able to touch the
/// floor y = 0: q = (x, y, φ). Contacts: 0 = end at −s, 1 = end at +s.
#[derive(Clone, Debug)]
pub struct Rod {
    pub m: f64,
    pub s: f64,
    pub laws: Vec<ContactLaw>,
}

impl Rod {
    pub fn new(eps_n: f64, mu: f64) -> Self {
        let law = ContactLaw::new(eps_n, 0.0, mu).unwrap();
        Self { m: 1.0, s: 0.5, laws: vec![law, law] }
    }
    fn side(i: usize) -> f64 {
        if i == 0 { -1.0 } else { 1.0 }
    }
    /// The gap of end i from `sn` = sin φ.
    pub fn gap(&self, i: usize, q: &[f64], sn: f64) -> f64 {
        q[1] + Self::side(i) * self.s * sn
    }
    /// End i's kinematics from `(sn, cs)` = (sin φ, cos φ).
    pub fn end(
        &self,
        i: usize,
        q: &[f64],
        (sn, cs): (f64, f64),
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) -> ContactPoint {
        let k = Self::side(i) * self.s;
        w_n.copy_from_slice(&[0.0, 1.0, k * cs]);
        w_t.copy_from_slice(&[1.0, 0.0, -k * sn]);
        ContactPoint { g_n: self.gap(i, q, sn), g_t: q[0] + k * cs, w_n_hat: 0.0, w_t_hat: 0.0 }
    }
}

impl ContactKinematics for Rod {
    fn num_coordinates(&self) -> usize {
        3
    }
    fn num_contacts(&self) -> usize {
        2
    }
    fn normal_gap(&self, i: usize, q: &[f64], _t: f64) -> f64 {
        self.gap(i, q, q[2].sin())
    }
    fn contact(
        &self,
        i: usize,
        q: &[f64],
        _t: f64,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) -> ContactPoint {
        self.end(i, q, q[2].sin_cos(), w_n, w_t)
    }
}

impl Mechanism for Rod {
    fn laws(&self) -> &[ContactLaw] {
        &self.laws
    }
    fn mass_matrix(&self, _q: &[f64], _t: f64, m: &mut [f64]) {
        let j = self.m * self.s * self.s / 3.0;
        m.copy_from_slice(&[self.m, 0.0, 0.0, 0.0, self.m, 0.0, 0.0, 0.0, j]);
    }
    fn forces(&self, _q: &[f64], _u: &[f64], _t: f64, h: &mut [f64]) {
        h.copy_from_slice(&[0.0, -self.m * G, 0.0]);
    }
    fn potential_energy(&self, q: &[f64], _t: f64) -> Option<f64> {
        Some(self.m * G * q[1])
    }
    fn constant_mass_matrix(&self) -> bool {
        true
    }
}
