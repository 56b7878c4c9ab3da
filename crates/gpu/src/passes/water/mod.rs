//! FC5's water in the frame (seed 003), one module per pass; the order, the targets and
//! the per-frame constants are here. [`crate::water_scene`] has the API and the table of
//! passes, `water::draw` the CPU side (meshes, sector tree, material map);
//! this module runs them after the opaque frame's lighting:
//!
//! hiz -> [`visibility`] -> [`position`] -> [`displacement`] -> [`tiles`] -> depth copy ->
//! [`tessellation`] -> light tiles -> [`normals`] -> [`foam`] -> [`composite`]
//!
//! Everything sized by the image lives in [`WaterTargets`] (made with the state), the
//! world's data in [`WaterData`] (made by `Renderer::set_water`).

pub(crate) mod composite;
pub(crate) mod data;
pub(crate) mod displacement;
pub(crate) mod foam;
pub(crate) mod groups;
pub(crate) mod normals;
pub(crate) mod position;
pub(crate) mod rows;
pub(crate) mod targets;
pub(crate) mod tessellation;
pub(crate) mod tiles;
pub(crate) mod visibility;

use super::context::FrameContext;
use super::depth_reductions::TILE_DEPTH;
use crate::error::Result;
use crate::timing::GpuTimer;
use crate::water_scene::{MAX_WATER_DECALS, WaterDecal, WaterStats};
use shader::pipeline::ComputePass;

pub(crate) use data::{Built, WaterData};
pub(crate) use groups::{Shared, WaterGroups};
use rows::*;
pub(crate) use targets::WaterTargets;

/// Every water pass's pipelines, and the lighting variant's group.
/// Records `pass`, one grid dispatch over `size` with `group`, as a compute pass of its own
/// timed under its description's name: the water's grid passes (displacement, normals,
/// foam, composite).
fn record_grid(
    e: &mut wgpu::CommandEncoder,
    pass: &ComputePass<[u32; 2]>,
    group: &wgpu::BindGroup,
    size: [u32; 2],
    timer: &mut GpuTimer,
) {
    let mut compute = timer.begin_compute(e, pass.pass.name);
    pass.record(&mut compute, &[group], &size);
}

pub(crate) struct WaterPasses {
    pub visibility: visibility::Visibility,
    pub position: position::Position,
    pub displacement: ComputePass<[u32; 2]>,
    pub tiles: tiles::Tiles,
    pub tessellation: tessellation::Tessellation,
    pub tile_depth: ComputePass<[u32; 2]>,
    pub cull: ComputePass<deferred::pass::LightCullParams>,
    pub normals: ComputePass<[u32; 2]>,
    pub foam: ComputePass<[u32; 2]>,
    pub composite: ComputePass<[u32; 2]>,
}

impl WaterPasses {
    pub(crate) fn new(device: &wgpu::Device, subgroups: bool, half: bool) -> Result<Self> {
        Ok(Self {
            visibility: visibility::Visibility::new(device)?,
            position: position::Position::new(device)?,
            displacement: displacement::new(device)?,
            tiles: tiles::Tiles::new(device, subgroups)?,
            tessellation: tessellation::Tessellation::new(device)?,
            tile_depth: ComputePass::new(device, &TILE_DEPTH, &[], &[])?,
            cull: ComputePass::new(device, &deferred::pass::LIGHT_CULL_PASS, &[], &[])?,
            normals: normals::new(device)?,
            foam: foam::new(device)?,
            composite: composite::new(device, half)?,
        })
    }
}

/// The water in a renderer: pipelines, targets, the world's data and their groups.
pub(crate) struct WaterState {
    pub passes: WaterPasses,
    pub targets: WaterTargets,
    pub data: WaterData,
    pub groups: WaterGroups,
    /// Whether the composite runs in half precision.
    pub half: bool,
    /// A mini G-buffer given for the next frames instead of the position pass's (tests:
    /// garbage words).
    pub gbuffer_given: bool,
}

impl WaterState {
    /// The bind groups over the targets, the data and `s`.
    pub(crate) fn groups(
        device: &wgpu::Device,
        passes: &WaterPasses,
        t: &WaterTargets,
        d: &WaterData,
        s: &Shared<'_>,
    ) -> Result<WaterGroups> {
        use wgpu::BindingResource::TextureView as T;
        fn b(x: &wgpu::Buffer) -> wgpu::BindingResource<'_> {
            x.as_entire_binding()
        }
        Ok(WaterGroups {
            hiz: passes.visibility.hiz_groups(device, &d.hiz, s.depth)?,
            visibility: passes.visibility.pass.bind_group(
                device,
                "water",
                &[
                    ("frame", b(s.frame)),
                    ("water", b(&d.frame)),
                    ("bodies", b(&d.bodies)),
                    ("near_args", b(&d.near_args)),
                    ("nodes", b(&d.nodes)),
                    ("lists", b(&d.lists)),
                    ("far_list", b(&d.far_list)),
                    ("far_args", b(&d.far_args)),
                    ("hiz", b(&d.hiz.buffer)),
                    ("stats", b(&d.stats)),
                ],
            )?,
            position: passes.position.layouts.bind_group(
                device,
                "water",
                &[
                    ("frame", b(s.frame)),
                    ("water", b(&d.frame)),
                    ("world", T(&d.world)),
                    ("materials", b(&d.materials)),
                    ("vertices", b(&d.vertices)),
                    ("nodes", b(&d.nodes)),
                    ("far_list", b(&d.far_list)),
                    ("hiz", b(&d.hiz.buffer)),
                ],
            )?,
            displacement: passes.displacement.bind_group(
                device,
                "water",
                &[
                    ("frame", b(s.frame)),
                    ("water", b(&d.frame)),
                    ("data", T(&t.data.1)),
                    ("depth", T(&t.linear.1)),
                    ("materials", b(&d.materials)),
                    ("noise", T(&d.noise)),
                    ("decals", b(&d.decals)),
                    ("decal_texels", T(&d.decal_texels)),
                    ("displacement", T(&t.displacement.1)),
                    ("vertices", b(&t.vertices)),
                ],
            )?,
            tiles: passes.tiles.pass.bind_group(
                device,
                "water",
                &[
                    ("water", b(&d.frame)),
                    ("data", T(&t.data.1)),
                    ("counts", b(&t.tile_counts)),
                    ("tile_list", b(&t.tile_list)),
                    ("args", b(&t.tile_args)),
                ],
            )?,
            tessellation: passes.tessellation.layouts.bind_group(
                device,
                "water",
                &[
                    ("frame", b(s.frame)),
                    ("water", b(&d.frame)),
                    ("vertices", b(&t.vertices)),
                    ("tile_list", b(&t.tile_list)),
                ],
            )?,
            tile_depth: passes.tile_depth.bind_group(
                device,
                "tiles",
                &[
                    ("params", b(&s.lights.tile_params)),
                    ("depth_texture", T(&t.depth_water.1)),
                    ("tile_depths", b(&t.tile_depths)),
                ],
            )?,
            cull: passes.cull.bind_group(
                device,
                "cull",
                &[
                    ("params", b(&s.lights.cull_params)),
                    ("tile_depths", b(&t.tile_depths)),
                    ("lights", b(&s.lights.lights)),
                    ("counts", b(&t.light_counts)),
                    ("indices", b(&t.light_indices)),
                    ("counters", b(&t.light_counters)),
                ],
            )?,
            normals: passes.normals.bind_group(
                device,
                "water",
                &[
                    ("frame", b(s.frame)),
                    ("water", b(&d.frame)),
                    ("surface", T(&t.surface.1)),
                    ("data", T(&t.data.1)),
                    ("mesh_normal", T(&t.normal.1)),
                    ("materials", b(&d.materials)),
                    ("normals", T(&t.normals.1)),
                ],
            )?,
            foam: passes.foam.bind_group(
                device,
                "water",
                &[
                    ("frame", b(s.frame)),
                    ("water", b(&d.frame)),
                    ("surface", T(&t.surface.1)),
                    ("data", T(&t.data.1)),
                    ("materials", b(&d.materials)),
                    ("atlas", T(&d.atlas)),
                    ("shore", T(&d.shore)),
                    ("noise", T(&d.noise)),
                    ("displacement", T(&t.displacement.1)),
                    ("scene_depth", T(s.depth)),
                    ("foam", T(&t.foam.1)),
                ],
            )?,
            composite: passes.composite.bind_group(
                device,
                "water",
                &[
                    ("frame", b(s.frame)),
                    ("water", b(&d.frame)),
                    ("local", b(s.local)),
                    ("lights", b(&s.lights.lights)),
                    ("light_counts", b(&t.light_counts)),
                    ("light_indices", b(&t.light_indices)),
                    ("surface", T(&t.surface.1)),
                    ("normals", T(&t.normals.1)),
                    ("foam", T(&t.foam.1)),
                    ("data", T(&t.data.1)),
                    ("materials", b(&d.materials)),
                    ("material_map", T(&d.material_map)),
                    ("scene_hdr", T(&t.hdr.1)),
                    ("scene_depth", T(s.depth)),
                    ("output", T(s.output)),
                ],
            )?,
            hdr: s
                .hdr_layout
                .bind_group(device, "water", &[("scene_hdr", T(&t.hdr.1))])?,
        })
    }

    /// Records every water pass, after lighting.
    pub(crate) fn record(
        &self,
        e: &mut wgpu::CommandEncoder,
        f: &FrameContext<'_>,
        timer: &mut GpuTimer,
    ) {
        let (t, d, g, p) = (&self.targets, &self.data, &self.groups, &self.passes);
        e.clear_buffer(&t.tile_counts, 0, None);
        e.clear_buffer(&t.tile_args, 0, None);
        e.clear_buffer(&t.light_counters, 0, None);
        if !self.gbuffer_given {
            e.clear_buffer(&d.far_args, 0, None);
            e.clear_buffer(&d.stats, 0, None);
            {
                let mut pass = timer.begin_compute(e, "water hiz");
                p.visibility.record_hiz(&mut pass, &g.hiz);
            }
            p.visibility.record(e, g, d, timer);
            p.position.record(e, t, d, g, timer);
        }
        record_grid(e, &p.displacement, &g.displacement, t.size, timer);
        p.tiles.record(e, t, g, timer);
        // The depth with water starts as the opaque depth.
        e.copy_texture_to_texture(
            f.targets.depth.as_image_copy(),
            t.depth_water.0.as_image_copy(),
            t.depth_water.0.size(),
        );
        p.tessellation.record(e, t, g, timer);
        {
            let mut pass = timer.begin_compute(e, "water light tiles");
            let size = [f.targets.width, f.targets.height];
            p.tile_depth.record(&mut pass, &[&g.tile_depth], &size);
            let (tx, ty) = deferred::lights::tile_counts(size[0], size[1]);
            let dispatch = deferred::pass::LightCullParams {
                tiles: [tx, ty],
                ..Default::default()
            };
            p.cull.record(&mut pass, &[&g.cull], &dispatch);
        }
        let size = [f.targets.width, f.targets.height];
        record_grid(e, &p.normals, &g.normals, size, timer);
        record_grid(e, &p.foam, &g.foam, size, timer);
        record_grid(e, &p.composite, &g.composite, size, timer);
    }

    /// Sets this frame's decals (checked against the scene's textures and the limit).
    pub(crate) fn set_decals(&mut self, decals: &[WaterDecal]) -> Result<()> {
        if decals.len() as u64 > u64::from(MAX_WATER_DECALS) {
            return Err(crate::water_scene::limit(
                "water decals in a frame",
                decals.len() as u64,
                u64::from(MAX_WATER_DECALS),
                "MAX_WATER_DECALS",
            ));
        }
        self.data.decals_cpu = decals
            .iter()
            .map(|d| crate::water_scene::decal_record(d, &self.data.decal_textures))
            .collect::<Result<_>>()?;
        Ok(())
    }

    /// Reads the last frame's counters back.
    pub(crate) fn stats(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<WaterStats> {
        use crate::resources::readback::read_buffer;
        let words = |b: &wgpu::Buffer, bytes: u64| -> Result<Vec<u32>> {
            Ok(bytemuck::pod_collect_to_vec(&read_buffer(
                device, queue, b, 0, bytes,
            )?))
        };
        let stats = words(&self.data.stats, STAT_WORDS * 4)?;
        let args = words(&self.targets.tile_args, 20)?;
        let tiles_total = self.targets.tile_count();
        let counts = words(&self.targets.tile_counts, u64::from(tiles_total) * 4)?;
        let tiles = args[1].min(tiles_total);
        Ok(WaterStats {
            buffer: self.targets.size,
            half_precision: self.half,
            near_bodies: stats[STAT_NEAR],
            far_sectors: stats[STAT_FAR],
            nodes_tested: stats[STAT_NODES],
            water_pixels: counts.iter().map(|&c| u64::from(c)).sum(),
            tiles,
            tiles_total,
            triangles: u64::from(tiles) * u64::from(args[0] / 3),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shadercheck::{Caps, assert_struct_layout, members};

    #[test]
    fn structs_match_their_wgsl_twins() {
        let m = shadercheck::assert_composed(
            crate::shaders::LIBRARY,
            "gpu::water_frame",
            &[],
            Caps::CORE,
        );
        assert_struct_layout(
            &m,
            "GpuWaterFrame",
            size_of::<GpuWaterFrame>(),
            &members!(GpuWaterFrame {
                view_proj,
                inv_rotation,
                planes,
                camera,
                tan_half,
                size,
                grid,
                far,
                counts,
                sectors,
                shore,
                material_map,
                misc,
                normals,
                fbm,
                flow,
                foam,
                shore_size
            }),
        );
        assert_struct_layout(
            &m,
            "GpuWaterBody",
            size_of::<GpuWaterBody>(),
            &members!(GpuWaterBody {
                min,
                max,
                first_index,
                index_count,
                body,
                material
            }),
        );
        assert_struct_layout(
            &m,
            "GpuWaterDecal",
            size_of::<GpuWaterDecal>(),
            &members!(GpuWaterDecal {
                world_to_box,
                box_to_world,
                params,
                texture
            }),
        );
        let (size, _) = shadercheck::struct_layout(&m, "GpuWaterVertex").unwrap();
        assert_eq!(size, 32);
        let (size, _) = shadercheck::struct_layout(&m, "GpuWaterNode").unwrap();
        assert_eq!(size, 32);
        let u = |n: &str| shadercheck::const_u32(&m, n);
        assert_eq!(u("GPU_WATER_FLAG_FLOW"), Some(FLAG_FLOW));
        assert_eq!(u("GPU_WATER_FLAG_SHORE"), Some(FLAG_SHORE));
        assert_eq!(u("GPU_WATER_FLAG_SSR"), Some(FLAG_SSR));
        assert_eq!(u("GPU_WATER_FLAG_MATERIAL_MAP"), Some(FLAG_MATERIAL_MAP));
        use water::draw::{
            NODE_FLAT, NODE_MATERIAL_SHIFT, NODE_OCEAN, NODE_PURE, NODE_WATER, WATER_NO_MATERIAL,
        };
        assert_eq!(u("GPU_WATER_NODE_PURE"), Some(NODE_PURE));
        assert_eq!(
            u("GPU_WATER_NODE_MATERIAL_SHIFT"),
            Some(NODE_MATERIAL_SHIFT)
        );
        assert_eq!(u("GPU_WATER_NODE_WATER"), Some(NODE_WATER));
        assert_eq!(u("GPU_WATER_NODE_OCEAN"), Some(NODE_OCEAN));
        assert_eq!(u("GPU_WATER_NODE_FLAT"), Some(NODE_FLAT));
        assert_eq!(
            u("GPU_WATER_OCEAN_BODY"),
            Some(water::world::BodyId::OCEAN.0)
        );
        assert_eq!(u("GPU_WATER_NO_MATERIAL"), Some(WATER_NO_MATERIAL));
        assert_eq!(u("GPU_WATER_FAR_BODY"), Some(u32::MAX));
    }
}
