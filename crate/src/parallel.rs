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
