//! A thinned record keeps one step in n and the last step of each run.

use std::ops::ControlFlow;

use moreau_stepper::{Mechanism, Observer, Recorder, StepReport, Stepper, StepperOptions};
use moreau_testsupport::Block;

/// A recorder that stops the run after the step whose index is `stop`.
struct StopAfter<'a> {
    inner: &'a mut Recorder,
    stop: u64,
}

impl<M: Mechanism> Observer<M> for StopAfter<'_> {
    fn observe(&mut self, m: &M, r: &StepReport<'_>) -> ControlFlow<()> {
        let _ = self.inner.observe(m, r);
        if r.step == self.stop { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
    }

    fn finish(&mut self, m: &M, last: &StepReport<'_>) {
        self.inner.finish(m, last);
    }
}

#[test]
fn a_thinned_record_ends_at_the_last_step() {
    let dt = 0.01;
    let stepper = || {
        Stepper::new(Block::new(0.3, 0.5), &[0.0, 0.0], &[1.0, 0.0], 0.0, StepperOptions::new(dt))
            .unwrap()
    };
    // Ten steps kept one in four: rows at steps 0, 4, 8 and 10.
    let mut s = stepper();
    let mut every = Recorder::every(4);
    every.push_initial(s.mechanism(), 0.0, s.q(), s.u());
    s.run_until(10.0 * dt, &mut every).unwrap();
    let mut all = Recorder::new();
    let mut s = stepper();
    all.push_initial(s.mechanism(), 0.0, s.q(), s.u());
    s.run_until(10.0 * dt, &mut all).unwrap();
    let rows: Vec<usize> = vec![0, 4, 8, 10];
    assert_eq!(every.record.len(), rows.len());
    for (k, &j) in rows.iter().enumerate() {
        assert_eq!(every.record.t[k], all.record.t[j]);
        assert_eq!(every.record.q.get(k), all.record.q.get(j));
    }
    // Stopped by its observer after step index 5 (six steps): rows at steps 0, 4 and 6.
    let mut s = stepper();
    let mut every = Recorder::every(4);
    every.push_initial(s.mechanism(), 0.0, s.q(), s.u());
    let summary = s.run_until(1.0, &mut StopAfter { inner: &mut every, stop: 5 }).unwrap();
    assert!(summary.stopped_early);
    assert_eq!(every.record.len(), 3);
    assert_eq!(every.record.t[2], all.record.t[6]);
    assert_eq!(every.record.q.get(2), all.record.q.get(6));
}
