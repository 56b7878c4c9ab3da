//! Deferred lighting in compute (`gpu::lighting`): KZ2's sun (its slice of the shadow
//! maps with the slice's PCF radius, and the G-buffer's baked term), ambient and local
//! lights over the G-buffer, tone mapped into the sRGB-encoded output image. The same pass
//! ends both the deferred and the baseline frames. Local lights come from each tile's list
//! ([`super::lights`]), shadowed spots through their maps ([`crate::spot_shadows`]);
//! feature `all_lights` tests every light at every pixel instead (the reference the tiled
//! image equals, and the baseline of its measurements); feature `light_volumes` adds the
//! stencil volumes' accumulation ([`super::light_volumes`]).

use shader::pipeline::ComputePass;
use shader::{Binding, Dim, Entry, Format, Group, Kind, Pass, Sample};

use super::lights::LightBuffers;
use super::{FrameContext, LIBRARY};
use crate::error::Result;
use crate::gbuffer::{KZ2_LOAD_BINDINGS, LOAD_BINDINGS};
use crate::resources::rows::FrameUniforms;
use crate::resources::targets::Targets;
use crate::timing::GpuTimer;
use bytemuck::{Pod, Zeroable};
use deferred::DeferredLight;
use deferred::GBufferLayout;

/// What lighting needs of the local lights besides the lights (WGSL `GpuLocalLights`),
/// 80 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct GpuLocalLights {
    /// Camera-relative world to view space: the camera's rotation.
    pub view_rotation: [[f32; 4]; 4],
    /// Light tiles across and down.
    pub tiles: [u32; 2],
    /// Zero.
    pub pad: [u32; 2],
}

// The tiled path stages a tile's list with one load per invocation.
const _: () = assert!(
    deferred::lights::MAX_LIGHTS_PER_TILE
        == deferred::lights::TILE_SIZE * deferred::lights::TILE_SIZE
);

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
                Binding::new(
                    "depth_texture",
                    Kind::Texture {
                        sample: Sample::Depth,
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

/// The lighting pipelines: without and with the stencil volumes' accumulation.
pub(crate) struct Lighting {
    load: &'static [Binding; 4],
    pass: ComputePass<[u32; 2]>,
    with_volumes: Option<ComputePass<[u32; 2]>>,
}

/// The renderer's bind groups for lighting (they change only when the light buffer grows).
pub(crate) struct Groups {
    pub frame: wgpu::BindGroup,
    pub gbuffer: wgpu::BindGroup,
}

impl Lighting {
    /// For `paths`: tiled, or every light at every pixel; the variant adding the volumes'
    /// accumulation where some light may take a volume.
    pub(crate) fn new(
        device: &wgpu::Device,
        paths: crate::LightPaths,
        layout: GBufferLayout,
    ) -> Result<Self> {
        let (pass, load) = match layout {
            GBufferLayout::Kz2 => (&LIGHTING_KZ2, &KZ2_LOAD_BINDINGS),
            GBufferLayout::Octahedral => (&LIGHTING, &LOAD_BINDINGS),
        };
        let mut features = crate::gbuffer::features(layout).to_vec();
        if paths == crate::LightPaths::EveryPixel {
            features.push("all_lights");
        }
        let mut volume_features = crate::gbuffer::features(layout).to_vec();
        volume_features.push("light_volumes");
        Ok(Self {
            load,
            pass: ComputePass::new(device, pass, &features, &[])?,
            with_volumes: if paths.volumes() {
                Some(ComputePass::new(device, pass, &volume_features, &[])?)
            } else {
                None
            },
        })
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
        Ok(Groups {
            frame: self.pass.bind_group(
                device,
                "frame",
                &[
                    ("frame", frame.as_entire_binding()),
                    (
                        "depth_texture",
                        wgpu::BindingResource::TextureView(&targets.depth_view),
                    ),
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
                        wgpu::BindingResource::TextureView(
                            &targets.light_volumes.accumulation_view,
                        ),
                    ),
                ]
                .into_iter()
                .chain(targets.spot_shadows.resources())
                .collect::<Vec<_>>(),
            )?,
            gbuffer: self.pass.bind_group(
                device,
                "gbuffer",
                &crate::gbuffer::resources(self.load, &targets.gbuffer_views),
            )?,
        })
    }

    /// Records lighting and tone mapping into the output image.
    pub(crate) fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("lighting"),
            timestamp_writes: timer.compute("lighting"),
        });
        let g = &f.groups.lighting;
        let pass_variant = match &self.with_volumes {
            Some(v) if !f.volumes.is_empty() => v,
            _ => &self.pass,
        };
        pass_variant.record(
            &mut pass,
            &[&g.frame, &g.gbuffer],
            &[f.targets.width, f.targets.height],
        );
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
