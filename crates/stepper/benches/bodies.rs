//! Time per step of the many-body path on a resting pile of disks, with its split by phase.
//!
//! `cargo bench -p moreau-stepper --bench bodies` steps a pile of N disks (N = 100, 1000) of
//! radius 0.1 m stacked in a box 20 diameters wide, square-packed, touching and at rest
//! under gravity with friction: one island of about 2 N contacts, warm-started from the
//! step before. Before the criterion groups it prints the time per step split into
//! detection, assembly and solution over 200 steps, and the solver's sweeps; last, the time
//! per step of twenty separate columns (twenty islands) on one and on two threads, and that of
//! a pile of 10,000 disks (one island) with its phases on one and on two threads.

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use moreau_setvalued::ContactLaw;
use moreau_stepper::{PhaseTimes, Stepper, StepperOptions};
use moreau_testsupport::Disks;

/// A pile of `n` disks in rows of `width`, resting, with the stepper warmed up.
fn pile(n: usize, width: usize) -> Stepper<Disks> {
    let r = 0.1;
    let law = ContactLaw::new(0.0, 0.0, 0.3).unwrap();
    let disks =
        Disks::new(vec![1.0; n], vec![r; n], law, true).with_walls(0.0, 2.0 * r * width as f64);
    let centres: Vec<_> = (0..n)
        .map(|k| (r + 2.0 * r * (k % width) as f64, r + 2.0 * r * (k / width) as f64))
        .collect();
    let (q, u) = Disks::state_at(&centres);
    let opts = StepperOptions::new(1e-3).with_gap_tolerance(1e-9);
    let mut s = Stepper::new(disks, &q, &u, 0.0, opts).unwrap();
    for _ in 0..50 {
        // The error's display names the island and the solver's status (its Debug form
        // would print the whole state).
        s.step().unwrap_or_else(|e| panic!("{e}"));
    }
    s
}

fn bodies(c: &mut Criterion) {
    for n in [100, 1000] {
        let mut s = pile(n, 20);
        let (mut sum, steps) = (PhaseTimes::default(), 200);
        let (mut contacts, mut sweeps, mut residual) = (0, 0, 0.0f64);
        for _ in 0..steps {
            let r = s.step().unwrap();
            sum.detection += r.times.detection;
            sum.assembly += r.times.assembly;
            sum.solution += r.times.solution;
            contacts = r.contacts.len();
            let info = r.lcp.unwrap();
            sweeps = sweeps.max(info.iterations);
            residual = residual.max(info.residual);
        }
        let ms = |d: Duration| d.as_secs_f64() * 1e3 / steps as f64;
        eprintln!(
            "pile of {n} disks, {contacts} contacts: detection {:.4} ms, assembly {:.4} ms, \
             solution {:.4} ms per step; at most {sweeps} sweeps, residual <= {residual:.1e}",
            ms(sum.detection),
            ms(sum.assembly),
            ms(sum.solution)
        );
        c.bench_function(&format!("bodies/pile of {n} disks, one step"), |b| {
            b.iter(|| black_box(s.step().unwrap().q[0]));
        });
    }
}

/// Twenty separate columns of fifty disks (twenty islands, grouped into batches of at least
/// 256 contacts): the time per step on rayon pools of one and two threads, printed.
fn islands(_: &mut Criterion) {
    let (r, n) = (0.1, 1000);
    let law = ContactLaw::new(0.0, 0.0, 0.3).unwrap();
    let centres: Vec<_> =
        (0..n).map(|k| (1.0 * (k / 50) as f64, r + 2.0 * r * (k % 50) as f64)).collect();
    let (q, u) = Disks::state_at(&centres);
    let mut per_step = [(0.0, 0.0); 2];
    for (threads, out) in [1, 2].into_iter().zip(&mut per_step) {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        *out = pool.install(|| {
            let disks = Disks::new(vec![1.0; n], vec![r; n], law, true);
            let opts = StepperOptions::new(1e-3).with_gap_tolerance(1e-9);
            let mut s = Stepper::new(disks, &q, &u, 0.0, opts).unwrap();
            for _ in 0..50 {
                s.step().unwrap_or_else(|e| panic!("{e}"));
            }
            let start = std::time::Instant::now();
            let mut solution = Duration::ZERO;
            for _ in 0..200 {
                solution += s.step().unwrap_or_else(|e| panic!("{e}")).times.solution;
            }
            let ms = |d: Duration| d.as_secs_f64() * 1e3 / 200.0;
            (ms(start.elapsed()), ms(solution))
        });
    }
    let [(one, one_solution), (two, two_solution)] = per_step;
    eprintln!(
        "20 columns of 50 disks: {one:.3} ms per step on one thread ({one_solution:.3} ms \
         solution), {two:.3} ms on two ({two_solution:.3} ms solution): {:.2} times, the \
         solution {:.2} times",
        one / two,
        one_solution / two_solution
    );
}

/// A pile of 10,000 disks in 50 rows of 200 (one island of about 20,000 contacts): the time
/// per step and its phases on rayon pools of one and two threads, printed.
fn large(_: &mut Criterion) {
    let mut s = pile(10_000, 200);
    let steps = 50;
    let mut per_pool = [(PhaseTimes::default(), Duration::ZERO, 0); 2];
    for (threads, out) in [1, 2].into_iter().zip(&mut per_pool) {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        *out = pool.install(|| {
            let (mut sum, mut contacts) = (PhaseTimes::default(), 0);
            let start = std::time::Instant::now();
            for _ in 0..steps {
                let r = s.step().unwrap_or_else(|e| panic!("{e}"));
                sum.detection += r.times.detection;
                sum.assembly += r.times.assembly;
                sum.solution += r.times.solution;
                contacts = r.contacts.len();
            }
            (sum, start.elapsed(), contacts)
        });
    }
    let ms = |d: Duration| d.as_secs_f64() * 1e3 / steps as f64;
    for (threads, (sum, total, contacts)) in [1, 2].into_iter().zip(per_pool) {
        eprintln!(
            "pile of 10000 disks, {contacts} contacts, {threads} thread(s): {:.3} ms per step = \
             detection {:.3} ms, assembly {:.3} ms, solution {:.3} ms",
            ms(total),
            ms(sum.detection),
            ms(sum.assembly),
            ms(sum.solution)
        );
    }
    let (one, two) = (per_pool[0].1, per_pool[1].1);
    eprintln!(
        "pile of 10000 disks: two threads {:.2} times one",
        one.as_secs_f64() / two.as_secs_f64()
    );
}

criterion_group!(benches, bodies, islands, large);
criterion_main!(benches);
