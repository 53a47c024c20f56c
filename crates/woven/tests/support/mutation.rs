//! Byte-level mutation of valid files for the property tests over hostile input of the renderer,
//! the fitter's readers and the explorer (one copy, included by path from each crate's tests).

use proptest::prelude::*;

/// `seed` with `edits` applied in turn: `(position, byte, kind)` replaces (0), inserts (1) or
/// removes (2) the byte at `position` (taken modulo the length).
pub fn mutate(seed: &[u8], edits: &[(usize, u8, u8)]) -> Vec<u8> {
    let mut out = seed.to_vec();
    for &(at, byte, kind) in edits {
        let at = at % (out.len() + 1);
        match kind % 3 {
            _ if at == out.len() => out.push(byte),
            0 => out[at] = byte,
            1 => out.insert(at, byte),
            _ => {
                out.remove(at);
            }
        }
    }
    out
}

/// One to seven edits.
pub fn edits() -> impl Strategy<Value = Vec<(usize, u8, u8)>> {
    proptest::collection::vec((any::<usize>(), any::<u8>(), any::<u8>()), 1..8)
}
