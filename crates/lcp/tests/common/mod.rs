//! Shared helpers of the integration tests and benches: a seeded generator and problem
//! builders (random SPD and P-matrices with planted solutions, the friction LCP of the
//! time-stepper, Murty's exponential problem).
#![allow(dead_code, non_snake_case)]

use faer::linalg::solvers::DenseSolveCore;
use faer::{Col, Mat};
use moreau_lcp::{Auto, Lcp, Solution, Solver};

/// splitmix64: a tiny deterministic generator.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [a, b).
    pub fn uniform(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }

    pub fn below(&mut self, k: u64) -> u64 {
        self.next_u64() % k
    }
}

/// A random symmetric positive definite matrix `B B' / n + 0.1 I`.
pub fn random_spd(n: usize, rng: &mut Rng) -> Mat<f64> {
    let b = Mat::from_fn(n, n, |_, _| rng.uniform(-1.0, 1.0));
    let mut a = &b * b.transpose() * (1.0 / n as f64);
    for i in 0..n {
        a[(i, i)] += 0.1;
    }
    a
}

/// A random non-symmetric P-matrix: positive diagonal, strictly dominant by rows.
pub fn random_p_matrix(n: usize, rng: &mut Rng) -> Mat<f64> {
    let mut a = Mat::from_fn(n, n, |i, j| if i == j { 0.0 } else { rng.uniform(-1.0, 1.0) });
    for i in 0..n {
        let off: f64 = (0..n).map(|j| a[(i, j)].abs()).sum();
        a[(i, i)] = off * rng.uniform(1.1, 2.0) + 0.1;
    }
    a
}

/// Chooses complementary (z*, w*) (some pairs both zero when `degenerate`) and returns
/// the LCP with `q = w* - M z*` and z*.
pub fn planted(m: Mat<f64>, rng: &mut Rng, degenerate: bool) -> (Lcp, Vec<f64>) {
    let n = m.nrows();
    let mut z = vec![0.0; n];
    let mut w = vec![0.0; n];
    for i in 0..n {
        match rng.below(if degenerate { 3 } else { 2 }) {
            0 => z[i] = rng.uniform(0.1, 2.0),
            1 => w[i] = rng.uniform(0.1, 2.0),
            _ => {}
        }
    }
    let q = Col::from_fn(n, |i| w[i] - (0..n).map(|j| m[(i, j)] * z[j]).sum::<f64>());
    (Lcp::new(m, q).expect("valid planted problem"), z)
}

/// Independent check that z solves the LCP: recomputes w = M z + q in a different
/// order and tests the conditions with scaled bounds.
pub fn assert_solves(lcp: &Lcp, z: &[f64], tol: f64) {
    let n = lcp.n();
    let (m, q) = (lcp.m(), lcp.q());
    let zmax = z.iter().fold(1.0f64, |a, v| a.max(v.abs()));
    for i in 0..n {
        let mut w = q[i];
        let mut scale = q[i].abs().max(1.0);
        for j in (0..n).rev() {
            w += m[(i, j)] * z[j];
            scale = scale.max((m[(i, j)] * z[j]).abs());
        }
        assert!(z[i] >= -tol * zmax, "z[{i}] = {} < 0", z[i]);
        assert!(w >= -tol * scale, "w[{i}] = {w} < 0 (scale {scale})");
        assert!(z[i].min(w).abs() <= tol * scale.max(zmax), "z[{i}] = {}, w[{i}] = {w}", z[i]);
    }
}

/// Max-norm distance between two vectors relative to `max(1, ‖a‖∞)`.
pub fn rel_dist(a: &[f64], b: &[f64]) -> f64 {
    let scale = a.iter().fold(1.0f64, |s, v| s.max(v.abs()));
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max) / scale
}

/// Murty's problem: M upper triangular with 1 on the diagonal and 2 above, q = -1.
pub fn murty(n: usize) -> Lcp {
    let m = Mat::from_fn(n, n, |i, j| {
        if i == j {
            1.0
        } else if j > i {
            2.0
        } else {
            0.0
        }
    });
    Lcp::new(m, Col::from_fn(n, |_| -1.0)).expect("valid Murty problem")
}

/// The data of one step LCP with friction (EQUATIONS.md section 5).
pub struct Friction {
    pub lcp: Lcp,
    pub nc: usize,
    pub mass_inv: Mat<f64>,
    pub wn: Mat<f64>,
    pub wt: Mat<f64>,
    pub mu: Vec<f64>,
}

impl Friction {
    /// The velocity change `Mi (W_N P_N + W_T P_T)` of an LCP solution x, with
    /// `P_T = P_R - μ P_N` (the quantity that is unique when x is not).
    pub fn delta_u(&self, x: &[f64]) -> Vec<f64> {
        let (nc, ndof) = (self.nc, self.mass_inv.nrows());
        let mut f = vec![0.0; ndof];
        for c in 0..nc {
            let pn = x[c];
            let pt = x[nc + c] - self.mu[c] * pn;
            for k in 0..ndof {
                f[k] += self.wn[(k, c)] * pn + self.wt[(k, c)] * pt;
            }
        }
        (0..ndof).map(|k| (0..ndof).map(|l| self.mass_inv[(k, l)] * f[l]).sum()).collect()
    }
}

/// The friction LCP of `nc` contacts on a system with `ndof` coordinates: random SPD mass
/// matrix, random W_N, W_T, μ in [0.1, 0.8], gravity-like h, approaching normal velocities.
pub fn friction(nc: usize, ndof: usize, rng: &mut Rng) -> Friction {
    let mass = random_spd(ndof, rng);
    let mass_inv = mass.partial_piv_lu().inverse();
    let wn = Mat::from_fn(ndof, nc, |_, _| rng.uniform(-1.0, 1.0));
    let wt = Mat::from_fn(ndof, nc, |_, _| rng.uniform(-1.0, 1.0));
    let mu: Vec<f64> = (0..nc).map(|_| rng.uniform(0.1, 0.8)).collect();
    let h = Col::from_fn(ndof, |_| rng.uniform(-10.0, 10.0));
    let u = Col::from_fn(ndof, |_| rng.uniform(-1.0, 1.0));
    let dt = 1e-3;
    let (en, et) = (0.5, 0.0);
    let mu_m = Mat::from_fn(nc, nc, |i, j| if i == j { mu[i] } else { 0.0 });
    let wn_wt_mu = &wn - &wt * &mu_m;
    let a11 = wn.transpose() * &mass_inv * &wn_wt_mu;
    let a12 = wn.transpose() * &mass_inv * &wt;
    let a21 = wt.transpose() * &mass_inv * &wn_wt_mu;
    let a22 = wt.transpose() * &mass_inv * &wt;
    let n = 3 * nc;
    let a = Mat::from_fn(n, n, |i, j| {
        let (bi, ii) = (i / nc, i % nc);
        let (bj, jj) = (j / nc, j % nc);
        match (bi, bj) {
            (0, 0) => a11[(ii, jj)],
            (0, 1) => a12[(ii, jj)],
            (1, 0) => a21[(ii, jj)],
            (1, 1) => a22[(ii, jj)],
            (1, 2) => f64::from(u8::from(ii == jj)),
            (2, 0) => 2.0 * if ii == jj { mu[ii] } else { 0.0 },
            (2, 1) => -f64::from(u8::from(ii == jj)),
            _ => 0.0,
        }
    });
    let mih = &mass_inv * &h;
    let gn = wn.transpose() * &u;
    let gt = wt.transpose() * &u;
    let bn = wn.transpose() * &mih * dt;
    let bt = wt.transpose() * &mih * dt;
    // Make every contact approach, so that impulses are needed.
    let b = Col::from_fn(n, |i| {
        let c = i % nc;
        match i / nc {
            0 => bn[c] + (1.0 + en) * (-gn[c].abs() - 0.1),
            1 => bt[c] + (1.0 + et) * gt[c],
            _ => 0.0,
        }
    });
    Friction { lcp: Lcp::new(a, b).expect("valid friction LCP"), nc, mass_inv, wn, wt, mu }
}

/// Asserts the shared status rule: Solved only with an accepted residual.
pub fn assert_status_honest(sol: &Solution, tol: f64) {
    if sol.is_solved() {
        assert!(
            sol.residual.relative <= tol,
            "solved with relative residual {}",
            sol.residual.relative
        );
    }
}

/// The names of the problem sets of the benches, in their order.
pub const BENCH_SETS: [&str; 6] =
    ["friction_3", "friction_9", "spd_3", "spd_9", "spd_30", "spd_90"];

/// The 16 problems of a bench set: `friction_3` and `friction_9` (the step LCP with friction
/// of 1 and 3 contacts, kept when `Auto` solves them), `spd_3` to `spd_90` (random SPD
/// matrices with planted solutions); `None` for another name.
pub fn bench_set(name: &str) -> Option<Vec<Lcp>> {
    let friction_set = |nc: usize, seed: u64| {
        let mut rng = Rng::new(seed);
        let mut out = Vec::new();
        while out.len() < 16 {
            let f = friction(nc, 3 + nc, &mut rng);
            if Auto::default().solve(&f.lcp).is_ok_and(|s| s.is_solved()) {
                out.push(f.lcp);
            }
        }
        out
    };
    let spd_set = |n: usize, seed: u64| {
        let mut rng = Rng::new(seed);
        (0..16).map(|_| planted(random_spd(n, &mut rng), &mut rng, false).0).collect()
    };
    Some(match name {
        "friction_3" => friction_set(1, 1),
        "friction_9" => friction_set(3, 2),
        "spd_3" => spd_set(3, 3),
        "spd_9" => spd_set(9, 4),
        "spd_30" => spd_set(30, 5),
        "spd_90" => spd_set(90, 6),
        _ => return None,
    })
}
