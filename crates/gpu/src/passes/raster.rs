//! What the raster passes share: the scene's bind group, the geometry's primitive and
//! depth states as [`shader::Raster`] parts (each pass declares its pipelines from them,
//! next to its `Pass`), the G-buffer's colour targets, and the depth attachment.

use shader::{
    Bias, Binding, Depth, DepthFormat, Face, Format, FrontFace, Group, Kind, Primitive, Sample,
    Target, Topology,
};

use crate::passes::context::FrameContext;
use crate::resources::plan::Draw;
use crate::resources::rows::{FrameUniforms, GpuInstance, GpuMaterial, GpuVertex};
use crate::resources::static_draws::DRAW_BYTES;
use crate::resources::static_draws::STATIC_COUNTER_DRAWS;
use crate::resources::static_draws::STATIC_COUNTER_LATE_DRAWS;
use crate::resources::static_draws::StaticBuffers;

/// Group 0 of every pass that draws or resolves the scene (`gpu::scene_bindings`).
pub(crate) const SCENE_GROUP: Group = Group {
    name: "scene",
    bindings: &[
        Binding::new("frame", Kind::uniform(size_of::<FrameUniforms>())),
        Binding::new("vertices", Kind::read(size_of::<GpuVertex>())),
        Binding::new("instances", Kind::read(size_of::<GpuInstance>())),
        Binding::new("materials", Kind::read(size_of::<GpuMaterial>())),
        Binding::new(
            "albedo",
            Kind::Texture {
                sample: Sample::Float { filterable: true },
                dim: shader::Dim::D2Array,
            },
        ),
        Binding::new("albedo_sampler", Kind::Sampler),
        Binding::new("baked_sun_map", Kind::texture_2d(Sample::Depth)),
        Binding::new(
            "data_maps",
            Kind::Texture {
                sample: Sample::Float { filterable: true },
                dim: shader::Dim::D2Array,
            },
        ),
    ],
};

/// The frame's depth target's format
/// ([`DEPTH_FORMAT`](crate::resources::targets::DEPTH_FORMAT)).
pub(crate) const DEPTH: DepthFormat = DepthFormat::Depth32Float;

/// The shadow maps' format ([`SHADOW_FORMAT`](crate::shadows::SHADOW_FORMAT)).
pub(crate) const SHADOW: DepthFormat = DepthFormat::Depth32Float;

/// Primitive state of every geometry pipeline: triangle lists, counter-clockwise front
/// faces, back faces culled (foliage cards carry both faces as geometry).
pub(crate) const GEOMETRY: Primitive = Primitive {
    topology: Topology::TriangleList,
    front_face: FrontFace::Ccw,
    cull: Some(Face::Back),
};

/// Reversed-Z depth state of the frame's depth: `Greater`, writing.
pub(crate) const DEPTH_WRITE: Depth = Depth::reversed_z(DEPTH);

/// The depth-equal passes' state over a prepass's depth: `Equal`, not writing.
pub(crate) const DEPTH_EQUAL: Depth = Depth::equal(DEPTH);

/// The sun and spot shadow passes' depth state: depth 0 nearest the light, `Less`,
/// writing, with a slope-scaled bias against acne.
pub(crate) const SHADOW_DEPTH: Depth = Depth::shadow(
    SHADOW,
    Bias {
        constant: 2,
        slope_scale: 2.0,
        clamp: 0.0,
    },
);

/// The colour-target format of a G-buffer target format (a depth format is none).
const fn gbuffer_format(f: deferred::TargetFormat) -> Format {
    match f {
        deferred::TargetFormat::Rgba8Unorm => Format::Rgba8Unorm,
        deferred::TargetFormat::Rgba8Uint => Format::Rgba8Uint,
        deferred::TargetFormat::Rgba16Float => Format::Rgba16Float,
        deferred::TargetFormat::Depth24PlusStencil8 | deferred::TargetFormat::Depth32Float => {
            panic!("a depth format is no colour target")
        }
    }
}

const fn gbuffer_targets_of(layout: deferred::GBufferLayout) -> [Target; 4] {
    let f = layout.color_formats();
    [
        Target::replace(gbuffer_format(f[0])),
        Target::replace(gbuffer_format(f[1])),
        Target::replace(gbuffer_format(f[2])),
        Target::replace(gbuffer_format(f[3])),
    ]
}

const KZ2_TARGETS: [Target; 4] = gbuffer_targets_of(deferred::GBufferLayout::Kz2);
const OCTAHEDRAL_TARGETS: [Target; 4] = gbuffer_targets_of(deferred::GBufferLayout::Octahedral);

/// The G-buffer of `layout` as colour targets RT0..RT3, each replaced.
pub(crate) const fn gbuffer_targets(layout: deferred::GBufferLayout) -> &'static [Target] {
    match layout {
        deferred::GBufferLayout::Kz2 => &KZ2_TARGETS,
        deferred::GBufferLayout::Octahedral => &OCTAHEDRAL_TARGETS,
    }
}

/// The depth target cleared to the far plane (reversed Z: 0), or loaded (`load`).
pub(crate) fn depth_attachment(
    view: &wgpu::TextureView,
    load: bool,
) -> wgpu::RenderPassDepthStencilAttachment<'_> {
    wgpu::RenderPassDepthStencilAttachment {
        view,
        depth_ops: Some(wgpu::Operations {
            load: if load {
                wgpu::LoadOp::Load
            } else {
                wgpu::LoadOp::Clear(0.0)
            },
            store: wgpu::StoreOp::Store,
        }),
        stencil_ops: None,
    }
}

/// `views` as colour attachments whose contents are loaded and stored (the G-buffer drawn
/// over by a second geometry pass).
pub(crate) fn loaded_colors(
    views: &[wgpu::TextureView],
) -> Vec<Option<wgpu::RenderPassColorAttachment<'_>>> {
    views
        .iter()
        .map(|v| {
            Some(wgpu::RenderPassColorAttachment {
                view: v,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })
        })
        .collect()
}

/// Records static draw lists into a geometry pass: the opaque list with `opaque`, the
/// alpha-tested list with `alpha` (index buffer and bind groups are the caller's); the full
/// lists, or with `late` the late ones.
pub(crate) fn record_static_draws(
    pass: &mut wgpu::RenderPass<'_>,
    b: &StaticBuffers,
    opaque: &wgpu::RenderPipeline,
    alpha: &wgpu::RenderPipeline,
    late: bool,
) {
    let (block, count_word) = if late {
        (b.setup_count, STATIC_COUNTER_LATE_DRAWS)
    } else {
        (0, STATIC_COUNTER_DRAWS)
    };
    for (list, pipeline, first, count) in [
        (0u64, opaque, 0u32, b.opaque),
        (1, alpha, b.opaque, b.alpha),
    ] {
        if count == 0 {
            continue;
        }
        pass.set_pipeline(pipeline);
        let offset = u64::from(block + first) * DRAW_BYTES;
        if b.with_count {
            pass.multi_draw_indexed_indirect_count(
                &b.draws,
                offset,
                &b.counters,
                4 * (u64::from(count_word) + list),
                count,
            );
        } else {
            pass.multi_draw_indexed_indirect(&b.draws, offset, count);
        }
    }
}

/// Records the scene's planned draws with the opaque or alpha-tested pipeline as each
/// needs, opaque draws first (they fill depth that early-Z then uses against the
/// foliage), then, in a frame with a static query, the static draw lists (opaque, then
/// alpha-tested) with `statics`, a pipeline that applies the LOD fade dither (static
/// instances may fade). `skip_regular`: leave out the draws of regular materials (the
/// mixed frame's laydown). Bind groups are the caller's.
pub(crate) fn record_draws(
    pass: &mut wgpu::RenderPass<'_>,
    f: &FrameContext<'_>,
    opaque: &wgpu::RenderPipeline,
    alpha: &wgpu::RenderPipeline,
    statics: &wgpu::RenderPipeline,
    skip_regular: bool,
) {
    draw_planned(pass, f.scene, opaque, alpha, skip_regular);
    if f.static_query
        && let Some(b) = &f.scene.statics
    {
        record_static_draws(pass, b, statics, statics, false);
    }
}

/// The scene's planned draws (its batches), opaque first, then alpha-tested; without the
/// regular materials' with `skip_regular`.
pub(crate) fn draw_planned(
    pass: &mut wgpu::RenderPass<'_>,
    scene: &crate::resources::PreparedScene,
    opaque: &wgpu::RenderPipeline,
    alpha: &wgpu::RenderPipeline,
    skip_regular: bool,
) {
    let draws: &[Draw] = &scene.draws;
    pass.set_index_buffer(scene.index_buffer.slice(..), wgpu::IndexFormat::Uint32);
    for alpha_pass in [false, true] {
        pass.set_pipeline(if alpha_pass { alpha } else { opaque });
        for d in draws.iter().filter(|d| {
            d.alpha_tested == alpha_pass && d.instance_count > 0 && !(skip_regular && d.regular)
        }) {
            draw(pass, d);
        }
    }
}

/// One planned draw: its index range, base vertex and instances.
pub(crate) fn draw(pass: &mut wgpu::RenderPass<'_>, d: &Draw) {
    pass.draw_indexed(
        d.first_index..d.first_index + d.index_count,
        d.base_vertex as i32,
        d.first_instance..d.first_instance + d.instance_count,
    );
}

#[cfg(test)]
mod tests {
    use shader::pipeline::{depth_format, texture_format};

    use super::*;

    /// The descriptions' formats are the textures' they draw into.
    #[test]
    fn formats_are_the_targets() {
        assert_eq!(depth_format(DEPTH), crate::resources::targets::DEPTH_FORMAT);
        assert_eq!(depth_format(SHADOW), crate::shadows::SHADOW_FORMAT);
        for layout in deferred::GBufferLayout::ALL {
            let want = crate::gbuffer::color_formats(layout);
            let got: Vec<_> = gbuffer_targets(layout)
                .iter()
                .map(|t| texture_format(t.format))
                .collect();
            assert_eq!(got, want, "{layout:?}");
            assert!(gbuffer_targets(layout).iter().all(|t| t.blend.is_none()));
        }
    }
}
