//! The 32-bit vis-buffer ID, as Horizon Forbidden West lays it down.
//!
//! Every covered pixel of the visibility buffer (an `R32Uint` target) holds one word:
//!
//! | bits   | [`VisLayout::Standard`]    | [`VisLayout::Vrs`]                      |
//! |--------|----------------------------|-----------------------------------------|
//! | 31..30 | micro-batch ID, high bits  | shading rate ([`ShadingRate`], 2 bits)   |
//! | 29..16 | micro-batch ID, low bits   | micro-batch ID (14 bits)                 |
//! | 15..p  | instance field (`16 - p` bits)                                       ||
//! | p-1..0 | primitive index (`p` bits, `p = ceil(log2(primitive count))`)        ||
//!
//! `p` is the geometry's [`PrimitiveBits`]: 0 for a one-triangle geometry, 16 for one of
//! 32 769 to 65 536 triangles ([`MAX_PRIMITIVES_PER_GEOMETRY`]). It is not stored in the
//! word: the decoder reads it from the micro-batch table, found through the micro-batch ID.
//!
//! **Instance overflow.** A batch of `n` instances whose geometry leaves `16 - p` instance
//! bits occupies `ceil(n / 2^(16 - p))` consecutive micro-batch IDs (see
//! [`micro_batch_ids_needed`]); instance `i` is written with micro-batch ID
//! `first + i >> (16 - p)` and instance field `i & (2^(16 - p) - 1)`, and
//! [`instance_index`] maps the pair back. [`VisIdRanges`] hands out these ranges and
//! resolves a word back to (batch, instance, primitive).
//!
//! **The reserved value.** [`VIS_NONE`] = `0xFFFF_FFFF` means "no vis-buffer geometry
//! here" (clear the target to it). To keep it unambiguous the last micro-batch ID of each
//! layout (`0xFFFF`, or `0x3FFF` with VRS) is never handed out, so no packed ID can equal
//! it: the standard layout has [`MICRO_BATCH_IDS`] `- 1` = 65 535 usable IDs, the VRS
//! layout [`MICRO_BATCH_IDS_VRS`] `- 1` = 16 383.
//!
//! ```
//! use visbuf::{PrimitiveBits, ShadingRate, VisFields, VisId, VisLayout};
//!
//! let bits = PrimitiveBits::for_count(1000)?; // 10 primitive bits, 6 instance bits
//! let fields = VisFields { micro_batch: 7, instance: 63, primitive: 999, rate: ShadingRate::Rate2x1 };
//! let id = VisId::pack(VisLayout::Vrs, bits, fields)?;
//! assert_eq!(id.unpack(VisLayout::Vrs, bits), Some(fields));
//! assert_eq!(VisId::NONE.unpack(VisLayout::Vrs, bits), None);
//! # Ok::<(), visbuf::Error>(())
//! ```

use crate::Error;

/// The word that means "no vis-buffer geometry at this pixel": clear the vis buffer to it.
/// No [`VisId::pack`] result equals it, because the last micro-batch ID of each layout is
/// reserved.
pub const VIS_NONE: u32 = 0xFFFF_FFFF;

/// Bit position of the micro-batch ID (and, with VRS, of the field holding rate + ID).
pub const VIS_MICRO_BATCH_SHIFT: u32 = 16;
/// Width of the micro-batch ID in the standard layout.
pub const VIS_MICRO_BATCH_BITS: u32 = 16;
/// Width of the micro-batch ID when the top 2 bits hold the shading rate.
pub const VIS_MICRO_BATCH_BITS_VRS: u32 = 14;
/// Bit position of the shading rate in the VRS layout.
pub const VIS_RATE_SHIFT: u32 = 30;
/// Width of the shading rate field.
pub const VIS_RATE_BITS: u32 = 2;
/// Width of the instance + primitive half of the word.
pub const VIS_INSTANCE_PRIMITIVE_BITS: u32 = 16;
/// Mask of the instance + primitive half of the word.
pub const VIS_INSTANCE_PRIMITIVE_MASK: u32 = 0xFFFF;

/// Micro-batch IDs in the standard layout, including the reserved last one.
pub const MICRO_BATCH_IDS: u32 = 1 << VIS_MICRO_BATCH_BITS;
/// Micro-batch IDs in the VRS layout, including the reserved last one.
pub const MICRO_BATCH_IDS_VRS: u32 = 1 << VIS_MICRO_BATCH_BITS_VRS;
/// Most primitives one geometry may have: HFW limits geometry to 16-bit indices and 64k
/// primitives so a primitive index fits the low half of the word.
pub const MAX_PRIMITIVES_PER_GEOMETRY: u32 = 1 << MAX_PRIMITIVE_BITS;
/// Most primitive bits a geometry may use.
pub const MAX_PRIMITIVE_BITS: u32 = 16;
/// Most instances one micro batch may hold (the talk: "from 1 to 64k instances").
pub const MAX_INSTANCES_PER_MICRO_BATCH: u32 = 1 << 16;

/// Which of the two word layouts the vis buffer uses; one choice per frame (HFW turned VRS
/// on for PS4 base only).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum VisLayout {
    /// 16-bit micro-batch ID, no shading rate (every pixel shades at 1x1).
    #[default]
    Standard,
    /// 2-bit shading rate in bits 31..30, 14-bit micro-batch ID.
    Vrs,
}

impl VisLayout {
    /// Micro-batch IDs the layout can express, including the reserved last one.
    #[must_use]
    #[inline]
    pub const fn micro_batch_ids(self) -> u32 {
        match self {
            VisLayout::Standard => MICRO_BATCH_IDS,
            VisLayout::Vrs => MICRO_BATCH_IDS_VRS,
        }
    }

    /// Micro-batch IDs usable for geometry: IDs `0..usable_micro_batch_ids()`.
    #[must_use]
    #[inline]
    pub const fn usable_micro_batch_ids(self) -> u32 {
        self.micro_batch_ids() - 1
    }

    /// The micro-batch ID reserved so no packed word equals [`VIS_NONE`].
    #[must_use]
    #[inline]
    pub const fn reserved_micro_batch(self) -> u32 {
        self.micro_batch_ids() - 1
    }

    /// Width of the micro-batch ID field.
    #[must_use]
    #[inline]
    pub const fn micro_batch_bits(self) -> u32 {
        match self {
            VisLayout::Standard => VIS_MICRO_BATCH_BITS,
            VisLayout::Vrs => VIS_MICRO_BATCH_BITS_VRS,
        }
    }
}

/// A DirectX tier-1 shading rate (width x height of the pixel block one shading sample
/// covers), stored in 2 bits: bit 0 = log2(height), bit 1 = log2(width). This is D3D12's
/// `D3D12_SHADING_RATE` with its bits 2 and 0 brought together, so the order (1x1, 1x2,
/// 2x1, 2x2) is the same.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
#[repr(u8)]
pub enum ShadingRate {
    /// Full rate: one sample per pixel. Code 0.
    #[default]
    Rate1x1 = 0,
    /// One sample per 1-wide, 2-tall block. Code 1.
    Rate1x2 = 1,
    /// One sample per 2-wide, 1-tall block. Code 2.
    Rate2x1 = 2,
    /// One sample per 2x2 block. Code 3.
    Rate2x2 = 3,
}

impl ShadingRate {
    /// All four rates in code order.
    pub const ALL: [ShadingRate; 4] = [
        ShadingRate::Rate1x1,
        ShadingRate::Rate1x2,
        ShadingRate::Rate2x1,
        ShadingRate::Rate2x2,
    ];

    /// The rate of a 2-bit code; only the low 2 bits of `code` are read.
    #[must_use]
    #[inline]
    pub const fn from_bits(code: u32) -> ShadingRate {
        match code & 3 {
            0 => ShadingRate::Rate1x1,
            1 => ShadingRate::Rate1x2,
            2 => ShadingRate::Rate2x1,
            _ => ShadingRate::Rate2x2,
        }
    }

    /// The 2-bit code.
    #[must_use]
    #[inline]
    pub const fn bits(self) -> u32 {
        self as u32
    }

    /// Block width in pixels (1 or 2).
    #[must_use]
    #[inline]
    pub const fn width(self) -> u32 {
        1 + ((self as u32) >> 1)
    }

    /// Block height in pixels (1 or 2).
    #[must_use]
    #[inline]
    pub const fn height(self) -> u32 {
        1 + ((self as u32) & 1)
    }

    /// The rate with the given block size, if it is a tier-1 rate (each side 1 or 2).
    #[must_use]
    #[inline]
    pub const fn from_size(width: u32, height: u32) -> Option<ShadingRate> {
        match (width, height) {
            (1, 1) => Some(ShadingRate::Rate1x1),
            (1, 2) => Some(ShadingRate::Rate1x2),
            (2, 1) => Some(ShadingRate::Rate2x1),
            (2, 2) => Some(ShadingRate::Rate2x2),
            _ => None,
        }
    }
}

/// A geometry's primitive-bit count `p = ceil(log2(primitive count))`, validated to be at
/// most [`MAX_PRIMITIVE_BITS`]; the instance field gets the other `16 - p` bits of the low
/// half. The micro-batch table stores it so the decoder can split the word.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct PrimitiveBits(u8);

impl PrimitiveBits {
    /// A bit count; an error above [`MAX_PRIMITIVE_BITS`].
    #[inline]
    pub const fn new(bits: u32) -> Result<PrimitiveBits, Error> {
        if bits > MAX_PRIMITIVE_BITS {
            Err(Error::PrimitiveBitsTooLarge {
                bits,
                limit: MAX_PRIMITIVE_BITS,
            })
        } else {
            Ok(PrimitiveBits(bits as u8))
        }
    }

    /// The bits a geometry of `primitive_count` primitives needs: `ceil(log2(count))`, so 0
    /// for one primitive and 16 for 32 769..=65 536. Errors for 0 primitives and above
    /// [`MAX_PRIMITIVES_PER_GEOMETRY`].
    #[inline]
    pub const fn for_count(primitive_count: u32) -> Result<PrimitiveBits, Error> {
        if primitive_count == 0 {
            return Err(Error::EmptyGeometry);
        }
        if primitive_count > MAX_PRIMITIVES_PER_GEOMETRY {
            return Err(Error::TooManyPrimitives {
                count: primitive_count as u64,
                limit: MAX_PRIMITIVES_PER_GEOMETRY,
            });
        }
        // ceil(log2(n)) = 32 - lzcnt(n - 1) for n >= 1 (0 for n = 1).
        Ok(PrimitiveBits(
            (32 - (primitive_count - 1).leading_zeros()) as u8,
        ))
    }

    /// The primitive-bit count, 0..=16.
    #[must_use]
    #[inline]
    pub const fn get(self) -> u32 {
        self.0 as u32
    }

    /// Instance bits left in the low half: `16 - p`.
    #[must_use]
    #[inline]
    pub const fn instance_bits(self) -> u32 {
        VIS_INSTANCE_PRIMITIVE_BITS - self.0 as u32
    }

    /// Instances one micro-batch ID can name: `2^(16 - p)`.
    #[must_use]
    #[inline]
    pub const fn instances_per_id(self) -> u32 {
        1 << self.instance_bits()
    }

    /// Mask of the primitive field (low `p` bits).
    #[must_use]
    #[inline]
    pub const fn primitive_mask(self) -> u32 {
        (1 << self.0) - 1
    }
}

/// The decoded fields of a vis ID.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct VisFields {
    /// Micro-batch ID: below 65 535 (standard) or 16 383 (VRS).
    pub micro_batch: u32,
    /// Instance field: below `2^(16 - p)`. Not the instance index when a batch spans
    /// several micro-batch IDs: see [`instance_index`].
    pub instance: u32,
    /// Primitive (triangle) index within the geometry: below `2^p`.
    pub primitive: u32,
    /// Shading rate; always [`ShadingRate::Rate1x1`] in the standard layout (packing
    /// another rate there is an error-free no-op: the standard layout has no rate bits, so
    /// [`VisId::pack`] ignores it and [`VisId::unpack`] returns 1x1).
    pub rate: ShadingRate,
}

/// One vis-buffer word. See the [module docs](self) for the layout.
#[derive(
    Clone,
    Copy,
    Debug,
    PartialEq,
    Eq,
    Hash,
    PartialOrd,
    Ord,
    Default,
    bytemuck::Pod,
    bytemuck::Zeroable,
)]
#[repr(transparent)]
pub struct VisId(pub u32);

const _: () = assert!(size_of::<VisId>() == 4);

impl VisId {
    /// "No vis-buffer geometry here": [`VIS_NONE`].
    pub const NONE: VisId = VisId(VIS_NONE);

    /// Packs the fields, checking each fits: the micro-batch ID must be below
    /// [`VisLayout::usable_micro_batch_ids`], the instance field below `2^(16 - p)`, the
    /// primitive below `2^p`. In the standard layout `fields.rate` is ignored.
    #[inline]
    pub const fn pack(
        layout: VisLayout,
        bits: PrimitiveBits,
        fields: VisFields,
    ) -> Result<VisId, Error> {
        if fields.micro_batch >= layout.usable_micro_batch_ids() {
            return Err(Error::MicroBatchIdOutOfRange {
                id: fields.micro_batch,
                limit: layout.micro_batch_ids(),
                layout,
            });
        }
        if fields.instance >= bits.instances_per_id() {
            return Err(Error::InstanceFieldOutOfRange {
                instance: fields.instance,
                bits: bits.instance_bits(),
            });
        }
        if fields.primitive > bits.primitive_mask() {
            return Err(Error::PrimitiveOutOfRange {
                primitive: fields.primitive,
                bits: bits.get(),
            });
        }
        let rate = match layout {
            VisLayout::Standard => 0,
            VisLayout::Vrs => fields.rate.bits() << VIS_RATE_SHIFT,
        };
        Ok(VisId(
            rate | (fields.micro_batch << VIS_MICRO_BATCH_SHIFT)
                | (fields.instance << bits.get())
                | fields.primitive,
        ))
    }

    /// Whether this is [`VIS_NONE`].
    #[must_use]
    #[inline]
    pub const fn is_none(self) -> bool {
        self.0 == VIS_NONE
    }

    /// The micro-batch ID field (no check: the reserved ID comes back as is).
    #[must_use]
    #[inline]
    pub const fn micro_batch(self, layout: VisLayout) -> u32 {
        (self.0 >> VIS_MICRO_BATCH_SHIFT) & (layout.micro_batch_ids() - 1)
    }

    /// The shading rate: the top 2 bits in the VRS layout, 1x1 in the standard one.
    #[must_use]
    #[inline]
    pub const fn shading_rate(self, layout: VisLayout) -> ShadingRate {
        match layout {
            VisLayout::Standard => ShadingRate::Rate1x1,
            VisLayout::Vrs => ShadingRate::from_bits(self.0 >> VIS_RATE_SHIFT),
        }
    }

    /// The instance field, `16 - p` bits above the primitive.
    #[must_use]
    #[inline]
    pub const fn instance_field(self, bits: PrimitiveBits) -> u32 {
        (self.0 & VIS_INSTANCE_PRIMITIVE_MASK) >> bits.get()
    }

    /// The primitive index, the low `p` bits.
    #[must_use]
    #[inline]
    pub const fn primitive(self, bits: PrimitiveBits) -> u32 {
        self.0 & bits.primitive_mask()
    }

    /// All fields, or `None` when the word's micro-batch ID is the layout's reserved one
    /// (which covers [`VIS_NONE`]). Never panics: any `u32` decodes.
    #[must_use]
    #[inline]
    pub const fn unpack(self, layout: VisLayout, bits: PrimitiveBits) -> Option<VisFields> {
        let micro_batch = self.micro_batch(layout);
        if micro_batch == layout.reserved_micro_batch() {
            return None;
        }
        Some(VisFields {
            micro_batch,
            instance: self.instance_field(bits),
            primitive: self.primitive(bits),
            rate: self.shading_rate(layout),
        })
    }
}

/// How many consecutive micro-batch IDs a batch of `instance_count` instances of a
/// geometry of `primitive_count` primitives needs: `ceil(instances / 2^(16 - p))`.
///
/// Errors name the limit: 0 or more than [`MAX_PRIMITIVES_PER_GEOMETRY`] primitives, 0 or
/// more than [`MAX_INSTANCES_PER_MICRO_BATCH`] instances.
///
/// ```
/// // 1000 triangles: 10 primitive bits, 64 instances per ID; 200 instances need 4 IDs.
/// assert_eq!(visbuf::micro_batch_ids_needed(1000, 200), Ok(4));
/// // A full 64k-triangle geometry leaves no instance bits: one ID per instance.
/// assert_eq!(visbuf::micro_batch_ids_needed(65536, 3), Ok(3));
/// ```
#[inline]
pub const fn micro_batch_ids_needed(
    primitive_count: u32,
    instance_count: u32,
) -> Result<u32, Error> {
    let bits = match PrimitiveBits::for_count(primitive_count) {
        Ok(b) => b,
        Err(e) => return Err(e),
    };
    if instance_count == 0 || instance_count > MAX_INSTANCES_PER_MICRO_BATCH {
        return Err(Error::InstanceCountOutOfRange {
            count: instance_count,
            limit: MAX_INSTANCES_PER_MICRO_BATCH,
        });
    }
    Ok(instance_count.div_ceil(bits.instances_per_id()))
}

/// The micro-batch ID and instance field that instance `instance` of a batch whose range
/// starts at `first_micro_batch` is written with. The inverse of [`instance_index`]. No
/// range checks: use [`VisId::pack`] on the result to check the fields fit.
#[must_use]
#[inline]
pub const fn split_instance(
    first_micro_batch: u32,
    instance: u32,
    bits: PrimitiveBits,
) -> (u32, u32) {
    (
        first_micro_batch.wrapping_add(instance >> bits.instance_bits()),
        instance & (bits.instances_per_id() - 1),
    )
}

/// The instance index within its batch of a pixel whose word holds `micro_batch` and
/// `instance_field`, for a batch whose micro-batch-ID range starts at `first_micro_batch`:
/// `(micro_batch - first_micro_batch) * 2^(16 - p) + instance_field`. Wrapping arithmetic,
/// never panics; the caller looked `first_micro_batch` up for this `micro_batch`.
#[must_use]
#[inline]
pub const fn instance_index(
    micro_batch: u32,
    first_micro_batch: u32,
    instance_field: u32,
    bits: PrimitiveBits,
) -> u32 {
    (micro_batch.wrapping_sub(first_micro_batch) << bits.instance_bits()) | instance_field
}

/// The micro-batch-ID range of one batch: GPU-visible, one per batch, 16 bytes. WGSL:
/// `struct VisbufIdRange { first_id: u32, id_count: u32, instance_count: u32,
/// primitive_count: u32 }`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
pub struct VisbufIdRange {
    /// First micro-batch ID of the range.
    pub first_id: u32,
    /// IDs in the range, [`micro_batch_ids_needed`].
    pub id_count: u32,
    /// Instances in the batch, 1..=65 536.
    pub instance_count: u32,
    /// Primitives in the batch's geometry, 1..=65 536.
    pub primitive_count: u32,
}

const _: () = assert!(size_of::<VisbufIdRange>() == 16);

impl VisbufIdRange {
    /// The geometry's primitive bits. A range with a primitive count outside 1..=65 536
    /// (only possible when built by hand) gives 16.
    #[must_use]
    #[inline]
    pub const fn primitive_bits(&self) -> PrimitiveBits {
        match PrimitiveBits::for_count(self.primitive_count) {
            Ok(b) => b,
            Err(_) => PrimitiveBits(MAX_PRIMITIVE_BITS as u8),
        }
    }

    /// Whether the micro-batch ID lies in this range.
    #[must_use]
    #[inline]
    pub const fn contains(&self, micro_batch: u32) -> bool {
        micro_batch >= self.first_id && micro_batch - self.first_id < self.id_count
    }
}

/// A pixel's word resolved through [`VisIdRanges`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ResolvedVisId {
    /// Index of the batch (order of [`VisIdRanges::push`]).
    pub batch: u32,
    /// Instance index within the batch.
    pub instance: u32,
    /// Primitive index within the geometry.
    pub primitive: u32,
    /// Shading rate (1x1 in the standard layout).
    pub rate: ShadingRate,
}

/// Hands out consecutive micro-batch-ID ranges to batches and maps words back to
/// (batch, instance, primitive): the CPU side of the micro-batch table's ID bookkeeping.
///
/// ```
/// use visbuf::{PrimitiveBits, ShadingRate, VisFields, VisId, VisIdRanges, VisLayout};
///
/// let mut ranges = VisIdRanges::new(VisLayout::Standard);
/// let a = ranges.push(1000, 200)?; // 4 IDs: 0..4
/// let b = ranges.push(65536, 2)?; // 2 IDs: 4..6
/// assert_eq!((a.first_id, b.first_id, ranges.ids_used()), (0, 4, 6));
///
/// // Instance 130 of batch 0: micro batch 0 + 130 / 64 = 2, instance field 130 % 64 = 2.
/// let id = VisId::pack(VisLayout::Standard, PrimitiveBits::for_count(1000)?,
///     VisFields { micro_batch: 2, instance: 2, primitive: 17, rate: ShadingRate::Rate1x1 })?;
/// let hit = ranges.resolve(id).unwrap();
/// assert_eq!((hit.batch, hit.instance, hit.primitive), (0, 130, 17));
/// # Ok::<(), visbuf::Error>(())
/// ```
#[derive(Clone, Debug, Default)]
pub struct VisIdRanges {
    layout: VisLayout,
    ranges: alloc::vec::Vec<VisbufIdRange>,
    next: u32,
}

impl VisIdRanges {
    /// No batches yet.
    #[must_use]
    #[inline]
    pub fn new(layout: VisLayout) -> Self {
        Self {
            layout,
            ranges: alloc::vec::Vec::new(),
            next: 0,
        }
    }

    /// The layout IDs are allocated for.
    #[must_use]
    #[inline]
    pub fn layout(&self) -> VisLayout {
        self.layout
    }

    /// Allocates the next batch's range; errors when the counts are out of range or the
    /// layout's usable IDs would run out (the reserved last ID is never handed out).
    #[inline]
    pub fn push(
        &mut self,
        primitive_count: u32,
        instance_count: u32,
    ) -> Result<VisbufIdRange, Error> {
        let needed = micro_batch_ids_needed(primitive_count, instance_count)?;
        let available = self.layout.usable_micro_batch_ids() - self.next;
        if needed > available {
            return Err(Error::MicroBatchIdsExhausted {
                batch: self.ranges.len() as u32,
                needed,
                available,
                layout: self.layout,
            });
        }
        let range = VisbufIdRange {
            first_id: self.next,
            id_count: needed,
            instance_count,
            primitive_count,
        };
        self.next += needed;
        self.ranges.push(range);
        Ok(range)
    }

    /// Micro-batch IDs handed out so far.
    #[must_use]
    #[inline]
    pub fn ids_used(&self) -> u32 {
        self.next
    }

    /// The ranges in batch order (upload this as the GPU's range table).
    #[must_use]
    #[inline]
    pub fn ranges(&self) -> &[VisbufIdRange] {
        &self.ranges
    }

    /// The batch whose range holds `micro_batch`, with its range.
    #[must_use]
    #[inline]
    pub fn batch_of(&self, micro_batch: u32) -> Option<(u32, VisbufIdRange)> {
        let i = self
            .ranges
            .partition_point(|r| r.first_id + r.id_count <= micro_batch);
        let r = *self.ranges.get(i)?;
        r.contains(micro_batch).then_some((i as u32, r))
    }

    /// The batch, instance index and primitive of a word, or `None` for [`VIS_NONE`], an
    /// unallocated micro-batch ID, or an instance or primitive past the batch's counts
    /// (words the laydown never writes). Never panics.
    #[must_use]
    #[inline]
    pub fn resolve(&self, id: VisId) -> Option<ResolvedVisId> {
        let micro_batch = id.micro_batch(self.layout);
        let (batch, range) = self.batch_of(micro_batch)?;
        let bits = range.primitive_bits();
        let instance = instance_index(micro_batch, range.first_id, id.instance_field(bits), bits);
        let primitive = id.primitive(bits);
        (instance < range.instance_count && primitive < range.primitive_count).then_some(
            ResolvedVisId {
                batch,
                instance,
                primitive,
                rate: id.shading_rate(self.layout),
            },
        )
    }

    /// The word instance `instance` of batch `batch` writes for `primitive`, checked
    /// against the batch's counts.
    #[inline]
    pub fn pack(
        &self,
        batch: u32,
        instance: u32,
        primitive: u32,
        rate: ShadingRate,
    ) -> Result<VisId, Error> {
        let Some(range) = self.ranges.get(batch as usize) else {
            return Err(Error::UnknownBatch {
                batch,
                batches: self.ranges.len() as u32,
            });
        };
        if instance >= range.instance_count {
            return Err(Error::InstanceOutOfRange {
                instance,
                count: range.instance_count,
            });
        }
        let bits = range.primitive_bits();
        if primitive >= range.primitive_count {
            return Err(Error::PrimitiveOutOfRange {
                primitive,
                bits: bits.get(),
            });
        }
        let (micro_batch, field) = split_instance(range.first_id, instance, bits);
        VisId::pack(
            self.layout,
            bits,
            VisFields {
                micro_batch,
                instance: field,
                primitive,
                rate,
            },
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::vec::Vec;
    use proptest::prelude::*;

    /// Independent reference: smallest b with 2^b >= n, by a loop.
    fn naive_bits(n: u32) -> u32 {
        let mut b = 0;
        while (1u64 << b) < n as u64 {
            b += 1;
        }
        b
    }

    #[test]
    fn primitive_bits_matches_a_loop_for_every_count() {
        for n in 1..=MAX_PRIMITIVES_PER_GEOMETRY {
            assert_eq!(
                PrimitiveBits::for_count(n).unwrap().get(),
                naive_bits(n),
                "n={n}"
            );
        }
        assert_eq!(PrimitiveBits::for_count(0), Err(Error::EmptyGeometry));
        assert_eq!(
            PrimitiveBits::for_count(65537),
            Err(Error::TooManyPrimitives {
                count: 65537,
                limit: 65536
            })
        );
        assert!(PrimitiveBits::new(16).is_ok());
        assert_eq!(
            PrimitiveBits::new(17),
            Err(Error::PrimitiveBitsTooLarge {
                bits: 17,
                limit: 16
            })
        );
    }

    #[test]
    fn fixed_vectors() {
        let b = |n| PrimitiveBits::new(n).unwrap();
        let f = |mb, inst, prim, rate| VisFields {
            micro_batch: mb,
            instance: inst,
            primitive: prim,
            rate,
        };
        // Standard layout, 10 primitive bits.
        let id = VisId::pack(
            VisLayout::Standard,
            b(10),
            f(0x1234, 0x2a, 0x3ff, ShadingRate::Rate1x1),
        );
        assert_eq!(id, Ok(VisId(0x1234_abff)));
        // VRS: rate 2x2 (code 3) in bits 31..30, micro batch 0x3ffe (last usable).
        let id = VisId::pack(
            VisLayout::Vrs,
            b(0),
            f(0x3ffe, 0xffff, 0, ShadingRate::Rate2x2),
        );
        assert_eq!(id, Ok(VisId(0xfffe_ffff)));
        // 16 primitive bits: no instance bits, instance field must be 0.
        let id = VisId::pack(
            VisLayout::Standard,
            b(16),
            f(1, 0, 0xffff, ShadingRate::Rate1x1),
        );
        assert_eq!(id, Ok(VisId(0x0001_ffff)));
        // Decoding a fixed word.
        let w = VisId(0x9234_5678);
        assert_eq!(w.micro_batch(VisLayout::Standard), 0x9234);
        assert_eq!(w.micro_batch(VisLayout::Vrs), 0x1234);
        assert_eq!(w.shading_rate(VisLayout::Vrs), ShadingRate::Rate2x1);
        assert_eq!(w.shading_rate(VisLayout::Standard), ShadingRate::Rate1x1);
        assert_eq!(w.instance_field(b(4)), 0x567);
        assert_eq!(w.primitive(b(4)), 0x8);
    }

    #[test]
    fn pack_rejects_fields_that_do_not_fit_and_names_the_limit() {
        let b10 = PrimitiveBits::new(10).unwrap();
        let f = |mb, inst, prim| VisFields {
            micro_batch: mb,
            instance: inst,
            primitive: prim,
            rate: ShadingRate::Rate1x1,
        };
        assert_eq!(
            VisId::pack(VisLayout::Standard, b10, f(0xffff, 0, 0)),
            Err(Error::MicroBatchIdOutOfRange {
                id: 0xffff,
                limit: 65536,
                layout: VisLayout::Standard
            })
        );
        assert_eq!(
            VisId::pack(VisLayout::Vrs, b10, f(0x3fff, 0, 0)),
            Err(Error::MicroBatchIdOutOfRange {
                id: 0x3fff,
                limit: 16384,
                layout: VisLayout::Vrs
            })
        );
        assert_eq!(
            VisId::pack(VisLayout::Standard, b10, f(0, 64, 0)),
            Err(Error::InstanceFieldOutOfRange {
                instance: 64,
                bits: 6
            })
        );
        assert_eq!(
            VisId::pack(VisLayout::Standard, b10, f(0, 0, 1024)),
            Err(Error::PrimitiveOutOfRange {
                primitive: 1024,
                bits: 10
            })
        );
        let msg = alloc::format!(
            "{}",
            VisId::pack(VisLayout::Vrs, b10, f(20000, 0, 0)).unwrap_err()
        );
        assert!(msg.contains("20000") && msg.contains("Vrs"), "{msg}");
    }

    #[test]
    fn no_packed_word_is_the_reserved_value() {
        // The only way to reach 0xffffffff is micro batch all-ones, which pack refuses; check
        // the largest packable words of every layout and bit count.
        for layout in [VisLayout::Standard, VisLayout::Vrs] {
            for p in 0..=16 {
                let bits = PrimitiveBits::new(p).unwrap();
                let f = VisFields {
                    micro_batch: layout.usable_micro_batch_ids() - 1,
                    instance: bits.instances_per_id() - 1,
                    primitive: bits.primitive_mask(),
                    rate: ShadingRate::Rate2x2,
                };
                let id = VisId::pack(layout, bits, f).unwrap();
                assert!(!id.is_none());
                assert_eq!(
                    id.unpack(layout, bits),
                    Some(if layout == VisLayout::Standard {
                        VisFields {
                            rate: ShadingRate::Rate1x1,
                            ..f
                        }
                    } else {
                        f
                    })
                );
                assert_eq!(VisId::NONE.unpack(layout, bits), None);
            }
        }
    }

    #[test]
    fn shading_rates_match_d3d12_sizes() {
        // D3D12_SHADING_RATE: (log2 w << 2) | log2 h; ours: (log2 w << 1) | log2 h.
        for r in ShadingRate::ALL {
            let d3d = ((r.width().trailing_zeros()) << 2) | r.height().trailing_zeros();
            assert_eq!(((d3d >> 1) & 2) | (d3d & 1), r.bits());
            assert_eq!(ShadingRate::from_size(r.width(), r.height()), Some(r));
            assert_eq!(ShadingRate::from_bits(r.bits()), r);
        }
        assert_eq!(ShadingRate::from_size(4, 4), None);
        assert_eq!(
            (ShadingRate::Rate1x2.width(), ShadingRate::Rate1x2.height()),
            (1, 2)
        );
    }

    #[test]
    fn micro_batch_ids_needed_matches_naive_count() {
        for pc in [1u32, 2, 3, 1000, 1024, 1025, 32768, 32769, 65536] {
            for ic in [1u32, 2, 63, 64, 65, 1000, 65535, 65536] {
                // Naive: walk the instances, counting how many distinct IDs they land on.
                let ib = 16 - naive_bits(pc);
                let naive = (ic as u64 - 1) / (1u64 << ib) + 1;
                assert_eq!(
                    micro_batch_ids_needed(pc, ic),
                    Ok(naive as u32),
                    "pc={pc} ic={ic}"
                );
            }
        }
        assert_eq!(
            micro_batch_ids_needed(10, 0),
            Err(Error::InstanceCountOutOfRange {
                count: 0,
                limit: 65536
            })
        );
        assert_eq!(
            micro_batch_ids_needed(10, 65537),
            Err(Error::InstanceCountOutOfRange {
                count: 65537,
                limit: 65536
            })
        );
        assert_eq!(micro_batch_ids_needed(0, 1), Err(Error::EmptyGeometry));
    }

    #[test]
    fn ranges_run_out_with_an_error_naming_the_batch() {
        let mut r = VisIdRanges::new(VisLayout::Vrs);
        for _ in 0..16383 / 2 {
            r.push(65536, 2).unwrap();
        }
        assert_eq!(r.ids_used(), 16382);
        assert_eq!(
            r.push(65536, 2),
            Err(Error::MicroBatchIdsExhausted {
                batch: 8191,
                needed: 2,
                available: 1,
                layout: VisLayout::Vrs
            })
        );
        r.push(65536, 1).unwrap();
        assert_eq!(r.ids_used(), 16383); // the reserved ID 0x3fff was never handed out
        assert!(r.push(1, 1).is_err());
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]

        #[test]
        fn pack_unpack_roundtrip(vrs: bool, p in 0u32..=16, mb: u32, inst: u32, prim: u32, rate in 0u32..4) {
            let layout = if vrs { VisLayout::Vrs } else { VisLayout::Standard };
            let bits = PrimitiveBits::new(p).unwrap();
            let f = VisFields {
                micro_batch: mb % layout.usable_micro_batch_ids(),
                instance: inst % (1 << (16 - p)),
                primitive: prim % (1 << p),
                rate: if vrs { ShadingRate::from_bits(rate) } else { ShadingRate::Rate1x1 },
            };
            let id = VisId::pack(layout, bits, f).unwrap();
            // Independent reference: the word by arithmetic, not shifts and masks.
            let expect = (f.rate.bits() as u64) * (1 << 30)
                + (f.micro_batch as u64) * 65536
                + (f.instance as u64) * (1u64 << p)
                + f.primitive as u64;
            prop_assert_eq!(id.0 as u64, expect);
            prop_assert_eq!(id.unpack(layout, bits), Some(f));
        }

        #[test]
        fn unpack_any_word_never_panics_and_repacks(word: u32, vrs: bool, p in 0u32..=16) {
            let layout = if vrs { VisLayout::Vrs } else { VisLayout::Standard };
            let bits = PrimitiveBits::new(p).unwrap();
            match VisId(word).unpack(layout, bits) {
                Some(f) => prop_assert_eq!(VisId::pack(layout, bits, f), Ok(VisId(word))),
                None => prop_assert_eq!(VisId(word).micro_batch(layout), layout.reserved_micro_batch()),
            }
        }

        #[test]
        fn ranges_resolve_every_instance(
            batches in proptest::collection::vec((1u32..=65536, 1u32..=3000), 1..20),
            picks in proptest::collection::vec((any::<u32>(), any::<u32>(), any::<u32>()), 32),
        ) {
            let mut r = VisIdRanges::new(VisLayout::Standard);
            let mut ok = Vec::new();
            for (pc, ic) in batches {
                if r.push(pc, ic).is_ok() {
                    ok.push((pc, ic));
                }
            }
            for (b, i, p) in picks {
                let batch = b % ok.len() as u32;
                let (pc, ic) = ok[batch as usize];
                let (inst, prim) = (i % ic, p % pc);
                let id = r.pack(batch, inst, prim, ShadingRate::Rate1x1).unwrap();
                let hit = r.resolve(id).unwrap();
                prop_assert_eq!((hit.batch, hit.instance, hit.primitive), (batch, inst, prim));
                // Reference through the free functions and the range.
                let range = r.ranges()[batch as usize];
                let bits = range.primitive_bits();
                prop_assert_eq!(
                    instance_index(id.micro_batch(VisLayout::Standard), range.first_id, id.instance_field(bits), bits),
                    inst
                );
            }
            prop_assert_eq!(r.resolve(VisId::NONE), None);
        }
    }
}
