//! One raster pipeline of a render [`Pass`](crate::Pass), described in the crate's own
//! types: which vertex and fragment entry points, the vertex buffers, the colour targets
//! (format, blend, write mask), the depth-stencil state (format, compare, write, bias,
//! stencil), the primitive state (topology, front face, cull) and the sample count. A pass
//! declares its pipelines as consts next to its `Pass`; `pipeline::RasterPass` builds them
//! on a wgpu device from the pass's layouts and `shadercheck::check_raster` proves each
//! against the composed module.
//!
//! Only what the workspace's passes set is describable; the rest is wgpu's default (no
//! strip index format, filled polygons, clipped depth, no conservative rasterisation, an
//! all-ones sample mask, no alpha to coverage, no multiview).

use crate::pass::Format;

/// A raster pipeline of a pass. `'a` is the lifetime of its vertex-buffer and colour-target
/// lists: `'static` for a const, shorter for one whose target formats the device picks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Raster<'a> {
    /// Label for the pipeline.
    pub name: &'static str,
    /// The vertex entry point (a [`Stage::Vertex`](crate::Stage::Vertex) entry of the pass).
    pub vertex: &'static str,
    /// The fragment entry point (a [`Stage::Fragment`](crate::Stage::Fragment) entry), or
    /// none: depth only.
    pub fragment: Option<&'static str>,
    /// Vertex buffers, slot `i` is `buffers[i]` (empty: vertices pulled from storage).
    pub buffers: &'a [VertexBuffer<'a>],
    /// Colour targets, `@location(i)` is `targets[i]`.
    pub targets: &'a [Target],
    /// The depth-stencil state, or no depth attachment.
    pub depth: Option<Depth>,
    /// Topology, winding and culling.
    pub primitive: Primitive,
    /// Samples per pixel of the attachments (1: no multisampling).
    pub samples: u32,
}

impl<'a> Raster<'a> {
    /// A pipeline named `name` drawing triangle lists with vertex entry `vertex`: no
    /// fragment stage, no vertex buffers, no targets, no depth, no culling, one sample.
    #[must_use]
    pub const fn new(name: &'static str, vertex: &'static str) -> Self {
        Self {
            name,
            vertex,
            fragment: None,
            buffers: &[],
            targets: &[],
            depth: None,
            primitive: Primitive::TRIANGLES,
            samples: 1,
        }
    }
    /// With fragment entry point `fragment`.
    #[must_use]
    pub const fn fragment(self, fragment: &'static str) -> Self {
        Self {
            fragment: Some(fragment),
            ..self
        }
    }
    /// With colour targets `targets`.
    #[must_use]
    pub const fn targets(self, targets: &'a [Target]) -> Self {
        Self { targets, ..self }
    }
    /// With vertex buffers `buffers`.
    #[must_use]
    pub const fn buffers(self, buffers: &'a [VertexBuffer<'a>]) -> Self {
        Self { buffers, ..self }
    }
    /// With depth-stencil state `depth`.
    #[must_use]
    pub const fn depth(self, depth: Depth) -> Self {
        Self {
            depth: Some(depth),
            ..self
        }
    }
    /// With its depth attachment's format `format` (a pass whose format the device picks;
    /// no depth state: unchanged).
    #[must_use]
    pub const fn depth_format(self, format: DepthFormat) -> Self {
        Self {
            depth: match self.depth {
                Some(d) => Some(Depth { format, ..d }),
                None => None,
            },
            ..self
        }
    }
    /// With primitive state `primitive`.
    #[must_use]
    pub const fn primitive(self, primitive: Primitive) -> Self {
        Self { primitive, ..self }
    }
    /// Culling `cull` (none: both faces drawn).
    #[must_use]
    pub const fn cull(self, cull: Option<Face>) -> Self {
        Self {
            primitive: Primitive {
                cull,
                ..self.primitive
            },
            ..self
        }
    }
    /// With `samples` samples per pixel.
    #[must_use]
    pub const fn samples(self, samples: u32) -> Self {
        Self { samples, ..self }
    }
    /// Labelled `name`.
    #[must_use]
    pub const fn named(self, name: &'static str) -> Self {
        Self { name, ..self }
    }
}

/// A colour target: its format, blending and the channels written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Target {
    /// The attachment's format.
    pub format: Format,
    /// Blending with what the target holds, or none: replaced.
    pub blend: Option<Blend>,
    /// The channels written, wgpu's `ColorWrites` bits: red 1, green 2, blue 4, alpha 8.
    pub write_mask: u8,
}

impl Target {
    /// Every channel written.
    pub const WRITE_ALL: u8 = 0xf;

    /// A target of `format` whose every channel the fragment replaces.
    #[must_use]
    pub const fn replace(format: Format) -> Self {
        Self {
            format,
            blend: None,
            write_mask: Self::WRITE_ALL,
        }
    }
    /// A target of `format` the fragment adds into (colour and alpha: `src + dst`), every
    /// channel: light accumulation.
    #[must_use]
    pub const fn additive(format: Format) -> Self {
        Self {
            format,
            blend: Some(Blend::ADDITIVE),
            write_mask: Self::WRITE_ALL,
        }
    }
    /// A target of `format` attached but never written (write mask empty): a pass that
    /// shares its render pass with writing pipelines but only tests.
    #[must_use]
    pub const fn untouched(format: Format) -> Self {
        Self {
            format,
            blend: None,
            write_mask: 0,
        }
    }
}

/// Blending of colour and alpha.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Blend {
    /// The colour channels' equation.
    pub color: BlendComponent,
    /// The alpha channel's equation.
    pub alpha: BlendComponent,
}

impl Blend {
    /// `src + dst` for colour and alpha.
    pub const ADDITIVE: Blend = Blend {
        color: BlendComponent::ADD,
        alpha: BlendComponent::ADD,
    };
}

/// One blend equation: `src * src_factor (op) dst * dst_factor`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BlendComponent {
    /// The fragment's factor.
    pub src: BlendFactor,
    /// The target's factor.
    pub dst: BlendFactor,
    /// How they combine.
    pub op: BlendOp,
}

impl BlendComponent {
    /// `src + dst`.
    pub const ADD: BlendComponent = BlendComponent {
        src: BlendFactor::One,
        dst: BlendFactor::One,
        op: BlendOp::Add,
    };
}

/// A blend factor (wgpu's of the same name).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum BlendFactor {
    /// 0.
    Zero,
    /// 1.
    One,
    /// The fragment's value.
    Src,
    /// 1 - the fragment's value.
    OneMinusSrc,
    /// The fragment's alpha.
    SrcAlpha,
    /// 1 - the fragment's alpha.
    OneMinusSrcAlpha,
    /// The target's value.
    Dst,
    /// 1 - the target's value.
    OneMinusDst,
    /// The target's alpha.
    DstAlpha,
    /// 1 - the target's alpha.
    OneMinusDstAlpha,
}

/// A blend operation (wgpu's of the same name).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BlendOp {
    /// `src + dst`.
    Add,
    /// `src - dst`.
    Subtract,
    /// `dst - src`.
    ReverseSubtract,
    /// `min(src, dst)`.
    Min,
    /// `max(src, dst)`.
    Max,
}

/// Depth(-stencil) attachment formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum DepthFormat {
    /// 32-bit float depth.
    Depth32Float,
    /// 32-bit float depth, 8-bit stencil (`Features::DEPTH32FLOAT_STENCIL8`).
    Depth32FloatStencil8,
    /// At least 24-bit depth, 8-bit stencil.
    Depth24PlusStencil8,
}

/// A comparison (depth or stencil test: passes when `new <op> stored`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Compare {
    /// Never passes.
    Never,
    /// `new < stored`.
    Less,
    /// `new == stored`.
    Equal,
    /// `new <= stored`.
    LessEqual,
    /// `new > stored`.
    Greater,
    /// `new != stored`.
    NotEqual,
    /// `new >= stored`.
    GreaterEqual,
    /// Always passes.
    Always,
}

/// The depth-stencil state of a pipeline.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Depth {
    /// The attachment's format.
    pub format: DepthFormat,
    /// Whether a passing fragment writes its depth.
    pub write: bool,
    /// The depth test.
    pub compare: Compare,
    /// The stencil test and operations.
    pub stencil: Stencil,
    /// The depth bias.
    pub bias: Bias,
}

impl Depth {
    /// Depth tested with `compare`, written where `write`, no stencil, no bias.
    #[must_use]
    pub const fn test(format: DepthFormat, compare: Compare, write: bool) -> Self {
        Self {
            format,
            write,
            compare,
            stencil: Stencil::NONE,
            bias: Bias::NONE,
        }
    }
    /// Reversed Z (1 at the near plane, cleared to 0): nearer is `Greater`, written.
    #[must_use]
    pub const fn reversed_z(format: DepthFormat) -> Self {
        Self::test(format, Compare::Greater, true)
    }
    /// Only the fragments at the depth a prepass left (`Equal`), not written.
    #[must_use]
    pub const fn equal(format: DepthFormat) -> Self {
        Self::test(format, Compare::Equal, false)
    }
    /// A shadow map's (0 nearest the light, cleared to 1): nearer is `Less`, written, with
    /// `bias` against acne.
    #[must_use]
    pub const fn shadow(format: DepthFormat, bias: Bias) -> Self {
        Self {
            bias,
            ..Self::test(format, Compare::Less, true)
        }
    }
    /// With stencil state `stencil`.
    #[must_use]
    pub const fn stencil(self, stencil: Stencil) -> Self {
        Self { stencil, ..self }
    }
}

/// Depth bias: `constant` depth units plus `slope_scale` times the triangle's depth slope,
/// clamped to `clamp` (0: unclamped).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bias {
    /// Constant bias, in the format's smallest depth steps.
    pub constant: i32,
    /// Factor of the triangle's largest depth slope.
    pub slope_scale: f32,
    /// Largest bias (0: no clamp).
    pub clamp: f32,
}

impl Bias {
    /// No bias.
    pub const NONE: Bias = Bias {
        constant: 0,
        slope_scale: 0.0,
        clamp: 0.0,
    };
}

/// The stencil test and operations of both faces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Stencil {
    /// Front faces'.
    pub front: StencilFace,
    /// Back faces'.
    pub back: StencilFace,
    /// Bits the test reads.
    pub read_mask: u32,
    /// Bits the operations write.
    pub write_mask: u32,
}

impl Stencil {
    /// No stencil (wgpu's default: both faces [`StencilFace::KEEP`], masks 0).
    pub const NONE: Stencil = Stencil {
        front: StencilFace::KEEP,
        back: StencilFace::KEEP,
        read_mask: 0,
        write_mask: 0,
    };
    /// `face` on both faces, the low 8 bits read and written.
    #[must_use]
    pub const fn both(face: StencilFace) -> Self {
        Self {
            front: face,
            back: face,
            read_mask: 0xff,
            write_mask: 0xff,
        }
    }
}

/// One face's stencil test and what it does to the stored value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StencilFace {
    /// The test (against the reference value).
    pub compare: Compare,
    /// When the stencil test fails.
    pub fail: StencilOp,
    /// When it passes and the depth test fails.
    pub depth_fail: StencilOp,
    /// When both pass.
    pub pass: StencilOp,
}

impl StencilFace {
    /// Always passes, changes nothing.
    pub const KEEP: StencilFace =
        StencilFace::new(Compare::Always, StencilOp::Keep, StencilOp::Keep);

    /// Tested with `compare`; `pass` where depth passes too, `depth_fail` where it fails,
    /// kept where the stencil test fails.
    #[must_use]
    pub const fn new(compare: Compare, pass: StencilOp, depth_fail: StencilOp) -> Self {
        Self {
            compare,
            fail: StencilOp::Keep,
            depth_fail,
            pass,
        }
    }
}

/// A stencil operation (wgpu's of the same name).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StencilOp {
    /// Unchanged.
    Keep,
    /// Set to 0.
    Zero,
    /// Set to the reference value.
    Replace,
    /// Bitwise inverted.
    Invert,
    /// Incremented, clamped at the maximum.
    IncrementClamp,
    /// Decremented, clamped at 0.
    DecrementClamp,
    /// Incremented, wrapping.
    IncrementWrap,
    /// Decremented, wrapping.
    DecrementWrap,
}

/// Topology, winding and culling.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Primitive {
    /// How vertices make primitives.
    pub topology: Topology,
    /// Which winding faces the viewer.
    pub front_face: FrontFace,
    /// The faces not drawn, or none.
    pub cull: Option<Face>,
}

impl Primitive {
    /// Triangle lists, counter-clockwise front faces, both faces drawn (wgpu's default).
    pub const TRIANGLES: Primitive = Primitive {
        topology: Topology::TriangleList,
        front_face: FrontFace::Ccw,
        cull: None,
    };
}

/// A primitive topology (strips without a strip index format).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Topology {
    /// Every three vertices a triangle.
    TriangleList,
    /// Each vertex after the second a triangle with the two before.
    TriangleStrip,
    /// Every two vertices a line.
    LineList,
    /// Each vertex after the first a line to the one before.
    LineStrip,
    /// Every vertex a point.
    PointList,
}

/// The winding of a front face in framebuffer coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrontFace {
    /// Counter-clockwise.
    Ccw,
    /// Clockwise.
    Cw,
}

/// A face.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Face {
    /// Front faces.
    Front,
    /// Back faces.
    Back,
}

/// One vertex buffer: its stride, step and attributes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct VertexBuffer<'a> {
    /// Bytes from one element to the next.
    pub stride: u64,
    /// Whether it advances per instance (else per vertex).
    pub per_instance: bool,
    /// The attributes read from each element.
    pub attributes: &'a [Attribute],
}

/// One vertex attribute: `@location(location)` read as `format` at `offset` bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Attribute {
    /// Its format.
    pub format: VertexFormat,
    /// Bytes from the element's start.
    pub offset: u64,
    /// The vertex stage's input location.
    pub location: u32,
}

/// A vertex attribute format (WGSL type in the docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum VertexFormat {
    /// `f32`.
    Float32,
    /// `vec2<f32>`.
    Float32x2,
    /// `vec3<f32>`.
    Float32x3,
    /// `vec4<f32>`.
    Float32x4,
    /// `u32`.
    Uint32,
    /// `vec2<u32>`.
    Uint32x2,
    /// `vec4<u32>`.
    Uint32x4,
}

impl VertexFormat {
    /// Its size in bytes.
    #[must_use]
    pub const fn size(self) -> u64 {
        match self {
            VertexFormat::Float32 | VertexFormat::Uint32 => 4,
            VertexFormat::Float32x2 | VertexFormat::Uint32x2 => 8,
            VertexFormat::Float32x3 => 12,
            VertexFormat::Float32x4 | VertexFormat::Uint32x4 => 16,
        }
    }
}

/// Whether a colour target of `format` takes integer (`u32`) fragment outputs, else
/// float ones.
#[must_use]
pub const fn integer_target(format: Format) -> bool {
    matches!(
        format,
        Format::Rgba8Uint | Format::R32Uint | Format::R64Uint
    )
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    const VOLUME: &[VertexBuffer<'static>] = &[VertexBuffer {
        stride: 12,
        per_instance: false,
        attributes: &[Attribute {
            format: VertexFormat::Float32x3,
            offset: 0,
            location: 0,
        }],
    }];

    /// The light volumes' shading pipeline, its depth state given in full (the pipeline
    /// tests convert it to wgpu's).
    pub(crate) const SHADE: Raster<'static> = Raster::new("shade", "vs_volume")
        .fragment("fs_shade")
        .buffers(VOLUME)
        .targets(&[Target::additive(Format::Rgba16Float)])
        .depth(
            Depth::test(
                DepthFormat::Depth24PlusStencil8,
                Compare::GreaterEqual,
                false,
            )
            .stencil(Stencil::both(StencilFace::new(
                Compare::Equal,
                StencilOp::Zero,
                StencilOp::Zero,
            ))),
        )
        .cull(Some(Face::Back));

    #[test]
    fn builders_set_only_their_field() {
        assert_eq!(SHADE.fragment, Some("fs_shade"));
        assert_eq!(SHADE.primitive.topology, Topology::TriangleList);
        assert_eq!(SHADE.primitive.cull, Some(Face::Back));
        assert_eq!(SHADE.samples, 1);
        let d = SHADE.depth.unwrap();
        assert!(!d.write);
        assert_eq!(d.bias, Bias::NONE);
        assert_eq!(d.stencil.front, d.stencil.back);
        assert_eq!(d.stencil.front.fail, StencilOp::Keep);
        let d32 = SHADE
            .depth_format(DepthFormat::Depth32FloatStencil8)
            .depth
            .unwrap();
        assert_eq!(d32.format, DepthFormat::Depth32FloatStencil8);
        assert_eq!(d32.stencil, d.stencil);
        let four = SHADE.samples(4).named("shade msaa");
        assert_eq!((four.samples, four.name), (4, "shade msaa"));
        assert_eq!(four.targets, SHADE.targets);
    }

    #[test]
    fn common_depth_states() {
        let f = DepthFormat::Depth32Float;
        assert_eq!(
            (Depth::reversed_z(f).compare, Depth::reversed_z(f).write),
            (Compare::Greater, true)
        );
        assert_eq!(
            (Depth::equal(f).compare, Depth::equal(f).write),
            (Compare::Equal, false)
        );
        let bias = Bias {
            constant: 2,
            slope_scale: 2.0,
            clamp: 0.0,
        };
        let s = Depth::shadow(f, bias);
        assert_eq!((s.compare, s.write, s.bias), (Compare::Less, true, bias));
        assert_eq!(Stencil::NONE.read_mask | Stencil::NONE.write_mask, 0);
    }

    #[test]
    fn targets_and_formats() {
        assert_eq!(Target::replace(Format::R32Uint).write_mask, 0xf);
        assert_eq!(Target::untouched(Format::R32Uint).write_mask, 0);
        assert_eq!(
            Target::additive(Format::Rgba32Float).blend,
            Some(Blend::ADDITIVE)
        );
        assert!(integer_target(Format::Rgba8Uint));
        assert!(!integer_target(Format::Rgba8Unorm));
        assert_eq!(VertexFormat::Float32x3.size(), 12);
    }
}
