use crate::error::Result;
use crate::passes::water::rows::GRID_QUADS;
use crate::resources::targets::DEPTH_FORMAT;
use crate::resources::targets::texture;
use wgpu::util::DeviceExt;
/// The mini G-buffer's size for an image of `width` x `height` at `scale`.
pub(crate) fn buffer_size(width: u32, height: u32, scale: f32) -> [u32; 2] {
    [
        ((width as f32 * scale).round() as u32).clamp(1, water::tiles::MAX_BUFFER_SIZE),
        ((height as f32 * scale).round() as u32).clamp(1, water::tiles::MAX_BUFFER_SIZE),
    ]
}

/// Textures and buffers sized by the image (and the mini G-buffer).
pub(crate) struct WaterTargets {
    /// The mini G-buffer's size.
    pub size: [u32; 2],
    pub data: (wgpu::Texture, wgpu::TextureView),
    pub normal: (wgpu::Texture, wgpu::TextureView),
    pub linear: (wgpu::Texture, wgpu::TextureView),
    pub depth: wgpu::TextureView,
    pub displacement: (wgpu::Texture, wgpu::TextureView),
    /// The tessellation's vertices: per mini G-buffer pixel the displaced point in clip
    /// space (the displacement pass writes them).
    pub vertices: wgpu::Buffer,
    /// The depth with water (full resolution).
    pub depth_water: (wgpu::Texture, wgpu::TextureView),
    /// The tessellation's view depth and mini G-buffer UV (full resolution).
    pub surface: (wgpu::Texture, wgpu::TextureView),
    pub normals: (wgpu::Texture, wgpu::TextureView),
    pub foam: (wgpu::Texture, wgpu::TextureView),
    /// Lighting's HDR colour before tone mapping.
    pub hdr: (wgpu::Texture, wgpu::TextureView),
    /// The water's light tiles.
    pub tile_depths: wgpu::Buffer,
    pub light_counts: wgpu::Buffer,
    pub light_indices: wgpu::Buffer,
    pub light_counters: wgpu::Buffer,
    /// Tiles of the mini G-buffer: counts, list, and the grid's indexed indirect args.
    pub tile_counts: wgpu::Buffer,
    pub tile_list: wgpu::Buffer,
    pub tile_args: wgpu::Buffer,
    /// The grid's 16-bit vertex words, as an index buffer.
    pub grid: wgpu::Buffer,
    pub tiles: [u32; 2],
}

pub(crate) fn storage(
    device: &wgpu::Device,
    label: &str,
    bytes: u64,
    extra: wgpu::BufferUsages,
) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.max(16).next_multiple_of(4),
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC
            | extra,
        mapped_at_creation: false,
    })
}

pub(crate) fn init(
    device: &wgpu::Device,
    label: &str,
    bytes: &[u8],
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    crate::resources::buffers::buffer_init(
        device,
        label,
        bytes,
        16,
        usage | wgpu::BufferUsages::STORAGE,
    )
}

impl WaterTargets {
    pub(crate) fn new(device: &wgpu::Device, width: u32, height: u32, scale: f32) -> Result<Self> {
        use wgpu::TextureUsages as U;
        let size = buffer_size(width, height, scale);
        let [w, h] = size;
        let rw = U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC | U::COPY_DST;
        let sw = U::STORAGE_BINDING | U::TEXTURE_BINDING | U::COPY_SRC | U::COPY_DST;
        let grid = water::tiles::TileGrid::new(w, h, water::tiles::TILE_SIZE)?;
        let tiles = [grid.tiles_x(), grid.tiles_y()];
        let tile_count = u64::from(grid.tile_count());
        let mesh = water::tiles::GridMesh::new(GRID_QUADS)?;
        let (ltx, lty) = deferred::lights::tile_counts(width, height);
        let light_tiles = u64::from(ltx) * u64::from(lty);
        Ok(Self {
            size,
            data: texture(device, "water data", w, h, wgpu::TextureFormat::R32Uint, rw),
            normal: texture(
                device,
                "water mesh normal",
                w,
                h,
                wgpu::TextureFormat::Rgba16Float,
                rw,
            ),
            linear: texture(
                device,
                "water view depth",
                w,
                h,
                wgpu::TextureFormat::R32Float,
                rw,
            ),
            depth: texture(
                device,
                "water position depth",
                w,
                h,
                DEPTH_FORMAT,
                U::RENDER_ATTACHMENT,
            )
            .1,
            displacement: texture(
                device,
                "water displacement",
                w,
                h,
                wgpu::TextureFormat::Rgba32Float,
                sw,
            ),
            vertices: storage(
                device,
                "water grid vertices",
                u64::from(w) * u64::from(h) * 16,
                wgpu::BufferUsages::empty(),
            ),
            depth_water: texture(
                device,
                "depth with water",
                width,
                height,
                DEPTH_FORMAT,
                U::RENDER_ATTACHMENT | U::TEXTURE_BINDING | U::COPY_SRC | U::COPY_DST,
            ),
            surface: texture(
                device,
                "water surface",
                width,
                height,
                wgpu::TextureFormat::Rgba32Float,
                rw,
            ),
            normals: texture(
                device,
                "water normals",
                width,
                height,
                wgpu::TextureFormat::Rgba16Float,
                sw,
            ),
            foam: texture(
                device,
                "water foam",
                width,
                height,
                wgpu::TextureFormat::R32Float,
                sw,
            ),
            hdr: texture(
                device,
                "scene hdr",
                width,
                height,
                wgpu::TextureFormat::Rgba16Float,
                sw,
            ),
            tile_depths: storage(
                device,
                "water light tile depths",
                light_tiles * 8,
                wgpu::BufferUsages::empty(),
            ),
            light_counts: storage(
                device,
                "water light counts",
                light_tiles * 4,
                wgpu::BufferUsages::empty(),
            ),
            light_indices: storage(
                device,
                "water light indices",
                light_tiles * u64::from(deferred::lights::MAX_LIGHTS_PER_TILE) * 4,
                wgpu::BufferUsages::empty(),
            ),
            light_counters: storage(
                device,
                "water light counters",
                size_of::<deferred::pass::LightCullCounters>() as u64,
                wgpu::BufferUsages::empty(),
            ),
            tile_counts: storage(
                device,
                "water tile counts",
                tile_count * 4,
                wgpu::BufferUsages::empty(),
            ),
            tile_list: storage(
                device,
                "water tile list",
                tile_count * 4,
                wgpu::BufferUsages::empty(),
            ),
            tile_args: storage(device, "water tile args", 20, wgpu::BufferUsages::INDIRECT),
            grid: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("water grid words"),
                contents: bytemuck::cast_slice(&pad_even(mesh.vertices())),
                usage: wgpu::BufferUsages::INDEX,
            }),
            tiles,
        })
    }

    /// Tiles of the mini G-buffer.
    pub(crate) fn tile_count(&self) -> u32 {
        self.tiles[0] * self.tiles[1]
    }
}

/// `words` padded to an even count (buffers are whole words).
fn pad_even(words: &[u16]) -> Vec<u16> {
    let mut v = words.to_vec();
    if v.len() % 2 == 1 {
        v.push(0);
    }
    v
}
