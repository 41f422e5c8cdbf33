//! After extraction: the generated vertices fitted to the input points ([`fit`]), and the
//! surface completed between them where the input says there is surface ([`complete`]).

pub mod complete;
pub mod fit;
