//! The step problem of a run that stopped on it, written to a file so that it can be examined,
//! solved by other solvers (Siconos reads the same formats) or sent with a report.
//!
//! A run stops with [`StepError::LcpFailed`] when no solver of the chosen kind solves a step's
//! LCP of eq. 7.41, and with [`StepError::IslandFailed`] when an island's planar
//! frictional-contact problem stays unsolved; both errors keep the problem. `simulate` writes
//! it to `<out>.failed.dat` and `sweep` to `<out>.member-<i>.failed.dat`, and the error says
//! where; `moreau solve` ([`crate::solve`]) tries any solver on it.

use std::borrow::Cow;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use moreau_lcp::fc2d::SiconosStorage;
use moreau_models::ModelError;
use moreau_stepper::StepError;

use crate::output::suffixed;

/// The most contacts of an island with joints whose problem is written: the elimination of its
/// bilateral rows makes W dense (2 n_c × 2 n_c, 32 MB at this size).
const ELIMINATED_CONTACTS: usize = 1_000;

/// `<path>.failed.dat`: the file that receives the problem of the step a run stopped on.
pub fn failed_problem_path(path: &Path) -> PathBuf {
    suffixed(path, ".failed.dat")
}

/// The step error inside `error`, if the run stopped on one.
fn step_error(error: &anyhow::Error) -> Option<&StepError> {
    error.chain().find_map(|cause| {
        cause.downcast_ref::<StepError>().or_else(|| match cause.downcast_ref::<ModelError>() {
            Some(ModelError::Step(step)) => Some(step),
            _ => None,
        })
    })
}

/// Writes the problem of the step that `error` stopped a run on to `path`: the LCP of eq.
/// 7.41 in Siconos' LCP format (dense), or an island's contact problem in Siconos' FC2D format
/// (W by sparse 2 × 2 blocks, q, μ; Moreau's `moreau_lcp::Lcp::read_siconos` and
/// `moreau_lcp::fc2d::Fc2d::read_siconos` read them back).
///
/// An island with joints is written as the equivalent problem of its contacts alone (its
/// bilateral rows eliminated by their Schur complement, `Fc2dRef::without_bilateral`), since
/// the format has no bilateral rows. Returns `error` as it is when it is not such a stop,
/// otherwise with a sentence added: where the problem is, or why it could not be written
/// (joints whose rows repeat each other, an island with joints of more than 1,000 contacts; a
/// file that cannot be created).
pub fn with_failed_problem(error: anyhow::Error, path: &Path) -> anyhow::Error {
    match failed_problem(&error, path) {
        Some(note) => error.context(note),
        None => error,
    }
}

/// Writes the problem of [`with_failed_problem`] and returns its sentence, or `None` when
/// `error` is not a stop on a step problem.
fn failed_problem(error: &anyhow::Error, path: &Path) -> Option<String> {
    let shown = path.display();
    let written = match step_error(error)? {
        StepError::LcpFailed { lcp, step, .. } => write_to(path, |w| Ok(lcp.write_siconos(w)?))
            .map(|()| {
                format!(
                    "the LCP of step {step} ({} rows) is in {shown}, in Siconos' LCP format",
                    lcp.n()
                )
            }),
        StepError::IslandFailed { problem, step, .. } => {
            // Siconos' FC2D format has no bilateral rows: an island with joints is written as
            // the equivalent problem of its contacts alone.
            let bilateral = problem.view().n_bilateral();
            if bilateral > 0 && problem.n_contacts() > ELIMINATED_CONTACTS {
                return Some(format!(
                    "the island's problem of step {step} was not written: Siconos' FC2D format \
                     has no bilateral rows, and eliminating its {bilateral} would make the W of \
                     its {} contacts dense",
                    problem.n_contacts()
                ));
            }
            let (contacts, joints) = if bilateral > 0 {
                match problem.view().without_bilateral() {
                    Ok(alone) => (
                        Cow::Owned(alone),
                        format!(
                            ", its {bilateral} bilateral rows (joints) eliminated by their \
                             Schur complement"
                        ),
                    ),
                    Err(e) => {
                        return Some(format!(
                            "the island's problem of step {step} was not written: Siconos' FC2D \
                             format has no bilateral rows, and its {bilateral} cannot be \
                             eliminated ({e})"
                        ));
                    }
                }
            } else {
                (Cow::Borrowed(&**problem), String::new())
            };
            write_to(path, |w| Ok(contacts.write_siconos(w, SiconosStorage::SparseBlock)?)).map(
                |()| {
                    format!(
                        "the island's contact problem of step {step} ({} contacts{joints}) is in \
                         {shown}, in Siconos' FC2D format",
                        problem.n_contacts()
                    )
                },
            )
        }
        _ => return None,
    };
    Some(
        written
            .unwrap_or_else(|e| format!("the failed step's problem could not be written: {e:#}")),
    )
}

/// Creates `path` and writes it with `write`.
fn write_to(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> anyhow::Result<()>,
) -> anyhow::Result<()> {
    let mut w =
        BufWriter::new(File::create(path).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?);
    write(&mut w)?;
    w.flush()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use moreau_lcp::Status;
    use moreau_lcp::fc2d::{Fc2d, Fc2dBuilder};

    use super::*;

    /// An island of `n_c` contacts with one bilateral row, each row on its own.
    fn island(n_c: usize) -> anyhow::Error {
        let mut b = Fc2dBuilder::new(n_c);
        b.bilateral_group(1);
        for i in 0..2 * n_c + 1 {
            b.add_entry(i, i, 1.0);
        }
        let problem = b.build(&vec![-1.0; 2 * n_c + 1], &vec![0.5; n_c]).expect("island builds");
        anyhow::Error::new(StepError::IslandFailed {
            step: 7,
            t: 0.007,
            q: Vec::new(),
            u: Vec::new(),
            status: Status::IterationLimit,
            problem: Box::new(problem),
        })
    }

    #[test]
    fn an_island_with_joints_is_written_up_to_a_size_that_stays_small_when_dense() {
        let dir = tempfile::tempdir().expect("a temporary folder");
        let path = dir.path().join("p.failed.dat");
        let small = format!("{:#}", with_failed_problem(island(ELIMINATED_CONTACTS), &path));
        assert!(
            small.contains("(1000 contacts, its 1 bilateral rows (joints) eliminated"),
            "{small}"
        );
        let written = Fc2d::read_siconos(File::open(&path).expect("written")).expect("reads");
        assert_eq!(written.n_contacts(), ELIMINATED_CONTACTS);
        std::fs::remove_file(&path).expect("removed");
        let large = format!("{:#}", with_failed_problem(island(ELIMINATED_CONTACTS + 1), &path));
        assert!(large.contains("would make the W of its 1001 contacts dense"), "{large}");
        assert!(!path.exists());
        // Another error is left as it is.
        let other = with_failed_problem(anyhow::anyhow!("no step problem"), &path);
        assert_eq!(format!("{other:#}"), "no step problem");
        assert!(!path.exists());
    }
}
