//! Weave patterns and their weft fraction `γ` (paper Eq. (23); docs/spec.md §2.7).
//!
//! ```
//! use woven::weave::Pattern;
//! // A 5-harness satin shows its weft at one cell in five: γ = 1/5.
//! let satin = Pattern::from_name("satin-5")?;
//! assert_eq!(satin.weft_fraction(), 0.2);
//! # Ok::<(), woven::Error>(())
//! ```
//!
//! The cloth BRDF of Eq. (23) mixes the two yarn directions by the visible fraction of weft,
//! `f_cloth = γ f_yarn(φ = 0) + (1 − γ) f_yarn(φ = π/2)`. A [`Pattern`] is the binary weave matrix
//! that fixes `γ` (its mean) and tells a renderer which yarn lies on top at a texture coordinate.
//!
//! Layout of the matrix (docs/spec.md §0: weft along `x`, warp along `y`):
//! - a **row** is one weft pick; successive rows advance along the warp direction `y`;
//! - a **column** is one warp end; successive columns advance along the weft direction `x`;
//! - a cell is `true` (`1`, `#`) where the **weft** floats on top and `false` (`0`, `.`) where
//!   the warp does (docs/spec.md §2.7: "1 where weft floats on top").
//!
//! The matrix is one repeat of a periodic tiling: every index wraps around.
//!
//! | parameter | meaning | unit | default | valid range |
//! |---|---|---|---|---|
//! | `weave.pattern` (name) | `plain`, `twill-N/M`, `satin-N` or `sateen-N` | — | — | see below |
//! | `weave.pattern` (matrix) | rows of `0` (warp on top) / `1` (weft on top) | — | — | rectangular, non-empty, ≤ [`MAX_THREADS`] per side |
//! | `weave.twill.over` | `N` of `twill-N/M`: picks each warp end passes over | picks | — | `≥ 1`, `N + M ≤` [`MAX_THREADS`] |
//! | `weave.twill.under` | `M` of `twill-N/M`: picks each warp end passes under | picks | — | `≥ 1` |
//! | `weave.satin.n`, `weave.sateen.n` | harness count `n` of a satin / sateen | — | — | `n ≥ 5`, `n ≠ 6`, `n ≤` [`MAX_THREADS`] |
//! | WIF `[WEAVING] Rising Shed` | whether tie-up / lift plan marks *lifted* shafts | — | `yes` | `yes`/`no`, `true`/`false`, `1`/`0`, `on`/`off` |
//! | `γ` (derived) | visible weft fraction, the mean of the matrix | — | — | `[0, 1]` |
//!
//! The named weaves and their weft fractions:
//!
//! | name | γ | face |
//! |---|---|---|
//! | `plain` | 1/2 | balanced |
//! | `twill-N/M` | `M / (N + M)` (`twill-2/1`: 1/3) | warp-faced when `N > M` |
//! | `satin-N` | `1/N` (`satin-5`: 1/5) | warp-faced |
//! | `sateen-N` | `(N − 1)/N` (`sateen-5`: 4/5) | weft-faced |
//!
//! Patterns also come from Weaving Information Files (WIF, an INI-like text format; see
//! [`Pattern::from_wif_str`]), which is how hand-loom drafts are exchanged.

mod pattern;
mod spec;
mod wif;

pub use pattern::{CellPoint, FloatPlace, Pattern, MAX_THREADS, MAX_WIF_BYTES};
pub use spec::{PatternSpec, PATTERN_FORMS};
