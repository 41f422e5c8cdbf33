//! After extraction: the generated vertices fitted to the input points ([`fit`]), and the
//! surface completed between them where the input says there is surface ([`complete`]), and
//! the holes left after that closed ([`close`]).

pub mod close;
pub mod complete;
pub mod fit;
