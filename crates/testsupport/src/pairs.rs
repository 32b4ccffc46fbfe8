//! A [`ContactKinematics`] built from closures returning [`ContactGeometry`].

use moreau_kinematics::{ContactGeometry, ContactKinematics, ContactPoint, KinematicsError};
use nalgebra::SVector;

/// One contact: its geometry at `(q, t)`, typically a planar pair chained to the coordinates.
pub type Pair<const F: usize> =
    Box<dyn Fn(&SVector<f64, F>, f64) -> Result<ContactGeometry<F>, KinematicsError>>;

/// Contacts of a mechanism with `F` coordinates, each given as a closure; lets a test check
/// the planar pairs of `moreau-kinematics` against closed forms and the Jacobian checker
/// without writing a mechanism type.
pub struct Pairs<const F: usize> {
    /// The contacts, in order.
    pub contacts: Vec<Pair<F>>,
}

impl<const F: usize> Pairs<F> {
    /// Contact `i`'s geometry at `(q, t)`.
    ///
    /// # Panics
    /// If the closure fails: a test evaluates its pairs only at states where they are valid.
    pub fn geometry(&self, i: usize, q: &[f64], t: f64) -> ContactGeometry<F> {
        let q = SVector::<f64, F>::from_column_slice(q);
        (self.contacts[i])(&q, t).expect("test geometry is valid at the sampled states")
    }
}

impl<const F: usize> ContactKinematics for Pairs<F> {
    fn num_coordinates(&self) -> usize {
        F
    }
    fn num_contacts(&self) -> usize {
        self.contacts.len()
    }
    fn normal_gap(&self, i: usize, q: &[f64], t: f64) -> f64 {
        self.geometry(i, q, t).g_n
    }
    fn contact(
        &self,
        i: usize,
        q: &[f64],
        t: f64,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) -> ContactPoint {
        self.geometry(i, q, t).write(w_n, w_t).expect("slices of length F")
    }
}
