// gpu: FC5's displacement (seed 003): per mini G-buffer pixel with water, the high
// frequency surface shape from FBM with the talk's octave LOD (9 octaves near, fading to 3
// far, never 0: water::noise's `water_fbm_sample`, exact texel loads) at the pixel's world
// position, times its material's amplitude, plus the vector displacement decals:
// projected boxes, faded to zero at their edges, max-blended per component from a value
// cleared to -f32::MAX (the talk renders each box with a max blend; here every pixel
// loops over this frame's decals, the same arithmetic as water::decal's
// `combined_displacement`). Then the seam fix: where a pixel's neighbours within 8 pixels
// belong to another material or lie at another depth (two bodies meeting), the
// displacement is lowered towards the seam so the two meshes do not tear apart.
// Output: xyz the displacement (metres, +Y up), w the decals' foam; and each pixel's
// displaced point in the camera's clip space, the tessellation's vertex.

#import gpu::frame
#import gpu::water_frame
#import water::gbuffer
#import water::material
#import water::decal

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var<uniform> water: GpuWaterFrame;
@group(0) @binding(2) var data: texture_2d<u32>;
@group(0) @binding(3) var depth: texture_2d<f32>;
@group(0) @binding(4) var<storage, read> materials: array<WaterMaterialGpu>;
@group(0) @binding(5) var noise: texture_2d<f32>;
@group(0) @binding(6) var<storage, read> decals: array<GpuWaterDecal>;
@group(0) @binding(7) var decal_texels: texture_2d_array<f32>;
@group(0) @binding(8) var displacement: texture_storage_2d<rgba32float, write>;
// The tessellation's vertices, one per pixel (row-major): the displaced point in the
// camera's clip space, w <= 0 where there is no water. The talk's "we could do a compute
// pass which does all the ALU operations beforehand, and then we simply do a fetch from
// a buffer": the grid's vertex shader fetches three of these and nothing else.
@group(0) @binding(9) var<storage, read_write> vertices: array<vec4<f32>>;

// A pixel without water: its vertices kill their triangles.
const GPU_WATER_NO_VERTEX: vec4<f32> = vec4<f32>(0.0, 0.0, 0.0, -1.0);

fn gpu_water_store_vertex(p: vec2<u32>, v: vec4<f32>) {
    let at = p.y * water.size.z + p.x;
    if (at < arrayLength(&vertices)) {
        vertices[at] = v;
    }
}

// Texel (x, y) of layer `layer` clamped to the decal texture's own size `size`.
fn gpu_water_decal_texel(layer: u32, x: i32, y: i32, size: vec2<u32>) -> vec3<f32> {
    let dims = textureDimensions(decal_texels);
    let s = max(min(size, dims), vec2<u32>(1u));
    let c = vec2<u32>(clamp(vec2<i32>(x, y), vec2<i32>(0), vec2<i32>(s) - 1));
    let l = min(layer, textureNumLayers(decal_texels) - 1u);
    return textureLoad(decal_texels, c, l, 0).xyz;
}

// `DecalTexture::sample`: bilinear, texel centres at (i + 0.5) / size, clamped.
fn gpu_water_decal_sample(layer: u32, uv: vec2<f32>, size: vec2<u32>) -> vec3<f32> {
    let p = uv * vec2<f32>(size) - 0.5;
    let f = floor(p);
    let t = p - f;
    let x = i32(f.x);
    let y = i32(f.y);
    let a = mix(gpu_water_decal_texel(layer, x, y, size), gpu_water_decal_texel(layer, x + 1, y, size), t.x);
    let b = mix(gpu_water_decal_texel(layer, x, y + 1, size), gpu_water_decal_texel(layer, x + 1, y + 1, size), t.x);
    return mix(a, b, t.y);
}

// The decals' displacement at water-space (+Z up) point `p`: `combined_displacement`.
fn gpu_water_decals(p: vec3<f32>) -> vec3<f32> {
    var best = vec3<f32>(WATER_CLEAR_DISPLACEMENT);
    let n = min(water.far.w, arrayLength(&decals));
    for (var i = 0u; i < n; i++) {
        let d = decals[i];
        let local = (d.world_to_box * vec4<f32>(p, 1.0)).xyz;
        if (!water_decal_inside(local)) {
            continue;
        }
        let uv = water_decal_uv(local);
        // `sample_animated`: the two frames around the position, blended.
        let frames = max(d.texture.y, 1u);
        let fr = select(0.0, d.params.y, abs(d.params.y) < 1.0e30);
        let base = floor(fr);
        let t = fr - base;
        let i0 = u32(((i32(base) % i32(frames)) + i32(frames)) % i32(frames));
        let i1 = (i0 + 1u) % frames;
        let size = d.texture.zw;
        let v = mix(gpu_water_decal_sample(d.texture.x + i0, uv, size), gpu_water_decal_sample(d.texture.x + i1, uv, size), t);
        let w = water_decal_fade(local, d.params.z) * d.params.x;
        best = max(best, (d.box_to_world * vec4<f32>(v, 0.0)).xyz * w);
    }
    return water_decal_resolve(best);
}

// The world height (+Y) of mini G-buffer pixel `q` at view depth `d`.
fn gpu_water_height_at(q: vec2<i32>, d: f32) -> f32 {
    return gpu_water_relative(water, vec2<f32>(q) + 0.5, d, water.size.zw, water.tan_half.zw).y;
}

// Whether neighbour `q`, `r` pixels from a pixel of material `m` at height `y` whose
// pixels span `footprint` metres, is across a seam between two bodies: water of another
// material, or water at a height step steeper than a river's slope over that distance
// (a waterfall's foot, a river above a lake). The depth alone would not do: a plane seen
// at a grazing angle steps in depth from pixel to pixel.
fn gpu_water_seam_at(q: vec2<i32>, m: u32, y: f32, footprint: f32, r: f32) -> bool {
    let size = vec2<i32>(water.size.zw);
    if (any(q < vec2<i32>(0)) || any(q >= size)) {
        return false;
    }
    let w = textureLoad(data, q, 0).r;
    let dq = textureLoad(depth, q, 0).r;
    if (!water_data_is_valid(w) || !gpu_water_depth_ok(dq)) {
        return false;
    }
    let step = abs(gpu_water_height_at(q, dq) - y);
    return (w >> WATER_MATERIAL_SHIFT) != m || !(step <= 0.5 + 0.5 * footprint * r);
}

// How much of the displacement a pixel keeps: 1 from 8 pixels away from a seam, falling
// to 0 at one (the talk's "lowers the displacement ... then blur", as a falloff with the
// distance to the nearest seam found at 1, 2, 4 and 8 pixels).
fn gpu_water_seam(p: vec2<i32>, m: u32, d: f32) -> f32 {
    let y = gpu_water_height_at(p, d);
    // Metres per mini G-buffer pixel at this depth.
    let footprint = d * 2.0 * water.tan_half.w / f32(max(water.size.w, 1u));
    var r = 1;
    for (var k = 0u; k < 4u; k++) {
        let rf = f32(r);
        if (gpu_water_seam_at(p + vec2<i32>(r, 0), m, y, footprint, rf) || gpu_water_seam_at(p - vec2<i32>(r, 0), m, y, footprint, rf)
            || gpu_water_seam_at(p + vec2<i32>(0, r), m, y, footprint, rf) || gpu_water_seam_at(p - vec2<i32>(0, r), m, y, footprint, rf)) {
            return smoothstep(0.0, 8.0, rf - 1.0);
        }
        r *= 2;
    }
    return 1.0;
}

@compute @workgroup_size(8, 8)
fn displace(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = water.size.zw;
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let dims = min(textureDimensions(data), textureDimensions(depth));
    if (id.x >= dims.x || id.y >= dims.y) {
        textureStore(displacement, id.xy, vec4<f32>(0.0));
        gpu_water_store_vertex(id.xy, GPU_WATER_NO_VERTEX);
        return;
    }
    let word = textureLoad(data, id.xy, 0).r;
    let d = textureLoad(depth, id.xy, 0).r;
    if (!water_data_is_valid(word) || !gpu_water_depth_ok(d)) {
        textureStore(displacement, id.xy, vec4<f32>(0.0));
        gpu_water_store_vertex(id.xy, GPU_WATER_NO_VERTEX);
        return;
    }
    let rel = gpu_water_relative(water, vec2<f32>(id.xy) + 0.5, d, size, water.tan_half.zw);
    let p = rel + water.camera.xyz;
    let count = max(min(water.counts.x, arrayLength(&materials)), 1u);
    let m = min(word >> WATER_MATERIAL_SHIFT, count - 1u);
    let s = water_fbm_sample(noise, gpu_water_xy(p), length(rel), water.fbm);
    var total = vec3<f32>(0.0, s.height * materials[m].displacement_amplitude, 0.0);
    let decal = gpu_water_y_up(gpu_water_decals(gpu_water_z_up(p)));
    total += decal;
    let keep = gpu_water_seam(vec2<i32>(id.xy), word >> WATER_MATERIAL_SHIFT, d);
    let limit = vec3<f32>(max(water.shore.w, 0.0));
    let out = select(vec3<f32>(0.0), clamp(total * keep, -limit, limit), total == total);
    textureStore(displacement, id.xy, vec4<f32>(out, saturate(length(decal))));
    // The grid vertex at this pixel: the displaced point seen by the camera.
    let clip = frame.view_proj * vec4<f32>(rel + out, 1.0);
    let finite = all(abs(clip) < vec4<f32>(1.0e30));
    gpu_water_store_vertex(id.xy, select(GPU_WATER_NO_VERTEX, clip, finite && clip.w > 0.0));
}
