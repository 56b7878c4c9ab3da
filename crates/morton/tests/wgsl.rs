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
fn every_function_is_prefixed() {
    let module = module();
    let mut names = Vec::new();
    for (_, f) in module.functions.iter() {
        let name = f.name.clone().unwrap_or_default();
        assert!(name.starts_with("morton_"), "{name}");
        names.push(name);
    }
    for want in [
        "morton_encode2_u32",
        "morton_decode2_u32",
        "morton_encode3_u32",
        "morton_decode3_u32",
        "morton_quantize3",
        "morton_key3_u32",
    ] {
        assert!(names.iter().any(|n| n == want), "{want} missing");
    }
    for name in shadercheck::const_names(&module) {
        assert!(name.starts_with("MORTON_"), "{name}");
    }
    assert!(module.entry_points.is_empty());
    assert!(module.global_variables.is_empty(), "no bindings");
}
