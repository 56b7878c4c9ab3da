//! Test support for the whole workspace, so no test file sets up its own device, kernel
//! runner or random generator:
//!
//! - [`Rng`]: the deterministic generator every test, bench and example draws from.
//! - [`device`] (feature `device`): the one headless device of a test binary (a machine
//!   without a Vulkan driver fails with the command that installs lavapipe), a runner for
//!   described passes ([`device::run_pass`]: buffers by binding name, the description's
//!   dispatches), a runner for ad-hoc kernels ([`device::run_kernel`],
//!   [`device::run_words`]), and golden-image checks with a bless switch
//!   ([`device::check_golden`]).
//!
//! The rule for where tests live: a crate's GPU twins run on a device in that crate's
//! `tests/device.rs`, the renderer's frame tests in `crates/gpu/tests/`, and every one of
//! them gets its device and runs its kernels through [`device`].
//!
//! ```
//! let mut rng = testkit::Rng::new(7);
//! let x = rng.range(-1.0, 1.0);
//! assert!((-1.0..1.0).contains(&x));
//! assert!(rng.below(10) < 10);
//! assert_eq!(testkit::Rng::new(7).next_u64(), testkit::Rng::new(7).next_u64());
//! ```

#[cfg(feature = "device")]
pub mod device;
mod rng;

pub use rng::Rng;
