//! One description per pass: which module, which features it reads, its bind groups and
//! bindings by name and kind, its entry points in dispatch order with their workgroup sizes
//! and dispatch geometry, and which buffers hold zeros when it starts. The crate that owns
//! the pass's algorithm declares it next to the WGSL; the renderer builds its layouts,
//! pipelines, bind groups and dispatches from it, the device tests run the pass through it,
//! and `shadercheck::check_pass` proves it matches the composed module.

use alloc::string::String;

use crate::compose::{Error, Module, compose};

/// Workgroups per dispatch dimension that every wgpu device accepts
/// (`max_compute_workgroups_per_dimension`'s default). [`Dispatch::Items`] past this many
/// workgroups continues in rows.
pub const MAX_WORKGROUPS_X: u32 = 65_535;

/// A described pass: a WGSL module and how to bind and run it.
///
/// `P` is the parameter type its dispatch geometry is computed from (for `tiling`'s
/// classification, `tiling::TilingParams`).
#[derive(Debug)]
pub struct Pass<P: 'static = ()> {
    /// Name for labels and errors.
    pub name: &'static str,
    /// The root module (see [`Module::name`]).
    pub module: &'static str,
    /// Every crate's module list the root may import from.
    pub library: &'static [&'static [Module]],
    /// The features the module's `#if`s read; any combination of them composes.
    pub features: &'static [&'static str],
    /// Bind groups: group `i` of the shader is `groups[i]`.
    pub groups: &'static [Group],
    /// Entry points, in the order a frame runs them (render passes: vertex, fragment).
    pub entries: &'static [Entry<P>],
    /// Storage bindings that must hold zeros when the pass's first entry point starts.
    pub zeroed: &'static [&'static str],
}

/// One bind group: binding `i` of the shader is `bindings[i]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Group {
    /// Name for labels and lookups.
    pub name: &'static str,
    /// The bindings, in binding order from 0.
    pub bindings: &'static [Binding],
}

/// One binding: its WGSL variable name and what it is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Binding {
    /// The WGSL global's name.
    pub name: &'static str,
    /// What kind of resource, with the size the shader reads.
    pub kind: Kind,
}

impl Binding {
    /// A binding named `name` of kind `kind`.
    #[must_use]
    pub const fn new(name: &'static str, kind: Kind) -> Self {
        Self { name, kind }
    }
}

/// The kind of a binding, as the shader declares it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Kind {
    /// `var<uniform>` of `size` bytes; `dynamic`: bound at a dynamic offset.
    Uniform {
        /// Bytes of the uniform struct.
        size: u32,
        /// Whether the bind group is set with a dynamic offset.
        dynamic: bool,
    },
    /// `var<storage, read>` or `var<storage, read_write>`: `size` is the bytes the
    /// shader needs at least (a runtime-sized array's one element, a struct's size).
    Storage {
        /// `read_write` when true.
        writable: bool,
        /// Minimum binding size in bytes.
        size: u32,
    },
    /// A sampled texture.
    Texture {
        /// What `textureLoad` / `textureSample` return.
        sample: Sample,
        /// Its view dimension.
        dim: Dim,
    },
    /// A write-only storage texture.
    StorageTexture {
        /// Its texel format.
        format: Format,
        /// Its view dimension.
        dim: Dim,
    },
    /// A storage texture with atomic access (`texture_storage_*<format, atomic>`: load,
    /// store and `textureAtomic*`).
    AtomicStorageTexture {
        /// Its texel format.
        format: Format,
        /// Its view dimension.
        dim: Dim,
    },
    /// A sampler (filtering, non-comparison).
    Sampler,
}

impl Kind {
    /// A uniform struct of `size` bytes.
    #[must_use]
    pub const fn uniform(size: usize) -> Kind {
        Kind::Uniform {
            size: size as u32,
            dynamic: false,
        }
    }
    /// A read-only storage buffer of at least `size` bytes.
    #[must_use]
    pub const fn read(size: usize) -> Kind {
        Kind::Storage {
            writable: false,
            size: size as u32,
        }
    }
    /// A `read_write` storage buffer of at least `size` bytes.
    #[must_use]
    pub const fn read_write(size: usize) -> Kind {
        Kind::Storage {
            writable: true,
            size: size as u32,
        }
    }
    /// A 2D texture of `sample` texels.
    #[must_use]
    pub const fn texture_2d(sample: Sample) -> Kind {
        Kind::Texture {
            sample,
            dim: Dim::D2,
        }
    }
    /// A 2D write-only storage texture of `format`.
    #[must_use]
    pub const fn storage_texture_2d(format: Format) -> Kind {
        Kind::StorageTexture {
            format,
            dim: Dim::D2,
        }
    }
    /// A 2D storage texture of `format` with atomic access.
    #[must_use]
    pub const fn atomic_storage_texture_2d(format: Format) -> Kind {
        Kind::AtomicStorageTexture {
            format,
            dim: Dim::D2,
        }
    }
    /// The minimum binding size in bytes of a buffer binding (`None` for others).
    #[must_use]
    pub const fn buffer_size(self) -> Option<u32> {
        match self {
            Kind::Uniform { size, .. } | Kind::Storage { size, .. } => Some(size),
            _ => None,
        }
    }
}

/// What a sampled texture returns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sample {
    /// `texture_*<f32>`; `filterable`: may be sampled with a filtering sampler.
    Float {
        /// Whether it is filterable.
        filterable: bool,
    },
    /// `texture_*<u32>`.
    Uint,
    /// `texture_*<i32>`.
    Sint,
    /// `texture_depth_*`.
    Depth,
}

/// A texture view dimension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dim {
    /// `texture_2d`.
    D2,
    /// `texture_2d_array`.
    D2Array,
    /// `texture_3d`.
    D3,
    /// `texture_multisampled_2d` / `texture_depth_multisampled_2d` (read with
    /// `textureLoad(t, texel, sample)`).
    D2Multisampled,
}

/// Texel formats the workspace's passes use for storage textures and colour targets (WGSL
/// storage-format names in the docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Format {
    /// `rgba8unorm`.
    Rgba8Unorm,
    /// `rgba8uint`.
    Rgba8Uint,
    /// `rgba16float`.
    Rgba16Float,
    /// `r32uint`.
    R32Uint,
    /// `r32float`.
    R32Float,
    /// `r64uint` (`Features::TEXTURE_INT64_ATOMIC`; atomic min and max).
    R64Uint,
    /// `rgba32float`.
    Rgba32Float,
}

/// A dimension of a compute entry point's workgroup size.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Size {
    /// A literal.
    Fixed(u32),
    /// A WGSL `override` constant of this name, set at pipeline creation.
    Override(&'static str),
}

/// The stage of an entry point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// `@vertex`.
    Vertex,
    /// `@fragment`.
    Fragment,
    /// `@compute` with its `@workgroup_size`.
    Compute([Size; 3]),
}

impl Stage {
    /// A compute stage with a literal workgroup size.
    #[must_use]
    pub const fn compute(x: u32, y: u32, z: u32) -> Stage {
        Stage::Compute([Size::Fixed(x), Size::Fixed(y), Size::Fixed(z)])
    }
}

/// How many workgroups an entry point is dispatched with.
#[derive(Debug)]
pub enum Dispatch<P: 'static> {
    /// A render stage: drawn, not dispatched.
    Draw,
    /// One workgroup.
    Once,
    /// One invocation per cell of a `[width, height]` grid: `ceil(width / size.x)` by
    /// `ceil(height / size.y)` workgroups.
    Grid(fn(&P) -> [u32; 2]),
    /// One invocation per item: `ceil(items / size.x)` workgroups, in rows of
    /// [`MAX_WORKGROUPS_X`] past that many; the shader's item index is
    /// `gid.y * MAX_WORKGROUPS_X * size.x + gid.x`.
    Items(fn(&P) -> u32),
    /// `dispatch_workgroups_indirect` with arguments from the named binding (the caller
    /// picks the offset).
    Indirect(&'static str),
}

/// One entry point of a pass.
#[derive(Debug)]
pub struct Entry<P: 'static> {
    /// Its WGSL name.
    pub name: &'static str,
    /// Its stage (and workgroup size).
    pub stage: Stage,
    /// How it is dispatched.
    pub dispatch: Dispatch<P>,
}

impl<P> Entry<P> {
    /// A compute entry point of `x` × `y` invocations per workgroup, one invocation per
    /// cell of the grid `grid(params)` returns.
    #[must_use]
    pub const fn grid(name: &'static str, x: u32, y: u32, grid: fn(&P) -> [u32; 2]) -> Self {
        Self {
            name,
            stage: Stage::compute(x, y, 1),
            dispatch: Dispatch::Grid(grid),
        }
    }

    /// A compute entry point of `x` invocations per workgroup, one workgroup.
    #[must_use]
    pub const fn once(name: &'static str, x: u32) -> Self {
        Self {
            name,
            stage: Stage::compute(x, 1, 1),
            dispatch: Dispatch::Once,
        }
    }

    /// A compute entry point of `x` invocations per workgroup, one invocation per item of
    /// `items(params)`.
    #[must_use]
    pub const fn items(name: &'static str, x: u32, items: fn(&P) -> u32) -> Self {
        Self {
            name,
            stage: Stage::compute(x, 1, 1),
            dispatch: Dispatch::Items(items),
        }
    }

    /// A render entry point of `stage`.
    #[must_use]
    pub const fn draw(name: &'static str, stage: Stage) -> Self {
        Self {
            name,
            stage,
            dispatch: Dispatch::Draw,
        }
    }

    /// The workgroup counts of a direct dispatch with `params`, reading override-sized
    /// dimensions from `constants` (their values at pipeline creation); `None` for
    /// [`Dispatch::Draw`], [`Dispatch::Indirect`] and a render stage, or an override
    /// missing from `constants`.
    pub fn workgroups(&self, params: &P, constants: &[(&str, f64)]) -> Option<[u32; 3]> {
        let Stage::Compute(size) = self.stage else {
            return None;
        };
        let dim = |s: Size| -> Option<u32> {
            match s {
                Size::Fixed(n) => Some(n),
                Size::Override(name) => constants
                    .iter()
                    .find(|(n, _)| *n == name)
                    .map(|&(_, v)| v as u32),
            }
        };
        let (x, y) = (dim(size[0])?.max(1), dim(size[1])?.max(1));
        match &self.dispatch {
            Dispatch::Draw | Dispatch::Indirect(_) => None,
            Dispatch::Once => Some([1, 1, 1]),
            Dispatch::Grid(f) => {
                let [w, h] = f(params);
                Some([w.div_ceil(x), h.div_ceil(y), 1])
            }
            Dispatch::Items(f) => {
                let groups = f(params).div_ceil(x);
                Some(if groups <= MAX_WORKGROUPS_X {
                    [groups, 1, 1]
                } else {
                    [MAX_WORKGROUPS_X, groups.div_ceil(MAX_WORKGROUPS_X), 1]
                })
            }
        }
    }
}

/// `a` followed by `b` (`C` must be `A + B`): how passes that share bindings list them
/// once.
#[must_use]
pub const fn join<const A: usize, const B: usize, const C: usize>(
    a: [Binding; A],
    b: [Binding; B],
) -> [Binding; C] {
    assert!(A + B == C, "join: C must be A + B");
    let mut out = [Binding::new("", Kind::Sampler); C];
    let mut i = 0;
    while i < A {
        out[i] = a[i];
        i += 1;
    }
    while i < C {
        out[i] = b[i - A];
        i += 1;
    }
    out
}

/// Bindings one stage of a pass uses, by kind: what wgpu's per-stage limits count.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StageCounts {
    /// Uniform buffers (`max_uniform_buffers_per_shader_stage`).
    pub uniform_buffers: u32,
    /// Of those, with dynamic offsets (`max_dynamic_uniform_buffers_per_pipeline_layout`).
    pub dynamic_uniform_buffers: u32,
    /// Storage buffers (`max_storage_buffers_per_shader_stage`).
    pub storage_buffers: u32,
    /// Sampled textures (`max_sampled_textures_per_shader_stage`).
    pub sampled_textures: u32,
    /// Storage textures (`max_storage_textures_per_shader_stage`).
    pub storage_textures: u32,
    /// Samplers (`max_samplers_per_shader_stage`).
    pub samplers: u32,
    /// Bind groups (`max_bind_groups`).
    pub bind_groups: u32,
    /// Bindings in one group (`max_bindings_per_bind_group`).
    pub bindings_per_group: u32,
    /// The largest `x * y * z` of a compute entry point's fixed workgroup size
    /// (`max_compute_invocations_per_workgroup`; override sizes count as 1).
    pub invocations_per_workgroup: u32,
}

impl StageCounts {
    /// The larger of each count.
    #[must_use]
    pub fn max(self, o: StageCounts) -> StageCounts {
        StageCounts {
            uniform_buffers: self.uniform_buffers.max(o.uniform_buffers),
            dynamic_uniform_buffers: self.dynamic_uniform_buffers.max(o.dynamic_uniform_buffers),
            storage_buffers: self.storage_buffers.max(o.storage_buffers),
            sampled_textures: self.sampled_textures.max(o.sampled_textures),
            storage_textures: self.storage_textures.max(o.storage_textures),
            samplers: self.samplers.max(o.samplers),
            bind_groups: self.bind_groups.max(o.bind_groups),
            bindings_per_group: self.bindings_per_group.max(o.bindings_per_group),
            invocations_per_workgroup: self
                .invocations_per_workgroup
                .max(o.invocations_per_workgroup),
        }
    }
}

impl<P> Pass<P> {
    /// The composed WGSL with `features` on.
    ///
    /// # Errors
    /// A feature the pass does not declare, or a composition error.
    pub fn source(&self, features: &[&str]) -> Result<String, Error> {
        if let Some(f) = features.iter().find(|f| !self.features.contains(f)) {
            return Err(Error::UndeclaredFeature {
                feature: (*f).into(),
                pass: self.name,
            });
        }
        compose(self.library, self.module, features)
    }

    /// The index and description of the group named `name`.
    ///
    /// # Errors
    /// [`Error::UnknownName`].
    pub fn group(&self, name: &str) -> Result<(u32, &'static Group), Error> {
        self.groups
            .iter()
            .position(|g| g.name == name)
            .map(|i| (i as u32, &self.groups[i]))
            .ok_or_else(|| self.unknown("group", name))
    }

    /// `(group, binding)` and the description of the binding named `name`.
    ///
    /// # Errors
    /// [`Error::UnknownName`].
    pub fn binding(&self, name: &str) -> Result<(u32, u32, &'static Binding), Error> {
        for (g, group) in self.groups.iter().enumerate() {
            if let Some(b) = group.bindings.iter().position(|b| b.name == name) {
                return Ok((g as u32, b as u32, &group.bindings[b]));
            }
        }
        Err(self.unknown("binding", name))
    }

    /// The entry point named `name`.
    ///
    /// # Errors
    /// [`Error::UnknownName`].
    pub fn entry(&self, name: &str) -> Result<&'static Entry<P>, Error> {
        self.entries
            .iter()
            .find(|e| e.name == name)
            .ok_or_else(|| self.unknown("entry point", name))
    }

    fn unknown(&self, what: &'static str, name: &str) -> Error {
        Error::UnknownName {
            pass: self.name,
            what,
            name: name.into(),
        }
    }

    /// Whether the pass has a compute entry point (else it is a render pass).
    #[must_use]
    pub fn is_compute(&self) -> bool {
        self.entries
            .iter()
            .any(|e| matches!(e.stage, Stage::Compute(_)))
    }

    /// What one stage of this pass binds (every binding is visible to every stage the
    /// pass's entry points run in).
    #[must_use]
    pub fn stage_counts(&self) -> StageCounts {
        let mut c = StageCounts {
            bind_groups: self.groups.len() as u32,
            ..StageCounts::default()
        };
        for g in self.groups {
            c.bindings_per_group = c.bindings_per_group.max(g.bindings.len() as u32);
            for b in g.bindings {
                match b.kind {
                    Kind::Uniform { dynamic, .. } => {
                        c.uniform_buffers += 1;
                        c.dynamic_uniform_buffers += u32::from(dynamic);
                    }
                    Kind::Storage { .. } => c.storage_buffers += 1,
                    Kind::Texture { .. } => c.sampled_textures += 1,
                    Kind::StorageTexture { .. } | Kind::AtomicStorageTexture { .. } => {
                        c.storage_textures += 1;
                    }
                    Kind::Sampler => c.samplers += 1,
                }
            }
        }
        for e in self.entries {
            if let Stage::Compute(size) = e.stage {
                let n: u32 = size
                    .iter()
                    .map(|s| match s {
                        Size::Fixed(n) => *n,
                        Size::Override(_) => 1,
                    })
                    .product();
                c.invocations_per_workgroup = c.invocations_per_workgroup.max(n);
            }
        }
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct P {
        w: u32,
        h: u32,
        n: u32,
    }

    const LIB: &[Module] = &[Module::new(
        "t::pass",
        "#if fast\nconst T_FAST: bool = true;\n#endif\n",
    )];

    const PASS: Pass<P> = Pass {
        name: "test pass",
        module: "t::pass",
        library: &[LIB],
        features: &["fast"],
        groups: &[
            Group {
                name: "params",
                bindings: &[Binding::new("params", Kind::uniform(16))],
            },
            Group {
                name: "data",
                bindings: &[
                    Binding::new("input", Kind::read(4)),
                    Binding::new("output", Kind::read_write(4)),
                    Binding::new("image", Kind::texture_2d(Sample::Uint)),
                ],
            },
        ],
        entries: &[
            Entry {
                name: "grid",
                stage: Stage::compute(16, 8, 1),
                dispatch: Dispatch::Grid(|p| [p.w, p.h]),
            },
            Entry {
                name: "items",
                stage: Stage::Compute([Size::Override("T_WIDTH"), Size::Fixed(1), Size::Fixed(1)]),
                dispatch: Dispatch::Items(|p| p.n),
            },
            Entry {
                name: "once",
                stage: Stage::compute(256, 1, 1),
                dispatch: Dispatch::Once,
            },
            Entry {
                name: "indirect",
                stage: Stage::compute(64, 1, 1),
                dispatch: Dispatch::Indirect("output"),
            },
        ],
        zeroed: &["output"],
    };

    #[test]
    fn workgroups_follow_the_geometry() {
        let p = P {
            w: 33,
            h: 17,
            n: 100,
        };
        let e = |n: &str| PASS.entry(n).unwrap();
        assert_eq!(e("grid").workgroups(&p, &[]), Some([3, 3, 1]));
        assert_eq!(e("items").workgroups(&p, &[]), None, "override unset");
        assert_eq!(
            e("items").workgroups(&p, &[("T_WIDTH", 32.0)]),
            Some([4, 1, 1])
        );
        assert_eq!(e("once").workgroups(&p, &[]), Some([1, 1, 1]));
        assert_eq!(e("indirect").workgroups(&p, &[]), None);
        // Past 65 535 workgroups the items continue in rows.
        let big = P {
            w: 0,
            h: 0,
            n: 70_000 * 32,
        };
        assert_eq!(
            e("items").workgroups(&big, &[("T_WIDTH", 32.0)]),
            Some([MAX_WORKGROUPS_X, 2, 1])
        );
    }

    #[test]
    fn lookups_by_name() {
        assert_eq!(PASS.group("data").unwrap().0, 1);
        let (g, b, d) = PASS.binding("image").unwrap();
        assert_eq!((g, b), (1, 2));
        assert_eq!(d.kind, Kind::texture_2d(Sample::Uint));
        assert!(matches!(
            PASS.binding("nope"),
            Err(Error::UnknownName {
                what: "binding",
                ..
            })
        ));
        assert!(PASS.entry("nope").is_err());
        assert!(PASS.is_compute());
    }

    #[test]
    fn stage_counts_count_every_binding() {
        let c = PASS.stage_counts();
        assert_eq!(c.uniform_buffers, 1);
        assert_eq!(c.storage_buffers, 2);
        assert_eq!(c.sampled_textures, 1);
        assert_eq!(c.bind_groups, 2);
        assert_eq!(c.bindings_per_group, 3);
        assert_eq!(c.invocations_per_workgroup, 256);
    }

    #[test]
    fn source_rejects_undeclared_features() {
        assert!(PASS.source(&["fast"]).unwrap().contains("T_FAST"));
        assert!(!PASS.source(&[]).unwrap().contains("T_FAST"));
        assert!(matches!(
            PASS.source(&["slow"]),
            Err(Error::UndeclaredFeature { .. })
        ));
    }
}
