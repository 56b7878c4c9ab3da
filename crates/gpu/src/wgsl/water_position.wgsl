// gpu: FC5's position pass, the mini G-buffer (seed 003: "a mini G-buffer, which is a
// little bit lower resolution and a higher FOV, which defines the surface shape"). Every
// visible water body's low-resolution mesh (`vs_near`, one indexed indirect draw per body)
// and the far sectors (`vs_far`, one draw, an instance per visible sector, a grid whose
// heights come from the water query) are drawn from the water view into three targets:
// the data word (water::gbuffer: shader ID, valid / front face / lit flags, material,
// foam and algae mips), the mesh normal and the linear view depth, plus their own depth
// buffer. The fragment asks the water query (`water_world_query`, the same words the CPU
// reads) which body is there, so shores follow the baked world exactly and each pixel
// keeps the body that owns it; near meshes draw within the near radius, the far draw
// beyond it (and the ocean everywhere). Pixels hidden behind the opaque scene by more
// than the largest displacement are dropped, so tiles under terrain draw nothing.

#import gpu::frame
#import gpu::water_frame
#import water::world
#import water::gbuffer
#import water::material
#import staticscene::query

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var<uniform> water: GpuWaterFrame;
@group(0) @binding(2) var world: texture_2d<u32>;
@group(0) @binding(3) var<storage, read> materials: array<WaterMaterialGpu>;
@group(0) @binding(4) var<storage, read> vertices: array<GpuWaterVertex>;
@group(0) @binding(5) var<storage, read> nodes: array<GpuWaterNode>;
@group(0) @binding(6) var<storage, read> far_list: array<u32>;
// The HiZ of this frame's opaque depth (the camera's, reversed Z; staticscene's layout).
@group(0) @binding(7) var<storage, read> hiz: array<u32>;

// The level of `hiz` whose texels are 8x8 pixels.
const GPU_WATER_OCCLUSION_LEVEL: u32 = 3u;

// The farthest opaque depth over the 3x3 HiZ texels of GPU_WATER_OCCLUSION_LEVEL around
// camera pixel `px` (0: no HiZ, or sky there).
fn gpu_water_farthest_around(px: vec2<u32>) -> f32 {
    if (arrayLength(&hiz) < STATICSCENE_HIZ_HEADER_WORDS) {
        return 0.0;
    }
    let levels = min(hiz[0], STATICSCENE_HIZ_MAX_LEVELS);
    if (levels == 0u) {
        return 0.0;
    }
    let level = min(GPU_WATER_OCCLUSION_LEVEL, levels - 1u);
    let w = max(hiz[4u + 4u * level], 1u);
    let h = max(hiz[5u + 4u * level], 1u);
    let c = vec2<i32>(px >> vec2<u32>(level));
    var farthest = 3.0e38;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let t = vec2<u32>(clamp(c + vec2<i32>(dx, dy), vec2<i32>(0), vec2<i32>(i32(w) - 1, i32(h) - 1)));
            let at = hiz[6u + 4u * level] + t.y * w + t.x;
            farthest = min(farthest, bitcast<f32>(hiz[min(at, arrayLength(&hiz) - 1u)]));
        }
    }
    return farthest;
}

struct GpuWaterVarying {
    @builtin(position) clip: vec4<f32>,
    // camera-relative position
    @location(0) rel: vec3<f32>,
    @location(1) normal: vec3<f32>,
    // the near body's word, or GPU_WATER_FAR_BODY, or GPU_WATER_OCEAN_BODY for a far
    // sector of ocean alone (no query needed)
    @location(2) @interpolate(flat) body: u32,
    // a near body's or a pure ocean sector's material
    @location(3) @interpolate(flat) material: u32,
}

@vertex
fn vs_near(@builtin(vertex_index) vi: u32) -> GpuWaterVarying {
    let v = vertices[min(vi, arrayLength(&vertices) - 1u)];
    let rel = v.position - water.camera.xyz;
    return GpuWaterVarying(water.view_proj * vec4<f32>(rel, 1.0), rel, v.normal, v.body, v.material);
}

// Vertex `vi` of a far sector's grid of `quads` x `quads` quads: its corner in the
// sector's box (two counter-clockwise triangles per quad seen from above), at the water's
// height there (flat sectors at theirs; the others from the water query).
fn gpu_water_far_vertex(sector: u32, vi: u32, quads: u32) -> GpuWaterVarying {
    let side = max(water.far.x, 1u);
    let s = sector % (side * side);
    let quad = vi / 6u;
    var corner = array<vec2<u32>, 6>(vec2<u32>(0u, 0u), vec2<u32>(0u, 1u), vec2<u32>(1u, 1u), vec2<u32>(0u, 0u), vec2<u32>(1u, 1u), vec2<u32>(1u, 0u));
    let c = vec2<u32>(quad % quads, quad / quads) + corner[vi % 6u];
    let levels = clamp(water.far.y, 1u, 7u);
    let leaf = ((1u << (2u * (levels - 1u))) - 1u) / 3u + s;
    let node = nodes[min(leaf, arrayLength(&nodes) - 1u)];
    let xz = mix(node.min.xz, node.max.xz, vec2<f32>(c) / f32(quads));
    let flags = bitcast<u32>(node.min.w);
    var h = node.max.w;
    if ((flags & GPU_WATER_NODE_FLAT) == 0u) {
        let q = water_world_query(world, vec2<f32>(xz.x, -xz.y));
        h = select(node.min.y, q.height, q.found != 0u);
    }
    let rel = vec3<f32>(xz.x, h, xz.y) - water.camera.xyz;
    let pure = (flags & GPU_WATER_NODE_PURE) != 0u;
    let body = select(GPU_WATER_FAR_BODY, GPU_WATER_OCEAN_BODY, pure);
    return GpuWaterVarying(water.view_proj * vec4<f32>(rel, 1.0), rel, vec3<f32>(0.0, 1.0, 0.0), body, flags >> GPU_WATER_NODE_MATERIAL_SHIFT);
}

// The far draw of flat sectors (the talk's "flat water"): one quad each, from the front
// of the far list.
@vertex
fn vs_far_flat(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> GpuWaterVarying {
    let n = max(arrayLength(&far_list) / 2u, 1u);
    return gpu_water_far_vertex(far_list[min(ii, n - 1u)], vi % 6u, 1u);
}

// The far draw of height-map sectors (rivers, lakes and the ocean meeting): a grid each,
// from the back half of the far list.
@vertex
fn vs_far_height(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> GpuWaterVarying {
    let n = max(arrayLength(&far_list) / 2u, 1u);
    let quads = clamp(water.far.z, 1u, 64u);
    return gpu_water_far_vertex(far_list[n + min(ii, n - 1u)], vi, quads);
}

struct GpuWaterTargets {
    @location(0) data: u32,
    @location(1) normal: vec4<f32>,
    @location(2) depth: f32,
}

// Foam and algae noise frequencies for the mips the data word keeps (periods per metre of
// the noise texture): the foam pass's detail noise, and a 4x coarser algae layer.
fn gpu_water_foam_uv(p: vec2<f32>) -> vec2<f32> {
    return p * water.misc.z * 4.0;
}

@fragment
fn fs_position(in: GpuWaterVarying, @builtin(front_facing) front: bool) -> GpuWaterTargets {
    let p = in.rel + water.camera.xyz;
    let wp = gpu_water_xy(p);
    // The mips before any discard (derivatives need every invocation of the quad).
    let uv = gpu_water_foam_uv(wp);
    let tex = vec2<f32>(water.normals.w);
    let foam_mip = water_mip_level(dpdx(uv), dpdy(uv), tex);
    let algae_mip = water_mip_level(dpdx(uv * 0.25), dpdy(uv * 0.25), tex);
    let d = length(in.rel);
    // Hidden behind the opaque scene (beyond what displacement can lift) over the whole
    // neighbourhood a tessellated triangle can reach: no water here, and no tile. Only
    // there: a pixel dropped next to a silhouette would kill the triangles around it and
    // let the sky show between the water and the object. Tested first: it is cheap, the
    // water query is not.
    let clip = frame.view_proj * vec4<f32>(in.rel, 1.0);
    if (clip.w > 0.0) {
        let ndc = clip.xy / clip.w;
        if (all(abs(ndc) < vec2<f32>(1.0))) {
            let px = vec2<u32>((ndc * vec2<f32>(0.5, -0.5) + 0.5) * frame.viewport.xy);
            let ds = gpu_water_farthest_around(px);
            let view = gpu_water_view_depth(water, in.rel);
            let scene = select(3.0e38, water.camera.w / ds, ds > 0.0);
            if (view > scene + 2.0 * water.shore.w + 0.5) {
                discard;
            }
        }
    }
    var found = true;
    var body = in.body;
    var material = in.material;
    if (in.body != GPU_WATER_OCEAN_BODY) {
        // Which body the baked world says is here (the highest surface).
        let q = water_world_query(world, wp);
        found = q.found != 0u;
        body = q.body;
        material = q.material;
    }
    if (!found) {
        discard;
    }
    if (in.body == GPU_WATER_FAR_BODY) {
        // The far draw: the ocean everywhere, other water beyond the near radius.
        if (body != GPU_WATER_OCEAN_BODY && d < water.sectors.w) {
            discard;
        }
    } else if (in.body != GPU_WATER_OCEAN_BODY && (body != in.body || d >= water.sectors.w)) {
        discard;
    }
    let count = max(water.counts.x, 1u);
    material = min(material, count - 1u);
    let shader = materials[min(material, arrayLength(&materials) - 1u)].ids & WATER_SHADER_ID_MASK;
    var flags = WATER_FLAG_VALID | WATER_FLAG_LIT;
    if (front) {
        flags |= WATER_FLAG_FRONT_FACE;
    }
    var out: GpuWaterTargets;
    out.data = water_pack_data(shader, flags, material, foam_mip, algae_mip);
    out.normal = vec4<f32>(normalize(select(in.normal, vec3<f32>(0.0, 1.0, 0.0), dot(in.normal, in.normal) < 1e-12)), 1.0);
    out.depth = gpu_water_view_depth(water, in.rel);
    return out;
}
