//! Everything an embedder does not need to render: read-backs of the last frame's
//! targets and buffers, the CPU twins' statistics and the talks' tables, and the hooks
//! tests and experiments use. Reached through [`Renderer::inspect`] (read-only) and
//! [`Renderer::hooks`] (hooks that record or overwrite).

use super::*;
use crate::water_scene::WaterStats;

/// The last frame's light tiles ([`Inspect::read_light_tiles`]), in the layout of
/// `deferred::lights::cull_tiles`: tiles of 16x16 pixels, row-major from the top-left.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LightTiles {
    /// Tiles across and down.
    pub tiles: [u32; 2],
    /// Per tile: the nearest and farthest depth of its geometry (reversed Z).
    pub depths: Vec<deferred::DeferredTileDepth>,
    /// Per tile: its lights (at most `MAX_LIGHTS_PER_TILE`).
    pub counts: Vec<u32>,
    /// Per tile, `MAX_LIGHTS_PER_TILE` slots: its lights' indices (ascending) in
    /// [`LightTiles::lights`], the first `counts[t]` valid.
    pub indices: Vec<u32>,
    /// The lights that took the tiled path in the last frame, in view space: all of
    /// [`local_light_rows`](crate::inspect::local_light_rows), in its order, under
    /// [`LightPaths::Tiled`]; under [`LightPaths::Classified`], those KZ2's classifier
    /// left to the tiles, in the same relative order.
    pub lights: Vec<deferred::DeferredLight>,
    /// Tiles with geometry, (tile, light) pairs, tiles that overflowed.
    pub stats: deferred::lights::CullStats,
}

/// One light the last frame tested for KZ2's conditional rendering, as the GPU decided
/// ([`Inspect::read_conditional_volumes`]): a test and measurement aid.
#[doc(hidden)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ConditionalLight {
    /// Its row (view space; its spot map's slot + 1 in `flags` bits 8-15).
    pub light: deferred::DeferredLight,
    /// What its occlusion query counted (non-zero: some pixel is shaded).
    pub samples: u64,
    /// Instances of its volume draws' indirect arguments: 1, or 0 where skipped.
    pub volume_instances: u32,
    /// Its map's caster draws: rows the CPU culled, the count words' total (0 where
    /// skipped), and the instances their arguments hold (0 where skipped).
    pub caster_rows: u32,
    pub caster_count: u32,
    pub caster_instances: u64,
    /// The static query's draws its map draws (the placement's counts, or 0 where
    /// skipped; 0 in a frame without static content).
    pub static_count: u32,
}

/// Read-backs and statistics of a renderer ([`Renderer::inspect`]). Each read-back waits
/// for the GPU.
pub struct Inspect<'r> {
    r: &'r Renderer,
}

/// Hooks that record or overwrite on a renderer, for tests and experiments
/// ([`Renderer::hooks`]).
pub struct Hooks<'r> {
    r: &'r mut Renderer,
}

impl Renderer {
    /// Read-backs of the last frame and statistics: not needed to render.
    pub fn inspect(&self) -> Inspect<'_> {
        Inspect { r: self }
    }

    /// Test and measurement hooks: the laydown alone, classification of given words,
    /// corrupt payloads, classification variants, held upload completions.
    pub fn hooks(&mut self) -> Hooks<'_> {
        Hooks { r: self }
    }
}

impl<'r> Inspect<'r> {
    /// What the last frame's water passes did: bodies and sectors drawn, water pixels,
    /// tiles and triangles (read back; `None` without water).
    ///
    /// # Errors
    /// A device or mapping error.
    pub fn water_stats(&self) -> Result<Option<WaterStats>> {
        self.r
            .water
            .as_ref()
            .map(|w| w.stats(&self.r.device, &self.r.queue))
            .transpose()
    }

    /// Reads the last frame's mini G-buffer back: data words and view depths.
    ///
    /// # Errors
    /// A device or mapping error.
    pub fn read_water_gbuffer(&self) -> Result<Option<WaterGBuffer>> {
        let Some(w) = &self.r.water else {
            return Ok(None);
        };
        let t = &w.targets;
        let read = |tex: &wgpu::Texture| {
            read_texture(
                &self.r.device,
                &self.r.queue,
                tex,
                wgpu::TextureAspect::All,
                4,
            )
        };
        Ok(Some(WaterGBuffer {
            size: t.size,
            data: bytemuck::pod_collect_to_vec(&read(&t.data.0)?),
            depth: bytemuck::pod_collect_to_vec(&read(&t.linear.0)?),
        }))
    }

    /// Reads the last frame's displacement texture back (mini G-buffer pixels, row-major:
    /// xyz metres +Y up, w the decals' foam).
    ///
    /// # Errors
    /// A device or mapping error.
    pub fn read_water_displacement(&self) -> Result<Option<Vec<[f32; 4]>>> {
        let Some(w) = &self.r.water else {
            return Ok(None);
        };
        Ok(Some(self.r.texels(
            &w.targets.displacement.0,
            wgpu::TextureAspect::All,
        )?))
    }

    /// Reads the last frame's tiles back: counts, list and the draw's arguments.
    ///
    /// # Errors
    /// A device or mapping error.
    pub fn read_water_tiles(&self) -> Result<Option<WaterTiles>> {
        let Some(w) = &self.r.water else {
            return Ok(None);
        };
        let t = &w.targets;
        let n = u64::from(t.tile_count());
        let words = |b: &wgpu::Buffer, bytes: u64| self.r.words::<u32>(b, 0, bytes);
        let args = words(&t.tile_args, 20)?;
        let counts = words(&t.tile_counts, n * 4)?;
        let mut list = words(&t.tile_list, n * 4)?;
        list.truncate((args[1] as usize).min(n as usize));
        Ok(Some(WaterTiles {
            tiles: t.tiles,
            counts,
            list,
            index_count: args[0],
            instance_count: args[1],
        }))
    }

    /// Reads the last frame's tessellated surface back at full resolution: per pixel the
    /// view depth of the water drawn there (0: none) and its mini G-buffer UV.
    ///
    /// # Errors
    /// A device or mapping error.
    pub fn read_water_surface(&self) -> Result<Option<Vec<[f32; 4]>>> {
        let Some(w) = &self.r.water else {
            return Ok(None);
        };
        Ok(Some(
            self.r
                .texels(&w.targets.surface.0, wgpu::TextureAspect::All)?,
        ))
    }

    /// Reads the last frame's depth with water back (row-major, reversed Z): the opaque
    /// depth with the tessellated water drawn into it. See [`crate::water_scene`] for which
    /// passes read which depth.
    ///
    /// # Errors
    /// A device or mapping error.
    pub fn read_water_depth(&self) -> Result<Option<Vec<f32>>> {
        let Some(w) = &self.r.water else {
            return Ok(None);
        };
        Ok(Some(self.r.texels(
            &w.targets.depth_water.0,
            wgpu::TextureAspect::DepthOnly,
        )?))
    }
    /// What the last frame's uploads took from the upload pool: bytes, blocks, the CPU
    /// time spent in `framealloc`, the pool's free blocks and the frames in flight.
    pub fn upload_stats(&self) -> &'r UploadStats {
        self.r.uploads.stats()
    }

    /// Reads the G-buffer of the last frame back, one [`deferred::Surface`] per pixel
    /// (row-major; world-space normals, turned back from view space under the KZ2 preset;
    /// motion in pixels, `+y` down): what lighting read.
    ///
    /// # Errors
    /// A device or mapping error.
    pub fn read_gbuffer(&self) -> Result<Vec<deferred::Surface>> {
        let targets: Vec<(Vec<u8>, usize)> = self
            .r
            .targets
            .gbuffer
            .iter()
            .map(|t| {
                let texel = t.format().block_copy_size(None).unwrap_or(4) as usize;
                let bytes = read_texture(
                    &self.r.device,
                    &self.r.queue,
                    t,
                    wgpu::TextureAspect::All,
                    texel as u32,
                )?;
                Ok((bytes, texel))
            })
            .collect::<Result<_>>()?;
        let n = (self.r.config.image.width * self.r.config.image.height) as usize;
        let mut texel = Vec::with_capacity(20);
        // The KZ2 preset's view-space normals, back to world directions.
        let to_world = self.r.view_rotation.transpose();
        (0..n)
            .map(|i| {
                texel.clear();
                for (bytes, size) in &targets {
                    texel.extend_from_slice(&bytes[i * size..(i + 1) * size]);
                }
                let layout = self.r.config.image.gbuffer;
                let mut s = layout.unpack_bytes(&texel).ok_or_else(|| {
                    Error::Map(format!(
                        "a G-buffer texel read back as {} bytes, not the layout's",
                        texel.len()
                    ))
                })?;
                if layout.normal_space() == deferred::NormalSpace::View {
                    s.normal = to_world.transform_vector3(s.normal);
                }
                Ok(s)
            })
            .collect()
    }

    /// Reads the depth buffer of the last single-sampled frame back (row-major, reversed
    /// Z: 1 at the near plane, 0 for the sky): what lighting read and what a HiZ for the
    /// next frame's occlusion is built from.
    ///
    /// # Errors
    /// A device or mapping error.
    pub fn read_depth(&self) -> Result<Vec<f32>> {
        self.r
            .texels(&self.r.targets.depth_float, wgpu::TextureAspect::All)
    }

    /// What the last compute laydown of `scene` drew: its triangles and those the hardware
    /// part drew. `None` where the renderer or the scene has no compute laydown.
    ///
    /// # Errors
    /// A scene prepared by another renderer, or a device or mapping error.
    pub fn read_laydown_stats(
        &self,
        scene: &PreparedScene,
    ) -> Result<Option<crate::inspect::LaydownStats>> {
        self.r.check_scene(scene)?;
        let Some(g) = &scene.compute_laydown else {
            return Ok(None);
        };
        let vertex_count = self.r.words::<u32>(&g.list, 0, 4)?[0];
        let large = self.r.words::<u32>(&g.large, 12, 4)?[0];
        Ok(Some(passes::compute_laydown::stats(
            g.items,
            vertex_count,
            large,
        )))
    }

    /// Reads the static placement's debug words of the last frame with a static query of
    /// `scene` (what [`debug::static_lod_fade`](crate::inspect::debug::static_lod_fade) and
    /// [`debug::static_two_pass`](crate::inspect::debug::static_two_pass) colour the vis buffer by).
    ///
    /// # Errors
    /// A scene without static setups, a scene prepared by another renderer, or a device
    /// or mapping error.
    pub fn read_static_debug(&self, scene: &PreparedScene) -> Result<crate::statics::StaticDebug> {
        self.r.check_scene(scene)?;
        let b = Renderer::static_buffers(scene)?;
        let words = self.r.words(&b.debug, 0, b.debug.size())?;
        let mut ranges: Vec<_> = scene
            .static_table
            .iter()
            .enumerate()
            .map(|(i, s)| (i as u32, *s))
            .collect();
        ranges.sort_by_key(|(_, s)| s.first_id);
        Ok(crate::statics::StaticDebug {
            ranges,
            words,
            base: b.debug_base,
        })
    }

    /// How the last frame's local lights were split between the tiles and the stencil
    /// volumes.
    pub fn light_path_counts(&self) -> LightPathCounts {
        LightPathCounts {
            tiled: self.r.light.tiled.len() as u32,
            volumes: self.r.light.volume_draws.len() as u32,
            volumes_from_inside: self
                .r
                .light
                .volume_draws
                .iter()
                .filter(|d| d.inside)
                .count() as u32,
            spot_shadow_maps: self.r.targets.spot_shadows.active,
            volumes_tested: self
                .r
                .light
                .conditional
                .as_ref()
                .map_or(0, |c| c.plan.tests.len() as u32),
            spot_shadow_maps_skipped: self.r.light.conditional.as_ref().map_or(0, |c| {
                c.plan
                    .maps
                    .iter()
                    .filter(|m| **m == crate::resources::conditional::MapDraw::Skipped)
                    .count() as u32
            }),
        }
    }

    /// Reads back what the last frame's GPU decided for each light tested for KZ2's
    /// conditional rendering (empty with the emulation off or no light tested): its query's
    /// count and the indirect arguments of its volume and its map's casters.
    ///
    /// # Errors
    /// A device or mapping error.
    #[doc(hidden)]
    pub fn read_conditional_volumes(&self) -> Result<Vec<ConditionalLight>> {
        use crate::resources::conditional::{COUNT_WORDS, DRAW_WORDS, MapDraw};
        let Some(c) = &self.r.light.conditional else {
            return Ok(Vec::new());
        };
        let n = c.plan.tests.len() as u64;
        if n == 0 {
            return Ok(Vec::new());
        }
        let words = |buffer: &wgpu::Buffer, bytes: u64| self.r.words::<u32>(buffer, 0, bytes);
        let samples = words(&c.resolved, n * 8)?;
        let volumes = words(&c.volume_args, n * 4 * u64::from(DRAW_WORDS))?;
        let counts = words(&c.counts, n * 4 * u64::from(COUNT_WORDS))?;
        let casters = if c.casters > 0 {
            words(
                &c.caster_args,
                u64::from(c.casters) * 4 * u64::from(DRAW_WORDS),
            )?
        } else {
            Vec::new()
        };
        let (w, cw) = (DRAW_WORDS as usize, COUNT_WORDS as usize);
        Ok((0..n as usize)
            .map(|t| {
                let (first, rows) = c
                    .plan
                    .maps
                    .iter()
                    .find_map(|m| match *m {
                        MapDraw::Indirect {
                            test,
                            first,
                            opaque,
                            alpha,
                        } if test as usize == t => {
                            Some((first as usize, (opaque + alpha) as usize))
                        }
                        _ => None,
                    })
                    .unwrap_or((0, 0));
                ConditionalLight {
                    light: c.plan.lights.get(t).copied().unwrap_or_default(),
                    samples: u64::from(samples[2 * t]) | u64::from(samples[2 * t + 1]) << 32,
                    volume_instances: volumes[t * w + 1],
                    caster_rows: rows as u32,
                    caster_count: counts[cw * t] + counts[cw * t + 1],
                    static_count: counts[cw * t + 2] + counts[cw * t + 3],
                    caster_instances: (first..first + rows)
                        .filter_map(|r| casters.get(r * w + 1))
                        .map(|&i| u64::from(i))
                        .sum(),
                }
            })
            .collect())
    }

    /// Reads back the last frame's light tiles: each 16x16 tile's depth range, light count
    /// and list, and what the culling pass counted.
    ///
    /// # Errors
    /// A device or mapping error.
    pub fn read_light_tiles(&self) -> Result<LightTiles> {
        let b = &self.r.light.buffers;
        let n = u64::from(b.tiles[0]) * u64::from(b.tiles[1]);
        let counters: Vec<deferred::pass::LightCullCounters> = self.r.words(
            &b.counters,
            0,
            size_of::<deferred::pass::LightCullCounters>() as u64,
        )?;
        Ok(LightTiles {
            tiles: b.tiles,
            depths: self.r.words(&b.tile_depths, 0, n * 8)?,
            counts: self.r.words(&b.counts, 0, n * 4)?,
            indices: self.r.words(
                &b.indices,
                0,
                n * u64::from(deferred::lights::MAX_LIGHTS_PER_TILE) * 4,
            )?,
            lights: self.r.light.tiled.clone(),
            stats: counters[0].stats(),
        })
    }

    /// Reads back the edge pixels of the last MSAA baseline frame under
    /// [`MsaaLighting::Kz2`]: row-major pixel indices, ascending (the pixels whose samples
    /// hold more than one surface, lit per sample). Empty without MSAA or after a frame
    /// that lit every sample.
    ///
    /// # Errors
    /// A device or mapping error.
    pub fn read_msaa_edges(&self) -> Result<Vec<u32>> {
        let Some(t) = &self.r.targets.msaa else {
            return Ok(Vec::new());
        };
        let header_bytes = crate::resources::targets::MSAA_EDGES_HEADER;
        let header: Vec<u32> = self.r.words(&t.edges, 0, header_bytes)?;
        let pixels = u64::from(self.r.targets.width) * u64::from(self.r.targets.height);
        let count = u64::from(header[3]).min(pixels);
        if count == 0 {
            return Ok(Vec::new());
        }
        let mut edges: Vec<u32> = self
            .r
            .words::<u32>(&t.edges, header_bytes, count * 4)?
            .into_iter()
            .map(|w| (w >> 16) * self.r.targets.width + (w & 0xffff))
            .collect();
        edges.sort_unstable();
        Ok(edges)
    }

    /// Reads the vis buffer of the last frame back (row-major words, `visbuf`'s layout;
    /// `VIS_NONE` where nothing was drawn).
    ///
    /// # Errors
    /// A device or mapping error.
    pub fn read_vis(&self) -> Result<Vec<u32>> {
        self.r.texels(&self.r.targets.vis, wgpu::TextureAspect::All)
    }

    /// Reads back what the last deferred frame's classification wrote.
    ///
    /// # Errors
    /// A scene prepared by another renderer, or a device error.
    pub fn read_classification(&self, scene: &PreparedScene) -> Result<GpuClassification> {
        self.r.check_scene(scene)?;
        GpuClassification::read(
            &self.r.device,
            &self.r.queue,
            &scene.classification,
            &self.r.targets.vis_words,
        )
    }

    /// What HFW's vertex side wrote in the last deferred frame of `scene` (vertex wave
    /// commands, dispatches, the ring), read back; `None` without
    /// [`RendererConfig::geometry.vertex_ring`](crate::config::GeometryConfig::vertex_ring).
    ///
    /// # Errors
    /// A scene of another renderer, or a device error.
    pub fn read_vertex_ring(
        &self,
        scene: &PreparedScene,
    ) -> Result<Option<crate::inspect::VertexRingReadback>> {
        self.r.check_scene(scene)?;
        scene
            .vertex_ring
            .as_ref()
            .map(|b| crate::inspect::VertexRingReadback::read(&self.r.device, &self.r.queue, b))
            .transpose()
    }

    /// The talk's counters for a read-back classification: runs `tiling`'s CPU twin on the
    /// same vis words, compares every output (returning the first difference, if any), and
    /// measures depth-equal waves and chunk-culled vertices with `tiling::measure`.
    ///
    /// # Errors
    /// A read-back that the CPU twin rejects (a wrong-sized vis buffer).
    pub fn classification_statistics(
        &self,
        scene: &PreparedScene,
        gpu: &GpuClassification,
    ) -> Result<(ClassificationStats, Option<String>)> {
        classification_statistics(scene, gpu)
    }

    /// The sun's cascades fitted to the last frame's camera (world space, f64), with
    /// shadows on: each map's slice, snapped centre, texel size and matrix.
    #[must_use]
    pub fn shadow_cascades(&self) -> Option<&'r deferred::cascades::StableCascades> {
        self.r.shadow.cascades.as_ref()
    }

    /// Reads the last frame's sun shadow maps back, one `resolution`² depth layer per
    /// cascade (row-major, 0 nearest the sun, 1 where nothing casts); empty with shadows
    /// off.
    ///
    /// # Errors
    /// A device or mapping error.
    pub fn read_shadow_maps(&self) -> Result<Vec<Vec<f32>>> {
        let maps = &self.r.targets.shadows;
        self.read_depth_layers(&maps.texture, maps.cascades())
    }

    /// Layers `0..layers` of the depth-array `texture`, each row-major.
    fn read_depth_layers(&self, texture: &wgpu::Texture, layers: u32) -> Result<Vec<Vec<f32>>> {
        (0..layers)
            .map(|layer| {
                let bytes = crate::resources::readback::read_texture_layer(
                    &self.r.device,
                    &self.r.queue,
                    texture,
                    wgpu::TextureAspect::DepthOnly,
                    4,
                    layer,
                )?;
                Ok(bytemuck::pod_collect_to_vec(&bytes))
            })
            .collect()
    }

    /// Reads the last frame's spot shadow maps back, one `resolution`² depth layer per map
    /// in slot order (0 at the light's near plane, 1 where nothing casts): a test aid.
    ///
    /// # Errors
    /// A device or mapping error.
    #[doc(hidden)]
    pub fn read_spot_shadow_maps(&self) -> Result<Vec<Vec<f32>>> {
        let maps = &self.r.targets.spot_shadows;
        self.read_depth_layers(&maps.texture, maps.active.min(maps.layers()))
    }
}

impl Hooks<'_> {
    /// Replaces the position pass's mini G-buffer with `given` (data words, view depths,
    /// mesh normals as half-float bit patterns: any values) for the next frames, which skip
    /// the visibility and position passes; `None` goes back to drawing it. How tests feed
    /// a corrupt mini G-buffer to the passes after it.
    ///
    /// # Errors
    /// Slices of the wrong length, or no water.
    #[doc(hidden)]
    pub fn set_water_gbuffer(&mut self, given: Option<WaterGBufferInput<'_>>) -> Result<()> {
        let Some(w) = &mut self.r.water else {
            return Err(Error::Length {
                what: "a mini G-buffer for a renderer without water",
                got: 0,
                expected: 0,
            });
        };
        let Some((data, depth, normal)) = given else {
            w.gbuffer_given = false;
            return Ok(());
        };
        let [sw, sh] = w.targets.size;
        let n = (sw * sh) as usize;
        for (what, len) in [
            ("mini G-buffer data words", data.len()),
            ("mini G-buffer depths", depth.len()),
            ("mini G-buffer normals", normal.len()),
        ] {
            if len != n {
                return Err(Error::Length {
                    what,
                    got: len,
                    expected: n,
                });
            }
        }
        let write = |t: &wgpu::Texture, bytes: &[u8], texel: u32| {
            self.r.queue.write_texture(
                t.as_image_copy(),
                bytes,
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(sw * texel),
                    rows_per_image: Some(sh),
                },
                t.size(),
            );
        };
        write(&w.targets.data.0, bytemuck::cast_slice(data), 4);
        write(&w.targets.linear.0, bytemuck::cast_slice(depth), 4);
        write(&w.targets.normal.0, bytemuck::cast_slice(normal), 8);
        w.gbuffer_given = true;
        Ok(())
    }
    /// Renders the laydown alone and returns the vis buffer (row-major words) and the depth
    /// buffer: what the classification passes and their CPU twins read.
    ///
    /// # Errors
    /// As [`Renderer::render`].
    pub fn render_laydown(
        &mut self,
        scene: &PreparedScene,
        frame: &FrameInput,
    ) -> Result<(Vec<u32>, Vec<f32>)> {
        self.r
            .run(scene, frame, "laydown", Recording::Laydown, None, true)?;
        Ok((
            self.r
                .texels(&self.r.targets.vis, wgpu::TextureAspect::All)?,
            self.r
                .texels(&self.r.targets.depth, wgpu::TextureAspect::DepthOnly)?,
        ))
    }

    /// Uploads `words` (row-major, `width * height`, any values: bad IDs are the
    /// classification's to count) as the vis buffer, runs the three classification phases
    /// on them alone, and reads the result back. How tests feed random vis buffers.
    ///
    /// # Errors
    /// `words` is not `width * height` long ([`Error::Length`]), or a device error.
    pub fn classify_words(
        &mut self,
        scene: &PreparedScene,
        words: &[u32],
    ) -> Result<GpuClassification> {
        let n = (self.r.config.image.width * self.r.config.image.height) as usize;
        if words.len() != n {
            return Err(Error::Length {
                what: "vis words (width * height of the renderer)",
                got: words.len(),
                expected: n,
            });
        }
        self.r.check_scene(scene)?;
        let device = self.r.device.clone();
        scoped(&device, || {
            self.r
                .queue
                .write_buffer(&self.r.targets.vis_words, 0, bytemuck::cast_slice(words));
            let mut encoder = device.create_command_encoder(&Default::default());
            let f = FrameContext {
                scene,
                targets: &self.r.targets,
                groups: &self.r.groups,
                static_query: false,
                volumes: &[],
                casters: &self.r.shadow.casters,
                static_slices: &[],
                conditional: None,
                origin_offset: self.r.origin_offset,
                msaa: false,
                compute_laydown: false,
                water_hdr: None,
            };
            self.r.pipelines.record(
                Recording::Classification,
                &mut encoder,
                &f,
                None,
                &mut self.r.timer,
            );
            self.r.timer.resolve(&mut encoder);
            self.r.queue.submit([encoder.finish()]);
            wait_idle(&device)
        })?;
        let _ = self.r.timer.read(&self.r.device, &self.r.queue)?;
        self.r.inspect().read_classification(scene)
    }

    /// Overwrites `scene`'s primitive-ID payloads (one word per vertex of its encoded
    /// geometry, any values) until it is prepared again: how tests feed corrupt primitive
    /// IDs to the passes that read them (the laydown's payload paths, the pixel-pull
    /// path), which must never read out of bounds.
    ///
    /// # Errors
    /// `words` is not one per vertex ([`Error::Length`]), or a scene prepared by another
    /// renderer.
    #[doc(hidden)]
    pub fn write_payloads(&self, scene: &PreparedScene, words: &[u32]) -> Result<()> {
        self.r.check_scene(scene)?;
        let buffer = scene.payloads();
        let expected = (buffer.size() / 4) as usize;
        if words.len() != expected {
            return Err(Error::Length {
                what: "payloads (one per vertex)",
                got: words.len(),
                expected,
            });
        }
        self.r
            .queue
            .write_buffer(buffer, 0, bytemuck::cast_slice(words));
        Ok(())
    }

    /// Holds the GPU's completion notices back from the upload pool (`true`), as a GPU
    /// that is slow to finish would: no block of a held frame is handed out again. `false`
    /// delivers the held notices and resumes. For tests of the allocator in the frame.
    #[doc(hidden)]
    pub fn hold_upload_completions(&self, hold: bool) {
        self.r.uploads.hold_completions(hold);
    }

    /// Replaces the classification phases' `override`s and skips entry points, for timing
    /// experiments (`examples/classify_variants.rs`).
    #[doc(hidden)]
    pub fn set_classification_variant(&mut self, variant: &ClassificationVariant) -> Result<()> {
        let device = self.r.device.clone();
        scoped(&device, || {
            self.r.pipelines.classify.set_variant(&device, variant)
        })
    }
}

/// The read-backs' shared helpers.
impl Renderer {
    /// Mip 0, layer 0 of `texture` read back as `T`s, one a texel (row-major).
    pub(super) fn texels<T: bytemuck::Pod>(
        &self,
        texture: &wgpu::Texture,
        aspect: wgpu::TextureAspect,
    ) -> Result<Vec<T>> {
        let bytes = read_texture(
            &self.device,
            &self.queue,
            texture,
            aspect,
            size_of::<T>() as u32,
        )?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }

    /// `bytes` of `buffer` from `offset` read back as `T`s.
    pub(super) fn words<T: bytemuck::Pod>(
        &self,
        buffer: &wgpu::Buffer,
        offset: u64,
        bytes: u64,
    ) -> Result<Vec<T>> {
        let data = read_buffer(&self.device, &self.queue, buffer, offset, bytes)?;
        Ok(bytemuck::pod_collect_to_vec(&data))
    }
}
