//! The yarn: arc-topped prism cross-sections, their exact masking, and the distributions of
//! slopes and twist (paper §3; MODEL.md §2.1–§2.6).

pub mod profile;
pub mod raycast;
