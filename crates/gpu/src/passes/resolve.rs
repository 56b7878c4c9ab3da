//! The material resolve in compute (`gpu::resolve`): per pixel, the vis word decoded, the
//! triangle's vertices pulled and transformed, analytic barycentrics and derivatives,
//! textures sampled with gradients, the G-buffer written. By wave commands (one
//! `dispatch_workgroups_indirect` per pass, one workgroup of wave-width lanes per wave
//! command), or over every pixel (a diagnostic without classification). HFW's resolve
//! per material shader: each pass of the wave-command resolve may dispatch a pipeline
//! specialised for its material permutation (`MATERIAL_FEATURES`, gpu::material), made
//! from the same module and layout on first use and cached.

use std::collections::HashMap;
use std::sync::Mutex;

use shader::pipeline::ComputePass;
use shader::{Binding, Dispatch, Entry, Group, Kind, Pass, Sample, Size, Stage};
use tiling::{PassDispatch, WaveCommand};

use super::context::FrameContext;
use super::raster::SCENE_GROUP;
use crate::error::Result;
use crate::gbuffer::{KZ2_STORE_BINDINGS, STORE_BINDINGS};
pub(crate) use crate::resources::groups::ResolveGroups as Groups;
use crate::resources::rows::{GpuMesh, GpuMicroBatch};
use crate::shaders::LIBRARY;
use crate::timing::GpuTimer;
use deferred::GBufferLayout;

/// Bytes of the per-pass uniform (the pass index in `x`), bound at a dynamic offset.
pub(crate) const PASS_UNIFORM_BYTES: u64 = 16;

/// The resolve, over the image (`[width, height]`) or by wave commands.
pub(crate) const RESOLVE: Pass<[u32; 2]> = Pass {
    name: "material resolve",
    module: "gpu::resolve",
    library: LIBRARY,
    // `vrs`: HFW's software VRS broadcast (workgroup memory only where it is used).
    features: &["vrs"],
    groups: &[
        SCENE_GROUP,
        Group {
            name: "inputs",
            bindings: &[
                Binding::new("indices", Kind::read(4)),
                Binding::new("meshes", Kind::read(size_of::<GpuMesh>())),
                Binding::new("micro_batches", Kind::read(size_of::<GpuMicroBatch>())),
                Binding::new("vis_texture", Kind::texture_2d(Sample::Uint)),
                Binding::new(
                    "ring",
                    Kind::read(crate::resources::ring::RING_VERTEX_BYTES as usize),
                ),
                Binding::new("table", Kind::read(size_of::<tiling::MicroBatchInfo>())),
            ],
        },
        Group {
            name: "gbuffer",
            bindings: &STORE_BINDINGS,
        },
        Group {
            name: "waves",
            bindings: &[
                Binding::new("wave_commands", Kind::read(size_of::<WaveCommand>())),
                Binding::new("pixel_commands", Kind::read(4)),
                Binding::new("pass_dispatches", Kind::read(size_of::<PassDispatch>())),
                Binding::new(
                    "resolve_pass",
                    Kind::Uniform {
                        size: PASS_UNIFORM_BYTES as u32,
                        dynamic: true,
                    },
                ),
            ],
        },
    ],
    entries: &[
        Entry {
            name: "resolve_waves",
            stage: Stage::Compute([
                Size::Override("RESOLVE_WAVE_WIDTH"),
                Size::Fixed(1),
                Size::Fixed(1),
            ]),
            dispatch: Dispatch::Indirect("pass_dispatches"),
        },
        Entry::grid("resolve_fullscreen", 8, 8, |size| *size),
    ],
    zeroed: &[],
};

/// [`RESOLVE`] writing KZ2's G-buffer preset (with feature `kz2_gbuffer`).
pub(crate) const RESOLVE_KZ2: Pass<[u32; 2]> = Pass {
    groups: &[
        RESOLVE.groups[0],
        RESOLVE.groups[1],
        Group {
            name: "gbuffer",
            bindings: &KZ2_STORE_BINDINGS,
        },
        RESOLVE.groups[3],
    ],
    features: &["kz2_gbuffer", "vrs"],
    ..RESOLVE
};

/// The resolve's description for a G-buffer layout.
pub(crate) fn resolve_pass(layout: GBufferLayout) -> &'static Pass<[u32; 2]> {
    match layout {
        GBufferLayout::Kz2 => &RESOLVE_KZ2,
        GBufferLayout::Octahedral => &RESOLVE,
    }
}

/// The resolve's pipelines, for one wave width and G-buffer layout.
pub(crate) struct Resolve {
    pass: ComputePass<[u32; 2]>,
    store: &'static [Binding; 4],
    /// Indices into `pass.steps`.
    waves: usize,
    full_screen: usize,
    wave_width: u32,
    /// The wave-command resolve specialised per material permutation (the map bits of
    /// `scene::MaterialFeatures`), compiled on first use.
    permutations: Mutex<HashMap<u32, wgpu::ComputePipeline>>,
}

/// The `scene::MaterialFeatures` bits the resolve specialises on: the maps and emission
/// (the alpha test is the laydown's, not the resolve's).
pub(crate) const RESOLVE_FEATURE_BITS: u32 = 0b1111;

impl Resolve {
    /// The pipelines for wave commands of `wave_width` lanes, writing `layout`; `vrs`:
    /// with HFW's software VRS broadcast.
    pub(crate) fn new(
        device: &wgpu::Device,
        wave_width: u32,
        layout: GBufferLayout,
        vrs: bool,
    ) -> Result<Self> {
        let mut features = crate::gbuffer::features(layout).to_vec();
        if vrs {
            features.push("vrs");
        }
        let pass = ComputePass::new(
            device,
            resolve_pass(layout),
            &features,
            &[("RESOLVE_WAVE_WIDTH", f64::from(wave_width))],
        )?;
        Ok(Self {
            waves: pass.step_index("resolve_waves")?,
            full_screen: pass.step_index("resolve_fullscreen")?,
            wave_width,
            permutations: Mutex::new(HashMap::new()),
            pass,
            store: match layout {
                GBufferLayout::Kz2 => &KZ2_STORE_BINDINGS,
                GBufferLayout::Octahedral => &STORE_BINDINGS,
            },
        })
    }

    /// The wave-command resolve for material permutation `key` (`Material::shader_key`;
    /// only its [`RESOLVE_FEATURE_BITS`] matter), from the cache or compiled now.
    pub(crate) fn permutation(
        &self,
        device: &wgpu::Device,
        key: u32,
    ) -> Result<wgpu::ComputePipeline> {
        let key = key & RESOLVE_FEATURE_BITS;
        let mut cache = self
            .permutations
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some(p) = cache.get(&key) {
            return Ok(p.clone());
        }
        let pipeline = self.pass.variant(
            device,
            "resolve_waves",
            &[
                ("RESOLVE_WAVE_WIDTH", f64::from(self.wave_width)),
                ("MATERIAL_FEATURES", f64::from(key)),
            ],
        )?;
        cache.insert(key, pipeline.clone());
        Ok(pipeline)
    }

    /// The renderer's G-buffer group (storage views of RT0..RT3).
    pub(crate) fn gbuffer_group(
        &self,
        device: &wgpu::Device,
        views: &[wgpu::TextureView],
    ) -> Result<wgpu::BindGroup> {
        Ok(self.pass.bind_group(
            device,
            "gbuffer",
            &crate::gbuffer::resources(self.store, views),
        )?)
    }

    /// A prepared scene's groups: its `scene` resources, the resolve's inputs, and the
    /// classification's wave commands for `passes` passes.
    #[expect(
        clippy::too_many_arguments,
        reason = "one call site; every buffer a distinct binding of the description"
    )]
    pub(crate) fn groups(
        &self,
        device: &wgpu::Device,
        scene: &[(&str, wgpu::BindingResource<'_>)],
        indices: &wgpu::Buffer,
        meshes: &wgpu::Buffer,
        micro_batches: &wgpu::Buffer,
        vis_view: &wgpu::TextureView,
        classification: &crate::resources::groups::ClassifyBuffers,
        ring: Option<&crate::resources::groups::RingBuffers>,
        pass_pipelines: Vec<wgpu::ComputePipeline>,
    ) -> Result<Groups> {
        let passes = classification.sizes.passes;
        // The pass's half of the ring, where the ring holds it.
        let half = |p: u32| {
            ring.and_then(|r| r.half_base.get(p as usize).copied())
                .unwrap_or(crate::resources::ring::RING_NONE)
        };
        let stride =
            u64::from(device.limits().min_uniform_buffer_offset_alignment).max(PASS_UNIFORM_BYTES);
        let mut words = vec![0u8; (stride * u64::from(passes)) as usize];
        for p in 0..passes {
            let at = (stride * u64::from(p)) as usize;
            words[at..at + 4].copy_from_slice(&p.to_le_bytes());
            words[at + 4..at + 8].copy_from_slice(&half(p).to_le_bytes());
        }
        let stand_in = crate::resources::buffers::buffer_init(
            device,
            "vertex ring stand-in",
            &[0u8; crate::resources::ring::RING_VERTEX_BYTES as usize],
            0,
            wgpu::BufferUsages::STORAGE,
        );
        let pass_uniforms = crate::resources::buffers::buffer_init(
            device,
            "resolve pass index",
            &words,
            0,
            wgpu::BufferUsages::UNIFORM,
        );
        let waves = self.pass.bind_group(
            device,
            "waves",
            &[
                ("wave_commands", classification.waves.as_entire_binding()),
                (
                    "pixel_commands",
                    classification.commands.as_entire_binding(),
                ),
                (
                    "pass_dispatches",
                    classification.pass_dispatch.as_entire_binding(),
                ),
                (
                    "resolve_pass",
                    wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &pass_uniforms,
                        offset: 0,
                        size: wgpu::BufferSize::new(PASS_UNIFORM_BYTES),
                    }),
                ),
            ],
        )?;
        Ok(Groups {
            scene: self.pass.bind_group(device, "scene", scene)?,
            inputs: self.pass.bind_group(
                device,
                "inputs",
                &[
                    ("indices", indices.as_entire_binding()),
                    ("meshes", meshes.as_entire_binding()),
                    ("micro_batches", micro_batches.as_entire_binding()),
                    ("vis_texture", wgpu::BindingResource::TextureView(vis_view)),
                    (
                        "ring",
                        ring.map_or(&stand_in, |r| &r.ring).as_entire_binding(),
                    ),
                    ("table", classification.table().as_entire_binding()),
                ],
            )?,
            waves,
            pass_pipelines,
            pass_stride: stride as u32,
            reads_ring: ring.is_some(),
            _pass_uniforms: pass_uniforms,
            _ring_stand_in: stand_in,
        })
    }

    fn bind(&self, pass: &mut wgpu::ComputePass<'_>, f: &FrameContext<'_>) {
        let g = &f.scene.resolve;
        pass.set_bind_group(0, &g.scene, &[]);
        pass.set_bind_group(1, &g.inputs, &[]);
        pass.set_bind_group(2, &f.groups.gbuffer_store, &[]);
    }

    /// Records the resolve by wave commands: one indirect dispatch per pass; with the
    /// vertex ring, each pass's transform (`ring`) right before its resolve, each in its
    /// own timed compute pass (a single queue runs them in order: pass p + 1's transform
    /// waits for pass p's resolve, which the alternating halves would let overlap on an
    /// async compute queue).
    pub(crate) fn record_waves(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
        mut transform: impl FnMut(
            &mut wgpu::CommandEncoder,
            &crate::resources::groups::RingBuffers,
            u32,
            &mut GpuTimer,
        ),
    ) {
        let c = &f.scene.classification;
        let g = &f.scene.resolve;
        if let (true, Some(b)) = (g.reads_ring, &f.scene.vertex_ring) {
            for p in 0..c.sizes.passes {
                transform(encoder, b, p, timer);
                let mut pass = timer.begin_compute_as(
                    encoder,
                    "material resolve (wave commands, ring)",
                    "resolve (wave commands)",
                );
                self.bind(&mut pass, f);
                pass.set_pipeline(self.pass_pipeline(g, p));
                pass.set_bind_group(3, &g.waves, &[p * g.pass_stride]);
                pass.dispatch_workgroups_indirect(
                    &c.pass_dispatch,
                    u64::from(p) * size_of::<PassDispatch>() as u64,
                );
            }
            return;
        }
        let mut pass = timer.begin_compute_as(
            encoder,
            "material resolve (wave commands)",
            "resolve (wave commands)",
        );
        self.bind(&mut pass, f);
        for p in 0..c.sizes.passes {
            pass.set_pipeline(self.pass_pipeline(g, p));
            pass.set_bind_group(3, &g.waves, &[p * g.pass_stride]);
            pass.dispatch_workgroups_indirect(
                &c.pass_dispatch,
                u64::from(p) * size_of::<PassDispatch>() as u64,
            );
        }
    }

    /// Pass `p`'s wave-command pipeline: its permutation's, or the uber resolve.
    fn pass_pipeline<'a>(&'a self, g: &'a Groups, p: u32) -> &'a wgpu::ComputePipeline {
        g.pass_pipelines
            .get(p as usize)
            .unwrap_or(&self.pass.steps[self.waves].pipeline)
    }

    /// Records the full-screen resolve (every pixel, no classification).
    pub(crate) fn record_full_screen(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
    ) {
        let mut pass = timer.begin_compute_as(encoder, "material resolve (full screen)", "resolve");
        self.bind(&mut pass, f);
        // Group 3 is in the layout; the full-screen entry point reads none of it.
        pass.set_bind_group(3, &f.scene.resolve.waves, &[0]);
        let step = &self.pass.steps[self.full_screen];
        if let Some([x, y, z]) = self
            .pass
            .workgroups(step, &[f.targets.width, f.targets.height])
        {
            pass.set_pipeline(&step.pipeline);
            pass.dispatch_workgroups(x, y, z);
        }
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn description_matches_its_module() {
        shadercheck::check_pass(&super::RESOLVE, |_| shadercheck::Caps::CORE);
        shadercheck::check_pass_with(&super::RESOLVE_KZ2, &["kz2_gbuffer"], |_| {
            shadercheck::Caps::CORE
        });
    }

    /// The resolve specialises on the maps and emission, not on the alpha test (the
    /// laydown's).
    #[test]
    fn specialised_features_are_the_maps_and_emission() {
        use crate::scene::MaterialFeatures as F;
        assert_eq!(
            super::RESOLVE_FEATURE_BITS,
            F::NORMAL_MAP.0 | F::METALLIC_ROUGHNESS_MAP.0 | F::OCCLUSION_MAP.0 | F::EMISSIVE.0
        );
    }
}
