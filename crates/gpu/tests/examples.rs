//! The examples refuse bad arguments with a usage error, never a panic.

#[test]
fn classify_variants_refuses_bad_arguments() {
    testkit::check_example_cli(
        "classify_variants",
        &[&["--width", "0"], &["--frames", "0"], &["--scene", "city"]],
    );
}

#[test]
fn static_query_refuses_bad_arguments() {
    testkit::check_example_cli(
        "static_query",
        &[
            &["--instances", "0"],
            &["--width", "0"],
            &["--frames", "0"],
            &["--camera", "orbit"],
        ],
    );
}

#[test]
fn float_river_refuses_bad_arguments() {
    testkit::check_example_cli(
        "float_river",
        &[
            &["--crates", "0"],
            &["--seconds", "-1"],
            &["--frames", "0"],
            &["--width", "0"],
        ],
    );
}
