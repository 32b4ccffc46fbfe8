//! Every solver, problem and solution can move to another thread and be shared between
//! threads, which the parallel sweeps and the independent contact clusters of large scenes
//! rely on.

use moreau_lcp::fc2d::{
    Fc2d, Fc2dAuto, Fc2dRef, Fc2dResidual, Fc2dSolution, Gfc2d, LcpRoute, Newton, Nsgs, Proximal,
};
use moreau_lcp::{Auto, Enumeration, Lcp, LcpError, LcpRef, Lemke, Pgs, Residual, Solution};

fn send_sync<T: Send + Sync>() {}

#[test]
fn solvers_problems_and_solutions_are_send_and_sync() {
    send_sync::<Lemke>();
    send_sync::<Auto>();
    send_sync::<Pgs>();
    send_sync::<Enumeration>();
    send_sync::<Nsgs>();
    send_sync::<Newton>();
    send_sync::<Proximal>();
    send_sync::<LcpRoute>();
    send_sync::<Fc2dAuto>();
    send_sync::<Lcp>();
    send_sync::<LcpRef<'static>>();
    send_sync::<Fc2d>();
    send_sync::<Fc2dRef<'static>>();
    send_sync::<Gfc2d>();
    send_sync::<Solution>();
    send_sync::<Fc2dSolution>();
    send_sync::<Residual>();
    send_sync::<Fc2dResidual>();
    send_sync::<LcpError>();
}
