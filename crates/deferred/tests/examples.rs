//! The examples refuse bad arguments with a usage error, never a panic.

#[test]
fn culling_stats_refuses_bad_arguments() {
    testkit::check_example_cli("culling_stats", &[&["x"]]);
}

#[test]
fn depth_precision_refuses_bad_arguments() {
    testkit::check_example_cli("depth_precision", &[&["3"]]);
}

#[test]
fn normal_error_refuses_bad_arguments() {
    testkit::check_example_cli("normal_error", &[&["0"], &["-3"], &["1.5"]]);
}
