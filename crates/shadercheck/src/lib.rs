//! Test-only helper: validate the workspace's WGSL with naga, without a GPU, and read a
//! module's constants so a test can tie them to the Rust definition they were made from.
//!
//! Every crate that exports WGSL uses this from its unit tests (as a dev-dependency), so
//! that a shader that does not parse or validate fails `cargo test`, not a device.
//!
//! ```
//! let src = "const VIS_PRIMITIVE_BITS_MAX: u32 = 16u;\n\
//!            fn twice(x: u32) -> u32 { return x * 2u; }";
//! let module = shadercheck::validate(src, shadercheck::Caps::CORE).expect("valid WGSL");
//! assert_eq!(shadercheck::const_u32(&module, "VIS_PRIMITIVE_BITS_MAX"), Some(16));
//! ```

use naga::valid::{Capabilities, ValidationFlags, Validator};

mod pass;
pub use pass::{assert_composed, check_pass, check_pass_with, check_raster};

/// Which optional capabilities the validator allows: a shader written for the fallback
/// path is validated with [`Caps::CORE`] to prove that it needs none of them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Caps(Capabilities);

impl Caps {
    /// What every wgpu adapter has: naga's defaults.
    pub const CORE: Caps =
        Caps(Capabilities::MULTISAMPLED_SHADING.union(Capabilities::CUBE_ARRAY_TEXTURES));
    /// CORE plus subgroup operations in compute and fragment stages (`Features::SUBGROUP`).
    pub const SUBGROUP: Caps = Caps(Self::CORE.0.union(Capabilities::SUBGROUP));
    /// CORE plus `@builtin(primitive_index)` (`Features::PRIMITIVE_INDEX`).
    pub const PRIMITIVE_INDEX: Caps = Caps(Self::CORE.0.union(Capabilities::PRIMITIVE_INDEX));
    /// CORE plus per-vertex fragment inputs (`Features::SHADER_PER_VERTEX`).
    pub const PER_VERTEX: Caps = Caps(Self::CORE.0.union(Capabilities::PER_VERTEX));
    /// CORE plus 64-bit integers and their atomic min/max.
    pub const INT64: Caps = Caps(
        Self::CORE
            .0
            .union(Capabilities::SHADER_INT64)
            .union(Capabilities::SHADER_INT64_ATOMIC_MIN_MAX),
    );
    /// INT64 plus 64-bit texture atomics (`Features::TEXTURE_INT64_ATOMIC`: `r64uint`
    /// storage textures with atomic min and max).
    pub const TEXTURE_INT64: Caps = Caps(
        Self::INT64
            .0
            .union(Capabilities::TEXTURE_ATOMIC)
            .union(Capabilities::TEXTURE_INT64_ATOMIC),
    );
    /// CORE plus `f16` (`Features::SHADER_F16`).
    pub const F16: Caps = Caps(Self::CORE.0.union(Capabilities::SHADER_FLOAT16));
    /// Core plus `@early_depth_test` (`Features::SHADER_EARLY_DEPTH_TEST`).
    pub const EARLY_DEPTH_TEST: Caps = Caps(Self::CORE.0.union(Capabilities::EARLY_DEPTH_TEST));
    /// Core plus `@builtin(barycentric)` (`Features::SHADER_BARYCENTRICS`).
    pub const BARYCENTRICS: Caps = Caps(Self::CORE.0.union(Capabilities::SHADER_BARYCENTRICS));
    /// Everything naga knows.
    pub const ALL: Caps = Caps(Capabilities::all());

    /// Both capability sets.
    #[must_use]
    pub const fn union(self, other: Caps) -> Caps {
        Caps(self.0.union(other.0))
    }
}

/// Parse and validate `source`, returning the module or a readable report (with the
/// offending source line) naming what failed.
pub fn validate(source: &str, caps: Caps) -> Result<naga::Module, String> {
    let module = naga::front::wgsl::parse_str(source).map_err(|e| e.emit_to_string(source))?;
    Validator::new(ValidationFlags::all(), caps.0)
        .validate(&module)
        .map_err(|e| format!("{}", WithSource(&e, source)))?;
    Ok(module)
}

/// Like [`validate`], but panics with the report: for use directly in `#[test]`s.
#[track_caller]
pub fn assert_valid(name: &str, source: &str, caps: Caps) -> naga::Module {
    match validate(source, caps) {
        Ok(m) => m,
        Err(report) => panic!("WGSL module `{name}` failed naga validation:\n{report}"),
    }
}

struct WithSource<'a>(&'a naga::WithSpan<naga::valid::ValidationError>, &'a str);

impl core::fmt::Display for WithSource<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        writeln!(f, "{:?}", self.0.as_inner())?;
        for (span, label) in self.0.spans() {
            let loc = span.location(self.1);
            let line = self
                .1
                .lines()
                .nth(loc.line_number.saturating_sub(1) as usize)
                .unwrap_or("");
            writeln!(f, "  at line {}: {label}\n    {line}", loc.line_number)?;
        }
        Ok(())
    }
}

fn literal(module: &naga::Module, name: &str) -> Option<naga::Literal> {
    let (_, c) = module
        .constants
        .iter()
        .find(|(_, c)| c.name.as_deref() == Some(name))?;
    match module.global_expressions[c.init] {
        naga::Expression::Literal(l) => Some(l),
        _ => None,
    }
}

/// The value of a module-scope `const NAME: u32 = ...;` (or a non-negative `i32`), if the
/// module declares it with a literal value. Give shared constants an explicit type: naga
/// drops untyped (abstract) constants that nothing uses.
pub fn const_u32(module: &naga::Module, name: &str) -> Option<u32> {
    match literal(module, name)? {
        naga::Literal::U32(v) => Some(v),
        naga::Literal::I32(v) => u32::try_from(v).ok(),
        naga::Literal::AbstractInt(v) => u32::try_from(v).ok(),
        _ => None,
    }
}

/// The value of a module-scope `const NAME: f32 = ...;`, if declared with a literal.
pub fn const_f32(module: &naga::Module, name: &str) -> Option<f32> {
    match literal(module, name)? {
        naga::Literal::F32(v) => Some(v),
        naga::Literal::AbstractFloat(v) => Some(v as f32),
        _ => None,
    }
}

/// The default of a module-scope `override NAME: f32 = ...;`, if declared with a literal
/// (the value a pipeline gets when Rust sets none).
pub fn override_f32(module: &naga::Module, name: &str) -> Option<f32> {
    let (_, o) = module
        .overrides
        .iter()
        .find(|(_, o)| o.name.as_deref() == Some(name))?;
    match module.global_expressions[o.init?] {
        naga::Expression::Literal(naga::Literal::F32(v)) => Some(v),
        naga::Expression::Literal(naga::Literal::AbstractFloat(v)) => Some(v as f32),
        _ => None,
    }
}

/// The layout naga gives a WGSL struct: its size and its members' names and offsets, in
/// bytes, in declaration order. `None` when the module declares no struct `name`.
pub fn struct_layout(module: &naga::Module, name: &str) -> Option<(u32, Vec<(String, u32)>)> {
    let (_, ty) = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some(name))?;
    match &ty.inner {
        naga::TypeInner::Struct { members, span } => Some((
            *span,
            members
                .iter()
                .map(|m| (m.name.clone().unwrap_or_default(), m.offset))
                .collect(),
        )),
        _ => None,
    }
}

/// `[(WGSL member name, byte offset)]` of fields of a `#[repr(C)]` Rust struct, in the
/// order given, for [`assert_struct_layout`]: the offsets come from `offset_of!`, so a Rust
/// field moved or resized fails the check. A member named differently in WGSL gives its
/// WGSL name after a colon.
///
/// ```
/// #[repr(C)]
/// struct Light { position: [f32; 3], range: f32, color: [f32; 3], flags: u32 }
/// let m = shadercheck::members!(Light { position, range, color: "colour", flags });
/// assert_eq!(m, [("position", 0), ("range", 12), ("colour", 16), ("flags", 28)]);
/// ```
#[macro_export]
macro_rules! members {
    ($t:ty { $($f:ident $(: $wgsl:literal)?),* $(,)? }) => {
        [$(($crate::members!(@name $f $($wgsl)?), ::core::mem::offset_of!($t, $f) as u32)),*]
    };
    (@name $f:ident) => { stringify!($f) };
    (@name $f:ident $wgsl:literal) => { $wgsl };
}

/// Checks that WGSL struct `name` is `size` bytes with exactly `members` (name, byte
/// offset), in order: how a crate proves its `#[repr(C)]` twin and its WGSL agree.
#[track_caller]
pub fn assert_struct_layout(
    module: &naga::Module,
    name: &str,
    size: usize,
    members: &[(&str, u32)],
) {
    let (span, found) =
        struct_layout(module, name).unwrap_or_else(|| panic!("no WGSL struct {name}"));
    let found: Vec<(&str, u32)> = found.iter().map(|(n, o)| (n.as_str(), *o)).collect();
    assert_eq!(found, members, "WGSL struct {name}: (member, offset)");
    assert_eq!(span as usize, size, "WGSL struct {name}: size in bytes");
}

/// Checks a crate's naming rule on a validated module: every function starts with
/// `{prefix}_`, every constant with `{PREFIX}_`, every struct with `{Prefix}` (naga's
/// predeclared `__*` result types excepted), every module-scope `var<workgroup>` with
/// `{prefix}_`. Items of the crates in `also` (imported modules) are allowed under their
/// own prefixes. With `snippet`, the module must also declare no bindings and no entry
/// points (what a library module shipped for others to import looks like).
#[track_caller]
pub fn assert_prefixed(
    name: &str,
    module: &naga::Module,
    prefix: &str,
    also: &[&str],
    snippet: bool,
) {
    let lower: Vec<String> = core::iter::once(prefix)
        .chain(also.iter().copied())
        .map(|p| format!("{p}_"))
        .collect();
    let upper: Vec<String> = lower.iter().map(|p| p.to_uppercase()).collect();
    let camel: Vec<String> = core::iter::once(prefix)
        .chain(also.iter().copied())
        .map(|p| {
            let mut c = p.chars();
            c.next()
                .map(|f| f.to_uppercase().chain(c).collect())
                .unwrap_or_default()
        })
        .collect();
    let ok = |n: &str, ps: &[String]| ps.iter().any(|p| n.starts_with(p.as_str()));
    for (_, f) in module.functions.iter() {
        let n = f.name.as_deref().unwrap_or("");
        assert!(
            ok(n, &lower),
            "{name}: function `{n}` is not prefixed `{prefix}_`"
        );
    }
    for n in const_names(module) {
        assert!(ok(&n, &upper), "{name}: constant `{n}` is not prefixed");
    }
    for (_, t) in module.types.iter() {
        if let Some(n) = t.name.as_deref()
            && matches!(t.inner, naga::TypeInner::Struct { .. })
            && !n.starts_with("__")
        {
            assert!(ok(n, &camel), "{name}: struct `{n}` is not prefixed");
        }
    }
    for (_, g) in module.global_variables.iter() {
        let n = g.name.as_deref().unwrap_or("");
        if snippet {
            assert!(
                g.binding.is_none(),
                "{name}: a library module declares binding `{n}`"
            );
        }
        if g.space == naga::AddressSpace::WorkGroup {
            assert!(
                ok(n, &lower),
                "{name}: workgroup variable `{n}` is not prefixed"
            );
        }
    }
    if snippet {
        assert!(
            module.entry_points.is_empty(),
            "{name}: a library module declares entry points"
        );
    }
}

/// Names of all module-scope constants, for tests that check every WGSL constant has a
/// Rust counterpart.
pub fn const_names(module: &naga::Module) -> Vec<String> {
    module
        .constants
        .iter()
        .filter_map(|(_, c)| c.name.clone())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_subgroup_ops_without_the_capability() {
        let src = "@compute @workgroup_size(32) fn main(@builtin(subgroup_invocation_id) l: u32) {\n\
                   let b = subgroupBallot(l == 0u);\n}";
        assert!(validate(src, Caps::CORE).is_err());
        assert!(validate(src, Caps::SUBGROUP).is_ok());
    }

    #[test]
    fn reports_parse_errors_with_the_line() {
        let err = validate("fn f() -> u32 { return 1.0; }", Caps::CORE).unwrap_err();
        assert!(err.contains("return"), "{err}");
    }

    #[test]
    fn reads_constants() {
        let m = assert_valid(
            "t",
            "const A: u32 = 7u; const B: f32 = 0.5; const C: i32 = 3; const E: i32 = -1;",
            Caps::CORE,
        );
        assert_eq!(const_u32(&m, "A"), Some(7));
        assert_eq!(const_f32(&m, "B"), Some(0.5));
        assert_eq!(const_u32(&m, "C"), Some(3));
        assert_eq!(const_u32(&m, "D"), None);
        assert_eq!(const_u32(&m, "E"), None, "negative values are not u32");
    }

    const STRUCT: &str = "struct S { a: vec3<f32>, b: u32, c: vec2<f32> }\n\
                          @group(0) @binding(0) var<storage> s: array<S>;";

    #[test]
    fn reads_struct_layouts_by_wgsl_rules() {
        let m = assert_valid("t", STRUCT, Caps::CORE);
        // vec3 is 12 bytes aligned to 16, so b packs after it; vec2 aligns to 8;
        // the struct rounds up to its 16-byte alignment.
        let (size, members) = struct_layout(&m, "S").unwrap();
        assert_eq!(size, 32);
        assert_eq!(
            members,
            [("a".into(), 0), ("b".into(), 12), ("c".into(), 16)]
        );
        assert!(struct_layout(&m, "T").is_none());
        assert_struct_layout(&m, "S", 32, &[("a", 0), ("b", 12), ("c", 16)]);
    }

    #[test]
    #[should_panic(expected = "(member, offset)")]
    fn a_wrong_offset_fails() {
        let m = assert_valid("t", STRUCT, Caps::CORE);
        assert_struct_layout(&m, "S", 32, &[("a", 0), ("b", 16), ("c", 16)]);
    }

    #[test]
    #[should_panic(expected = "size in bytes")]
    fn a_wrong_size_fails() {
        let m = assert_valid("t", STRUCT, Caps::CORE);
        assert_struct_layout(&m, "S", 24, &[("a", 0), ("b", 12), ("c", 16)]);
    }
}
