//! The example refuses bad arguments with a usage error, never a panic.

#[test]
fn gpu_append_timing_refuses_bad_arguments() {
    testkit::check_example_cli(
        "gpu_append_timing",
        &[&["--log2-items", "99"], &["--reps", "0"]],
    );
}
