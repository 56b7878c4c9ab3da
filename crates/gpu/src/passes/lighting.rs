//! Deferred lighting in compute (`gpu::lighting`): KZ2's sun (its slice of the shadow
//! maps with the slice's PCF radius, and the G-buffer's baked term), ambient and local
//! lights over the G-buffer, tone mapped into the sRGB-encoded output image. The same pass
//! ends both the deferred and the baseline frames. Local lights come from each tile's list
//! ([`super::lights`]), shadowed spots through their maps ([`crate::spot_shadows`]);
//! feature `all_lights` tests every light at every pixel instead (the reference the tiled
//! image equals, and the baseline of its measurements); feature `light_volumes` adds the
//! stencil volumes' accumulation (the light volumes pass). With MSAA on, the baseline's
//! frame takes [`LIGHTING_MSAA`]: its multisampled G-buffer resolved by KZ2's tricks
//! (interior pixels lit once, edge pixels appended to a list and lit per sample by an
//! indirect dispatch with the PCF taps split across the samples) or, for measurement,
//! every sample lit.

use shader::pipeline::ComputePass;
use shader::{Binding, Dim, Dispatch, Entry, Format, Group, Kind, Pass, Sample, Stage};

use super::context::FrameContext;
use crate::error::Result;
use crate::gbuffer::{
    KZ2_LOAD_BINDINGS, KZ2_MSAA_LOAD_BINDINGS, LOAD_BINDINGS, MSAA_LOAD_BINDINGS,
};
pub(crate) use crate::resources::groups::LightingGroups as Groups;
use crate::resources::lights::GpuLocalLights;
use crate::resources::lights::LightBuffers;
use crate::resources::rows::FrameUniforms;
use crate::resources::targets::Targets;
use crate::shaders::LIBRARY;
use crate::timing::GpuTimer;
use bytemuck::{Pod, Zeroable};
use deferred::DeferredLight;
use deferred::GBufferLayout;

// The tiled path stages a tile's list with one load per invocation.
const _: () = assert!(
    deferred::lights::MAX_LIGHTS_PER_TILE
        == deferred::lights::TILE_SIZE * deferred::lights::TILE_SIZE
);

/// Taps of the PCF kernels of every radius 0..=[`MAX_PCF_RADIUS`](crate::shadows::MAX_PCF_RADIUS):
/// (2r + 1)² each.
pub(crate) const PCF_SPLIT_TAPS: usize = 1 + 9 + 25;

/// KZ2's PCF tap split for 4x MSAA (WGSL `GpuPcfSplit`), 656 bytes: per radius r, the
/// (2r + 1)² box kernel split into per-sample subsets by
/// [`deferred::msaa::split_taps`] (radius 0's single tap goes to every sample).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub(crate) struct GpuPcfSplit {
    /// Per radius, per sample: its first tap in `taps`.
    pub first: [[u32; 4]; 3],
    /// Per radius, per sample: its tap count.
    pub count: [[u32; 4]; 3],
    /// The taps, per radius, sorted by sample.
    pub taps: [deferred::msaa::DeferredPcfTap; PCF_SPLIT_TAPS],
}

const _: () = assert!(crate::shadows::MAX_PCF_RADIUS == 2 && crate::config::MSAA_SAMPLES == 4);

impl GpuPcfSplit {
    /// The split of every radius's box kernel.
    pub(crate) fn new() -> Self {
        let mut out = Self::zeroed();
        let mut at = 0usize;
        for r in 0..=crate::shadows::MAX_PCF_RADIUS as usize {
            let side = 2 * r as u32 + 1;
            let kernel: Vec<_> = deferred::msaa::box_kernel(side).collect();
            match deferred::msaa::split_taps(&kernel, deferred::msaa::SampleCount::X4) {
                Ok(split) => {
                    out.taps[at..at + split.taps().len()].copy_from_slice(split.taps());
                    for (s, &(first, count)) in split.ranges().iter().enumerate() {
                        out.first[r][s] = at as u32 + first;
                        out.count[r][s] = count;
                    }
                }
                // Fewer taps than samples (radius 0): every sample takes them all.
                Err(_) => {
                    for (i, &(o, _)) in kernel.iter().enumerate() {
                        out.taps[at + i] = deferred::msaa::DeferredPcfTap {
                            offset: o.into(),
                            weight: 1.0 / kernel.len() as f32,
                            sample: 0,
                        };
                    }
                    out.first[r] = [at as u32; 4];
                    out.count[r] = [kernel.len() as u32; 4];
                }
            }
            at += kernel.len();
        }
        out
    }
}

/// Lighting, over the image (`[width, height]`).
pub(crate) const LIGHTING: Pass<[u32; 2]> = Pass {
    name: "lighting",
    module: "gpu::lighting",
    library: LIBRARY,
    features: &["all_lights", "light_volumes"],
    groups: &[
        Group {
            name: "frame",
            bindings: &[
                Binding::new("frame", Kind::uniform(size_of::<FrameUniforms>())),
                // Targets::depth_float (the multisampled variant binds the depth itself).
                Binding::new(
                    "depth_texture",
                    Kind::Texture {
                        sample: Sample::Float { filterable: false },
                        dim: Dim::D2,
                    },
                ),
                Binding::new("local", Kind::uniform(size_of::<GpuLocalLights>())),
                Binding::new("lights", Kind::read(size_of::<DeferredLight>())),
                Binding::new("light_counts", Kind::read(4)),
                Binding::new("light_indices", Kind::read(4)),
                Binding::new(
                    "shadow_map",
                    Kind::Texture {
                        sample: Sample::Depth,
                        dim: Dim::D2Array,
                    },
                ),
                Binding::new(
                    "sun_shadow",
                    Kind::uniform(size_of::<crate::shadows::GpuSunShadow>()),
                ),
                Binding::new("output", Kind::storage_texture_2d(Format::Rgba8Unorm)),
                Binding::new(
                    "light_accumulation",
                    Kind::texture_2d(Sample::Float { filterable: false }),
                ),
                crate::spot_shadows::MAP_BINDING,
                crate::spot_shadows::ROWS_BINDING,
            ],
        },
        Group {
            name: "gbuffer",
            bindings: &LOAD_BINDINGS,
        },
    ],
    entries: &[Entry::grid(
        "main",
        deferred::lights::TILE_SIZE,
        deferred::lights::TILE_SIZE,
        |size| *size,
    )],
    zeroed: &[],
};

/// [`LIGHTING`] reading KZ2's G-buffer preset (with feature `kz2_gbuffer`).
pub(crate) const LIGHTING_KZ2: Pass<[u32; 2]> = Pass {
    groups: &[
        LIGHTING.groups[0],
        Group {
            name: "gbuffer",
            bindings: &KZ2_LOAD_BINDINGS,
        },
    ],
    features: &["kz2_gbuffer", "all_lights", "light_volumes"],
    ..LIGHTING
};

/// The group [`LIGHTING_WATER`] adds: the HDR colour the water refracts.
const WATER_GROUP: Group = Group {
    name: "water",
    bindings: &[Binding::new(
        "scene_hdr",
        Kind::storage_texture_2d(Format::Rgba16Float),
    )],
};

/// [`LIGHTING`] in a frame with FC5's water (feature `water`): the colour before tone
/// mapping kept in `scene_hdr` too.
pub(crate) const LIGHTING_WATER: Pass<[u32; 2]> = Pass {
    groups: &[LIGHTING.groups[0], LIGHTING.groups[1], WATER_GROUP],
    features: &["water", "all_lights", "light_volumes"],
    ..LIGHTING
};

/// [`LIGHTING_KZ2`] with the water's HDR colour.
pub(crate) const LIGHTING_KZ2_WATER: Pass<[u32; 2]> = Pass {
    groups: &[LIGHTING_KZ2.groups[0], LIGHTING_KZ2.groups[1], WATER_GROUP],
    features: &["water", "kz2_gbuffer", "all_lights", "light_volumes"],
    ..LIGHTING
};

/// The bindings [`LIGHTING_MSAA`] adds to the frame group.
const MSAA_FRAME_BINDINGS: [Binding; 14] = {
    let b = LIGHTING.groups[0].bindings;
    [
        b[0],
        Binding::new(
            "depth_texture",
            Kind::Texture {
                sample: Sample::Depth,
                dim: Dim::D2Multisampled,
            },
        ),
        b[2],
        b[3],
        b[4],
        b[5],
        b[6],
        b[7],
        b[8],
        b[9],
        b[10],
        b[11],
        Binding::new("pcf_split", Kind::uniform(size_of::<GpuPcfSplit>())),
        // The header and one edge pixel.
        Binding::new(
            "msaa_edges",
            Kind::read_write(crate::resources::targets::MSAA_EDGES_HEADER as usize + 4),
        ),
    ]
};

/// The entry points of [`LIGHTING_MSAA`]: the pixels, the edge count as indirect
/// arguments, the edges per sample.
const MSAA_ENTRIES: &[Entry<[u32; 2]>] = &[
    Entry::grid(
        "main",
        deferred::lights::TILE_SIZE,
        deferred::lights::TILE_SIZE,
        |size| *size,
    ),
    Entry::once("edge_args", 1),
    Entry {
        name: "edges",
        stage: Stage::compute(64, 1, 1),
        dispatch: Dispatch::Indirect("msaa_edges"),
    },
];

/// [`LIGHTING`] over the baseline's multisampled G-buffer and depth (feature `msaa`; with
/// `msaa_every_sample`, every sample lit; `subgroups`: the edge appends per subgroup).
pub(crate) const LIGHTING_MSAA: Pass<[u32; 2]> = Pass {
    groups: &[
        Group {
            name: "frame",
            bindings: &MSAA_FRAME_BINDINGS,
        },
        Group {
            name: "gbuffer",
            bindings: &MSAA_LOAD_BINDINGS,
        },
    ],
    features: &["msaa", "all_lights", "msaa_every_sample", "subgroups"],
    entries: MSAA_ENTRIES,
    ..LIGHTING
};

/// [`LIGHTING_MSAA`] reading KZ2's G-buffer preset.
pub(crate) const LIGHTING_KZ2_MSAA: Pass<[u32; 2]> = Pass {
    groups: &[
        LIGHTING_MSAA.groups[0],
        Group {
            name: "gbuffer",
            bindings: &KZ2_MSAA_LOAD_BINDINGS,
        },
    ],
    features: &[
        "msaa",
        "kz2_gbuffer",
        "all_lights",
        "msaa_every_sample",
        "subgroups",
    ],
    ..LIGHTING_MSAA
};

/// The lighting pipelines: without and with the stencil volumes' accumulation, and the
/// baseline's MSAA variant.
pub(crate) struct Lighting {
    load: &'static [Binding; 4],
    pass: ComputePass<[u32; 2]>,
    with_volumes: Option<ComputePass<[u32; 2]>>,
    msaa: Option<MsaaLighting>,
    /// The water variants (without and with the volumes' accumulation), made when a water
    /// scene is first set, and what they are made from.
    water: Option<WaterVariants>,
    water_pass: &'static Pass<[u32; 2]>,
    features: Vec<&'static str>,
    volume_features: Option<Vec<&'static str>>,
}

/// The water variants of lighting: without and with the volumes' accumulation.
type WaterVariants = (ComputePass<[u32; 2]>, Option<ComputePass<[u32; 2]>>);

/// The MSAA variant: its pipelines, its lighting mode and the tap split.
struct MsaaLighting {
    load: &'static [Binding; 4],
    pass: ComputePass<[u32; 2]>,
    mode: crate::config::MsaaLighting,
    pcf_split: wgpu::Buffer,
}

impl Lighting {
    /// For `paths`: tiled, or every light at every pixel; the variant adding the volumes'
    /// accumulation where some light may take a volume; with `msaa`, the baseline's MSAA
    /// variant (`subgroups`: the device's subgroups aggregate its edge appends).
    pub(crate) fn new(
        device: &wgpu::Device,
        paths: crate::config::LightPaths,
        layout: GBufferLayout,
        msaa: Option<crate::config::MsaaLighting>,
        subgroups: bool,
    ) -> Result<Self> {
        let (pass, load) = match layout {
            GBufferLayout::Kz2 => (&LIGHTING_KZ2, &KZ2_LOAD_BINDINGS),
            GBufferLayout::Octahedral => (&LIGHTING, &LOAD_BINDINGS),
        };
        let mut features = crate::gbuffer::features(layout).to_vec();
        if paths == crate::config::LightPaths::EveryPixel {
            features.push("all_lights");
        }
        let mut volume_features = crate::gbuffer::features(layout).to_vec();
        volume_features.push("light_volumes");
        let msaa = match msaa {
            Some(mode) => {
                let (pass, load) = match layout {
                    GBufferLayout::Kz2 => (&LIGHTING_KZ2_MSAA, &KZ2_MSAA_LOAD_BINDINGS),
                    GBufferLayout::Octahedral => (&LIGHTING_MSAA, &MSAA_LOAD_BINDINGS),
                };
                let mut f = features.clone();
                f.push("msaa");
                if mode == crate::config::MsaaLighting::EverySample {
                    f.push("msaa_every_sample");
                }
                if subgroups {
                    f.push("subgroups");
                }
                use wgpu::util::DeviceExt;
                let split = GpuPcfSplit::new();
                Some(MsaaLighting {
                    load,
                    pass: ComputePass::new(device, pass, &f, &[])?,
                    mode,
                    pcf_split: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                        label: Some("msaa pcf split"),
                        contents: bytemuck::bytes_of(&split),
                        usage: wgpu::BufferUsages::UNIFORM,
                    }),
                })
            }
            None => None,
        };
        Ok(Self {
            msaa,
            load,
            pass: ComputePass::new(device, pass, &features, &[])?,
            with_volumes: if paths.volumes() {
                Some(ComputePass::new(device, pass, &volume_features, &[])?)
            } else {
                None
            },
            water: None,
            water_pass: match layout {
                GBufferLayout::Kz2 => &LIGHTING_KZ2_WATER,
                GBufferLayout::Octahedral => &LIGHTING_WATER,
            },
            features,
            volume_features: paths.volumes().then_some(volume_features),
        })
    }

    /// Makes the water variants (once): the same features plus `water`.
    pub(crate) fn enable_water(&mut self, device: &wgpu::Device) -> Result<()> {
        if self.water.is_some() {
            return Ok(());
        }
        let with = |f: &[&'static str]| {
            let mut f = f.to_vec();
            f.push("water");
            f
        };
        let plain = ComputePass::new(device, self.water_pass, &with(&self.features), &[])?;
        let volumes = match &self.volume_features {
            Some(v) => Some(ComputePass::new(device, self.water_pass, &with(v), &[])?),
            None => None,
        };
        self.water = Some((plain, volumes));
        Ok(())
    }

    /// The water variants' layouts, whose group `water` (2) holds the HDR target (after
    /// [`Lighting::enable_water`]).
    pub(crate) fn water_layout(&self) -> Option<&shader::pipeline::Layouts> {
        self.water.as_ref().map(|(p, _)| &p.layouts)
    }

    /// The groups over the renderer's targets, frame uniforms and light buffers.
    pub(crate) fn groups(
        &self,
        device: &wgpu::Device,
        targets: &Targets,
        frame: &wgpu::Buffer,
        local: &wgpu::Buffer,
        lights: &LightBuffers,
    ) -> Result<Groups> {
        let frame_resources = |depth| {
            [
                ("frame", frame.as_entire_binding()),
                ("depth_texture", wgpu::BindingResource::TextureView(depth)),
                ("local", local.as_entire_binding()),
                ("lights", lights.lights.as_entire_binding()),
                ("light_counts", lights.counts.as_entire_binding()),
                ("light_indices", lights.indices.as_entire_binding()),
                (
                    "shadow_map",
                    wgpu::BindingResource::TextureView(&targets.shadows.array_view),
                ),
                ("sun_shadow", targets.shadows.sun.as_entire_binding()),
                (
                    "output",
                    wgpu::BindingResource::TextureView(&targets.output_view),
                ),
                (
                    "light_accumulation",
                    wgpu::BindingResource::TextureView(&targets.light_volumes.accumulation_view),
                ),
            ]
            .into_iter()
            .chain(targets.spot_shadows.resources())
            .collect::<Vec<_>>()
        };
        let msaa = match (&self.msaa, &targets.msaa) {
            (Some(m), Some(t)) => {
                let mut r = frame_resources(&t.depth_view);
                r.push(("pcf_split", m.pcf_split.as_entire_binding()));
                r.push(("msaa_edges", t.edges.as_entire_binding()));
                Some((
                    m.pass.bind_group(device, "frame", &r)?,
                    m.pass.bind_group(
                        device,
                        "gbuffer",
                        &crate::gbuffer::resources(m.load, &t.gbuffer_views),
                    )?,
                ))
            }
            _ => None,
        };
        Ok(Groups {
            frame: self.pass.bind_group(
                device,
                "frame",
                &frame_resources(&targets.depth_float_view),
            )?,
            gbuffer: self.pass.bind_group(
                device,
                "gbuffer",
                &crate::gbuffer::resources(self.load, &targets.gbuffer_views),
            )?,
            msaa,
        })
    }

    /// Records lighting and tone mapping into the output image.
    pub(crate) fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
    ) {
        let g = &f.groups.lighting;
        let size = [f.targets.width, f.targets.height];
        if f.msaa
            && let (Some(m), Some((frame, gbuffer)), Some(t)) =
                (&self.msaa, &g.msaa, &f.targets.msaa)
        {
            // The edge count (and the arguments after it) start at 0.
            encoder.clear_buffer(&t.edges, 0, Some(16));
            let mut pass = timer.begin_compute(encoder, "lighting");
            // The pixels, then the edge count as arguments.
            m.pass.record(&mut pass, &[frame, gbuffer], &size);
            drop(pass);
            if m.mode == crate::config::MsaaLighting::Kz2
                && let Ok(edges) = m.pass.step("edges")
            {
                encoder.copy_buffer_to_buffer(&t.edges, 0, &t.edge_dispatch, 0, 12);
                let mut pass = timer.begin_compute(encoder, "msaa edges");
                pass.set_bind_group(0, frame, &[]);
                pass.set_bind_group(1, gbuffer, &[]);
                pass.set_pipeline(&edges.pipeline);
                pass.dispatch_workgroups_indirect(&t.edge_dispatch, 0);
            }
            return;
        }
        let mut pass = timer.begin_compute(encoder, "lighting");
        if let (Some(hdr), Some((plain, volumes))) = (f.water_hdr, &self.water) {
            let variant = match volumes {
                Some(v) if !f.volumes.is_empty() => v,
                _ => plain,
            };
            variant.record(&mut pass, &[&g.frame, &g.gbuffer, hdr], &size);
            return;
        }
        let pass_variant = match &self.with_volumes {
            Some(v) if !f.volumes.is_empty() => v,
            _ => &self.pass,
        };
        pass_variant.record(&mut pass, &[&g.frame, &g.gbuffer], &size);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shadercheck::{Caps, assert_struct_layout, members};

    #[test]
    fn description_matches_its_module() {
        shadercheck::check_pass(&LIGHTING, |_| Caps::CORE);
        shadercheck::check_pass_with(&LIGHTING_KZ2, &["kz2_gbuffer"], |_| Caps::CORE);
        shadercheck::check_pass_with(&LIGHTING_WATER, &["water"], |_| Caps::CORE);
        shadercheck::check_pass_with(&LIGHTING_KZ2_WATER, &["water", "kz2_gbuffer"], |_| {
            Caps::CORE
        });
        let caps = |f: &[&str]| {
            if f.contains(&"subgroups") {
                Caps::SUBGROUP
            } else {
                Caps::CORE
            }
        };
        shadercheck::check_pass_with(&LIGHTING_MSAA, &["msaa"], caps);
        shadercheck::check_pass_with(&LIGHTING_KZ2_MSAA, &["msaa", "kz2_gbuffer"], caps);
        let ms = shadercheck::assert_composed(LIBRARY, LIGHTING.module, &["msaa"], Caps::CORE);
        assert_struct_layout(
            &ms,
            "GpuPcfSplit",
            size_of::<GpuPcfSplit>(),
            &members!(GpuPcfSplit { first, count, taps }),
        );
        assert_eq!(
            shadercheck::const_u32(&ms, "GPU_PCF_SPLIT_TAPS"),
            Some(PCF_SPLIT_TAPS as u32)
        );
        assert_eq!(
            shadercheck::const_u32(&ms, "GPU_MAX_WORKGROUPS_X"),
            Some(shader::MAX_WORKGROUPS_X)
        );
        let (_, members) = shadercheck::struct_layout(&ms, "GpuMsaaEdges").unwrap();
        assert_eq!(
            members.last(),
            Some(&(
                "pixels".to_string(),
                crate::resources::targets::MSAA_EDGES_HEADER as u32
            ))
        );
        let m = shadercheck::assert_composed(LIBRARY, LIGHTING.module, &[], Caps::CORE);
        assert_struct_layout(
            &m,
            "GpuLocalLights",
            size_of::<GpuLocalLights>(),
            &members!(GpuLocalLights {
                view_rotation,
                tiles,
                pad
            }),
        );
        assert_struct_layout(
            &m,
            "GpuSunShadow",
            size_of::<crate::shadows::GpuSunShadow>(),
            &members!(crate::shadows::GpuSunShadow {
                cascades,
                count,
                resolution,
                pad,
                pcf_radius,
                slice_texels
            }),
        );
        assert_struct_layout(
            &m,
            "GpuSpotShadow",
            size_of::<crate::spot_shadows::GpuSpotShadow>(),
            &members!(crate::spot_shadows::GpuSpotShadow {
                view_to_clip,
                strength,
                texel_per_metre,
                resolution,
                pad
            }),
        );
        assert_eq!(
            shadercheck::const_u32(&m, "GPU_LIGHT_SHADOW_SLOT_SHIFT"),
            Some(crate::spot_shadows::LIGHT_SHADOW_SLOT_SHIFT)
        );
        assert_eq!(
            shadercheck::const_u32(&m, "GPU_MAX_PCF_RADIUS"),
            Some(crate::shadows::MAX_PCF_RADIUS)
        );
    }
}
