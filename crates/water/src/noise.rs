//! The tileable noise texture and the FBM that samples it, with the talk's octave LOD.
//!
//! Far Cry 5 builds the water's high-frequency surface shape from fractional Brownian
//! motion over a noise texture: "nine iterations per pixel ... each iteration adds more
//! frequency as you double the UV scale", 3 texture fetches in the distance and 9 close by,
//! never 0 "because otherwise the reflections look really bad in the distance" (seed 003).
//!
//! # The texture
//!
//! [`NoiseTexture::generate`] bakes periodic gradient noise (Perlin's gradient noise with
//! a quintic fade, gradients from the integer hash [`crate::hash::hash3`], one of 8 unit
//! directions, no trigonometry) into a `size x size` f32 texture that tiles: texel `(i, j)`
//! holds the noise at `uv = (i, j) / size`, and the lattice repeats every `cells` cells, so
//! the texture wraps with no seam. Values are scaled by `sqrt(2)` into `[-1, 1]`. The GPU
//! can upload these texels or generate the same ones itself (`water_noise_texel` in
//! [`wgsl::NOISE`](crate::wgsl::NOISE), equal within 2e-6).
//!
//! # Sampling and precision
//!
//! A sample point is first turned into 32-bit fixed point of the texture period
//! (`fract(u) * 2^32`, exact); octave `k` then shifts it left by `k` (an exact doubling that
//! wraps exactly at the period) and adds a per-octave offset, so the nine octaves cost
//! integer shifts, four texel loads and three lerps each, and lose no precision however high
//! the octave. The one rounding is `u = position * frequency` in f32: keep positions within
//! a few kilometres of the origin (or pass camera- or sector-relative positions), as on the
//! GPU.
//!
//! Interpolation is bilinear between texel corners (texel `i` at `u = i / size`), exactly
//! what `water_fbm` in WGSL does with `textureLoad`; `water_fbm_filtered` uses the sampler
//! instead (one fetch per octave, as in the talk) and agrees within the sampler's
//! sub-texel precision (see the crate docs).
//!
//! # Octave LOD
//!
//! The octave count is continuous: `c(d) = clamp(near - log2(max(d, d0) / d0), far, near)`
//! for view distance `d` and [`FbmParams::lod_distance`] `d0`, so one octave goes per
//! doubling of distance, which keeps the finest octave at about the same size on screen.
//! Octave `k` is weighted `w_k = saturate(c - k)`: it fades out over one doubling instead
//! of popping. The slope variance that fading removes, `sum_k (1 - w_k^2) (a_k f_k)^2 S`
//! (amplitude `a_k` in metres, frequency `f_k` in periods per metre, `S` the texture's mean
//! squared slope per period per axis, measured at bake time), is returned for specular
//! anti-aliasing ([`crate::specaa`]): the total of kept and dropped variance stays what the
//! full nine octaves have.

use alloc::vec::Vec;

use glam::Vec2;

use crate::Error;
use crate::hash::{hash3, pcg};
use crate::math;

/// Smallest texture side [`NoiseTexture::generate`] accepts.
pub const MIN_NOISE_SIZE: u32 = 4;
/// Largest texture side [`NoiseTexture::generate`] accepts (the CPU keeps a 16-byte
/// 2 x 2 footprint per texel for one-load bilinear sampling: 64 MiB at this size).
pub const MAX_NOISE_SIZE: u32 = 2048;
/// Most octaves an [`Fbm`] sums.
pub const MAX_OCTAVES: u32 = 16;
/// The talk's octave count close to the camera.
pub const OCTAVES_NEAR: u32 = 9;
/// The talk's octave count in the distance ("we don't want to go to 0").
pub const OCTAVES_FAR: u32 = 3;
/// Scale from the gradient noise's range (about `[-1/sqrt 2, 1/sqrt 2]`) to `[-1, 1]`.
pub const NOISE_SCALE: f32 = core::f32::consts::SQRT_2;

/// Seed of the per-octave offsets.
pub const OCTAVE_SEED: u32 = 0x5eed;

/// The per-octave offset added to the fixed-point position (in 2^-32 periods), so octaves
/// do not line up at the origin. The WGSL twin computes the same from `water_pcg`.
#[inline]
#[must_use]
pub const fn octave_offset(octave: u32, axis: u32) -> u32 {
    pcg(octave
        .wrapping_mul(2)
        .wrapping_add(axis)
        .wrapping_add(OCTAVE_SEED))
}

/// The 8 gradient directions (unit vectors at multiples of 45 degrees).
const GRADIENTS: [[f32; 2]; 8] = [
    [1.0, 0.0],
    [
        core::f32::consts::FRAC_1_SQRT_2,
        core::f32::consts::FRAC_1_SQRT_2,
    ],
    [0.0, 1.0],
    [
        -core::f32::consts::FRAC_1_SQRT_2,
        core::f32::consts::FRAC_1_SQRT_2,
    ],
    [-1.0, 0.0],
    [
        -core::f32::consts::FRAC_1_SQRT_2,
        -core::f32::consts::FRAC_1_SQRT_2,
    ],
    [0.0, -1.0],
    [
        core::f32::consts::FRAC_1_SQRT_2,
        -core::f32::consts::FRAC_1_SQRT_2,
    ],
];

#[inline]
fn quintic(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// Periodic gradient noise at lattice coordinates `(x, y)` with period `cells` (a power of
/// two), already scaled by [`NOISE_SCALE`] and clamped to `[-1, 1]`.
#[must_use]
pub fn periodic_gradient_noise(x: f32, y: f32, cells: u32, seed: u32) -> f32 {
    let fx = math::floor(x);
    let fy = math::floor(y);
    let (tx, ty) = (x - fx, y - fy);
    let mask = cells.wrapping_sub(1);
    let ix = (fx as i64 as u32) & mask;
    let iy = (fy as i64 as u32) & mask;
    let ix1 = ix.wrapping_add(1) & mask;
    let iy1 = iy.wrapping_add(1) & mask;
    let g = |i: u32, j: u32, dx: f32, dy: f32| {
        let d = GRADIENTS[(hash3(i, j, seed) >> 29) as usize];
        d[0] * dx + d[1] * dy
    };
    let n00 = g(ix, iy, tx, ty);
    let n10 = g(ix1, iy, tx - 1.0, ty);
    let n01 = g(ix, iy1, tx, ty - 1.0);
    let n11 = g(ix1, iy1, tx - 1.0, ty - 1.0);
    let (u, v) = (quintic(tx), quintic(ty));
    let a = n00 + (n10 - n00) * u;
    let b = n01 + (n11 - n01) * u;
    let n = (a + (b - a) * v) * NOISE_SCALE;
    n.clamp(-1.0, 1.0)
}

/// A square, tileable noise texture (f32 texels in `[-1, 1]`, row-major, texel `(i, j)` at
/// `uv = (i, j) / size`), and its slope statistics.
#[derive(Clone, Debug, PartialEq)]
pub struct NoiseTexture {
    size: u32,
    shift: u32,
    texels: Vec<f32>,
    /// Per texel `(i, j)` the bilinear coefficients of the cell to its lower right,
    /// [`bilinear_coefficients`] of texels `(i, j)`, `(i + 1, j)`, `(i, j + 1)`,
    /// `(i + 1, j + 1)` (wrapping), so a sample is one 16-byte load.
    quads: Vec<[f32; 4]>,
    mean: f32,
    slope_variance: f32,
}

impl NoiseTexture {
    /// Bakes `size x size` texels of periodic gradient noise with `cells` lattice cells per
    /// side. `size` and `cells` are powers of two, `size` in
    /// [`MIN_NOISE_SIZE`]`..=`[`MAX_NOISE_SIZE`], `cells` in `1..=size`. 256 texels with 32
    /// cells (8 texels per cell) is a good default ([`NoiseTexture::default_water`]).
    pub fn generate(size: u32, cells: u32, seed: u32) -> Result<Self, Error> {
        if !size.is_power_of_two() || !(MIN_NOISE_SIZE..=MAX_NOISE_SIZE).contains(&size) {
            return Err(Error::InvalidSize {
                field: "noise texture size",
                value: size,
                rule: "a power of two in MIN_NOISE_SIZE..=MAX_NOISE_SIZE (4..=2048)",
            });
        }
        if !cells.is_power_of_two() || cells > size {
            return Err(Error::InvalidSize {
                field: "noise lattice cells",
                value: cells,
                rule: "a power of two no larger than the texture size",
            });
        }
        let n = size as usize;
        let mut texels = Vec::with_capacity(n * n);
        let scale = cells as f32 / size as f32;
        for j in 0..size {
            for i in 0..size {
                texels.push(periodic_gradient_noise(
                    i as f32 * scale,
                    j as f32 * scale,
                    cells,
                    seed,
                ));
            }
        }
        Ok(Self::from_texels(size, texels).expect("generated texels are valid"))
    }

    /// The default water noise: 256 x 256 texels, 32 lattice cells, seed 0.
    #[must_use]
    pub fn default_water() -> Self {
        Self::generate(256, 32, 0).expect("valid constants")
    }

    /// Wraps existing texels (`size x size`, row-major, finite), for example loaded from an
    /// asset, and measures their slope statistics.
    pub fn from_texels(size: u32, texels: Vec<f32>) -> Result<Self, Error> {
        if !size.is_power_of_two() || !(MIN_NOISE_SIZE..=MAX_NOISE_SIZE).contains(&size) {
            return Err(Error::InvalidSize {
                field: "noise texture size",
                value: size,
                rule: "a power of two in MIN_NOISE_SIZE..=MAX_NOISE_SIZE (4..=2048)",
            });
        }
        let n = size as usize;
        if texels.len() != n * n {
            return Err(Error::LengthMismatch {
                field: "noise texels",
                len: texels.len(),
                expected: n * n,
            });
        }
        if texels.iter().any(|t| !t.is_finite()) {
            return Err(Error::NonFinite {
                field: "noise texel",
            });
        }
        // Mean squared slope of the bilinear surface per axis, exactly: in a cell, d/dx is
        // a(1 - y) + b y with a, b the texel differences of its two rows, whose mean square
        // over y in [0, 1] is (a^2 + ab + b^2) / 3. Averaged over both axes, in per-period
        // units (times size^2).
        let at = |i: usize, j: usize| f64::from(texels[(j & (n - 1)) * n + (i & (n - 1))]);
        let mut sum = 0.0f64;
        let mut mean = 0.0f64;
        for j in 0..n {
            for i in 0..n {
                let (v00, v10, v01, v11) = (at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1));
                mean += v00;
                let (a, b) = (v10 - v00, v11 - v01);
                sum += (a * a + a * b + b * b) / 3.0;
                let (c, d) = (v01 - v00, v11 - v10);
                sum += (c * c + c * d + d * d) / 3.0;
            }
        }
        let cells = (n * n) as f64;
        let mut quads = Vec::with_capacity(n * n);
        for j in 0..n {
            for i in 0..n {
                let t = |i: usize, j: usize| texels[(j & (n - 1)) * n + (i & (n - 1))];
                quads.push(bilinear_coefficients(
                    t(i, j),
                    t(i + 1, j),
                    t(i, j + 1),
                    t(i + 1, j + 1),
                ));
            }
        }
        let slope_variance = (sum / (2.0 * cells) * (n * n) as f64) as f32;
        Ok(Self {
            size,
            shift: 32 - size.trailing_zeros(),
            texels,
            quads,
            mean: (mean / cells) as f32,
            slope_variance,
        })
    }

    /// Side length in texels.
    #[must_use]
    pub fn size(&self) -> u32 {
        self.size
    }

    /// The texels, row-major (`texels()[j * size + i]` is texel `(i, j)`): upload as an
    /// `R32Float` texture for `water_fbm`, or as `R16Float` for `water_fbm_filtered`.
    #[must_use]
    pub fn texels(&self) -> &[f32] {
        &self.texels
    }

    /// Mean texel value (close to 0).
    #[must_use]
    pub fn mean(&self) -> f32 {
        self.mean
    }

    /// Mean squared slope of the bilinearly interpolated texture per axis, with `uv` in
    /// texture periods: `E[(dn/du)^2]` averaged over `u` and `v`. An octave of amplitude `a`
    /// metres and frequency `f` periods per metre has slope variance `a^2 f^2` times this.
    #[must_use]
    pub fn slope_variance(&self) -> f32 {
        self.slope_variance
    }

    /// Texel `(i, j)`, wrapping.
    #[inline]
    #[must_use]
    pub fn texel(&self, i: u32, j: u32) -> f32 {
        let m = self.size - 1;
        self.texels[((j & m) * self.size + (i & m)) as usize]
    }

    /// Bilinear sample at fixed-point position `(x, y)` (2^-32 texture periods, wrapping).
    #[inline]
    #[must_use]
    pub fn sample_fixed(&self, x: u32, y: u32) -> f32 {
        self.sample_fixed_grad(x, y).0
    }

    /// Bilinear sample at fixed-point `(x, y)` and its derivatives per texel.
    #[inline]
    fn sample_fixed_grad(&self, x: u32, y: u32) -> (f32, f32, f32) {
        self.sample_l::<0>(x, y)
    }

    /// [`NoiseTexture::sample_fixed_grad`] for a texture of `2^L` texels per side, with
    /// constant shifts (`L = 0`: the size read at run time).
    #[inline(always)]
    fn sample_l<const L: u32>(&self, x: u32, y: u32) -> (f32, f32, f32) {
        let s = if L == 0 { self.shift } else { 32 - L };
        let (ix, iy) = (x >> s, y >> s);
        // The next 24 bits below the texel index are the fraction, exact in f32.
        let tx = ((x << (32 - s)) >> 8) as f32 * (1.0 / 16_777_216.0);
        let ty = ((y << (32 - s)) >> 8) as f32 * (1.0 / 16_777_216.0);
        let [c0, c1, c2, c3] = self.quads[((iy << (32 - s)) | ix) as usize];
        let ddy = c2 + c3 * tx;
        (c0 + c1 * tx + ddy * ty, c1 + c3 * ty, ddy)
    }

    /// Bilinear sample at `uv` (texture periods; wraps).
    #[must_use]
    pub fn sample(&self, uv: Vec2) -> f32 {
        self.sample_fixed(to_fixed(uv.x), to_fixed(uv.y))
    }
}

/// The bilinear form of a cell with corners `v00` (at the origin), `v10` (+x), `v01` (+y),
/// `v11`: `[v00, v10 - v00, v01 - v00, (v11 - v01) - (v10 - v00)]`, so that the value at
/// `(tx, ty)` is `c0 + c1 tx + (c2 + c3 tx) ty` and the derivatives are `c1 + c3 ty` and
/// `c2 + c3 tx`. `water_noise_bilinear` in WGSL evaluates the same expression.
#[inline]
#[must_use]
pub fn bilinear_coefficients(v00: f32, v10: f32, v01: f32, v11: f32) -> [f32; 4] {
    [v00, v10 - v00, v01 - v00, (v11 - v01) - (v10 - v00)]
}

/// `fract(u) * 2^32` as an integer: `u` in 2^-32 texture periods, wrapping, exact (the WGSL
/// twin computes `u32(fract(u) * 4294967296.0)`, the same value). NaN gives 0.
#[inline]
#[must_use]
pub fn to_fixed(u: f32) -> u32 {
    // u * 2^32 is exact in f32 (a power-of-two scale). Its floor by truncation and a
    // correction, then wrapped: floor(u * 2^32) mod 2^32 = fract(u) * 2^32. Wherever x has
    // a fraction, |x| < 2^23, so `t as f32` is exact and the comparison is right; above,
    // x is an integer and t == x.
    let x = u * 4_294_967_296.0;
    let t = x as i64;
    let t = if (t as f32) > x { t.wrapping_sub(1) } else { t };
    t as u32
}

/// Calls `self.$f::<L>(args)` with `L` the texture's `log2(size)` as a constant, so the
/// texel addressing compiles to constant shifts (every size the texture accepts has an
/// arm; `L = 0` reads the size at run time).
macro_rules! dispatch {
    ($self:ident . $f:ident ( $($arg:expr),* )) => {
        match $self.texture.size.trailing_zeros() {
            2 => $self.$f::<2>($($arg),*),
            3 => $self.$f::<3>($($arg),*),
            4 => $self.$f::<4>($($arg),*),
            5 => $self.$f::<5>($($arg),*),
            6 => $self.$f::<6>($($arg),*),
            7 => $self.$f::<7>($($arg),*),
            8 => $self.$f::<8>($($arg),*),
            9 => $self.$f::<9>($($arg),*),
            10 => $self.$f::<10>($($arg),*),
            11 => $self.$f::<11>($($arg),*),
            _ => $self.$f::<0>($($arg),*),
        }
    };
}

/// FBM parameters. Lengths are metres, frequencies texture periods per metre.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FbmParams {
    /// Octave 0's frequency: texture periods per metre (`uv = position * frequency`).
    pub frequency: f32,
    /// Octave 0's amplitude: metres of height per unit texel value.
    pub amplitude: f32,
    /// Amplitude ratio from one octave to the next (0.5 is classic FBM). Frequency always
    /// doubles.
    pub gain: f32,
    /// Octaves close to the camera (the talk: 9), at most [`MAX_OCTAVES`].
    pub octaves_near: u32,
    /// Octaves kept however far (the talk: 3), at least 1, at most `octaves_near`.
    pub octaves_far: u32,
    /// Distance (metres) up to which all near octaves are summed; beyond it one octave
    /// fades out per doubling of distance.
    pub lod_distance: f32,
}

impl Default for FbmParams {
    /// The talk's 9 / 3 octaves; a 64 m noise period, 0.25 m amplitude, gain 0.5; all
    /// octaves up to 16 m.
    fn default() -> Self {
        Self {
            frequency: 1.0 / 64.0,
            amplitude: 0.25,
            gain: 0.5,
            octaves_near: OCTAVES_NEAR,
            octaves_far: OCTAVES_FAR,
            lod_distance: 16.0,
        }
    }
}

/// [`FbmParams`] and the texture's slope variance as the WGSL FBM takes them (uniform or
/// storage), 32 bytes.
#[derive(Clone, Copy, Debug, PartialEq, Default, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
pub struct WaterFbmParams {
    /// Texture periods per metre, octave 0.
    pub frequency: f32,
    /// Metres, octave 0.
    pub amplitude: f32,
    /// Amplitude ratio per octave.
    pub gain: f32,
    /// Metres.
    pub lod_distance: f32,
    /// Octaves near.
    pub octaves_near: u32,
    /// Octaves far.
    pub octaves_far: u32,
    /// [`NoiseTexture::slope_variance`].
    pub slope_variance: f32,
    /// Padding.
    pub _pad: u32,
}
const _: () = assert!(size_of::<WaterFbmParams>() == 32);

/// One FBM sample with octave LOD.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct FbmSample {
    /// Height in metres.
    pub height: f32,
    /// Height gradient (metres per metre) along +x and +y of the sample position.
    pub gradient: Vec2,
    /// Slope variance per axis (dimensionless) of the part of the octaves that the LOD
    /// faded out: add it to the normal variance for specular AA.
    pub dropped_variance: f32,
    /// The continuous octave count used, in `[octaves_far, octaves_near]`.
    pub octaves: f32,
}

/// FBM over a [`NoiseTexture`]: per octave, amplitude times gain and frequency times 2.
#[derive(Clone, Debug)]
pub struct Fbm<'a> {
    texture: &'a NoiseTexture,
    params: FbmParams,
    amp: [f32; MAX_OCTAVES as usize],
    /// Per-octave slope variance `a_k^2 f_k^2 S`.
    var: [f32; MAX_OCTAVES as usize],
    offset: [[u32; 2]; MAX_OCTAVES as usize],
}

impl<'a> Fbm<'a> {
    /// Checks the parameters (finite, positive frequency and lod distance, gain in
    /// `[0, 1]`, `1 <= far <= near <= MAX_OCTAVES`).
    pub fn new(texture: &'a NoiseTexture, params: FbmParams) -> Result<Self, Error> {
        let finite = |field, v: f32| {
            if v.is_finite() {
                Ok(())
            } else {
                Err(Error::NonFinite { field })
            }
        };
        finite("fbm frequency", params.frequency)?;
        finite("fbm amplitude", params.amplitude)?;
        finite("fbm gain", params.gain)?;
        finite("fbm lod distance", params.lod_distance)?;
        let range = |field, v: f32, min: f32, max: f32| {
            if v >= min && v <= max {
                Ok(())
            } else {
                Err(Error::OutOfRange {
                    field,
                    value: v,
                    min,
                    max,
                })
            }
        };
        range(
            "fbm frequency",
            params.frequency,
            f32::MIN_POSITIVE,
            f32::MAX,
        )?;
        range("fbm gain", params.gain, 0.0, 1.0)?;
        range(
            "fbm lod distance",
            params.lod_distance,
            f32::MIN_POSITIVE,
            f32::MAX,
        )?;
        if params.octaves_near > MAX_OCTAVES {
            return Err(Error::LimitExceeded {
                what: "fbm octaves_near",
                value: u64::from(params.octaves_near),
                limit: u64::from(MAX_OCTAVES),
                limit_name: "MAX_OCTAVES",
            });
        }
        if params.octaves_far == 0 || params.octaves_far > params.octaves_near {
            return Err(Error::OutOfRange {
                field: "fbm octaves_far",
                value: params.octaves_far as f32,
                min: 1.0,
                max: params.octaves_near as f32,
            });
        }
        let mut amp = [0.0; MAX_OCTAVES as usize];
        let mut var = [0.0; MAX_OCTAVES as usize];
        let mut offset = [[0; 2]; MAX_OCTAVES as usize];
        let (mut a, mut f) = (params.amplitude, params.frequency);
        for k in 0..MAX_OCTAVES as usize {
            amp[k] = a;
            var[k] = (a * f) * (a * f) * texture.slope_variance;
            offset[k] = [octave_offset(k as u32, 0), octave_offset(k as u32, 1)];
            a *= params.gain;
            f *= 2.0;
        }
        Ok(Self {
            texture,
            params,
            amp,
            var,
            offset,
        })
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &FbmParams {
        &self.params
    }

    /// Height (metres) at horizontal position `p` (metres) with all `octaves_near` octaves.
    #[inline]
    #[must_use]
    pub fn height(&self, p: Vec2) -> f32 {
        dispatch!(self.height_l(p))
    }

    #[inline(always)]
    fn height_l<const L: u32>(&self, p: Vec2) -> f32 {
        let mut x = to_fixed(p.x * self.params.frequency);
        let mut y = to_fixed(p.y * self.params.frequency);
        let n = self.params.octaves_near as usize;
        let mut h = 0.0;
        for (&a, &[ox, oy]) in self.amp[..n].iter().zip(&self.offset[..n]) {
            let v = self
                .texture
                .sample_l::<L>(x.wrapping_add(ox), y.wrapping_add(oy))
                .0;
            h += a * v;
            // Frequency doubles: an exact shift of the fixed-point position.
            x <<= 1;
            y <<= 1;
        }
        h
    }

    /// The continuous octave count at view distance `distance` (metres; NaN counts as
    /// near, like `water_fbm_octave_count`'s `select`).
    #[must_use]
    pub fn octave_count(&self, distance: f32) -> f32 {
        let (near, far) = (
            self.params.octaves_near as f32,
            self.params.octaves_far as f32,
        );
        let d0 = self.params.lod_distance;
        let d = if distance > d0 { distance } else { d0 };
        (near - math::log2(d / d0)).clamp(far, near)
    }

    /// The parameters as the WGSL twins take them (`WaterFbmParams`).
    #[must_use]
    pub fn gpu_params(&self) -> WaterFbmParams {
        WaterFbmParams {
            frequency: self.params.frequency,
            amplitude: self.params.amplitude,
            gain: self.params.gain,
            lod_distance: self.params.lod_distance,
            octaves_near: self.params.octaves_near,
            octaves_far: self.params.octaves_far,
            slope_variance: self.texture.slope_variance,
            _pad: 0,
        }
    }

    /// Height, gradient and dropped slope variance at `p` (metres) seen from `distance`
    /// metres away. Octaves with zero weight are not sampled.
    #[must_use]
    pub fn sample(&self, p: Vec2, distance: f32) -> FbmSample {
        dispatch!(self.sample_at_l(p, distance))
    }

    #[inline(always)]
    fn sample_at_l<const L: u32>(&self, p: Vec2, distance: f32) -> FbmSample {
        let c = self.octave_count(distance);
        let mut x = to_fixed(p.x * self.params.frequency);
        let mut y = to_fixed(p.y * self.params.frequency);
        let texels_per_period = self.texture.size as f32;
        let mut out = FbmSample {
            octaves: c,
            ..FbmSample::default()
        };
        let mut f = self.params.frequency * texels_per_period;
        for k in 0..self.params.octaves_near as usize {
            let w = math::saturate(c - k as f32);
            if w > 0.0 {
                let [ox, oy] = self.offset[k];
                let (v, dx, dy) = self
                    .texture
                    .sample_l::<L>(x.wrapping_add(ox), y.wrapping_add(oy));
                let a = self.amp[k] * w;
                out.height += a * v;
                out.gradient += Vec2::new(dx, dy) * (a * f);
            }
            out.dropped_variance += (1.0 - w * w) * self.var[k];
            f *= 2.0;
            x <<= 1;
            y <<= 1;
        }
        out
    }

    /// Height with the octave LOD at `distance`, without gradient.
    #[must_use]
    pub fn height_lod(&self, p: Vec2, distance: f32) -> f32 {
        dispatch!(self.height_lod_l(p, distance))
    }

    #[inline(always)]
    fn height_lod_l<const L: u32>(&self, p: Vec2, distance: f32) -> f32 {
        let c = self.octave_count(distance);
        let mut x = to_fixed(p.x * self.params.frequency);
        let mut y = to_fixed(p.y * self.params.frequency);
        let mut h = 0.0;
        for k in 0..self.params.octaves_near as usize {
            let w = math::saturate(c - k as f32);
            if w <= 0.0 {
                break;
            }
            let [ox, oy] = self.offset[k];
            let v = self
                .texture
                .sample_l::<L>(x.wrapping_add(ox), y.wrapping_add(oy))
                .0;
            h += self.amp[k] * w * v;
            x <<= 1;
            y <<= 1;
        }
        h
    }

    /// Total slope variance per axis of all `octaves_near` octaves: the most any LOD can
    /// drop.
    #[must_use]
    pub fn total_slope_variance(&self) -> f32 {
        self.var[..self.params.octaves_near as usize].iter().sum()
    }

    /// Slope variance per axis of octave `k` at full weight (`a_k^2 f_k^2 S`).
    #[must_use]
    pub fn octave_slope_variance(&self, k: u32) -> f32 {
        self.var.get(k as usize).copied().unwrap_or(0.0)
    }

    /// Heights of a row of `out.len()` points starting at `start`, `step` apart (metres),
    /// all octaves: the CPU twin of filling a displacement texture row.
    pub fn height_row(&self, start: Vec2, step: Vec2, out: &mut [f32]) {
        for (i, h) in out.iter_mut().enumerate() {
            *h = self.height(start + step * i as f32);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn to_fixed_is_fract_times_2_pow_32() {
        assert_eq!(to_fixed(0.5), 1 << 31);
        assert_eq!(to_fixed(-0.25), 3 << 30);
        assert_eq!(to_fixed(3.75), 3 << 30);
        assert_eq!(to_fixed(f32::NAN), 0);
        assert_eq!(to_fixed(-1e-12), 0xffff_ffff); // floor, like fract(u) * 2^32 rounded down
        let _ = to_fixed(f32::INFINITY);
        let _ = to_fixed(-3.0e38);
        // Same as the WGSL formula u32(fract(u) * 2^32) wherever it is exact.
        for u in [0.1f32, 123.456, -7.001, 0.999_999_9] {
            let f = u - math::floor(u);
            assert_eq!(to_fixed(u), (f64::from(f) * 4_294_967_296.0) as u32, "{u}");
        }
    }

    #[test]
    fn texture_tiles_without_a_seam() {
        let t = NoiseTexture::generate(64, 8, 3).unwrap();
        // The noise one texel past the edge equals the first texel: sample the generator.
        for j in 0..64 {
            let past = periodic_gradient_noise(8.0, j as f32 / 8.0, 8, 3);
            assert!((past - t.texel(0, j)).abs() < 1e-6);
        }
        assert!(t.texels().iter().all(|v| (-1.0..=1.0).contains(v)));
        assert!(t.mean().abs() < 0.1);
    }

    #[test]
    fn rejects_bad_sizes() {
        assert!(NoiseTexture::generate(100, 4, 0).is_err());
        assert!(NoiseTexture::generate(2, 2, 0).is_err());
        assert!(NoiseTexture::generate(64, 128, 0).is_err());
        assert!(NoiseTexture::from_texels(4, alloc::vec![0.0; 15]).is_err());
        assert!(NoiseTexture::from_texels(4, alloc::vec![f32::NAN; 16]).is_err());
    }
}
