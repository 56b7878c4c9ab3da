//! The query's batched output ("GPU compute thread: Batched output"): one
//! [`DrawableSetupInstance`] per visible instance and one [`DrawableSetupBatch`] header per
//! run of consecutive visible instances of one setup within a wave.
//!
//! # DrawableSetupInstance (64 bytes, or 112 with the previous transform)
//!
//! | bytes | field | meaning |
//! | --- | --- | --- |
//! | 0-3 | `state.fade` | LOD fade opacity in (0, 1]: 1 when not fading; dither the instance out with `1 - fade` |
//! | 4-7 | `state.flags` | [`STATE_FADING`], [`STATE_FADING_OUT`] |
//! | 8-11 | `state.tile` | the [`TileId`](crate::TileId) of the instance's tile |
//! | 12-15 | `state.instance` | the instance's index in its tile (its QueryInstance) |
//! | 16-63 | `local_to_floating` | setup local space to the view's floating space ([`Transform4x3`]) |
//! | 64-111 | `prev_local_to_floating` | ([`DrawableSetupInstancePrev`] only) the same transform in the floating space of the previous frame's snapped origin |
//!
//! # DrawableSetupBatch (48 bytes)
//!
//! | bytes | field | meaning |
//! | --- | --- | --- |
//! | 0-7 | `sort_key` | bits 32-63: low 32 bits of the setup handle; bits 0-31: the f32 bits of the batch's nearest view depth (metres along the view axis, >= 0, so the bits sort like the float): sorting by key groups by setup, then front to back |
//! | 8-15 | `setup` | the setup's handle ([`QuerySetup::handle`](crate::QuerySetup)) |
//! | 16-31 | `sphere` | bounding sphere of the batch's instances in floating space: centre xyz, radius (enclosing their boxes) |
//! | 32-35 | `first_instance` | index of the batch's first instance in the instance output |
//! | 36-39 | `flags` | OR of the instances' `state.flags` ([`STATE_FADING`]: draw with the dithered variant) |
//! | 40-43 | `count` | instances in the batch, 1 to the wave width |
//! | 44-47 | `stride` | bytes per instance record: 64 or 112 |

use bytemuck::{Pod, Zeroable};

use crate::Transform4x3;

/// Instance state flag: the instance is fading (`fade < 1`).
pub const STATE_FADING: u32 = 1;
/// Instance state flag: the instance's LOD is no longer selected and it is fading out
/// (use the dither pattern complementary to the one fading in).
pub const STATE_FADING_OUT: u32 = 2;

/// The 16-byte instance state of a [`DrawableSetupInstance`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct InstanceState {
    /// LOD fade opacity, in (0, 1].
    pub fade: f32,
    /// `STATE_*` flags.
    pub flags: u32,
    /// The instance's tile.
    pub tile: u32,
    /// The instance's index in its tile.
    pub instance: u32,
}

const _: () = assert!(size_of::<InstanceState>() == 16);

/// One visible instance, 64 bytes. WGSL: `StaticsceneDrawableSetupInstance`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct DrawableSetupInstance {
    /// Renderer state.
    pub state: InstanceState,
    /// Setup local space to floating space.
    pub local_to_floating: Transform4x3,
}

const _: () = assert!(size_of::<DrawableSetupInstance>() == 64);

/// One visible instance with its previous-frame transform, 112 bytes (for motion
/// vectors). WGSL: `StaticsceneDrawableSetupInstancePrev`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct DrawableSetupInstancePrev {
    /// Renderer state.
    pub state: InstanceState,
    /// Setup local space to floating space.
    pub local_to_floating: Transform4x3,
    /// Setup local space to the previous frame's floating space.
    pub prev_local_to_floating: Transform4x3,
}

const _: () = assert!(size_of::<DrawableSetupInstancePrev>() == 112);

/// An instance record the query can write: [`DrawableSetupInstance`] or
/// [`DrawableSetupInstancePrev`].
pub trait OutputInstance: Pod + Send + Sync {
    /// Bytes per record (the batch's `stride`).
    const STRIDE: u32;
    /// Whether the record carries the previous transform.
    const PREVIOUS: bool;
    /// The record; `prev` is only called when [`PREVIOUS`](Self::PREVIOUS).
    fn make(state: InstanceState, l2f: Transform4x3, prev: impl FnOnce() -> Transform4x3) -> Self;
    /// The record's state.
    fn state(&self) -> &InstanceState;
    /// The record's local-to-floating transform.
    fn local_to_floating(&self) -> &Transform4x3;
}

impl OutputInstance for DrawableSetupInstance {
    const STRIDE: u32 = 64;
    const PREVIOUS: bool = false;
    #[inline]
    fn make(state: InstanceState, l2f: Transform4x3, _: impl FnOnce() -> Transform4x3) -> Self {
        DrawableSetupInstance {
            state,
            local_to_floating: l2f,
        }
    }
    fn state(&self) -> &InstanceState {
        &self.state
    }
    fn local_to_floating(&self) -> &Transform4x3 {
        &self.local_to_floating
    }
}

impl OutputInstance for DrawableSetupInstancePrev {
    const STRIDE: u32 = 112;
    const PREVIOUS: bool = true;
    #[inline]
    fn make(state: InstanceState, l2f: Transform4x3, prev: impl FnOnce() -> Transform4x3) -> Self {
        DrawableSetupInstancePrev {
            state,
            local_to_floating: l2f,
            prev_local_to_floating: prev(),
        }
    }
    fn state(&self) -> &InstanceState {
        &self.state
    }
    fn local_to_floating(&self) -> &Transform4x3 {
        &self.local_to_floating
    }
}

/// A batch header, 48 bytes: a run of consecutive visible instances of one setup. WGSL:
/// `StaticsceneDrawableSetupBatch` (the two `u64`s as `vec2<u32>`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct DrawableSetupBatch {
    /// Setup handle's low 32 bits, then nearest view depth bits.
    pub sort_key: u64,
    /// The setup's handle.
    pub setup: u64,
    /// Floating-space bounding sphere: centre xyz, radius.
    pub sphere: [f32; 4],
    /// Index of the first instance in the instance output.
    pub first_instance: u32,
    /// OR of the instances' state flags.
    pub flags: u32,
    /// Number of instances.
    pub count: u32,
    /// Bytes per instance record.
    pub stride: u32,
}

const _: () = assert!(size_of::<DrawableSetupBatch>() == 48);

/// The batch sort key: setup handle's low bits, then the nearest depth (clamped to >= 0).
#[must_use]
#[inline]
pub fn sort_key(setup: u64, nearest_depth: f32) -> u64 {
    let d = if nearest_depth > 0.0 {
        nearest_depth.to_bits()
    } else {
        0
    };
    (setup & 0xffff_ffff) << 32 | u64::from(d)
}

/// A batch in canonical form: its setup, flags and its instances' `(tile, index)` keys.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct CanonicalBatch {
    /// The batch's instances' `(tile, instance index in the tile)`, in output order.
    pub instances: alloc::vec::Vec<(u32, u32)>,
    /// The setup handle.
    pub setup: u64,
    /// OR of the instances' state flags.
    pub flags: u32,
}

/// The canonical form of a query's output, in which the GPU query and the CPU twin
/// compare: on the GPU, jobs append in scheduling order, so instance and batch positions
/// differ while each batch's contents do not. Each batch becomes its setup, flags and
/// instance keys; the list is sorted by the keys (a batch's keys are unique). Batches
/// pointing past `instances` keep only the keys that exist.
#[must_use]
pub fn canonical_batches<I: OutputInstance>(
    instances: &[I],
    batches: &[DrawableSetupBatch],
) -> alloc::vec::Vec<CanonicalBatch> {
    let mut v: alloc::vec::Vec<CanonicalBatch> = batches
        .iter()
        .map(|b| CanonicalBatch {
            instances: (b.first_instance..b.first_instance.saturating_add(b.count))
                .filter_map(|i| instances.get(i as usize))
                .map(|d| (d.state().tile, d.state().instance))
                .collect(),
            setup: b.setup,
            flags: b.flags,
        })
        .collect();
    v.sort();
    v
}
