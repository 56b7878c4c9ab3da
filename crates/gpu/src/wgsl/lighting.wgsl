// gpu: deferred lighting in compute (KZ2's sun + ambient + local lights over the
// G-buffer), then tone mapping into the sRGB-encoded output image. One 16x16 workgroup
// per light tile: each pixel reads its tile's light list (deferred's culling pass) and
// shades the lights whose volume holds it; with feature `all_lights`, every light is
// tested at every pixel instead (the reference the tiled path must equal). With feature
// `light_volumes`, the lights drawn as stencil volumes before (their sum in
// `light_accumulation`) are added. Local lights
// are in view space: the pixel's camera-relative position and normal are rotated into it
// (dot products, and so the shading, do not change). The sun is shadowed by its slice of
// the cascaded shadow maps (gpu::shadows) and the G-buffer's baked term, the darker of the
// two; its shader is skipped where the baked term is 0.
//
// With feature `msaa` the G-buffer and depth are the baseline's 4x multisampled targets
// and the output is the average of the samples' tone-mapped colours. KZ2's tricks (no
// `msaa_every_sample`): a pixel whose samples hold one surface is lit once, with the full
// PCF kernel; the others (edges) are appended to `msaa_edges` (wave-aggregated) and lit
// per sample by `edges`, an indirect dispatch sized by `edge_args`, each sample filtering
// the sun with its own disjoint subset of the PCF taps (deferred::msaa::split_taps).
// `msaa_every_sample`: every sample of every pixel lit with the full kernel (the
// measurement baseline).
//
// With feature `water` (a frame with FC5's water) the colour before tone mapping is also
// kept, in `scene_hdr`, for the water's refraction and reflections.

#import gpu::frame
#import gpu::gbuffer_load
#import deferred::lights
#import deferred::shadow
#import gpu::light_shading
#if msaa
#import wave::append
#endif

// Rust: gpu::shadows::GpuSunShadow (720 bytes).
struct GpuSunShadow {
    cascades: array<DeferredCascade, 8>,
    // cascades in use; 0: no real-time sun shadow
    count: u32,
    // texels per side of each map
    resolution: u32,
    pad: vec2<u32>,
    // per slice: its PCF radius in texels, at most GPU_MAX_PCF_RADIUS
    pcf_radius: array<vec4<u32>, 2>,
    // per slice: texels per side of its map, in the corner of its layer
    slice_texels: array<vec4<u32>, 2>,
}

// Rust: shadows::MAX_PCF_RADIUS.
const GPU_MAX_PCF_RADIUS: u32 = 2u;

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
#if msaa
@group(0) @binding(1) var depth_texture: texture_depth_multisampled_2d;
#else
// The float copy of the depth (`Targets::depth_float`): compute passes cannot write
// depth textures, and the compute laydown writes only this one.
@group(0) @binding(1) var depth_texture: texture_2d<f32>;
#endif
@group(0) @binding(2) var<uniform> local: GpuLocalLights;

// The depth at `pixel`, sample `s` of the multisampled depth with MSAA.
fn gpu_depth_at(pixel: vec2<i32>, s: i32) -> f32 {
#if msaa
    return textureLoad(depth_texture, pixel, s);
#else
    return textureLoad(depth_texture, pixel, 0).x;
#endif
}
@group(0) @binding(3) var<storage, read> lights: array<DeferredLight>;
@group(0) @binding(4) var<storage, read> light_counts: array<u32>;
@group(0) @binding(5) var<storage, read> light_indices: array<u32>;
@group(0) @binding(6) var shadow_map: texture_depth_2d_array;
@group(0) @binding(7) var<uniform> sun_shadow: GpuSunShadow;
@group(0) @binding(8) var output: texture_storage_2d<rgba8unorm, write>;
// The stencil light volumes' sum (read with feature `light_volumes`).
@group(0) @binding(9) var light_accumulation: texture_2d<f32>;
// The shadowed spots' maps and rows (spot_shadows.rs).
@group(0) @binding(10) var spot_shadow_map: texture_depth_2d_array;
@group(0) @binding(11) var<storage, read> spot_shadows: array<GpuSpotShadow>;
#if msaa
// Rust: passes::lighting::GpuPcfSplit (656 bytes). Per PCF radius r (0 ..=
// GPU_MAX_PCF_RADIUS), the (2r + 1)^2 box kernel split into per-sample subsets: sample s
// takes taps[first[r][s] .. first[r][s] + count[r][s]].
struct GpuPcfSplit {
    first: array<vec4<u32>, 3>,
    count: array<vec4<u32>, 3>,
    taps: array<DeferredPcfTap, GPU_PCF_SPLIT_TAPS>,
}

// Rust: resources::targets::MsaaTargets::edges. The edge pass's indirect arguments, the
// edge count, and the edge pixels (x | y << 16).
struct GpuMsaaEdges {
    dispatch: array<u32, 3>,
    count: atomic<u32>,
    pixels: array<u32>,
}

// Rust: passes::lighting::PCF_SPLIT_TAPS (1 + 9 + 25).
const GPU_PCF_SPLIT_TAPS: u32 = 35u;
// Edge pixels per workgroup of `edges` (its workgroup size).
const GPU_MSAA_EDGE_GROUP: u32 = 64u;
// Rust: shader::MAX_WORKGROUPS_X: the edge dispatch's rows.
const GPU_MAX_WORKGROUPS_X: u32 = 65535u;

@group(0) @binding(12) var<uniform> pcf_split: GpuPcfSplit;
@group(0) @binding(13) var<storage, read_write> msaa_edges: GpuMsaaEdges;
#endif
// Group 1: the G-buffer (gpu::gbuffer_load).
#if water
// FC5's water composites over the lit image (passes/water): the colour before tone
// mapping, which it refracts and reflects.
@group(2) @binding(0) var scene_hdr: texture_storage_2d<rgba16float, write>;
#endif

// Narkowicz's ACES fit.
fn lighting_tonemap(x: vec3<f32>) -> vec3<f32> {
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), vec3<f32>(0.0), vec3<f32>(1.0));
}

fn lighting_srgb(c: vec3<f32>) -> vec3<f32> {
    let lo = c * 12.92;
    let hi = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(hi, lo, c <= vec3<f32>(0.0031308));
}

// Where camera-relative `p` (normal `n`, view distance `dist`) falls in the sun's maps:
// the first cascade whose slice reaches `dist`, the point pushed 1.5 texels along its
// normal (against acne on slopes); `valid` false beyond the last slice, off the map, or
// with shadows off.
struct LightingSunCoord {
    valid: bool,
    layer: i32,
    // texel the kernel centres on, within the slice's map
    centre: vec2<i32>,
    // the slice's own resolution (KZ2: per slice), within its layer
    size: vec2<i32>,
    depth: f32,
    // the slice's PCF radius
    radius: u32,
}

fn lighting_sun_coord(p: vec3<f32>, n: vec3<f32>, dist: f32) -> LightingSunCoord {
    var out = LightingSunCoord(false, 0, vec2<i32>(0), vec2<i32>(1), 0.0, 0u);
    let count = min(sun_shadow.count, 8u);
    var k = 0u;
    while (k < count && dist > sun_shadow.cascades[k].split_far) {
        k += 1u;
    }
    if (k >= count || k >= textureNumLayers(shadow_map)) {
        return out;
    }
    let c = sun_shadow.cascades[k];
    let coord = deferred_shadow_coord(c, p + n * (1.5 * c.texel_size));
    let layer = vec2<i32>(textureDimensions(shadow_map));
    let size = min(vec2<i32>(i32(sun_shadow.slice_texels[k / 4u][k % 4u])), layer);
    if (!(all(coord.xy >= vec2<f32>(0.0)) && all(coord.xy < vec2<f32>(1.0)) && coord.z <= 1.0)) {
        return out;
    }
    out.valid = true;
    out.layer = i32(k);
    out.centre = vec2<i32>(coord.xy * vec2<f32>(size));
    out.size = size;
    out.depth = coord.z;
    out.radius = min(sun_shadow.pcf_radius[k / 4u][k % 4u], GPU_MAX_PCF_RADIUS);
    return out;
}

// Whether the sun reaches the map texel `offset` from the kernel's centre.
fn lighting_sun_tap(c: LightingSunCoord, offset: vec2<i32>) -> f32 {
    let t = clamp(c.centre + offset, vec2<i32>(0), c.size - 1);
    return select(0.0, 1.0, c.depth <= textureLoad(shadow_map, t, c.layer, 0));
}

// The sun's visibility at camera-relative `p`: a (2r + 1)^2 texel PCF of
// `depth <= stored` (0 nearest the sun) with the slice's radius r (KZ2: each slice its
// own tap count). 1 where `lighting_sun_coord` finds no map.
fn lighting_sun_visibility(p: vec3<f32>, n: vec3<f32>, dist: f32) -> f32 {
    let c = lighting_sun_coord(p, n, dist);
    if (!c.valid) {
        return 1.0;
    }
    let r = i32(c.radius);
    var lit = 0.0;
    for (var dy = -r; dy <= r; dy++) {
        for (var dx = -r; dx <= r; dx++) {
            lit += lighting_sun_tap(c, vec2<i32>(dx, dy));
        }
    }
    let side = f32(2 * r + 1);
    return lit / (side * side);
}

#if msaa
// The same with MSAA sample `sample`'s subset of the kernel's taps (KZ2's split): the
// samples' average filters with the whole kernel.
fn lighting_sun_visibility_sample(p: vec3<f32>, n: vec3<f32>, dist: f32, sample: u32) -> f32 {
    let c = lighting_sun_coord(p, n, dist);
    if (!c.valid) {
        return 1.0;
    }
    let r = min(c.radius, 2u);
    let first = pcf_split.first[r][sample % 4u];
    let count = min(pcf_split.count[r][sample % 4u], GPU_PCF_SPLIT_TAPS - min(first, GPU_PCF_SPLIT_TAPS));
    var lit = 0.0;
    for (var i = 0u; i < count; i++) {
        let tap = pcf_split.taps[first + i];
        lit += tap.weight * lighting_sun_tap(c, vec2<i32>(round(tap.offset)));
    }
    return lit;
}
#endif

#if !all_lights
// The tile's lights, staged once per workgroup (DEFERRED_MAX_LIGHTS_PER_TILE is the
// workgroup's size: one load per invocation), as three vec4 arrays so that the sphere
// test reads one vector and only lights that reach the pixel read the rest.
var<workgroup> lighting_pos_range: array<vec4<f32>, DEFERRED_MAX_LIGHTS_PER_TILE>;
var<workgroup> lighting_dir_cos: array<vec4<f32>, DEFERRED_MAX_LIGHTS_PER_TILE>;
var<workgroup> lighting_color_flags: array<vec4<f32>, DEFERRED_MAX_LIGHTS_PER_TILE>;
var<workgroup> lighting_tile_count: u32;
#endif

// Local light `l` at `at`, shadowed through its spot map if it has one this frame.
fn lighting_local_light(l: DeferredLight, at: LightShadingPoint, s: DeferredSurface) -> vec3<f32> {
    let c = light_shading_local(l, at, s);
    let slot = light_shading_shadow_slot(l);
    if (slot == 0u || slot > arrayLength(&spot_shadows) || !any(c > vec3<f32>(0.0))) {
        return c;
    }
    return c * light_shading_spot_visibility(spot_shadow_map, spot_shadows[slot - 1u], slot - 1u, l, at);
}

// Every light tested at `at` (feature `all_lights`: the reference).
fn lighting_every_light(light_count: u32, at: LightShadingPoint, s: DeferredSurface) -> vec3<f32> {
    var color = vec3<f32>(0.0);
    for (var i = 0u; i < light_count; i++) {
        let l = lights[i];
        if (light_shading_in_sphere(vec4<f32>(l.position, l.range), at.p)) {
            color += lighting_local_light(l, at, s);
        }
    }
    return color;
}

#if !all_lights
// The `count` lights staged for the workgroup's tile.
fn lighting_staged_lights(count: u32, at: LightShadingPoint, s: DeferredSurface) -> vec3<f32> {
    var color = vec3<f32>(0.0);
    for (var k = 0u; k < count; k++) {
        let pr = lighting_pos_range[k];
        if (!light_shading_in_sphere(pr, at.p)) {
            continue;
        }
        let dc = lighting_dir_cos[k];
        let cf = lighting_color_flags[k];
        let l = DeferredLight(pr.xyz, pr.w, dc.xyz, dc.w, cf.xyz, bitcast<u32>(cf.w));
        color += lighting_local_light(l, at, s);
    }
    return color;
}
#endif

// A lit sample's colour before local lights, and where they shade it.
struct LightingBase {
    color: vec3<f32>,
    at: LightShadingPoint,
}

// Sun (the baked term and the real-time shadow; `taps`: the MSAA sample whose subset of
// the PCF kernel filters it, or 4 or more for the whole kernel), ambient, the G-buffer's
// own lighting and (feature `light_volumes`) the volumes' sum, at image point `xy` (in
// `pixel`) of depth `d`.
fn lighting_base(pixel: vec2<u32>, xy: vec2<f32>, d: f32, s: DeferredSurface, taps: u32) -> LightingBase {
    let p = light_shading_position_at(frame.inv_view_proj, frame.viewport.zw, xy, d);
    let at = light_shading_point(local.view_rotation, p, s);
    let v = normalize(-p);
    let n = s.normal;
    let l = frame.sun_direction.xyz;
    let nl = max(dot(n, l), 0.0);
    // The geometry pass's own term: ambient (with occlusion) and emission (gpu::material).
    var color = s.lighting;
    // KZ2's mix of the baked sun term and the real-time shadow: the darker of the two;
    // the sun's shader is skipped where the baked term is 0 (fully in baked shadow) or
    // the surface faces away.
    var sun = s.sun_shadow;
    if (sun > 0.0 && nl > 0.0) {
#if msaa
        if (taps < 4u) {
            sun = min(sun, lighting_sun_visibility_sample(p, n, -at.p.z, taps));
        } else {
            sun = min(sun, lighting_sun_visibility(p, n, -at.p.z));
        }
#else
        sun = min(sun, lighting_sun_visibility(p, n, -at.p.z));
#endif
    }
    color += frame.sun_color.rgb * (at.diffuse * nl * sun + light_shading_surface_specular(n, v, l, s) * sun);
#if light_volumes
    // The lights the stencil volumes drew (passes::light_volumes), summed there.
    color += textureLoad(light_accumulation, vec2<i32>(pixel), 0).rgb;
#endif
    return LightingBase(color, at);
}

#if msaa
// Vulkan's (and D3D's) standard 4x sample positions, as an image point in `pixel`. They
// are symmetric about the pixel's centre: the mean of a plane's four sample depths is its
// depth at the centre.
fn lighting_sample_xy(pixel: vec2<u32>, sample: u32) -> vec2<f32> {
    var at = array<vec2<f32>, 4>(vec2<f32>(0.375, 0.125), vec2<f32>(0.875, 0.375), vec2<f32>(0.125, 0.625), vec2<f32>(0.625, 0.875));
    return vec2<f32>(pixel) + at[sample % 4u];
}

// The pixel's sample `sample` of depth `d` (at its own position in the pixel), lit with
// the workgroup's staged lights (`staged` of them) or every light; tone mapped. Sky where
// `d` is 0.
fn lighting_pixel_sample(pixel: vec2<u32>, sample: u32, d: f32, taps: u32, light_count: u32, staged: u32) -> vec3<f32> {
    if (d <= 0.0) {
        return lighting_tonemap(frame.sky.rgb);
    }
    let s = gbuffer_unpack(gbuffer_texels(pixel, sample), frame.view_rotation);
    let b = lighting_base(pixel, lighting_sample_xy(pixel, sample), d, s, taps);
#if all_lights
    return lighting_tonemap(b.color + lighting_every_light(light_count, b.at, s));
#else
    return lighting_tonemap(b.color + lighting_staged_lights(staged, b.at, s));
#endif
}
#endif

#if msaa
// A pixel's samples as KZ2's edge test sees them.
struct LightingMsaaPixel {
    // some sample holds another surface than sample 0
    edge: bool,
    // the mean of the samples' depths: an interior pixel's depth at its centre
    depth: f32,
    // sample 0's surface (where it is geometry): what an interior pixel is lit with
    surface: DeferredSurface,
}

// KZ2's edge test: a sample is another surface than sample 0 when one of them is sky and
// the other not, any G-buffer bit differs, or it lies off sample 0's plane (the plane of
// its normal) by more than a pixel's width there (a relative depth tolerance would flag
// every pixel of a surface seen at a grazing angle).
fn lighting_msaa_pixel(pixel: vec2<u32>, d0: f32) -> LightingMsaaPixel {
    let t0 = gbuffer_texels(pixel, 0u);
    var s0: DeferredSurface;
    var p0 = vec3<f32>(0.0);
    var width = 0.0;
    let xy0 = lighting_sample_xy(pixel, 0u);
    if (d0 > 0.0) {
        s0 = gbuffer_unpack(t0, frame.view_rotation);
        p0 = light_shading_position_at(frame.inv_view_proj, frame.viewport.zw, xy0, d0);
        width = distance(light_shading_position_at(frame.inv_view_proj, frame.viewport.zw, xy0 + vec2<f32>(1.0, 0.0), d0), p0);
    }
    let n0 = s0.normal;
    var out = LightingMsaaPixel(false, d0, s0);
    let samples = textureNumSamples(depth_texture);
    for (var s = 1u; s < samples; s++) {
        let d = gpu_depth_at(vec2<i32>(pixel), i32(s));
        out.depth += d;
        if ((d > 0.0) != (d0 > 0.0)) {
            out.edge = true;
        } else if (d > 0.0) {
            let p = light_shading_position_at(frame.inv_view_proj, frame.viewport.zw, lighting_sample_xy(pixel, s), d);
            let off_plane = !(abs(dot(p - p0, n0)) <= width);
            if (off_plane || gbuffer_texels_differ(t0, gbuffer_texels(pixel, s))) {
                out.edge = true;
            }
        }
    }
    out.depth /= f32(max(samples, 1u));
    return out;
}
#endif

@compute @workgroup_size(16, 16)
fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) li: u32) {
    let light_count = min(frame.local_light_count, arrayLength(&lights));
#if !all_lights
    // Staging first (a chain of three loads: count, index, light), then the pixel's own
    // loads and the sun, so that the two overlap before the barrier. Every invocation
    // takes part, whether its pixel exists or holds geometry.
    let tile = wid.y * local.tiles.x + wid.x;
    var count = 0u;
    if (tile < arrayLength(&light_counts)) {
        count = min(light_counts[tile], DEFERRED_MAX_LIGHTS_PER_TILE);
    }
    let slot = tile * DEFERRED_MAX_LIGHTS_PER_TILE + li;
    if (li < count && slot < arrayLength(&light_indices)) {
        let i = light_indices[slot];
        let l = lights[min(i, max(light_count, 1u) - 1u)];
        // A corrupt index stages a light that lights nothing.
        let range = select(0.0, l.range, i < light_count);
        lighting_pos_range[li] = vec4<f32>(l.position, range);
        lighting_dir_cos[li] = vec4<f32>(l.direction, l.cos_outer);
        lighting_color_flags[li] = vec4<f32>(l.color, bitcast<f32>(l.flags));
    }
    if (li == 0u) {
        lighting_tile_count = count;
    }
#endif
    let size = vec2<u32>(frame.viewport.xy);
    let inside = id.x < size.x && id.y < size.y;
    let pixel = min(id.xy, max(size, vec2<u32>(1u)) - 1u);
    let d = gpu_depth_at(vec2<i32>(pixel), 0);
    var write = inside;
#if msaa
#if !msaa_every_sample
    // KZ2: edge pixels go to the list (one atomic per wave), lit per sample by `edges`;
    // the others once, at their centre's depth.
    let m = lighting_msaa_pixel(pixel, d);
    let edge = inside && m.edge;
    let d_lit = m.depth;
    let a = wave_append_begin(edge, li);
    var old = 0u;
    if (a.total != 0u) {
        old = atomicAdd(&msaa_edges.count, a.total);
    }
    let at = wave_append_end(a, old);
    if (edge && at < arrayLength(&msaa_edges.pixels)) {
        msaa_edges.pixels[at] = pixel.x | (pixel.y << 16u);
    }
    write = inside && !edge;
#else
    let d_lit = d;
#endif
#else
    let d_lit = d;
#endif
#if msaa_every_sample
#if all_lights
    let staged = 0u;
#else
    let staged = workgroupUniformLoad(&lighting_tile_count);
#endif
    var out = vec3<f32>(0.0);
    if (write) {
        let samples = textureNumSamples(depth_texture);
        for (var s = 0u; s < samples; s++) {
            let ds = gpu_depth_at(vec2<i32>(pixel), i32(s));
            out += lighting_pixel_sample(pixel, s, ds, 4u, light_count, staged);
        }
        out /= f32(max(samples, 1u));
    }
#else
    // The pixel's G-buffer and sun before the staging barrier, so that they overlap.
    let lit = write && d_lit > 0.0;
    var s: DeferredSurface;
    var b = LightingBase(frame.sky.rgb, LightShadingPoint(vec3<f32>(0.0), vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(0.0)));
    if (lit) {
#if msaa
        // Unpacked by the edge test.
        s = m.surface;
#else
        s = gbuffer_surface(pixel, frame.view_rotation);
#endif
        b = lighting_base(pixel, vec2<f32>(pixel) + 0.5, d_lit, s, 4u);
    }
#if all_lights
    if (lit) {
        b.color += lighting_every_light(light_count, b.at, s);
    }
#else
    let staged = workgroupUniformLoad(&lighting_tile_count);
    if (lit) {
        b.color += lighting_staged_lights(staged, b.at, s);
    }
#endif
    let out = lighting_tonemap(b.color);
#if water
    if (write) {
        textureStore(scene_hdr, vec2<i32>(pixel), vec4<f32>(b.color, 1.0));
    }
#endif
#endif
    if (write) {
        textureStore(output, vec2<i32>(pixel), vec4<f32>(lighting_srgb(out), 1.0));
    }
}

#if msaa
// The edge count as `edges`' indirect arguments: rows of GPU_MAX_WORKGROUPS_X workgroups.
@compute @workgroup_size(1)
fn edge_args() {
    let count = min(atomicLoad(&msaa_edges.count), arrayLength(&msaa_edges.pixels));
    let groups = (count + GPU_MSAA_EDGE_GROUP - 1u) / GPU_MSAA_EDGE_GROUP;
    msaa_edges.dispatch[0] = min(groups, GPU_MAX_WORKGROUPS_X);
    msaa_edges.dispatch[1] = (groups + GPU_MAX_WORKGROUPS_X - 1u) / GPU_MAX_WORKGROUPS_X;
    msaa_edges.dispatch[2] = 1u;
}

// The tile list's lights at `at`, read from the lists (no staging: an edge pixel's
// neighbours in the dispatch are other tiles' edges).
fn lighting_tile_lights(tile: u32, light_count: u32, at: LightShadingPoint, s: DeferredSurface) -> vec3<f32> {
    var color = vec3<f32>(0.0);
    if (tile >= arrayLength(&light_counts)) {
        return color;
    }
    let count = min(light_counts[tile], DEFERRED_MAX_LIGHTS_PER_TILE);
    for (var k = 0u; k < count; k++) {
        let slot = tile * DEFERRED_MAX_LIGHTS_PER_TILE + k;
        if (slot >= arrayLength(&light_indices)) {
            break;
        }
        let i = light_indices[slot];
        if (i >= light_count) {
            continue;
        }
        let l = lights[i];
        if (light_shading_in_sphere(vec4<f32>(l.position, l.range), at.p)) {
            color += lighting_local_light(l, at, s);
        }
    }
    return color;
}

// KZ2's per-sample lighting of the edge pixels: each sample with its own PCF taps, the
// pixel the average of the samples' tone-mapped colours.
@compute @workgroup_size(GPU_MSAA_EDGE_GROUP)
fn edges(@builtin(workgroup_id) wid: vec3<u32>, @builtin(local_invocation_index) li: u32) {
    let item = (wid.y * GPU_MAX_WORKGROUPS_X + wid.x) * GPU_MSAA_EDGE_GROUP + li;
    let count = min(atomicLoad(&msaa_edges.count), arrayLength(&msaa_edges.pixels));
    if (item >= count) {
        return;
    }
    let word = msaa_edges.pixels[item];
    let pixel = vec2<u32>(word & 0xffffu, word >> 16u);
    if (any(pixel >= vec2<u32>(frame.viewport.xy))) {
        return;
    }
    let light_count = min(frame.local_light_count, arrayLength(&lights));
    let tile = (pixel.y / DEFERRED_TILE_SIZE) * local.tiles.x + pixel.x / DEFERRED_TILE_SIZE;
    let samples = textureNumSamples(depth_texture);
    var out = vec3<f32>(0.0);
    for (var sample = 0u; sample < samples; sample++) {
        let d = gpu_depth_at(vec2<i32>(pixel), i32(sample));
        if (d <= 0.0) {
            out += lighting_tonemap(frame.sky.rgb);
            continue;
        }
        let s = gbuffer_unpack(gbuffer_texels(pixel, sample), frame.view_rotation);
        let b = lighting_base(pixel, lighting_sample_xy(pixel, sample), d, s, sample);
#if all_lights
        out += lighting_tonemap(b.color + lighting_every_light(light_count, b.at, s));
#else
        out += lighting_tonemap(b.color + lighting_tile_lights(tile, light_count, b.at, s));
#endif
    }
    out /= f32(max(samples, 1u));
    textureStore(output, vec2<i32>(pixel), vec4<f32>(lighting_srgb(out), 1.0));
}
#endif
