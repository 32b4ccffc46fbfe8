//! Planar frictional contact (FC2D): the problem, its residual and its solvers.

mod auto;
mod lcp_route;
mod local;
mod newton;
mod nsgs;
mod problem;
mod residual;
mod solution;

pub use crate::io::{Gfc2d, Reduced, SiconosStorage};
pub use auto::{Fc2dAuto, Fc2dAutoOptions};
pub use lcp_route::{LcpRoute, LcpRouteOptions, LcpRouteSolver};
pub use newton::{Newton, NewtonOptions, Rho};
pub use nsgs::{Nsgs, NsgsOptions};
pub use problem::{Fc2d, Fc2dBuilder, Fc2dParts, Fc2dRef, PSD_TOLERANCE};
pub use residual::Fc2dResidual;
pub use solution::{Fc2dSolution, Fc2dSolver};
