//! The WGSL twins. Each module is a binding-free snippet; the constants in it are tied to
//! the Rust definitions by the unit tests at the bottom of this file.

/// Vis-buffer ID pack/unpack in WGSL. See the crate docs' WGSL table.
pub const ID_WGSL: &str = include_str!("wgsl/id.wgsl");

#[cfg(test)]
mod tests {
    use super::*;
    use crate::id::*;
    use shadercheck::{Caps, assert_valid, const_u32};

    #[test]
    fn id_wgsl_is_valid_core_wgsl_and_its_constants_match_rust() {
        let m = assert_valid("visbuf ID_WGSL", ID_WGSL, Caps::CORE);
        let expect = [
            ("VISBUF_NONE", VIS_NONE),
            ("VISBUF_MICRO_BATCH_SHIFT", VIS_MICRO_BATCH_SHIFT),
            ("VISBUF_MICRO_BATCH_MASK", MICRO_BATCH_IDS - 1),
            ("VISBUF_MICRO_BATCH_MASK_VRS", MICRO_BATCH_IDS_VRS - 1),
            ("VISBUF_RATE_SHIFT", VIS_RATE_SHIFT),
            ("VISBUF_RATE_MASK", (1 << VIS_RATE_BITS) - 1),
            (
                "VISBUF_INSTANCE_PRIMITIVE_BITS",
                VIS_INSTANCE_PRIMITIVE_BITS,
            ),
            (
                "VISBUF_INSTANCE_PRIMITIVE_MASK",
                VIS_INSTANCE_PRIMITIVE_MASK,
            ),
            ("VISBUF_MAX_PRIMITIVE_BITS", MAX_PRIMITIVE_BITS),
            ("VISBUF_MICRO_BATCH_IDS", MICRO_BATCH_IDS),
            ("VISBUF_MICRO_BATCH_IDS_VRS", MICRO_BATCH_IDS_VRS),
        ];
        for (name, value) in expect {
            assert_eq!(const_u32(&m, name), Some(value), "WGSL const {name}");
        }
        // Every constant the snippet declares is one of those checked above.
        for name in shadercheck::const_names(&m) {
            assert!(
                expect.iter().any(|(n, _)| *n == name),
                "unchecked WGSL const {name}"
            );
        }
    }

    #[test]
    fn every_wgsl_name_is_prefixed() {
        for (name, src) in [("ID_WGSL", ID_WGSL)] {
            for line in src.lines() {
                let t = line.trim_start();
                for kw in ["fn ", "const ", "struct "] {
                    if let Some(rest) = t.strip_prefix(kw) {
                        let lower = rest.to_ascii_lowercase();
                        assert!(lower.starts_with("visbuf"), "{name}: unprefixed `{t}`");
                    }
                }
                assert!(
                    !t.starts_with('@'),
                    "{name}: attributes (bindings/entry points) not allowed: `{t}`"
                );
                assert!(
                    !t.starts_with("var"),
                    "{name}: module-scope var not allowed: `{t}`"
                );
            }
        }
    }
}
