//! After extraction: the generated vertices fitted to the input points ([`fit`]), and the
//! surface completed between them where the input says there is surface ([`complete`]), and
//! the holes left after that closed ([`close`]); last, the surface made flat where the input
//! is flat and sharp where it creases ([`sharpen`]).

pub mod close;
pub mod complete;
pub mod fit;
pub mod input;
pub mod sharpen;
