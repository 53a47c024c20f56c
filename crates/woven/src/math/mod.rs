//! Small numerical building blocks: vectors and frames, special functions, quadrature,
//! interpolation and sampling. Everything the model's integrals need, written and tested here.

pub mod basis;
pub mod hemisphere;
pub mod interp;
pub mod lanes;
pub mod legendre;
pub mod marginal;
pub mod quadrature;
pub mod rng;
pub mod roots;
pub mod sampling;
pub mod special;
pub mod vec3;

pub use vec3::Vec3;
