//! The query module's WGSL run on testkit's device (lavapipe in CI) against the Rust
//! reference. There is no query pass yet; until there is, the functions a pass will call
//! are run here one by one. A machine without a GPU driver fails, saying how to install one.

/// `staticscene_f16` (the half-float decode of the culling boxes and LOD scales, written
/// out because `unpack2x16float` needs a capability) against the `half` crate for every
/// finite f16 pattern: exact.
#[test]
fn wgsl_f16_decode_is_exact_for_every_finite_half() {
    let items = 1u32 << 16;
    let out = testkit::device::run_words(
        &[staticscene::wgsl::MODULES],
        "#import staticscene::query",
        "_ = input[0];\n    output[i] = bitcast<u32>(staticscene_f16(i));",
        &[0],
        items,
        1,
        &[],
    );
    let mut checked = 0;
    for h in 0..=u16::MAX {
        let want = half::f16::from_bits(h);
        // The encoder never stores infinities or NaN.
        if !want.is_finite() {
            continue;
        }
        let got = f32::from_bits(out[usize::from(h)]);
        assert_eq!(
            got.to_bits(),
            want.to_f32().to_bits(),
            "{h:#06x}: {got} vs {want}"
        );
        checked += 1;
    }
    assert_eq!(
        checked, 63_488,
        "every finite half (2^16 - 2 * 1024 inf/NaN)"
    );
}
