//! Evaluation: the paper's metrics (docs/design.md section 3).

pub mod metrics;
