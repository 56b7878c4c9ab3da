//! KZ2's stencil light volumes (`gpu::light_volumes`): the lights [`LightPaths`] sends
//! here (KZ2: large ones, or the eye inside) are drawn as convex meshes over a copy of the
//! frame's depth with a stencil buffer, and their shading is summed into an accumulation
//! target that the compute lighting adds. wgpu has no depth-bounds test and the frame's
//! depth target has no stencil, so the pass first copies depth into its own depth-stencil
//! target (one full-screen triangle). Per light (camera outside its mesh): back faces
//! behind the scene mark stencil, front faces in front of the scene where stencil is set
//! shade and clear it; with the eye inside (or the mesh reaching the near plane), back
//! faces behind the scene shade alone. KZ2's light-shader permutations: each light's shade
//! pipeline is compiled without the spot shadow code unless the light has a map this frame,
//! and without the specular term for lights that have none ([`PointLight::specular`]).
//!
//! [`LightPaths`]: crate::config::LightPaths
//! [`PointLight::specular`]: crate::PointLight::specular

use deferred::DeferredLight;
use glam::Vec3;
use shader::pipeline::{Layouts, RasterPass};
use shader::{
    Attribute, Binding, Compare, Depth, DepthFormat, Entry, Face, Group, Kind, Pass, Raster,
    Sample, Stage, Stencil, StencilFace, StencilOp, Target, VertexBuffer, VertexFormat,
};

use super::context::FrameContext;
use super::raster::GEOMETRY;
use crate::error::Result;
use crate::gbuffer::{KZ2_LOAD_BINDINGS, LOAD_BINDINGS};
use crate::resources::conditional::{DRAW_BYTES, MAX_TESTS};
pub(crate) use crate::resources::groups::LightVolumeGroups as Groups;
use crate::resources::lights::GpuLightVolume;
use crate::resources::lights::GpuLocalLights;
use crate::resources::rows::FrameUniforms;
use crate::resources::targets::{accumulation, cleared_color, depth_stencil};
use crate::shaders::LIBRARY;
use crate::timing::GpuTimer;
use deferred::GBufferLayout;

/// The pass: the depth copy and the volumes (group `volume`), over the G-buffer.
pub(crate) const LIGHT_VOLUMES: Pass = Pass {
    name: "light volumes",
    module: "gpu::light_volumes",
    library: LIBRARY,
    features: &["spot_shadows", "no_specular"],
    groups: &[
        Group {
            name: "volume",
            bindings: &[
                Binding::new("frame", Kind::uniform(size_of::<FrameUniforms>())),
                Binding::new("depth_texture", Kind::texture_2d(Sample::Depth)),
                Binding::new("local", Kind::uniform(size_of::<GpuLocalLights>())),
                Binding::new("lights", Kind::read(size_of::<DeferredLight>())),
                Binding::new("volumes", Kind::read(size_of::<GpuLightVolume>())),
                crate::spot_shadows::MAP_BINDING,
                crate::spot_shadows::ROWS_BINDING,
            ],
        },
        Group {
            name: "gbuffer",
            bindings: &LOAD_BINDINGS,
        },
    ],
    entries: &[
        Entry::draw("vs_full_screen", Stage::Vertex),
        Entry::draw("fs_copy_depth", Stage::Fragment),
        Entry::draw("vs_volume", Stage::Vertex),
        Entry::draw("fs_mark", Stage::Fragment),
        Entry::draw("fs_shade", Stage::Fragment),
    ],
    zeroed: &[],
};

/// [`LIGHT_VOLUMES`] reading KZ2's G-buffer preset (with feature `kz2_gbuffer`).
pub(crate) const LIGHT_VOLUMES_KZ2: Pass = Pass {
    groups: &[
        LIGHT_VOLUMES.groups[0],
        Group {
            name: "gbuffer",
            bindings: &KZ2_LOAD_BINDINGS,
        },
    ],
    features: &["kz2_gbuffer", "spot_shadows", "no_specular"],
    ..LIGHT_VOLUMES
};

/// The unit volume mesh: an icosahedron subdivided once (42 vertices, 80 faces, wound
/// counter-clockwise seen from outside), scaled so that every face's plane lies at least 1
/// from the origin: it encloses the unit sphere. Returns the positions and the indices.
pub(crate) fn unit_volume_mesh() -> (Vec<[f32; 3]>, Vec<u16>) {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut v: Vec<glam::DVec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .into_iter()
    .map(|(x, y, z)| glam::DVec3::new(x, y, z).normalize())
    .collect();
    let faces: [[u16; 3]; 20] = [
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    // One midpoint per edge, shared by the edge's two faces.
    let mut midpoints = std::collections::HashMap::new();
    let mut midpoint = |a: u16, b: u16, v: &mut Vec<glam::DVec3>| -> u16 {
        *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
            v.push((v[a as usize] + v[b as usize]).normalize());
            (v.len() - 1) as u16
        })
    };
    let mut indices = Vec::with_capacity(80 * 3);
    for [a, b, c] in faces {
        let ab = midpoint(a, b, &mut v);
        let bc = midpoint(b, c, &mut v);
        let ca = midpoint(c, a, &mut v);
        for tri in [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]] {
            let [p, q, r] = tri.map(|i| v[i as usize]);
            // Outward: counter-clockwise seen from outside.
            if (q - p).cross(r - p).dot(p + q + r) > 0.0 {
                indices.extend(tri);
            } else {
                indices.extend([tri[0], tri[2], tri[1]]);
            }
        }
    }
    let inradius = indices
        .chunks_exact(3)
        .map(|t| {
            let [p, q, r] = [t[0], t[1], t[2]].map(|i| v[i as usize]);
            (q - p).cross(r - p).normalize().dot(p)
        })
        .fold(f64::INFINITY, f64::min);
    // A hair more than 1 / inradius, so that f32 rounding keeps every plane outside.
    let scale = 1.0 / inradius * (1.0 + 1e-5);
    let positions = v
        .iter()
        .map(|p| (*p * scale).as_vec3().to_array())
        .collect();
    (positions, indices)
}

/// How far the unit mesh reaches from its centre (its vertices' radius).
pub(crate) fn unit_volume_reach(positions: &[[f32; 3]]) -> f32 {
    positions
        .iter()
        .map(|p| Vec3::from_array(*p).length())
        .fold(0.0, f32::max)
}

/// The pipelines' depth-stencil format as declared; [`depth_stencil`] replaces it with
/// the device's when they are built.
const DS: DepthFormat = DepthFormat::Depth24PlusStencil8;

/// Stencil untouched (both faces keep, always pass).
const KEEP: Stencil = Stencil::both(StencilFace::KEEP);

/// The unit mesh's positions (`vs_volume`'s `@location(0)`).
const VOLUME_BUFFERS: &[VertexBuffer<'static>] = &[VertexBuffer {
    stride: 12,
    per_instance: false,
    attributes: &[Attribute {
        format: VertexFormat::Float32x3,
        offset: 0,
        location: 0,
    }],
}];

/// The frame's depth copied into the depth-stencil target (full-screen triangle). Its
/// colour target, where attached, is the accumulation, untouched.
pub(crate) const COPY_DEPTH: Raster<'static> =
    Raster::new("light volumes: depth copy", "vs_full_screen")
        .fragment("fs_copy_depth")
        .primitive(GEOMETRY)
        .cull(None)
        .depth(Depth::test(DS, Compare::Always, true).stencil(KEEP));

/// Back faces behind the scene mark stencil (reversed Z: "behind the scene" is `Less`).
/// Its colour target, where attached, is the accumulation, untouched.
pub(crate) const MARK: Raster<'static> = Raster::new("light volumes: stencil mark", "vs_volume")
    .fragment("fs_mark")
    .buffers(VOLUME_BUFFERS)
    .primitive(GEOMETRY)
    .cull(Some(Face::Front))
    .depth(
        Depth::test(DS, Compare::Less, false).stencil(Stencil::both(StencilFace::new(
            Compare::Always,
            StencilOp::Replace,
            StencilOp::Keep,
        ))),
    );

/// Front faces in front of or at the scene (`GreaterEqual`) where stencil is set shade,
/// added into the accumulation, and clear it.
pub(crate) const SHADE: Raster<'static> = MARK
    .named("light volumes: shade")
    .fragment("fs_shade")
    .cull(Some(Face::Back))
    .depth(
        Depth::test(DS, Compare::GreaterEqual, false).stencil(Stencil::both(StencilFace::new(
            Compare::Equal,
            StencilOp::Zero,
            StencilOp::Zero,
        ))),
    );

/// The eye inside the mesh: back faces behind the scene shade alone, no stencil.
pub(crate) const INSIDE: Raster<'static> = MARK
    .named("light volumes: shade from inside")
    .fragment("fs_shade")
    .depth(Depth::test(DS, Compare::Less, false).stencil(KEEP));

/// KZ2's conditional rendering emulated: the same draws with the same tests, depth and
/// stencil only (no colour target), so that an occlusion query counts exactly the pixels
/// the shading would run on.
pub(crate) const TEST_COPY: Raster<'static> = COPY_DEPTH.named("light volume tests: depth copy");

/// The test pass's stencil mark.
pub(crate) const TEST_MARK: Raster<'static> = MARK.named("light volume tests: stencil mark");

/// The test pass's counted front faces (the shade's tests, stencil reset as it does).
pub(crate) const TEST_COUNT: Raster<'static> =
    SHADE.named("light volume tests: count").fragment("fs_mark");

/// The test pass's counted inside draw.
pub(crate) const TEST_INSIDE: Raster<'static> = INSIDE
    .named("light volume tests: count from inside")
    .fragment("fs_mark");

/// The composer features of KZ2's light-shader permutation over the G-buffer of `layout`:
/// without the specular term unless `specular`, with the spot shadow code if `shadowed`.
fn permutation(layout: GBufferLayout, specular: bool, shadowed: bool) -> Vec<&'static str> {
    let mut features = crate::gbuffer::features(layout).to_vec();
    if shadowed {
        features.push("spot_shadows");
    }
    if !specular {
        features.push("no_specular");
    }
    features
}

/// The pass's pipelines and the unit mesh.
pub(crate) struct LightVolumes {
    layouts: Layouts,
    load: &'static [Binding; 4],
    copy_depth: wgpu::RenderPipeline,
    mark: wgpu::RenderPipeline,
    /// Shading from outside and from inside, KZ2's light-shader permutations: indexed
    /// `[specular][shadowed]`, without and with the specular term, without and with the
    /// spot shadow code.
    shade: [[wgpu::RenderPipeline; 2]; 2],
    inside: [[wgpu::RenderPipeline; 2]; 2],
    /// The test pass's (no colour target): the depth copy, the mark, the counted front
    /// faces (the shade's tests, stencil reset as it does), the counted inside draw.
    test_copy: wgpu::RenderPipeline,
    test_mark: wgpu::RenderPipeline,
    test_count: wgpu::RenderPipeline,
    test_inside: wgpu::RenderPipeline,
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
    /// How far the unit mesh reaches (its vertices' radius).
    pub reach: f32,
}

impl LightVolumes {
    /// The pipelines over the G-buffer of `layout`.
    pub(crate) fn new(device: &wgpu::Device, layout: GBufferLayout) -> Result<Self> {
        use wgpu::util::DeviceExt;
        let (description, load) = match layout {
            GBufferLayout::Kz2 => (&LIGHT_VOLUMES_KZ2, &KZ2_LOAD_BINDINGS),
            GBufferLayout::Octahedral => (&LIGHT_VOLUMES, &LOAD_BINDINGS),
        };
        // KZ2's light-shader permutations, [specular][shadowed], sharing one set of
        // layouts; the mark and the depth copy shade nothing: the plain one.
        let plain = RasterPass::new(device, description, &permutation(layout, true, false), &[])?;
        let variant =
            |specular, shadowed| plain.variant(device, &permutation(layout, specular, shadowed));
        let others = [
            variant(false, false)?,
            variant(false, true)?,
            variant(true, true)?,
        ];
        let passes = [[&others[0], &others[1]], [&plain, &others[2]]];
        let ds = depth_stencil(device);
        let accumulation = accumulation(device);
        let untouched = [Target::untouched(accumulation)];
        let add = [Target::additive(accumulation)];
        let make = |pass: &RasterPass, r: Raster<'static>, targets: &[Target]| {
            pass.pipeline(device, &r.targets(targets).depth_format(ds))
        };
        let permutations = |r: Raster<'static>| -> Result<[[wgpu::RenderPipeline; 2]; 2]> {
            let [[a, b], [c, d]] = passes;
            Ok([
                [make(a, r, &add)?, make(b, r, &add)?],
                [make(c, r, &add)?, make(d, r, &add)?],
            ])
        };
        let copy_depth = make(&plain, COPY_DEPTH, &untouched)?;
        let mark = make(&plain, MARK, &untouched)?;
        let shade = permutations(SHADE)?;
        let inside = permutations(INSIDE)?;
        let test_copy = make(&plain, TEST_COPY, &[])?;
        let test_mark = make(&plain, TEST_MARK, &[])?;
        let test_count = make(&plain, TEST_COUNT, &[])?;
        let test_inside = make(&plain, TEST_INSIDE, &[])?;
        let layouts = plain.layouts.clone();
        let (positions, indices) = unit_volume_mesh();
        let reach = unit_volume_reach(&positions);
        let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("light volume mesh vertices"),
            contents: bytemuck::cast_slice(&positions),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let index_count = indices.len() as u32;
        let indices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("light volume mesh indices"),
            contents: bytemuck::cast_slice(&indices),
            usage: wgpu::BufferUsages::INDEX,
        });
        Ok(Self {
            layouts,
            load,
            copy_depth,
            mark,
            shade,
            inside,
            test_copy,
            test_mark,
            test_count,
            test_inside,
            vertices,
            indices,
            index_count,
            reach,
        })
    }

    /// Indices of the unit volume mesh (every volume draw's count).
    pub(crate) fn index_count(&self) -> u32 {
        self.index_count
    }

    /// The groups: the frame's uniforms, depth target and lights, the volume rows, and the
    /// G-buffer.
    pub(crate) fn groups(
        &self,
        device: &wgpu::Device,
        targets: &crate::resources::targets::Targets,
        frame: &wgpu::Buffer,
        local: &wgpu::Buffer,
        lights: &wgpu::Buffer,
        volumes: &wgpu::Buffer,
    ) -> Result<Groups> {
        Ok(Groups {
            volume: self.layouts.bind_group(
                device,
                "volume",
                &[
                    ("frame", frame.as_entire_binding()),
                    (
                        "depth_texture",
                        wgpu::BindingResource::TextureView(&targets.depth_view),
                    ),
                    ("local", local.as_entire_binding()),
                    ("lights", lights.as_entire_binding()),
                    ("volumes", volumes.as_entire_binding()),
                ]
                .into_iter()
                .chain(targets.spot_shadows.resources())
                .collect::<Vec<_>>(),
            )?,
            gbuffer: self.layouts.bind_group(
                device,
                "gbuffer",
                &crate::gbuffer::resources(self.load, &targets.gbuffer_views),
            )?,
        })
    }

    /// Records the test pass of KZ2's conditional rendering ([`super::conditional`]): the
    /// depth copy into the depth-stencil target (kept for [`LightVolumes::record`]), then
    /// per tested light the draws its shading would make, its shading draw inside
    /// occlusion query `test`. Records nothing without tests.
    pub(crate) fn record_tests(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
    ) {
        let (Some(g), Some(c)) = (&f.groups.light_volumes, f.conditional) else {
            return;
        };
        if c.plan.tests.is_empty() {
            return;
        }
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("light volume tests"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &f.targets.light_volumes.depth_stencil_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0),
                    store: wgpu::StoreOp::Discard,
                }),
            }),
            timestamp_writes: timer.render("light volume tests"),
            occlusion_query_set: Some(&c.queries),
            multiview_mask: None,
        });
        pass.set_bind_group(0, &g.volume, &[]);
        pass.set_bind_group(1, &g.gbuffer, &[]);
        pass.set_pipeline(&self.test_copy);
        pass.draw(0..3, 0..1);
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint16);
        pass.set_stencil_reference(1);
        let n = self.index_count;
        for (test, &draw) in c.plan.tests.iter().enumerate().take(MAX_TESTS as usize) {
            let Some(d) = f.volumes.get(draw as usize) else {
                // A plan never points past the draws; an empty query counts nothing.
                pass.begin_occlusion_query(test as u32);
                pass.end_occlusion_query();
                continue;
            };
            let instance = d.volume..d.volume + 1;
            if d.inside {
                pass.set_pipeline(&self.test_inside);
            } else {
                pass.set_pipeline(&self.test_mark);
                pass.draw_indexed(0..n, 0, instance.clone());
                pass.set_pipeline(&self.test_count);
            }
            pass.begin_occlusion_query(test as u32);
            pass.draw_indexed(0..n, 0, instance);
            pass.end_occlusion_query();
        }
    }

    /// Records the depth copy and `draws` into the accumulation target (cleared first).
    /// Records nothing without draws (lighting then does not read the accumulation). With
    /// KZ2's conditional rendering emulated and lights tested this frame, the depth copy is
    /// the test pass's, and each tested light is drawn through the arguments its test
    /// wrote (no instance where it covers no pixel).
    pub(crate) fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
    ) {
        let Some(g) = &f.groups.light_volumes else {
            return;
        };
        if f.volumes.is_empty() {
            return;
        }
        let tested = f.conditional.filter(|c| !c.plan.tests.is_empty());
        let t = &f.targets.light_volumes;
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("light volumes"),
            color_attachments: &[cleared_color(&t.accumulation_view)],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &t.depth_stencil_view,
                depth_ops: Some(wgpu::Operations {
                    load: if tested.is_some() {
                        wgpu::LoadOp::Load
                    } else {
                        wgpu::LoadOp::Clear(0.0)
                    },
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0),
                    store: wgpu::StoreOp::Discard,
                }),
            }),
            timestamp_writes: timer.render("light volumes"),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, &g.volume, &[]);
        pass.set_bind_group(1, &g.gbuffer, &[]);
        if tested.is_none() {
            pass.set_pipeline(&self.copy_depth);
            pass.draw(0..3, 0..1);
        }
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint16);
        pass.set_stencil_reference(1);
        let n = self.index_count;
        for (k, d) in f.volumes.iter().enumerate() {
            let instance = d.volume..d.volume + 1;
            let (specular, shadowed) = (usize::from(d.specular), usize::from(d.map.is_some()));
            // A tested light: its test's arguments, one instance or none.
            let args = tested.and_then(|c| {
                let test = (*c.plan.draw_test.get(k)?)?;
                (test < MAX_TESTS).then_some((c, u64::from(test) * DRAW_BYTES))
            });
            let draw = |pass: &mut wgpu::RenderPass<'_>| match args {
                Some((c, offset)) => pass.draw_indexed_indirect(&c.volume_args, offset),
                None => pass.draw_indexed(0..n, 0, instance.clone()),
            };
            if d.inside {
                pass.set_pipeline(&self.inside[specular][shadowed]);
                draw(&mut pass);
            } else {
                pass.set_pipeline(&self.mark);
                draw(&mut pass);
                pass.set_pipeline(&self.shade[specular][shadowed]);
                draw(&mut pass);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shader::Format;
    use shadercheck::{Caps, assert_struct_layout, members};

    #[test]
    fn description_matches_its_module() {
        shadercheck::check_pass(&LIGHT_VOLUMES, |_| Caps::CORE);
        // KZ2's no-specular permutation: the shading calls no GGX term; the other one
        // calls it, behind the light's flag.
        let shading = |features: &[&str]| {
            let src = LIGHT_VOLUMES.source(features).unwrap();
            let start = src.find("fn light_shading_local(").unwrap();
            let end = src[start..].find("\n}").unwrap();
            src[start..start + end].to_string()
        };
        assert!(!shading(&["no_specular"]).contains("light_shading_surface_specular("));
        let with = shading(&[]);
        assert!(
            with.contains("light_shading_surface_specular(")
                && with.contains("deferred_light_has_specular(l)")
        );
        shadercheck::check_pass_with(&LIGHT_VOLUMES_KZ2, &["kz2_gbuffer"], |_| Caps::CORE);
        let m = shadercheck::assert_composed(LIBRARY, LIGHT_VOLUMES.module, &[], Caps::CORE);
        assert_struct_layout(
            &m,
            "GpuLightVolume",
            size_of::<GpuLightVolume>(),
            &members!(GpuLightVolume { sphere, light, pad }),
        );
    }

    /// Every pipeline against every permutation of both G-buffer layouts: the shading ones
    /// with their accumulation target, the copy and mark with theirs or none, the tests
    /// with none.
    #[test]
    fn pipelines_match_their_modules() {
        let add = [Target::additive(Format::Rgba16Float)];
        let untouched = [Target::untouched(Format::Rgba16Float)];
        for layout in GBufferLayout::ALL {
            let pass = match layout {
                GBufferLayout::Kz2 => &LIGHT_VOLUMES_KZ2,
                GBufferLayout::Octahedral => &LIGHT_VOLUMES,
            };
            for (specular, shadowed) in [(false, false), (false, true), (true, false), (true, true)]
            {
                let f = permutation(layout, specular, shadowed);
                for r in [SHADE, INSIDE] {
                    let r = r.targets(&add);
                    shadercheck::check_raster(pass, &r, &f, Caps::CORE);
                }
            }
            let f = permutation(layout, true, false);
            for r in [COPY_DEPTH, MARK] {
                let r = r.targets(&untouched);
                shadercheck::check_raster(pass, &r, &f, Caps::CORE);
            }
            for r in [TEST_COPY, TEST_MARK, TEST_COUNT, TEST_INSIDE] {
                shadercheck::check_raster(pass, &r, &f, Caps::CORE);
            }
        }
    }

    /// The mesh is closed (every edge in exactly two faces, once each way), wound outwards,
    /// and encloses the unit sphere: every face's plane at least 1 from the centre, in f64
    /// over the f32 positions the GPU gets.
    #[test]
    fn unit_mesh_is_closed_outward_and_encloses_the_unit_sphere() {
        let (p, idx) = unit_volume_mesh();
        assert_eq!((p.len(), idx.len()), (42, 240));
        let v = |i: u16| glam::DVec3::from_array(p[i as usize].map(f64::from));
        let mut edges = std::collections::HashMap::new();
        for t in idx.chunks_exact(3) {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                *edges.entry((a, b)).or_insert(0) += 1;
            }
            let n = (v(t[1]) - v(t[0])).cross(v(t[2]) - v(t[0])).normalize();
            let plane = n.dot(v(t[0]));
            assert!(plane >= 1.0, "face {t:?} plane at {plane}");
            assert!(
                n.dot(v(t[0]) + v(t[1]) + v(t[2])) > 0.0,
                "face {t:?} inward"
            );
        }
        for (&(a, b), &k) in &edges {
            assert_eq!(k, 1, "edge {a}-{b} used {k} times one way");
            assert_eq!(edges.get(&(b, a)), Some(&1), "edge {a}-{b} open");
        }
        let reach = unit_volume_reach(&p);
        assert!((1.0..1.3).contains(&reach), "reach {reach}");
    }
}
