//! A [`ContactKinematics`] built from closures returning [`ContactGeometry`], for the tests.

use moreau_kinematics::{ContactGeometry, ContactKinematics, ContactPoint, KinematicsError};
use nalgebra::SVector;

/// One contact: the geometry at `(q, t)`.
pub type Pair<const F: usize> =
    Box<dyn Fn(&SVector<f64, F>, f64) -> Result<ContactGeometry<F>, KinematicsError>>;

/// Contacts given as closures of `F` coordinates.
pub struct Pairs<const F: usize> {
    pub contacts: Vec<Pair<F>>,
}

impl<const F: usize> Pairs<F> {
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
        self.geometry(i, q, t).write(w_n, w_t).expect("slices of length f")
    }
}
