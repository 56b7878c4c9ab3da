//! The depth + visibility laydown (seed 000) and the baseline's depth prepass: one render
//! pass each, one indexed draw per micro batch, vertices pulled from storage, the primitive
//! ID from the adapter's best path (`gpu::laydown_builtin`, `_xor`, `_provoking`).

use shader::pipeline::{Layouts, RasterPass};
use shader::{Binding, Entry, Format, Group, Kind, Pass, Raster, Stage, Target};

use super::context::FrameContext;
use super::raster::{DEPTH_WRITE, GEOMETRY, SCENE_GROUP, SHADOW_DEPTH, depth_attachment};
use super::raster::{draw_planned, record_draws};
use crate::context::PrimitiveIdPath;
use crate::error::Result;
pub(crate) use crate::resources::groups::LaydownGroups as Groups;
use crate::resources::plan::Draw;
use crate::resources::static_draws::StaticBuffers;
use crate::shaders::LIBRARY;
use crate::timing::GpuTimer;

const GROUPS: &[Group] = &[
    SCENE_GROUP,
    Group {
        name: "payloads",
        bindings: &[Binding::new("payloads", Kind::read(4))],
    },
];

const ENTRIES: &[Entry<()>] = &[
    Entry::draw("vs_main", Stage::Vertex),
    Entry::draw("vs_payload", Stage::Vertex),
    Entry::draw("fs_depth_alpha", Stage::Fragment),
    Entry::draw("fs_vis", Stage::Fragment),
    Entry::draw("fs_vis_alpha", Stage::Fragment),
];

/// The laydown on the `primitive_index` path (`Features::PRIMITIVE_INDEX`).
pub(crate) const LAYDOWN_BUILTIN: Pass = Pass {
    name: "laydown (primitive_index)",
    module: "gpu::laydown_builtin",
    library: LIBRARY,
    features: &[],
    groups: GROUPS,
    entries: ENTRIES,
    zeroed: &[],
};

/// The laydown on HFW's XOR path (`Features::SHADER_PER_VERTEX`).
pub(crate) const LAYDOWN_XOR: Pass = Pass {
    name: "laydown (XOR payloads)",
    module: "gpu::laydown_xor",
    ..LAYDOWN_BUILTIN
};

/// The laydown on the provoking-vertex path (every adapter).
pub(crate) const LAYDOWN_PROVOKING: Pass = Pass {
    name: "laydown (provoking vertex)",
    module: "gpu::laydown_provoking",
    ..LAYDOWN_BUILTIN
};

/// The laydown description of `path`.
pub(crate) fn pass(path: PrimitiveIdPath) -> &'static Pass {
    match path {
        PrimitiveIdPath::Builtin => &LAYDOWN_BUILTIN,
        PrimitiveIdPath::PerVertexXor => &LAYDOWN_XOR,
        PrimitiveIdPath::ProvokingVertex => &LAYDOWN_PROVOKING,
    }
}

/// The vis buffer as a colour target ([`VIS_FORMAT`](crate::resources::targets::VIS_FORMAT)).
const VIS_TARGETS: &[Target] = &[Target::replace(Format::R32Uint)];

/// The sun and spot shadows' opaque casters: depth only.
pub(crate) const SHADOW_OPAQUE: Raster<'static> = Raster::new("sun shadow opaque", "vs_main")
    .primitive(GEOMETRY)
    .depth(SHADOW_DEPTH);

/// The shadows' alpha-tested casters.
pub(crate) const SHADOW_ALPHA: Raster<'static> = SHADOW_OPAQUE
    .named("sun shadow alpha")
    .fragment("fs_depth_alpha");

/// The laydown's opaque draws into depth and the vis buffer (the payload vertex stage;
/// the `primitive_index` path takes `vs_main`).
pub(crate) const VIS_OPAQUE: Raster<'static> = Raster::new("laydown vis opaque", "vs_payload")
    .fragment("fs_vis")
    .targets(VIS_TARGETS)
    .primitive(GEOMETRY)
    .depth(DEPTH_WRITE);

/// The laydown's alpha-tested draws.
pub(crate) const VIS_ALPHA: Raster<'static> = VIS_OPAQUE
    .named("laydown vis alpha")
    .fragment("fs_vis_alpha");

/// The depth prepass's opaque draws: depth only.
pub(crate) const DEPTH_OPAQUE: Raster<'static> = Raster::new("prepass depth opaque", "vs_main")
    .primitive(GEOMETRY)
    .depth(DEPTH_WRITE);

/// The depth prepass's alpha-tested draws.
pub(crate) const DEPTH_ALPHA: Raster<'static> = DEPTH_OPAQUE
    .named("prepass depth alpha")
    .fragment("fs_depth_alpha");

/// Timing labels of the sun-shadow passes, one per cascade.
const SHADOW_LABELS: [&str; deferred::cascades::MAX_CASCADES] = [
    "sun shadow 0",
    "sun shadow 1",
    "sun shadow 2",
    "sun shadow 3",
    "sun shadow 4",
    "sun shadow 5",
    "sun shadow 6",
    "sun shadow 7",
];

/// The laydown's pipelines for one primitive-ID path, the depth prepass's and the sun
/// shadows'.
pub(crate) struct Laydown {
    layouts: Layouts,
    vis_opaque: wgpu::RenderPipeline,
    vis_alpha: wgpu::RenderPipeline,
    depth_opaque: wgpu::RenderPipeline,
    depth_alpha: wgpu::RenderPipeline,
    /// The depth prepass at [`crate::config::MSAA_SAMPLES`] samples (opaque, alpha-tested), with
    /// MSAA on.
    depth_msaa: Option<(wgpu::RenderPipeline, wgpu::RenderPipeline)>,
    shadow_opaque: wgpu::RenderPipeline,
    shadow_alpha: wgpu::RenderPipeline,
}

impl Laydown {
    /// The pipelines of `path`; with `msaa`, the multisampled depth prepass's too.
    pub(crate) fn new(device: &wgpu::Device, path: PrimitiveIdPath, msaa: bool) -> Result<Self> {
        let raster = RasterPass::new(device, pass(path), &[], &[])?;
        let make = |r: &Raster<'_>| raster.pipeline(device, r);
        // The builtin path needs no payload: its vertex stage passes none.
        let vs = if path == PrimitiveIdPath::Builtin {
            "vs_main"
        } else {
            "vs_payload"
        };
        let depth_msaa = if msaa {
            let ms = |r: Raster<'static>, name| {
                make(&r.samples(crate::config::MSAA_SAMPLES).named(name))
            };
            Some((
                ms(DEPTH_OPAQUE, "prepass depth opaque msaa")?,
                ms(DEPTH_ALPHA, "prepass depth alpha msaa")?,
            ))
        } else {
            None
        };
        Ok(Self {
            shadow_opaque: make(&SHADOW_OPAQUE)?,
            shadow_alpha: make(&SHADOW_ALPHA)?,
            vis_opaque: make(&Raster {
                vertex: vs,
                ..VIS_OPAQUE
            })?,
            vis_alpha: make(&Raster {
                vertex: vs,
                ..VIS_ALPHA
            })?,
            depth_opaque: make(&DEPTH_OPAQUE)?,
            depth_alpha: make(&DEPTH_ALPHA)?,
            depth_msaa,
            layouts: raster.layouts,
        })
    }

    /// The bind groups of a prepared scene: `scene` resources by binding name (group 0) and
    /// the payload buffer.
    pub(crate) fn groups(
        &self,
        device: &wgpu::Device,
        scene: &[(&str, wgpu::BindingResource<'_>)],
        payloads: &wgpu::Buffer,
    ) -> Result<Groups> {
        Ok(Groups {
            scene: self.layouts.bind_group(device, "scene", scene)?,
            payloads: self.layouts.bind_group(
                device,
                "payloads",
                &[("payloads", payloads.as_entire_binding())],
            )?,
        })
    }

    /// A scene group (group 0) over `scene` resources by binding name: the sun-shadow
    /// passes' groups, whose `frame` is a cascade's.
    pub(crate) fn scene_group(
        &self,
        device: &wgpu::Device,
        scene: &[(&str, wgpu::BindingResource<'_>)],
    ) -> Result<wgpu::BindGroup> {
        Ok(self.layouts.bind_group(device, "scene", scene)?)
    }

    /// Records the sun's shadow maps, one render pass per cascade: the casters of the
    /// scene's own batches whose chunks meet the cascade's clip volume (every one with
    /// `cull_shadow_casters` off; opaque, then alpha-tested), drawn with the cascade's frame
    /// uniforms, then, in a frame with a static query, the static casters of the slice's
    /// own shadow view (the static query over the slice's volume with KZ2's size
    /// threshold, placed into the slice's own rows and draw lists), or, for a slice
    /// without one, the camera query's lists.
    pub(crate) fn record_shadows(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
    ) {
        let maps = &f.targets.shadows;
        for (i, (view, group)) in maps
            .layer_views
            .iter()
            .zip(&f.scene.shadow_scene)
            .take(maps.cascades() as usize)
            .enumerate()
        {
            if !maps.dirty.get(i).copied().unwrap_or(true) {
                continue;
            }
            let mut pass = shadow_pass(encoder, view, SHADOW_LABELS[i], timer);
            // KZ2's per-slice resolution: the slice's map in the corner of its layer.
            let texels = maps
                .config
                .map_or(1, |c| c.slice_resolution(i))
                .min(maps.texture.width()) as f32;
            pass.set_viewport(0.0, 0.0, texels, texels, 0.0, 1.0);
            let statics = match f.scene.static_shadows.get(i) {
                Some(set) if f.static_slices.get(i).copied().unwrap_or(false) => {
                    set.slice_group.as_ref().map(|g| (&set.buffers, g))
                }
                _ => None,
            };
            self.draw_shadow_view(&mut pass, f, group, f.casters.slices.get(i), statics);
        }
    }

    /// One shadow view's casters through its scene group (whose frame uniforms hold the
    /// view's matrix): the planned ones culled by `planes` where given, then the static
    /// ones: `statics`' lists through its group (the view's own shadow query: rows of its
    /// own, same frame uniforms), else, in a frame with a static query, the camera
    /// query's lists. Static instances may fade, so they take the alpha-tested pipeline,
    /// which dithers them (a shadow view's own instances never fade: no effect).
    fn draw_shadow_view(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        f: &FrameContext<'_>,
        group: &wgpu::BindGroup,
        planes: Option<&[glam::Vec4; 6]>,
        statics: Option<(&StaticBuffers, &wgpu::BindGroup)>,
    ) {
        pass.set_bind_group(0, group, &[]);
        pass.set_bind_group(1, &f.scene.laydown.payloads, &[]);
        let (opaque, alpha) = (&self.shadow_opaque, &self.shadow_alpha);
        match planes {
            Some(planes) => {
                draw_planned_culled(pass, f.scene, opaque, alpha, planes, f.origin_offset);
            }
            None => draw_planned(pass, f.scene, opaque, alpha, false),
        }
        match statics {
            Some((b, own)) => {
                pass.set_bind_group(0, own, &[]);
                pass.set_index_buffer(f.scene.index_buffer.slice(..), wgpu::IndexFormat::Uint32);
                super::raster::record_static_draws(pass, b, alpha, alpha, false);
            }
            None => {
                if f.static_query
                    && let Some(b) = &f.scene.statics
                {
                    super::raster::record_static_draws(pass, b, alpha, alpha, false);
                }
            }
        }
    }

    /// Records this frame's spot shadow maps (KZ2's shadowed local lights): the scene's
    /// casters meeting each chosen light's view, drawn from the light, one layer each.
    /// With KZ2's conditional rendering emulated ([`super::conditional`]), a shadowed
    /// volume light's map draws its planned casters through the arguments its test wrote
    /// (none where its volume covers no pixel), and a map whose light has no volume draw is
    /// skipped.
    pub(crate) fn record_spot_shadows(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
    ) {
        use crate::resources::conditional::{COUNT_WORDS, DRAW_BYTES, MapDraw, draw_rows};
        let maps = &f.targets.spot_shadows;
        for (k, (view, group)) in maps
            .layer_views
            .iter()
            .zip(&f.scene.spot_shadow_scene)
            .take(maps.active as usize)
            .enumerate()
        {
            let plan = f
                .conditional
                .and_then(|c| c.plan.maps.get(k).map(|m| (c, *m)));
            match plan {
                None | Some((_, MapDraw::Direct)) => {
                    let mut pass = shadow_pass(encoder, view, "spot shadow maps", timer);
                    self.draw_shadow_view(&mut pass, f, group, f.casters.spots.get(k), None);
                }
                Some((_, MapDraw::Skipped)) => {}
                Some((
                    c,
                    MapDraw::Indirect {
                        test,
                        first,
                        opaque,
                        alpha,
                    },
                )) => {
                    let mut pass = shadow_pass(encoder, view, "spot shadow maps", timer);
                    pass.set_bind_group(0, group, &[]);
                    pass.set_bind_group(1, &f.scene.laydown.payloads, &[]);
                    pass.set_index_buffer(
                        f.scene.index_buffer.slice(..),
                        wgpu::IndexFormat::Uint32,
                    );
                    let word = u64::from(COUNT_WORDS) * u64::from(test);
                    pass.set_pipeline(&self.shadow_opaque);
                    draw_rows(&mut pass, c, first, opaque, word);
                    pass.set_pipeline(&self.shadow_alpha);
                    draw_rows(&mut pass, c, first + opaque, alpha, word + 1);
                    if f.static_query
                        && let Some(b) = &f.scene.statics
                    {
                        if c.with_count && b.with_count {
                            // The full lists with this light's copies of their counts.
                            for (list, first, count) in [(2, 0, b.opaque), (3, b.opaque, b.alpha)] {
                                if count > 0 {
                                    pass.multi_draw_indexed_indirect_count(
                                        &b.draws,
                                        u64::from(first) * DRAW_BYTES,
                                        &c.counts,
                                        4 * (word + list),
                                        count,
                                    );
                                }
                            }
                        } else {
                            super::raster::record_static_draws(
                                &mut pass,
                                b,
                                &self.shadow_alpha,
                                &self.shadow_alpha,
                                false,
                            );
                        }
                    }
                }
            }
        }
    }

    /// Records KZ2's pre-rendered sun map: every caster of the scene's own batches into
    /// `target`, through the bake group (whose frame holds the bake's matrix), then, with
    /// `statics`, the static casters its shadow view placed (lists and their group).
    pub(crate) fn record_bake(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        scene: &crate::resources::PreparedScene,
        target: &wgpu::TextureView,
        statics: Option<(&StaticBuffers, &wgpu::BindGroup)>,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("baked sun map"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: target,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, &scene.bake_scene, &[]);
        pass.set_bind_group(1, &scene.laydown.payloads, &[]);
        draw_planned(
            &mut pass,
            scene,
            &self.shadow_opaque,
            &self.shadow_alpha,
            false,
        );
        if let Some((b, group)) = statics {
            pass.set_bind_group(0, group, &[]);
            pass.set_index_buffer(scene.index_buffer.slice(..), wgpu::IndexFormat::Uint32);
            let alpha = &self.shadow_alpha;
            super::raster::record_static_draws(&mut pass, b, alpha, alpha, false);
        }
    }

    /// Records the depth + visibility laydown; `late`: its second geometry pass of two-pass
    /// occlusion, the late static lists over the depth and vis buffer the first left.
    pub(crate) fn record_vis(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
        late: bool,
    ) {
        let load = if late {
            wgpu::LoadOp::Load
        } else {
            wgpu::LoadOp::Clear(wgpu::Color {
                r: f64::from(visbuf::VIS_NONE),
                g: 0.0,
                b: 0.0,
                a: 0.0,
            })
        };
        let label = if late { "late laydown" } else { "laydown" };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(label),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &f.targets.vis_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(depth_attachment(&f.targets.depth_view, late)),
            timestamp_writes: timer.render(label),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        // The mixed frame leaves the regular batches to its regular geometry pass.
        let skip_regular = f.scene.regular.is_some();
        self.draw(
            &mut pass,
            f,
            &self.vis_opaque,
            &self.vis_alpha,
            late,
            skip_regular,
        );
    }

    /// Records the baseline's depth prepass (alpha-tested, no colour); `late`: its second
    /// geometry pass of two-pass occlusion, the late static lists over the depth the first
    /// left.
    pub(crate) fn record_depth(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
        late: bool,
    ) {
        let label = if late {
            "late depth prepass"
        } else {
            "depth prepass"
        };
        // The baseline's MSAA frame: the multisampled depth and pipelines.
        let (view, opaque, alpha) = match (f.msaa, &f.targets.msaa, &self.depth_msaa) {
            (true, Some(t), Some((o, a))) => (&t.depth_view, o, a),
            _ => (&f.targets.depth_view, &self.depth_opaque, &self.depth_alpha),
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(label),
            color_attachments: &[],
            depth_stencil_attachment: Some(depth_attachment(view, late)),
            timestamp_writes: timer.render(label),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        self.draw(&mut pass, f, opaque, alpha, late, false);
    }

    fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        f: &FrameContext<'_>,
        opaque: &wgpu::RenderPipeline,
        alpha: &wgpu::RenderPipeline,
        late: bool,
        skip_regular: bool,
    ) {
        let groups = &f.scene.laydown;
        pass.set_bind_group(0, &groups.scene, &[]);
        pass.set_bind_group(1, &groups.payloads, &[]);
        if late {
            if let Some(b) = &f.scene.statics {
                pass.set_index_buffer(f.scene.index_buffer.slice(..), wgpu::IndexFormat::Uint32);
                // Static instances may fade: the alpha-tested pipeline dithers them.
                super::raster::record_static_draws(pass, b, alpha, alpha, true);
            }
        } else {
            // Static instances may fade: the alpha-tested pipeline dithers them.
            record_draws(pass, f, opaque, alpha, alpha, skip_regular);
        }
    }
}

/// A depth-only pass into one shadow-map layer, cleared to 1 (farthest from the light),
/// timed under `label`.
fn shadow_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    view: &wgpu::TextureView,
    label: &'static str,
    timer: &mut GpuTimer,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Clear(1.0),
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: timer.render(label),
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

/// The scene's planned draws as [`draw_planned`], each reduced to its chunks whose
/// spheres (origin-relative, moved by `offset` to camera-relative) meet `planes`.
fn draw_planned_culled(
    pass: &mut wgpu::RenderPass<'_>,
    scene: &crate::resources::PreparedScene,
    opaque: &wgpu::RenderPipeline,
    alpha: &wgpu::RenderPipeline,
    planes: &[glam::Vec4; 6],
    offset: glam::Vec3,
) {
    pass.set_index_buffer(scene.index_buffer.slice(..), wgpu::IndexFormat::Uint32);
    for alpha_pass in [false, true] {
        pass.set_pipeline(if alpha_pass { alpha } else { opaque });
        for_each_caster(
            scene,
            Some(planes),
            offset,
            alpha_pass,
            |d, first, count| {
                pass.draw_indexed(
                    d.first_index..d.first_index + d.index_count,
                    d.base_vertex as i32,
                    first..first + count,
                );
            },
        );
    }
}

/// Calls `draw(d, first_instance, instance_count)` for the scene's planned draws that are
/// alpha-tested (`alpha_pass`) or opaque, each reduced with `planes` as
/// [`draw_planned_culled`] does (whole without planes): what a shadow view draws.
pub(crate) fn for_each_caster(
    scene: &crate::resources::PreparedScene,
    planes: Option<&[glam::Vec4; 6]>,
    offset: glam::Vec3,
    alpha_pass: bool,
    mut draw: impl FnMut(&Draw, u32, u32),
) {
    for d in scene
        .draws
        .iter()
        .filter(|d| d.alpha_tested == alpha_pass && d.instance_count > 0)
    {
        let Some(planes) = planes else {
            draw(d, d.first_instance, d.instance_count);
            continue;
        };
        let chunks = scene
            .chunks
            .get(d.first_chunk as usize..(d.first_chunk + d.chunk_count) as usize)
            .unwrap_or(&[]);
        let mut run: Option<(u32, u32)> = None;
        let mut flush = |run: &mut Option<(u32, u32)>| {
            if let Some((first, count)) = run.take() {
                draw(d, first, count);
            }
        };
        for c in chunks {
            if crate::shadows::sphere_meets(planes, c.center + offset, c.radius) {
                run = match run {
                    Some((first, count)) if first + count == c.first_instance => {
                        Some((first, count + c.instance_count))
                    }
                    other => {
                        let mut other = other;
                        flush(&mut other);
                        Some((c.first_instance, c.instance_count))
                    }
                };
            } else {
                flush(&mut run);
            }
        }
        flush(&mut run);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shadercheck::Caps;

    fn caps(path: PrimitiveIdPath) -> Caps {
        match path {
            PrimitiveIdPath::Builtin => Caps::PRIMITIVE_INDEX,
            PrimitiveIdPath::PerVertexXor => Caps::PER_VERTEX,
            PrimitiveIdPath::ProvokingVertex => Caps::CORE,
        }
    }

    #[test]
    fn descriptions_match_their_modules_with_only_their_path_capability() {
        for path in PrimitiveIdPath::ALL {
            let p = pass(path);
            shadercheck::check_pass(p, |_| caps(path));
            if path != PrimitiveIdPath::ProvokingVertex {
                let src = p.source(&[]).unwrap();
                assert!(
                    shadercheck::validate(&src, Caps::CORE).is_err(),
                    "{} must need its feature",
                    path.name()
                );
            }
        }
    }

    #[test]
    fn pipelines_match_their_modules() {
        for path in PrimitiveIdPath::ALL {
            let vs = if path == PrimitiveIdPath::Builtin {
                "vs_main"
            } else {
                "vs_payload"
            };
            for r in [SHADOW_OPAQUE, SHADOW_ALPHA, DEPTH_OPAQUE, DEPTH_ALPHA] {
                shadercheck::check_raster(pass(path), &r, &[], caps(path));
            }
            for r in [VIS_OPAQUE, VIS_ALPHA] {
                let r = Raster { vertex: vs, ..r };
                shadercheck::check_raster(pass(path), &r, &[], caps(path));
            }
        }
        assert_eq!(
            shader::pipeline::texture_format(VIS_TARGETS[0].format),
            crate::resources::targets::VIS_FORMAT
        );
    }
}
