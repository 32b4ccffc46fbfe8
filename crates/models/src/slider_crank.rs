//! The slider-crank with a translational clearance joint (docs/theory.md §7.3):
//! q = (θ1, θ2, θ3), four frictional corner contacts of the slider with the guide.

use moreau_kinematics::{ContactKinematics, ContactPoint};
use moreau_setvalued::ContactLaw;
use moreau_stepper::{Mechanism, SharedWork};
use serde::{Deserialize, Serialize};

use crate::ModelError;
use crate::draw::{Drawing, Role};
use crate::params::{LawParams, all_finite, positive, relation};
use crate::slider_crank_ideal::{SliderCrankIdealInit, SliderCrankIdealParams};

fn enabled() -> bool {
    true
}

/// Parameters of the slider-crank with a clearance joint (the report's Table 8.4 in
/// [`SliderCrankParams::report`]).
///
/// The crank (length l1) turns about the origin, the connecting rod (length l2) joins its tip
/// to the slider's centre, and the slider, a rectangle 2a × 2b, moves between two guide
/// surfaces Y = ±d/2 with d = 2b + c. The crank is not driven: only its initial speed is
/// given. Gravity acts along −Y.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SliderCrankParams {
    /// Crank length l1 (m), < l2.
    pub l1: f64,
    /// Connecting-rod length l2 (m).
    pub l2: f64,
    /// Half length a of the slider (m).
    pub a: f64,
    /// Half height b of the slider (m).
    pub b: f64,
    /// Radial clearance c: the guide is d = 2b + c wide (m).
    pub c: f64,
    /// Crank mass m1 (kg).
    pub m1: f64,
    /// Connecting-rod mass m2 (kg).
    pub m2: f64,
    /// Slider mass m3 (kg).
    pub m3: f64,
    /// Crank moment of inertia J1 about its centre of mass (kg m²).
    pub j1: f64,
    /// Connecting-rod moment of inertia J2 about its centre of mass (kg m²).
    pub j2: f64,
    /// Slider moment of inertia J3 (kg m²).
    pub j3: f64,
    /// Gravitational acceleration g (m/s²).
    pub g: f64,
    /// Normal restitution ε_N of the four corners (dimensionless, in `[0, 1]`).
    pub eps_n: f64,
    /// Tangential restitution ε_T of the four corners (dimensionless, in `[0, 1]`).
    pub eps_t: f64,
    /// Friction coefficient μ of the four corners (dimensionless, >= 0).
    pub mu: f64,
    /// Whether the upper guide surface (corners 1 and 2) is modelled; default `true`.
    #[serde(default = "enabled")]
    pub upper_surface: bool,
    /// Whether the lower guide surface (corners 3 and 4) is modelled; default `true`.
    #[serde(default = "enabled")]
    pub lower_surface: bool,
    /// Initial state; the report's when omitted.
    #[serde(default = "SliderCrankInit::report")]
    pub init: SliderCrankInit,
}

/// Initial state of the slider-crank.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SliderCrankInit {
    /// Crank angle θ1 (rad).
    pub th1: f64,
    /// Connecting-rod angle θ2 (rad).
    pub th2: f64,
    /// Slider angle θ3 (rad).
    pub th3: f64,
    /// Crank speed ω1 (rad/s).
    pub w1: f64,
    /// Connecting-rod speed ω2 (rad/s); −(l1 cos θ1)/(l2 cos θ2) ω1 keeps the slider's
    /// vertical velocity zero.
    pub w2: f64,
    /// Slider angular speed ω3 (rad/s).
    pub w3: f64,
}

impl SliderCrankInit {
    /// The report's initial state: all angles 0, ω1 = 150 rad/s, ω2 = −75 rad/s, ω3 = 0.
    pub fn report() -> Self {
        Self { th1: 0.0, th2: 0.0, th3: 0.0, w1: 150.0, w2: -75.0, w3: 0.0 }
    }
}

impl SliderCrankParams {
    /// The report's Table 8.4 (ε_N = 0.4, μ = 0.01, c = 1 mm).
    pub fn report() -> Self {
        Self {
            l1: 0.1530,
            l2: 0.3060,
            a: 0.0500,
            b: 0.0250,
            c: 0.0010,
            m1: 0.0380,
            m2: 0.0380,
            m3: 0.0760,
            j1: 7.4e-5,
            j2: 5.9e-4,
            j3: 2.7e-6,
            g: 9.81,
            eps_n: 0.4,
            eps_t: 0.0,
            mu: 0.01,
            upper_surface: true,
            lower_surface: true,
            init: SliderCrankInit::report(),
        }
    }

    /// The ideal (no clearance) slider-crank with the same bodies, started at the same crank
    /// angle and speed.
    pub fn ideal(&self) -> SliderCrankIdealParams {
        SliderCrankIdealParams {
            l1: self.l1,
            l2: self.l2,
            a: self.a,
            b: self.b,
            m1: self.m1,
            m2: self.m2,
            m3: self.m3,
            j1: self.j1,
            j2: self.j2,
            g: self.g,
            init: SliderCrankIdealInit { th1: self.init.th1, w1: self.init.w1 },
        }
    }

    /// Width d = 2b + c of the guide (m).
    pub fn guide_width(&self) -> f64 {
        2.0 * self.b + self.c
    }
}

/// The slider-crank with a clearance joint as a [`Mechanism`] (docs/theory.md §7.3); corners on
/// a switched-off guide surface are not listed.
#[derive(Clone, Debug)]
pub struct SliderCrank {
    params: SliderCrankParams,
    /// Which corner (0..4 for corners 1..4) each listed contact is.
    corners: Vec<usize>,
    laws: Vec<ContactLaw>,
    /// Per listed contact: the corner's body coordinates and whether it faces the upper
    /// surface.
    local: Vec<([f64; 2], bool)>,
    /// Combinations of the parameters that every step uses.
    k: Constants,
}

/// The parameter combinations of M, h and the gaps (docs/theory.md §7.3).
#[derive(Clone, Debug)]
struct Constants {
    /// M11 and M22 (constant) and the factor of cos(θ2 − θ1) in M12.
    m11: f64,
    m22: f64,
    m12: f64,
    /// The gravity terms of h1 and h2 without cos θ1, cos θ2.
    g1: f64,
    g2: f64,
    /// Half the guide's width.
    half: f64,
}

/// Corner k (0-based) in the slider's frame, and whether it faces the upper surface.
fn corner_local(a: f64, b: f64, k: usize) -> ([f64; 2], bool) {
    match k {
        0 => ([-a, b], true),
        1 => ([a, b], true),
        2 => ([-a, -b], false),
        _ => ([a, -b], false),
    }
}

impl SliderCrank {
    /// Names of the coordinates q.
    pub const COORDINATES: &'static [&'static str] = &["th1", "th2", "th3"];
    /// Names of the velocities u.
    pub const VELOCITIES: &'static [&'static str] = &["w1", "w2", "w3"];

    /// Validates the parameters and builds the model.
    ///
    /// # Errors
    /// [`ModelError::InvalidParameter`] naming the field for a non-positive length, mass or
    /// inertia, a crank not shorter than the rod, a bad law or a non-finite initial state.
    pub fn new(params: SliderCrankParams) -> Result<Self, ModelError> {
        let p = &params;
        for (f, v) in [
            ("l1", p.l1),
            ("l2", p.l2),
            ("a", p.a),
            ("b", p.b),
            ("c", p.c),
            ("m1", p.m1),
            ("m2", p.m2),
            ("m3", p.m3),
            ("j1", p.j1),
            ("j2", p.j2),
            ("j3", p.j3),
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
        let i = &p.init;
        all_finite(&[
            ("init.th1", i.th1),
            ("init.th2", i.th2),
            ("init.th3", i.th3),
            ("init.w1", i.w1),
            ("init.w2", i.w2),
            ("init.w3", i.w3),
        ])?;
        let law = LawParams::new(p.eps_n, p.eps_t, p.mu).law("")?;
        let corners: Vec<usize> =
            (0..4).filter(|&k| if k < 2 { p.upper_surface } else { p.lower_surface }).collect();
        let laws = vec![law; corners.len()];
        let local = corners.iter().map(|&k| corner_local(p.a, p.b, k)).collect();
        let k = Constants {
            m11: p.j1 + (0.25 * p.m1 + p.m2 + p.m3) * p.l1 * p.l1,
            m22: p.j2 + (0.25 * p.m2 + p.m3) * p.l2 * p.l2,
            m12: (0.5 * p.m2 + p.m3) * p.l1 * p.l2,
            g1: (0.5 * p.m1 + p.m2 + p.m3) * p.g * p.l1,
            g2: (0.5 * p.m2 + p.m3) * p.g * p.l2,
            half: 0.5 * p.guide_width(),
        };
        Ok(Self { params, corners, laws, local, k })
    }

    /// The parameters.
    pub fn params(&self) -> &SliderCrankParams {
        &self.params
    }

    /// Which corner (0..4 for the report's corners 1..4) each listed contact is.
    pub fn corner_ids(&self) -> &[usize] {
        &self.corners
    }

    /// The initial state (q0, u0).
    pub fn initial_state(&self) -> (Vec<f64>, Vec<f64>) {
        let i = &self.params.init;
        (vec![i.th1, i.th2, i.th3], vec![i.w1, i.w2, i.w3])
    }

    /// Names of the listed contacts.
    pub fn contact_names(&self) -> Vec<String> {
        self.corners
            .iter()
            .map(|&k| format!("corner {} ({})", k + 1, if k < 2 { "upper" } else { "lower" }))
            .collect()
    }

    /// Crank tip l1 (cos θ1, sin θ1) (m).
    pub fn crank_tip(&self, q: &[f64]) -> [f64; 2] {
        [self.params.l1 * q[0].cos(), self.params.l1 * q[0].sin()]
    }

    /// Slider centre (x3, y3) = l1 (c1, s1) + l2 (c2, s2) (m).
    pub fn slider_center(&self, q: &[f64]) -> [f64; 2] {
        let p = &self.params;
        [p.l1 * q[0].cos() + p.l2 * q[1].cos(), p.l1 * q[0].sin() + p.l2 * q[1].sin()]
    }

    /// Position of corner `k` (0-based: 0..4 are the report's corners 1..4) (m).
    pub fn corner_position(&self, k: usize, q: &[f64]) -> [f64; 2] {
        let ([sx, sy], _) = corner_local(self.params.a, self.params.b, k);
        let [x3, y3] = self.slider_center(q);
        let (s3, c3) = q[2].sin_cos();
        [x3 + sx * c3 - sy * s3, y3 + sx * s3 + sy * c3]
    }

    /// Normalised vertical corner position Y_k = (y_corner − y_centred)/(c/2), with
    /// y_centred = +b for corners 1, 2 and −b for corners 3, 4: +1 touches the upper surface,
    /// −1 the lower one, and |Y_k| > 1 is penetration.
    pub fn normalized_corner(&self, k: usize, q: &[f64]) -> f64 {
        let centred = if k < 2 { self.params.b } else { -self.params.b };
        (self.corner_position(k, q)[1] - centred) / (0.5 * self.params.c)
    }

    /// The slider portrait ((x3 − l2)/l1, y3/(c/2)).
    pub fn slider_portrait(&self, q: &[f64]) -> [f64; 2] {
        let p = &self.params;
        let [x3, y3] = self.slider_center(q);
        [(x3 - p.l2) / p.l1, y3 / (0.5 * p.c)]
    }

    fn full_gap(&self, i: usize, q: &[f64]) -> f64 {
        let y3 = self.params.l1 * q[0].sin() + self.params.l2 * q[1].sin();
        let (s3, c3) = q[2].sin_cos();
        self.gap_at(i, y3, s3, c3)
    }

    /// M with cos(θ2 − θ1) given (docs/theory.md §7.3).
    fn mass_at(&self, cos21: f64, m: &mut [f64]) {
        let k = &self.k;
        let m12 = k.m12 * cos21;
        m[..9].copy_from_slice(&[k.m11, m12, 0.0, m12, k.m22, 0.0, 0.0, 0.0, self.params.j3]);
    }

    /// h with sin(θ2 − θ1), cos θ1 and cos θ2 given (docs/theory.md §7.3).
    fn forces_at(&self, sin21: f64, c1: f64, c2: f64, u: &[f64], h: &mut [f64]) {
        let k = &self.k;
        let a = k.m12 * sin21;
        h[0] = a * u[1] * u[1] - k.g1 * c1;
        h[1] = -a * u[0] * u[0] - k.g2 * c2;
        h[2] = 0.0;
    }

    /// g_N of every modelled corner, in contact order, from y3 and (sin θ3, cos θ3).
    fn gaps_at(&self, y3: f64, s3: f64, c3: f64, g: &mut [f64]) {
        for (i, gi) in g.iter_mut().enumerate() {
            *gi = self.gap_at(i, y3, s3, c3);
        }
    }

    /// g_N of the listed contact i from the slider centre's height y3 and (sin θ3, cos θ3).
    #[inline]
    fn gap_at(&self, i: usize, y3: f64, s3: f64, c3: f64) -> f64 {
        let ([sx, sy], upper) = self.local[i];
        let y = y3 + sx * s3 + sy * c3;
        if upper { self.k.half - y } else { self.k.half + y }
    }

    /// Locations of the listed contacts' corners at `q`.
    pub fn contact_points(&self, q: &[f64], _t: f64) -> Vec<[f64; 2]> {
        self.corners.iter().map(|&k| self.corner_position(k, q)).collect()
    }

    /// Draws the crank, the connecting rod, the slider, the modelled guide surfaces and the
    /// joints; closed corners are marked.
    pub fn draw(&self, q: &[f64], t: f64) -> Drawing {
        let p = &self.params;
        let mut d = Drawing::new();
        let tip = self.crank_tip(q);
        let centre = self.slider_center(q);
        let half = 0.5 * p.guide_width();
        let (x0, x1) = (p.l2 - p.l1 - 2.0 * p.a, p.l2 + p.l1 + 2.0 * p.a);
        if p.upper_surface {
            d.line(Role::Guide, vec![[x0, half], [x1, half]]);
        }
        if p.lower_surface {
            d.line(Role::Guide, vec![[x0, -half], [x1, -half]]);
        }
        d.line(Role::Crank, vec![[0.0, 0.0], tip]);
        d.line(Role::Rod, vec![tip, centre]);
        d.polygon(Role::Slider, [0, 1, 3, 2].iter().map(|&k| self.corner_position(k, q)).collect());
        let r = 0.04 * p.l1;
        d.circle(Role::Ground, [0.0, 0.0], r);
        d.circle(Role::Joint, tip, r);
        d.circle(Role::Joint, centre, r);
        for (i, &k) in self.corners.iter().enumerate() {
            if self.normal_gap(i, q, t) <= 1e-6 * p.c {
                d.circle(Role::ContactPoint, self.corner_position(k, q), 0.5 * r);
            }
        }
        d
    }
}

impl ContactKinematics for SliderCrank {
    fn num_coordinates(&self) -> usize {
        3
    }
    fn num_contacts(&self) -> usize {
        self.corners.len()
    }
    fn normal_gap(&self, i: usize, q: &[f64], _t: f64) -> f64 {
        self.full_gap(i, q)
    }
    fn normal_gaps(&self, q: &[f64], _t: f64, g: &mut [f64]) {
        // The corners share the slider's height and angle: three sines for all of them.
        let y3 = self.params.l1 * q[0].sin() + self.params.l2 * q[1].sin();
        let (s3, c3) = q[2].sin_cos();
        self.gaps_at(y3, s3, c3, g);
    }
    fn contact(
        &self,
        i: usize,
        q: &[f64],
        _t: f64,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) -> ContactPoint {
        self.corner_at(i, &Angles::new(q), w_n, w_t)
    }
    fn contacts(
        &self,
        which: &[usize],
        q: &[f64],
        _t: f64,
        w_n: &mut [f64],
        w_t: &mut [f64],
        points: &mut [ContactPoint],
    ) {
        // The corners share the three angles' sines and cosines.
        self.corners_at(which, &Angles::new(q), w_n, w_t, points);
    }
}

/// The sines and cosines of θ1, θ2 and θ3.
struct Angles {
    s: [f64; 3],
    c: [f64; 3],
}

impl Angles {
    fn new(q: &[f64]) -> Self {
        let (s1, c1) = q[0].sin_cos();
        let (s2, c2) = q[1].sin_cos();
        let (s3, c3) = q[2].sin_cos();
        Self { s: [s1, s2, s3], c: [c1, c2, c3] }
    }

    /// The layout kept in the stepper's memo: the sines, then the cosines.
    fn to_memo(&self) -> [f64; 6] {
        let ([s1, s2, s3], [c1, c2, c3]) = (self.s, self.c);
        [s1, s2, s3, c1, c2, c3]
    }

    fn from_memo(memo: &[f64]) -> Self {
        let [s1, s2, s3, c1, c2, c3] = memo[..6].try_into().expect("a memo of 6 values");
        Self { s: [s1, s2, s3], c: [c1, c2, c3] }
    }
}

impl SliderCrank {
    /// [`ContactKinematics::contacts`] from the angles' sines and cosines.
    fn corners_at(
        &self,
        which: &[usize],
        angles: &Angles,
        w_n: &mut [f64],
        w_t: &mut [f64],
        points: &mut [ContactPoint],
    ) {
        for (k, &i) in which.iter().enumerate() {
            let (w_n, w_t) = (&mut w_n[3 * k..3 * k + 3], &mut w_t[3 * k..3 * k + 3]);
            points[k] = self.corner_at(i, angles, w_n, w_t);
        }
    }

    /// The kinematics of the listed contact i from the angles' sines and cosines.
    fn corner_at(
        &self,
        i: usize,
        angles: &Angles,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) -> ContactPoint {
        let p = &self.params;
        let ([sx, sy], upper) = self.local[i];
        let ([s1, s2, s3], [c1, c2, c3]) = (angles.s, angles.c);
        // The corner's world position (x, y) and its gradients with respect to q.
        let dy = [p.l1 * c1, p.l2 * c2, sx * c3 - sy * s3];
        let dx = [-p.l1 * s1, -p.l2 * s2, -sx * s3 - sy * c3];
        let sign = if upper { -1.0 } else { 1.0 };
        for j in 0..3 {
            w_n[j] = sign * dy[j];
            w_t[j] = dx[j];
        }
        let x = p.l1 * c1 + p.l2 * c2 + sx * c3 - sy * s3;
        let g_n = self.gap_at(i, p.l1 * s1 + p.l2 * s2, s3, c3);
        ContactPoint { g_n, g_t: x, w_n_hat: 0.0, w_t_hat: 0.0 }
    }
}

impl Mechanism for SliderCrank {
    fn laws(&self) -> &[ContactLaw] {
        &self.laws
    }
    fn mass_matrix(&self, q: &[f64], _t: f64, m: &mut [f64]) {
        self.mass_at((q[1] - q[0]).cos(), m);
    }
    fn forces(&self, q: &[f64], u: &[f64], _t: f64, h: &mut [f64]) {
        self.forces_at((q[1] - q[0]).sin(), q[0].cos(), q[1].cos(), u, h);
    }
    fn shared_work(&self) -> Option<&dyn SharedWork> {
        Some(self)
    }
    fn potential_energy(&self, q: &[f64], _t: f64) -> Option<f64> {
        let p = &self.params;
        Some(
            (0.5 * p.m1 + p.m2 + p.m3) * p.g * p.l1 * q[0].sin()
                + (0.5 * p.m2 + p.m3) * p.g * p.l2 * q[1].sin(),
        )
    }
}

/// M, h, the gaps and the closed corners' kinematics from one set of sines and cosines.
impl SharedWork for SliderCrank {
    fn evaluate(
        &self,
        q: &[f64],
        u: &[f64],
        _t: f64,
        mass: Option<&mut [f64]>,
        h: &mut [f64],
        gaps: &mut [f64],
        memo: &mut [f64],
    ) {
        // Three sine-cosine pairs serve M, h, every gap and, kept in `memo`, the closed
        // corners' kinematics; θ2 − θ1 by the difference formulas.
        let angles = Angles::new(q);
        memo[..6].copy_from_slice(&angles.to_memo());
        let ([s1, s2, s3], [c1, c2, c3]) = (angles.s, angles.c);
        if let Some(m) = mass {
            self.mass_at(c2 * c1 + s2 * s1, m);
        }
        self.forces_at(s2 * c1 - c2 * s1, c1, c2, u, h);
        self.gaps_at(self.params.l1 * s1 + self.params.l2 * s2, s3, c3, gaps);
    }
    fn memo_len(&self) -> usize {
        6
    }
    fn midpoint_contacts(
        &self,
        which: &[usize],
        _q: &[f64],
        _t: f64,
        memo: &[f64],
        w_n: &mut [f64],
        w_t: &mut [f64],
        points: &mut [ContactPoint],
    ) {
        self.corners_at(which, &Angles::from_memo(memo), w_n, w_t, points);
    }
}
