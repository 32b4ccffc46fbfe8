//! The robust default: trivial check, Lemke, Lemke with other covering vectors, then
//! enumeration.
#![allow(non_snake_case)]

use serde::{Deserialize, Serialize};

use crate::lemke::Cover;
use crate::solution::{check_warm_start, residual_of_zero};
use crate::{
    Enumeration, EnumerationOptions, LcpError, LcpRef, Lemke, LemkeOptions, Method, Solution,
    Solver, Status,
};

/// Options of [`Auto`]: the default, changed field by field with the `with_*` setters
/// (or by assigning the fields of a default value).
///
/// ```
/// use moreau_lcp::{Auto, AutoOptions};
///
/// # fn main() -> Result<(), moreau_lcp::LcpError> {
/// let options = AutoOptions::default().with_alternative_coverings(2).with_enumeration_max_n(8);
/// assert_eq!((options.alternative_coverings, options.enumeration_max_n), (2, 8));
/// let solver = Auto::new(options)?;
/// # let _ = solver;
/// # Ok(())
/// # }
/// ```
///
/// The struct is `#[non_exhaustive]`, so that fields added later keep their defaults in
/// callers' code; a struct literal does not compile outside this crate:
///
/// ```compile_fail,E0639
/// let options = moreau_lcp::AutoOptions { alternative_coverings: 2, ..Default::default() };
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct AutoOptions {
    /// Options of the first Lemke attempt (its covering vector is the first one tried).
    /// Default [`LemkeOptions::default`].
    pub lemke: LemkeOptions,
    /// How many other covering vectors Lemke's method tries after the first fails:
    /// [`Covering::RowScaled`](crate::Covering::RowScaled), then
    /// `d_i = max(|q_i|, 1e-3 ‖q‖∞)`, then `d_i = 1 + i / n`, then deterministic
    /// pseudo-random vectors with entries in [0.5, 1.5]. Default 4.
    pub alternative_coverings: usize,
    /// Enumeration is the last resort, used only when n <= `enumeration_max_n`.
    /// Default 12 (the friction LCP of 4 contacts).
    pub enumeration_max_n: usize,
    /// Options of that enumeration. Default [`EnumerationOptions::default`].
    pub enumeration: EnumerationOptions,
}

with_setters!(AutoOptions {
    with_lemke => lemke: LemkeOptions,
    with_alternative_coverings => alternative_coverings: usize,
    with_enumeration_max_n => enumeration_max_n: usize,
    with_enumeration => enumeration: EnumerationOptions,
});

impl Default for AutoOptions {
    fn default() -> Self {
        AutoOptions {
            lemke: LemkeOptions::default(),
            alternative_coverings: 4,
            enumeration_max_n: 12,
            enumeration: EnumerationOptions::default(),
        }
    }
}

/// The robust default solver, as in the step LCP's recipe.
///
/// 1. If q >= 0, z = 0 at once ([`Method::Trivial`]).
/// 2. With a warm start z⁰, the complementary basis it names (z basic where z⁰_i > 0, w
///    elsewhere) is solved directly by LU and taken when z ≥ 0 and its residual passes
///    ([`Method::WarmBasis`]). A time-stepper's previous impulses name the new step's basis
///    whenever no contact changes its state (closed, sticking, sliding one way), which is
///    most steps; when they do not, this costs one small solve before Lemke's method.
/// 3. Lemke's method with the configured covering vector (ones by default).
/// 4. Lemke's method with up to `alternative_coverings` other positive covering vectors.
/// 5. If n <= `enumeration_max_n`, complete [`Enumeration`].
///
/// The first accepted result is returned with the method that produced it. The status is
/// [`Status::NoSolution`] only when enumeration proved that there is no solution;
/// otherwise a failed solve reports the first Lemke attempt's status
/// ([`Status::RayTermination`], [`Status::IterationLimit`] or
/// [`Status::NumericalFailure`]).
///
/// # References
/// - C. E. Lemke, Bimatrix equilibrium points and mathematical programming, Management
///   Science 11 (1965) 681-689.
/// - R. W. Cottle, J.-S. Pang, R. E. Stone, The Linear Complementarity Problem, Academic
///   Press, 1992.
/// - C. Glocker, Set-Valued Force Laws, Springer, 2001.
#[derive(Default)]
pub struct Auto {
    options: AutoOptions,
    lemke: Lemke,
    enumeration: Enumeration,
    q: Vec<f64>,
    d: Vec<f64>,
    first: Solution,
}

impl Auto {
    /// A solver with the given options.
    ///
    /// # Errors
    /// [`LcpError::InvalidOption`] for out-of-range options; a field of the nested options is
    /// named by its path (`lemke.tolerance`, `enumeration.max_n`).
    pub fn new(options: AutoOptions) -> Result<Auto, LcpError> {
        let lemke = Lemke::new(options.lemke.clone()).map_err(|e| nested("lemke", e))?;
        let enumeration =
            Enumeration::new(options.enumeration.clone()).map_err(|e| nested("enumeration", e))?;
        if options.enumeration_max_n > options.enumeration.max_n {
            return Err(LcpError::InvalidOption {
                name: "enumeration_max_n",
                reason: format!(
                    "must not exceed enumeration.max_n = {}",
                    options.enumeration.max_n
                ),
            });
        }
        Ok(Auto { options, lemke, enumeration, ..Auto::default() })
    }

    /// The options in use.
    pub fn options(&self) -> &AutoOptions {
        &self.options
    }

    /// Fills `self.d` with alternative covering vector number `k` (2-based; number 1 is
    /// [`Covering::RowScaled`](crate::Covering::RowScaled)).
    fn covering(&mut self, k: usize) {
        let n = self.q.len();
        match k {
            2 => {
                let qmax = self.q.iter().fold(0.0f64, |a, v| a.max(v.abs()));
                let floor = (1e-3 * qmax).max(f64::MIN_POSITIVE);
                for (d, q) in self.d.iter_mut().zip(&self.q) {
                    *d = q.abs().max(floor);
                }
            }
            3 => {
                for (i, d) in self.d.iter_mut().enumerate() {
                    *d = 1.0 + i as f64 / n as f64;
                }
            }
            _ => {
                let mut state = 0x5EED_0000_0000_0000u64 ^ k as u64;
                for d in self.d.iter_mut() {
                    *d = 0.5 + unit(&mut state);
                }
            }
        }
    }
}

/// `error` of the options in field `parent`, its option named by its path from
/// [`AutoOptions`] (`lemke.tolerance`): the nested solvers name only their own fields.
fn nested(parent: &'static str, error: LcpError) -> LcpError {
    let LcpError::InvalidOption { name, reason } = error else { return error };
    let path = match (parent, name) {
        ("lemke", "max_pivots") => "lemke.max_pivots",
        ("lemke", "tolerance") => "lemke.tolerance",
        ("lemke", "pivot_tolerance") => "lemke.pivot_tolerance",
        ("lemke", "tie_tolerance") => "lemke.tie_tolerance",
        ("lemke", "covering") => "lemke.covering",
        ("enumeration", "max_n") => "enumeration.max_n",
        ("enumeration", "tolerance") => "enumeration.tolerance",
        ("enumeration", "max_n_degenerate") => "enumeration.max_n_degenerate",
        _ => return LcpError::InvalidOption { name, reason: format!("{reason} (in {parent})") },
    };
    LcpError::InvalidOption { name: path, reason }
}

/// splitmix64 mapped to [0, 1).
fn unit(state: &mut u64) -> f64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64
}

impl Solver for Auto {
    fn solve_into(
        &mut self,
        lcp: LcpRef<'_>,
        warm_start: Option<&[f64]>,
        out: &mut Solution,
    ) -> Result<(), LcpError> {
        let n = lcp.n();
        check_warm_start(n, warm_start)?;
        self.q.resize(n, 0.0);
        self.d.resize(n, 1.0);
        lcp.copy_q(&mut self.q);
        if self.q.iter().all(|&v| v >= 0.0) {
            out.reset(n, Method::Trivial);
            out.w.copy_from_slice(&self.q);
            out.residual = residual_of_zero(&self.q);
            out.status = Status::Solved;
            return Ok(());
        }
        if let Some(guess) = warm_start
            && self.lemke.solve_guessed_basis(lcp, guess, out)
        {
            return Ok(());
        }
        self.lemke.solve_covering(lcp, Cover::FromOptions, out)?;
        if out.is_solved() {
            return Ok(());
        }
        std::mem::swap(out, &mut self.first);
        for k in 1..=self.options.alternative_coverings {
            if k == 1 {
                self.lemke.solve_covering(lcp, Cover::RowScaled, out)?;
            } else {
                self.covering(k);
                self.lemke.solve_covering(lcp, Cover::Given(&self.d), out)?;
            }
            if out.is_solved() {
                return Ok(());
            }
        }
        if n <= self.options.enumeration_max_n {
            self.enumeration.solve_into(lcp, None, out)?;
            if out.is_solved() || out.status == Status::NoSolution {
                return Ok(());
            }
        }
        std::mem::swap(out, &mut self.first);
        Ok(())
    }
}
