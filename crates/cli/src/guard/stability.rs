//! The stability limit of the divergence guard: the largest natural angular frequency ω_max of
//! the smooth dynamics at the initial state, ω_max² the largest eigenvalue of M⁻¹K with
//! K = −sym(∂h/∂q) by central differences (see the module [`super`]'s documentation).

use moreau_models::AnyModel;
use moreau_stepper::{BodyStructure, Mechanism};

use super::Scales;

/// The largest natural angular frequency ω_max (rad/s) of the smooth dynamics at the
/// model's initial state (see the module's documentation); 0 without stiffness.
///
/// A mechanism with a [`BodyStructure`] (maximal coordinates, M block-diagonal by body) never
/// forms an f × f matrix: K's columns are kept as their nonzero entries, and the eigenvalue
/// problem is solved on the coupled set S only, the bodies whose coordinates have a nonzero
/// row or column of sym(K). Every other coordinate has a zero row and column of M⁻¹ sym(K)
/// (M does not couple bodies), so that it adds only zero eigenvalues; ω_max = 0 when S is
/// empty (gravity alone has no stiffness). K's columns are differenced only for the bodies on
/// which h depends (found by shifting ranges of bodies at once, see
/// `stiffness_columns_by_body`). Memory is O(f + nnz(K) + |S|²), time O(|S| log n_b) calls
/// of h plus the dense method's O(|S|³). Other models take the dense method on all of q.
pub fn omega_max(model: &AnyModel) -> f64 {
    let (q0, u0) = model.initial_state();
    let f = q0.len();
    if let Some(structure) = by_body(model, f) {
        return omega_max_by_body(model, structure, &q0, &u0);
    }
    let mut m = vec![0.0; f * f];
    model.mass_matrix(&q0, 0.0, &mut m);
    let mut k = vec![0.0; f * f];
    let mut diff = Differences::new(model, &q0);
    stiffness_columns(model, &q0, &u0, 0..f, &mut diff, &mut |i, j, kij| k[i + f * j] = kij);
    largest_frequency(&m, &k, f)
}

/// The buffers of K's central differences: the shifted q, h at both shifts, and each
/// coordinate's unit (the model's length for a length, 1 for an angle, see [`Scales`]).
struct Differences {
    q: Vec<f64>,
    hp: Vec<f64>,
    hm: Vec<f64>,
    unit: Vec<f64>,
}

impl Differences {
    fn new(model: &AnyModel, q0: &[f64]) -> Self {
        let f = q0.len();
        let unit = (0..f).map(|j| Scales::coordinate(model, j)).collect();
        Self { q: q0.to_vec(), hp: vec![0.0; f], hm: vec![0.0; f], unit }
    }

    /// h at (q₀ ± δ, u₀, t = 0) into `hp` and `hm`, where δ shifts each coordinate j of
    /// `columns` by [`shift`]`(unit_j, q₀_j) · weight(j)`; q is left at q₀.
    fn evaluate(
        &mut self,
        model: &AnyModel,
        q0: &[f64],
        u0: &[f64],
        columns: std::ops::Range<usize>,
        weight: impl Fn(usize) -> f64,
    ) {
        for (sign, h) in [(1.0, &mut self.hp), (-1.0, &mut self.hm)] {
            for j in columns.clone() {
                self.q[j] = q0[j] + sign * shift(self.unit[j], q0[j]) * weight(j);
            }
            model.forces(&self.q, u0, 0.0, h);
        }
        self.q[columns.clone()].copy_from_slice(&q0[columns]);
    }
}

/// Calls `keep(i, j, K_ij)` for every nonzero entry of K = −∂h/∂q at (q₀, u₀, t = 0) in the
/// columns `columns`, by central differences, column j from a shift of q_j.
fn stiffness_columns(
    model: &AnyModel,
    q0: &[f64],
    u0: &[f64],
    columns: std::ops::Range<usize>,
    diff: &mut Differences,
    keep: &mut impl FnMut(usize, usize, f64),
) {
    for j in columns {
        let d = shift(diff.unit[j], q0[j]);
        diff.evaluate(model, q0, u0, j..j + 1, |_| 1.0);
        for (i, (p, m)) in diff.hp.iter().zip(&diff.hm).enumerate() {
            // Forces that do not depend on q_j are computed alike at both shifts, so that
            // their difference is exactly zero and the column keeps only real couplings.
            if p != m {
                keep(i, j, -(p - m) / (2.0 * d));
            }
        }
    }
}

/// The finite-difference shift of a coordinate of value `q` in a model whose unit for it is
/// `unit`.
fn shift(unit: f64, q: f64) -> f64 {
    1e-6 * (unit + q.abs())
}

/// [`stiffness_columns`] of a mechanism with a body structure, over the columns of the bodies
/// `bodies` only where h depends on their coordinates: all their coordinates are shifted at
/// once, each by its own amount (scaled by 1 + j/(3 n_b), so that no two columns can cancel
/// by symmetry), and a range whose shifts leave every entry of h exactly as it was (forces
/// that do not depend on these coordinates are computed alike) has zero columns; other
/// ranges are halved, down to single bodies, whose columns are differenced one by one. A pile
/// under gravity alone costs two evaluations of h instead of 2f, and k coupled bodies
/// O(k log n_b) evaluations besides their 6k.
fn stiffness_columns_by_body(
    model: &AnyModel,
    q0: &[f64],
    u0: &[f64],
    bodies: std::ops::Range<usize>,
    diff: &mut Differences,
    keep: &mut impl FnMut(usize, usize, f64),
) {
    let columns = 3 * bodies.start..3 * bodies.end;
    if bodies.len() <= 1 {
        return stiffness_columns(model, q0, u0, columns, diff, keep);
    }
    let f = q0.len() as f64;
    diff.evaluate(model, q0, u0, columns, |j| 1.0 + j as f64 / f);
    if diff.hp == diff.hm {
        return;
    }
    let mid = bodies.start + bodies.len() / 2;
    stiffness_columns_by_body(model, q0, u0, bodies.start..mid, diff, keep);
    stiffness_columns_by_body(model, q0, u0, mid..bodies.end, diff, keep);
}

/// The body structure of `model` when its f coordinates are its bodies' (x, y, θ), so that M
/// is block-diagonal by body.
pub(super) fn by_body(model: &AnyModel, f: usize) -> Option<&dyn BodyStructure> {
    model.body_structure().filter(|s| 3 * s.num_bodies() == f)
}

/// ω_max on the coupled set of a mechanism with a body structure (see [`omega_max`]).
fn omega_max_by_body(
    model: &AnyModel,
    structure: &dyn BodyStructure,
    q0: &[f64],
    u0: &[f64],
) -> f64 {
    let mut entries = Vec::new();
    let nb = structure.num_bodies();
    let mut diff = Differences::new(model, q0);
    let mut keep = |i, j, kij| entries.push((i, j, kij));
    stiffness_columns_by_body(model, q0, u0, 0..nb, &mut diff, &mut keep);
    // Sorted by (row, column), so that K_ji is found by a binary search for each K_ij.
    entries.sort_by_key(|&(i, j, _)| (i, j));
    let at = |i: usize, j: usize| {
        entries.binary_search_by_key(&(i, j), |&(r, c, _)| (r, c)).map_or(0.0, |p| entries[p].2)
    };
    let mut coupled = vec![false; nb];
    for &(i, j, kij) in &entries {
        if kij + at(j, i) != 0.0 {
            coupled[i / 3] = true;
            coupled[j / 3] = true;
        }
    }
    // Each coupled body's place in S, `NOT_COUPLED` for the others.
    const NOT_COUPLED: usize = usize::MAX;
    let mut place = vec![NOT_COUPLED; nb];
    let mut s = 0;
    for (p, &c) in place.iter_mut().zip(&coupled) {
        if c {
            *p = s;
            s += 1;
        }
    }
    if s == 0 {
        return 0.0;
    }
    let n = 3 * s;
    let mut blocks = vec![[0.0; 9]; nb];
    structure.mass_blocks(q0, 0.0, &mut blocks);
    let mut m = vec![0.0; n * n];
    for (block, &p) in blocks.iter().zip(&place).filter(|(_, p)| **p != NOT_COUPLED) {
        for c in 0..3 {
            for r in 0..3 {
                m[3 * p + r + n * (3 * p + c)] = block[r + 3 * c];
            }
        }
    }
    let mut k = vec![0.0; n * n];
    let local = |i: usize| place[i / 3].checked_mul(3).map(|b| b + i % 3);
    for &(i, j, kij) in &entries {
        // An entry whose symmetric part vanishes may join S's body to one outside it.
        if let (Some(a), Some(b)) = (local(i), local(j)) {
            k[a + n * b] = kij;
        }
    }
    largest_frequency(&m, &k, n)
}

/// The square root of the largest eigenvalue of M⁻¹ sym(K) (0 when none is positive or M is
/// not SPD), for dense column-major n × n matrices M (SPD) and K: the eigenvalues of
/// A = L⁻¹ sym(K) L⁻ᵀ with M = L Lᵀ, a symmetric matrix, by faer's Cholesky factor and
/// self-adjoint eigenvalues.
fn largest_frequency(m: &[f64], k: &[f64], f: usize) -> f64 {
    use faer::{Mat, Side};
    if f == 0 {
        return 0.0;
    }
    let m = Mat::from_fn(f, f, |i, j| m[i + f * j]);
    let Ok(llt) = m.llt(Side::Lower) else { return 0.0 };
    let l = llt.L();
    // L⁻¹ sym(K), then (L⁻¹ (L⁻¹ sym(K))ᵀ) = L⁻¹ sym(K) L⁻ᵀ, sym(K) being symmetric.
    let mut a = Mat::from_fn(f, f, |i, j| 0.5 * (k[i + f * j] + k[j + f * i]));
    l.solve_lower_triangular_in_place(a.as_mut());
    let mut a = a.transpose().to_owned();
    l.solve_lower_triangular_in_place(a.as_mut());
    match a.self_adjoint_eigenvalues(Side::Lower) {
        Ok(e) => e.into_iter().fold(0.0, f64::max).sqrt(),
        Err(_) => 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn largest_frequency_of_a_planted_pencil() {
        // K = M^½ Q diag(1, 4, 9) Qᵀ M^½ with M = diag(4, 1, 9) and Q a rotation by 0.3 in the
        // (0, 2) plane: M⁻¹ K is similar to Q diag(1, 4, 9) Qᵀ, so ω_max = √9 = 3; K is given
        // unsymmetric (its symmetric part counts) and M not SPD gives 0.
        let (c, s) = (0.3f64.cos(), 0.3f64.sin());
        let d = [1.0, 4.0, 9.0];
        let q = [c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c];
        let root = [2.0, 1.0, 3.0];
        let mut m = vec![0.0; 9];
        let mut k = vec![0.0; 9];
        for i in 0..3 {
            m[i + 3 * i] = root[i] * root[i];
            for j in 0..3 {
                let a: f64 = (0..3).map(|p| q[i + 3 * p] * d[p] * q[j + 3 * p]).sum();
                k[i + 3 * j] = root[i] * a * root[j]
                    + if i < j {
                        0.25
                    } else if i > j {
                        -0.25
                    } else {
                        0.0
                    };
            }
        }
        assert!((largest_frequency(&m, &k, 3) - 3.0).abs() < 1e-12);
        let k_neg: Vec<f64> = k.iter().map(|x| -x).collect();
        assert_eq!(largest_frequency(&m, &k_neg, 3), 0.0);
        m[4] = -1.0;
        assert_eq!(largest_frequency(&m, &k, 3), 0.0);
        assert_eq!(largest_frequency(&[], &[], 0), 0.0);
    }
}
