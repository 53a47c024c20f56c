//! The key parameters of a material in words: for `woven materials` and for figure titles. The
//! library's ([`woven::figures::words`]).

pub use woven::figures::words::{description, short, Summary};
