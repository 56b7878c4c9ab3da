//! Per-frame uploads through KZ2's render-memory allocator (`framealloc`).
//!
//! Every per-frame write of the renderer (frame uniforms, lights, volumes and the light
//! passes' uniforms, cascade matrices and the sun's shadow uniforms, the static query's
//! parameters, jobs and counters) goes through [`Uploads::write`]: the bytes are queued
//! during the frame, then [`Uploads::commit`] sub-allocates them from a
//! [`framealloc::BlockPool`] over one persistent upload buffer (blocks taken with this
//! frame's AllocationIDs), writes them there and records one copy per upload into the
//! destination buffer, in a command buffer submitted ahead of the frame's. After the
//! submission, [`Uploads::submitted`] registers `Queue::on_submitted_work_done`, which
//! advances the pool's FreeID past the frame's IDs once the GPU has finished it: a block is
//! reused only after the frame that filled it has completed, frames never wait for each
//! other, and several can be in flight. A frame whose uploads find the pool full waits for
//! the device once; if the pool is still full (it is smaller than a frame's uploads, or
//! completions are held back), the frame fails with [`Error::UploadPoolExhausted`], naming
//! the pool size, and nothing is overwritten.

use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use framealloc::{AllocId, BlockPool, FrameIds, FramePlan, PoolConfig, Stream};

use crate::error::{Error, Result};

/// Where the per-frame writes of a pass go: the renderer's [`Uploads`] (deferred into the
/// frame's pool blocks) or, for standalone use, the queue directly.
pub(crate) trait UploadSink {
    /// Writes `bytes` at `offset` of `dst` before the frame's commands run.
    fn write(&mut self, dst: &wgpu::Buffer, offset: u64, bytes: &[u8]);
}

impl UploadSink for wgpu::Queue {
    fn write(&mut self, dst: &wgpu::Buffer, offset: u64, bytes: &[u8]) {
        self.write_buffer(dst, offset, bytes);
    }
}

/// What the last committed frame's uploads took.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct UploadStats {
    /// Bytes uploaded (the sum of the writes, before alignment).
    pub bytes: u64,
    /// Writes (one copy each, more for writes larger than a block).
    pub writes: u32,
    /// The pool blocks the frame took, by index.
    pub blocks: Vec<u32>,
    /// CPU time in `framealloc` (block allocation and sub-allocation), nanoseconds.
    pub allocator_ns: u64,
    /// CPU time of the whole commit (allocation, the writes into the upload buffer, the
    /// copies recorded), nanoseconds.
    pub commit_ns: u64,
    /// Free blocks after the commit, of [`UploadStats::pool_blocks`].
    pub free_blocks: u32,
    /// Blocks in the pool.
    pub pool_blocks: u32,
    /// Frames in flight when this one was submitted, itself included: submitted, their
    /// completion not yet delivered to the pool.
    pub frames_in_flight: u32,
}

/// How completions reach the pool: as the GPU finishes frames, or held back (a GPU that
/// appears slow: the allocator must then never hand out a held frame's blocks).
#[derive(Default)]
struct Completions {
    held: bool,
    /// Frames completed while held: their last IDs, oldest first.
    pending: Vec<AllocId>,
    /// Frames submitted whose completion has not reached the pool (running, or held).
    in_flight: u32,
}

/// The pool, its buffer and this frame's queued writes.
pub(crate) struct Uploads {
    pool: Arc<BlockPool>,
    buffer: wgpu::Buffer,
    /// The next frame's IDs.
    frame: FrameIds,
    queued: Vec<(wgpu::Buffer, u64, Vec<u8>)>,
    completions: Arc<Mutex<Completions>>,
    stats: UploadStats,
}

/// IDs one frame may tag blocks with (each block of the frame its own ID, so blocks could
/// free in order; more blocks share the last).
const IDS_PER_FRAME: u32 = 256;

impl Uploads {
    /// A pool of `config`'s layout over a new upload buffer.
    pub(crate) fn new(device: &wgpu::Device, config: PoolConfig) -> Result<Self> {
        let pool = BlockPool::new(config).map_err(|e| Error::Config {
            field: "RendererConfig::frames.upload_pool",
            value: config.pool_bytes as f64,
            allowed: match e {
                framealloc::Error::BadConfig { what, .. } => what,
                _ => "a valid framealloc::PoolConfig",
            },
        })?;
        let max = device.limits().max_buffer_size;
        if pool.pool_bytes() > max {
            return Err(Error::DeviceLimit {
                limit: "max_buffer_size",
                needed: pool.pool_bytes(),
                available: max,
            });
        }
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("upload pool (framealloc)"),
            size: pool.pool_bytes(),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let plan = FramePlan::new(&[IDS_PER_FRAME]).map_err(|_| Error::Config {
            field: "upload IDs per frame",
            value: f64::from(IDS_PER_FRAME),
            allowed: "framealloc's MAX_FRAME_SPAN",
        })?;
        let frame = plan.frame(pool.free_id().next());
        Ok(Self {
            stats: UploadStats {
                pool_blocks: pool.block_count(),
                free_blocks: pool.block_count(),
                ..UploadStats::default()
            },
            pool: Arc::new(pool),
            buffer,
            frame,
            queued: Vec::new(),
            completions: Arc::default(),
        })
    }

    /// The last committed frame's figures.
    pub(crate) fn stats(&self) -> &UploadStats {
        &self.stats
    }

    /// Holds completions back (`true`), or delivers the held ones and goes on delivering.
    pub(crate) fn hold_completions(&self, hold: bool) {
        let pending = {
            let mut c = self.completions.lock().unwrap_or_else(|e| e.into_inner());
            c.held = hold;
            if hold {
                return;
            }
            let pending = std::mem::take(&mut c.pending);
            c.in_flight = c.in_flight.saturating_sub(pending.len() as u32);
            pending
        };
        for last in pending {
            let _ = self.pool.advance_free_id(last);
        }
    }

    /// Drops this frame's queued writes (a frame that failed before its commit).
    pub(crate) fn discard(&mut self) {
        self.queued.clear();
    }

    /// Sub-allocates the queued writes from the pool with this frame's IDs, writes them
    /// into the upload buffer and returns the command buffer of their copies (submit it
    /// first). When the pool is full, waits for the device once and retries.
    ///
    /// # Errors
    /// [`Error::UploadPoolExhausted`] when the pool stays full; the frame's IDs are kept
    /// for the next frame then, so blocks it took free with that frame.
    pub(crate) fn commit(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<wgpu::CommandBuffer> {
        let t0 = Instant::now();
        let queued = std::mem::take(&mut self.queued);
        let pass = self.frame.pass(0).map_err(|_| Error::Config {
            field: "upload IDs per frame",
            value: f64::from(IDS_PER_FRAME),
            allowed: "one pass",
        })?;
        let mut stream = Stream::new(&self.pool, pass);
        let block_bytes = self.pool.block_bytes();
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("frame uploads"),
        });
        let mut allocator = Duration::ZERO;
        let mut stats = UploadStats {
            pool_blocks: self.pool.block_count(),
            ..UploadStats::default()
        };
        let mut waited = false;
        for (dst, offset, bytes) in &queued {
            stats.bytes += bytes.len() as u64;
            // Copies move multiples of 4 bytes; every upload here is made of 4-byte words.
            for (k, chunk) in bytes.chunks(block_bytes as usize).enumerate() {
                let len = chunk.len() as u32;
                let span = loop {
                    let a = Instant::now();
                    let r = stream.push_data(len.next_multiple_of(4), 256);
                    allocator += a.elapsed();
                    match r {
                        Ok(span) => break span,
                        Err(framealloc::Error::Exhausted { blocks, .. }) if waited => {
                            return Err(Error::UploadPoolExhausted {
                                pool_bytes: self.pool.pool_bytes(),
                                blocks,
                                frame_bytes: queued.iter().map(|q| q.2.len() as u64).sum(),
                            });
                        }
                        Err(framealloc::Error::Exhausted { .. }) => {
                            // The GPU is behind: let finished frames free their blocks.
                            waited = true;
                            crate::context::wait_idle(device)?;
                        }
                        Err(e) => return Err(Error::Upload(e.to_string())),
                    }
                };
                if span.new_block {
                    stats.blocks.push(span.block);
                }
                if len.is_multiple_of(4) {
                    queue.write_buffer(&self.buffer, span.offset, chunk);
                } else {
                    let mut padded = chunk.to_vec();
                    padded.resize(len.next_multiple_of(4) as usize, 0);
                    queue.write_buffer(&self.buffer, span.offset, &padded);
                }
                let at = offset + k as u64 * u64::from(block_bytes);
                let copy = u64::from(len.next_multiple_of(4));
                encoder.copy_buffer_to_buffer(&self.buffer, span.offset, dst, at, copy);
                stats.writes += 1;
            }
        }
        stats.allocator_ns = allocator.as_nanos() as u64;
        stats.commit_ns = t0.elapsed().as_nanos() as u64;
        stats.free_blocks = self.pool.free_blocks();
        self.stats = stats;
        Ok(encoder.finish())
    }

    /// After the frame's submission (uploads first): its blocks free once the GPU has
    /// finished it; the next frame takes the next IDs.
    pub(crate) fn submitted(&mut self, queue: &wgpu::Queue) {
        let last = self.frame.last();
        let pool = Arc::clone(&self.pool);
        let completions = Arc::clone(&self.completions);
        {
            let mut c = completions.lock().unwrap_or_else(|e| e.into_inner());
            c.in_flight += 1;
            self.stats.frames_in_flight = c.in_flight;
        }
        queue.on_submitted_work_done(move || {
            let mut c = completions.lock().unwrap_or_else(|e| e.into_inner());
            if c.held {
                c.pending.push(last);
            } else {
                c.in_flight = c.in_flight.saturating_sub(1);
                drop(c);
                let _ = pool.advance_free_id(last);
            }
        });
        self.frame = self.frame.next();
    }
}

impl UploadSink for Uploads {
    fn write(&mut self, dst: &wgpu::Buffer, offset: u64, bytes: &[u8]) {
        if !bytes.is_empty() {
            self.queued.push((dst.clone(), offset, bytes.to_vec()));
        }
    }
}
