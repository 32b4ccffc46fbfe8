//! LCP problems with known answers: random SPD and P-matrices with planted solutions, and
//! Murty's exponential problem.

use faer::{Col, Mat};
use moreau_lcp::Lcp;

use crate::SplitMix64;

/// A random symmetric positive definite matrix `B Bᵀ / n + 0.1 I`, B uniform in [−1, 1)
/// (the shape of a frictionless step's Delassus matrix `W_Nᵀ M⁻¹ W_N`).
pub fn random_spd(n: usize, rng: &mut SplitMix64) -> Mat<f64> {
    let b = Mat::from_fn(n, n, |_, _| rng.uniform(-1.0, 1.0));
    let mut a = &b * b.transpose() * (1.0 / n as f64);
    for i in 0..n {
        a[(i, i)] += 0.1;
    }
    a
}

/// A random non-symmetric P-matrix: off-diagonal entries uniform in [−1, 1), each positive
/// diagonal entry larger than its row's off-diagonal sum (strict row dominance), so that
/// every LCP with it has exactly one solution.
pub fn random_p_matrix(n: usize, rng: &mut SplitMix64) -> Mat<f64> {
    let mut a = Mat::from_fn(n, n, |i, j| if i == j { 0.0 } else { rng.uniform(-1.0, 1.0) });
    for i in 0..n {
        let off: f64 = (0..n).map(|j| a[(i, j)].abs()).sum();
        a[(i, i)] = off * rng.uniform(1.1, 2.0) + 0.1;
    }
    a
}

/// The LCP(M, q) with a planted solution: chooses complementary (z*, w*), each pair with
/// z*_i > 0 or w*_i > 0 (or, when `degenerate`, also both zero) and values in [0.1, 2),
/// and returns the problem with `q = w* − M z*` together with z*.
///
/// # Panics
/// If `m` is not square or not finite.
pub fn planted(m: Mat<f64>, rng: &mut SplitMix64, degenerate: bool) -> (Lcp, Vec<f64>) {
    let n = m.nrows();
    let mut z = vec![0.0; n];
    let mut w = vec![0.0; n];
    for i in 0..n {
        match rng.next_u64() % if degenerate { 3 } else { 2 } {
            0 => z[i] = rng.uniform(0.1, 2.0),
            1 => w[i] = rng.uniform(0.1, 2.0),
            _ => {}
        }
    }
    let q = Col::from_fn(n, |i| w[i] - (0..n).map(|j| m[(i, j)] * z[j]).sum::<f64>());
    (Lcp::new(m, q).expect("valid planted problem"), z)
}

/// Murty's problem of size n: M upper triangular with 1 on the diagonal and 2 above it,
/// q = −1. Its unique solution is z = e_n; with other orderings or right-hand sides it
/// makes complementary pivoting take 2ⁿ pivots.
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

#[cfg(test)]
mod tests {
    use super::*;
    use moreau_lcp::{Lemke, Solver, Status};

    #[test]
    fn spd_matrices_are_symmetric_with_eigenvalues_above_the_shift() {
        let mut rng = SplitMix64::new(11);
        for n in [1, 2, 5, 12] {
            let a = random_spd(n, &mut rng);
            for i in 0..n {
                for j in 0..n {
                    assert_eq!(a[(i, j)], a[(j, i)]);
                }
            }
            // A − 0.1 I = B Bᵀ / n is positive semidefinite, so A − 0.099 I has a Cholesky factor.
            let mut shifted = a.clone();
            for i in 0..n {
                shifted[(i, i)] -= 0.099;
            }
            assert!(shifted.llt(faer::Side::Lower).is_ok(), "n = {n}");
        }
    }

    #[test]
    fn p_matrices_are_strictly_row_dominant() {
        let mut rng = SplitMix64::new(12);
        let a = random_p_matrix(9, &mut rng);
        for i in 0..9 {
            let off: f64 = (0..9).filter(|&j| j != i).map(|j| a[(i, j)].abs()).sum();
            assert!(a[(i, i)] >= 1.1 * off + 0.1 - 1e-12, "row {i}");
        }
    }

    #[test]
    fn planted_solutions_are_complementary_and_seeded() {
        for degenerate in [false, true] {
            let mut rng = SplitMix64::new(13);
            let (lcp, z) = planted(random_spd(8, &mut rng), &mut rng, degenerate);
            let mut again = SplitMix64::new(13);
            let (lcp2, z2) = planted(random_spd(8, &mut again), &mut again, degenerate);
            assert_eq!((lcp.q(), &z), (lcp2.q(), &z2));
            let (m, q) = (lcp.m(), lcp.q());
            for i in 0..8 {
                let w: f64 = q[i] + (0..8).map(|j| m[(i, j)] * z[j]).sum::<f64>();
                assert!(z[i] >= 0.0 && w >= -1e-12 && (z[i] * w).abs() < 1e-12, "row {i}");
                assert!(z[i] == 0.0 || z[i] >= 0.1);
            }
        }
    }

    #[test]
    fn murty_is_solved_by_the_last_unit_vector() {
        let s = Lemke::default().solve(&murty(6)).unwrap();
        assert_eq!(s.status, Status::Solved);
        assert_eq!(s.z, vec![0.0, 0.0, 0.0, 0.0, 0.0, 1.0]);
    }
}
