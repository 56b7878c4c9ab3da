//! Test support for the whole workspace, so no test file sets up its own device, kernel
//! runner or random generator:
//!
//! - [`Rng`]: the deterministic generator every test, bench and example draws from (the
//!   demo scenes' one, `staticscene::demo::Rng`).
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
/// The workspace's one deterministic generator (SplitMix64), shared with the demo scenes.
pub use staticscene::demo::Rng;

use std::path::PathBuf;
use std::process::Command;

/// What an example printed when run: exit code (-1 if killed), stdout, stderr.
#[derive(Clone, Debug)]
pub struct ExampleRun {
    /// Exit code; clap's usage errors are 2, a panic is 101.
    pub code: i32,
    /// Standard output.
    pub stdout: String,
    /// Standard error.
    pub stderr: String,
}

/// Runs example `name` of the package under test with `args`, from the build `cargo test`
/// made beside the test binary (`target/<profile>/examples/`). How tests check that every
/// example refuses bad arguments with a message instead of panicking.
///
/// # Panics
/// When the example was not built (a test of an example that needs a feature must be
/// gated on it) or cannot be started.
pub fn run_example(name: &str, args: &[&str]) -> ExampleRun {
    let exe = std::env::current_exe().expect("the test binary's path");
    // target/<profile>/deps/<test> -> target/<profile>/examples/<name>
    let dir: PathBuf = exe
        .parent()
        .and_then(|deps| deps.parent())
        .map(|profile| profile.join("examples"))
        .expect("target/<profile>/deps");
    let path = dir.join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    let out = Command::new(&path)
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("{}: {e} (is the example built?)", path.display()));
    ExampleRun {
        code: out.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

/// Checks that example `name` answers `--help` (exit 0) and refuses each of `bad` with
/// clap's usage error (exit 2, a message on stderr), never a panic.
///
/// # Panics
/// With the arguments, the exit code and the output, when one is not so.
pub fn check_example_cli(name: &str, bad: &[&[&str]]) {
    let help = run_example(name, &["--help"]);
    assert_eq!(help.code, 0, "{name} --help:\n{}", help.stderr);
    assert!(
        help.stdout.contains("Usage"),
        "{name} --help:\n{}",
        help.stdout
    );
    for args in bad {
        let r = run_example(name, args);
        assert_eq!(
            r.code, 2,
            "{name} {args:?} must be refused with a usage error (2), got {}:\n{}",
            r.code, r.stderr
        );
        assert!(r.stderr.contains("error"), "{name} {args:?}:\n{}", r.stderr);
    }
}
