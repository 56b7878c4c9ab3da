// water: integer hashing, the tileable noise texture and FBM with octave LOD.
// Twin of `water::hash` and `water::noise`; constants are tied to Rust by unit tests.

const WATER_MAX_OCTAVES: u32 = 16u;
const WATER_OCTAVE_SEED: u32 = 24301u;
const WATER_NOISE_SCALE: f32 = 1.4142135;

// PCG hash (Jarzynski and Olano 2020).
fn water_pcg(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

fn water_hash2(x: u32, y: u32) -> u32 {
    return water_pcg(x + water_pcg(y));
}

fn water_hash3(x: u32, y: u32, z: u32) -> u32 {
    return water_pcg(x + water_pcg(y + water_pcg(z)));
}

// Top 24 bits to [0, 1).
fn water_hash_unit(h: u32) -> f32 {
    return f32(h >> 8u) * (1.0 / 16777216.0);
}

fn water_quintic(t: f32) -> f32 {
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

fn water_gradient(h: u32) -> vec2<f32> {
    let d = 0.70710677;
    switch (h >> 29u) {
        case 0u: { return vec2<f32>(1.0, 0.0); }
        case 1u: { return vec2<f32>(d, d); }
        case 2u: { return vec2<f32>(0.0, 1.0); }
        case 3u: { return vec2<f32>(-d, d); }
        case 4u: { return vec2<f32>(-1.0, 0.0); }
        case 5u: { return vec2<f32>(-d, -d); }
        case 6u: { return vec2<f32>(0.0, -1.0); }
        default: { return vec2<f32>(d, -d); }
    }
}

// Periodic gradient noise at lattice coordinates p, period `cells` (a power of two),
// scaled by sqrt(2) and clamped to [-1, 1]: `water::noise::periodic_gradient_noise`.
fn water_periodic_gradient_noise(p: vec2<f32>, cells: u32, seed: u32) -> f32 {
    let fl = floor(p);
    let t = p - fl;
    let m = cells - 1u;
    let ix = bitcast<u32>(i32(fl.x)) & m;
    let iy = bitcast<u32>(i32(fl.y)) & m;
    let ix1 = (ix + 1u) & m;
    let iy1 = (iy + 1u) & m;
    let n00 = dot(water_gradient(water_hash3(ix, iy, seed)), t);
    let n10 = dot(water_gradient(water_hash3(ix1, iy, seed)), t - vec2<f32>(1.0, 0.0));
    let n01 = dot(water_gradient(water_hash3(ix, iy1, seed)), t - vec2<f32>(0.0, 1.0));
    let n11 = dot(water_gradient(water_hash3(ix1, iy1, seed)), t - vec2<f32>(1.0, 1.0));
    let u = water_quintic(t.x);
    let v = water_quintic(t.y);
    let a = n00 + (n10 - n00) * u;
    let b = n01 + (n11 - n01) * u;
    return clamp((a + (b - a) * v) * WATER_NOISE_SCALE, -1.0, 1.0);
}

// Texel (i, j) of a size x size noise texture with `cells` lattice cells: what
// `NoiseTexture::generate` bakes, for a compute pass that makes the texture on the GPU.
fn water_noise_texel(i: u32, j: u32, size: u32, cells: u32, seed: u32) -> f32 {
    let scale = f32(cells) / f32(size);
    return water_periodic_gradient_noise(vec2<f32>(f32(i) * scale, f32(j) * scale), cells, seed);
}

// fract(u) * 2^32: the position in 2^-32 texture periods.
fn water_to_fixed(u: f32) -> u32 {
    return u32((u - floor(u)) * 4294967296.0);
}

fn water_octave_offset(octave: u32, axis: u32) -> u32 {
    return water_pcg(octave * 2u + axis + WATER_OCTAVE_SEED);
}

// Bilinear sample at fixed-point (x, y) with four loads: (value, d/dx, d/dy) per texel,
// the same expression as the CPU's precomputed coefficients.
fn water_noise_bilinear(tex: texture_2d<f32>, x: u32, y: u32) -> vec3<f32> {
    let size = textureDimensions(tex).x;
    let bits = countTrailingZeros(size);
    let s = 32u - bits;
    let m = size - 1u;
    let ix = x >> s;
    let iy = y >> s;
    let tx = f32((x << bits) >> 8u) * (1.0 / 16777216.0);
    let ty = f32((y << bits) >> 8u) * (1.0 / 16777216.0);
    let v00 = textureLoad(tex, vec2<u32>(ix, iy), 0).r;
    let v10 = textureLoad(tex, vec2<u32>((ix + 1u) & m, iy), 0).r;
    let v01 = textureLoad(tex, vec2<u32>(ix, (iy + 1u) & m), 0).r;
    let v11 = textureLoad(tex, vec2<u32>((ix + 1u) & m, (iy + 1u) & m), 0).r;
    let c1 = v10 - v00;
    let c2 = v01 - v00;
    let c3 = (v11 - v01) - (v10 - v00);
    let ddy = c2 + c3 * tx;
    return vec3<f32>(v00 + c1 * tx + ddy * ty, c1 + c3 * ty, ddy);
}

// `FbmParams` plus the texture's slope variance (`Fbm::gpu_params`), 32 bytes.
struct WaterFbmParams {
    frequency: f32,
    amplitude: f32,
    gain: f32,
    lod_distance: f32,
    octaves_near: u32,
    octaves_far: u32,
    slope_variance: f32,
    _pad: u32,
}

// `Fbm::sample`'s result.
struct WaterFbmSample {
    height: f32,
    gradient: vec2<f32>,
    dropped_variance: f32,
    octaves: f32,
}

// Height (metres) at p (metres) with all near octaves: `Fbm::height`.
fn water_fbm(tex: texture_2d<f32>, p: vec2<f32>, prm: WaterFbmParams) -> f32 {
    let x = water_to_fixed(p.x * prm.frequency);
    let y = water_to_fixed(p.y * prm.frequency);
    var h = 0.0;
    var a = prm.amplitude;
    let n = min(prm.octaves_near, WATER_MAX_OCTAVES);
    for (var k = 0u; k < n; k++) {
        let v = water_noise_bilinear(tex, (x << k) + water_octave_offset(k, 0u), (y << k) + water_octave_offset(k, 1u)).x;
        h += a * v;
        a *= prm.gain;
    }
    return h;
}

// The continuous octave count at a view distance: `Fbm::octave_count`.
fn water_fbm_octave_count(distance: f32, prm: WaterFbmParams) -> f32 {
    let near = f32(prm.octaves_near);
    let far = f32(prm.octaves_far);
    let d0 = prm.lod_distance;
    let d = select(d0, distance, distance > d0);
    return clamp(near - log2(d / d0), far, near);
}

// Height, gradient and dropped slope variance with the octave LOD: `Fbm::sample`.
fn water_fbm_sample(tex: texture_2d<f32>, p: vec2<f32>, distance: f32, prm: WaterFbmParams) -> WaterFbmSample {
    let c = water_fbm_octave_count(distance, prm);
    let x = water_to_fixed(p.x * prm.frequency);
    let y = water_to_fixed(p.y * prm.frequency);
    var out = WaterFbmSample(0.0, vec2<f32>(0.0), 0.0, c);
    var a = prm.amplitude;
    var fr = prm.frequency;
    var f = prm.frequency * f32(textureDimensions(tex).x);
    let n = min(prm.octaves_near, WATER_MAX_OCTAVES);
    for (var k = 0u; k < n; k++) {
        let w = saturate(c - f32(k));
        if (w > 0.0) {
            let s = water_noise_bilinear(tex, (x << k) + water_octave_offset(k, 0u), (y << k) + water_octave_offset(k, 1u));
            let aw = a * w;
            out.height += aw * s.x;
            out.gradient += vec2<f32>(s.y, s.z) * (aw * f);
        }
        let af = a * fr;
        out.dropped_variance += (1.0 - w * w) * (af * af * prm.slope_variance);
        a *= prm.gain;
        fr *= 2.0;
        f *= 2.0;
    }
    return out;
}

// Height with the sampler's bilinear filtering, one fetch per octave as in the talk
// (upload the texels as R16Float, or R32Float with FLOAT32_FILTERABLE; repeat addressing,
// linear filtering). Agrees with `water_fbm` within the sampler's sub-texel precision.
fn water_fbm_filtered(tex: texture_2d<f32>, samp: sampler, p: vec2<f32>, prm: WaterFbmParams) -> f32 {
    let x = water_to_fixed(p.x * prm.frequency);
    let y = water_to_fixed(p.y * prm.frequency);
    let half_texel = 0.5 / f32(textureDimensions(tex).x);
    var h = 0.0;
    var a = prm.amplitude;
    let n = min(prm.octaves_near, WATER_MAX_OCTAVES);
    for (var k = 0u; k < n; k++) {
        let px = (x << k) + water_octave_offset(k, 0u);
        let py = (y << k) + water_octave_offset(k, 1u);
        let uv = vec2<f32>(f32(px), f32(py)) * (1.0 / 4294967296.0) + half_texel;
        h += a * textureSampleLevel(tex, samp, uv, 0.0).r;
        a *= prm.gain;
    }
    return h;
}
