//! Independent pieces of work on rayon's threads where threads exist (native targets and the
//! threaded wasm module, feature `threads`), in order where they do not (the other wasm32
//! modules).

/// `f(k, item)` for every item, results in order, on rayon's threads.
#[cfg(any(not(target_arch = "wasm32"), feature = "threads"))]
pub(crate) fn map_in_parallel<T, R, F>(items: Vec<T>, f: F) -> Vec<R>
where
    T: Send,
    R: Send,
    F: Fn(usize, T) -> R + Sync + Send,
{
    use rayon::prelude::*;
    items
        .into_par_iter()
        .enumerate()
        .map(|(k, t)| f(k, t))
        .collect()
}

/// `f(k, item)` for every item, results in order (this wasm32 module has no threads).
#[cfg(all(target_arch = "wasm32", not(feature = "threads")))]
pub(crate) fn map_in_parallel<T, R, F>(items: Vec<T>, f: F) -> Vec<R>
where
    F: Fn(usize, T) -> R,
{
    items
        .into_iter()
        .enumerate()
        .map(|(k, t)| f(k, t))
        .collect()
}

/// The threads [`map_in_parallel`] and [`in_parts`] spread work over: rayon's pool.
#[cfg(any(not(target_arch = "wasm32"), feature = "threads"))]
pub(crate) fn threads() -> usize {
    rayon::current_num_threads()
}

/// `f()` on one of rayon's threads: the parallel work inside it is then shared among the
/// pool's threads, where from a thread outside the pool (the page's model worker in the
/// threaded module) each parallel call is handed to the pool and waited for.
#[cfg(all(target_arch = "wasm32", feature = "threads"))]
pub(crate) fn on_pool<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    rayon::scope(|_| f())
}

/// The lengths of the contiguous runs that `count` items are cut into for `parts` workers: at
/// most `parts` runs (at least one), of nearly equal length, the first ones one longer.
pub(crate) fn run_lengths(count: usize, parts: usize) -> Vec<usize> {
    let parts = parts.clamp(1, count.max(1));
    let (short, long) = (count / parts, count % parts);
    (0..parts).map(|k| short + usize::from(k < long)).collect()
}

/// `items` cut into [`run_lengths`] runs, results in order: `first` takes the first run on the calling thread, so it may
/// hold what cannot cross threads (a progress callback), while `rest` takes each of the others
/// on rayon's threads at the same time.
#[cfg(any(not(target_arch = "wasm32"), feature = "threads"))]
pub(crate) fn in_parts<T, R>(
    items: Vec<T>,
    parts: usize,
    first: impl FnOnce(Vec<T>) -> R,
    rest: impl Fn(Vec<T>) -> R + Sync,
) -> Vec<R>
where
    T: Send,
    R: Send,
{
    let lengths = run_lengths(items.len(), parts);
    let mut items = items.into_iter();
    let mut runs: Vec<Vec<T>> = (lengths.iter())
        .map(|&n| items.by_ref().take(n).collect())
        .collect();
    let head = runs.remove(0);
    let mut outs: Vec<Option<R>> = (0..runs.len()).map(|_| None).collect();
    let rest = &rest;
    let head_out = rayon::in_place_scope(|scope| {
        for (run, slot) in runs.into_iter().zip(outs.iter_mut()) {
            scope.spawn(move |_| *slot = Some(rest(run)));
        }
        first(head)
    });
    std::iter::once(head_out)
        .chain(outs.into_iter().map(|o| o.expect("every run ran")))
        .collect()
}

#[cfg(all(test, any(not(target_arch = "wasm32"), feature = "threads")))]
mod tests {
    use super::*;

    /// Every item lands in exactly one run, in order, and the runs differ by at most one item.
    #[test]
    fn in_parts_keeps_order_and_balances_the_runs() {
        for (n, parts) in [(12, 2), (12, 5), (3, 8), (1, 1), (0, 3), (7, 3)] {
            let runs = in_parts((0..n).collect(), parts, |r: Vec<usize>| r, |r| r);
            let flat: Vec<usize> = runs.iter().flatten().copied().collect();
            assert_eq!(flat, (0..n).collect::<Vec<_>>(), "{n} in {parts}");
            let (lo, hi) = (
                runs.iter().map(Vec::len).min().unwrap(),
                runs.iter().map(Vec::len).max().unwrap(),
            );
            assert!(
                hi - lo <= 1 && runs.len() <= parts.max(1),
                "{n} in {parts}: {runs:?}"
            );
        }
    }
}
