//! Planar frictional contact (FC2D): the problem, its residual and its solvers.
#![allow(dead_code, unused_imports)]

mod problem;
mod residual;
mod solution;

pub use crate::io::{Gfc2d, Reduced, SiconosStorage};
pub use problem::{Fc2d, Fc2dBuilder, Fc2dParts, Fc2dRef, PSD_TOLERANCE};
pub use residual::Fc2dResidual;
pub(crate) use residual::{natural_map, project_cone};
pub(crate) use solution::check_warm_start;
pub use solution::{Fc2dSolution, Fc2dSolver};
