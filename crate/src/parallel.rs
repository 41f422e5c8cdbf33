//! Independent pieces of work on rayon's threads where threads exist (native targets), in
//! order where they do not (wasm32).

/// `f(k, item)` for every item, results in order; on native targets on rayon's threads.
#[cfg(not(target_arch = "wasm32"))]
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

/// `f(k, item)` for every item, results in order (wasm32 has no threads here).
#[cfg(target_arch = "wasm32")]
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
