//! Weave patterns and their weft fraction `γ` (paper Eq. (23); MODEL.md §2.7).
