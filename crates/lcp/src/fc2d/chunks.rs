//! The per-group work of a large problem in chunks on rayon's pool: the checks of its parts,
//! u = W r + q and the residual. The chunks are cut by the number of groups alone, never by
//! the number of threads, so that a result is the same, bit for bit, on any pool; a problem
//! of at most [`CHUNK_GROUPS`] groups is one chunk, done in place as a plain loop.

use std::ops::Range;

/// Groups per chunk: enough work per rayon task (a few thousand blocks) that its overhead is
/// small.
pub(crate) const CHUNK_GROUPS: usize = 1024;

/// Splits `groups` in halves down to chunks of at most [`CHUNK_GROUPS`], runs `op` on each
/// chunk (the halves through `rayon::join`) and combines the chunks' results with `merge`, the
/// earlier chunk's first. The tree of the combinations depends on the number of groups only.
pub(crate) fn reduce<R: Send>(
    groups: Range<usize>,
    op: &(impl Fn(Range<usize>) -> R + Sync),
    merge: &(impl Fn(R, R) -> R + Sync),
) -> R {
    if groups.len() <= CHUNK_GROUPS {
        return op(groups);
    }
    let mid = groups.start + groups.len() / 2;
    let (a, b) =
        rayon::join(|| reduce(groups.start..mid, op, merge), || reduce(mid..groups.end, op, merge));
    merge(a, b)
}

/// Runs `op(groups, rows)` on chunks of at most [`CHUNK_GROUPS`] groups, where `rows` is the
/// part of `out` that the chunk's groups own (`out[group_start[g0]..group_start[g1]]`, with
/// `out` given from the rows of `groups.start`), the halves through `rayon::join`.
pub(crate) fn for_rows<T: Send>(
    group_start: &[usize],
    groups: Range<usize>,
    out: &mut [T],
    op: &(impl Fn(Range<usize>, &mut [T]) + Sync),
) {
    if groups.len() <= CHUNK_GROUPS {
        return op(groups, out);
    }
    let mid = groups.start + groups.len() / 2;
    let (a, b) = out.split_at_mut(group_start[mid] - group_start[groups.start]);
    rayon::join(
        || for_rows(group_start, groups.start..mid, a, op),
        || for_rows(group_start, mid..groups.end, b, op),
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chunks_cover_the_groups_once_in_order() {
        for n in [0, 1, CHUNK_GROUPS, CHUNK_GROUPS + 1, 5 * CHUNK_GROUPS + 17] {
            let seen = reduce(0..n, &|r| vec![r], &|mut a, b| {
                a.extend(b);
                a
            });
            let mut next = 0;
            for r in &seen {
                assert_eq!(r.start, next);
                assert!(!r.is_empty() || n == 0);
                assert!(r.len() <= CHUNK_GROUPS);
                next = r.end;
            }
            assert_eq!(next, n);
            // Groups of one and two rows: each chunk writes its own rows.
            let gs: Vec<usize> = (0..=n).map(|g| g + g / 3).collect();
            let mut out = vec![usize::MAX; gs[n]];
            for_rows(&gs, 0..n, &mut out, &|groups, rows| {
                let base = gs[groups.start];
                for g in groups {
                    for row in gs[g]..gs[g + 1] {
                        rows[row - base] = g;
                    }
                }
            });
            for g in 0..n {
                assert!(out[gs[g]..gs[g + 1]].iter().all(|&v| v == g));
            }
        }
    }
}
