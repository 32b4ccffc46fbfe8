//! The cam-follower (docs/theory.md §7.4): the first impact against the closed-form free fall,
//! bounded penetration and persistent contact between drops; the variant with the spring law
//! as printed against its own closed-form fall, riding the end of each lobe.

use moreau_kinematics::ContactKinematics;
use moreau_models::*;
use moreau_testsupport::onsets;
use std::f64::consts::TAU;

#[test]
fn first_impact_matches_the_closed_form_fall() {
    let p = CamParams::report();
    let sim = Scene::report(ModelKind::Cam).run().unwrap();
    // Free motion from rest at y0 = H under gravity and the spring:
    // y(t) = (H + m g/K) cos(ω_n t) − m g/K with ω_n = sqrt(K/m); contact when y(t) = s(t).
    let wn = (p.ks / p.m).sqrt();
    let st = p.m * p.g / p.ks;
    let gap = |t: f64| (p.stroke + st) * (wn * t).cos() - st - p.lift(t);
    let (mut lo, mut hi) = (0.0, std::f64::consts::PI / wn);
    assert!(gap(lo) > 0.0 && gap(hi) < 0.0);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if gap(mid) > 0.0 { lo = mid } else { hi = mid }
    }
    let t_hit = onsets(&sim.record, 0)[0];
    let t_num = sim.record.t[t_hit];
    eprintln!("cam: first impact at {t_num:.4} s, closed form {lo:.5} s");
    assert!((t_num - lo).abs() <= 2.0 * sim.record.t[1], "{t_num} vs {lo}");
}

#[test]
fn follower_never_penetrates_more_than_a_step_and_rests_between_drops() {
    let mut scene = Scene::report(ModelKind::Cam);
    scene.t_end = 0.16;
    let p = CamParams::report();
    let dt = scene.dt;
    let sim = scene.run().unwrap();
    let (r, m) = (&sim.record, &sim.model);
    let mut pen = 0.0f64;
    let mut speed = 0.0f64;
    for k in 0..r.len() {
        pen = pen.max(-m.normal_gap(0, &r.q[k], r.t[k]));
        speed = speed.max((r.u[k][0] - p.lift_rate(r.t[k])).abs());
    }
    eprintln!("cam: largest penetration {pen:.3e} m, bound {:.3e} m", speed * dt);
    assert!(pen <= speed * dt);
    // In the last quarter of each lobe the follower rides on the cam: the contact is closed
    // and carries an impulse at every step, and the relative velocity is that of the cam
    // between t_M and t_E, at most max|s''| Δt/2 with max|s''| = 2π H ω²/β².
    let s2 = TAU * p.stroke * p.omega * p.omega / (p.beta * p.beta);
    let lobes = (r.t.last().unwrap() / p.lobe_period()).floor() as usize;
    assert_eq!(lobes, 3);
    for lobe in 0..lobes {
        let (a, b) =
            ((lobe as f64 + 0.75) * p.lobe_period(), (lobe as f64 + 0.98) * p.lobe_period());
        let rows: Vec<usize> = (0..r.len()).filter(|&k| r.t[k] >= a && r.t[k] <= b).collect();
        assert!(rows.len() > 50);
        for &k in &rows {
            assert!(r.active[k][0] && r.p_n[k][0] > 0.0, "lobe {lobe}: open at t = {}", r.t[k]);
            assert!((r.u[k][0] - p.lift_rate(r.t[k])).abs() <= s2 * dt, "t = {}", r.t[k]);
            assert!(m.normal_gap(0, &r.q[k], r.t[k]).abs() <= pen + 1e-12);
        }
    }
    // The follower leaves every drop from the up-dead point at rest, as at t = 0, so every
    // lobe shows the same impacts.
    let hits = onsets(r, 0);
    let per_lobe: Vec<usize> = (0..lobes)
        .map(|l| {
            hits.iter()
                .filter(|&&k| {
                    r.t[k] >= l as f64 * p.lobe_period()
                        && r.t[k] < (l + 1) as f64 * p.lobe_period()
                })
                .count()
        })
        .collect();
    eprintln!("cam: impacts per lobe {per_lobe:?}");
    assert!(per_lobe.iter().all(|&n| n >= 2));
    assert!(per_lobe.windows(2).all(|w| w[0] == w[1]));
}

#[test]
fn printed_spring_variant_meets_its_closed_form_fall_and_rides_each_lobe_to_its_drop() {
    let mut scene = Scene::report(ModelKind::Cam);
    scene.set("spring_law", "as_printed").unwrap();
    assert!(scene.set("spring_law", "sideways").is_err());
    scene.t_end = 0.16;
    let p = CamParams::as_printed();
    let dt = scene.dt;
    let sim = scene.run().unwrap();
    let r = &sim.record;
    // The printed law's spring pushes with K_s s(t) whatever y is: from rest at y0 = H,
    // m ÿ = −m g − K0 − K_s s(t) with the cycloid s = H (a t − sin(b t)/(2π)), a = ω/β,
    // b = 2π a, gives y(t) = y0 − (g + K0/m) t²/2 − (K_s/m) H (a t³/6 − (t/b − sin(b t)/b²)/(2π))
    // while the lobe rises; contact when y(t) = R_b + s(t).
    let (a, b) = (p.omega / p.beta, TAU * p.omega / p.beta);
    let y = |t: f64| {
        let lift2 = p.stroke * (a * t.powi(3) / 6.0 - (t / b - (b * t).sin() / (b * b)) / TAU);
        p.init.y0 - (p.g + p.k0 / p.m) * t * t / 2.0 - p.ks / p.m * lift2
    };
    let gap = |t: f64| y(t) - p.rb - p.lift(t);
    let (mut lo, mut hi) = (0.0, p.beta / p.omega);
    assert!(gap(lo) > 0.0 && gap(hi) < 0.0);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if gap(mid) > 0.0 { lo = mid } else { hi = mid }
    }
    let hits = onsets(r, 0);
    let t_num = r.t[hits[0]];
    eprintln!("printed cam: first impact at {t_num:.4} s, closed form {lo:.5} s");
    assert!((t_num - lo).abs() <= 2.0 * dt, "{t_num} vs {lo}");
    // After the impacts that follow, the spring holds the follower on the cam: over the last
    // tenth of each lobe the contact is closed and carries an impulse at every step, and the
    // relative velocity is that of the cam between t_M and t_E, at most max|s''| Δt/2.
    // (Earlier, the midpoint rule lets the contact open for single steps, after which the
    // spring, thousands of newtons, closes it again.) At the drop the follower leaves the cam.
    let s2 = TAU * p.stroke * p.omega * p.omega / (p.beta * p.beta);
    let lobes = (r.t.last().unwrap() / p.lobe_period()).floor() as usize;
    assert_eq!(lobes, 3);
    for lobe in 0..lobes {
        let (start, end) =
            ((lobe as f64 + 0.9) * p.lobe_period(), (lobe as f64 + 1.0) * p.lobe_period());
        let rows: Vec<usize> =
            (0..r.len()).filter(|&k| r.t[k] >= start && r.t[k] < end - 0.5 * dt).collect();
        assert!(rows.len() > 40);
        for &k in &rows {
            assert!(r.active[k][0] && r.p_n[k][0] > 0.0, "lobe {lobe}: open at t = {}", r.t[k]);
            assert!((r.u[k][0] - p.lift_rate(r.t[k])).abs() <= s2 * dt, "t = {}", r.t[k]);
        }
        // The first step whose midpoint is past the drop sees the gap H open.
        let after = (0..r.len()).find(|&k| r.t[k] - 0.5 * dt > end).unwrap();
        assert!(!r.active[after][0] && r.p_n[after][0] == 0.0, "lobe {lobe}: still closed");
    }
}
