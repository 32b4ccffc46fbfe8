//! Small mechanisms with closed-form answers: a ball over a moving floor, a block on an
//! incline, a rod with two ends on the ground and a chain of balls on a line.

use moreau_kinematics::{ContactKinematics, ContactPoint};
use moreau_setvalued::ContactLaw;
use moreau_stepper::Mechanism;

/// Gravity g (m/s²) of the test mechanisms.
pub const G: f64 = 9.81;

/// A ball of mass m and radius r above a floor at height A sin(Ω t): q = (y), one contact
/// with g_N = y − r − A sin(Ω t) and ŵ_N = −A Ω cos(Ω t).
#[derive(Clone, Debug)]
pub struct Ball {
    /// Mass m (kg).
    pub m: f64,
    /// Radius r (m).
    pub r: f64,
    /// Amplitude A of the floor's motion (m).
    pub amplitude: f64,
    /// Angular frequency Ω of the floor's motion (rad/s).
    pub omega: f64,
    /// The contact's law.
    pub laws: Vec<ContactLaw>,
}

impl Ball {
    /// A ball of 1 kg and radius 0.1 m over a still floor y = 0, without friction, with
    /// Newton's restitution coefficient `eps_n`.
    ///
    /// # Panics
    /// If `eps_n` is not in [0, 1].
    pub fn new(eps_n: f64) -> Self {
        Self {
            m: 1.0,
            r: 0.1,
            amplitude: 0.0,
            omega: 0.0,
            laws: vec![ContactLaw::frictionless(eps_n).expect("ε_N in [0, 1]")],
        }
    }

    /// The floor's height and vertical velocity at time t.
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

/// A point mass (a block whose rotation plays no part) on a plane through the origin
/// inclined by α, in world coordinates q = (x, y) with gravity along −y; one contact with
/// g_N = −x sin α + y cos α and g_T = x cos α + y sin α (along the slope, upwards).
#[derive(Clone, Debug)]
pub struct Block {
    /// Mass m (kg).
    pub m: f64,
    /// Inclination α of the plane (rad).
    pub alpha: f64,
    /// The contact's law.
    pub laws: Vec<ContactLaw>,
}

impl Block {
    /// A block of 2 kg on a plane inclined by `alpha` with friction coefficient `mu` and no
    /// restitution.
    ///
    /// # Panics
    /// If `mu` is negative or not finite.
    pub fn new(alpha: f64, mu: f64) -> Self {
        Self { m: 2.0, alpha, laws: vec![ContactLaw::new(0.0, 0.0, mu).expect("μ ≥ 0")] }
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

/// A rod of half-length s, mass m and moment of inertia J = m s²/3 about its centre (x, y),
/// at angle φ, whose two ends can touch the ground y = 0: q = (x, y, φ). Contact 0 is the
/// end at (x − s cos φ, y − s sin φ), contact 1 the end at (x + s cos φ, y + s sin φ).
#[derive(Clone, Debug)]
pub struct Rod {
    /// Mass m (kg).
    pub m: f64,
    /// Half-length s (m).
    pub s: f64,
    /// Gravity g (m/s²).
    pub g: f64,
    /// The two ends' laws.
    pub laws: Vec<ContactLaw>,
}

impl Rod {
    /// A rod of 1 kg and half-length 0.5 m under gravity [`G`], both ends under the law
    /// (ε_N = `eps_n`, ε_T = 0, μ = `mu`).
    ///
    /// # Panics
    /// If the law is invalid.
    pub fn new(eps_n: f64, mu: f64) -> Self {
        Self::with(1.0, 0.5, G, eps_n, mu)
    }

    /// A rod of mass `m`, half-length `s` under gravity `g`, both ends under the law
    /// (ε_N = `eps_n`, ε_T = 0, μ = `mu`).
    ///
    /// # Panics
    /// If the law is invalid.
    pub fn with(m: f64, s: f64, g: f64, eps_n: f64, mu: f64) -> Self {
        let law = ContactLaw::new(eps_n, 0.0, mu).expect("valid law");
        Self { m, s, g, laws: vec![law, law] }
    }

    /// The sign of end i's offset along the rod: −1 for end 0, +1 for end 1.
    fn side(i: usize) -> f64 {
        if i == 0 { -1.0 } else { 1.0 }
    }

    /// The gap of end i, given `sn` = sin φ (so that callers can share it between ends).
    pub fn gap(&self, i: usize, q: &[f64], sn: f64) -> f64 {
        q[1] + Self::side(i) * self.s * sn
    }

    /// End i's kinematics, given `(sn, cs)` = (sin φ, cos φ).
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

    /// Total energy m (v_x² + v_y²)/2 + J ω²/2 + m g y (J).
    pub fn energy(&self, q: &[f64], u: &[f64]) -> f64 {
        let j = self.m * self.s * self.s / 3.0;
        0.5 * self.m * (u[0] * u[0] + u[1] * u[1]) + 0.5 * j * u[2] * u[2] + self.m * self.g * q[1]
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
        h.copy_from_slice(&[0.0, -self.m * self.g, 0.0]);
    }
    fn potential_energy(&self, q: &[f64], _t: f64) -> Option<f64> {
        Some(self.m * self.g * q[1])
    }
    fn constant_mass_matrix(&self) -> bool {
        true
    }
}

/// N balls of radius R on a horizontal line without gravity (Newton's cradle):
/// q = (x_1, ..., x_N); contact i lies between balls i and i+1, with
/// g_N,i = x_(i+1) − x_i − 2R, w_N,i = e_(i+1) − e_i and μ = 0.
#[derive(Clone, Debug)]
pub struct Chain {
    /// Masses m_i (kg).
    pub masses: Vec<f64>,
    /// Radius R (m).
    pub radius: f64,
    /// The N − 1 contacts' laws.
    pub laws: Vec<ContactLaw>,
}

impl Chain {
    /// A chain with the given masses (at least two), radius and one ε_N for every contact.
    ///
    /// # Panics
    /// If there are fewer than two masses or `eps_n` is not in [0, 1].
    pub fn new(masses: Vec<f64>, radius: f64, eps_n: f64) -> Self {
        assert!(masses.len() >= 2, "a chain has at least two balls");
        let laws = vec![ContactLaw::frictionless(eps_n).expect("ε_N in [0, 1]"); masses.len() - 1];
        Self { masses, radius, laws }
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

#[cfg(test)]
mod tests {
    use super::*;
    use moreau_kinematics::{SampleOptions, assert_consistent, sample_states};

    /// Every mechanism's hand-written w_N, w_T, ŵ_N, ŵ_T match finite differences of its
    /// gaps at seeded states, so the tests built on them start from correct kinematics.
    #[test]
    fn jacobians_match_finite_differences() {
        let options = |count| SampleOptions { count, q_radius: 0.3, t_radius: 0.2, seed: 5 };
        let mut ball = Ball::new(0.5);
        (ball.amplitude, ball.omega) = (0.05, 20.0);
        assert_consistent(&ball, &sample_states(&[0.3], 0.1, options(8)).unwrap(), 1e-7).unwrap();
        let block = Block::new(0.4, 0.3);
        assert_consistent(&block, &sample_states(&[0.2, 0.1], 0.0, options(8)).unwrap(), 1e-7)
            .unwrap();
        let rod = Rod::new(0.5, 0.3);
        let states = sample_states(&[0.1, 0.2, 0.7], 0.0, options(8)).unwrap();
        assert_consistent(&rod, &states, 1e-7).unwrap();
        let chain = Chain::new(vec![1.0, 2.0, 3.0], 0.5, 1.0);
        let states = sample_states(&[0.0, 1.0, 2.0], 0.0, options(8)).unwrap();
        assert_consistent(&chain, &states, 1e-7).unwrap();
    }

    #[test]
    fn closed_forms_of_gaps_masses_and_energies() {
        let mut ball = Ball::new(0.0);
        (ball.amplitude, ball.omega) = (0.05, 20.0);
        let t = 0.1;
        assert_eq!(ball.normal_gap(0, &[1.0], t), 1.0 - 0.1 - 0.05 * (2.0f64).sin());
        // The rod lying at φ = π/2 stands on end 0 at height y − s.
        let rod = Rod::new(0.0, 0.0);
        let q = [0.0, 0.7, std::f64::consts::FRAC_PI_2];
        assert!((rod.normal_gap(0, &q, 0.0) - 0.2).abs() < 1e-15);
        assert!((rod.normal_gap(1, &q, 0.0) - 1.2).abs() < 1e-15);
        let mut m = [0.0; 9];
        rod.mass_matrix(&q, 0.0, &mut m);
        assert_eq!(m[8], 0.25 / 3.0);
        let u = [1.0, 2.0, 3.0];
        assert!((rod.energy(&q, &u) - (2.5 + 0.375 + 0.7 * G)).abs() < 1e-14);
        let chain = Chain::new(vec![1.0, 3.0], 0.5, 1.0);
        assert_eq!(chain.normal_gap(0, &[0.0, 1.5], 0.0), 0.5);
        assert_eq!(chain.momentum(&[2.0, -1.0]), -1.0);
        assert_eq!(chain.kinetic(&[2.0, -1.0]), 3.5);
        let block = Block::new(0.3, 0.2);
        // A point on the incline's surface has no gap; one above it, its height times cos α.
        assert!(block.normal_gap(0, &[1.0, 0.3f64.tan()], 0.0).abs() < 1e-15);
        assert!((block.normal_gap(0, &[0.0, 1.0], 0.0) - 0.3f64.cos()).abs() < 1e-15);
    }
}
