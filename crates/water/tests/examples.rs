//! The examples refuse bad arguments with a usage error, never a panic.

#[test]
fn bake_refuses_bad_arguments() {
    testkit::check_example_cli("bake", &[&["10"], &["100000"], &["2048", "seq"]]);
}

#[test]
fn edt_timing_refuses_bad_arguments() {
    testkit::check_example_cli("edt_timing", &[&["8"], &["64", "0"], &["64", "1", "gpu"]]);
}

#[test]
fn fbm_timing_refuses_bad_arguments() {
    testkit::check_example_cli("fbm_timing", &[&["0"], &["NaN"]]);
}

#[test]
fn world_stats_refuses_bad_arguments() {
    testkit::check_example_cli("world_stats", &[&["2"], &["10001"]]);
}
