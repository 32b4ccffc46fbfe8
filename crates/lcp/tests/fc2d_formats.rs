//! Siconos' FC2D, GFC2D and LCP files: every file of the collection is read, and the
//! readers agree with each other across storages.

use std::fs::File;
use std::path::PathBuf;

use faer::Mat;
use moreau_lcp::fc2d::{
    Fc2d, Fc2dBuilder, Fc2dParts, Fc2dRef, Fc2dResidual, Gfc2d, SiconosStorage,
};
use moreau_lcp::{Lcp, LcpError};

fn data(dir: &str) -> Vec<PathBuf> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/siconos").join(dir);
    let mut files: Vec<PathBuf> = std::fs::read_dir(root)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "dat"))
        .collect();
    files.sort();
    files
}

fn name(p: &std::path::Path) -> String {
    p.file_name().unwrap().to_string_lossy().into_owned()
}

/// (file, contacts, stored 2x2 blocks) of every reduced FC2D file, counted from the files.
const FC2D_FILES: &[(&str, usize, usize)] = &[
    ("FC2D_SliderCrankLagrangian00000.dat", 2, 4),
    ("FC2D_SliderCrankLagrangian00001.dat", 2, 4),
    ("FrictionContactProblem00031.dat", 11, 15),
    ("FrictionContactProblem00071.dat", 89, 0),
    ("FrictionContactProblem00237.dat", 376, 0),
    ("FrictionContactProblem00374.dat", 28, 0),
    ("FrictionContactProblem00394.dat", 6, 0),
    ("FrictionContactProblem00727.dat", 367, 0),
    ("fc2d_granularflowonwall_00667_00000.dat", 667, 0),
    ("fc2d_granularflowonwall_02020_00213.dat", 2020, 0),
    ("fc2d_granularflowonwall_07002_00801.dat", 7002, 0),
];

#[test]
fn every_fc2d_file_is_read_and_validated() {
    let files: Vec<PathBuf> =
        data("fc2d").into_iter().filter(|p| !name(p).starts_with("gfc2d")).collect();
    assert_eq!(files.len(), FC2D_FILES.len());
    for path in files {
        let problem = Fc2d::read_siconos(File::open(&path).unwrap())
            .unwrap_or_else(|e| panic!("{}: {e}", name(&path)));
        let &(_, contacts, blocks) =
            FC2D_FILES.iter().find(|f| f.0 == name(&path)).expect("file listed");
        assert_eq!(problem.n_contacts(), contacts, "{}", name(&path));
        println!("{}: {} contacts, {} blocks", name(&path), contacts, problem.n_blocks());
        if blocks > 0 {
            assert_eq!(problem.n_blocks(), blocks, "{}", name(&path));
        }
        // Every storage writes and reads back to the same problem.
        for storage in [SiconosStorage::SparseBlock, SiconosStorage::Sparse] {
            let mut text = Vec::new();
            problem.write_siconos(&mut text, storage).unwrap();
            let back = Fc2d::read_siconos(text.as_slice()).unwrap();
            assert_eq!(back, problem, "{} through {storage:?}", name(&path));
        }
        if contacts <= 100 {
            let mut text = Vec::new();
            problem.write_siconos(&mut text, SiconosStorage::Dense).unwrap();
            let back = Fc2d::read_siconos(text.as_slice()).unwrap();
            assert_eq!(back.view().to_dense(), problem.view().to_dense(), "{}", name(&path));
        }
    }
}

#[test]
fn global_files_reduce_to_the_contact_space() {
    let files: Vec<PathBuf> =
        data("fc2d").into_iter().filter(|p| name(p).starts_with("gfc2d")).collect();
    assert_eq!(files.len(), 3);
    for path in files {
        let global = Gfc2d::read_siconos(File::open(&path).unwrap()).unwrap();
        let reduced = global.reduce().unwrap();
        let p = reduced.problem.view();
        assert_eq!(p.n_contacts(), global.n_contacts());
        // For some r, u = W r + q_W must equal Hᵀ v + b with M v = q + H r.
        let r: Vec<f64> = (0..p.n_rows()).map(|k| ((k * 7 % 5) as f64 - 1.5) * 1e-3).collect();
        let mut u = vec![0.0; p.n_rows()];
        p.velocity(&r, &mut u);
        let v = reduced.global_velocity(&global, &r);
        let (m, h) = (global.m(), global.h());
        let mut mv = vec![0.0; v.len()];
        for j in 0..v.len() {
            for (i, x) in m.row_idx_of_col(j).zip(m.val_of_col(j)) {
                mv[i] += x * v[j];
            }
        }
        let mut hr = global.q().to_vec();
        let mut htv = global.b().to_vec();
        for j in 0..r.len() {
            for (i, x) in h.row_idx_of_col(j).zip(h.val_of_col(j)) {
                hr[i] += x * r[j];
                htv[j] += x * v[i];
            }
        }
        let scale = hr.iter().fold(1e-300f64, |a, x| a.max(x.abs()));
        for i in 0..v.len() {
            assert!((mv[i] - hr[i]).abs() <= 1e-10 * scale, "{}: M v != q + H r", name(&path));
        }
        let scale = htv.iter().fold(1e-300f64, |a, x| a.max(x.abs()));
        for k in 0..u.len() {
            assert!((u[k] - htv[k]).abs() <= 1e-9 * scale, "{}: row {k}", name(&path));
        }
    }
}

#[test]
fn block_lcp_files_equal_their_dense_twins() {
    for (block, dense) in [
        ("lcp_deudeu_block.dat", "lcp_deudeu.dat"),
        ("lcp_ortiz_block.dat", "lcp_ortiz.dat"),
        ("lcp_trivial_block.dat", "lcp_trivial.dat"),
    ] {
        let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/siconos/lcp");
        let a = Lcp::read_siconos(File::open(dir.join(block)).unwrap()).unwrap();
        let text = std::fs::read_to_string(dir.join(dense)).unwrap();
        let b = Lcp::read_any(&text).unwrap();
        assert_eq!(a, b, "{block}");
    }
    for path in data("lcp") {
        let text = std::fs::read_to_string(&path).unwrap();
        Lcp::read_any(&text).unwrap_or_else(|e| panic!("{}: {e}", name(&path)));
    }
}

#[test]
fn read_any_names_both_formats() {
    // A Siconos header with a storage type that does not exist.
    let err = Lcp::read_any("2\n7\n2\n2\n2 2\n1 0 0 1\n-1 -1\n").unwrap_err();
    let text = err.to_string();
    assert!(matches!(err, LcpError::UnknownFormat { .. }), "{text}");
    assert!(text.contains("storage type 7") && text.contains("after q"), "{text}");
    // A non-square Siconos matrix.
    let err = Lcp::read_any("2\n0\n2\n3\n2 3\n1 0 0 1 0 0\n-1 -1\n").unwrap_err();
    assert!(err.to_string().contains("2 x 3"), "{err}");
    // A plain file whose n is too small for its data is not taken for a Siconos file.
    let err = Lcp::read_any("1\n2\n3\n4 5\n").unwrap_err();
    assert!(matches!(err, LcpError::UnknownFormat { .. }), "{err}");
}

#[test]
fn validation_names_the_problem() {
    let w = Mat::from_fn(2, 2, |i, j| [[1.0, 0.5], [0.2, 1.0]][i][j]);
    let err = Fc2d::from_dense(w.as_ref(), &[0.0, 0.0], &[0.1]).unwrap_err();
    assert!(
        matches!(err, LcpError::NotPositiveSemidefinite { what: "contact", index: 0, .. }),
        "{err}"
    );
    let w = Mat::from_fn(2, 2, |i, j| [[1.0, 2.0], [2.0, 1.0]][i][j]);
    let err = Fc2d::from_dense(w.as_ref(), &[0.0, 0.0], &[0.1]).unwrap_err();
    assert!(err.to_string().contains("determinant"), "{err}");
    let w = Mat::<f64>::identity(2, 2);
    let err = Fc2d::from_dense(w.as_ref(), &[0.0, 0.0], &[-0.1]).unwrap_err();
    assert!(matches!(err, LcpError::NegativeFriction { contact: 0, .. }), "{err}");
    let err = Fc2d::from_dense(w.as_ref(), &[0.0, f64::NAN], &[0.1]).unwrap_err();
    assert!(matches!(err, LcpError::NonFinite { what: "q", index: (1, 0) }), "{err}");
    let err = Fc2d::from_dense(w.as_ref(), &[0.0], &[0.1]).unwrap_err();
    assert!(matches!(err, LcpError::DimensionMismatch { what: "q", .. }), "{err}");
    // A relative asymmetry below the documented tolerance is accepted.
    let w = Mat::from_fn(2, 2, |i, j| [[1000.0, 1.0], [1.004, 500.0]][i][j]);
    assert!(Fc2d::from_dense(w.as_ref(), &[0.0, 0.0], &[0.1]).is_ok());
    let mut b = Fc2dBuilder::new(1);
    b.add_block(0, 0, [1.0, f64::INFINITY, 0.0, 1.0]);
    let err = b.build(&[0.0, 0.0], &[0.1]).unwrap_err();
    assert!(matches!(err, LcpError::NonFinite { what: "W", index: (0, 1) }), "{err}");
}

#[test]
fn a_builders_entry_outside_the_declared_rows_is_refused_by_build_naming_it() {
    // One contact has rows 0 and 1: W_55 and W_02 are in no group; add_entry panicked.
    for (i, j) in [(5, 5), (0, 2), (2, 0)] {
        let mut b = Fc2dBuilder::new(1);
        b.add_entry(0, 0, 1.0);
        b.add_entry(1, 1, 1.0);
        b.add_entry(i, j, 0.5);
        b.add_entry(7, 7, 0.5); // a second one: the first is named
        let err = b.build(&[-1.0, 0.0], &[0.3]).unwrap_err();
        let expected = format!(
            "entry ({i}, {j}) is outside the 2 rows of the groups declared when it was added"
        );
        assert!(matches!(&err, LcpError::Structure(m) if *m == expected), "{err}");
    }
    // Row 2 is a row once its bilateral group is declared, and the entries in it count.
    let mut b = Fc2dBuilder::new(1);
    b.bilateral_group(1);
    b.add_entry(0, 0, 2.0);
    b.add_entry(1, 1, 2.0);
    b.add_entry(2, 2, 4.0);
    let problem = b.build(&[-1.0, 0.0, 2.0], &[0.3]).unwrap();
    assert_eq!(problem.view().to_dense(), vec![2.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 4.0]);
}

#[test]
fn a_builders_block_is_kept_in_the_groups_it_names_or_refused() {
    // Group 2^32 is no group of a one-contact problem: refused, not taken for group 0.
    let far = 1usize << 32;
    for (row, col) in [(far, 0), (0, far), (far + 1, far)] {
        let mut b = Fc2dBuilder::new(1);
        b.add_block(0, 0, [1.0, 0.0, 0.0, 1.0]);
        b.add_block(row, col, [5.0, 0.0, 0.0, 5.0]);
        let err = b.build(&[-1.0, 0.0], &[0.3]).unwrap_err();
        let expected = format!("block ({row}, {col}) outside the 1 groups");
        assert!(matches!(&err, LcpError::Structure(m) if *m == expected), "{err}");
    }
    // A bilateral group of an absurd number of rows is reported, not an overflow.
    let mut b = Fc2dBuilder::new(1);
    b.bilateral_group(usize::MAX);
    b.add_block(0, 0, [1.0, 0.0, 0.0, 1.0]);
    let err = b.build(&[-1.0, 0.0, 0.0], &[0.3]).unwrap_err();
    let rows = format!("group 1 has {} rows, from 2 to {}", usize::MAX - 2, usize::MAX);
    assert!(matches!(&err, LcpError::Structure(m) if m.starts_with(&rows)), "{err}");
    // Parts that announce more contacts than any slice can hold, or groups that go back.
    let n_contacts = usize::MAX;
    let parts = |n_contacts, group_start| Fc2dParts {
        n_contacts,
        group_start,
        row_ptr: &[0, 1],
        col: &[0],
        blocks: &[[1.0, 0.0, 0.0, 1.0]],
        q: &[-1.0, 0.0],
        mu: &[0.3],
    };
    let err = Fc2dRef::from_parts(parts(n_contacts, &[0, 2])).unwrap_err();
    let expected = format!("2 group starts for {n_contacts} contacts");
    assert!(matches!(&err, LcpError::Structure(m) if *m == expected), "{err}");
    let err = Fc2dRef::from_parts(parts(0, &[0, 2, 1])).unwrap_err();
    let expected = "group 1 has -1 rows, from 2 to 1";
    assert!(matches!(&err, LcpError::Structure(m) if m.starts_with(expected)), "{err}");
    // Blocks within the groups, given in any order and repeated, add up where they name.
    let mut b = Fc2dBuilder::new(2);
    b.add_block(1, 1, [1.0, 0.0, 0.0, 1.0]);
    b.add_block(0, 0, [2.0, 0.0, 0.0, 2.0]);
    b.add_block(1, 1, [1.0, 0.0, 0.0, 1.0]);
    let problem = b.build(&[-1.0, 0.0, -1.0, 0.0], &[0.3, 0.3]).unwrap();
    let dense = problem.view().to_dense();
    assert_eq!((dense[0], dense[5], dense[10], dense[15]), (2.0, 2.0, 2.0, 2.0));
}

#[test]
fn the_natural_map_weighs_an_approaching_sliding_contact_by_one_over_sqrt_one_plus_mu_squared() {
    // W = I, q = (-1, 1) and r = 0: u = (-1, 1), a contact sliding into the ground.
    let w = Mat::<f64>::identity(2, 2);
    for mu in [0.0, 0.5, 1.0, 10.0, 1e3, 1e9] {
        let problem = Fc2d::from_dense(w.as_ref(), &[-1.0, 1.0], &[mu]).unwrap();
        let mut u = vec![0.0; 2];
        let r = Fc2dResidual::compute(problem.view(), &[0.0, 0.0], &mut u);
        let expected = 1.0 / (1.0 + mu * mu).sqrt();
        assert!((r.natural - expected).abs() <= 1e-15 * expected, "μ = {mu}: {r:?}");
    }
    // And velocities below 1 are measured absolutely: W = 1e-12 I, q = (-1e-12, 0), whose
    // solution is r = (1, 0), has natural 1e-12 at r = 0.
    let tiny = Mat::from_fn(2, 2, |i, j| if i == j { 1e-12 } else { 0.0 });
    let problem = Fc2d::from_dense(tiny.as_ref(), &[-1e-12, 0.0], &[0.5]).unwrap();
    let mut u = vec![0.0; 2];
    assert_eq!(Fc2dResidual::compute(problem.view(), &[0.0, 0.0], &mut u).natural, 1e-12);
    assert_eq!(Fc2dResidual::compute(problem.view(), &[1.0, 0.0], &mut u).natural, 0.0);
}

#[test]
fn residual_is_zero_at_planted_solutions_and_siconos_normalised() {
    // One contact, W = I: slip with r = (1, -0.5), μ = 0.5, u = (0, 2): q = u - r.
    let w = Mat::<f64>::identity(2, 2);
    let p = Fc2d::from_dense(w.as_ref(), &[-1.0, 2.5], &[0.5]).unwrap();
    let mut u = vec![0.0; 2];
    let res = Fc2dResidual::compute(p.view(), &[1.0, -0.5], &mut u);
    assert_eq!(u, vec![0.0, 2.0]);
    assert_eq!(res.natural, 0.0);
    // r = 0 there: u = q, the natural map is -proj_K(-(q + μ |q_T| e_N)) = -proj_K(-0.25, -2.5)
    // = -(t, -μ t) with t = (-0.25 + 1.25) / 1.25 = 0.8.
    let res = Fc2dResidual::compute(p.view(), &[0.0, 0.0], &mut u);
    let e = (0.8f64.powi(2) + 0.4f64.powi(2)).sqrt();
    assert!((res.absolute - e).abs() < 1e-15);
    assert!((res.natural - e / 2.5).abs() < 1e-15);
    let scale = (1.0f64 + 2.5 * 2.5).sqrt();
    assert!((res.siconos - e / scale).abs() < 1e-15);
    // An r or u of a length other than the problem's 2 rows is measured as infinite, u
    // untouched, where it panicked.
    let mut short = vec![7.0];
    assert_eq!(Fc2dResidual::compute(p.view(), &[1.0, -0.5], &mut short), Fc2dResidual::INFINITE);
    assert_eq!(short, vec![7.0]);
    assert_eq!(Fc2dResidual::compute(p.view(), &[1.0], &mut u), Fc2dResidual::INFINITE);
    assert!(!Fc2dResidual::INFINITE.meets(1.0));
}
