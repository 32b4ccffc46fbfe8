//! `check_evaluate`: overrides of `Mechanism::evaluate` and `Mechanism::midpoint_contacts`
//! against the separate methods.

use moreau_kinematics::{ContactKinematics, ContactPoint};
use moreau_setvalued::ContactLaw;
use moreau_stepper::{Mechanism, SharedWork, StepError, check_evaluate};
use moreau_testsupport::Rod;

/// The shared test rod, q = (x, y, φ), with overrides of `evaluate` and `midpoint_contacts`
/// that share sin φ and cos φ through the memo. `bug` plants one mistake.
struct SharedRod {
    rod: Rod,
    bug: Bug,
}

#[derive(Clone, Copy, PartialEq)]
enum Bug {
    None,
    /// `evaluate` gives end 1 the gap of end 0.
    Gap,
    /// `midpoint_contacts` reads the memo with sine and cosine swapped.
    MemoLayout,
}

impl SharedRod {
    fn new(bug: Bug) -> Self {
        Self { rod: Rod::new(0.5, 0.3), bug }
    }
}

impl ContactKinematics for SharedRod {
    fn num_coordinates(&self) -> usize {
        self.rod.num_coordinates()
    }
    fn num_contacts(&self) -> usize {
        self.rod.num_contacts()
    }
    fn normal_gap(&self, i: usize, q: &[f64], t: f64) -> f64 {
        self.rod.normal_gap(i, q, t)
    }
    fn contact(
        &self,
        i: usize,
        q: &[f64],
        t: f64,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) -> ContactPoint {
        self.rod.contact(i, q, t, w_n, w_t)
    }
}

impl Mechanism for SharedRod {
    fn laws(&self) -> &[ContactLaw] {
        self.rod.laws()
    }
    fn mass_matrix(&self, q: &[f64], t: f64, m: &mut [f64]) {
        self.rod.mass_matrix(q, t, m);
    }
    fn forces(&self, q: &[f64], u: &[f64], t: f64, h: &mut [f64]) {
        self.rod.forces(q, u, t, h);
    }
    fn shared_work(&self) -> Option<&dyn SharedWork> {
        Some(self)
    }
}

impl SharedWork for SharedRod {
    fn evaluate(
        &self,
        q: &[f64],
        u: &[f64],
        t: f64,
        mass: Option<&mut [f64]>,
        h: &mut [f64],
        gaps: &mut [f64],
        memo: &mut [f64],
    ) {
        let (s, c) = q[2].sin_cos();
        memo.copy_from_slice(&[s, c]);
        if let Some(m) = mass {
            self.mass_matrix(q, t, m);
        }
        self.forces(q, u, t, h);
        gaps[0] = self.rod.gap(0, q, s);
        gaps[1] = if self.bug == Bug::Gap { gaps[0] } else { self.rod.gap(1, q, s) };
    }
    fn memo_len(&self) -> usize {
        2
    }
    fn midpoint_contacts(
        &self,
        which: &[usize],
        q: &[f64],
        _t: f64,
        memo: &[f64],
        w_n: &mut [f64],
        w_t: &mut [f64],
        points: &mut [ContactPoint],
    ) {
        let sc = if self.bug == Bug::MemoLayout { (memo[1], memo[0]) } else { (memo[0], memo[1]) };
        for (k, &i) in which.iter().enumerate() {
            points[k] = self.rod.end(i, q, sc, &mut w_n[3 * k..][..3], &mut w_t[3 * k..][..3]);
        }
    }
}

/// States with the rod at several angles and heights.
fn states() -> Vec<([f64; 3], [f64; 3])> {
    (0..12)
        .map(|k| {
            let x = f64::from(k);
            ([0.1 * x - 0.4, 0.05 * x, 0.37 * x - 2.0], [x.sin(), x.cos(), 3.0 - x])
        })
        .collect()
}

#[test]
fn overrides_that_share_the_same_formulas_agree_to_the_last_bit() {
    let rod = SharedRod::new(Bug::None);
    for (q, u) in states() {
        assert_eq!(check_evaluate(&rod, &q, &u, 0.2, 0.0).unwrap(), None, "q = {q:?}");
    }
}

#[test]
fn a_wrong_gap_in_evaluate_is_named_with_its_contact() {
    let rod = SharedRod::new(Bug::Gap);
    let (q, u) = states()[3];
    let found = check_evaluate(&rod, &q, &u, 0.0, 1e-12).unwrap().expect("gap 1 differs");
    assert_eq!((found.what, found.index), ("g_N", 1));
    assert_eq!(found.separate, rod.normal_gap(1, &q, 0.0));
    assert!(found.scaled > 1e-12);
    assert!(found.to_string().starts_with("g_N[1]: "), "{found}");
}

#[test]
fn a_misread_memo_in_midpoint_contacts_is_named_with_its_contact_and_entry() {
    let rod = SharedRod::new(Bug::MemoLayout);
    let (q, u) = states()[5];
    let found = check_evaluate(&rod, &q, &u, 0.0, 1e-12).unwrap().expect("w_N differs");
    // w_N of end 0 = (0, 1, −s cos φ): entry 2 is the first that reads the memo.
    assert_eq!((found.what, found.index), ("w_N", 2));
    let expected = -rod.rod.s * q[2].cos();
    assert_eq!(found.separate, expected);
    assert_eq!(found.combined, -rod.rod.s * q[2].sin());
}

#[test]
fn bad_states_are_refused_with_typed_errors() {
    let rod = SharedRod::new(Bug::None);
    let short = check_evaluate(&rod, &[0.0, 1.0], &[0.0; 3], 0.0, 0.0);
    assert!(matches!(short, Err(StepError::Dimension { what: "q", expected: 3, found: 2 })));
    let nan_u = check_evaluate(&rod, &[0.0; 3], &[0.0, f64::NAN, 0.0], 0.0, 0.0);
    assert!(matches!(nan_u, Err(StepError::NonFinite { what: "u", index: 1, .. })));
    let inf_tol = check_evaluate(&rod, &[0.0; 3], &[0.0; 3], 0.0, f64::INFINITY);
    assert!(matches!(inf_tol, Err(StepError::NonFinite { what: "tol", .. })));
}
