//! One pixel's word → (pass, batch group, micro batch, instance, primitive), with the rules
//! every phase (and its WGSL twin) applies in the same way. Private: the passes share it.

use alloc::vec::Vec;

use visbuf::{PrimitiveBits, VIS_NONE, VisId, VisLayout};

use crate::plan::{MAX_BATCH_GROUPS_PER_PASS, MicroBatchInfo};

/// `pass << 5 | group`: the (pass, batch group) of a pixel in one number.
pub(crate) type PassGroup = u16;

/// Entry of a row that names nothing valid.
const INVALID: PassGroup = PassGroup::MAX;

/// The (pass, group) given to pixels that are not valid: one past every real one, so
/// per-(pass, group) arrays of [`PG_SLOTS`] entries can absorb them without a branch.
pub(crate) const TRASH_PG: PassGroup =
    (crate::plan::MAX_PASSES * MAX_BATCH_GROUPS_PER_PASS) as PassGroup;

/// Entries of a per-(pass, group) array that [`TRASH_PG`] may index.
pub(crate) const PG_SLOTS: usize = TRASH_PG as usize + MAX_BATCH_GROUPS_PER_PASS as usize;

/// The kind [`Decoder::classify`] returns for a valid pixel (0 empty, 1 unknown, 2 out of
/// range).
pub(crate) const KIND_VALID: u32 = 3;

/// Precomputed per micro-batch ID.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Entry {
    /// `pass * 32 + group`, or [`INVALID`].
    pub pg: PassGroup,
    /// Primitive bits (0..=16).
    pub bits: PrimitiveBits,
    /// Instance fields below this name an instance of the micro batch.
    pub field_limit: u32,
    /// Primitives per instance.
    pub prim_count: u32,
    /// First micro-batch ID of the row's range.
    pub first_id: u32,
}

/// A decoded valid pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Decoded {
    pub pg: PassGroup,
    /// Micro-batch ID (table index).
    pub mb: u32,
    /// Instance index within the micro batch.
    pub instance: u32,
    /// Primitive index within the geometry.
    pub prim: u32,
}

/// Why a pixel is not shaded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Px {
    /// [`VIS_NONE`] or masked out by the validity bitmask.
    Empty,
    /// The micro-batch ID names no (valid) row.
    Unknown,
    /// The instance or primitive lies past the row's counts.
    OutOfRange,
    /// Shaded.
    Valid(Decoded),
}

/// Whether a table row is usable by the given ID, and its entry.
pub(crate) fn entry(id: u32, row: &MicroBatchInfo, passes: u32, layout: VisLayout) -> Entry {
    let in_range = u64::from(id) >= u64::from(row.first_id)
        && u64::from(id) < u64::from(row.first_id) + u64::from(row.id_count);
    let ok = in_range
        && id != layout.reserved_micro_batch()
        && row.pass < passes
        && row.batch_group < MAX_BATCH_GROUPS_PER_PASS
        && row.primitive_bits <= visbuf::MAX_PRIMITIVE_BITS;
    if !ok {
        return Entry {
            pg: INVALID,
            bits: PrimitiveBits::default(),
            field_limit: 0,
            prim_count: 0,
            first_id: 0,
        };
    }
    let bits = row.bits();
    let instance_bits = bits.instance_bits();
    // Instance index = (id - first_id) << instance_bits | field < instance_count.
    let before = u64::from(id - row.first_id) << instance_bits;
    let left = u64::from(row.instance_count).saturating_sub(before);
    Entry {
        pg: ((row.pass << 5) | row.batch_group) as PassGroup,
        bits,
        field_limit: left.min(u64::from(bits.instances_per_id())) as u32,
        prim_count: row.primitive_count,
        first_id: row.first_id,
    }
}

/// The table seen through the per-ID entries.
#[derive(Clone, Debug)]
pub(crate) struct Decoder {
    layout: VisLayout,
    entries: Vec<Entry>,
}

impl Decoder {
    pub fn new(table: &[MicroBatchInfo], passes: u32, layout: VisLayout) -> Self {
        // IDs past the layout's range can never be named by a word.
        let n = table.len().min(layout.micro_batch_ids() as usize);
        let mut entries: Vec<Entry> = table[..n]
            .iter()
            .enumerate()
            .map(|(id, row)| entry(id as u32, row, passes, layout))
            .collect();
        // The sentinel every ID past the table maps to.
        entries.push(Entry {
            pg: INVALID,
            bits: PrimitiveBits::default(),
            field_limit: 0,
            prim_count: 0,
            first_id: 0,
        });
        Self { layout, entries }
    }

    /// The pixel's kind (0 empty, 1 unknown, 2 out of range, [`KIND_VALID`]) and its
    /// decode, without branches: invalid pixels get [`TRASH_PG`]. `bit` is the validity
    /// bitmask's bit (true without one). The same rules as [`Decoder::decode`].
    #[inline(always)]
    pub fn classify(&self, word: u32, bit: bool) -> (u32, Decoded) {
        let id = VisId(word);
        let mb = id.micro_batch(self.layout);
        let last = self.entries.len() - 1;
        let e = &self.entries[(mb as usize).min(last)];
        let field = id.instance_field(e.bits);
        let prim = id.primitive(e.bits);
        let present = (word != VIS_NONE) & bit;
        let known = e.pg != INVALID;
        let in_range = (field < e.field_limit) & (prim < e.prim_count);
        let kind = u32::from(present) * (1 + u32::from(known) * (1 + u32::from(in_range)));
        let pg = if kind == KIND_VALID { e.pg } else { TRASH_PG };
        (
            kind,
            Decoded {
                pg,
                mb,
                instance: visbuf::instance_index(mb, e.first_id, field, e.bits),
                prim,
            },
        )
    }

    /// The pixel's classification, validity bit already applied by the caller (`valid`).
    #[inline(always)]
    pub fn decode(&self, word: u32, valid: bool) -> Px {
        if word == VIS_NONE || !valid {
            return Px::Empty;
        }
        let id = VisId(word);
        let mb = id.micro_batch(self.layout);
        let Some(e) = self.entries[..self.entries.len() - 1].get(mb as usize) else {
            return Px::Unknown;
        };
        if e.pg == INVALID {
            return Px::Unknown;
        }
        let field = id.instance_field(e.bits);
        let prim = id.primitive(e.bits);
        if field >= e.field_limit || prim >= e.prim_count {
            return Px::OutOfRange;
        }
        Px::Valid(Decoded {
            pg: e.pg,
            mb,
            instance: visbuf::instance_index(mb, e.first_id, field, e.bits),
            prim,
        })
    }
}
