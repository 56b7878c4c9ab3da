//! Tiled local lights (KZ2's hundreds of point and spot lights): the depth target reduced
//! to per-tile depth ranges (`gpu::tile_depth`, pass 1 of `deferred`'s tiled culling),
//! then `deferred`'s light-culling pass ([`deferred::pass::LIGHT_CULL_PASS`]) writes each
//! 16x16 tile's light list, which lighting reads. Lights are uploaded in view space each
//! frame ([`crate::frame::local_light_rows`]).

use bytemuck::{Pod, Zeroable};
use deferred::lights::{DeferredLight, DeferredTileDepth, MAX_LIGHTS_PER_TILE, tile_counts};
use deferred::pass::{LIGHT_CULL_PASS, LightCullCounters, LightCullParams};
use shader::pipeline::ComputePass;
use shader::{Binding, Dim, Entry, Group, Kind, Pass, Sample};

use super::{FrameContext, LIBRARY};
use crate::error::Result;
use crate::resources::static_pool::empty_storage;
use crate::resources::targets::Targets;
use crate::timing::GpuTimer;

/// The tile-depth pass's parameters (WGSL `GpuTileDepthParams`), 16 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub(crate) struct GpuTileDepthParams {
    /// Viewport width and height in pixels.
    pub size: [u32; 2],
    /// Tiles across.
    pub tiles_x: u32,
    /// Non-zero for reversed depth.
    pub reversed: u32,
}

/// Pass 1's workgroups are TILE x TILE invocations: one per pixel of a tile.
const TILE: u32 = deferred::lights::TILE_SIZE;

/// Pass 1 over the depth target (`[width, height]`): one workgroup per 2x2 tiles.
pub(crate) const TILE_DEPTH: Pass<[u32; 2]> = Pass {
    name: "light tile depth",
    module: "gpu::tile_depth",
    library: LIBRARY,
    features: &[],
    groups: &[Group {
        name: "tiles",
        bindings: &[
            Binding::new("params", Kind::uniform(size_of::<GpuTileDepthParams>())),
            // Targets::depth_float (the multisampled variant binds the depth itself).
            Binding::new(
                "depth_texture",
                Kind::texture_2d(Sample::Float { filterable: false }),
            ),
            Binding::new(
                "tile_depths",
                Kind::read_write(size_of::<DeferredTileDepth>()),
            ),
        ],
    }],
    // One workgroup of TILE_SIZE² invocations per 2x2 tiles, an invocation a pixel of each.
    entries: &[Entry::grid("tile_depth", TILE, TILE, |size| {
        let (tx, ty) = tile_counts(size[0], size[1]);
        [tx.div_ceil(2) * TILE, ty.div_ceil(2) * TILE]
    })],
    zeroed: &[],
};

/// [`TILE_DEPTH`] over the baseline's multisampled depth (feature `msaa`): each tile's
/// range covers every sample.
pub(crate) const TILE_DEPTH_MSAA: Pass<[u32; 2]> = Pass {
    groups: &[Group {
        name: "tiles",
        bindings: &[
            TILE_DEPTH.groups[0].bindings[0],
            Binding::new(
                "depth_texture",
                Kind::Texture {
                    sample: Sample::Depth,
                    dim: Dim::D2Multisampled,
                },
            ),
            TILE_DEPTH.groups[0].bindings[2],
        ],
    }],
    features: &["msaa"],
    ..TILE_DEPTH
};

/// The light buffers of one target size: the lights (grown as needed), the per-tile depth
/// ranges and lists, the counters and the two passes' uniforms.
#[derive(Clone)]
pub(crate) struct LightBuffers {
    pub tile_params: wgpu::Buffer,
    pub cull_params: wgpu::Buffer,
    pub lights: wgpu::Buffer,
    /// The stencil volumes' rows (`GpuLightVolume`), as many as lights.
    pub volumes: wgpu::Buffer,
    pub tile_depths: wgpu::Buffer,
    pub counts: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub counters: wgpu::Buffer,
    /// Tiles across and down.
    pub tiles: [u32; 2],
    /// Lights `lights` holds.
    pub capacity: usize,
}

impl LightBuffers {
    /// Buffers for `targets` and `capacity` lights.
    pub(crate) fn new(device: &wgpu::Device, targets: &Targets, capacity: usize) -> Result<Self> {
        let (tx, ty) = tile_counts(targets.width, targets.height);
        let tiles = u64::from(tx) * u64::from(ty);
        let uniform = |label, size: usize| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let capacity = capacity.max(1);
        let (lights, volumes) = Self::light_rows(device, capacity)?;
        Ok(Self {
            tile_params: uniform("light tile depth params", size_of::<GpuTileDepthParams>()),
            cull_params: uniform("light culling params", size_of::<LightCullParams>()),
            lights,
            volumes,
            tile_depths: empty_storage(
                device,
                "light tile depths",
                tiles * size_of::<DeferredTileDepth>() as u64,
            )?,
            counts: empty_storage(device, "light tile counts", tiles * 4)?,
            indices: empty_storage(
                device,
                "light tile indices",
                tiles * u64::from(MAX_LIGHTS_PER_TILE) * 4,
            )?,
            counters: empty_storage(
                device,
                "light culling counters",
                size_of::<LightCullCounters>() as u64,
            )?,
            tiles: [tx, ty],
            capacity,
        })
    }

    /// These buffers with room for `capacity` lights: new light and volume rows, the same
    /// per-tile buffers (so what binds them outside the light passes, the compute laydown's
    /// unpack writing the tile depths, stays bound).
    pub(crate) fn with_capacity(&self, device: &wgpu::Device, capacity: usize) -> Result<Self> {
        let capacity = capacity.max(1);
        let (lights, volumes) = Self::light_rows(device, capacity)?;
        Ok(Self {
            lights,
            volumes,
            capacity,
            ..self.clone()
        })
    }

    /// The light rows and volume rows for `capacity` lights.
    fn light_rows(device: &wgpu::Device, capacity: usize) -> Result<(wgpu::Buffer, wgpu::Buffer)> {
        Ok((
            empty_storage(
                device,
                "local lights",
                (capacity * size_of::<DeferredLight>()) as u64,
            )?,
            empty_storage(
                device,
                "light volumes",
                (capacity * size_of::<super::light_volumes::GpuLightVolume>()) as u64,
            )?,
        ))
    }
}

/// The two passes' pipelines.
pub(crate) struct LocalLights {
    tile_depth: ComputePass<[u32; 2]>,
    /// Over the multisampled depth, with MSAA on.
    tile_depth_msaa: Option<ComputePass<[u32; 2]>>,
    cull: ComputePass<LightCullParams>,
}

/// Their bind groups over one set of [`LightBuffers`].
pub(crate) struct Groups {
    tile_depth: wgpu::BindGroup,
    tile_depth_msaa: Option<wgpu::BindGroup>,
    cull: wgpu::BindGroup,
    /// The counters, cleared before each culling pass.
    counters: wgpu::Buffer,
    /// Tiles across and down.
    tiles: [u32; 2],
}

impl LocalLights {
    pub(crate) fn new(device: &wgpu::Device, msaa: bool) -> Result<Self> {
        Ok(Self {
            tile_depth: ComputePass::new(device, &TILE_DEPTH, &[], &[])?,
            tile_depth_msaa: if msaa {
                Some(ComputePass::new(device, &TILE_DEPTH_MSAA, &["msaa"], &[])?)
            } else {
                None
            },
            cull: ComputePass::new(device, &LIGHT_CULL_PASS, &[], &[])?,
        })
    }

    pub(crate) fn groups(
        &self,
        device: &wgpu::Device,
        targets: &Targets,
        b: &LightBuffers,
    ) -> Result<Groups> {
        Ok(Groups {
            tile_depth: self.tile_depth.bind_group(
                device,
                "tiles",
                &[
                    ("params", b.tile_params.as_entire_binding()),
                    (
                        "depth_texture",
                        wgpu::BindingResource::TextureView(&targets.depth_float_view),
                    ),
                    ("tile_depths", b.tile_depths.as_entire_binding()),
                ],
            )?,
            tile_depth_msaa: match (&self.tile_depth_msaa, &targets.msaa) {
                (Some(p), Some(t)) => Some(p.bind_group(
                    device,
                    "tiles",
                    &[
                        ("params", b.tile_params.as_entire_binding()),
                        (
                            "depth_texture",
                            wgpu::BindingResource::TextureView(&t.depth_view),
                        ),
                        ("tile_depths", b.tile_depths.as_entire_binding()),
                    ],
                )?),
                _ => None,
            },
            cull: self.cull.bind_group(
                device,
                "cull",
                &[
                    ("params", b.cull_params.as_entire_binding()),
                    ("tile_depths", b.tile_depths.as_entire_binding()),
                    ("lights", b.lights.as_entire_binding()),
                    ("counts", b.counts.as_entire_binding()),
                    ("indices", b.indices.as_entire_binding()),
                    ("counters", b.counters.as_entire_binding()),
                ],
            )?,
            counters: b.counters.clone(),
            tiles: b.tiles,
        })
    }

    /// Records pass 1 (unless `tile_depths_done`: the compute laydown's unpack reduced the
    /// frame's final depth already) and the culling pass (the counters cleared first).
    pub(crate) fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
        tile_depths_done: bool,
    ) {
        let g = &f.groups.lights;
        encoder.clear_buffer(&g.counters, 0, None);
        if !tile_depths_done {
            let mut pass = timer.begin_compute(encoder, "light tile depth");
            let size = [f.targets.width, f.targets.height];
            match (f.msaa, &self.tile_depth_msaa, &g.tile_depth_msaa) {
                (true, Some(p), Some(group)) => p.record(&mut pass, &[group], &size),
                _ => self.tile_depth.record(&mut pass, &[&g.tile_depth], &size),
            }
        }
        let mut pass = timer.begin_compute(encoder, "light culling");
        let dispatch = LightCullParams {
            tiles: g.tiles,
            ..LightCullParams::default()
        };
        self.cull.record(&mut pass, &[&g.cull], &dispatch);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shadercheck::{Caps, assert_struct_layout, members};

    #[test]
    fn description_matches_its_module() {
        shadercheck::check_pass(&TILE_DEPTH, |_| Caps::CORE);
        shadercheck::check_pass_with(&TILE_DEPTH_MSAA, &["msaa"], |_| Caps::CORE);
        let m = shadercheck::assert_composed(LIBRARY, TILE_DEPTH.module, &[], Caps::CORE);
        assert_struct_layout(
            &m,
            "GpuTileDepthParams",
            size_of::<GpuTileDepthParams>(),
            &members!(GpuTileDepthParams {
                size,
                tiles_x,
                reversed
            }),
        );
    }
}
