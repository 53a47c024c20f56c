//! The arc-topped prism profile and its exact lit-and-visible intervals (MODEL.md §2.1–§2.2).
