//! Shared helpers of the integration tests and benches: the friction LCP of the
//! time-stepper, the bench sets and independent checks of solutions; the seeded generator
//! and the SPD, P-matrix, planted and Murty problems come from `moreau-testsupport`.
#![allow(dead_code, non_snake_case)]

use faer::linalg::solvers::DenseSolveCore;
use faer::{Col, Mat};
use moreau_lcp::fc2d::{Fc2d, Fc2dBuilder, Gfc2d};
use moreau_lcp::{Auto, Lcp, Solution, Solver};
// Each test file takes the part of these it needs.
#[allow(unused_imports)]
pub use moreau_testsupport::{SplitMix64 as Rng, murty, planted, random_p_matrix, random_spd};

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

/// The data of one step LCP with friction (docs/theory.md section 5).
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

/// Every FC2D and GFC2D file of Siconos' collection in `tests/data/siconos/fc2d` (GFC2D
/// reduced to the contact space), by file name, read once per test binary.
pub fn fc2d_collection() -> &'static [(String, Fc2d)] {
    static FILES: std::sync::OnceLock<Vec<(String, Fc2d)>> = std::sync::OnceLock::new();
    FILES.get_or_init(|| {
        let root =
            std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/siconos/fc2d");
        let mut files: Vec<std::path::PathBuf> = std::fs::read_dir(root)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "dat"))
            .collect();
        files.sort();
        files
            .into_iter()
            .map(|path| {
                let name = path.file_name().unwrap().to_string_lossy().into_owned();
                let file = std::fs::File::open(&path).unwrap();
                let problem = if name.starts_with("gfc2d") {
                    Gfc2d::read_siconos(file).unwrap().reduce().unwrap().problem
                } else {
                    Fc2d::read_siconos(file).unwrap()
                };
                (name, problem)
            })
            .collect()
    })
}

/// A planted FC2D problem and the reactions r that solve it.
pub struct PlantedFc2d {
    /// The problem.
    pub problem: Fc2d,
    /// Its planted solution (contacts' (r_N, r_T), then the joint's multipliers).
    pub r: Vec<f64>,
}

/// W = H M⁻¹ Hᵀ + 0.05 I of a chain of n_c + 1 bodies: contact i touches bodies i and i + 1
/// (a random 2x3 Jacobian on each), random diagonal masses, and with `joint` two more rows of
/// a joint between the first two bodies.
pub fn chain_w(n_c: usize, joint: bool, rng: &mut Rng) -> Mat<f64> {
    let bodies = n_c + 1;
    let rows = 2 * n_c + if joint { 2 } else { 0 };
    let h = Mat::from_fn(rows, 3 * bodies, |row, col| {
        let b = col / 3;
        let touches = if row < 2 * n_c { b == row / 2 || b == row / 2 + 1 } else { b <= 1 };
        if touches { rng.uniform(-1.0, 1.0) } else { 0.0 }
    });
    let mass: Vec<f64> = (0..3 * bodies).map(|_| rng.uniform(0.5, 2.0)).collect();
    Mat::from_fn(rows, rows, |i, j| {
        let coupling: f64 = (0..3 * bodies).map(|k| h[(i, k)] * h[(j, k)] / mass[k]).sum();
        coupling + if i == j { 0.05 } else { 0.0 }
    })
}

/// A planted problem with the W of [`chain_w`], each contact's mode chosen at random (open, stick, slip
/// either way), the joint's multipliers free, and q set so that r solves it.
pub fn planted_fc2d(n_c: usize, mu_max: f64, joint: bool, rng: &mut Rng) -> PlantedFc2d {
    let w = chain_w(n_c, joint, rng);
    let rows = w.nrows();
    let mu: Vec<f64> = (0..n_c).map(|_| rng.uniform(0.0, mu_max)).collect();
    let mut r = vec![0.0; rows];
    let mut u = vec![0.0; rows];
    for i in 0..n_c {
        match rng.below(4) {
            0 => {
                u[2 * i] = rng.uniform(0.1, 1.0);
                u[2 * i + 1] = rng.uniform(-1.0, 1.0);
            }
            1 => {
                r[2 * i] = rng.uniform(0.1, 1.0);
                r[2 * i + 1] = rng.uniform(-0.9, 0.9) * mu[i] * r[2 * i];
            }
            k => {
                let s = if k == 2 { 1.0 } else { -1.0 };
                r[2 * i] = rng.uniform(0.1, 1.0);
                r[2 * i + 1] = -s * mu[i] * r[2 * i];
                u[2 * i + 1] = s * rng.uniform(0.1, 1.0);
            }
        }
    }
    for v in &mut r[2 * n_c..] {
        *v = rng.uniform(-1.0, 1.0);
    }
    let q: Vec<f64> =
        (0..rows).map(|i| u[i] - (0..rows).map(|j| w[(i, j)] * r[j]).sum::<f64>()).collect();
    let mut builder = Fc2dBuilder::new(n_c);
    if joint {
        builder.bilateral_group(2);
    }
    for i in 0..rows {
        for j in 0..rows {
            if w[(i, j)] != 0.0 {
                builder.add_entry(i, j, w[(i, j)]);
            }
        }
    }
    PlantedFc2d { problem: builder.build(&q, &mu).unwrap(), r }
}

/// A certificate that a problem has one solution only: the smallest over σ ∈ {−1, 1}^n_c of
/// λ_min of the symmetric part of (I + D_σ) W, with D_σ = Σ_i μ_i σ_i e_N,i e_T,iᵀ.
///
/// The problem is the variational inequality r ∈ K, ⟨û(r), s − r⟩ >= 0 for all s ∈ K, with
/// û = W r + q + μ |u_T| e_N on the contacts' rows and û = W r + q on the bilateral rows
/// (whose cone is the whole line). Between two r, |u_T,i| changes by σ_i Δu_T,i with σ_i ∈
/// [−1, 1], so Δû = (I + D_σ) W Δr; the symmetric part is affine in σ and its smallest
/// eigenvalue concave, smallest at a vertex. A positive value c makes û strongly monotone,
/// ⟨Δû, Δr⟩ >= c |Δr|², and two solutions would give ⟨Δû, Δr⟩ <= 0: there is one. W
/// positive definite is not enough on its own: friction makes û non-monotone for μ large.
pub fn uniqueness_margin(problem: &Fc2d) -> f64 {
    let view = problem.view();
    let (n, mu) = (view.n_rows(), view.mu());
    let w = view.to_dense();
    let mut worst = f64::INFINITY;
    for signs in 0..1usize << mu.len() {
        // Row 2 i of (I + D_σ) W is W's normal row plus μ_i σ_i times its tangential row.
        let g = |i: usize, j: usize| {
            let mut x = w[i + j * n];
            if i < 2 * mu.len() && i.is_multiple_of(2) {
                let sigma = if signs >> (i / 2) & 1 == 1 { 1.0 } else { -1.0 };
                x += mu[i / 2] * sigma * w[i + 1 + j * n];
            }
            x
        };
        let sym = Mat::from_fn(n, n, |i, j| 0.5 * (g(i, j) + g(j, i)));
        let eigenvalues = sym.self_adjoint_eigenvalues(faer::Side::Lower).unwrap();
        worst = worst.min(eigenvalues[0]);
    }
    worst
}
