//! Store-once tables: each distinct record (bit for bit) gets one index, found by hashing.

use alloc::vec::Vec;

use bytemuck::Pod;

const EMPTY: u32 = u32::MAX;

/// A list of distinct `T`s with a hash index over their bytes (open addressing, linear
/// probing). `T`'s size must be a multiple of 4 bytes.
pub(crate) struct Dedup<T: Pod> {
    items: Vec<T>,
    slots: Vec<u32>,
}

fn hash(bytes: &[u8]) -> u64 {
    // FxHash-style over 32-bit words, then a final avalanche.
    let mut h: u64 = 0;
    for w in bytes.chunks_exact(4) {
        let v = u32::from_le_bytes([w[0], w[1], w[2], w[3]]);
        h = (h.rotate_left(5) ^ u64::from(v)).wrapping_mul(0x517c_c1b7_2722_0a95);
    }
    h ^= h >> 29;
    h = h.wrapping_mul(0xbf58_476d_1ce4_e5b9);
    h ^ (h >> 32)
}

impl<T: Pod> Dedup<T> {
    pub(crate) fn new() -> Self {
        const { assert!(size_of::<T>().is_multiple_of(4)) };
        Dedup {
            items: Vec::new(),
            slots: alloc::vec![EMPTY; 64],
        }
    }

    pub(crate) fn len(&self) -> usize {
        self.items.len()
    }

    /// The index of `v`, inserting it if new.
    pub(crate) fn insert(&mut self, v: T) -> u32 {
        if (self.items.len() + 1) * 2 > self.slots.len() {
            self.grow();
        }
        let bytes = bytemuck::bytes_of(&v);
        let mask = self.slots.len() - 1;
        let mut i = hash(bytes) as usize & mask;
        loop {
            let s = self.slots[i];
            if s == EMPTY {
                let idx = self.items.len() as u32;
                self.slots[i] = idx;
                self.items.push(v);
                return idx;
            }
            if bytemuck::bytes_of(&self.items[s as usize]) == bytes {
                return s;
            }
            i = (i + 1) & mask;
        }
    }

    fn grow(&mut self) {
        let n = self.slots.len() * 2;
        self.slots.clear();
        self.slots.resize(n, EMPTY);
        let mask = n - 1;
        for (idx, v) in self.items.iter().enumerate() {
            let mut i = hash(bytemuck::bytes_of(v)) as usize & mask;
            while self.slots[i] != EMPTY {
                i = (i + 1) & mask;
            }
            self.slots[i] = idx as u32;
        }
    }

    pub(crate) fn into_items(self) -> Vec<T> {
        self.items
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_bits_same_index() {
        let mut d = Dedup::<[u32; 3]>::new();
        let mut want = Vec::new();
        for i in 0..5000u32 {
            let v = [i % 777, (i % 777) * 3, 1];
            let idx = d.insert(v);
            // Naive reference: first position of v in the distinct list.
            match want.iter().position(|w| *w == v) {
                Some(p) => assert_eq!(idx as usize, p),
                None => {
                    assert_eq!(idx as usize, want.len());
                    want.push(v);
                }
            }
        }
        assert_eq!(d.len(), 777);
        assert_eq!(d.into_items(), want);
    }
}
