//! Fiber BRDF properties (MODEL.md §1, §6).
