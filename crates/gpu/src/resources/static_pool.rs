//! The static scene's pooled GPU buffers: every active tile's QueryInstances, record
//! block and state block (`staticscene::pass`), placed by a first-fit range allocator and
//! released when the tile is removed. Buffers grow by doubling (a GPU copy of the live
//! contents), so activating a tile costs its upload and, rarely, one copy.

use std::collections::BTreeMap;

use staticscene::pass::{TileSlots, tile_record_words, tile_records, tile_state_words};
use staticscene::{StaticTile, TileId};

use crate::error::{Error, Result};

/// First-fit ranges of `u32` units (instances, words), merged on release.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct RangeAlloc {
    /// Free ranges `(start, len)`, sorted by start, never adjacent.
    free: Vec<(u32, u32)>,
    /// End of the highest range ever handed out.
    end: u32,
}

impl RangeAlloc {
    /// A range of `len` units (`len > 0`), or `None` past `u32::MAX`.
    pub(crate) fn alloc(&mut self, len: u32) -> Option<u32> {
        if let Some(i) = self.free.iter().position(|&(_, l)| l >= len) {
            let (s, l) = self.free[i];
            if l == len {
                self.free.remove(i);
            } else {
                self.free[i] = (s + len, l - len);
            }
            return Some(s);
        }
        // Extend the last free range if it ends at `end`.
        let start = match self.free.last() {
            Some(&(s, l)) if s + l == self.end => {
                self.free.pop();
                s
            }
            _ => self.end,
        };
        self.end = start.checked_add(len)?;
        Some(start)
    }

    /// Returns `[start, start + len)`.
    pub(crate) fn release(&mut self, start: u32, len: u32) {
        let i = self.free.partition_point(|&(s, _)| s < start);
        self.free.insert(i, (start, len));
        if i + 1 < self.free.len() && start + len == self.free[i + 1].0 {
            self.free[i].1 += self.free[i + 1].1;
            self.free.remove(i + 1);
        }
        if i > 0 && self.free[i - 1].0 + self.free[i - 1].1 == start {
            self.free[i - 1].1 += self.free[i].1;
            self.free.remove(i);
        }
    }

    /// Units below the highest range handed out (the buffer must hold them).
    pub(crate) fn end(&self) -> u32 {
        self.end
    }
}

/// A storage buffer that grows by doubling, keeping its contents.
pub(crate) struct GrowBuffer {
    label: &'static str,
    /// The buffer (`STORAGE | COPY_DST | COPY_SRC`).
    pub buffer: wgpu::Buffer,
    /// Bumped whenever `buffer` is replaced (bind groups over it are stale).
    pub generation: u64,
}

impl GrowBuffer {
    fn new(device: &wgpu::Device, label: &'static str, bytes: u64) -> Self {
        Self {
            label,
            buffer: Self::make(device, label, bytes),
            generation: 0,
        }
    }

    fn make(device: &wgpu::Device, label: &'static str, bytes: u64) -> wgpu::Buffer {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: bytes.max(16).next_multiple_of(4),
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        })
    }

    /// Makes room for `bytes`, copying the old contents on the GPU.
    fn reserve(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, bytes: u64) -> Result<()> {
        if bytes <= self.buffer.size() {
            return Ok(());
        }
        let max = device.limits().max_storage_buffer_binding_size;
        let next = empty_storage(
            device,
            self.label,
            bytes.max((self.buffer.size() * 2).min(max)),
        )?;
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("static pool growth"),
        });
        encoder.copy_buffer_to_buffer(&self.buffer, 0, &next, 0, self.buffer.size());
        queue.submit([encoder.finish()]);
        self.buffer = next;
        self.generation += 1;
        Ok(())
    }
}

/// An uninitialised storage buffer (`STORAGE | COPY_DST | COPY_SRC`) of at least `bytes`,
/// after checking the device's binding-size limit.
pub(crate) fn empty_storage(
    device: &wgpu::Device,
    label: &'static str,
    bytes: u64,
) -> Result<wgpu::Buffer> {
    let max = device.limits().max_storage_buffer_binding_size;
    if bytes > max {
        return Err(Error::DeviceLimit {
            limit: "max_storage_buffer_binding_size",
            needed: bytes,
            available: max,
        });
    }
    Ok(GrowBuffer::make(device, label, bytes))
}

/// Where one active tile sits, and its sizes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Placed {
    slots: TileSlots,
    instances: u32,
    records: u32,
    state: u32,
}

/// The pooled buffers of every active static tile.
pub(crate) struct StaticPool {
    /// QueryInstances (16 bytes each).
    pub instances: GrowBuffer,
    /// Record blocks (words).
    pub records: GrowBuffer,
    /// Fade bytes and cluster live serials (words).
    pub state: GrowBuffer,
    alloc: [RangeAlloc; 3],
    tiles: BTreeMap<TileId, Placed>,
}

impl StaticPool {
    pub(crate) fn new(device: &wgpu::Device) -> Self {
        Self {
            instances: GrowBuffer::new(device, "static instances", 1 << 16),
            records: GrowBuffer::new(device, "static records", 1 << 16),
            state: GrowBuffer::new(device, "static state", 1 << 12),
            alloc: Default::default(),
            tiles: BTreeMap::new(),
        }
    }

    /// Uploads `tile`'s records and zeroed state (fade states 0, clusters never run).
    pub(crate) fn activate(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        tile: &StaticTile,
    ) -> Result<TileSlots> {
        if self.tiles.contains_key(&tile.id()) {
            return Err(Error::Scene(crate::SceneError::StaticTile {
                tile: tile.id().0,
                problem: "a tile of this id is already active",
            }));
        }
        let too_big = || {
            Error::Scene(crate::SceneError::StaticTile {
                tile: tile.id().0,
                problem: "the tile's buffers pass u32 indexing",
            })
        };
        let sizes = [
            u32::try_from(tile.instances().len()).map_err(|_| too_big())?,
            u32::try_from(tile_record_words(tile)).map_err(|_| too_big())?,
            u32::try_from(tile_state_words(tile)).map_err(|_| too_big())?,
        ];
        let mut starts = [0u32; 3];
        for k in 0..3 {
            match self.alloc[k].alloc(sizes[k].max(1)) {
                Some(s) => starts[k] = s,
                None => {
                    for j in 0..k {
                        self.alloc[j].release(starts[j], sizes[j].max(1));
                    }
                    return Err(too_big());
                }
            }
        }
        let grown = [
            self.instances
                .reserve(device, queue, u64::from(self.alloc[0].end()) * 16),
            self.records
                .reserve(device, queue, u64::from(self.alloc[1].end()) * 4),
            self.state
                .reserve(device, queue, u64::from(self.alloc[2].end()) * 4),
        ];
        if let Some(Err(e)) = grown.into_iter().find(Result::is_err) {
            for k in 0..3 {
                self.alloc[k].release(starts[k], sizes[k].max(1));
            }
            return Err(e);
        }
        queue.write_buffer(
            &self.instances.buffer,
            u64::from(starts[0]) * 16,
            bytemuck::cast_slice(tile.instances()),
        );
        let records = tile_records(tile);
        queue.write_buffer(
            &self.records.buffer,
            u64::from(starts[1]) * 4,
            bytemuck::cast_slice(&records),
        );
        let zeros = vec![0u32; sizes[2] as usize];
        queue.write_buffer(
            &self.state.buffer,
            u64::from(starts[2]) * 4,
            bytemuck::cast_slice(&zeros),
        );
        let slots = TileSlots {
            instance_base: starts[0],
            records: starts[1],
            state: starts[2],
        };
        self.tiles.insert(
            tile.id(),
            Placed {
                slots,
                instances: sizes[0],
                records: sizes[1],
                state: sizes[2],
            },
        );
        Ok(slots)
    }

    /// Releases a tile's ranges; false if it was not active.
    pub(crate) fn deactivate(&mut self, id: TileId) -> bool {
        let Some(p) = self.tiles.remove(&id) else {
            return false;
        };
        self.alloc[0].release(p.slots.instance_base, p.instances.max(1));
        self.alloc[1].release(p.slots.records, p.records.max(1));
        self.alloc[2].release(p.slots.state, p.state.max(1));
        true
    }

    /// Where tile `id` sits, if active.
    pub(crate) fn slots(&self, id: TileId) -> Option<TileSlots> {
        self.tiles.get(&id).map(|p| p.slots)
    }

    /// Active tiles.
    pub(crate) fn len(&self) -> usize {
        self.tiles.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The allocator against a naive occupancy map: ranges never overlap, released
    /// space is reused, neighbours merge.
    #[test]
    fn ranges_never_overlap_and_are_reused() {
        let mut rng = testkit::Rng::new(5);
        let mut a = RangeAlloc::default();
        let mut live: Vec<(u32, u32)> = Vec::new();
        for _ in 0..2000 {
            if live.is_empty() || rng.below(3) != 0 {
                let len = 1 + rng.below(50) as u32;
                let s = a.alloc(len).unwrap();
                for &(ls, ll) in &live {
                    assert!(s + len <= ls || ls + ll <= s, "overlap");
                }
                live.push((s, len));
            } else {
                let i = rng.below(live.len() as u64) as usize;
                let (s, l) = live.swap_remove(i);
                a.release(s, l);
            }
            let used: u32 = live.iter().map(|r| r.1).sum();
            let free: u32 = a.free.iter().map(|r| r.1).sum();
            assert_eq!(used + free, a.end(), "every unit below end is used or free");
            assert!(a.free.windows(2).all(|w| w[0].0 + w[0].1 < w[1].0));
        }
        for (s, l) in live.drain(..) {
            a.release(s, l);
        }
        assert_eq!(a.free, vec![(0, a.end())]);
    }
}
