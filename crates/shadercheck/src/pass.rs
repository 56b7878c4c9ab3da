//! Proof that a pass description matches its module: every feature combination composes
//! and validates, the entry points are the described ones with the described stages and
//! workgroup sizes, every compute entry point's workgroup memory fits wgpu's default limit,
//! and every binding has the described group, index, name, kind and size.

use naga::proc::Layouter;
use naga::{AddressSpace, ArraySize, Expression, ImageClass, ImageDimension, ScalarKind};
use naga::{Handle, Module, ShaderStage, StorageAccess, StorageFormat, Type, TypeInner};
use shader::{Dim, Format, Kind, Pass, Raster, Sample, Size, Stage};

use crate::{Caps, validate};

/// Composes `root` from `library` with `features`, validates it with `caps`, and returns
/// the module; panics with the composer's or naga's report.
#[track_caller]
pub fn assert_composed(
    library: &[&[shader::Module]],
    root: &str,
    features: &[&str],
    caps: Caps,
) -> Module {
    let src = shader::compose(library, root, features)
        .unwrap_or_else(|e| panic!("composing `{root}` with {features:?}: {e}"));
    validate(&src, caps).unwrap_or_else(|report| {
        panic!("WGSL module `{root}` with {features:?} failed naga validation:\n{report}")
    })
}

/// Every subset of `features`.
fn subsets<'a>(features: &[&'a str]) -> Vec<Vec<&'a str>> {
    (0..1u32 << features.len())
        .map(|bits| {
            features
                .iter()
                .enumerate()
                .filter(|(i, _)| bits >> i & 1 == 1)
                .map(|(_, f)| *f)
                .collect()
        })
        .collect()
}

/// Checks `pass` against its module under every combination of its features, each
/// validated with `caps(features)` (the narrowest capabilities that combination needs),
/// and returns the modules in subset order (the empty set first). Panics with a report
/// naming the pass, the features and what differs.
#[track_caller]
pub fn check_pass<P>(pass: &Pass<P>, caps: impl Fn(&[&str]) -> Caps) -> Vec<Module> {
    check_pass_with(pass, &[], caps)
}

/// [`check_pass`] for a description that holds only with the features `fixed` on (say, a
/// variant of a pass whose bindings differ under a feature): every combination of the
/// pass's other features, each with `fixed` added.
#[track_caller]
pub fn check_pass_with<P>(
    pass: &Pass<P>,
    fixed: &[&str],
    caps: impl Fn(&[&str]) -> Caps,
) -> Vec<Module> {
    if let Some(f) = fixed.iter().find(|f| !pass.features.contains(f)) {
        panic!(
            "pass `{}`: fixed feature `{f}` is not one of its features",
            pass.name
        );
    }
    let free: Vec<&str> = pass
        .features
        .iter()
        .copied()
        .filter(|f| !fixed.contains(f))
        .collect();
    subsets(&free)
        .into_iter()
        .map(|mut features| {
            features.extend_from_slice(fixed);
            let src = pass
                .source(&features)
                .unwrap_or_else(|e| panic!("pass `{}` with {features:?}: {e}", pass.name));
            let module = validate(&src, caps(&features)).unwrap_or_else(|report| {
                panic!(
                    "pass `{}` with {features:?} failed naga validation:\n{report}",
                    pass.name
                )
            });
            if let Err(problems) = compare(pass, &module) {
                panic!(
                    "pass `{}` with {features:?} does not match its description:\n  {}",
                    pass.name,
                    problems.join("\n  ")
                );
            }
            module
        })
        .collect()
}

/// `wgpu::Limits::default().max_compute_workgroup_storage_size` (WebGPU's minimum too):
/// the renderer asks for no more, so a pass over it fails on devices at the default.
pub const MAX_WORKGROUP_STORAGE: u32 = 16384;

/// Compute entry points whose workgroup variables (those the entry point uses) exceed
/// [`MAX_WORKGROUP_STORAGE`] bytes.
fn workgroup_memory_problems(m: &Module, layouter: &Layouter) -> Vec<String> {
    let info = match naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(m)
    {
        Ok(info) => info,
        Err(e) => return vec![format!("revalidating for workgroup memory: {e}")],
    };
    let mut problems = Vec::new();
    for (i, ep) in m.entry_points.iter().enumerate() {
        if ep.stage != ShaderStage::Compute {
            continue;
        }
        let uses = info.get_entry_point(i);
        let bytes: u32 = m
            .global_variables
            .iter()
            .filter(|(h, g)| g.space == AddressSpace::WorkGroup && !uses[*h].is_empty())
            .map(|(_, g)| layouter[g.ty].size)
            .sum();
        if bytes > MAX_WORKGROUP_STORAGE {
            problems.push(format!(
                "entry point `{}` uses {bytes} bytes of workgroup memory, over wgpu's default \
                 limit of {MAX_WORKGROUP_STORAGE}",
                ep.name
            ));
        }
    }
    problems
}

fn override_name(m: &Module, h: Handle<Expression>) -> Option<&str> {
    match m.global_expressions[h] {
        Expression::Override(o) => m.overrides[o].name.as_deref(),
        _ => None,
    }
}

/// The smallest buffer size a binding of type `ty` accepts.
fn min_size(m: &Module, layouter: &Layouter, ty: Handle<Type>) -> u32 {
    match &m.types[ty].inner {
        TypeInner::Array {
            size: ArraySize::Dynamic,
            stride,
            ..
        } => *stride,
        TypeInner::Struct { members, .. } => match members.last() {
            Some(last) => match m.types[last.ty].inner {
                TypeInner::Array {
                    size: ArraySize::Dynamic,
                    stride,
                    ..
                } => last.offset + stride,
                _ => layouter[ty].size,
            },
            None => layouter[ty].size,
        },
        _ => layouter[ty].size,
    }
}

fn dim_of(dim: ImageDimension, arrayed: bool) -> Option<Dim> {
    match (dim, arrayed) {
        (ImageDimension::D2, false) => Some(Dim::D2),
        (ImageDimension::D2, true) => Some(Dim::D2Array),
        (ImageDimension::D3, false) => Some(Dim::D3),
        _ => None,
    }
}

fn format_of(f: StorageFormat) -> Option<Format> {
    Some(match f {
        StorageFormat::Rgba8Unorm => Format::Rgba8Unorm,
        StorageFormat::Rgba8Uint => Format::Rgba8Uint,
        StorageFormat::Rgba16Float => Format::Rgba16Float,
        StorageFormat::R32Uint => Format::R32Uint,
        StorageFormat::R32Float => Format::R32Float,
        StorageFormat::R64Uint => Format::R64Uint,
        StorageFormat::Rgba32Float => Format::Rgba32Float,
        _ => return None,
    })
}

/// The kind the module declares for a global, in the description's terms (`filterable`
/// is the description's to say: naga cannot know).
fn kind_of(m: &Module, layouter: &Layouter, g: &naga::GlobalVariable, want: Kind) -> Option<Kind> {
    match g.space {
        AddressSpace::Uniform => Some(Kind::Uniform {
            size: layouter[g.ty].size,
            dynamic: matches!(want, Kind::Uniform { dynamic: true, .. }),
        }),
        AddressSpace::Storage { access } => Some(Kind::Storage {
            writable: access.contains(StorageAccess::STORE),
            size: min_size(m, layouter, g.ty),
        }),
        AddressSpace::Handle => match m.types[g.ty].inner {
            TypeInner::Sampler { comparison: false } => Some(Kind::Sampler),
            TypeInner::Image {
                dim,
                arrayed,
                class,
            } => {
                let dim = match class {
                    ImageClass::Sampled { multi: true, .. } | ImageClass::Depth { multi: true }
                        if dim == ImageDimension::D2 && !arrayed =>
                    {
                        Dim::D2Multisampled
                    }
                    ImageClass::Sampled { multi: true, .. } | ImageClass::Depth { multi: true } => {
                        return None;
                    }
                    _ => dim_of(dim, arrayed)?,
                };
                match class {
                    ImageClass::Sampled { kind, .. } => Some(Kind::Texture {
                        sample: match kind {
                            ScalarKind::Float => match want {
                                Kind::Texture {
                                    sample: s @ Sample::Float { .. },
                                    ..
                                } => s,
                                _ => Sample::Float { filterable: false },
                            },
                            ScalarKind::Uint => Sample::Uint,
                            ScalarKind::Sint => Sample::Sint,
                            _ => return None,
                        },
                        dim,
                    }),
                    ImageClass::Depth { .. } => Some(Kind::Texture {
                        sample: Sample::Depth,
                        dim,
                    }),
                    ImageClass::Storage { format, access } if access == StorageAccess::STORE => {
                        Some(Kind::StorageTexture {
                            format: format_of(format)?,
                            dim,
                        })
                    }
                    ImageClass::Storage { format, access }
                        if access.contains(StorageAccess::ATOMIC) =>
                    {
                        Some(Kind::AtomicStorageTexture {
                            format: format_of(format)?,
                            dim,
                        })
                    }
                    _ => None,
                }
            }
            _ => None,
        },
        _ => None,
    }
}

/// Everything in which `module` differs from `pass`'s description.
fn compare<P>(pass: &Pass<P>, m: &Module) -> Result<(), Vec<String>> {
    let mut problems = Vec::new();
    let mut layouter = Layouter::default();
    if let Err(e) = layouter.update(m.to_ctx()) {
        return Err(vec![format!("layout: {e}")]);
    }
    for e in pass.entries {
        let Some(ep) = m.entry_points.iter().find(|ep| ep.name == e.name) else {
            problems.push(format!("entry point `{}` is not in the module", e.name));
            continue;
        };
        match (e.stage, ep.stage) {
            (Stage::Vertex, ShaderStage::Vertex) | (Stage::Fragment, ShaderStage::Fragment) => {}
            (Stage::Compute(size), ShaderStage::Compute) => {
                for (i, s) in size.iter().enumerate() {
                    let over = ep
                        .workgroup_size_overrides
                        .and_then(|o| o[i])
                        .map(|h| override_name(m, h));
                    let ok = match s {
                        Size::Fixed(n) => over.is_none() && ep.workgroup_size[i] == *n,
                        Size::Override(name) => over == Some(Some(name)),
                    };
                    if !ok {
                        problems.push(format!(
                            "entry point `{}`: workgroup size dimension {i} is {:?} (override {:?}), described {s:?}",
                            e.name, ep.workgroup_size[i], over
                        ));
                    }
                }
            }
            (want, got) => problems.push(format!(
                "entry point `{}` is a {got:?} stage, described {want:?}",
                e.name
            )),
        }
    }
    for ep in &m.entry_points {
        if !pass.entries.iter().any(|e| e.name == ep.name) {
            problems.push(format!("entry point `{}` is not described", ep.name));
        }
    }
    problems.extend(workgroup_memory_problems(m, &layouter));
    for (gi, group) in pass.groups.iter().enumerate() {
        for (bi, b) in group.bindings.iter().enumerate() {
            let found = m.global_variables.iter().find(|(_, g)| {
                g.binding
                    .as_ref()
                    .is_some_and(|r| r.group as usize == gi && r.binding as usize == bi)
            });
            let Some((_, g)) = found else {
                problems.push(format!(
                    "group {gi} (`{}`) binding {bi} (`{}`) is not declared",
                    group.name, b.name
                ));
                continue;
            };
            if g.name.as_deref() != Some(b.name) {
                problems.push(format!(
                    "@group({gi}) @binding({bi}) is named `{}`, described `{}`",
                    g.name.as_deref().unwrap_or("?"),
                    b.name
                ));
            }
            let got = kind_of(m, &layouter, g, b.kind);
            if got != Some(b.kind) {
                problems.push(format!(
                    "`{}` (@group({gi}) @binding({bi})) is {got:?}, described {:?}",
                    b.name, b.kind
                ));
            }
        }
    }
    for (_, g) in m.global_variables.iter() {
        if let Some(r) = &g.binding {
            let described = pass
                .groups
                .get(r.group as usize)
                .is_some_and(|grp| (r.binding as usize) < grp.bindings.len());
            if !described {
                problems.push(format!(
                    "`{}` (@group({}) @binding({})) is not described",
                    g.name.as_deref().unwrap_or("?"),
                    r.group,
                    r.binding
                ));
            }
        }
    }
    for z in pass.zeroed {
        match pass.binding(z) {
            Ok((_, _, b)) if matches!(b.kind, Kind::Storage { writable: true, .. }) => {}
            _ => problems.push(format!(
                "zeroed buffer `{z}` is not a read_write storage binding"
            )),
        }
    }
    for e in pass.entries {
        if let shader::Dispatch::Indirect(name) = e.dispatch
            && pass.binding(name).is_err()
        {
            problems.push(format!(
                "entry point `{}` dispatches indirectly from `{name}`, which is not a binding",
                e.name
            ));
        }
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(problems)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shader::{Binding, Dispatch, Entry, Group};

    const LIB: &[shader::Module] = &[shader::Module::new(
        "t::pass",
        "struct TParams { n: u32, m: u32 }
@group(0) @binding(0) var<uniform> params: TParams;
@group(0) @binding(1) var<storage, read_write> counts: array<atomic<u32>>;
@group(1) @binding(0) var image: texture_2d<u32>;
override T_WIDTH: u32 = 32u;
@compute @workgroup_size(T_WIDTH)
fn count(@builtin(global_invocation_id) id: vec3<u32>) {
#if twice
    atomicAdd(&counts[0], 2u * textureLoad(image, vec2<i32>(id.xy), 0).x + params.n);
#else
    atomicAdd(&counts[0], textureLoad(image, vec2<i32>(id.xy), 0).x + params.n);
#endif
}
",
    )];

    macro_rules! pass {
        ($bindings:expr, $size:expr) => {
            Pass {
                name: "t",
                module: "t::pass",
                library: &[LIB],
                features: &["twice"],
                groups: &[
                    Group {
                        name: "a",
                        bindings: $bindings,
                    },
                    Group {
                        name: "b",
                        bindings: &[Binding::new("image", Kind::texture_2d(Sample::Uint))],
                    },
                ],
                entries: &[Entry {
                    name: "count",
                    stage: Stage::Compute([$size, Size::Fixed(1), Size::Fixed(1)]),
                    dispatch: Dispatch::Once,
                }],
                zeroed: &["counts"],
            }
        };
    }

    const GOOD: &[Binding] = &[
        Binding::new("params", Kind::uniform(8)),
        Binding::new("counts", Kind::read_write(4)),
    ];

    #[test]
    fn a_matching_description_passes_under_every_feature_set() {
        static P: Pass = pass!(GOOD, Size::Override("T_WIDTH"));
        assert_eq!(check_pass(&P, |_| Caps::CORE).len(), 2);
    }

    /// A fixed feature is on in every checked combination (one module per subset of the
    /// others), and one the pass does not declare is refused.
    #[test]
    fn fixed_features_are_on_in_every_combination() {
        static P: Pass = pass!(GOOD, Size::Override("T_WIDTH"));
        let modules = check_pass_with(&P, &["twice"], |f| {
            assert!(f.contains(&"twice"), "{f:?}");
            Caps::CORE
        });
        assert_eq!(modules.len(), 1);
        let unknown = std::panic::catch_unwind(|| check_pass_with(&P, &["thrice"], |_| Caps::CORE));
        assert!(unknown.is_err());
    }

    fn problems(p: &Pass) -> Vec<String> {
        let src = p.source(&[]).unwrap();
        compare(p, &validate(&src, Caps::CORE).unwrap()).unwrap_err()
    }

    #[test]
    fn mismatches_are_named() {
        static SIZE: Pass = pass!(GOOD, Size::Fixed(32));
        assert!(
            problems(&SIZE)[0].contains("workgroup size"),
            "{:?}",
            problems(&SIZE)
        );
        static NAME: &[Binding] = &[
            Binding::new("params", Kind::uniform(8)),
            Binding::new("totals", Kind::read_write(4)),
        ];
        static P1: Pass = pass!(NAME, Size::Override("T_WIDTH"));
        assert!(problems(&P1).iter().any(|p| p.contains("named `counts`")));
        static KIND: &[Binding] = &[
            Binding::new("params", Kind::uniform(8)),
            Binding::new("counts", Kind::read(4)),
        ];
        static P2: Pass = pass!(KIND, Size::Override("T_WIDTH"));
        assert!(problems(&P2).iter().any(|p| p.contains("`counts`")));
        static SIZE2: &[Binding] = &[
            Binding::new("params", Kind::uniform(16)),
            Binding::new("counts", Kind::read_write(4)),
        ];
        static P3: Pass = pass!(SIZE2, Size::Override("T_WIDTH"));
        assert!(problems(&P3).iter().any(|p| p.contains("`params`")));
        static MISSING: &[Binding] = &[Binding::new("params", Kind::uniform(8))];
        static P4: Pass = pass!(MISSING, Size::Override("T_WIDTH"));
        assert!(problems(&P4).iter().any(|p| p.contains("not described")));
    }
}

/// Checks a raster pipeline `raster` of `pass` against the pass's module composed with
/// `features` (validated with `caps`): its vertex and fragment entry points exist with those
/// stages and are described so, every `@location` output of the fragment has a colour
/// target of its kind (integer outputs for integer formats) and every target it writes
/// (a non-empty write mask) an output, a depth-only pipeline has no targets, and every vertex attribute feeds a vertex input. Panics with a report naming
/// the pass, the pipeline and what differs.
#[track_caller]
pub fn check_raster<P>(pass: &Pass<P>, raster: &Raster<'_>, features: &[&str], caps: Caps) {
    let src = pass
        .source(features)
        .unwrap_or_else(|e| panic!("pass `{}` with {features:?}: {e}", pass.name));
    let module = validate(&src, caps).unwrap_or_else(|report| {
        panic!(
            "pass `{}` with {features:?} failed naga validation:\n{report}",
            pass.name
        )
    });
    if let Err(problems) = compare_raster(pass, raster, &module) {
        panic!(
            "pipeline `{}` of pass `{}` with {features:?} does not match its module:\n  {}",
            raster.name,
            pass.name,
            problems.join("\n  ")
        );
    }
}

/// The `@location` bindings of an entry point's arguments (`inputs`) or result, each with
/// whether its scalar is an integer.
fn locations(m: &Module, ep: &naga::EntryPoint, inputs: bool) -> Vec<(u32, bool)> {
    let mut out = Vec::new();
    let mut visit = |ty: Handle<Type>, binding: Option<&naga::Binding>| {
        let mut one = |ty: Handle<Type>, b: Option<&naga::Binding>| {
            if let Some(naga::Binding::Location { location, .. }) = b {
                let int = m.types[ty]
                    .inner
                    .scalar()
                    .is_some_and(|s| matches!(s.kind, ScalarKind::Uint | ScalarKind::Sint));
                out.push((*location, int));
            }
        };
        match &m.types[ty].inner {
            TypeInner::Struct { members, .. } if binding.is_none() => {
                for mem in members {
                    one(mem.ty, mem.binding.as_ref());
                }
            }
            _ => one(ty, binding),
        }
    };
    if inputs {
        for a in &ep.function.arguments {
            visit(a.ty, a.binding.as_ref());
        }
    } else if let Some(r) = &ep.function.result {
        visit(r.ty, r.binding.as_ref());
    }
    out.sort_unstable();
    out
}

/// Everything in which `raster` differs from `module` and `pass`.
fn compare_raster<P>(pass: &Pass<P>, raster: &Raster<'_>, m: &Module) -> Result<(), Vec<String>> {
    let mut problems = Vec::new();
    let mut entry = |name: &str, stage: Stage, naga_stage: ShaderStage| {
        if !pass
            .entries
            .iter()
            .any(|e| e.name == name && e.stage == stage)
        {
            problems.push(format!("`{name}` is not a described {stage:?} entry point"));
        }
        let ep = m
            .entry_points
            .iter()
            .find(|ep| ep.name == name && ep.stage == naga_stage);
        if ep.is_none() {
            problems.push(format!(
                "`{name}` is not a {naga_stage:?} entry point of the module"
            ));
        }
        ep
    };
    let vertex = entry(raster.vertex, Stage::Vertex, ShaderStage::Vertex);
    let fragment = raster
        .fragment
        .map(|f| entry(f, Stage::Fragment, ShaderStage::Fragment));
    if let Some(vs) = vertex {
        let inputs = locations(m, vs, true);
        for (slot, b) in raster.buffers.iter().enumerate() {
            for a in b.attributes {
                if !inputs.iter().any(|(l, _)| *l == a.location) {
                    problems.push(format!(
                        "vertex buffer {slot}'s attribute at location {} feeds no input of `{}`",
                        a.location, raster.vertex
                    ));
                }
                if a.offset + a.format.size() > b.stride {
                    problems.push(format!(
                        "vertex buffer {slot}'s attribute at location {} ends past its stride",
                        a.location
                    ));
                }
            }
        }
    }
    match fragment {
        None if !raster.targets.is_empty() => problems.push(format!(
            "{} colour targets without a fragment stage",
            raster.targets.len()
        )),
        Some(Some(fs)) => {
            let outputs = locations(m, fs, false);
            for &(location, int) in &outputs {
                match raster.targets.get(location as usize) {
                    None => problems.push(format!(
                        "`{}` writes @location({location}), which has no colour target",
                        fs.name
                    )),
                    Some(t) if shader::integer_target(t.format) != int => problems.push(format!(
                        "`{}` writes @location({location}) as {}, its target is {:?}",
                        fs.name,
                        if int { "an integer" } else { "a float" },
                        t.format
                    )),
                    Some(_) => {}
                }
            }
            for (i, t) in raster.targets.iter().enumerate() {
                if t.write_mask != 0 && !outputs.iter().any(|(l, _)| *l as usize == i) {
                    problems.push(format!(
                        "colour target {i} is written but `{}` has no @location({i}) output",
                        fs.name
                    ));
                }
            }
        }
        _ => {}
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(problems)
    }
}

#[cfg(test)]
mod raster_tests {
    use super::*;
    use shader::{Depth, DepthFormat, Entry, Target};

    const LIB: &[shader::Module] = &[shader::Module::new(
        "t::raster",
        "struct TOut { @location(0) id: u32, @location(1) colour: vec4<f32> }
@vertex
fn vs(@location(0) p: vec3<f32>) -> @builtin(position) vec4<f32> { return vec4<f32>(p, 1.0); }
@fragment
fn fs() -> TOut { return TOut(1u, vec4<f32>(1.0)); }
",
    )];

    static P: Pass = Pass {
        name: "t",
        module: "t::raster",
        library: &[LIB],
        features: &[],
        groups: &[],
        entries: &[
            Entry::draw("vs", Stage::Vertex),
            Entry::draw("fs", Stage::Fragment),
        ],
        zeroed: &[],
    };

    const BUFFERS: &[shader::VertexBuffer<'static>] = &[shader::VertexBuffer {
        stride: 12,
        per_instance: false,
        attributes: &[shader::Attribute {
            format: shader::VertexFormat::Float32x3,
            offset: 0,
            location: 0,
        }],
    }];

    const GOOD: Raster<'static> = Raster::new("good", "vs")
        .fragment("fs")
        .buffers(BUFFERS)
        .targets(&[
            Target::replace(Format::R32Uint),
            Target::replace(Format::Rgba16Float),
        ])
        .depth(Depth::reversed_z(DepthFormat::Depth32Float));

    fn problems(r: &Raster<'_>) -> Vec<String> {
        let m = validate(&P.source(&[]).unwrap(), Caps::CORE).unwrap();
        compare_raster(&P, r, &m).err().unwrap_or_default()
    }

    #[test]
    fn a_matching_pipeline_passes() {
        check_raster(&P, &GOOD, &[], Caps::CORE);
        // Depth only: no fragment, no targets.
        assert!(problems(&Raster::new("depth", "vs").buffers(BUFFERS)).is_empty());
    }

    #[test]
    fn mismatches_are_named() {
        let one = [Target::replace(Format::R32Uint)];
        assert!(problems(&GOOD.targets(&one))[0].contains("no colour target"));
        let three = [
            Target::replace(Format::R32Uint),
            Target::replace(Format::Rgba16Float),
            Target::replace(Format::Rgba16Float),
        ];
        assert!(problems(&GOOD.targets(&three))[0].contains("target 2 is written"));
        // An attached target the pipeline leaves untouched needs no output.
        let untouched = [three[0], three[1], Target::untouched(Format::Rgba16Float)];
        assert!(problems(&GOOD.targets(&untouched)).is_empty());
        let swapped = [
            Target::replace(Format::Rgba16Float),
            Target::replace(Format::R32Uint),
        ];
        assert_eq!(problems(&GOOD.targets(&swapped)).len(), 2);
        let stages = problems(&Raster::new("x", "fs").fragment("vs"));
        assert_eq!(stages.len(), 4, "{stages:?}");
        assert!(problems(&Raster::new("x", "vs").targets(&one))[0].contains("without"));
        let far = [shader::VertexBuffer {
            attributes: &[shader::Attribute {
                format: shader::VertexFormat::Float32x3,
                offset: 4,
                location: 1,
            }],
            ..BUFFERS[0]
        }];
        assert_eq!(problems(&GOOD.buffers(&far)).len(), 2);
    }
}
