//! Lookup tables for the channel encodings whose formulas need `pow`, `log2` or `exp2`
//! per value: a binary search over 255 thresholds (encode) or one load (decode) instead.
//!
//! The tables themselves are in `tables/generated.rs`, written by their generator
//! `crates/deferred/tests/tables.rs` (`DEFERRED_REGENERATE=1 cargo test -p deferred --test
//! tables`), which also fails when the committed file differs from what it generates.
//! Every entry is the f64 formula rounded to f32; the formulas live in the generator only.

mod generated;

pub(crate) use generated::{
    KZ2_ROUGHNESS, SPEC_POWER_THRESHOLDS, SRGB_DECODE, SRGB_ENCODE_THRESHOLDS,
};

/// The number of entries of an ascending 255-entry table at or below `x` (NaN: 0), by a
/// branch-free binary search.
#[inline]
pub(crate) fn count_at_or_below(table: &[f32; 255], x: f32) -> u8 {
    let mut i = 0usize;
    for step in [128usize, 64, 32, 16, 8, 4, 2, 1] {
        if x >= table[i + step - 1] {
            i += step;
        }
    }
    i as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encode_thresholds_ascend() {
        // `count_at_or_below` needs strictly ascending tables; the values themselves are
        // pinned by the generator's test (`tests/tables.rs`).
        assert!(SRGB_ENCODE_THRESHOLDS.windows(2).all(|w| w[0] < w[1]));
        assert!(SPEC_POWER_THRESHOLDS.windows(2).all(|w| w[0] < w[1]));
    }

    #[test]
    fn search_counts_entries() {
        let t: [f32; 255] = core::array::from_fn(|i| i as f32);
        assert_eq!(count_at_or_below(&t, -1.0), 0);
        assert_eq!(count_at_or_below(&t, 0.0), 1);
        assert_eq!(count_at_or_below(&t, 100.5), 101);
        assert_eq!(count_at_or_below(&t, 254.0), 255);
        assert_eq!(count_at_or_below(&t, f32::INFINITY), 255);
        assert_eq!(count_at_or_below(&t, f32::NAN), 0);
    }
}
