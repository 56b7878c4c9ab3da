//! The WGSL twin: valid under naga with core capabilities, constants equal to Rust's.

use shadercheck::{Caps, const_u32};

fn module() -> naga::Module {
    shadercheck::assert_composed(&[morton::wgsl::MODULES], "morton::codes", &[], Caps::CORE)
}

#[test]
fn wgsl_is_valid_and_constants_match() {
    let module = module();
    let c = |name| const_u32(&module, name).unwrap_or_else(|| panic!("{name} missing"));
    assert_eq!(c("MORTON_BITS2_U32"), morton::BITS2_U32);
    assert_eq!(c("MORTON_BITS3_U32"), morton::BITS3_U32);
    assert_eq!(c("MORTON_MASK2_X_U32"), morton::MASK2_X_U32);
    assert_eq!(c("MORTON_MASK2_Y_U32"), morton::MASK2_Y_U32);
    assert_eq!(c("MORTON_MASK3_X_U32"), morton::MASK3_X_U32);
    assert_eq!(c("MORTON_MASK3_Y_U32"), morton::MASK3_Y_U32);
    assert_eq!(c("MORTON_MASK3_Z_U32"), morton::MASK3_Z_U32);
}

#[test]
fn every_item_is_prefixed_and_the_twins_exist() {
    let module = module();
    // Functions `morton_`, constants `MORTON_`, no bindings, no entry points.
    shadercheck::assert_prefixed("morton::codes", &module, "morton", &[], true);
    // No module-scope variables of any kind (functions and constants only).
    assert!(
        module.global_variables.is_empty(),
        "no module-scope variables"
    );
    for want in [
        "morton_encode2_u32",
        "morton_decode2_u32",
        "morton_encode3_u32",
        "morton_decode3_u32",
        "morton_quantize3",
        "morton_key3_u32",
    ] {
        assert!(
            module
                .functions
                .iter()
                .any(|(_, f)| f.name.as_deref() == Some(want)),
            "{want} missing"
        );
    }
}
