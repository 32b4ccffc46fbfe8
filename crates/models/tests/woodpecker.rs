//! The woodpecker toy reaches a periodic motion and walks down the pole (docs/theory.md §7.2).

use moreau_models::*;
use moreau_testsupport::{onsets, up_crossings};

fn run(dt: f64, t_end: f64) -> Simulation {
    let mut scene = Scene::report(ModelKind::Woodpecker);
    scene.dt = dt;
    scene.t_end = t_end;
    scene.run().unwrap()
}

/// Periods between successive up-crossings of φ_S = 0, after the first two cycles.
fn periods(sim: &Simulation) -> (Vec<f64>, Vec<f64>) {
    let crossings = up_crossings(&sim.record, 2, 0.0);
    let p: Vec<f64> = crossings.windows(2).map(|w| w[1] - w[0]).skip(2).collect();
    (p, crossings)
}

fn spread(p: &[f64]) -> f64 {
    p.windows(2).map(|w| (w[1] - w[0]).abs() / w[0]).fold(0.0, f64::max)
}

#[test]
fn woodpecker_settles_into_a_periodic_motion_down_the_pole() {
    let coarse = run(1e-4, 1.5);
    let fine = run(2e-5, 1.5);
    let (pc, crossings) = periods(&coarse);
    let (pf, _) = periods(&fine);
    assert!(pc.len() >= 6 && pf.len() >= 6);
    let mean_c = pc.iter().sum::<f64>() / pc.len() as f64;
    let mean_f = pf.iter().sum::<f64>() / pf.len() as f64;
    let (sc, sf) = (spread(&pc), spread(&pf));
    eprintln!(
        "woodpecker period: {mean_c:.5} s (dt 1e-4, successive periods within {:.3}%), \
         {mean_f:.5} s (dt 2e-5, within {:.3}%)",
        100.0 * sc,
        100.0 * sf
    );
    // The cycle-to-cycle jitter comes from the penetration the midpoint rule leaves at each
    // impact (up to ~2e-5 m at dt = 1e-4 against a 0.6 mm clearance); it shrinks with dt.
    assert!(sc < 1e-2, "dt 1e-4: successive periods differ by {sc}");
    assert!(sf < 2e-3, "dt 2e-5: successive periods differ by {sf}");
    assert!(sf < sc);
    // The mean period converges to first order in Δt.
    assert!((mean_c - mean_f).abs() / mean_f < 5e-3, "{mean_c} vs {mean_f}");

    // One beak impact per period, always the same sequence of contact onsets.
    let r = &coarse.record;
    let beak = onsets(r, 0);
    assert!(beak.len() >= pc.len());
    let per_cycle: Vec<[usize; 3]> = beak
        .windows(2)
        .skip(1)
        .map(|w| {
            let mut n = [0; 3];
            for (i, slot) in n.iter_mut().enumerate() {
                *slot = onsets(r, i).iter().filter(|&&k| k >= w[0] && k < w[1]).count();
            }
            n
        })
        .collect();
    assert!(per_cycle.windows(2).all(|w| w[0] == w[1]), "{per_cycle:?}");
    assert_eq!(per_cycle[0][0], 1);

    // The sleeve goes down: mean velocity over whole periods is negative, and each period
    // drops it by the same height.
    let k0 = r.t.iter().position(|&t| t >= crossings[2]).unwrap();
    let k1 = r.t.iter().position(|&t| t >= *crossings.last().unwrap()).unwrap();
    let mean_v = (r.q[k1][0] - r.q[k0][0]) / (r.t[k1] - r.t[k0]);
    eprintln!("woodpecker mean descent speed: {mean_v:.4} m/s");
    assert!(mean_v < 0.0);
    let v_mean_from_u: f64 = r.u.column(0).take(k1).skip(k0).sum::<f64>() / (k1 - k0) as f64;
    assert!(v_mean_from_u < 0.0);
}

#[test]
fn woodpecker_without_its_beak_contact_has_a_smaller_lcp() {
    let mut scene = Scene::report(ModelKind::Woodpecker);
    scene.t_end = 0.05;
    scene.set("beak_contact", "false").unwrap();
    let sim = scene.run().unwrap();
    assert_eq!(sim.model.contact_names(), vec!["lower sleeve edge", "upper sleeve edge"]);
    assert!(sim.record.lcp_size.iter().all(|&s| s <= 6));
    assert!(sim.record.p_n.iter().all(|p| p.len() == 2));
}
