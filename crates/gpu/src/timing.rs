//! GPU timings from timestamp queries: each timed pass writes a timestamp at its beginning
//! and end (`TIMESTAMP_QUERY`), and spans with the same label are summed.

use crate::error::Result;
use crate::resources::readback::read_buffer;

/// Collects begin/end timestamps of passes in one frame. A frame with more passes than the
/// query set holds leaves the rest untimed and says how many ([`GpuTimer::untimed`]); the
/// next frame's [`GpuTimer::fit`] grows the set to hold them.
pub struct GpuTimer {
    query_set: Option<wgpu::QuerySet>,
    resolve: Option<wgpu::Buffer>,
    labels: Vec<&'static str>,
    capacity: u32,
    period_ns: f32,
    /// Passes begun this frame after the query set was full.
    overflowed: u32,
    /// The last finished frame's untimed passes.
    last_untimed: u32,
    /// Timed passes the next frame should have room for.
    wanted: u32,
}

/// One timed label: its total GPU time and how many passes it covered.
#[derive(Clone, Debug, PartialEq)]
pub struct Timing {
    /// The label the passes were timed under.
    pub label: &'static str,
    /// Sum over the passes (milliseconds).
    pub ms: f64,
    /// How many passes.
    pub passes: u32,
}

/// The query set and resolve buffer for `capacity` timestamps.
fn timestamp_storage(device: &wgpu::Device, capacity: u32) -> (wgpu::QuerySet, wgpu::Buffer) {
    let query_set = device.create_query_set(&wgpu::QuerySetDescriptor {
        label: Some("pass timestamps"),
        ty: wgpu::QueryType::Timestamp,
        count: capacity,
    });
    let resolve = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("timestamp resolve"),
        size: u64::from(capacity) * 8,
        usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    (query_set, resolve)
}

impl GpuTimer {
    /// A timer for up to `max_passes` passes; inert (records nothing) when the device lacks
    /// `TIMESTAMP_QUERY`.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, max_passes: u32) -> Self {
        let capacity = max_passes.max(1) * 2;
        let enabled = device.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let (query_set, resolve) = enabled.then(|| timestamp_storage(device, capacity)).unzip();
        Self {
            query_set,
            resolve,
            labels: Vec::new(),
            capacity,
            period_ns: queue.get_timestamp_period(),
            overflowed: 0,
            last_untimed: 0,
            wanted: 0,
        }
    }

    /// Before recording a frame: grows the query set where the last frame ran out of room
    /// (twice what it wanted, so a few more passes fit too).
    pub(crate) fn fit(&mut self, device: &wgpu::Device) {
        if self.query_set.is_none() || self.wanted * 2 <= self.capacity {
            return;
        }
        self.capacity = self
            .wanted
            .saturating_mul(4)
            .min(wgpu::QUERY_SET_MAX_QUERIES);
        let (query_set, resolve) = timestamp_storage(device, self.capacity);
        self.query_set = Some(query_set);
        self.resolve = Some(resolve);
    }

    /// Passes of the last finished (read or discarded) frame that found the query set full
    /// and went untimed: missing from its timings.
    pub fn untimed(&self) -> u32 {
        self.last_untimed
    }

    /// Ends the frame's bookkeeping: what it left untimed, and what the next frame wants.
    fn finish_frame(&mut self) {
        self.last_untimed = self.overflowed;
        if self.overflowed > 0 {
            self.wanted = self.wanted.max(self.labels.len() as u32 + self.overflowed);
        }
        self.overflowed = 0;
    }

    /// A timer that records nothing (passes submitted outside a measured frame).
    pub(crate) fn inert() -> Self {
        Self {
            query_set: None,
            resolve: None,
            labels: Vec::new(),
            capacity: 0,
            period_ns: 1.0,
            overflowed: 0,
            last_untimed: 0,
            wanted: 0,
        }
    }

    fn next(&mut self, label: &'static str) -> Option<(&wgpu::QuerySet, u32)> {
        self.query_set.as_ref()?;
        let i = self.labels.len() as u32;
        if 2 * i + 2 > self.capacity {
            self.overflowed += 1;
            return None;
        }
        let qs = self.query_set.as_ref()?;
        self.labels.push(label);
        Some((qs, 2 * i))
    }

    /// Timestamp writes for a compute pass timed under `label`.
    pub fn compute(&mut self, label: &'static str) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        self.next(label)
            .map(|(qs, i)| wgpu::ComputePassTimestampWrites {
                query_set: qs,
                beginning_of_pass_write_index: Some(i),
                end_of_pass_write_index: Some(i + 1),
            })
    }

    /// Begins a compute pass in `encoder`, labelled and timed under `label`.
    pub(crate) fn begin_compute<'e>(
        &mut self,
        encoder: &'e mut wgpu::CommandEncoder,
        label: &'static str,
    ) -> wgpu::ComputePass<'e> {
        self.begin_compute_as(encoder, label, label)
    }

    /// Begins a compute pass in `encoder` labelled `label` (what debuggers show) and timed
    /// under `timed` (where several passes share one timing, or the timing's name is shorter).
    pub(crate) fn begin_compute_as<'e>(
        &mut self,
        encoder: &'e mut wgpu::CommandEncoder,
        label: &'static str,
        timed: &'static str,
    ) -> wgpu::ComputePass<'e> {
        encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(label),
            timestamp_writes: self.compute(timed),
        })
    }

    /// Timestamp writes for a render pass timed under `label`.
    pub fn render(&mut self, label: &'static str) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        self.next(label)
            .map(|(qs, i)| wgpu::RenderPassTimestampWrites {
                query_set: qs,
                beginning_of_pass_write_index: Some(i),
                end_of_pass_write_index: Some(i + 1),
            })
    }

    /// Records the resolve of this frame's queries into `encoder` (call once, last).
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        if let (Some(qs), Some(buf)) = (&self.query_set, &self.resolve) {
            let n = self.labels.len() as u32 * 2;
            if n > 0 {
                encoder.resolve_query_set(qs, 0..n, buf, 0);
            }
        }
    }

    /// Forgets this frame's timed passes without reading them (a frame not waited for).
    pub fn discard(&mut self) {
        self.finish_frame();
        self.labels.clear();
    }

    /// After the frame's submission: reads the timestamps back and sums them per label, in
    /// first-use order. Clears the timer for the next frame.
    pub fn read(&mut self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<Vec<Timing>> {
        self.finish_frame();
        let labels = std::mem::take(&mut self.labels);
        let Some(buf) = &self.resolve else {
            return Ok(Vec::new());
        };
        if labels.is_empty() {
            return Ok(Vec::new());
        }
        let bytes = read_buffer(device, queue, buf, 0, labels.len() as u64 * 16)?;
        let ticks: Vec<u64> = bytemuck::pod_collect_to_vec(&bytes);
        let mut out: Vec<Timing> = Vec::new();
        for (i, label) in labels.into_iter().enumerate() {
            let (b, e) = (ticks[2 * i], ticks[2 * i + 1]);
            let ms = e.saturating_sub(b) as f64 * f64::from(self.period_ns) / 1e6;
            match out.iter_mut().find(|t| t.label == label) {
                Some(t) => {
                    t.ms += ms;
                    t.passes += 1;
                }
                None => out.push(Timing {
                    label,
                    ms,
                    passes: 1,
                }),
            }
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A frame with more passes than the query set holds times what fits, counts the rest
    /// as untimed, and the next frame (after `fit`) times them all.
    #[test]
    fn a_full_timer_counts_untimed_passes_and_grows() {
        let c = testkit::device::ctx();
        assert!(
            c.device
                .features()
                .contains(wgpu::Features::TIMESTAMP_QUERY),
            "{} has no timestamp queries (lavapipe has them)",
            c.adapter_line()
        );
        let labels = ["a", "b", "c", "d", "e"];
        let mut timer = GpuTimer::new(&c.device, &c.queue, 2);
        let frame = |timer: &mut GpuTimer| {
            timer.fit(&c.device);
            let mut encoder = c.device.create_command_encoder(&Default::default());
            for label in labels {
                drop(timer.begin_compute(&mut encoder, label));
            }
            timer.resolve(&mut encoder);
            c.queue.submit([encoder.finish()]);
            let timings = timer.read(&c.device, &c.queue).unwrap();
            let timed: Vec<&str> = timings.iter().map(|t| t.label).collect();
            (timed, timer.untimed())
        };
        assert_eq!(frame(&mut timer), (vec!["a", "b"], 3));
        assert_eq!(frame(&mut timer), (labels.to_vec(), 0));
        assert_eq!(frame(&mut timer), (labels.to_vec(), 0));
    }
}
