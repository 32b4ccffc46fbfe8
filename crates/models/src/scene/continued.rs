//! A scene continued from a state of its run: the same mechanism with that state as its
//! initial state and the run's time as its start time, so that a pile settled once, or a
//! mechanism brought to a steady motion, is the start of other runs and sweeps.

use moreau_kinematics::ContactKinematics;
use moreau_stepper::Impulses;

use super::Scene;
use crate::bodies::joints::JointKind;
use crate::bodies::{BodyType, JointSpec, Multibody, SystemSpec};
use crate::{AnyModel, ModelError, ModelParams};

impl Scene {
    /// The scene whose initial state is (q, u) at time t, reached by a step with `impulses`
    /// ([`Scene::impulses`]: `None` starts the continued run from zero impulses), for the same
    /// length of run (`t_start` = t, `t_end` = t + (t_end − t_start)); everything else is kept,
    /// but a stop rule that (q, u) has met (its coordinate on the other side of the rule's
    /// value than at the scene's start), which would never stop a run that starts there: the
    /// continued scene has none, and runs as long as the run that met it (t_end = 2t −
    /// t_start).
    ///
    /// A report model's initial state (`[params.init]`) is set from q and u. A declared
    /// mechanism's fills become the bodies they generate, each dynamic body's `position`,
    /// `angle`, `velocity` and `omega` are those of q and u (its origin's pose and velocity),
    /// and each joint's reference angle is written out as the joint had it, so that the
    /// continued scene has the mechanism it had: the run from it continues the run that
    /// reached (q, u) at t up to the assembly of its positions onto the joints, which moves
    /// them by the joints' drift, and the rounding of t + k Δt against the time of the run of
    /// the whole (which a driven body or a load in time reads). Without the impulses, a
    /// Gauss-Seidel island starts cold and the run follows only to the solvers' tolerance.
    ///
    /// ```
    /// # fn main() -> Result<(), Box<dyn std::error::Error>> {
    /// use moreau_models::{ModelKind, Scene};
    ///
    /// // The report's ball, 0.2 s into its fall from 1 m, and continued from there.
    /// let mut scene = Scene::report(ModelKind::Ball);
    /// scene.t_end = 0.2;
    /// let first = scene.run()?;
    /// let last = first.record.len() - 1;
    /// let (t, q, u) = (first.record.t[last], &first.record.q[last], &first.record.u[last]);
    /// let next = scene.continued(t, q, u, first.impulses.clone())?;
    /// assert_eq!((next.t_start, next.t_end), (0.2, 0.4));
    /// // Falling freely until it meets the floor at 0.43 s, y = 1 − g t²/2: the midpoint rule
    /// // is exact.
    /// let second = next.run()?;
    /// let y = second.record.q[second.record.len() - 1][0];
    /// assert!((y - (1.0 - 0.5 * 9.81 * 0.16)).abs() < 1e-12);
    /// # Ok(())
    /// # }
    /// ```
    ///
    /// # Errors
    /// The errors of [`Self::build`]; [`ModelError::BadValue`] (key `q` or `u`) when q or u
    /// has another length than the model's coordinates or holds a value that is not finite,
    /// and (key `t_start`) for a t that is not finite.
    pub fn continued(
        &self,
        t: f64,
        q: &[f64],
        u: &[f64],
        impulses: Option<Impulses>,
    ) -> Result<Scene, ModelError> {
        let model = self.build()?;
        let f = model.num_coordinates();
        for (key, x) in [("q", q), ("u", u)] {
            if x.len() != f {
                let reason = format!("has {} entries; the model has {f} coordinates", x.len());
                return Err(bad(key, &format!("{x:?}"), reason));
            }
            if let Some(j) = x.iter().position(|v| !v.is_finite()) {
                let reason = format!("entry {j} is not finite");
                return Err(bad(key, &format!("{x:?}"), reason));
            }
        }
        if !t.is_finite() {
            return Err(bad("t_start", &t.to_string(), "must be finite".to_owned()));
        }
        let params = match (&self.params, &model) {
            (ModelParams::Declared(spec), AnyModel::Declared(mb)) => {
                ModelParams::Declared(Box::new(declared_at(spec, mb, q, u)?))
            }
            (params, _) => report_at(params, q, u),
        };
        // A stop rule that the run has met would never stop the continued run, which starts
        // on its far side: the continued run is as long as the run was, without it.
        let met = self.stop_at.as_ref().is_some_and(|rule| {
            let (q0, _) = model.initial_state();
            let index = model.coordinate_names().position(&rule.coordinate);
            index.is_some_and(|i| (q0[i] < rule.value) != (q[i] < rule.value))
        });
        let (stop_at, t_end) = if met {
            (None, t + (t - self.t_start))
        } else {
            (self.stop_at.clone(), t + (self.t_end - self.t_start))
        };
        Ok(Scene { t_start: t, t_end, stop_at, params, impulses, ..self.clone() })
    }
}

fn bad(key: &str, value: &str, reason: String) -> ModelError {
    ModelError::BadValue { key: key.to_owned(), value: value.to_owned(), reason }
}

/// A report model's parameters with the initial state (q, u), in the order of the model's
/// `initial_state`.
fn report_at(params: &ModelParams, q: &[f64], u: &[f64]) -> ModelParams {
    let mut params = params.clone();
    match &mut params {
        ModelParams::Ball(p) => (p.init.y0, p.init.v0) = (q[0], u[0]),
        ModelParams::Cam(p) => (p.init.y0, p.init.v0) = (q[0], u[0]),
        ModelParams::Woodpecker(p) => {
            let i = &mut p.init;
            (i.y, i.phi_m, i.phi_s) = (q[0], q[1], q[2]);
            (i.v, i.omega_m, i.omega_s) = (u[0], u[1], u[2]);
        }
        ModelParams::SliderCrank(p) => {
            let i = &mut p.init;
            (i.th1, i.th2, i.th3) = (q[0], q[1], q[2]);
            (i.w1, i.w2, i.w3) = (u[0], u[1], u[2]);
        }
        ModelParams::SliderCrankIdeal(p) => (p.init.th1, p.init.w1) = (q[0], u[0]),
        ModelParams::Painleve(p) => {
            let i = &mut p.init;
            (i.x, i.y, i.phi) = (q[0], q[1], q[2]);
            (i.vx, i.vy, i.omega) = (u[0], u[1], u[2]);
        }
        ModelParams::Declared(_) => unreachable!("a declared mechanism is continued by its bodies"),
    }
    params
}

/// The declaration `spec`, built as `mb`, with the state (q, u): its fills made bodies, its
/// dynamic bodies at q and u, its joints' reference angles written out.
fn declared_at(
    spec: &SystemSpec,
    mb: &Multibody,
    q: &[f64],
    u: &[f64],
) -> Result<SystemSpec, ModelError> {
    let mut out = spec.clone();
    for fill in std::mem::take(&mut out.fill) {
        out.bodies.extend(fill.bodies()?);
    }
    // The dynamic bodies give q = (x, y, θ) each, in declaration order, the fills' last.
    let mut k = 0;
    for body in out.bodies.iter_mut().filter(|b| b.kind == BodyType::Dynamic) {
        body.position = [q[3 * k], q[3 * k + 1]];
        body.angle = q[3 * k + 2];
        body.velocity = [u[3 * k], u[3 * k + 1]];
        body.omega = u[3 * k + 2];
        k += 1;
    }
    debug_assert_eq!(3 * k, q.len());
    for (joint, built) in out.joints.iter_mut().zip(&mb.joints) {
        let reference = match built.kind {
            JointKind::Prismatic { angle, .. }
            | JointKind::Weld { angle, .. }
            | JointKind::Motor { angle, .. } => angle,
            _ => continue,
        };
        match joint {
            JointSpec::Prismatic { angle, .. }
            | JointSpec::Weld { angle, .. }
            | JointSpec::Motor { angle, .. } => *angle = Some(reference),
            _ => {}
        }
    }
    Ok(out)
}
