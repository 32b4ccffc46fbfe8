//! [`Disks`]: rigid disks on a floor y = 0 between two walls, written both ways the stepper
//! takes a mechanism: with fixed contacts and dense rows, and with a
//! [`BodyStructure`] whose contacts are detected at each step.

use std::sync::Mutex;

use moreau_kinematics::{ContactKinematics, ContactPoint};
use moreau_setvalued::ContactLaw;
use moreau_stepper::{BodyContact, BodyStructure, Mechanism, NO_BODY};

use crate::G;

/// Disks of given masses and radii in the plane, q = (x_k, y_k, θ_k) per disk, under gravity
/// g (downwards), with a floor y = 0 and walls x = `walls.0` and x = `walls.1` (each
/// optional), one contact law for every contact.
///
/// The contacts are numbered once: for disk k, 3k is the floor, 3k + 1 the left wall,
/// 3k + 2 the right wall; after them the pairs (i, j), i < j, in lexicographic order. The
/// number is the contact's identity on the many-body path and its index on the path of fixed
/// contacts, so that the two paths can be compared contact by contact.
///
/// With `structured`, [`Mechanism::body_structure`] returns the disks' [`BodyStructure`],
/// whose detection tries every pair (for up to 64 disks) or sweeps the disks sorted by
/// their lowest point; without it the stepper sees the fixed contacts.
pub struct Disks {
    /// Masses (kg); the inertia of disk k is m_k r_k² / 2.
    pub m: Vec<f64>,
    /// Radii (m).
    pub r: Vec<f64>,
    /// The floor y = 0, if present.
    pub floor: bool,
    /// The walls x = left and x = right, if present.
    pub walls: Option<(f64, f64)>,
    /// Gravity (m/s²).
    pub g: f64,
    structured: bool,
    laws: Vec<ContactLaw>,
    /// Disk indices sorted by lowest point, for the sweep of the detection.
    sorted: Mutex<Vec<u32>>,
}

/// The gap of a contact with a wall or floor the scene does not have, on the path of fixed
/// contacts: a contact that never closes (finite, so that the projection's LCP takes it).
const ABSENT: f64 = 1e9;

/// What a numbered contact touches.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Feature {
    /// Disk k on the floor.
    Floor(usize),
    /// Disk k on the left wall.
    Left(usize),
    /// Disk k on the right wall.
    Right(usize),
    /// Disks i < j.
    Pair(usize, usize),
}

impl Disks {
    /// Disks of masses `m` and radii `r` with one law for every contact, under gravity
    /// [`G`], on the floor, without walls.
    pub fn new(m: Vec<f64>, r: Vec<f64>, law: ContactLaw, structured: bool) -> Self {
        assert_eq!(m.len(), r.len());
        let n = m.len();
        let contacts = 3 * n + n * n.saturating_sub(1) / 2;
        Disks {
            m,
            r,
            floor: true,
            walls: None,
            g: G,
            structured,
            laws: vec![law; contacts],
            sorted: Mutex::new(Vec::new()),
        }
    }

    /// The same disks with walls at x = left and x = right.
    pub fn with_walls(mut self, left: f64, right: f64) -> Self {
        self.walls = Some((left, right));
        self
    }

    /// The same disks under gravity g.
    pub fn with_gravity(mut self, g: f64) -> Self {
        self.g = g;
        self
    }

    /// The number of disks.
    pub fn n(&self) -> usize {
        self.m.len()
    }

    /// The number of the contact between disks i < j.
    pub fn pair_id(&self, i: usize, j: usize) -> u64 {
        let n = self.n();
        (3 * n + i * (2 * n - i - 1) / 2 + (j - i - 1)) as u64
    }

    /// What contact `id` touches.
    pub fn feature(&self, id: u64) -> Feature {
        let n = self.n();
        let id = id as usize;
        if id < 3 * n {
            return match id % 3 {
                0 => Feature::Floor(id / 3),
                1 => Feature::Left(id / 3),
                _ => Feature::Right(id / 3),
            };
        }
        let mut rank = id - 3 * n;
        let mut i = 0;
        while rank >= n - i - 1 {
            rank -= n - i - 1;
            i += 1;
        }
        Feature::Pair(i, i + 1 + rank)
    }

    /// Contact `id` at q, or `None` when its feature is absent (a wall or floor the scene
    /// does not have).
    pub fn contact_at(&self, id: u64, q: &[f64]) -> Option<BodyContact> {
        self.contact_of(self.feature(id), id, q)
    }

    /// The contact `id` of `feature` at q (see [`Self::contact_at`]).
    fn contact_of(&self, feature: Feature, id: u64, q: &[f64]) -> Option<BodyContact> {
        let law = self.laws[0];
        let pos = |k: usize| (q[3 * k], q[3 * k + 1]);
        let one = |k: usize, g_n: f64, w_n: [f64; 3], w_t: [f64; 3]| BodyContact {
            id,
            bodies: [k as u32, NO_BODY],
            w_n: [w_n, [0.0; 3]],
            w_t: [w_t, [0.0; 3]],
            point: ContactPoint { g_n, ..ContactPoint::default() },
            law,
        };
        Some(match feature {
            Feature::Floor(k) => {
                if !self.floor {
                    return None;
                }
                let r = self.r[k];
                one(k, pos(k).1 - r, [0.0, 1.0, 0.0], [1.0, 0.0, r])
            }
            Feature::Left(k) => {
                let (left, _) = self.walls?;
                let r = self.r[k];
                one(k, pos(k).0 - r - left, [1.0, 0.0, 0.0], [0.0, 1.0, -r])
            }
            Feature::Right(k) => {
                let (_, right) = self.walls?;
                let r = self.r[k];
                one(k, right - pos(k).0 - r, [-1.0, 0.0, 0.0], [0.0, -1.0, -r])
            }
            Feature::Pair(i, j) => {
                let ((xi, yi), (xj, yj)) = (pos(i), pos(j));
                let (dx, dy) = (xj - xi, yj - yi);
                let d = dx.hypot(dy);
                let (nx, ny) = (dx / d, dy / d);
                let (tx, ty) = (-ny, nx);
                BodyContact {
                    id,
                    bodies: [i as u32, j as u32],
                    w_n: [[-nx, -ny, 0.0], [nx, ny, 0.0]],
                    w_t: [[-tx, -ty, -self.r[i]], [tx, ty, -self.r[j]]],
                    point: ContactPoint {
                        g_n: d - self.r[i] - self.r[j],
                        ..ContactPoint::default()
                    },
                    law,
                }
            }
        })
    }

    /// The initial state of disks at the given centres, at rest.
    pub fn state_at(centres: &[(f64, f64)]) -> (Vec<f64>, Vec<f64>) {
        let q = centres.iter().flat_map(|&(x, y)| [x, y, 0.0]).collect::<Vec<_>>();
        let u = vec![0.0; q.len()];
        (q, u)
    }
}

impl ContactKinematics for Disks {
    fn num_coordinates(&self) -> usize {
        3 * self.n()
    }
    fn num_contacts(&self) -> usize {
        self.laws.len()
    }
    fn normal_gap(&self, i: usize, q: &[f64], _t: f64) -> f64 {
        self.contact_at(i as u64, q).map_or(ABSENT, |c| c.point.g_n)
    }
    fn contact(
        &self,
        i: usize,
        q: &[f64],
        _t: f64,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) -> ContactPoint {
        w_n.fill(0.0);
        w_t.fill(0.0);
        let Some(c) = self.contact_at(i as u64, q) else {
            return ContactPoint { g_n: ABSENT, ..ContactPoint::default() };
        };
        for side in 0..2 {
            let k = c.bodies[side];
            if k != NO_BODY {
                let k = 3 * k as usize;
                for j in 0..3 {
                    w_n[k + j] += c.w_n[side][j];
                    w_t[k + j] += c.w_t[side][j];
                }
            }
        }
        c.point
    }
}

impl Mechanism for Disks {
    fn laws(&self) -> &[ContactLaw] {
        &self.laws
    }
    fn mass_matrix(&self, _q: &[f64], _t: f64, m: &mut [f64]) {
        let f = 3 * self.n();
        m.fill(0.0);
        for k in 0..self.n() {
            let diag = [self.m[k], self.m[k], 0.5 * self.m[k] * self.r[k] * self.r[k]];
            for j in 0..3 {
                m[(3 * k + j) * (f + 1)] = diag[j];
            }
        }
    }
    fn forces(&self, _q: &[f64], _u: &[f64], _t: f64, h: &mut [f64]) {
        for k in 0..self.n() {
            h[3 * k] = 0.0;
            h[3 * k + 1] = -self.m[k] * self.g;
            h[3 * k + 2] = 0.0;
        }
    }
    fn potential_energy(&self, q: &[f64], _t: f64) -> Option<f64> {
        Some((0..self.n()).map(|k| self.m[k] * self.g * q[3 * k + 1]).sum())
    }
    fn constant_mass_matrix(&self) -> bool {
        true
    }
    fn body_structure(&self) -> Option<&dyn BodyStructure> {
        if self.structured { Some(self) } else { None }
    }
}

impl BodyStructure for Disks {
    fn num_bodies(&self) -> usize {
        self.n()
    }
    fn mass_blocks(&self, _q: &[f64], _t: f64, blocks: &mut [[f64; 9]]) {
        for (k, b) in blocks.iter_mut().enumerate() {
            *b = [0.0; 9];
            b[0] = self.m[k];
            b[4] = self.m[k];
            b[8] = 0.5 * self.m[k] * self.r[k] * self.r[k];
        }
    }
    fn detect(&self, q: &[f64], _t: f64, margin: f64, out: &mut Vec<BodyContact>) {
        let n = self.n();
        for id in 0..3 * n as u64 {
            if let Some(c) = self.contact_at(id, q)
                && c.point.g_n <= margin
            {
                out.push(c);
            }
        }
        let first_pair = out.len();
        let mut push = |i: usize, j: usize| {
            let (i, j) = (i.min(j), i.max(j));
            if let Some(c) = self.contact_of(Feature::Pair(i, j), self.pair_id(i, j), q)
                && c.point.g_n <= margin
            {
                out.push(c);
            }
        };
        if n <= 64 {
            for i in 0..n {
                for j in i + 1..n {
                    push(i, j);
                }
            }
            return;
        }
        // Sweep along y: a disk can touch only the disks whose lowest point lies below its
        // highest point plus the margin.
        let mut sorted = self.sorted.lock().expect("the detection's scratch is not poisoned");
        sorted.clear();
        sorted.extend(0..n as u32);
        let low = |k: u32| q[3 * k as usize + 1] - self.r[k as usize];
        sorted.sort_unstable_by(|&a, &b| low(a).total_cmp(&low(b)).then(a.cmp(&b)));
        for (a, &i) in sorted.iter().enumerate() {
            let top = q[3 * i as usize + 1] + self.r[i as usize] + margin;
            for &j in &sorted[a + 1..] {
                if low(j) > top {
                    break;
                }
                push(i as usize, j as usize);
            }
        }
        drop(sorted);
        out[first_pair..].sort_unstable_by_key(|c| c.id);
    }
}
