//! A rectangular box on an inclined plane: three coordinates, four frictional corners.
//!
//! The box (mass m, width 2a, height 2b) moves in the plane of an incline of angle α. Its
//! pose is described in the incline's frame, x down the slope and y along the incline's
//! normal, so the incline is the line y = 0 and gravity has the components
//! (m g sin α, −m g cos α). q = (x, y, θ) is the centre's position and the box's angle,
//! u = (ẋ, ẏ, θ̇).
//!
//! Each corner k, at (c_x, c_y) = (±a, ±b) in the box's frame, is a contact with the incline:
//!
//! ```text
//! g_N = y + c_x sin θ + c_y cos θ           w_N = (0, 1,  c_x cos θ − c_y sin θ)ᵀ
//! g_T = x + c_x cos θ − c_y sin θ           w_T = (1, 0, −c_x sin θ − c_y cos θ)ᵀ
//! ```
//!
//! with the tangent pointing down the slope and no rheonomic terms (ŵ = 0).

use moreau::kinematics::{ContactKinematics, ContactPoint};
use moreau::setvalued::ContactLaw;
use moreau::stepper::Mechanism;

/// Gravitational acceleration g (m/s²).
pub const G: f64 = 9.81;

/// The corners in the box's frame, as multiples of (a, b): bottom left, bottom right, top
/// right, top left when θ = 0.
const CORNERS: [(f64, f64); 4] = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];

/// A box of mass m, width 2a and height 2b on an incline of angle α, with Coulomb friction μ
/// and restitution ε_N at each corner.
#[derive(Clone, Debug)]
pub struct BoxOnIncline {
    /// Mass m (kg).
    pub m: f64,
    /// Half-width a (m).
    pub a: f64,
    /// Half-height b (m).
    pub b: f64,
    /// Angle α of the incline (rad).
    pub alpha: f64,
    laws: [ContactLaw; 4],
}

impl BoxOnIncline {
    /// A box with the given dimensions, slope and contact law (the same at every corner).
    ///
    /// # Errors
    /// When m, a or b is not finite and positive, α is outside [0, π/2), or (ε_N, μ) is not
    /// a valid contact law.
    pub fn new(
        m: f64,
        a: f64,
        b: f64,
        alpha: f64,
        mu: f64,
        eps_n: f64,
    ) -> Result<Self, Box<dyn std::error::Error>> {
        for (name, value) in [("m", m), ("a", a), ("b", b)] {
            if !(value > 0.0 && value.is_finite()) {
                return Err(format!("{name} must be finite and positive, got {value}").into());
            }
        }
        if !(0.0..std::f64::consts::FRAC_PI_2).contains(&alpha) {
            return Err(format!("the slope α must be in [0, π/2), got {alpha}").into());
        }
        let law = ContactLaw::new(eps_n, 0.0, mu)?;
        Ok(Self { m, a, b, alpha, laws: [law; 4] })
    }

    /// Moment of inertia about the centre, J = m (a² + b²)/3 (kg m²).
    pub fn inertia(&self) -> f64 {
        self.m * (self.a * self.a + self.b * self.b) / 3.0
    }

    /// The corner k in the box's frame (m).
    fn corner(&self, k: usize) -> (f64, f64) {
        let (sx, sy) = CORNERS[k];
        (sx * self.a, sy * self.b)
    }

    /// The acceleration down the slope of the box sliding flat on its bottom face,
    /// g (sin α − μ cos α), when that is positive (m/s²).
    pub fn sliding_acceleration(&self) -> f64 {
        let mu = self.laws[0].mu();
        G * (self.alpha.sin() - mu * self.alpha.cos())
    }
}

impl ContactKinematics for BoxOnIncline {
    fn num_coordinates(&self) -> usize {
        3
    }

    fn num_contacts(&self) -> usize {
        4
    }

    fn normal_gap(&self, i: usize, q: &[f64], _t: f64) -> f64 {
        let (cx, cy) = self.corner(i);
        let (s, c) = q[2].sin_cos();
        q[1] + cx * s + cy * c
    }

    fn contact(
        &self,
        i: usize,
        q: &[f64],
        t: f64,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) -> ContactPoint {
        let (cx, cy) = self.corner(i);
        let (s, c) = q[2].sin_cos();
        w_n.copy_from_slice(&[0.0, 1.0, cx * c - cy * s]);
        w_t.copy_from_slice(&[1.0, 0.0, -cx * s - cy * c]);
        ContactPoint {
            g_n: self.normal_gap(i, q, t),
            g_t: q[0] + cx * c - cy * s,
            w_n_hat: 0.0,
            w_t_hat: 0.0,
        }
    }
}

impl Mechanism for BoxOnIncline {
    fn laws(&self) -> &[ContactLaw] {
        &self.laws
    }

    fn mass_matrix(&self, _q: &[f64], _t: f64, m: &mut [f64]) {
        m.fill(0.0);
        m[0] = self.m;
        m[4] = self.m;
        m[8] = self.inertia();
    }

    fn forces(&self, _q: &[f64], _u: &[f64], _t: f64, h: &mut [f64]) {
        let (s, c) = self.alpha.sin_cos();
        h.copy_from_slice(&[self.m * G * s, -self.m * G * c, 0.0]);
    }

    fn potential_energy(&self, q: &[f64], _t: f64) -> Option<f64> {
        let (s, c) = self.alpha.sin_cos();
        Some(self.m * G * (c * q[1] - s * q[0]))
    }

    fn constant_mass_matrix(&self) -> bool {
        true
    }
}
