//! Data parallelism on one CPU: a batch's gradient computed as the sum of its sub-batches'
//! gradients, the sub-batches' forward and backward passes running at once on rayon's threads.
//!
//! Why: a training step of either model keeps only about 1.1 of two cores busy (Burn's CPU
//! backend parallelises the matrix products, not the many small operations between them), so
//! two sub-batches at once take about 60% of the time of one pass over the batch
//! (docs/experiments/2026-11-28-data-parallel-training.md). Both models' losses are means over
//! the batch's examples, so a sub-batch's mean loss weighted by its share of the examples has
//! exactly its part of the batch's gradient; the sum differs from one pass only by float
//! rounding.
//!
//! Each sub-batch runs on its own copy of the model (`Fork`): the same parameter values, ids
//! and trainability, but fresh autodiff leaves. Burn's autodiff keeps the graphs that share a
//! node under one lock, so copies sharing the parameters' nodes would run one after the other.

use std::ops::Range;

use burn::module::{Module, ModuleMapper, ModuleVisitor, Param};
use burn::optim::GradientsParams;
use burn::tensor::Tensor;

use crate::parallel::map_in_parallel;

/// The default of the configurations' `data_parallel`: the whole batch in one pass.
pub(crate) fn one_pass() -> usize {
    1
}

/// Whether `data_parallel` is the default (left out of a written configuration, so files and
/// manifests from before it existed read the same).
pub(crate) fn is_one_pass(parts: &usize) -> bool {
    *parts == 1
}

/// `items` cut into at most `parts` contiguous ranges of near-equal size (the first ones one
/// longer), none empty; one range `0..items` when `parts` is 1 or `items` is at most 1.
pub fn sub_batches(items: usize, parts: usize) -> Vec<Range<usize>> {
    let parts = parts.clamp(1, items.max(1));
    let (size, extra) = (items / parts, items % parts);
    let mut start = 0;
    (0..parts)
        .map(|k| {
            let len = size + usize::from(k < extra);
            start += len;
            start - len..start
        })
        .collect()
}

/// The gradients of `sum_k share_k * loss_k` over the sub-batches in `work` (`(share, input)`
/// pairs), where `loss_of(model, input)` returns a sub-batch's mean loss and whatever else the
/// caller wants back. The sub-batches run at once, each on its own copy of `model`; the
/// results come back in `work`'s order with their shares, and the gradients are keyed by
/// `model`'s parameter ids, ready for the optimiser.
pub fn gradients_in_parallel<M, T, O, F>(
    model: &M,
    work: Vec<(f64, T)>,
    loss_of: F,
) -> (Vec<(f64, O)>, GradientsParams)
where
    M: Module + Send,
    T: Send,
    O: Send,
    F: Fn(&M, T) -> (Tensor<1>, O) + Sync + Send,
{
    let work: Vec<(M, f64, T)> = work
        .into_iter()
        .map(|(share, input)| (model.clone().map(&mut Fork), share, input))
        .collect();
    let done = map_in_parallel(work, |_, (copy, share, input)| {
        let (loss, out) = loss_of(&copy, input);
        let grads = GradientsParams::from_grads((loss * share).backward(), &copy);
        ((share, out), grads)
    });
    let mut outs = Vec::with_capacity(done.len());
    let mut sum = GradientsParams::new();
    for (out, grads) in done {
        outs.push(out);
        model.visit(&mut SumGrads {
            into: &mut sum,
            from: grads,
        });
    }
    (outs, sum)
}

/// Maps a module to a copy whose parameters are new autodiff leaves (`detach` keeps the value,
/// the id and whether it needs a gradient, and drops the graph node).
struct Fork;

impl ModuleMapper for Fork {
    fn map_float<const D: usize>(&mut self, param: Param<Tensor<D>>) -> Param<Tensor<D>> {
        param.map(|t| t.detach())
    }
}

/// Adds the gradients in `from` to those in `into`, parameter by parameter.
struct SumGrads<'a> {
    into: &'a mut GradientsParams,
    from: GradientsParams,
}

impl ModuleVisitor for SumGrads<'_> {
    fn visit_float<const D: usize>(&mut self, param: &Param<Tensor<D>>) {
        if let Some(g) = self.from.remove::<D>(param.id) {
            let sum = match self.into.remove::<D>(param.id) {
                Some(acc) => acc + g,
                None => g,
            };
            self.into.register(param.id, sum);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::sub_batches;

    #[test]
    fn sub_batches_cover_the_batch_in_near_equal_contiguous_parts() {
        assert_eq!(sub_batches(8, 2), vec![0..4, 4..8]);
        assert_eq!(sub_batches(4, 3), vec![0..2, 2..3, 3..4]);
        assert_eq!(sub_batches(3, 8), vec![0..1, 1..2, 2..3]);
        assert_eq!(sub_batches(5, 1), vec![0..5]);
        assert_eq!(sub_batches(1, 2), vec![0..1]);
        for items in 1..20 {
            for parts in 1..6 {
                let r = sub_batches(items, parts);
                assert_eq!(r.len(), parts.min(items));
                assert_eq!((r[0].start, r[r.len() - 1].end), (0, items));
                assert!(r.windows(2).all(|w| w[0].end == w[1].start));
                let lens: Vec<usize> = r.iter().map(|x| x.len()).collect();
                assert!(lens.iter().max().unwrap() - lens.iter().min().unwrap() <= 1);
            }
        }
    }
}
