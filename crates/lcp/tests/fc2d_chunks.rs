//! Problems of more groups than one chunk of the per-group work (1,024 groups): the checks of
//! the parts, u = W r + q, the residual and a solve give the same bits on pools of one and of
//! several threads, agree with plain loops, and the first error in group order is reported.

mod common;

use common::Rng;
use moreau_lcp::LcpError;
use moreau_lcp::fc2d::{
    Fc2d, Fc2dBuilder, Fc2dParts, Fc2dRef, Fc2dResidual, Fc2dSolution, Fc2dSolver, Nsgs,
    NsgsOptions,
};

/// A chain of n_c + 1 bodies of random diagonal mass: contact i touches bodies i and i + 1,
/// each through a random 2 × 3 Jacobian, and a two-row joint group acts on the last two
/// bodies; W = H M⁻¹ Hᵀ + 0.05 I by blocks (row groups i and j couple when they share a
/// body), q random.
fn chain(n_c: usize, rng: &mut Rng) -> Fc2d {
    let groups = n_c + 1;
    let bodies = n_c + 1;
    let inv: Vec<[f64; 3]> =
        (0..bodies).map(|_| [0.0; 3].map(|_: f64| 1.0 / rng.uniform(0.5, 2.0))).collect();
    // The two bodies of each group and the group's rows on each: h[g][side][row][k].
    let on = |g: usize| if g < n_c { [g, g + 1] } else { [n_c - 1, n_c] };
    let h: Vec<[[[f64; 3]; 2]; 2]> = (0..groups)
        .map(|_| [[[0.0; 3]; 2]; 2].map(|side| side.map(|row| row.map(|_| rng.uniform(-1.0, 1.0)))))
        .collect();
    let mut builder = Fc2dBuilder::new(n_c);
    builder.bilateral_group(2);
    for i in 0..groups {
        for j in i.saturating_sub(2)..(i + 3).min(groups) {
            let mut block = [0.0; 4];
            for (si, &bi) in on(i).iter().enumerate() {
                for (sj, &bj) in on(j).iter().enumerate() {
                    if bi != bj {
                        continue;
                    }
                    for a in 0..2 {
                        for c in 0..2 {
                            block[2 * a + c] += (0..3)
                                .map(|k| h[i][si][a][k] * inv[bi][k] * h[j][sj][c][k])
                                .sum::<f64>();
                        }
                    }
                }
            }
            if i == j {
                block[0] += 0.05;
                block[3] += 0.05;
            }
            if block != [0.0; 4] || i == j {
                builder.add_block(i, j, block);
            }
        }
    }
    let q: Vec<f64> = (0..2 * groups).map(|_| rng.uniform(-1.0, 1.0)).collect();
    let mu: Vec<f64> = (0..n_c).map(|_| rng.uniform(0.0, 0.8)).collect();
    builder.build(&q, &mu).unwrap()
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap()
}

/// u = W r + q by a plain loop over the stored blocks.
fn velocity_by_loop(p: Fc2dRef<'_>, r: &[f64]) -> Vec<f64> {
    let mut u = p.q().to_vec();
    p.for_each_entry(|i, j, v| u[i] += v * r[j]);
    u
}

#[test]
fn products_residuals_and_solves_do_not_depend_on_the_pool() {
    let mut rng = Rng::new(7);
    let problem = chain(3_000, &mut rng);
    let p = problem.view();
    assert!(p.n_groups() > 2 * 1024);
    let r: Vec<f64> = (0..p.n_rows()).map(|_| rng.uniform(-1.0, 1.0)).collect();
    let run = |threads: usize| {
        pool(threads).install(|| {
            let mut u = vec![0.0; p.n_rows()];
            let residual = Fc2dResidual::compute(p, &r, &mut u);
            let mut nsgs = Nsgs::new(NsgsOptions::default().with_tolerance(1e-10)).unwrap();
            let mut out = Fc2dSolution::new();
            nsgs.solve_into(p, None, &mut out).unwrap();
            (u, residual, out)
        })
    };
    let (u_1, res_1, out_1) = run(1);
    for threads in [2, 3] {
        let (u, res, out) = run(threads);
        assert_eq!(u, u_1);
        assert_eq!(res, res_1);
        assert_eq!(
            (&out.r, &out.u, out.iterations, out.residual),
            (&out_1.r, &out_1.u, out_1.iterations, out_1.residual)
        );
    }
    // The chunked product agrees with a plain loop to rounding, and the residual's largest
    // natural map with one recomputed contact by contact.
    let plain = velocity_by_loop(p, &r);
    let scale = plain.iter().fold(1.0f64, |m, v| m.max(v.abs()));
    assert!(u_1.iter().zip(&plain).all(|(a, b)| (a - b).abs() <= 1e-13 * scale));
    assert!(res_1.absolute > 0.0 && res_1.worst_group < p.n_groups());
    let mut absolute = 0.0f64;
    let mut sum = 0.0;
    for i in 0..p.n_contacts() {
        let (x_n, x_t) = (
            r[2 * i] - u_1[2 * i] - p.mu()[i] * u_1[2 * i + 1].abs(),
            r[2 * i + 1] - u_1[2 * i + 1],
        );
        let mu = p.mu()[i];
        let (p_n, p_t) = if x_t.abs() <= mu * x_n {
            (x_n, x_t)
        } else if mu * x_t.abs() <= -x_n {
            (0.0, 0.0)
        } else {
            let n = (x_n + mu * x_t.abs()) / (1.0 + mu * mu);
            (n, (mu * n).copysign(x_t))
        };
        let e2 = (r[2 * i] - p_n).powi(2) + (r[2 * i + 1] - p_t).powi(2);
        absolute = absolute.max(e2.sqrt());
        sum += e2;
    }
    for &v in &u_1[2 * p.n_contacts()..] {
        absolute = absolute.max(v.abs());
        sum += v * v;
    }
    assert_eq!(res_1.absolute, absolute);
    let norm = |x: &[f64]| x.iter().map(|v| v * v).sum::<f64>().sqrt();
    let siconos = sum.sqrt() / norm(&r).max(norm(&u_1)).max(norm(p.q()));
    assert!((res_1.siconos - siconos).abs() <= 1e-14 * siconos);
    assert_eq!(out_1.status, moreau_lcp::Status::Solved);
    assert!(out_1.residual.natural <= 1e-10);
}

#[test]
fn the_first_error_in_group_order_is_reported_on_any_pool() {
    let mut rng = Rng::new(11);
    let problem = chain(3_000, &mut rng);
    let parts = problem.view().parts();
    let check = |col: &[u32], blocks: &[[f64; 4]]| {
        let bad = Fc2dParts { col, blocks, ..parts };
        let one = pool(1).install(|| Fc2dRef::from_parts(bad).map(|_| ()));
        let two = pool(2).install(|| Fc2dRef::from_parts(bad).map(|_| ()));
        assert_eq!(format!("{one:?}"), format!("{two:?}"));
        one
    };
    assert!(check(parts.col, parts.blocks).is_ok());
    // A non-finite block in group 2,500 and an indefinite diagonal block in group 2,900.
    let mut blocks = parts.blocks.to_vec();
    let late = parts.row_ptr[2_900]..parts.row_ptr[2_901];
    let d = late.clone().find(|&k| parts.col[k] == 2_900).unwrap();
    blocks[d][0] = -1.0;
    let nan = parts.row_ptr[2_500];
    blocks[nan][3] = f64::NAN;
    let row = parts.group_start[2_500] + 1;
    let col = parts.group_start[parts.col[nan] as usize] + 1;
    assert!(matches!(
        check(parts.col, &blocks),
        Err(LcpError::NonFinite { what: "W", index }) if index == (row, col)
    ));
    // With the non-finite block gone, the diagonal block of group 2,900.
    blocks[nan][3] = parts.blocks[nan][3];
    assert!(matches!(
        check(parts.col, &blocks),
        Err(LcpError::NotPositiveSemidefinite { what: "contact", index: 2_900, .. })
    ));
    // A column out of order in group 1,500 comes before both.
    blocks[nan][3] = f64::NAN;
    let mut col = parts.col.to_vec();
    let k = parts.row_ptr[1_500];
    col.swap(k, k + 1);
    match check(&col, &blocks) {
        Err(LcpError::Structure(message)) => assert!(message.contains("group 1500"), "{message}"),
        other => panic!("{other:?}"),
    }
}
